// `billiard animate` from the command line: a movie with every frame (read back by ffprobe),
// free particles in a shape, and bad options refused in the program's format with nothing
// written.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>

#include <iterator>
#include <string>

namespace fs = std::filesystem;

namespace {

/// ffprobe's count of the frames it decodes in the movie's video stream.
std::string decoded_frames(const fs::path& movie) {
  const auto r = run_command("ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames "
                             "-of csv=p=0 " + movie.string());
  REQUIRE(r.status == 0);
  return r.output.substr(0, r.output.find_first_of("\r\n"));
}

std::size_t files_in(const fs::path& dir) {
  return std::distance(fs::directory_iterator(dir), fs::directory_iterator());
}

}  // namespace

TEST_CASE("animate writes an MP4 and a GIF with one frame per sample time") {
  const auto dir = scratch("animate");
  const auto mp4 = dir / "clover.mp4";
  auto r = billiard("animate scenes/clover-driven.yaml -o " + mp4.string() + " --particles 12 --time 0.4 --frames 7");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("wrote " + mp4.string() + ": 7 frames of 12 particles") != std::string::npos);
  CHECK(decoded_frames(mp4) == "7");
  const auto gif = dir / "stadium.gif";
  r = billiard("animate shapes/stadium.yaml -o " + gif.string() + " --particles 3 --frames 5 --trail 2 --time 2");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(decoded_frames(gif) == "5");
  CHECK(files_in(dir) == 2);  // no temporaries left
}

TEST_CASE("animate refuses bad options with exit status 2 and writes nothing") {
  const auto dir = scratch("animate-bad");
  const std::string out = (dir / "m").string();
  struct Case {
    std::string args, message;
  };
  for (const auto& c : {Case{"scenes/clover-free.yaml -o " + out + ".avi", "the movie's format follows its extension"},
                        Case{"scenes/clover-free.yaml -o " + out + ".gif --histogram", "--histogram needs a driven scene"},
                        Case{"scenes/sinai3-driven.yaml -o " + out + ".gif", "animate draws 2-D scenes"},
                        Case{"scenes/clover-free.yaml -o " + out + ".gif --frames 1", "--frames"},
                        Case{"scenes/clover-free.yaml -o " + out + ".gif --fps 0", "--fps"},
                        Case{"scenes/clover-free.yaml -o " + out + ".gif --time -1", "time"},
                        Case{"no-such.yaml -o " + out + ".gif", "no-such.yaml"}}) {
    const auto r = billiard("animate " + c.args);
    INFO(c.args << "\n" << r.output);
    CHECK(r.status != 0);
    CHECK(r.output.find("billiard: error: ") != std::string::npos);
    CHECK(r.output.find(c.message) != std::string::npos);
  }
  CHECK(files_in(dir) == 0);
}
