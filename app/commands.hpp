#pragma once
// Each subcommand of the fibrane command line registers itself on the CLI11 app.
#include <CLI/CLI.hpp>

namespace fibrane::app {

void register_run_command(CLI::App& app);
void register_law_command(CLI::App& app);
void register_study_command(CLI::App& app);

}  // namespace fibrane::app
