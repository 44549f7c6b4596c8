#pragma once
// VTK XML UnstructuredGrid (.vtu) writer and ParaView collection (.pvd) for time series.
// Arrays are written inline as base64 binary (Float64 values, Int64 connectivity/offsets, UInt8 types)
// with a UInt64 byte-count header, little-endian: exact values and about a third of the ASCII size.
#include <Eigen/Core>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace fibrane::io {

// VTK cell type codes (vtkCellType.h) used by fibrane.
namespace vtk_cell {
inline constexpr std::uint8_t vertex = 1;
inline constexpr std::uint8_t line = 3;
inline constexpr std::uint8_t poly_line = 4;
inline constexpr std::uint8_t triangle = 5;
inline constexpr std::uint8_t quad = 9;
}  // namespace vtk_cell

struct VtuMesh {
  std::vector<Eigen::Vector3d> points;
  // Cells in VTK layout: cell c uses connectivity[offsets[c-1] .. offsets[c]) (offsets[-1] = 0),
  // i.e. offsets holds the END of every cell, as in the .vtu format.
  std::vector<int> connectivity, offsets;
  std::vector<std::uint8_t> types;
  struct Field {
    std::string name;
    int components = 1;
    std::vector<double> values;  // values.size() = (points or cells) * components, point-major
  };
  std::vector<Field> point_data, cell_data;

  // Convenience: appends a cell with the given point indices and type.
  void add_cell(std::uint8_t type, std::initializer_list<int> point_ids);
};

// Throws std::invalid_argument if the mesh is inconsistent (offset/type counts, indices out of range,
// field sizes); the error names the offending field.
void validate(const VtuMesh& mesh);

// Writes `path` atomically (see atomic_file.hpp).
void write_vtu(const std::string& path, const VtuMesh& mesh);

// Standard base64 (RFC 4648) with padding.
std::string base64_encode(const void* data, std::size_t size);

// A ParaView time series: <Collection> of <DataSet timestep=... part=... file=...>. The .pvd is
// rewritten atomically after every add(), so it is valid while the run is still going.
class PvdCollection {
 public:
  explicit PvdCollection(std::string pvd_path);
  // `vtu_relative_path` is relative to the directory of the .pvd file.
  void add(double time, const std::string& vtu_relative_path, int part = 0);
  const std::string& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    double time;
    int part;
    std::string file;
  };
  void write() const;

  std::string path_;
  std::vector<Entry> entries_;
};

// Escapes &, <, >, " and ' for use in an XML attribute value.
std::string xml_escape(const std::string& text);

}  // namespace fibrane::io
