// Placeholder until the 'study' subcommand lands.
#include "commands.hpp"

namespace fibrane::app {
void register_study_command(CLI::App& app) { app.add_subcommand("study", "(not yet available)"); }
}  // namespace fibrane::app
