#pragma once
// An exception thrown inside an OpenMP parallel region must not leave it (the runtime would call
// std::terminate): every parallel region whose body can throw runs that body through a FirstError, which
// keeps the first exception of the region, and rethrows it after the region.
#include <atomic>
#include <exception>
#include <mutex>

namespace fibrane {

// The first exception of the calls made through run(), from any thread; rethrow() after the parallel region.
// Later calls still run (they may be needed to keep the threads in step); their exceptions are dropped.
class FirstError {
 public:
  template <typename F>
  void run(F&& f) noexcept {
    try {
      f();
    } catch (...) {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      failed_.store(true, std::memory_order_relaxed);
    }
  }
  // True once a call has thrown: a loop may skip its remaining work.
  bool failed() const { return failed_.load(std::memory_order_relaxed); }
  // Outside the parallel region: throws the first exception caught, if any.
  void rethrow() {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
};

}  // namespace fibrane
