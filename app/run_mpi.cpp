#include "run_mpi.hpp"

#ifdef FIBRANE_HAVE_PETSC

#include <algorithm>
#include <iostream>
#include <optional>
#include <thread>

#include <CLI/CLI.hpp>

#include "case/case_reader.hpp"
#include "common/error.hpp"
#include "parallel/mpi_distribution.hpp"
#include "parallel/petsc_solver.hpp"
#include "parallel/session.hpp"

namespace fibrane::app {

bool mpi_available() { return true; }

namespace {

// Reads the case on every process and, for a distributed run, the solver its steps and --mpi-solver ask
// for. The processes agree on the outcome before any goes on, so that a process that failed alone cannot
// leave the others waiting in the run's first collective.
casefile::Case read_everywhere(const RunCommandOptions& o, const parallel::MpiDistribution& d, bool distributed,
                               parallel::PetscSolverOptions& solver) {
  std::optional<casefile::Case> c;
  std::string error;
  int code = 0;
  try {
    c = casefile::read_case(o.case_file, distributed ? &d : nullptr);
    if (distributed) {
      try {
        solver = parallel::petsc_solver_options(c->run.linear_solver, o.mpi_solver, c->model->symmetric());
        if (c->run.newton.local_newton > 0)
          throw InputError("steps.local_newton: local Newton solves are a serial run's (each process holds part "
                           "of the tangent); leave the key out in a distributed run");
      } catch (const InputError& e) {
        throw InputError(o.case_file + ": " + e.what());
      }
    }
  } catch (const InputError& e) {
    error = std::string("fibrane: error: ") + e.what();
    code = 2;
  } catch (const std::exception& e) {
    error = std::string("fibrane: failed: ") + e.what();
    code = 1;
  }
  if (!d.all(code == 0)) {
    const std::string first = d.first_text(error);
    if (d.rank() == 0) std::cerr << first << "\n";
    throw CLI::RuntimeError(code != 0 ? code : 2);
  }
  return std::move(*c);
}

}  // namespace

void run_mpi(const RunCommandOptions& o) {
  parallel::Session session;
  parallel::MpiDistribution distribution(session.comm());
  using solve::Partitioning;
  distribution.set_partitioning(o.partition == "contiguous" ? Partitioning::contiguous : Partitioning::graph);
  const bool distributed = session.size() > 1 || !o.mpi_solver.empty();
  parallel::PetscSolverOptions solver;
  casefile::Case c = read_everywhere(o, distribution, distributed, solver);
  const std::string& note = c.model->partition().note;
  if (distributed && session.rank() == 0 && !note.empty()) std::cerr << "fibrane: warning: " << note << "\n";
  apply_max_steps(c, o);
  run::RunOptions options = o.run;
  if (!o.restart_directory.empty()) {
    options.output_directory = o.restart_directory;
    options.restart = true;
  }
  if (distributed) {
    options.newton_log = options.newton_log && session.rank() == 0;  // one log, not one per process
    options.make_solver = [&](bool symmetric) {
      return parallel::make_petsc_solver(solver, symmetric, distribution, c.model->partition().unknowns);
    };
    // The processes on one machine share its cores.
    const int cores = static_cast<int>(std::thread::hardware_concurrency());
    if (options.threads == 0) options.threads = std::max(1, cores / session.local_size());
  }
  try {
    const run::RunSummary s = run::run_case(c, options);
    // No process leaves before the first has written summary.json: mpirun ends the others' processes when
    // one exits with a nonzero code (an interrupted or stopped run).
    distribution.all(true);
    if (session.rank() == 0) report(s);
    // Interrupted: the shell's convention 128 + signal, as a serial run (the processes agree on the signal).
    if (!s.result.completed()) throw CLI::RuntimeError(s.interrupted_by ? 128 + s.interrupted_by : 1);
  } catch (const CLI::RuntimeError&) {
    throw;
  } catch (const std::exception& e) {
    if (session.size() == 1) throw;
    const bool input = dynamic_cast<const InputError*>(&e) != nullptr;
    std::cerr << "fibrane (process " << session.rank() << " of " << session.size() << "): "
              << (input ? "error: " : "failed: ") << e.what() << "\n";
    session.abort(input ? 2 : 1);
  }
}

}  // namespace fibrane::app

#else

namespace fibrane::app {

bool mpi_available() { return false; }

void run_mpi(const RunCommandOptions&) {}

}  // namespace fibrane::app

#endif
