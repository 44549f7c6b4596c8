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
// PETSc options (PETSC_OPTIONS) reach the KSP and MUMPS: -mat_mumps_icntl_35 2 -mat_mumps_cntl_7 1e-8
// for block low-rank factors, -mat_mumps_icntl_28 2 -mat_mumps_icntl_29 1 for a parallel ordering.
#include <memory>

#include "parallel/mpi_distribution.hpp"
#include "linalg/linear_solver.hpp"

namespace fibrane::parallel {

struct PetscSolverOptions {
  // direct: a MUMPS factorisation of every tangent (KSPPREONLY). gmres: GMRES on the tangent
  // (right-preconditioned, so the tolerance is on |K x - b| / |b|) with the MUMPS factorisation of an
  // earlier tangent as preconditioner; a tangent is factorised afresh when GMRES does not reach the
  // tolerance within max_iterations.
  enum class Method { direct, gmres };
  Method method = Method::direct;
  int max_iterations = 30;
  double relative_tolerance = 1e-10;
};

// `symmetric`: the model promises symmetric tangents (model::Model::symmetric()). `distribution` and
// `ownership` (the model's partition().unknowns) must outlive the solver, and PETSc must be initialised
// (parallel::Session) for the solver's lifetime.
std::unique_ptr<solve::LinearSolver> make_petsc_solver(const PetscSolverOptions& options, bool symmetric,
                                                       const MpiDistribution& distribution,
                                                       const solve::UnknownOwnership& ownership);

}  // namespace fibrane::parallel
