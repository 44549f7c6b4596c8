#pragma once
// VTK XML UnstructuredGrid (.vtu) writer and ParaView collection (.pvd) for time series.
// Arrays are Float64 (points, fields), Int64 (connectivity, offsets) and UInt8 (cell types), little-endian
// with UInt64 headers, in one of three encodings (VtuEncoding): zlib-compressed raw appended binary (the
// default), inline base64, or ASCII. All three are exact: binary keeps the bits, ASCII uses the shortest
// decimal that reads back to the same double.
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
// Bezier cells. Points in VTK's higher-order order (vtkHigherOrderCurve / vtkHigherOrderQuadrilateral::
// PointIndexFromIJK): a curve lists its two end points, then the interior points; a quadrilateral its
// 4 corners, its edges, its interior (see io/bezier_vtu.hpp). Their degrees come from the cell field
// vtk_bezier::degrees, their weights from the point field vtk_bezier::weights.
inline constexpr std::uint8_t bezier_curve = 75;
inline constexpr std::uint8_t bezier_quadrilateral = 77;
}  // namespace vtk_cell

// Names of the fields VTK reads as the degrees and rational weights of Bezier cells. The writer marks
// a point field named `weights` (1 component) as the RationalWeights attribute and a cell field named
// `degrees` (3 components) as the HigherOrderDegrees attribute, which is how VTK finds them.
namespace vtk_bezier {
inline constexpr const char* weights = "RationalWeights";
inline constexpr const char* degrees = "HigherOrderDegrees";
}  // namespace vtk_bezier

// How write_vtu encodes the data arrays.
enum class VtuEncoding {
  compressed,  // <AppendedData encoding="raw">, each array zlib-compressed in 32 KiB blocks (smallest)
  base64,      // inline base64 of the raw bytes, uncompressed
  ascii,       // inline decimal text, for reading a file by eye (debugging, tests)
};

// An unstructured grid to write: points, cells in VTK layout, and Float64 point and cell fields.
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
  // Values of the whole data set (<FieldData>, written as ASCII), e.g. the step and its t; each field's
  // values.size() / components tuples.
  std::vector<Field> field_data;

  // Convenience: appends a cell with the given point indices and type.
  void add_cell(std::uint8_t type, std::initializer_list<int> point_ids);
};

// Throws std::invalid_argument if the mesh is inconsistent (offset/type counts, indices out of range,
// field sizes, the Bezier degree and weight fields' components, a Bezier cell whose point count does not
// match its degrees); the error names the offending field or cell.
void validate(const VtuMesh& mesh);

// The complete .vtu file content. Validates the mesh first.
std::string vtu_document(const VtuMesh& mesh, VtuEncoding encoding = VtuEncoding::compressed);

// Writes `path` atomically (see atomic_file.hpp): readers see the previous file or the complete new one.
void write_vtu(const std::string& path, const VtuMesh& mesh, VtuEncoding encoding = VtuEncoding::compressed);

// VTK's zlib block stream of one array (vtkZLibDataCompressor with a UInt64 header): the header
// [number of blocks, block size, size of the last block if partial (else 0), compressed size of each
// block] followed by the compressed blocks. Every block but the last holds `block_size` raw bytes.
std::string zlib_blocks(const void* data, std::size_t size, std::size_t block_size = 32768);

// Standard base64 (RFC 4648) with padding.
std::string base64_encode(const void* data, std::size_t size);

// A ParaView time series: <Collection> of <DataSet timestep=... part=... file=...>. The .pvd is
// rewritten atomically after every add(), so it is valid while the run is still going.
class PvdCollection {
 public:
  // One data set of the collection.
  struct Entry {
    double time;
    int part;
    std::string file;
  };
  explicit PvdCollection(std::string pvd_path);
  // Continues a series (a restarted run): writes the file with `entries`.
  PvdCollection(std::string pvd_path, std::vector<Entry> entries);
  // `vtu_relative_path` is relative to the directory of the .pvd file.
  void add(double time, const std::string& vtu_relative_path, int part = 0);
  const std::string& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }

  const std::vector<Entry>& entries() const { return entries_; }

 private:
  void write() const;

  std::string path_;
  std::vector<Entry> entries_;
};

// Escapes &, <, >, " and ' for use in an XML attribute value.
std::string xml_escape(const std::string& text);

}  // namespace fibrane::io
