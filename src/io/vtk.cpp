#include "io/vtk.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "io/csv.hpp"

namespace fibrane::io {

static_assert(sizeof(double) == 8, "Float64 arrays are written from double");

void VtuMesh::add_cell(std::uint8_t type, std::initializer_list<int> point_ids) {
  connectivity.insert(connectivity.end(), point_ids.begin(), point_ids.end());
  offsets.push_back(static_cast<int>(connectivity.size()));
  types.push_back(type);
}

namespace {

bool is_little_endian() {
  const std::uint16_t probe = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

void validate_field(const VtuMesh::Field& field, std::size_t count, const char* where) {
  if (field.components < 1) {
    throw std::invalid_argument(fmt::format("vtu {} field '{}': components must be >= 1", where, field.name));
  }
  const std::size_t expected = count * static_cast<std::size_t>(field.components);
  if (field.values.size() != expected) {
    throw std::invalid_argument(fmt::format("vtu {} field '{}': {} values, expected {} ({} x {})", where,
                                            field.name, field.values.size(), expected, count,
                                            field.components));
  }
}

// One inline binary <DataArray>: base64 of (UInt64 byte count, raw little-endian values). For
// uncompressed data VTK reads header and payload from a single base64 stream.
template <typename T>
void append_data_array(std::string& out, const char* vtk_type, const std::string& name, int components,
                       const std::vector<T>& values, int indent) {
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::string raw(sizeof bytes + bytes, '\0');
  std::memcpy(raw.data(), &bytes, sizeof bytes);
  if (bytes > 0) std::memcpy(raw.data() + sizeof bytes, values.data(), bytes);
  out += fmt::format("{:{}}<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"binary\">\n",
                     "", indent, vtk_type, xml_escape(name), components);
  out += fmt::format("{:{}}{}\n", "", indent + 2, base64_encode(raw.data(), raw.size()));
  out += fmt::format("{:{}}</DataArray>\n", "", indent);
}

void append_fields(std::string& out, const char* section, const std::vector<VtuMesh::Field>& fields) {
  if (fields.empty()) return;
  out += fmt::format("      <{}>\n", section);
  for (const auto& field : fields) {
    append_data_array(out, "Float64", field.name, field.components, field.values, 8);
  }
  out += fmt::format("      </{}>\n", section);
}

}  // namespace

std::string base64_encode(const void* data, std::size_t size) {
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const std::size_t n = std::min<std::size_t>(3, size - i);
    std::uint32_t group = static_cast<std::uint32_t>(bytes[i]) << 16;
    if (n > 1) group |= static_cast<std::uint32_t>(bytes[i + 1]) << 8;
    if (n > 2) group |= bytes[i + 2];
    out += alphabet[(group >> 18) & 63];
    out += alphabet[(group >> 12) & 63];
    out += n > 1 ? alphabet[(group >> 6) & 63] : '=';
    out += n > 2 ? alphabet[group & 63] : '=';
  }
  return out;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

void validate(const VtuMesh& mesh) {
  if (mesh.offsets.size() != mesh.types.size()) {
    throw std::invalid_argument(
        fmt::format("vtu: {} offsets but {} cell types", mesh.offsets.size(), mesh.types.size()));
  }
  int previous_end = 0;
  for (const int end : mesh.offsets) {
    if (end < previous_end || static_cast<std::size_t>(end) > mesh.connectivity.size()) {
      throw std::invalid_argument("vtu: offsets must be non-decreasing cell ends within connectivity");
    }
    previous_end = end;
  }
  if (static_cast<std::size_t>(previous_end) != mesh.connectivity.size()) {
    throw std::invalid_argument("vtu: the last offset must equal the connectivity size");
  }
  for (const int id : mesh.connectivity) {
    if (id < 0 || static_cast<std::size_t>(id) >= mesh.points.size()) {
      throw std::invalid_argument(fmt::format("vtu: point index {} out of range [0, {})", id, mesh.points.size()));
    }
  }
  for (const auto& field : mesh.point_data) validate_field(field, mesh.points.size(), "point");
  for (const auto& field : mesh.cell_data) validate_field(field, mesh.types.size(), "cell");
}

void write_vtu(const std::string& path, const VtuMesh& mesh) {
  validate(mesh);
  if (!is_little_endian()) throw std::runtime_error("vtu writer assumes a little-endian machine");
  std::vector<double> coordinates;
  coordinates.reserve(3 * mesh.points.size());
  for (const auto& p : mesh.points) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  const std::vector<std::int64_t> connectivity(mesh.connectivity.begin(), mesh.connectivity.end());
  const std::vector<std::int64_t> offsets(mesh.offsets.begin(), mesh.offsets.end());

  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n";
  out += "  <UnstructuredGrid>\n";
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", mesh.points.size(),
                     mesh.types.size());
  append_fields(out, "PointData", mesh.point_data);
  append_fields(out, "CellData", mesh.cell_data);
  out += "      <Points>\n";
  append_data_array(out, "Float64", "Points", 3, coordinates, 8);
  out += "      </Points>\n";
  out += "      <Cells>\n";
  append_data_array(out, "Int64", "connectivity", 1, connectivity, 8);
  append_data_array(out, "Int64", "offsets", 1, offsets, 8);
  append_data_array(out, "UInt8", "types", 1, mesh.types, 8);
  out += "      </Cells>\n";
  out += "    </Piece>\n";
  out += "  </UnstructuredGrid>\n";
  out += "</VTKFile>\n";
  write_file_atomic(path, out);
}

PvdCollection::PvdCollection(std::string pvd_path) : path_(std::move(pvd_path)) { write(); }

void PvdCollection::add(double time, const std::string& vtu_relative_path, int part) {
  entries_.push_back({time, part, vtu_relative_path});
  write();
}

void PvdCollection::write() const {
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  out += "  <Collection>\n";
  for (const auto& entry : entries_) {
    out += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"/>\n",
                       format_double(entry.time), entry.part, xml_escape(entry.file));
  }
  out += "  </Collection>\n";
  out += "</VTKFile>\n";
  write_file_atomic(path_, out);
}

}  // namespace fibrane::io
