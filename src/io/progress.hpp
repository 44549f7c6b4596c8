#pragma once
// A single self-overwriting progress line on a terminal: step, t, Newton iterations, residual and an
// ETA from the average rate of simulated time per wall-clock second. When the output is not a terminal
// (log file, CI) it prints ordinary lines instead, at most one per `plain_interval`.
#include <chrono>
#include <iosfwd>
#include <string>

namespace fibrane::io {

class ProgressLine {
 public:
  using Clock = std::chrono::steady_clock;

  // Writes to std::cerr; interactive if stderr is a TTY.
  explicit ProgressLine(double t_end);
  // Explicit sink, mode and rate limits (tests, or a caller that wants stdout).
  ProgressLine(double t_end, std::ostream& out, bool interactive,
               Clock::duration tty_interval = std::chrono::milliseconds(100),
               Clock::duration plain_interval = std::chrono::seconds(10));

  // Paths on which t does not grow monotonically (arc-length continuation) get no percentage and no
  // ETA, which t could not predict, but the elapsed time.
  void set_monotone(bool monotone) { monotone_ = monotone; }
  // Reports the state after a converged step. Output is rate-limited; the first call always prints.
  void update(int step, double t, int iterations, double residual);
  // Replaces the progress line by `message` and ends the line.
  void finish(const std::string& message);

  // The text of the progress line for the given state (without control characters). `elapsed` is the
  // wall time since construction; the ETA assumes the average t-rate so far continues.
  std::string format(int step, double t, int iterations, double residual, Clock::duration elapsed) const;

 private:
  double t_end_;
  double t_start_ = 0.0;
  bool have_start_ = false;
  std::ostream& out_;
  bool interactive_;
  Clock::duration tty_interval_, plain_interval_;
  Clock::time_point started_ = Clock::now();
  Clock::time_point last_print_{};
  bool printed_ = false;
  bool line_open_ = false;  // a \r-line is on screen and needs clearing
  bool monotone_ = true;
};

// "12s", "3m05s", "2h07m"; "?" for a negative or non-finite number of seconds.
std::string format_duration(double seconds);

}  // namespace fibrane::io
