#pragma once
// PETSc and MPI for the lifetime of one command (src/parallel, FIBRANE_PETSC builds only): initialised
// without command-line arguments, so fibrane's options stay its own; PETSc options (e.g. MUMPS's
// -mat_mumps_icntl_35 2) come from the PETSC_OPTIONS environment variable.
#include <mpi.h>

namespace fibrane::parallel {

class Session {
 public:
  // Initialises PETSc (and MPI, unless it is running already). Throws std::runtime_error on failure.
  Session();
  // Finalises PETSc (and MPI if this session started it). Every process must get here: MPI_Finalize
  // waits for the others. A process that fails while others may wait in a collective calls abort().
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  MPI_Comm comm() const;
  int rank() const { return rank_; }
  int size() const { return size_; }
  // The number of processes of the run on this process's machine (shared-memory node).
  int local_size() const { return local_size_; }
  // Ends every process of the run with `code` (MPI_Abort); for errors that not all processes share.
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace fibrane::parallel
