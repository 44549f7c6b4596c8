#pragma once
// SIGINT and SIGTERM during a run: the handler only records the signal; the run driver sees it after the
// current step's output is written, writes a checkpoint and an "interrupted" summary and ends the run.
// A second signal of either kind ends the process at once (the handler is reset after the first).
namespace fibrane::run {

// Installs the handlers for its lifetime (the previous ones come back on destruction).
class InterruptHandlers {
 public:
  InterruptHandlers();
  ~InterruptHandlers();
  InterruptHandlers(const InterruptHandlers&) = delete;
  InterruptHandlers& operator=(const InterruptHandlers&) = delete;
  // The signal received since installation (SIGINT or SIGTERM), or 0.
  static int received();
};

// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int signal);

}  // namespace fibrane::run
