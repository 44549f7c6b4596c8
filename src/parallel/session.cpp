#include "parallel/session.hpp"

#include <petscsys.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace fibrane::parallel {

Session::Session() {
  if (PetscInitializeNoArguments() != 0) throw std::runtime_error("PETSc initialisation failed");
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
  MPI_Comm_size(PETSC_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(PETSC_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &local_size_);
  MPI_Comm_free(&node);
}

Session::~Session() { PetscFinalize(); }

MPI_Comm Session::comm() const { return PETSC_COMM_WORLD; }

void Session::abort(int code) const {
  MPI_Abort(PETSC_COMM_WORLD, code);
  std::exit(code);  // MPI_Abort does not return; this keeps [[noreturn]] honest
}

}  // namespace fibrane::parallel
