#pragma once
// The environment a run needs from before the program starts: OpenMP's thread limit and wait policy,
// glibc's malloc thresholds and OpenBLAS's waiting and kernel (process_environment.cpp says why each).
namespace fibrane::run {

/// Sets OMP_THREAD_LIMIT (`--threads N` among the arguments, or the cores), OMP_WAIT_POLICY=passive,
/// GLIBC_TUNABLES (malloc's mmap and trim thresholds), OPENBLAS_THREAD_TIMEOUT (how long OpenBLAS's idle
/// threads spin) and, where OpenBLAS chose a kernel older than the processor runs, OPENBLAS_CORETYPE,
/// each unless the user set it, by re-executing the program once.
/// Returns only in the final process. `fibrane` calls it first in main, and so do the bench programs that
/// time runs and factorisations, so that their figures are those of `fibrane run`.
/// FIBRANE_OPENMP_CONFIGURED=1 in the environment turns it off.
void configure_process_environment(int argc, char** argv);

}  // namespace fibrane::run
