#include "io/pvtu.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace fibrane::io {

std::pair<int, int> piece_cells(int cells, int piece, int pieces) {
  if (pieces < 1 || piece < 0 || piece >= pieces || cells < 0)
    throw std::invalid_argument(fmt::format("piece_cells: piece {} of {} over {} cells", piece, pieces, cells));
  const auto at = [&](int p) { return static_cast<int>(static_cast<long long>(cells) * p / pieces); };
  return {at(piece), at(piece + 1)};
}

VtuMesh vtu_piece(const VtuMesh& whole, int begin, int end) {
  const int cells = static_cast<int>(whole.types.size());
  if (begin < 0 || end < begin || end > cells)
    throw std::invalid_argument(fmt::format("vtu_piece: cells [{}, {}) of {}", begin, end, cells));
  const auto first = [&](int c) { return c == 0 ? 0 : whole.offsets[static_cast<std::size_t>(c - 1)]; };
  // The points the cells use, numbered in the whole grid's order.
  std::vector<int> number(whole.points.size(), -1);
  for (int k = first(begin); k < first(end); ++k) number[static_cast<std::size_t>(whole.connectivity[k])] = 0;
  VtuMesh piece;
  std::vector<int> kept;
  for (std::size_t p = 0; p < number.size(); ++p)
    if (number[p] == 0) {
      number[p] = static_cast<int>(kept.size());
      kept.push_back(static_cast<int>(p));
      piece.points.push_back(whole.points[p]);
    }
  for (int c = begin; c < end; ++c) {
    for (int k = first(c); k < first(c + 1); ++k) piece.connectivity.push_back(number[whole.connectivity[k]]);
    piece.offsets.push_back(static_cast<int>(piece.connectivity.size()));
    piece.types.push_back(whole.types[static_cast<std::size_t>(c)]);
  }
  const auto select = [](const VtuMesh::Field& f, auto&& indices) {
    VtuMesh::Field out{f.name, f.components, {}};
    for (int i : indices)
      for (int j = 0; j < f.components; ++j) out.values.push_back(f.values[static_cast<std::size_t>(i * f.components + j)]);
    return out;
  };
  for (const auto& f : whole.point_data) piece.point_data.push_back(select(f, kept));
  std::vector<int> cell_ids;
  for (int c = begin; c < end; ++c) cell_ids.push_back(c);
  for (const auto& f : whole.cell_data) piece.cell_data.push_back(select(f, cell_ids));
  piece.field_data = whole.field_data;
  return piece;
}

namespace {

void declare(std::string& xml, const char* section, const std::vector<VtuMesh::Field>& fields, const char* attribute) {
  if (fields.empty()) return;
  bool tagged = false;
  for (const auto& f : fields) tagged = tagged || f.name == attribute;
  xml += fmt::format("    <{}{}>\n", section, tagged ? fmt::format(" {0}=\"{0}\"", attribute) : "");
  for (const auto& f : fields)
    xml += fmt::format("      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", xml_escape(f.name),
                       f.components);
  xml += fmt::format("    </{}>\n", section);
}

}  // namespace

std::string pvtu_document(const VtuMesh& like, const std::vector<std::string>& sources) {
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  declare(xml, "PPointData", like.point_data, vtk_bezier::weights);
  declare(xml, "PCellData", like.cell_data, vtk_bezier::degrees);
  xml += "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const auto& s : sources) xml += fmt::format("    <Piece Source=\"{}\"/>\n", xml_escape(s));
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  return xml;
}

}  // namespace fibrane::io
