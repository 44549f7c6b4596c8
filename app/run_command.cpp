// `fibrane run CASE.yaml [-o OUTDIR | --restart OUTDIR] [--threads N] [--max-steps N] [--quiet] [--newton-log]`;
// in builds with PETSc also `[--mpi-solver mumps|gmres] [--partition graph|contiguous]`, and
// `mpirun -np N fibrane run CASE.yaml` runs distributed (run_mpi.cpp).
#include <algorithm>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "common/error.hpp"
#include "case/case_reader.hpp"
#include "run/run.hpp"
#include "run_mpi.hpp"

namespace fibrane::app {

void report(const run::RunSummary& s) {
  std::cout << "fibrane: " << (s.result.completed() ? "completed" : "stopped") << " at t = " << s.result.t_reached
            << " after " << s.result.steps << " steps, " << s.result.total_iterations << " Newton iterations, "
            << s.wall_seconds << " s; results in " << s.directory << "\n";
  if (!s.result.completed()) std::cerr << "fibrane: " << s.result.message << "\n";
}

void apply_max_steps(casefile::Case& c, const RunCommandOptions& options) {
  if (options.max_steps > 0) c.run.steps.max_steps = std::min(c.run.steps.max_steps, options.max_steps);
}

void register_run_command(CLI::App& app) {
  auto opt = std::make_shared<RunCommandOptions>();
  auto* cmd = app.add_subcommand("run", "Run a case file: continuation to the end time, writing results");
  cmd->add_option("case", opt->case_file, "YAML case file (see docs/case-format.md)")->required();
  auto* output = cmd->add_option("-o,--output", opt->run.output_directory,
                                 "Output directory (default: the case's output.directory); an earlier run's files there are replaced");
  cmd->add_option("--restart", opt->restart_directory,
                  "Continue the run whose output (and checkpoint.bin) is in this directory, from its last checkpoint "
                  "(in builds with PETSc also with another number of processes than the run that wrote it)")
      ->excludes(output);
  cmd->add_option("--threads", opt->run.threads, "Threads of the assembly (OpenMP) and of the solvers' BLAS (default: all cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("-q,--quiet", opt->run.quiet, "No progress line");
  cmd->add_option("--max-steps", opt->max_steps,
                  "Stop after at most this many steps, at least 1 (default: the case's steps.max_steps)")
      ->check(CLI::Range(1, 100'000'000));
  cmd->add_flag("--newton-log", opt->run.newton_log,
                "One line per Newton iteration (t, iteration, |r|) and one per new tangent (the solver that takes "
                "it, and the negative eigenvalues where that solver counts them) on stderr");
  if (mpi_available())
    cmd->add_option("--mpi-solver", opt->mpi_solver,
                    "Distributed linear solver (also on one process): mumps (a MUMPS factorisation of every tangent, "
                    "the default under mpirun unless the case's steps ask for krylov or low_rank) or gmres (GMRES "
                    "preconditioned by an earlier tangent's factorisation)")
        ->check(CLI::IsMember({"mumps", "gmres"}));
  if (mpi_available())
    cmd->add_option("--partition", opt->partition,
                    "How a distributed run shares the mesh: graph (a PT-Scotch partition of the elements' adjacency "
                    "graph, the default) or contiguous (the unknowns in contiguous ranges)")
        ->check(CLI::IsMember({"graph", "contiguous"}));
  cmd->callback([opt]() {
    if (mpi_available()) {
      run_mpi(*opt);
      return;
    }
    // Reading the whole case first: bad input stops here, before any output file exists.
    casefile::Case c = casefile::read_case(opt->case_file);
    apply_max_steps(c, *opt);
    if (!opt->restart_directory.empty()) {
      opt->run.output_directory = opt->restart_directory;
      opt->run.restart = true;
    }
    const auto s = run::run_case(c, opt->run);
    report(s);
    // Interrupted: the shell's convention 128 + signal (130 for SIGINT, 143 for SIGTERM).
    if (!s.result.completed()) throw CLI::RuntimeError(s.interrupted_by ? 128 + s.interrupted_by : 1);
  });
}

}  // namespace fibrane::app
