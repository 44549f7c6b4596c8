#pragma once
// How much memory a run needs, apart from what it keeps. fibrane's allocator keeps freed memory resident
// for reuse while the system has it to spare (run/process_environment.cpp, common/system_memory.hpp), so
// a run's peak resident set (getrusage) depends on what the machine had available while it ran. The bytes
// the allocator has handed out and not taken back do not: InUsePeak samples them on a thread of its own.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>

namespace fibrane {

// The bytes malloc has handed out and not had back: in its heaps (mallinfo2's uordblks) and in blocks of
// their own mappings (hblkhd). Memory that other libraries map themselves (OpenBLAS's thread buffers) and
// the program's code are not in it.
std::size_t allocated_bytes();

// The largest allocated_bytes() seen from construction on: a sample every `every` on a thread that waits
// in between, and one at each peak() call. A peak that lasts less than `every` may be missed; a run's
// largest ones, a factor held through a factorisation's work arrays, last seconds.
class InUsePeak {
 public:
  explicit InUsePeak(std::chrono::milliseconds every = std::chrono::milliseconds(20));
  ~InUsePeak();
  InUsePeak(const InUsePeak&) = delete;
  InUsePeak& operator=(const InUsePeak&) = delete;

  std::size_t peak();

 private:
  void sample();

  std::chrono::milliseconds every_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::size_t peak_ = 0;
  std::thread thread_;
};

}  // namespace fibrane
