#pragma once
// Each subcommand of the fibrane command line registers itself on the CLI11 app.
#include <CLI/CLI.hpp>

namespace fibrane::app {

void register_run_command(CLI::App& app);
void register_law_command(CLI::App& app);
void register_study_command(CLI::App& app);
// Sets OMP_THREAD_LIMIT (--threads N, or the cores) and OMP_WAIT_POLICY=passive unless the user set them,
// by re-executing the program once (openmp_environment.cpp says why). Returns only in the final process.
void configure_openmp_environment(int argc, char** argv);

}  // namespace fibrane::app
