#include "output/run_output.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <variant>

#include "case/case_interactions.hpp"
#include "case/case_methods.hpp"
#include "common/error.hpp"
#include "io/atomic_file.hpp"
#include "io/json.hpp"
#include "output/body_vtk.hpp"
#include "output/manifest.hpp"

namespace fibrane::output {

std::vector<std::string> history_columns(const model::Model& m, bool energy) {
  std::vector<std::string> columns{"step", "t", "load_factor", "iterations", "residual", "negative_eigenvalues",
                                   "limit_point"};
  for (const auto& o : model::observables(m)) columns.push_back(o.name);
  if (energy)
    for (const char* c : {"kinetic_energy", "interaction_energy", "external_work", "prescribed_work", "damping_work",
                          "energy_balance"})
      columns.push_back(c);
  return columns;
}

namespace {

// The names of the per-body and per-interaction files.
std::vector<std::string> output_names(const model::Model& m) {
  std::vector<std::string> names;
  for (const auto& s : m.shells) names.push_back(s.name());
  for (const auto& b : m.beams) names.push_back(b.name());
  for (const auto& i : m.interactions())
    for (const auto& p : i->point_series()) names.push_back(p.name);
  return names;
}

// The VTK series of a case, in the order write_vtk() writes them: per body its Bezier and/or sampled
// series, then the interactions' point series.
std::vector<std::string> vtk_series_names(const casefile::Case& c) {
  std::vector<std::string> names;
  const std::string sampled = c.output.bezier ? "_sampled" : "";
  auto body = [&](const std::string& name) {
    if (c.output.bezier) names.push_back(name);
    if (c.output.sampled) names.push_back(name + sampled);
  };
  for (const auto& s : c.model->shells) body(s.name());
  for (const auto& b : c.model->beams) body(b.name());
  for (const auto& i : c.model->interactions())
    for (const auto& p : i->point_series()) names.push_back(p.name);
  return names;
}

// A run into a directory that holds an earlier run's output removes that run's files first: otherwise a
// longer earlier run leaves steps beyond this run's end beside it, a run of another case leaves its other
// bodies' and interactions' files, an interrupted run keeps a summary saying "completed", and a collection
// of another VTK choice points at removed files. The files the earlier run's manifest lists are removed
// (output/manifest.hpp), and, for a directory without a manifest, the names this case writes
// (<name>[_sampled].pvd, <name>[_sampled]_<6 digits>.vtu, <name>_<6 digits>.csv, summary.json,
// checkpoint.bin); history.csv is replaced. Only regular files are removed, none through a link.
void remove_earlier_run(const std::filesystem::path& dir, const model::Model& m) {
  namespace fs = std::filesystem;
  std::vector<std::string> names = output_names(m);
  for (const auto& n : output_names(m)) names.push_back(n + "_sampled");
  auto is_step_file = [&](const fs::path& f, const std::string& ext) {
    const std::string stem = f.stem().string();
    if (f.extension() != ext || stem.size() < 8 || stem[stem.size() - 7] != '_') return false;
    const std::string digits = stem.substr(stem.size() - 6);
    if (digits.find_first_not_of("0123456789") != std::string::npos) return false;
    return std::find(names.begin(), names.end(), stem.substr(0, stem.size() - 7)) != names.end();
  };
  std::vector<std::string> known{"summary.json", kCheckpointFile};
  for (const auto& n : names) known.push_back(n + ".pvd");
  for (const auto& [sub, ext] : {std::pair{"vtk", ".vtu"}, std::pair{"interaction", ".csv"}}) {
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(dir / sub, ec))) continue;
    for (const auto& entry : fs::directory_iterator(dir / sub, ec))
      if (is_step_file(entry.path(), ext)) known.push_back(std::string(sub) + "/" + entry.path().filename().string());
  }
  remove_listed_files(dir.string(), read_manifest(dir.string()));
  remove_listed_files(dir.string(), known);
  for (const char* sub : {"vtk", "interaction"}) ::rmdir((dir / sub).c_str());  // if empty
}

// The entries a run writes through: vtk/ and interaction/ must be real directories (or absent), and a
// restart's history.csv a regular file. InputError before anything is written otherwise.
void check_entries(const std::filesystem::path& dir, bool resume) {
  namespace fs = std::filesystem;
  for (const char* sub : {"vtk", "interaction"}) {
    std::error_code ec;
    const fs::file_status s = fs::symlink_status(dir / sub, ec);
    if (fs::is_symlink(s))
      throw InputError((dir / sub).string() + ": is a symbolic link; fibrane writes and removes files only inside "
                       "the output directory (remove the link, or choose another output directory)");
    if (fs::exists(s) && !fs::is_directory(s))
      throw InputError((dir / sub).string() + ": exists and is not a directory");
  }
  std::error_code ec;
  const fs::file_status history = fs::symlink_status(dir / "history.csv", ec);
  if (resume && fs::exists(history) && !fs::is_regular_file(history))
    throw InputError((dir / "history.csv").string() + ": cannot continue it: it is not a regular file (a symbolic "
                     "link or another kind)");
}

}  // namespace

RunOutput::RunOutput(const casefile::Case& c, std::string directory, const OutputPosition* resume)
    : case_(c), dir_(std::move(directory)), observables_(model::observables(*c.model)) {
  namespace fs = std::filesystem;
  const std::string history = (fs::path(dir_) / "history.csv").string();
  energy_ = casefile::method_entry(c.run.method).traits.dynamic;
  const std::vector<std::string> names = c.output.vtk ? vtk_series_names(c) : std::vector<std::string>{};
  if (resume && resume->series.size() != names.size())
    throw InputError(dir_ + ": the checkpoint's VTK series do not match the case's output settings");
  check_entries(dir_, resume != nullptr);
  std::vector<std::string> listed{"history.csv", "summary.json", kCheckpointFile};
  for (const auto& n : names) listed.push_back(n + ".pvd");
  if (resume) {
    const std::vector<std::string> earlier = read_manifest(dir_);
    remove_listed_files(dir_, earlier, true);
    listed.insert(listed.end(), earlier.begin(), earlier.end());
  } else {
    remove_earlier_run(dir_, *c.model);
  }
  manifest_ = std::make_unique<Manifest>(dir_, listed);
  fs::create_directories(fs::path(dir_) / "vtk");
  bool tables = false;
  for (const auto& i : c.model->interactions())
    for (const auto& p : i->point_series()) tables |= p.table;
  if (tables) fs::create_directories(fs::path(dir_) / "interaction");
  if (resume) {
    std::error_code ec;
    fs::remove(fs::path(dir_) / "summary.json", ec);
    history_ = std::make_unique<io::CsvWriter>(history, history_columns(*c.model, energy_), resume->history_rows);
  } else {
    history_ = std::make_unique<io::CsvWriter>(history, history_columns(*c.model, energy_));
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string pvd = (fs::path(dir_) / (names[k] + ".pvd")).string();
    if (resume) series_.emplace_back(pvd, resume->series[k]);
    else series_.emplace_back(pvd);
  }
  for (const auto& i : c.model->interactions()) records_.push_back(i->run_record());
}

RunOutput::~RunOutput() = default;

void RunOutput::list(const std::string& relative_path) { manifest_->add(relative_path); }

OutputPosition RunOutput::position() const {
  OutputPosition p;
  p.history_rows = history_->rows_written();
  p.history_hash = history_->content_hash();
  for (const auto& s : series_) p.series.push_back(s.entries());
  return p;
}

void RunOutput::write_history(const model::Model& m, const solve::StepReport& r) {
  std::vector<double> row{static_cast<double>(r.step), r.t, m.functions(0, r.t), static_cast<double>(r.iterations),
                          r.residual_norm, static_cast<double>(r.negative_eigenvalues), r.limit_point ? 1.0 : 0.0};
  for (const auto& o : observables_) row.push_back(o.value(m));
  if (energy_) {
    // The energy balance E_kin + E_strain + E_interaction - W_ext - W_prescribed + D_damping: constant up to
    // the scheme's algorithmic dissipation (solve/generalized_alpha.hpp); the initial state has no account.
    const solve::EnergyReport e = r.energy.value_or(solve::EnergyReport{});
    const double interaction = m.energy(model::EnergyKind::interaction);
    const double balance = e.kinetic + m.strain_energy() + interaction - e.external_work - e.prescribed_work + e.damping;
    row.insert(row.end(), {e.kinetic, interaction, e.external_work, e.prescribed_work, e.damping, balance});
  }
  history_->row(row);
  for (const auto& i : m.interactions()) {
    const auto series = i->point_series();
    for (std::size_t k = 0; k < series.size(); ++k)
      if (series[k].table) write_table(series[k].name, i->point_table(k), r.step);
  }
  for (auto& record : records_)
    for (auto& w : record->step(r.step, r.t)) warnings_.push_back(std::move(w));
  recorded_ = true;
}

std::vector<std::string> RunOutput::take_warnings() {
  std::vector<std::string> out;
  out.swap(warnings_);
  return out;
}

void RunOutput::write_vtk(const model::Model& m, const solve::StepReport& r) {
  if (!case_.output.vtk) return;
  std::size_t k = 0;
  // body_vtk.hpp, series_timestep
  const bool by_path = casefile::method_entry(case_.run.method).traits.path_parametrised;
  auto write = [&](const std::string& name, io::VtuMesh mesh) {
    const std::string rel = fmt::format("vtk/{}_{:06d}.vtu", name, r.step);
    manifest_->add(rel);
    mesh.field_data = step_field_data(r, by_path);
    io::write_vtu((std::filesystem::path(dir_) / rel).string(), mesh);
    series_[k++].add(series_timestep(r, by_path), rel);
  };
  const auto& o = case_.output;
  const std::string sampled = o.bezier ? "_sampled" : "";
  for (const auto& s : m.shells) {
    if (o.bezier) write(s.name(), shell_bezier_vtu(m, s));
    if (o.sampled) write(s.name() + sampled, shell_vtu(m, s, o.samples));
  }
  for (const auto& b : m.beams) {
    if (o.bezier) write(b.name(), beam_bezier_vtu(m, b));
    if (o.sampled) write(b.name() + sampled, beam_vtu(m, b, o.samples));
  }
  for (const auto& i : m.interactions()) {
    const auto series = i->point_series();
    for (std::size_t n = 0; n < series.size(); ++n) write(series[n].name, point_cloud_vtu(i->point_cloud(n)));
  }
}

void RunOutput::write_table(const std::string& series, const model::PointTable& table, int step) const {
  std::string text;
  std::size_t rows = 0;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    const auto& col = table.columns[c];
    if (c > 0) text += ',';
    text += io::csv_field(col.name);
    const std::size_t n = col.texts.empty() ? col.numbers.size() : col.texts.size();
    if (c > 0 && n != rows) throw std::logic_error("point table of '" + series + "': columns of unequal length");
    rows = n;
  }
  text += "\n";
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < table.columns.size(); ++c) {
      const auto& col = table.columns[c];
      if (c > 0) text += ',';
      text += col.texts.empty() ? io::format_double(col.numbers[r]) : io::csv_field(col.texts[r]);
    }
    text += "\n";
  }
  const std::string rel = fmt::format("interaction/{}_{:06d}.csv", series, step);
  manifest_->add(rel);
  io::write_file_atomic((std::filesystem::path(dir_) / rel).string(), text);
}

namespace {

io::JsonValue json(const model::SummaryField& f) {
  return std::visit([](const auto& v) { return io::JsonValue(v); }, f.value);
}

}  // namespace

io::JsonValue RunOutput::interactions_json(const model::Model& m) const {
  io::JsonValue all = io::JsonValue::object();
  if (!recorded_) return all;
  for (std::size_t k = 0; k < m.interactions().size() && k < records_.size(); ++k) {
    io::JsonValue j = io::JsonValue::object();
    for (const auto& f : records_[k]->fields()) j.set(f.key, json(f));
    all.set(m.interactions()[k]->name(), std::move(j));
  }
  return all;
}

void RunOutput::write_summary(const model::Model& m, const solve::ContinuationResult& result, double wall_seconds,
                              const std::string& solver_name, const io::JsonValue* extra) {
  io::JsonValue j = io::JsonValue::object();
  j.set("case", case_.path).set("title", m.title).set("fibrane_version", FIBRANE_VERSION);
  j.set("dofs", m.dofs.size()).set("free_dofs", m.constraints.num_free()).set("elements", m.num_elements());
  j.set("completed", result.completed()).set("outcome", solve::outcome_name(result.outcome));
  j.set("message", result.message);
  j.set("t_reached", result.t_reached).set("steps", result.steps).set("newton_iterations", result.total_iterations);
  j.set("failed_attempts", result.failed_attempts).set("local_updates", result.local_updates);
  j.set("withdrawn_attempts", result.withdrawn_attempts);
  j.set("wall_seconds", wall_seconds).set("linear_solver", solver_name);
  io::JsonValue monitors = io::JsonValue::object();
  for (const auto& mon : m.monitors) monitors.set(mon->name(), mon->value(m));
  j.set("final_monitors", std::move(monitors));
  // The interaction kinds' sections (case/case_interactions.hpp), each present even when empty.
  for (const auto& section : casefile::interaction_kinds().summary_sections()) {
    io::JsonValue members = io::JsonValue::object();
    for (const auto& i : m.interactions())
      for (const auto& f : i->summary_sections())
        if (f.key == section) members.set(i->name(), json(f));
    j.set(section, std::move(members));
  }
  j.set("interactions", interactions_json(m));
  if (extra)
    for (const auto& [key, value] : extra->members()) j.set(key, value);
  io::write_file_atomic((std::filesystem::path(dir_) / "summary.json").string(), j.dump(2) + "\n");
}

}  // namespace fibrane::output
