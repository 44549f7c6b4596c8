// `fibrane study NAME -o DIR [--coarse]`: the error study of paper Sec. 4 as CSV (docs/laws.md).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "common/error.hpp"
#include "laws/study.hpp"

namespace fibrane::app {

void register_study_command(CLI::App& app) {
  struct Options {
    std::string name, directory = ".";
    bool coarse = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("study", "Write the CSV of an error-study figure (fig6 ... fig12, or all)");
  cmd->add_option("name", o->name, "fig6, fig7, fig8, fig9, fig11, fig12 or all")->required();
  cmd->add_option("-o,--output", o->directory, "Output directory (created if missing)");
  cmd->add_flag("--coarse", o->coarse, "Fewer gap samples (quick look)");
  cmd->callback([o]() {
    std::vector<std::string> names = laws::study::figure_names();
    if (o->name != "all") {
      bool known = false;
      for (const auto& n : names) known = known || n == o->name;
      if (!known) throw InputError("unknown study '" + o->name + "' (fig6, fig7, fig8, fig9, fig11, fig12, all)");
      names = {o->name};
    }
    std::filesystem::create_directories(o->directory);
    for (const auto& name : names) {
      const auto start = std::chrono::steady_clock::now();
      const auto path = std::filesystem::path(o->directory) / (name + ".csv");
      std::ofstream out(path);
      if (!out) throw InputError("cannot write " + path.string());
      laws::study::write_figure(name, out, o->coarse);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cout << "fibrane: wrote " << path.string() << " (" << seconds << " s)\n";
    }
  });
}

}  // namespace fibrane::app
