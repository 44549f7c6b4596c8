#include <dlfcn.h>
#include <link.h>
#include <omp.h>

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

// OpenBLAS (pthreads or OpenMP build) starts its own pool at load time, sized by the cores, and keeps
// it whatever omp_set_num_threads says; openblas_set_num_threads bounds it. A process can hold more than
// one OpenBLAS: Debian's libopenblas.so.0 and the libblas.so.3 / liblapack.so.3 of its alternatives
// (which CHOLMOD and MUMPS call) are separate copies, each with its own pool, so the function is looked
// up in every loaded library, at run time (the reference BLAS has no threads and no such function).
// OpenMP builds of OpenBLAS also follow omp_set_num_threads.
namespace {

using SetThreads = void (*)(int);
using GetThreads = int (*)();

// The function `symbol` of every loaded library that has one, each once.
template <class F>
std::vector<F> blas_functions(const char* symbol) {
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        if (info->dlpi_name && *info->dlpi_name) static_cast<std::vector<std::string>*>(data)->push_back(info->dlpi_name);
        return 0;
      },
      &names);
  std::vector<F> out;
  for (const auto& name : names) {
    void* handle = dlopen(name.c_str(), RTLD_LAZY | RTLD_NOLOAD);
    if (!handle) continue;
    // dlsym on a library handle also searches its dependencies: keep each function once.
    if (auto* f = reinterpret_cast<F>(dlsym(handle, symbol)))
      if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
    dlclose(handle);
  }
  return out;
}

// Looked up once: the libraries are loaded at start-up.
const std::vector<SetThreads>& setters() {
  static const std::vector<SetThreads> f = blas_functions<SetThreads>("openblas_set_num_threads");
  return f;
}

const std::vector<GetThreads>& getters() {
  static const std::vector<GetThreads> f = blas_functions<GetThreads>("openblas_get_num_threads");
  return f;
}

void set_blas_threads(int n) {
  for (SetThreads f : setters()) f(n);
}

}  // namespace

void set_thread_count(int n) {
  if (n <= 0) return;
  omp_set_num_threads(n);
  set_blas_threads(n);
}

int blas_thread_count() {
  int most = -1;
  for (GetThreads f : getters()) most = std::max(most, f());
  return most;
}

BlasThreadsForFactor::BlasThreadsForFactor(long factor_nonzeros) {
  if (factor_nonzeros >= kSmallFactorEntries) return;
  const int now = blas_thread_count();
  if (now <= 1) return;
  restore_ = now;
  set_blas_threads(1);
}

BlasThreadsForFactor::~BlasThreadsForFactor() { restore(); }

void BlasThreadsForFactor::restore() {
  if (restore_ > 0) set_blas_threads(restore_);
  restore_ = -1;
}

SerialLibraryRegions::SerialLibraryRegions() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }

SerialLibraryRegions::~SerialLibraryRegions() { omp_set_max_active_levels(levels_); }

std::string blas_core_upgrade(const std::string& chosen, bool avx512, bool avx2_fma) {
  // OpenBLAS's x86-64 cores without AVX2 kernels (its names, compared without case)
  static const char* const kOld[] = {"prescott", "core2",   "penryn",    "dunnington", "nehalem",   "atom",
                                     "opteron",  "barcelona", "bobcat",  "athlon",     "sandybridge", "bulldozer",
                                     "piledriver", "katmai", "coppermine", "northwood",
                                     "banias",   "unknown"};
  std::string name = chosen;
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool old = std::find(std::begin(kOld), std::end(kOld), name) != std::end(kOld);
  if (!old) return {};
  if (avx512) return "SkylakeX";
  if (avx2_fma) return "Haswell";
  return {};
}

std::string blas_core_upgrade() {
  using CoreName = char* (*)();
  const std::vector<CoreName> names = blas_functions<CoreName>("openblas_get_corename");
  if (names.empty()) return {};
  const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
                      __builtin_cpu_supports("avx512vl");
  const bool avx2_fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  for (CoreName f : names)  // every loaded OpenBLAS: the first whose choice is too old decides
    if (std::string upgrade = blas_core_upgrade(f(), avx512, avx2_fma); !upgrade.empty()) return upgrade;
  return {};
}

}  // namespace fibrane::solve
