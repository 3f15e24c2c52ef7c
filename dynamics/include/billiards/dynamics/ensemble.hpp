// Ensembles: many independent particles, each with its own random stream, run in parallel.
// Results are stored by particle index and reduced in index order, so they are bit-identical
// for any number of threads.
#pragma once

#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/first_error.hpp"
#include "billiards/dynamics/free_lockstep.hpp"
#include "billiards/dynamics/lockstep.hpp"
#include "billiards/dynamics/magnetic_lockstep.hpp"
#include "billiards/dynamics/random.hpp"
#include "billiards/geometry/input_error.hpp"

#include <boost/container/static_vector.hpp>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace billiards::dynamics {

/// A failure inside one particle's run (a field the integrator cannot follow, a root search
/// that does not converge): its message names the particle and the time its flight started,
/// "particle 17, in its flight from t = 0.43: the force is not finite at ...".
struct ParticleError : std::runtime_error {
  ParticleError(std::size_t particle, double t, const std::string& cause);
};

/// What happened to one particle.
struct ParticleLog {
  std::uint64_t collisions = 0;
  bool escaped = false;  // left the region: reported as an error, never dropped
};

struct RunOptions {
  std::vector<double> record_times;  // increasing, ≥ 0: energies are recorded at these times
  double mass = 1;
  /// Also test the midpoint of every flight with the independent point-in-region test
  /// (costs about as much as the collision search; on in the test suite).
  bool verify_every_flight = false;
  /// Consecutive collisions at zero flight time before a particle is declared stuck.
  int max_zero_flights = 1000;
  /// If set, asked by the calling thread every `StopCheck::period` rounds of collisions; false
  /// stops every particle where it is, the results left incomplete (Ctrl-C in Python, where a
  /// single particle may run for minutes).
  std::function<bool()> keep_going;
};

/// A run's stop: the calling thread (OpenMP's thread 0) asks opt.keep_going() now and then, and
/// once it says no, every thread sees `stopped()` at its next round.
class StopCheck {
 public:
  static constexpr std::size_t period = 4096;
  explicit StopCheck(const RunOptions& opt) : opt_(&opt) {}
  bool stopped() {
    if (!opt_->keep_going) return false;
    if (omp_get_thread_num() == 0 && ++rounds_ % period == 0 && !opt_->keep_going())
      stop_.store(true, std::memory_order_relaxed);
    return stop_.load(std::memory_order_relaxed);
  }

 private:
  const RunOptions* opt_;
  std::atomic<bool> stop_{false};
  std::size_t rounds_ = 0;  // thread 0's
};

template <class State>
double kinetic_energy(const State& s, double mass) { return 0.5 * mass * s.v.squaredNorm(); }

/// The energy an ensemble records: ½mv², plus U(x) for a flight in a potential.
template <class Flight>
double energy_of(const Flight& flight, const typename Flight::State& s, double mass) {
  if constexpr (requires { flight.potential(s.x); })
    return kinetic_energy(s, mass) + flight.potential(s.x);
  else
    return kinetic_energy(s, mass);
}

/// Does the flight record its energy from a mark computed once per record time for every
/// particle (`record_mark(t)`, `kinetic_energy_at_mark`)?  The periodic drive's mark is the sine
/// of its phase at t: a record then costs no sine or cosine of the particle's own.
template <class Flight>
concept marks_records = requires(const Flight& f, const typename Flight::State& s, double t) {
  f.kinetic_energy_at_mark(s, f.record_mark(t), 1.0);
};

/// What a run computes once per record time for every particle's record there (nothing for a
/// flight without marks).
template <class Flight>
struct RecordMarks {
  RecordMarks(const Flight&, const std::vector<double>&) {}
};
template <marks_records Flight>
struct RecordMarks<Flight> {
  std::vector<typename Flight::Scalar> at;
  RecordMarks(const Flight& flight, const std::vector<double>& times) {
    for (double t : times) at.push_back(flight.record_mark(t));
  }
};

/// One particle's run, a collision at a time: records its energy at each record time into
/// `energies` (NaN after an escape).  Flights are searched up to the last record time only.
/// Each flight runs on its own clock (collision.hpp's restart_clock): the state's t is the time
/// since the last bounce, the run's time is kept in `clock()`.
/// `TableT` is a 2-D table (table.hpp) or a 3-D one (table3.hpp): the verbs `collision`,
/// `bounce` and `sample_microcanonical` are found for either by overload resolution.
template <class Flight, class TableT = dynamics::Table>
class Trajectory {
 public:
  Trajectory(const TableT& table, const Flight& flight, typename Flight::State s, const RunOptions& opt,
             const RecordMarks<Flight>& marks, double* energies)
      : table_(&table), flight_(&flight), opt_(&opt), marks_(&marks), s_(s), energies_(energies),
        v2_(s.v.squaredNorm()), t_final_(opt.record_times.empty() ? s.t : opt.record_times.back()) {
    restart_clock(flight, s_, clock_);
  }

  /// Advances to the next collision (recording the times passed on the way); false when done.
  /// A straight flight's step is inlined whole (search, bounce and records: 3% fewer
  /// instructions in the clover); a driven one keeps its search out of line.
  bool step() {
    if constexpr (is_straight<Flight>) return flat_step();
    else return next_collision();
  }
  /// Has the particle passed the last record time (or escaped)?
  bool done() const { return k_ == opt_->record_times.size(); }
  /// The end of the search for the next collision.  A straight flight costs the same whatever
  /// the horizon: it is searched without one, so that a particle that meets no wall at all is
  /// caught as an escape at once.  A flight with a look-ahead (a magnetic field with a force)
  /// is searched that far ahead at most.  (On the flight's own clock.)
  double horizon() const {
    if constexpr (is_straight<Flight>) return never;
    else if constexpr (requires { flight_->lookahead(); }) return std::min(clock_.until(t_final_), flight_->lookahead());
    else return clock_.until(t_final_);
  }
  /// The state (its t on the flight's own clock) and the run's time at the start of its flight.
  const typename Flight::State& state() const { return s_; }
  const Clock& clock() const { return clock_; }
  /// `step` with the next collision, collision(table, flight, state(), horizon()), found by the
  /// caller (run_particles, several particles in lock step).  Inlined into the caller's loop:
  /// out of line, the driven clover in lock step runs 2–3% slower.
  template <class HitT>
  [[gnu::always_inline]] bool advance_to(const HitT& hit) {
    // A search that stopped at its look-ahead, short of the last record time, with no wall met.
    const double end = horizon();
    const bool looked_ahead = !hit.found() && end < clock_.until(t_final_);
    const double t_next = hit.found() ? hit.t : looked_ahead ? end : never;
    if (!record_until(t_next)) return escape();
    if (done()) return false;
    if (looked_ahead) {  // on to the look-ahead, to search again from there
      s_ = flight_->advance(s_, end);
      restart_clock(*flight_, s_, clock_);
      return true;
    }
    if (!hit.found()) return escape();  // no wall ahead of a particle that should meet one
    if (opt_->verify_every_flight && !midpoint_certified(hit) && !inside_at(0.5 * (s_.t + hit.t))) return escape();
    zero_flights_ = hit.t == s_.t ? zero_flights_ + 1 : 0;
    if (zero_flights_ > opt_->max_zero_flights) return escape();
    bounce(*flight_, s_, hit);
    if constexpr (Flight::conserves_energy) restore_speed(s_.v, v2_);
    restart_clock(*flight_, s_, clock_);
    ++log_.collisions;
    return true;
  }
  const ParticleLog& log() const { return log_; }
  /// The speed² the bounces restore, the next record (an index into the record times) and the
  /// particle's energies, one per record time.
  double speed2() const { return v2_; }
  std::size_t next_record() const { return k_; }
  double* energies() const { return energies_; }
  /// Takes up the particle where bounces and records made elsewhere (free_lanes::Propagator,
  /// with advance_to's arithmetic) left it: the state after the last bounce, its clock, their
  /// number (all of nonzero flights) and the next record.
  void resume(const typename Flight::State& s, const Clock& clock, std::uint64_t bounces, std::size_t next_record) {
    s_ = s, clock_ = clock, k_ = next_record;
    log_.collisions += bounces;
    if (bounces > 0) zero_flights_ = 0;
  }

 private:
  bool next_collision() { return !done() && advance_to(collision(*table_, *flight_, s_, horizon())); }
  /// Records the energies at the record times up to t_end (on the flight's clock); false when
  /// the particle is not inside the table at one.  A run that checks every flight's midpoint
  /// does not check its records too: a particle outside is caught at its flight's midpoint.
  bool record_until(double t_end) {
    if constexpr (marks_records<Flight>) {
      if (opt_->verify_every_flight) {
        record_marks_until(t_end);
        return true;
      }
    }
    const auto& times = opt_->record_times;
    for (double t; k_ < times.size() && (t = clock_.until(times[k_])) <= t_end; ++k_)
      if (!record(t)) return false;
    return true;
  }
  /// The same for a flight with marks, unchecked, four record times at a time while four are
  /// left.  A block's energies are stored before it is known which of its times the flight
  /// reaches (a later flight overwrites the others): the loop then ends on a branch per four
  /// records instead of one on each record's time, whose outcome (how many record times a
  /// flight spans) no predictor can guess.  The records taken are the same, in the same order.
  void record_marks_until(double t_end) {
    constexpr std::size_t block = 4;
    const auto& times = opt_->record_times;
    while (times.size() - k_ >= block) {
      std::size_t reached = 0;  // the block's records up to t_end, the first in order
      for (std::size_t b = 0; b < block; ++b) {
        energies_[k_ + b] = energy_at_mark(k_ + b);
        reached += (reached == b) & (clock_.until(times[k_ + b]) <= t_end);
      }
      k_ += reached;
      if (reached < block) return;
    }
    for (; k_ < times.size() && clock_.until(times[k_]) <= t_end; ++k_) energies_[k_] = energy_at_mark(k_);
  }
  /// The energy at record time k of a flight with marks, from the current flight.
  double energy_at_mark(std::size_t k) const {
    return flight_->kinetic_energy_at_mark(s_, marks_->at[k], opt_->mass);
  }
  /// Records the energy at the next record time, t on the flight's clock; false when the
  /// particle is not inside the table there (checked unless every flight's midpoint is).
  bool record(double t) {
    const bool check = !opt_->verify_every_flight;
    if constexpr (marks_records<Flight>) {
      if (check && !inside_at(t)) return false;
      energies_[k_] = energy_at_mark(k_);
    } else {
      const auto r = flight_->advance(s_, t);
      if (check && !table_->contains(r.x)) return false;
      energies_[k_] = energy_of(*flight_, r, opt_->mass);
    }
    return true;
  }
  [[gnu::flatten]] bool flat_step() { return next_collision(); }
  /// Did the search that found the hit certify the flight's midpoint inside already?
  template <class HitT>
  static bool midpoint_certified(const HitT& hit) {
    if constexpr (requires { hit.midpoint_inside; }) return hit.midpoint_inside;
    else return false;
  }
  /// Is the particle inside the region at time t of its current flight?  A driven flight's
  /// position lies on its oscillation segment, which the table can often certify inside at a
  /// lookup, without advancing the flight (a phase reduction and a sine and cosine).
  bool inside_at(double t) const {
    if constexpr (requires { table_->certainly_contains(flight_->sweep(s_, t).first, flight_->sweep(s_, t).second); }) {
      const auto [p, q] = flight_->sweep(s_, t);
      if (table_->certainly_contains(p, q)) return true;
    }
    return table_->contains(flight_->advance(s_, t).x);
  }
  bool escape() {
    log_.escaped = true;
    for (; k_ < opt_->record_times.size(); ++k_) energies_[k_] = std::nan("");
    return false;
  }
  const TableT* table_;
  const Flight* flight_;
  const RunOptions* opt_;
  const RecordMarks<Flight>* marks_;
  typename Flight::State s_;
  double* energies_;
  double v2_, t_final_;
  Clock clock_;
  std::size_t k_ = 0;
  int zero_flights_ = 0;
  ParticleLog log_;
};

/// Runs one particle to the end.
template <class Flight, class TableT>
ParticleLog simulate(const TableT& table, const Flight& flight, typename Flight::State s,
                     const RunOptions& opt, double* energies) {
  const RecordMarks<Flight> marks(flight, opt.record_times);
  Trajectory<Flight, TableT> run(table, flight, s, opt, marks, energies);
  while (run.step()) {
  }
  return run.log();
}

/// Results of an ensemble run: energies[i * record_times.size() + k] for particle i.
struct EnsembleResult {
  std::vector<double> energies;
  std::vector<ParticleLog> logs;
  std::uint64_t collisions() const;
  std::uint64_t escapes() const;
  /// E(t_k) − E(t_0) of every particle that did not escape (m record times per particle).
  std::vector<double> energy_changes(std::size_t k, std::size_t m) const;
  /// E(t_k) of every particle that did not escape.
  std::vector<double> energies_at(std::size_t k, std::size_t m) const;
};

/// Particles a thread advances together.  A straight flight's collision is a short chain of
/// dependent square roots and divisions: interleaving four independent particles lets the
/// processor overlap their chains (the circle 2×, the clover 2%).  A driven collision, ~3 000
/// instructions, is too long to overlap with another's, and interleaving only spreads the
/// working set: one particle at a time is 3–4% faster (BENCHMARKS.md).  Each particle's
/// arithmetic is the same either way.
template <class Flight>
inline constexpr std::size_t interleaved_particles = is_straight<Flight> ? 4 : 1;

/// The lock-step table that searches a flight's collisions (void: none): driven, free and
/// magnetic flights in 2-D, free flights in 3-D.
template <class Flight>
using LockstepTableOf = std::conditional_t<
    std::is_same_v<Flight, PeriodicDriveFlight>, LockstepTable,
    std::conditional_t<std::is_same_v<Flight, FreeFlight>, FreeLockstepTable,
                       std::conditional_t<std::is_same_v<Flight, MagneticFlight>, MagneticLockstepTable,
                                          std::conditional_t<std::is_same_v<Flight, FreeFlight3>, FreeLockstepTable3, void>>>>;

/// run_in_lockstep's particles kept in the lanes of a table that `propagates`: `runs[i]` the
/// particle of lane i (none: the lane parked), `finish(i)` keeps its log and puts the next
/// particle there.  A particle leaves its lane only for what the propagator does not do
/// (elliptic arcs, zero flights, no wall ahead, hits handed back, a record near a wall, the
/// end): the scalar code resumes it, takes its hit (Trajectory::advance_to) and loads it back.
template <class LockstepT, class Run, class Finish>
void propagate_in_lanes(const LockstepT& lockstep_table, const RunOptions& opt, std::optional<Run>* runs,
                        Finish& finish, StopCheck& stop, const FirstError& error) {
  constexpr int lanes = LockstepT::lanes;
  std::vector<double> times = opt.record_times;
  times.push_back(never);
  const free_lanes::Records records{times.data(), std::int64_t(opt.record_times.size()), 0.5 * opt.mass};
  free_lanes::Particles p;
  free_lanes::Hits hits;
  // Lane i given its particle (the next ones while a particle is done at its start).
  auto load = [&](int i) {
    while (runs[i] && runs[i]->done()) finish(i);
    if (const Run* run = runs[i] ? &*runs[i] : nullptr)
      free_lanes::load(p, i, run->state(), run->clock(), run->speed2(), records, std::int64_t(run->next_record()),
                       run->energies());
  };
  // A lane without a particle parked: a copy of a lane with one (there is one), never bounced.
  auto park = [&](int i) {
    int j = 0;
    while (!runs[j]) ++j;
    free_lanes::park(p, i, j, records);
  };
  int active = 0;
  for (int i = 0; i < lanes; ++i) load(i), active += runs[i].has_value();
  for (int i = 0; i < lanes && active > 0; ++i)
    if (!runs[i]) park(i);
  FlightHit<typename LockstepT::Flight> hit;
  while (active > 0 && !stop.stopped() && !error.failed()) {
    const std::uint32_t left = lockstep_table.propagate(records, p, hits);
    for (int i = 0; i < lanes; ++i) {
      if (!(left >> i & 1) || !runs[i]) continue;
      Run& run = *runs[i];
      run.resume(free_lanes::state_in(p, i), free_lanes::clock_in(p, i), std::uint64_t(p.bounces[i]),
                 std::size_t(p.record[i]));
      lockstep_table.hit_of(hits, i, run.state(), run.horizon(), hit);
      if (!run.advance_to(hit)) finish(i);
      load(i);
      if (!runs[i] && --active > 0) park(i);
    }
  }
}

/// Runs particles [first, last) of an ensemble in a table that a lock-step table can search
/// (LockstepTableOf the flight): each thread keeps
/// `lanes` particles in flight and finds their collisions together, taking the next particle as
/// soon as one is done.  Each particle's arithmetic is that of `simulate`, whatever its
/// neighbours in the lanes.
template <class Flight, class LockstepT, class TableT, class Initial>
void run_in_lockstep(const LockstepT& lockstep_table, const TableT& table, const Flight& flight,
                     const Initial& initial, const RunOptions& opt, std::size_t first, std::size_t last, int threads,
                     EnsembleResult& out, const std::function<void(std::size_t)>& progress) {
  using Run = Trajectory<Flight, TableT>;
  constexpr int lanes = LockstepT::lanes;
  const std::size_t m = opt.record_times.size();
  const RecordMarks<Flight> marks(flight, opt.record_times);
  std::atomic<std::size_t> next{first}, done{0};
  StopCheck stop(opt);
  FirstError error;
#pragma omp parallel num_threads(threads)
  error.run(0, [&] {
    std::optional<Run> runs[lanes];
    std::size_t index[lanes];
    auto refill = [&](int i) {
      runs[i].reset();
      const std::size_t k = next++;
      if (k < last) runs[i].emplace(table, flight, initial(k), opt, marks, &out.energies[k * m]), index[i] = k;
    };
    // A particle done: its log kept, the next one in its lane.
    auto finish = [&](int i) {
      out.logs[index[i]] = runs[i]->log();
      const std::size_t d = ++done;
      if (progress && omp_get_thread_num() == 0) progress(d);
      refill(i);
    };
    for (int i = 0; i < lanes; ++i) refill(i);
    // A mesh's walks as a stream: lane i's particle advanced to its hit, and the lane given its
    // next flight (or the next particle's) as soon as the hit is found.
    using Next = NextFlight<typename Flight::State>;
    if constexpr (requires { lockstep_table.streams(); })
      if (lockstep_table.streams())
        return lockstep_table.collision_stream([&](int i, const FlightHit<Flight>* hit) -> Next {
          if (hit && !runs[i]->advance_to(*hit)) finish(i);
          while (runs[i] && runs[i]->done()) finish(i);  // (no record time after the start)
          if (!runs[i] || stop.stopped() || error.failed()) return {};
          return {&runs[i]->state(), runs[i]->horizon()};
        });
    // Free flights in 2-D with nothing checked at every flight: the particles kept in the
    // lanes across their bounces, the lanes left to the scalar code here when a particle's hit
    // is not one the propagator bounces.
    if constexpr (requires(free_lanes::Particles& p, free_lanes::Hits& h) { lockstep_table.propagate({}, p, h); })
      if (lockstep_table.propagates() && !opt.verify_every_flight)
        return propagate_in_lanes(lockstep_table, opt, runs, finish, stop, error);
    // Else a batch of every lane's flight at a time.
    const typename Flight::State* states[lanes];
    double horizons[lanes];
    int lane_of[lanes];
    FlightHit<Flight> hits[lanes];
    for (;;) {
      int n = 0;
      for (int i = 0; i < lanes; ++i) {
        while (runs[i] && runs[i]->done()) finish(i);  // (no record time after the start)
        if (runs[i]) states[n] = &runs[i]->state(), horizons[n] = runs[i]->horizon(), lane_of[n++] = i;
      }
      if (n == 0 || stop.stopped() || error.failed()) break;
      lockstep_table.collisions(states, horizons, n, hits);
      for (int j = 0; j < n; ++j) {
        if (!runs[lane_of[j]]->advance_to(hits[j])) finish(lane_of[j]);
      }
    }
  });
  error.rethrow();
  if (progress) progress(done);
}

/// run.step() of particle i; a runtime error it throws becomes a ParticleError naming the
/// particle and the time its flight started (bad input, InputError, passes as it is).
template <class Run>
bool step_particle(Run& run, std::size_t i) {
  try {
    return run.step();
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw ParticleError(i, run.clock().after(0), e.what());
  }
}

/// Runs particles [first, last) of an ensemble.  `initial(i)` gives particle i's state (it
/// must depend on i only); `progress(done)` is called from one thread now and then.  An exception
/// thrown for a particle stops the run and is rethrown after it (first_error.hpp; in lock step,
/// the first one thrown).
template <class Flight, class TableT, class Initial>
void run_particles(const TableT& table, const Flight& flight, const Initial& initial,
                   const RunOptions& opt, std::size_t first, std::size_t last, int threads,
                   EnsembleResult& out, const std::function<void(std::size_t)>& progress = {}) {
  if constexpr (std::is_constructible_v<LockstepTableOf<Flight>, const TableT&, const Flight&>) {
    const LockstepTableOf<Flight> lockstep_table(table, flight);
    if (lockstep_table.usable())
      return run_in_lockstep(lockstep_table, table, flight, initial, opt, first, last, threads, out, progress);
  }
  const std::size_t m = opt.record_times.size();
  const RecordMarks<Flight> marks(flight, opt.record_times);
  constexpr std::size_t together = interleaved_particles<Flight>;
  const std::size_t batches = (last - first + together - 1) / together;
  std::atomic<std::size_t> done{0};
  StopCheck stop(opt);
  FirstError error;
#pragma omp parallel for schedule(dynamic, 2) num_threads(threads)
  for (std::ptrdiff_t b = 0; b < std::ptrdiff_t(batches); ++b) error.run(std::size_t(b), [&] {
    const std::size_t lo = first + std::size_t(b) * together;
    const std::size_t hi = std::min(last, lo + together);
    boost::container::static_vector<Trajectory<Flight, TableT>, together> runs;
    for (std::size_t i = lo; i < hi; ++i) runs.emplace_back(table, flight, initial(i), opt, marks, &out.energies[i * m]);
    std::size_t active = runs.size();
    while (active > 0 && !stop.stopped()) {
      active = 0;
      for (std::size_t j = 0; j < runs.size(); ++j) active += step_particle(runs[j], lo + j);
    }
    for (std::size_t i = lo; i < hi; ++i) out.logs[i] = runs[i - lo].log();
    const std::size_t d = done += hi - lo;
    if (progress && omp_get_thread_num() == 0) progress(d);
  });
  error.rethrow();
  if (progress) progress(done);
}

/// Runs a whole ensemble of `particles` particles.
template <class Flight, class TableT, class Initial>
EnsembleResult run_ensemble(const TableT& table, const Flight& flight, const Initial& initial, const RunOptions& opt,
                            std::size_t particles, int threads) {
  EnsembleResult result;
  result.energies.resize(particles * opt.record_times.size());
  result.logs.resize(particles);
  run_particles(table, flight, initial, opt, 0, particles, threads, result);
  return result;
}

/// Initial conditions of a microcanonical ensemble at the given speed: particle i is drawn from
/// ParticleRng(seed, i).
template <class Flight, class TableT>
auto microcanonical(const TableT& table, const Flight& flight, double speed, std::uint64_t seed) {
  return [&table, flight, speed, seed](std::size_t i) {
    ParticleRng rng(seed, i);
    return flight.start(sample_microcanonical(table, speed, rng));
  };
}

}  // namespace billiards::dynamics
