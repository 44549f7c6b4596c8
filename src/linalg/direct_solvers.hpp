#pragma once
// The sparse direct solvers behind make_linear_solver(), one by one: CHOLMOD and UMFPACK (SuiteSparse,
// suitesparse_solvers.cpp) and MUMPS (mumps_solver.cpp, built with FIBRANE_MUMPS). make_linear_solver()
// combines them for the case files' kinds; benchmarks and tests use them directly.
#include <memory>
#include <vector>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

// fibrane keeps freed memory in the process (run/process_environment.cpp: fewer page faults per
// iteration); a new pattern's factor is larger and rarely fits the old one's place. So every direct
// solver's analyze() frees the last factor and, where memory is short (hand_back_needed in
// common/system_memory.hpp), hands the freed memory back to the system (malloc_trim) before the new factor
// is made, instead of adding to the peak; elsewhere the freed memory stays for the new factor, which would
// otherwise fault its pages in anew.
void hand_back_freed_memory();

// malloc_trim whatever memory is left: for the out-of-core factorisations, whose factor files are read
// back through the system's page cache, which memory freed but kept would take the place of.
void hand_back_all_freed_memory();

// The memory one factorisation may take. kAvailableMemory: what the process can still allocate when the
// factorisation starts (available_memory()), less a share and a reserve for the rest of the step; 0: no
// limit; a positive value: that many MB. A factorisation that would need more fails, with a
// failure_detail() that says so, instead of growing until the system ends the process.
constexpr long kAvailableMemory = -1;
// The limit in bytes for `megabytes` as above; 0 when there is none (also when the memory is unknown).
double factorization_memory_limit(long megabytes);

// CHOLMOD supernodal LL^T of the lower triangle (symmetric positive definite). Name "cholmod";
// negative_eigenvalues() is 0 after a successful factorisation (a Cholesky factor exists only for a
// positive definite matrix; CHOLMOD stops at the first non-positive pivot). A factorisation whose factor
// would exceed `memory_limit_megabytes` (factorization_memory_limit) is not begun.
std::unique_ptr<LinearSolver> make_cholmod_llt(long memory_limit_megabytes = kAvailableMemory);

// CHOLMOD simplicial LDL^T of the lower triangle, without pivoting (symmetric, indefinite allowed while
// no pivot is zero). Name "ldlt"; negative_eigenvalues() counts the negative entries of D. The memory
// limit as for make_cholmod_llt.
std::unique_ptr<LinearSolver> make_cholmod_ldlt(long memory_limit_megabytes = kAvailableMemory);

// The pivot order of the last analysis of a solver from make_cholmod_llt() or make_cholmod_ldlt()
// (order[k] = the row and column of the matrix that is the k-th pivot: the fill-reducing ordering and
// CHOLMOD's postordering); empty for other solvers or before an analysis.
std::vector<int> cholmod_pivot_order(const LinearSolver& solver);

// CHOLMOD's fill-reducing pivot order (METIS or AMD, as CHOLMOD's default chooses) for the pattern of
// a's lower triangle, from a symbolic analysis alone.
std::vector<int> cholmod_ordering(const Eigen::SparseMatrix<double>& a);

// UMFPACK LU (any square matrix). Name "umfpack" (32-bit integer interface umfpack_di_*) or, with
// long_indices, "umfpack64" (umfpack_dl_*); negative_eigenvalues() is -1 (LU gives no inertia);
// failure_detail() names UMFPACK's status (a zero pivot is reported as a singular matrix).
std::unique_ptr<LinearSolver> make_umfpack(bool long_indices = false);

// Settings of the MUMPS solver (MUMPS 5.5 user guide numbering).
struct MumpsOptions {
  // ICNTL(7), the fill-reducing ordering: 0 AMD, 2 AMF, 3 SCOTCH, 4 PORD, 6 QAMD, 7 MUMPS's choice.
  // (5, METIS, is not in Debian's sequential build.)
  int ordering = 7;
  // ICNTL(35) = 2 and CNTL(7) = low_rank_tolerance: block low-rank factorisation, an approximate factor
  // (the solution's error grows with the tolerance; exact() is false). Off by default. With MUMPS's own
  // ordering (SCOTCH) Debian's build crashed in its BLR analysis on the bending tangent at 155 k unknowns
  // (docs/performance.md, "Symmetric indefinite solvers"); give it `cholmod_ordering`.
  bool low_rank = false;
  double low_rank_tolerance = 1e-10;
  // A pivot order (as cholmod_pivot_order gives it), used instead of `ordering` (ICNTL(7) = 1) by the
  // analyses of matrices of its size; empty: `ordering`.
  std::vector<int> pivot_order;
  // Each analysis takes CHOLMOD's pivot order for its pattern (cholmod_ordering), instead of `ordering`
  // and `pivot_order`: METIS, which Debian's sequential MUMPS lacks, with CHOLMOD's choice of AMD.
  bool cholmod_ordering = false;
  // SYM = 0: LU of the whole matrix with threshold partial pivoting (any non-singular matrix; no inertia).
  bool unsymmetric = false;
  // The factorisation in single precision (smumps): half the factor's memory and, where the BLAS rate
  // doubles, about half the time; solve() is then exact only to ~1e-7 relative times the condition
  // number, and exact() is false (KrylovReuseSolver refines it in double precision).
  bool single_precision = false;
  // Out-of-core factorisation (ICNTL(22) = 1): MUMPS writes the factor to files in this directory as it
  // is computed and reads it back at each solve, so only the active fronts stay in memory; empty: in core.
  // The files (named fibrane-<process id>-*) are deleted with the factor (a new analysis, or the solver's
  // end). The solution is the in-core factorisation's to round-off (exact() is unchanged).
  std::string out_of_core_directory;
  // With out_of_core_directory: each factorisation is in core where the analysis's in-core estimate, with
  // a tenth more, fits the memory limit (memory_limit_megabytes), and out of core where it does not or
  // where an in-core attempt stops for memory (INFOG(1) = -13, -19, or -9 at the limit). name() and
  // analysis_summary() tell which the last factorisation was.
  bool out_of_core_when_needed = false;
  // ICNTL(23), the most memory one factorisation may take (factorization_memory_limit). A factorisation
  // that would need more stops with INFOG(1) = -19, or -9 when delayed pivots outgrow it.
  long memory_limit_megabytes = kAvailableMemory;
};

// True when fibrane was built with MUMPS (FIBRANE_MUMPS, the default).
bool mumps_available();

// MUMPS symmetric LDL^T with threshold pivoting (SYM = 2) of the lower triangle: any symmetric matrix
// that is not numerically singular; negative_eigenvalues() is INFOG(12). With options.unsymmetric the LU
// of the whole matrix (SYM = 0), negative_eigenvalues() -1. Names "mumps" / "mumps-lu", with "-single"
// for single precision, "-blr" for block low-rank and "-ooc" out of core. Throws std::logic_error if !mumps_available().
std::unique_ptr<LinearSolver> make_mumps(const MumpsOptions& options = {});

}  // namespace fibrane::solve
