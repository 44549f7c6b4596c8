#pragma once
// The sparse direct solvers behind make_linear_solver(), one by one: CHOLMOD and UMFPACK (SuiteSparse,
// suitesparse_solvers.cpp) and MUMPS (mumps_solver.cpp, built with FIBRANE_MUMPS). make_linear_solver()
// combines them for the case files' kinds; benchmarks and tests use them directly.
#include <memory>
#include <vector>

#include "solve/linear_solver.hpp"

namespace fibrane::solve {

// CHOLMOD supernodal LL^T of the lower triangle (symmetric positive definite). Name "cholmod";
// negative_eigenvalues() is 0 after a successful factorisation (a Cholesky factor exists only for a
// positive definite matrix; CHOLMOD stops at the first non-positive pivot).
std::unique_ptr<LinearSolver> make_cholmod_llt();

// CHOLMOD simplicial LDL^T of the lower triangle, without pivoting (symmetric, indefinite allowed while
// no pivot is zero). Name "ldlt"; negative_eigenvalues() counts the negative entries of D.
std::unique_ptr<LinearSolver> make_cholmod_ldlt();

// The pivot order of the last analysis of a solver from make_cholmod_llt() or make_cholmod_ldlt()
// (order[k] = the row and column of the matrix that is the k-th pivot: the fill-reducing ordering and
// CHOLMOD's postordering); empty for other solvers or before an analysis.
std::vector<int> cholmod_pivot_order(const LinearSolver& solver);

// UMFPACK LU (any square matrix). Name "umfpack"; negative_eigenvalues() is -1 (LU gives no inertia).
std::unique_ptr<LinearSolver> make_umfpack();

// Settings of the MUMPS solver (MUMPS 5.5 user guide numbering).
struct MumpsOptions {
  // ICNTL(7), the fill-reducing ordering: 0 AMD, 2 AMF, 3 SCOTCH, 4 PORD, 6 QAMD, 7 MUMPS's choice.
  // (5, METIS, is not in Debian's sequential build.)
  int ordering = 7;
  // ICNTL(35) = 2 and CNTL(7) = low_rank_tolerance: block low-rank factorisation, an approximate factor
  // (the solution's error grows with the tolerance). Off by default, and for experiments only: Debian's
  // build crashed in its BLR analysis (SCOTCH) on the bending tangent at 155 k unknowns
  // (docs/performance.md, "Symmetric indefinite solvers").
  bool low_rank = false;
  double low_rank_tolerance = 1e-10;
  // A pivot order (as cholmod_pivot_order gives it), used instead of `ordering` (ICNTL(7) = 1) by the
  // analyses of matrices of its size; empty: `ordering`.
  std::vector<int> pivot_order;
};

// True when fibrane was built with MUMPS (FIBRANE_MUMPS, the default).
bool mumps_available();

// MUMPS symmetric LDL^T with threshold pivoting (SYM = 2) of the lower triangle: any symmetric matrix
// that is not numerically singular. Name "mumps"; negative_eigenvalues() is INFOG(12). Throws
// std::logic_error if !mumps_available().
std::unique_ptr<LinearSolver> make_mumps(const MumpsOptions& options = {});

}  // namespace fibrane::solve
