// Placeholder until the 'law' subcommand lands.
#include "commands.hpp"

namespace fibrane::app {
void register_law_command(CLI::App& app) { app.add_subcommand("law", "(not yet available)"); }
}  // namespace fibrane::app
