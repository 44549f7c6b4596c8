#include "io/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace fibrane::io {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const long long s = std::llround(seconds);
  if (s < 60) return fmt::format("{}s", s);
  if (s < 3600) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}h{:02}m", s / 3600, (s % 3600) / 60);
}

ProgressLine::ProgressLine(double t_end) : ProgressLine(t_end, std::cerr, ::isatty(::fileno(stderr)) == 1) {}

ProgressLine::ProgressLine(double t_end, std::ostream& out, bool interactive, Clock::duration tty_interval,
                           Clock::duration plain_interval)
    : t_end_(t_end), out_(out), interactive_(interactive), tty_interval_(tty_interval),
      plain_interval_(plain_interval) {}

std::string ProgressLine::format(int step, double t, int iterations, double residual,
                                 Clock::duration elapsed) const {
  const double seconds = std::chrono::duration<double>(elapsed).count();
  if (!monotone_)
    return fmt::format("step {:>5}  t = {:.4e} (end {:.4e})  newton {:>2}  |r| = {:.2e}  elapsed {}", step, t, t_end_,
                       iterations, residual, format_duration(seconds));
  const double advanced = t - (have_start_ ? t_start_ : 0.0);
  double remaining_seconds = -1.0;  // unknown until time has advanced
  if (t >= t_end_) {
    remaining_seconds = 0.0;
  } else if (advanced > 0 && seconds > 0) {
    remaining_seconds = (t_end_ - t) * seconds / advanced;
  }
  const double percent = t_end_ > 0 ? 100.0 * t / t_end_ : 0.0;
  return fmt::format("step {:>5}  t = {:.4e} / {:.4e} ({:5.1f}%)  newton {:>2}  |r| = {:.2e}  ETA {}", step, t,
                     t_end_, percent, iterations, residual,
                     format_duration(remaining_seconds));
}

void ProgressLine::update(int step, double t, int iterations, double residual) {
  const Clock::time_point now = Clock::now();
  if (!have_start_) {
    // The rate is measured from the first report, so a run resumed at t > 0 gets a sensible ETA.
    have_start_ = true;
    t_start_ = t;
    started_ = now;
  }
  const Clock::duration interval = interactive_ ? tty_interval_ : plain_interval_;
  if (printed_ && now - last_print_ < interval) return;
  printed_ = true;
  last_print_ = now;
  const std::string text = format(step, t, iterations, residual, now - started_);
  if (interactive_) {
    out_ << '\r' << text << "\x1b[K" << std::flush;  // ESC[K clears what a longer line left behind
    line_open_ = true;
  } else {
    out_ << text << '\n' << std::flush;
  }
}

void ProgressLine::finish(const std::string& message) {
  if (line_open_) out_ << "\r\x1b[K";
  line_open_ = false;
  out_ << message << '\n' << std::flush;
}

}  // namespace fibrane::io
