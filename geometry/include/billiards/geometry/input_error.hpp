// The one exception type for bad user input (shape files, scene files, command-line values).
// It always names where the problem is, so that the CLI can print "file:line: message".
#pragma once

#include <stdexcept>
#include <string>

namespace billiards {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, const std::string& message)
      : std::runtime_error(format(file, line, message)), file_(std::move(file)), line_(line), message_(message) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  /// What is wrong, without the file and line.
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& message) {
    if (file.empty()) return message;
    return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
  }
  std::string file_;
  int line_;
  std::string message_;
};

}  // namespace billiards
