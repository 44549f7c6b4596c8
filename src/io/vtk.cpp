#include "io/vtk.hpp"

#include <fmt/format.h>

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "common/parallel_errors.hpp"
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

const VtuMesh::Field* find_field(const std::vector<VtuMesh::Field>& fields, const char* name) {
  const auto it = std::find_if(fields.begin(), fields.end(), [&](const auto& f) { return f.name == name; });
  return it == fields.end() ? nullptr : &*it;
}

// The Bezier degree and weight fields have the shapes VTK expects, and each Bezier cell has the number
// of points its degrees need.
void validate_bezier(const VtuMesh& mesh) {
  const VtuMesh::Field* weights = find_field(mesh.point_data, vtk_bezier::weights);
  if (weights && weights->components != 1)
    throw std::invalid_argument(fmt::format("vtu point field '{}' must have 1 component", vtk_bezier::weights));
  const VtuMesh::Field* degrees = find_field(mesh.cell_data, vtk_bezier::degrees);
  if (!degrees) return;
  if (degrees->components != 3)
    throw std::invalid_argument(fmt::format("vtu cell field '{}' must have 3 components", vtk_bezier::degrees));
  for (std::size_t c = 0; c < mesh.types.size(); ++c) {
    const double p = degrees->values[3 * c], q = degrees->values[3 * c + 1];
    const int count = mesh.offsets[c] - (c == 0 ? 0 : mesh.offsets[c - 1]);
    const double expected = mesh.types[c] == vtk_cell::bezier_curve           ? p + 1
                            : mesh.types[c] == vtk_cell::bezier_quadrilateral ? (p + 1) * (q + 1)
                                                                              : count;
    if (count != expected)
      throw std::invalid_argument(fmt::format("vtu cell {}: {} points, its Bezier degrees ({}, {}) need {}", c,
                                              count, p, q, expected));
  }
}

// ASCII text of one value: shortest round-trip decimal for doubles, integers as numbers.
template <typename T>
std::string ascii_value(T value) {
  if constexpr (std::is_floating_point_v<T>) {
    return format_double(value);
  } else {
    return std::to_string(static_cast<long long>(value));
  }
}

// Collects the <DataArray> elements of one file in the chosen encoding; for the compressed encoding
// the arrays' block streams go to the appended section, each referenced by its offset from the first
// byte after the '_' that opens that section.
class ArrayWriter {
 public:
  explicit ArrayWriter(VtuEncoding encoding) : encoding_(encoding) {}

  template <typename T>
  void add(std::string& xml, const char* vtk_type, const std::string& name, int components,
           const std::vector<T>& values) {
    static constexpr int indent = 8;
    static constexpr const char* formats[] = {"appended", "binary", "ascii"};
    xml += fmt::format("{:{}}<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"{}\"", "", indent,
                       vtk_type, xml_escape(name), components, formats[static_cast<int>(encoding_)]);
    const std::size_t bytes = values.size() * sizeof(T);
    if (encoding_ == VtuEncoding::compressed) {
      xml += fmt::format(" offset=\"{}\"/>\n", appended_.size());
      appended_ += zlib_blocks(values.data(), bytes);
      return;
    }
    xml += ">\n";
    if (encoding_ == VtuEncoding::base64) {
      // One base64 stream of (UInt64 byte count, raw values), as VTK reads uncompressed inline data.
      const std::uint64_t header = bytes;
      std::string raw(sizeof header + bytes, '\0');
      std::memcpy(raw.data(), &header, sizeof header);
      if (bytes > 0) std::memcpy(raw.data() + sizeof header, values.data(), bytes);
      xml += fmt::format("{:{}}{}\n", "", indent + 2, base64_encode(raw.data(), raw.size()));
    } else {
      for (std::size_t i = 0; i < values.size(); i += components) {  // one tuple per line
        xml.append(indent + 2, ' ');
        for (int k = 0; k < components; ++k) {
          if (k > 0) xml += ' ';
          xml += ascii_value(values[i + k]);
        }
        xml += '\n';
      }
    }
    xml += fmt::format("{:{}}</DataArray>\n", "", indent);
  }

  const std::string& appended() const { return appended_; }

 private:
  VtuEncoding encoding_;
  std::string appended_;
};

// <PointData>/<CellData> with their fields; `attribute` names a field VTK should take as the attribute
// of the same name (RationalWeights, HigherOrderDegrees) if the mesh has it.
void append_fields(std::string& xml, ArrayWriter& arrays, const char* section, const std::vector<VtuMesh::Field>& fields,
                   const char* attribute) {
  if (fields.empty()) return;
  const bool tagged = find_field(fields, attribute) != nullptr;
  xml += fmt::format("      <{}{}>\n", section, tagged ? fmt::format(" {0}=\"{0}\"", attribute) : "");
  for (const auto& field : fields) arrays.add(xml, "Float64", field.name, field.components, field.values);
  xml += fmt::format("      </{}>\n", section);
}

}  // namespace

std::string zlib_blocks(const void* data, std::size_t size, std::size_t block_size) {
  if (block_size == 0) throw std::invalid_argument("zlib_blocks: block size must be > 0");
  const auto* bytes = static_cast<const unsigned char*>(data);
  const std::uint64_t blocks = (size + block_size - 1) / block_size;
  // The blocks are compressed independently, so side by side on OpenMP's threads; the stream is the same
  // bytes on any number of threads.
  std::vector<std::string> parts(blocks);
  std::vector<int> status(blocks, Z_OK);
  const auto count = static_cast<std::int64_t>(blocks);
  FirstError error;
#pragma omp parallel
  {
    std::string buffer;
    error.run([&] { buffer.resize(compressBound(static_cast<uLong>(std::min(block_size, size)))); });
#pragma omp for schedule(static)
    for (std::int64_t b = 0; b < count; ++b) error.run([&] {
      const std::size_t begin = static_cast<std::size_t>(b) * block_size, length = std::min(block_size, size - begin);
      uLongf compressed = static_cast<uLongf>(buffer.size());
      // zlib's default level: on fibrane's Float64 output about 5 % smaller than Z_BEST_SPEED, at about
      // 1.3 times its time.
      status[static_cast<std::size_t>(b)] = compress2(reinterpret_cast<Bytef*>(buffer.data()), &compressed, bytes + begin,
                                                      static_cast<uLong>(length), Z_DEFAULT_COMPRESSION);
      parts[static_cast<std::size_t>(b)].assign(buffer.data(), compressed);
    });
  }
  error.rethrow();
  std::vector<std::uint64_t> header{blocks, block_size, size % block_size};
  std::size_t total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    if (status[b] != Z_OK) throw std::runtime_error(fmt::format("zlib compress2 failed with status {}", status[b]));
    header.push_back(parts[b].size());
    total += parts[b].size();
  }
  std::string out(header.size() * sizeof(std::uint64_t), '\0');
  std::memcpy(out.data(), header.data(), out.size());
  out.reserve(out.size() + total);
  for (std::string& part : parts) {
    out += part;
    std::string().swap(part);
  }
  return out;
}

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
  for (const auto& field : mesh.field_data)
    if (field.components < 1 || field.values.empty() || field.values.size() % field.components != 0)
      throw std::invalid_argument(fmt::format("vtu field data '{}': {} values for {} components", field.name,
                                              field.values.size(), field.components));
  validate_bezier(mesh);
}

std::string vtu_document(const VtuMesh& mesh, VtuEncoding encoding) {
  validate(mesh);
  if (!is_little_endian()) throw std::runtime_error("vtu writer assumes a little-endian machine");
  std::vector<double> coordinates;
  coordinates.reserve(3 * mesh.points.size());
  for (const auto& p : mesh.points) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  const std::vector<std::int64_t> connectivity(mesh.connectivity.begin(), mesh.connectivity.end());
  const std::vector<std::int64_t> offsets(mesh.offsets.begin(), mesh.offsets.end());

  ArrayWriter arrays(encoding);
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += fmt::format("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                     "header_type=\"UInt64\"{}>\n",
                     encoding == VtuEncoding::compressed ? " compressor=\"vtkZLibDataCompressor\"" : "");
  xml += "  <UnstructuredGrid>\n";
  if (!mesh.field_data.empty()) {
    xml += "    <FieldData>\n";
    for (const auto& field : mesh.field_data) {
      xml += fmt::format("      <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" NumberOfTuples=\"{}\" "
                         "format=\"ascii\">\n       ",
                         xml_escape(field.name), field.components, field.values.size() / field.components);
      for (double v : field.values) {
        xml += ' ';
        xml += format_double(v);
      }
      xml += "\n      </DataArray>\n";
    }
    xml += "    </FieldData>\n";
  }
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", mesh.points.size(),
                     mesh.types.size());
  append_fields(xml, arrays, "PointData", mesh.point_data, vtk_bezier::weights);
  append_fields(xml, arrays, "CellData", mesh.cell_data, vtk_bezier::degrees);
  xml += "      <Points>\n";
  arrays.add(xml, "Float64", "Points", 3, coordinates);
  xml += "      </Points>\n";
  xml += "      <Cells>\n";
  arrays.add(xml, "Int64", "connectivity", 1, connectivity);
  arrays.add(xml, "Int64", "offsets", 1, offsets);
  arrays.add(xml, "UInt8", "types", 1, mesh.types);
  xml += "      </Cells>\n";
  xml += "    </Piece>\n";
  xml += "  </UnstructuredGrid>\n";
  if (encoding == VtuEncoding::compressed) {
    xml += "  <AppendedData encoding=\"raw\">\n   _";
    xml += arrays.appended();
    xml += "\n  </AppendedData>\n";
  }
  xml += "</VTKFile>\n";
  return xml;
}

void write_vtu(const std::string& path, const VtuMesh& mesh, VtuEncoding encoding) {
  write_file_atomic(path, vtu_document(mesh, encoding));
}

PvdCollection::PvdCollection(std::string pvd_path) : path_(std::move(pvd_path)) { write(); }

PvdCollection::PvdCollection(std::string pvd_path, std::vector<Entry> entries)
    : path_(std::move(pvd_path)), entries_(std::move(entries)) {
  write();
}

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
