// The settings of the OpenMP runtime, glibc's malloc and OpenBLAS that only the environment can give,
// applied by re-executing the program once before anything runs (libgomp, glibc and OpenBLAS read them
// when they are loaded, before main).
//
// Why: CHOLMOD's supernodal factorisation opens parallel regions with a fixed num_threads(4) clause for
// every supernode, whatever omp_set_num_threads says. On a 2-core machine that is twice as many threads as
// cores, and libgomp's default active waiting lets them spin between the many small regions, which costs
// system time on an idle machine and whole factorisations' worth of time on a busy one (docs/performance.md,
// "OpenBLAS threads: pthreads or OpenMP build"). OMP_THREAD_LIMIT (the cores, or --threads N) caps every
// region of every library, and OMP_WAIT_POLICY=passive lets idle threads sleep instead of spinning
// (fibrane's own calls of CHOLMOD's factorisation go further and keep its regions on the calling thread:
// solve::SerialLibraryRegions). A user's own setting of either variable is kept; likewise glibc's malloc
// tunables and OpenBLAS's waiting and kernel below.
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "run/process_environment.hpp"

#include "linalg/linear_solver.hpp"

namespace fibrane::run {
namespace {

// N of `--threads N` or `--threads=N` among the arguments, or 0.
int threads_argument(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) return std::atoi(argv[i + 1]);
    if (std::strncmp(argv[i], "--threads=", 10) == 0) return std::atoi(argv[i] + 10);
  }
  return 0;
}

// Sets `name` to `value` unless the environment already has it (the user's setting is kept) or `value` is
// empty; true where it set it.
bool set_default(const char* name, const std::string& value) {
  if (std::getenv(name) || value.empty()) return false;
  setenv(name, value.c_str(), 1);
  return true;
}

}  // namespace

void configure_process_environment(int argc, char** argv) {
  constexpr const char* kMarker = "FIBRANE_OPENMP_CONFIGURED";
  if (std::getenv(kMarker)) return;  // this is the re-executed process (or the user opted out)
  setenv(kMarker, "1", 1);
  bool changed = false;
  int limit = threads_argument(argc, argv);
  if (limit <= 0) limit = static_cast<int>(std::thread::hardware_concurrency());
  if (limit > 0) changed |= set_default("OMP_THREAD_LIMIT", std::to_string(limit));
  changed |= set_default("OMP_WAIT_POLICY", "passive");
  // glibc returns large freed blocks to the system (munmap, heap trimming), so the factorisation's and the
  // assembly's work arrays, allocated anew at every Newton iteration, fault in fresh zeroed pages each
  // time: with these thresholds the process keeps them (blocks up to 32 GiB come from the heap: the factor
  // of the membrane at 1.1 M unknowns is 5 GB), for half the page faults and a few per cent more peak
  // memory; fibrane hands freed memory back itself where memory is short (hand_back_needed in
  // common/system_memory.hpp). hugetlb=1 asks for transparent huge pages on malloc's memory (madvise;
  // where the system allows them), so that what is still faulted in comes 2 MiB at a time. arena_max=1
  // keeps every thread in the main arena: a thread's own arena grows in heaps of at most 64 MiB and serves
  // every larger block by mmap whatever the thresholds say, so the split factorisation's domains and the
  // pattern merge, which run on OpenMP's threads, would fault in their factors and arrays anew at every
  // iteration (docs/performance.md, "The paper-mesh bending run").
  changed |= set_default("GLIBC_TUNABLES",
                         "glibc.malloc.mmap_threshold=34359738368:glibc.malloc.trim_threshold=17179869184:"
                         "glibc.malloc.hugetlb=1:glibc.malloc.arena_max=1");
  // OpenBLAS's pthreads build keeps its idle worker threads spinning in sched_yield for 2^28 cycles (about
  // 0.1 s) after each BLAS call; between the factorisation's calls and through the assembly that follows,
  // they take turns with the threads that work, as system time. 2^20 cycles (under a millisecond) still
  // bridges the gaps between one factorisation's calls (docs/performance.md, "OpenBLAS threads").
  changed |= set_default("OPENBLAS_THREAD_TIMEOUT", "20");
  // A DYNAMIC_ARCH OpenBLAS that does not know the processor falls back to old kernels (linalg/linear_solver.hpp,
  // blas_core_upgrade); it reads OPENBLAS_CORETYPE when it is loaded.
  if (!std::getenv("OPENBLAS_CORETYPE")) changed |= set_default("OPENBLAS_CORETYPE", solve::blas_core_upgrade());
  if (changed) execv("/proc/self/exe", argv);  // on failure: go on with the settings as they are
}

}  // namespace fibrane::run
