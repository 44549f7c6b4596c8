// What memory that a process gets from the system costs at its first touch, against memory it already
// holds: the price of handing freed memory back (malloc_trim, munmap) and asking for it again later.
//
//   bench_fresh_memory [MEGABYTES] [PAUSE_SECONDS]
//
// Each round maps MEGABYTES of anonymous memory (with transparent huge pages asked for, as fibrane's malloc
// settings do, and without), writes it once (first touch: page faults and the kernel's zeroing) and again
// (the pages held), unmaps it and waits PAUSE_SECONDS. On a virtual machine whose host takes back the
// guest's free pages (a balloon's free page reporting), memory freed a few seconds before is slow to touch
// again; memory freed a moment before is not. docs/performance.md ("Memory handed back") has the figures.
#include <sys/mman.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One round: first-touch and second-touch times of `bytes` freshly mapped, in seconds; false if mmap fails.
bool touch_round(std::size_t bytes, bool huge, double& first, double& second) {
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return false;
  madvise(p, bytes, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
  auto t0 = std::chrono::steady_clock::now();
  std::memset(p, 1, bytes);
  first = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  std::memset(p, 2, bytes);
  second = seconds_since(t0);
  munmap(p, bytes);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  const long megabytes = argc > 1 ? std::atol(argv[1]) : 2048;
  const int pause = argc > 2 ? std::atoi(argv[2]) : 5;
  if (megabytes < 1 || pause < 0) {
    std::fprintf(stderr, "usage: bench_fresh_memory [MEGABYTES >= 1] [PAUSE_SECONDS >= 0]\n");
    return 2;
  }
  const std::size_t bytes = static_cast<std::size_t>(megabytes) << 20;
  // Round 0 takes the memory as the machine has it, round 1 what round 0 has just unmapped, round 2 the
  // same after the pause.
  std::printf("| huge pages | round | freed before [s] | first touch [s] | GB/s | second touch [s] | GB/s |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const bool huge : {true, false}) {
    for (int round = 0; round < 3; ++round) {
      const int waited = round == 2 ? pause : 0;
      if (waited > 0) sleep(static_cast<unsigned>(waited));
      double first = 0, second = 0;
      if (!touch_round(bytes, huge, first, second)) {
        std::fprintf(stderr, "bench_fresh_memory: mmap of %ld MiB failed\n", megabytes);
        return 1;
      }
      const std::string freed = round == 0 ? "-" : std::to_string(waited);
      std::printf("| %s | %d | %s | %.2f | %.2f | %.2f | %.2f |\n", huge ? "yes" : "no", round, freed.c_str(), first,
                  bytes / 1e9 / first, second, bytes / 1e9 / second);
    }
  }
  return 0;
}
