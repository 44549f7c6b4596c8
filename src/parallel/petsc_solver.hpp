#pragma once
// A solve::LinearSolver for distributed runs. The matrix it is given is this process's summand of the
// tangent (model/model.hpp) in the model's numbering; the tangent is their sum, assembled into a PETSc
// matrix whose rows are the unknowns renumbered so that each process's owned unknowns
// (solve::UnknownOwnership, the model's partition) are a contiguous range, with the summands' entries
// that fall into other processes' rows sent there by PETSc (MatSetValues, ADD_VALUES), and factorised
// by MUMPS (MPI) behind a KSP. Right-hand sides and solutions are in the model's numbering.
// - symmetric tangents: MATSBAIJ (one triangle, taken from the summands' lower triangles as the serial
//   solvers read them) and MUMPS's LDL^T with pivoting (SYM = 2), which counts the negative eigenvalues
//   (MatGetInertia; with the root front factorised without ScaLAPACK, ICNTL(13) = 1, which the count
//   needs);
// - otherwise MATAIJ and MUMPS's LU (no eigenvalue count).
// A model that cannot promise symmetry (point moments) takes the symmetric path while its tangent is
// symmetric to round-off on every process (solve::SymmetryProbe on the summands), as "auto" does.
// analyze() preallocates the matrix exactly from the summands' patterns (row_pattern.hpp); while the
// pattern is unchanged (LinearSolver::analyze_if_needed with the system's pattern_version) factorize()
// only re-assembles the values and MUMPS refactorises, reusing its analysis. Every call is collective.
// PETSc options (PETSC_OPTIONS) reach the KSP and MUMPS after fibrane's settings, e.g. -mat_mumps_icntl_28 2
// -mat_mumps_icntl_29 1 for a parallel ordering where MUMPS was built with one.
#include <memory>

#include "parallel/mpi_distribution.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::parallel {

struct PetscSolverOptions {
  // direct: a MUMPS factorisation of every tangent (KSPPREONLY). gmres: GMRES on the tangent
  // (right-preconditioned, so the tolerance is on |K x - b| / |b|) with the MUMPS factorisation of an
  // earlier tangent as preconditioner, as the serial KrylovReuseSolver does: a solve that needs more than
  // max_iterations marks the factorisation stale (the next tangent is factorised), and one that does not
  // converge within 3 x max_iterations factorises the current tangent at once.
  enum class Method { direct, gmres };
  Method method = Method::direct;
  int max_iterations = 20;
  double relative_tolerance = 1e-10;
  // > 0: MUMPS's block low-rank factorisations (ICNTL(35) = 2) with this dropping tolerance (CNTL(7));
  // needs method gmres, which refines them.
  double low_rank = 0;
  bool lu = false;  // LU also for symmetric tangents (steps.solver: mumps-lu)
  // Non-empty: out-of-core factorisations (ICNTL(22) = 1), each process's factor in files of this directory.
  std::string out_of_core_directory;
};

// The distributed solver that a case's steps.solver, precision, low_rank, out_of_core and krylov
// (settings) and the command line's --mpi-solver ("" or "mumps": direct unless the case asks for Krylov
// solves; "gmres") ask for: `krylov` and `low_rank` take GMRES with the case's tolerance and iteration
// limit. InputError for what the distributed path cannot do: a serial solver named in steps.solver,
// `mumps` (LDL^T) for a model that cannot promise symmetric tangents (`symmetric_model`, as the serial
// path refuses it), precision: single (PETSc's scalars are double), out_of_core: when_needed (a serial
// run's choice per factorisation), or --mpi-solver mumps against the case's Krylov solves
// (petsc_solver_options.cpp).
PetscSolverOptions petsc_solver_options(const solve::LinearSolverSettings& settings, const std::string& mpi_solver,
                                        bool symmetric_model);

// `symmetric`: the model promises symmetric tangents (model::Model::symmetric()). `distribution` and
// `ownership` (the model's partition().unknowns) must outlive the solver, and PETSc must be initialised
// (parallel::Session) for the solver's lifetime.
std::unique_ptr<solve::LinearSolver> make_petsc_solver(const PetscSolverOptions& options, bool symmetric,
                                                       const MpiDistribution& distribution,
                                                       const solve::UnknownOwnership& ownership);

}  // namespace fibrane::parallel
