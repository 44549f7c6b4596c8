#include "run/checkpoint.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "io/checkpoint_file.hpp"

namespace fibrane::run {
namespace {

// A count stored as a double: a whole number in [0, limit]; InputError otherwise.
std::size_t whole(const io::CheckpointData& d, const std::string& name, const std::string& what, double limit) {
  const double v = d.scalar(name, what);
  if (!(v >= 0 && v <= limit && v == std::floor(v)))
    throw InputError(fmt::format("{}: the checkpoint entry '{}' is {}, not a count up to {}", what, name, v, limit));
  return static_cast<std::size_t>(v);
}

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
  std::vector<std::vector<io::PvdCollection::Entry>> series(whole(d, "vtk_series", what, 1e6));
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

// history.csv in `directory` must begin with its header and the `rows` rows the checkpoint vouches for,
// byte for byte (their hash); rows after them are a killed run's steps after its checkpoint, which the
// restart cuts off.
void check_history(const std::string& directory, const std::string& checkpoint, std::size_t rows,
                   const std::string& hash) {
  const std::string path = (std::filesystem::path(directory) / "history.csv").string();
  // The restart appends to it, and nothing is written through a link (io/csv.hpp).
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(path)))
    throw InputError(path + ": cannot continue it: it is not a regular file (a symbolic link)");
  const std::string text = io::read_regular_file(path, "history");
  std::size_t end = 0, lines = 0;
  for (; lines < rows + 1; ++lines) {
    const std::size_t newline = text.find('\n', end);
    if (newline == std::string::npos) break;
    end = newline + 1;
  }
  if (lines < rows + 1)
    throw InputError(fmt::format("{}: it has {} complete rows, the checkpoint ({}) vouches for {}: rows are missing",
                                 path, lines == 0 ? 0 : lines - 1, checkpoint, rows));
  if (fmt::format("{:016x}", fnv1a64(text.data(), end)) != hash)
    throw InputError(fmt::format("{}: its header and first {} rows differ from those the run wrote (their hash is in "
                                 "{}): the file was edited or damaged",
                                 path, rows, checkpoint));
}

}  // namespace

std::string case_fingerprint(const std::string& case_text) { return fmt::format("{:016x}", fnv1a64(case_text)); }

std::size_t write_checkpoint(const std::string& directory, const casefile::Case& c, const RunCheckpoint& k) {
  io::CheckpointData d;
  d.texts["case_fingerprint"] = case_fingerprint(c.text);
  d.texts["case_path"] = c.path;
  d.texts["method"] = k.method_name;
  d.texts["history_hash"] = fmt::format("{:016x}", k.output.history_hash);
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
  if (d.text("case_fingerprint", path) != case_fingerprint(c.text))
    throw InputError(fmt::format("{}: written for another case file, or '{}' was changed since: its text differs "
                                 "from the text the run started with (read from '{}'); restart with the case "
                                 "file as it was when the run started",
                                 path, c.path, d.text("case_path", path)));
  if (whole(d, "dofs", path, 2e9) != static_cast<std::size_t>(c.model->dofs.size()) ||
      whole(d, "free_dofs", path, 2e9) != static_cast<std::size_t>(c.model->constraints.num_free()))
    throw InputError(path + ": its DOF counts differ from the model's (another build of the case)");
  if (d.scalar("completed", path) != 0.0)
    throw InputError(fmt::format("{}: the run completed at t = {} (step {}); there is nothing to continue (run the "
                                 "case without --restart to start anew)",
                                 path, d.scalar("t", path), whole(d, "step", path, 2e9)));
  RunCheckpoint k;
  k.method_name = d.text("method", path);
  k.step = static_cast<int>(whole(d, "step", path, 2e9));
  k.t = d.scalar("t", path);
  const auto& q = d.array("q", path);
  if (static_cast<int>(q.size()) != c.model->constraints.num_free())
    throw InputError(path + ": its unknowns do not fit the model");
  k.q = Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(q.size()));
  k.output.history_rows = whole(d, "history_rows", path, 2e9);
  check_history(directory, path, k.output.history_rows, d.text("history_hash", path));
  k.output.series = get_series(d, path);
  k.stop_peak = d.scalar("stop_peak", path);
  k.limit_points = d.array("limit_points", path);
  k.method = get_state(d, "method.");
  k.model = get_state(d, "model.");
  return k;
}

}  // namespace fibrane::run
