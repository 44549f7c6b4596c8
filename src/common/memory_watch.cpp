#include "common/memory_watch.hpp"

#include <malloc.h>

#include <algorithm>

namespace fibrane {

std::size_t allocated_bytes() {
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

InUsePeak::InUsePeak(std::chrono::milliseconds every) : every_(every), peak_(allocated_bytes()) {
  thread_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, every_, [this] { return stop_; })) {
      lock.unlock();
      sample();
      lock.lock();
    }
  });
}

InUsePeak::~InUsePeak() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

std::size_t InUsePeak::peak() {
  sample();
  const std::lock_guard<std::mutex> lock(mutex_);
  return peak_;
}

void InUsePeak::sample() {
  const std::size_t now = allocated_bytes();
  const std::lock_guard<std::mutex> lock(mutex_);
  peak_ = std::max(peak_, now);
}

}  // namespace fibrane
