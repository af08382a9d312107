/// A one-line progress bar for long runs on a terminal, silent in CI, in logs and on request.
#pragma once
#include <array>
#include <chrono>
#include <cstdio>
#include <string>

namespace mfv {

/// Progress of a long run, redrawn in place on `out`:
///   "label [#########...........]  45% step 1125/2500 t=0.0104 ms ETA 6 s"
/// and, on finish(), the last state with the elapsed time instead of the ETA, then a newline.
///
/// Enabled only if `out` is a terminal and neither CI nor MFV_QUIET is set in the
/// environment (to anything), unless `quiet` is true (always off) or `force` is true (on
/// regardless of the terminal and the environment; for tests and for logs that want it).
/// The decision is taken once, at construction.
///
/// update() is meant to be called every time step: it allocates nothing, reads the clock
/// only every N calls (N adapts so that the clock is read about every 20–100 ms) and
/// redraws at most about 5 times per second. Not thread-safe: call it from one thread.
class ProgressBar {
 public:
  /// Throws std::invalid_argument if total_steps is negative. `out` is not owned.
  ProgressBar(std::string label, long total_steps, bool quiet = false, std::FILE* out = stderr,
              bool force = false);
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Calls finish() if it has not been called.
  ~ProgressBar();

  /// Reports that `step` steps of total_steps are done and the simulated time is
  /// `sim_time`, printed with `time_unit` (e.g. "ms"; copied when drawn, up to 15 chars).
  /// The first call draws at once; the ETA is extrapolated from the steps done since it.
  void update(long step, double sim_time, const char* time_unit = "");

  /// Draws the last reported state with the elapsed time and ends the line. Does nothing
  /// when disabled, if update() was never called, or the second time.
  void finish();

  bool enabled() const { return enabled_; }

 private:
  using Clock = std::chrono::steady_clock;
  void draw(Clock::time_point now, bool final);

  std::string label_;
  long total_;
  std::FILE* out_;
  bool enabled_;
  bool finished_ = false;
  bool drawn_ = false;

  long step_ = 0, first_step_ = 0;
  double sim_time_ = 0;
  long calls_ = 0;        ///< update() calls since the clock was last read
  long check_every_ = 1;  ///< read the clock every this many calls
  Clock::time_point start_, last_check_, last_draw_;
  int last_length_ = 0;   ///< visible length of the last line, to blank a shorter one
  std::array<char, 16> unit_{};
  std::array<char, 256> line_{};
};

}  // namespace mfv
