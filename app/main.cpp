// The fibrane command line: `fibrane run CASE.yaml`, `fibrane law ...`, `fibrane study ...`.
#include <iostream>

#include "commands.hpp"
#include "common/error.hpp"
#include "run/process_environment.hpp"

// Exit codes: 0 completed; 1 a run that did not complete (failed, out of steps) or any other error; 2 bad
// input; 128 + signal for a run ended by SIGINT or SIGTERM. No exception leaves main.
int main(int argc, char** argv) {
  CLI::App app{"fibrane: van der Waals interactions between beams and shells"};
  try {
    fibrane::run::configure_process_environment(argc, argv);
    app.set_version_flag("--version", std::string("fibrane ") + FIBRANE_VERSION);
    app.require_subcommand(1);
    fibrane::app::register_run_command(app);
    fibrane::app::register_law_command(app);
    fibrane::app::register_study_command(app);
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a run that stopped early has already said why
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;  // usage errors are bad input
  } catch (const fibrane::InputError& e) {
    std::cerr << "fibrane: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "fibrane: failed: " << e.what() << "\n";
    return 1;
  } catch (...) {
    std::cerr << "fibrane: failed: an unknown error\n";
    return 1;
  }
  return 0;
}
