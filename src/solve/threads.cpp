#include <dlfcn.h>
#include <link.h>
#include <omp.h>

#include <string>
#include <vector>

#include "solve/linear_solver.hpp"

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

// The openblas_set_num_threads / openblas_get_num_threads of every loaded library that has one.
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
    if (auto* f = reinterpret_cast<F>(dlsym(handle, symbol))) {
      bool seen = false;
      for (F g : out) seen |= g == f;
      if (!seen) out.push_back(f);
    }
    dlclose(handle);
  }
  return out;
}

}  // namespace

void set_thread_count(int n) {
  if (n <= 0) return;
  omp_set_num_threads(n);
  for (SetThreads f : blas_functions<SetThreads>("openblas_set_num_threads")) f(n);
}

int blas_thread_count() {
  int most = -1;
  for (GetThreads f : blas_functions<GetThreads>("openblas_get_num_threads")) most = std::max(most, f());
  return most;
}

}  // namespace fibrane::solve
