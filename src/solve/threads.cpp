#include <dlfcn.h>
#include <omp.h>

#include "solve/linear_solver.hpp"

namespace fibrane::solve {

// OpenBLAS (pthreads or OpenMP build) starts its own pool at load time, sized by the cores, and keeps
// it whatever omp_set_num_threads says; openblas_set_num_threads bounds it. The function is looked up
// at run time, so any BLAS links (the reference BLAS has no threads and no such function). OpenMP
// builds of OpenBLAS also follow omp_set_num_threads.
void set_thread_count(int n) {
  if (n <= 0) return;
  omp_set_num_threads(n);
  using SetThreads = void (*)(int);
  if (auto* f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(n);
}

int blas_thread_count() {
  using GetThreads = int (*)();
  auto* f = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return f ? f() : -1;
}

}  // namespace fibrane::solve
