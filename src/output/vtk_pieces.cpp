#include "output/vtk_pieces.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "case/case_methods.hpp"
#include "io/atomic_file.hpp"
#include "io/pvtu.hpp"
#include "linalg/distribution.hpp"
#include "output/body_vtk.hpp"

namespace fibrane::output {

namespace {

// The VTK series of a case with their meshes (and their names alone), in the order RunOutput::write_vtk
// writes them.
std::vector<std::pair<std::string, io::VtuMesh>> series_meshes(const casefile::Case& c, const model::Model& m) {
  std::vector<std::pair<std::string, io::VtuMesh>> out;
  const auto& o = c.output;
  const std::string sampled = o.bezier ? "_sampled" : "";
  for (const auto& s : m.shells) {
    if (o.bezier) out.emplace_back(s.name(), shell_bezier_vtu(m, s));
    if (o.sampled) out.emplace_back(s.name() + sampled, shell_vtu(m, s, o.samples));
  }
  for (const auto& b : m.beams) {
    if (o.bezier) out.emplace_back(b.name(), beam_bezier_vtu(m, b));
    if (o.sampled) out.emplace_back(b.name() + sampled, beam_vtu(m, b, o.samples));
  }
  for (const auto& i : m.interactions()) {
    const auto series = i->point_series();
    for (std::size_t n = 0; n < series.size(); ++n) out.emplace_back(series[n].name, point_cloud_vtu(i->point_cloud(n)));
  }
  return out;
}

std::vector<std::string> series_names(const casefile::Case& c) {
  std::vector<std::string> names;
  const auto& o = c.output;
  const std::string sampled = o.bezier ? "_sampled" : "";
  auto body = [&](const std::string& name) {
    if (o.bezier) names.push_back(name);
    if (o.sampled) names.push_back(name + sampled);
  };
  for (const auto& s : c.model->shells) body(s.name());
  for (const auto& b : c.model->beams) body(b.name());
  for (const auto& i : c.model->interactions())
    for (const auto& p : i->point_series()) names.push_back(p.name);
  return names;
}

std::string piece_file(const std::string& series, int step, int rank) {
  return fmt::format("vtk/{}_{:06d}_{:04d}.vtu", series, step, rank);
}

// "vtk/<series>_<step>.vtu" -> "vtk/<series>_<step>.pvtu"
std::string pvtu_of(const std::string& vtu) { return vtu.substr(0, vtu.size() - 4) + ".pvtu"; }

}  // namespace

VtkPieces::VtkPieces(const casefile::Case& c, std::string directory, const model::Model& m, RunOutput* first,
                     const OutputPosition* resume)
    : case_(c), dir_(std::move(directory)), first_(first) {
  if (const solve::Distribution* d = m.distribution()) {
    rank_ = d->rank();
    size_ = d->size();
  }
  if (!first_) return;
  const std::vector<std::string> names = series_names(c);
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string pvd = names[k] + "_pieces.pvd";
    first_->list(pvd);
    const std::string path = (std::filesystem::path(dir_) / pvd).string();
    if (!resume || k >= resume->series.size()) {
      series_.emplace_back(path);
      continue;
    }
    // The pieces were written at the gathered series' steps.
    std::vector<io::PvdCollection::Entry> entries = resume->series[k];
    for (auto& e : entries) e.file = pvtu_of(e.file);
    series_.emplace_back(path, std::move(entries));
  }
}

void VtkPieces::write(const model::Model& m, const solve::StepReport& r) {
  const solve::Distribution* d = m.distribution();
  const bool by_path = casefile::method_entry(case_.run.method).traits.path_parametrised;
  auto meshes = series_meshes(case_, m);
  // Listed before any process creates them.
  if (first_)
    for (const auto& [name, mesh] : meshes) {
      first_->list(fmt::format("vtk/{}_{:06d}.pvtu", name, r.step));
      for (int p = 0; p < size_; ++p) first_->list(piece_file(name, r.step, p));
    }
  if (d) d->all(true);
  std::string error;
  try {
    for (auto& [name, mesh] : meshes) {
      mesh.field_data = step_field_data(r, by_path);
      const auto [begin, end] = io::piece_cells(static_cast<int>(mesh.types.size()), rank_, size_);
      io::write_vtu((std::filesystem::path(dir_) / piece_file(name, r.step, rank_)).string(),
                    io::vtu_piece(mesh, begin, end));
    }
  } catch (const std::exception& e) {
    error = fmt::format("process {}: {}", rank_, e.what());
  }
  if (d) error = d->first_text(error);
  if (!error.empty()) throw std::runtime_error("VTK pieces of step " + std::to_string(r.step) + ": " + error);
  if (!first_) return;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const std::string& name = meshes[k].first;
    std::vector<std::string> sources;
    for (int p = 0; p < size_; ++p) sources.push_back(std::filesystem::path(piece_file(name, r.step, p)).filename().string());
    const std::string rel = fmt::format("vtk/{}_{:06d}.pvtu", name, r.step);
    io::write_file_atomic((std::filesystem::path(dir_) / rel).string(), io::pvtu_document(meshes[k].second, sources));
    series_[k].add(series_timestep(r, by_path), rel);
  }
}

}  // namespace fibrane::output
