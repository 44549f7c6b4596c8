#pragma once
// `fibrane run` in builds with PETSc (FIBRANE_PETSC): every process of `mpirun -np N` reads the case and
// runs it; the model's elements and the linear solver are distributed (src/parallel).
#include <string>

#include "run/run.hpp"

namespace fibrane::app {

struct RunCommandOptions {
  std::string case_file;
  run::RunOptions run;
  int max_steps = 0;       // --max-steps: bounds the case's steps.max_steps; 0 keeps it
  std::string mpi_solver;  // "mumps" or "gmres": the distributed solver; empty: by the process count
  std::string restart_directory;  // --restart: continue the run in this directory
  std::string partition = "graph";  // --partition: graph or contiguous (solve::Partitioning)
};

// Lowers the case's steps.max_steps to options.max_steps when that is set and smaller.
void apply_max_steps(casefile::Case& c, const RunCommandOptions& options);

// Whether this fibrane was built with PETSc and MPI.
bool mpi_available();

// Runs the case under MPI: one process without --mpi-solver runs serially (the case's solver), several
// processes (or --mpi-solver) distributed. Errors while reading the case, which every process meets
// alike, end every process with exit code 2 (1 for other failures) and one message; an error during the
// run ends the whole run (MPI_Abort), since the other processes may be waiting for the failed one.
// --restart continues from the checkpoint, which holds the whole state in the model's numbering: any
// process count continues any process count's run. Throws CLI::RuntimeError(1) when the run stopped
// before its end, 128 + the signal when a signal interrupted it (on every process).
void run_mpi(const RunCommandOptions& options);

// Prints the run's closing line (stdout) and, for a run that stopped early, why (stderr).
void report(const run::RunSummary& s);

}  // namespace fibrane::app
