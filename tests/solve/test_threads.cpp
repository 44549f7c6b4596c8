// set_thread_count: the thread pools of OpenMP and of OpenBLAS follow it. SerialLibraryRegions keeps a
// library's regions on the calling thread. blas_core_upgrade: an OpenBLAS that chose an older kernel than
// the processor runs is given a fitting one.
#include <dlfcn.h>
#include <unistd.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdlib>
#include <string>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {
namespace {

// set_thread_count bounds OpenMP and OpenBLAS (the project links OpenBLAS: scripts/install-deps).
TEST(Threads, SetThreadCountBoundsOpenMpAndOpenBlas) {
  const int before = omp_get_max_threads();
  ASSERT_NE(blas_thread_count(), -1) << "the BLAS is not OpenBLAS";
  for (const int n : {1, 2, 1}) {
    set_thread_count(n);
    EXPECT_EQ(omp_get_max_threads(), n);
    EXPECT_EQ(blas_thread_count(), n);
  }
  set_thread_count(0);  // no change
  EXPECT_EQ(omp_get_max_threads(), 1);
  set_thread_count(before);
}

// The threads of a region that asks for four (as CHOLMOD's regions do: num_threads(4)).
int threads_of_a_four_thread_region() {
  int n = 0;
#pragma omp parallel num_threads(4)
  {
#pragma omp single
    n = omp_get_num_threads();
  }
  return n;
}

// SerialLibraryRegions: a region that asks for its own thread count runs on the calling thread alone while
// the guard lives, OpenMP's setting is back afterwards, and OpenBLAS's thread count is not touched.
TEST(Threads, SerialLibraryRegionsRunRegionsOnTheCallingThreadAlone) {
  const int before = omp_get_max_threads();
  set_thread_count(2);
  const int outside = threads_of_a_four_thread_region();
  if (outside < 2) GTEST_SKIP() << "OpenMP gives this process one thread (OMP_THREAD_LIMIT)";
  const int levels = omp_get_max_active_levels();
  {
    const SerialLibraryRegions serial;
    EXPECT_EQ(threads_of_a_four_thread_region(), 1);
    EXPECT_EQ(blas_thread_count(), 2);
  }
  EXPECT_EQ(omp_get_max_active_levels(), levels);
  EXPECT_EQ(threads_of_a_four_thread_region(), outside);
  set_thread_count(before);
}

TEST(BlasCore, TheRuleUpgradesOldKernelsOnlyWhereTheProcessorRunsNewerOnes) {
  EXPECT_EQ(blas_core_upgrade("Prescott", true, true), "SkylakeX");
  EXPECT_EQ(blas_core_upgrade("Prescott", false, true), "Haswell");
  EXPECT_EQ(blas_core_upgrade("Prescott", false, false), "");  // a processor without AVX2 keeps it
  EXPECT_EQ(blas_core_upgrade("NEHALEM", false, true), "Haswell");
  EXPECT_EQ(blas_core_upgrade("Unknown", true, true), "SkylakeX");
  for (const char* fitting : {"Haswell", "SkylakeX", "Zen", "CooperLake", "SapphireRapids", "Excavator"})
    EXPECT_EQ(blas_core_upgrade(fitting, true, true), "") << fitting;
}

// The expected upgrade of a Prescott choice on this processor.
std::string expected_from_prescott() {
  const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
                      __builtin_cpu_supports("avx512vl");
  return avx512 ? "SkylakeX" : __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? "Haswell" : "";
}

// OpenBLAS reads OPENBLAS_CORETYPE when it is loaded: the test runs itself again with Prescott forced (the
// choice Debian's OpenBLAS made on a virtual machine's Xeon) and reads OpenBLAS's choice in that process.
TEST(BlasCore, APrescottChoiceIsUpgradedToWhatThisProcessorRuns) {
  const char* forced = std::getenv("OPENBLAS_CORETYPE");
  if (forced && std::string(forced) == "Prescott") {  // the child
    using CoreName = char* (*)();
    auto* name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
    ASSERT_NE(name, nullptr);
    ASSERT_EQ(std::string(name()), "Prescott");
    EXPECT_EQ(blas_core_upgrade(), expected_from_prescott());
    return;
  }
  if (expected_from_prescott().empty()) GTEST_SKIP() << "this processor has no AVX2: Prescott's kernels may fit";
  const std::string command = "OPENBLAS_CORETYPE=Prescott /proc/" + std::to_string(getpid()) +
                              "/exe --gtest_filter=BlasCore.APrescottChoiceIsUpgradedToWhatThisProcessorRuns "
                              "> /dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0);
  // and this process's OpenBLAS, left to its own choice on this machine, is not upgraded unless it chose
  // an old kernel
  using CoreName = char* (*)();
  auto* name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  ASSERT_NE(name, nullptr);
  EXPECT_EQ(blas_core_upgrade().empty(), blas_core_upgrade(name(), true, true).empty());
}

}  // namespace
}  // namespace fibrane::solve
