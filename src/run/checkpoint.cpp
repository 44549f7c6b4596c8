#include "run/checkpoint.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "common/error.hpp"
#include "io/checkpoint_file.hpp"

namespace fibrane::run {
namespace {

std::string checkpoint_path(const std::string& directory) {
  return (std::filesystem::path(directory) / output::kCheckpointFile).string();
}

void put_state(io::CheckpointData& d, const std::string& prefix, const solve::MethodState& s) {
  for (const auto& [key, values] : s) d.arrays[prefix + key] = values;
}

solve::MethodState get_state(const io::CheckpointData& d, const std::string& prefix) {
  solve::MethodState s;
  for (const auto& [key, values] : d.arrays)
    if (key.compare(0, prefix.size(), prefix) == 0) s[key.substr(prefix.size())] = values;
  return s;
}

// The VTK series' entries: times and parts as arrays, file names as one text of lines.
void put_series(io::CheckpointData& d, const output::OutputPosition& p) {
  d.arrays["vtk_series"] = {static_cast<double>(p.series.size())};
  for (std::size_t k = 0; k < p.series.size(); ++k) {
    std::vector<double> times, parts;
    std::string files;
    for (const auto& e : p.series[k]) {
      times.push_back(e.time);
      parts.push_back(e.part);
      files += e.file + "\n";
    }
    d.arrays[fmt::format("vtk.{}.time", k)] = std::move(times);
    d.arrays[fmt::format("vtk.{}.part", k)] = std::move(parts);
    d.texts[fmt::format("vtk.{}.files", k)] = std::move(files);
  }
}

std::vector<std::vector<io::PvdCollection::Entry>> get_series(const io::CheckpointData& d, const std::string& what) {
  std::vector<std::vector<io::PvdCollection::Entry>> series(static_cast<std::size_t>(d.scalar("vtk_series", what)));
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& times = d.array(fmt::format("vtk.{}.time", k), what);
    const auto& parts = d.array(fmt::format("vtk.{}.part", k), what);
    const std::string& files = d.text(fmt::format("vtk.{}.files", k), what);
    std::size_t start = 0;
    for (std::size_t i = 0; i < times.size(); ++i) {
      const std::size_t end = files.find('\n', start);
      if (end == std::string::npos || i >= parts.size()) throw InputError(what + ": its VTK series are damaged");
      series[k].push_back({times[i], static_cast<int>(parts[i]), files.substr(start, end - start)});
      start = end + 1;
    }
  }
  return series;
}

}  // namespace

std::string case_fingerprint(const std::string& case_path) {
  std::ifstream in(case_path, std::ios::binary);
  if (!in) throw InputError(case_path + ": cannot read the case file to check the checkpoint against it");
  std::uint64_t h = 14695981039346656037ULL;
  for (auto it = std::istreambuf_iterator<char>(in); it != std::istreambuf_iterator<char>(); ++it) {
    h ^= static_cast<unsigned char>(*it);
    h *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", h);
}

std::size_t write_checkpoint(const std::string& directory, const casefile::Case& c, const RunCheckpoint& k) {
  io::CheckpointData d;
  d.texts["case_fingerprint"] = case_fingerprint(c.path);
  d.texts["case_path"] = c.path;
  d.texts["method"] = k.method_name;
  d.arrays["dofs"] = {static_cast<double>(c.model->dofs.size())};
  d.arrays["free_dofs"] = {static_cast<double>(c.model->constraints.num_free())};
  d.arrays["step"] = {static_cast<double>(k.step)};
  d.arrays["t"] = {k.t};
  d.arrays["q"] = std::vector<double>(k.q.data(), k.q.data() + k.q.size());
  d.arrays["history_rows"] = {static_cast<double>(k.output.history_rows)};
  d.arrays["stop_peak"] = {k.stop_peak};
  d.arrays["limit_points"] = k.limit_points;
  d.arrays["completed"] = {k.completed ? 1.0 : 0.0};
  put_state(d, "method.", k.method);
  put_state(d, "model.", k.model);
  put_series(d, k.output);
  return io::write_checkpoint_file(checkpoint_path(directory), d);
}

RunCheckpoint read_checkpoint(const std::string& directory, const casefile::Case& c) {
  const std::string path = checkpoint_path(directory);
  const io::CheckpointData d = io::read_checkpoint_file(path);
  if (d.text("case_fingerprint", path) != case_fingerprint(c.path))
    throw InputError(fmt::format("{}: written for another case file (or '{}' was changed since: restart needs the "
                                 "case text the run started with; the checkpoint's run read '{}')",
                                 path, c.path, d.text("case_path", path)));
  if (static_cast<int>(d.scalar("dofs", path)) != c.model->dofs.size() ||
      static_cast<int>(d.scalar("free_dofs", path)) != c.model->constraints.num_free())
    throw InputError(path + ": its DOF counts differ from the model's (another build of the case)");
  if (d.scalar("completed", path) != 0.0)
    throw InputError(fmt::format("{}: the run completed at t = {} (step {}); there is nothing to continue (run the "
                                 "case without --restart to start anew)",
                                 path, d.scalar("t", path), static_cast<int>(d.scalar("step", path))));
  RunCheckpoint k;
  k.method_name = d.text("method", path);
  k.step = static_cast<int>(d.scalar("step", path));
  k.t = d.scalar("t", path);
  const auto& q = d.array("q", path);
  if (static_cast<int>(q.size()) != c.model->constraints.num_free())
    throw InputError(path + ": its unknowns do not fit the model");
  k.q = Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(q.size()));
  k.output.history_rows = static_cast<std::size_t>(d.scalar("history_rows", path));
  k.output.series = get_series(d, path);
  k.stop_peak = d.scalar("stop_peak", path);
  k.limit_points = d.array("limit_points", path);
  k.method = get_state(d, "method.");
  k.model = get_state(d, "model.");
  return k;
}

}  // namespace fibrane::run
