// Placeholder until the 'run' subcommand lands.
#include "commands.hpp"

namespace fibrane::app {
void register_run_command(CLI::App& app) { app.add_subcommand("run", "(not yet available)"); }
}  // namespace fibrane::app
