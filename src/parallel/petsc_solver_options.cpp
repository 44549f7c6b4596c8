// The distributed solver's options from a case's settings (petsc_solver.hpp): what the distributed path
// can do of what the case asks for, and located refusals of the rest.
#include <string>

#include "common/error.hpp"
#include "parallel/petsc_solver.hpp"

namespace fibrane::parallel {

PetscSolverOptions petsc_solver_options(const solve::LinearSolverSettings& settings, const std::string& mpi_solver,
                                        bool symmetric_model) {
  const std::string& kind = settings.kind;
  if (kind != "auto" && kind != "mumps" && kind != "mumps-lu")
    throw InputError("steps.solver: '" + kind + "' is a serial solver; a distributed run factorises with MUMPS "
                     "through PETSc: use auto (LDL^T while the tangent is symmetric, LU otherwise), mumps or mumps-lu");
  if (kind == "mumps" && !symmetric_model)
    throw InputError("steps.solver: 'mumps' (LDL^T) needs a symmetric tangent, which this model cannot promise; "
                     "use auto or mumps-lu");
  if (settings.precision != "double")
    throw InputError("steps.precision: '" + settings.precision + "' is not available in a distributed run: "
                     "PETSc's scalars are double precision, and its MUMPS factorises in them");
  const bool krylov = settings.krylov || settings.low_rank > 0;
  if (mpi_solver == "mumps" && krylov)
    throw InputError(std::string("--mpi-solver mumps asks for direct solves, but the case's steps.") +
                     (settings.low_rank > 0 ? "low_rank" : "krylov") + " asks for Krylov solves: drop one");
  if (settings.out_of_core_when_needed)
    throw InputError("steps.out_of_core: 'when_needed' is a serial run's choice per factorisation; in a distributed "
                     "run each process's factor is in memory, or in files with out_of_core: true or a directory");
  PetscSolverOptions o;
  o.lu = kind == "mumps-lu";
  o.out_of_core_directory = settings.out_of_core_directory;
  if (krylov) {
    o.method = PetscSolverOptions::Method::gmres;
    o.relative_tolerance = settings.krylov_tolerance;
    o.max_iterations = settings.krylov_max_iterations;
    o.low_rank = settings.low_rank;
  } else if (mpi_solver == "gmres") {
    o.method = PetscSolverOptions::Method::gmres;
  }
  return o;
}

}  // namespace fibrane::parallel
