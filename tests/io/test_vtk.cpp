// The .vtu writer is checked against VTK itself: python3-vtk9's vtkXMLUnstructuredGridReader reads the
// file (in each encoding) and prints every coordinate, cell and field value with repr (shortest
// round-trip), which we compare bitwise with what was written. The .pvd is checked with Python's XML
// parser.
#include <gtest/gtest.h>
#include <omp.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <random>
#include <sstream>

#include "io/scratch_dir.hpp"
#include "io/vtk.hpp"

namespace fibrane::io {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Two quads sharing an edge, a line and a vertex; values chosen to need all 17 digits.
VtuMesh sample_mesh() {
  VtuMesh mesh;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) mesh.points.emplace_back(i / 3.0, j * std::sqrt(2.0), -0.1 * i * j);
  }
  mesh.add_cell(vtk_cell::quad, {0, 1, 4, 3});
  mesh.add_cell(vtk_cell::quad, {1, 2, 5, 4});
  mesh.add_cell(vtk_cell::line, {0, 5});
  mesh.add_cell(vtk_cell::vertex, {2});
  VtuMesh::Field displacement{"displacement", 3, {}};
  VtuMesh::Field gap{"gap <min> & \"max\"", 1, {}};
  for (std::size_t p = 0; p < mesh.points.size(); ++p) {
    for (int c = 0; c < 3; ++c) displacement.values.push_back(std::exp(-double(p)) * (c + 1) / 7.0);
    gap.values.push_back(1e-300 * double(p) - 1.0 / 3.0);
  }
  mesh.point_data = {displacement, gap};
  mesh.cell_data = {{"cell_id", 1, {0, 1, 2, 3}}, {"stress", 2, {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 1e100}}};
  return mesh;
}

// A sampled shell-like output: an n x n grid of points on a wavy sheet with quads, a displacement and a
// section-force-like field. n = 64 makes every array span several 32 KiB compression blocks, and the
// 1-component field exactly one full block (4096 doubles).
VtuMesh sampled_mesh(int n) {
  VtuMesh mesh;
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 1.0);
  VtuMesh::Field displacement{"displacement", 3, {}}, forces{"N_local", 3, {}}, gap{"gap", 1, {}};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i / (n - 1.0), y = j / (n - 1.0);
      mesh.points.emplace_back(x, y, 0.1 * std::sin(6 * x) * std::cos(5 * y));
      displacement.values.insert(displacement.values.end(), {1e-3 * x * y, -2e-3 * x, 0.05 * std::sin(3 * y)});
      forces.values.insert(forces.values.end(), {noise(rng), noise(rng), 1e5 * noise(rng)});
      gap.values.push_back(std::exp(-x - y));
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) mesh.add_cell(vtk_cell::quad, {j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i});
  mesh.point_data = {displacement, forces, gap};
  return mesh;
}

const char* const kReadVtu = R"(
import sys, vtk
errors = []
reader = vtk.vtkXMLUnstructuredGridReader()
reader.AddObserver("ErrorEvent", lambda obj, ev: errors.append(ev))
reader.SetFileName(sys.argv[1])
reader.Update()
if errors or reader.GetErrorCode() != 0:
    sys.exit(3)
grid = reader.GetOutput()
out = open(sys.argv[2], "w")
out.write("npoints %d\nncells %d\n" % (grid.GetNumberOfPoints(), grid.GetNumberOfCells()))
for i in range(grid.GetNumberOfPoints()):
    out.write("point " + " ".join(repr(x) for x in grid.GetPoint(i)) + "\n")
for c in range(grid.GetNumberOfCells()):
    ids = grid.GetCell(c).GetPointIds()
    out.write("cell %d " % grid.GetCellType(c) + " ".join(str(ids.GetId(k)) for k in range(ids.GetNumberOfIds())) + "\n")
for kind, data in (("pdata", grid.GetPointData()), ("cdata", grid.GetCellData())):
    for a in range(data.GetNumberOfArrays()):
        arr = data.GetArray(a)
        values = [arr.GetComponent(t, k) for t in range(arr.GetNumberOfTuples()) for k in range(arr.GetNumberOfComponents())]
        out.write("%s %s\n%d %s\n" % (kind, arr.GetName(), arr.GetNumberOfComponents(), " ".join(repr(v) for v in values)))
)";

std::vector<double> numbers(std::istringstream& line) {
  std::vector<double> values;
  for (std::string token; line >> token;) values.push_back(std::strtod(token.c_str(), nullptr));
  return values;
}

void expect_bitwise(const std::vector<double>& got, const std::vector<double>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_TRUE(same_bits(got[i], want[i])) << what << "[" << i << "]";
}

// Writes `mesh`, has VTK read it and compares everything VTK reports bitwise with the mesh.
void expect_vtk_reads_back(const testing::ScratchDir& dir, const VtuMesh& mesh, VtuEncoding encoding) {
  write_vtu(dir.file("mesh.vtu"), mesh, encoding);
  testing::write_text(dir.file("read.py"), kReadVtu);
  const std::string command = "/usr/bin/python3 " + dir.file("read.py") + " " + dir.file("mesh.vtu") + " " +
                              dir.file("dump.txt");
  ASSERT_EQ(std::system(command.c_str()), 0) << "VTK could not read the file";

  std::istringstream dump(testing::read_text(dir.file("dump.txt")));
  std::string line, tag;
  std::size_t point = 0, cell = 0;
  std::vector<const VtuMesh::Field*> fields_seen;
  while (std::getline(dump, line)) {
    std::istringstream in(line);
    in >> tag;
    if (tag == "npoints" || tag == "ncells") {
      std::size_t n = 0;
      in >> n;
      EXPECT_EQ(n, tag == "npoints" ? mesh.points.size() : mesh.types.size()) << tag;
    } else if (tag == "point") {
      ASSERT_LT(point, mesh.points.size());
      const Eigen::Vector3d& p = mesh.points[point++];
      expect_bitwise(numbers(in), {p.x(), p.y(), p.z()}, "point");
    } else if (tag == "cell") {
      ASSERT_LT(cell, mesh.types.size());
      int type = 0;
      in >> type;
      EXPECT_EQ(type, mesh.types[cell]);
      const int begin = cell == 0 ? 0 : mesh.offsets[cell - 1];
      const std::vector<double> want(mesh.connectivity.begin() + begin, mesh.connectivity.begin() + mesh.offsets[cell]);
      expect_bitwise(numbers(in), want, "cell " + std::to_string(cell));
      ++cell;
    } else {
      ASSERT_TRUE(tag == "pdata" || tag == "cdata") << line;
      std::string name;
      std::getline(in >> std::ws, name);
      const auto& fields = tag == "pdata" ? mesh.point_data : mesh.cell_data;
      const auto field = std::find_if(fields.begin(), fields.end(), [&](const auto& f) { return f.name == name; });
      ASSERT_NE(field, fields.end()) << "unexpected array " << name;
      fields_seen.push_back(&*field);
      ASSERT_TRUE(std::getline(dump, line));
      std::istringstream values(line);
      int components = 0;
      values >> components;
      EXPECT_EQ(components, field->components) << name;
      expect_bitwise(numbers(values), field->values, name);
    }
  }
  EXPECT_EQ(point, mesh.points.size());
  EXPECT_EQ(cell, mesh.types.size());
  EXPECT_EQ(fields_seen.size(), mesh.point_data.size() + mesh.cell_data.size());
}

class VtuEncodings : public ::testing::TestWithParam<VtuEncoding> {};

TEST_P(VtuEncodings, VtkReadsBackPointsCellsAndFieldsExactly) {
  if (!testing::python_has("vtk")) GTEST_SKIP() << "/usr/bin/python3 cannot import vtk";
  testing::ScratchDir dir;
  expect_vtk_reads_back(dir, sample_mesh(), GetParam());
}

TEST_P(VtuEncodings, VtkReadsBackASampledMeshExactly) {
  if (!testing::python_has("vtk")) GTEST_SKIP() << "/usr/bin/python3 cannot import vtk";
  testing::ScratchDir dir;
  expect_vtk_reads_back(dir, sampled_mesh(64), GetParam());
}

TEST_P(VtuEncodings, VtkReadsAnEmptyMesh) {
  if (!testing::python_has("vtk")) GTEST_SKIP() << "/usr/bin/python3 cannot import vtk";
  testing::ScratchDir dir;
  expect_vtk_reads_back(dir, VtuMesh{}, GetParam());
}

INSTANTIATE_TEST_SUITE_P(All, VtuEncodings,
                         ::testing::Values(VtuEncoding::compressed, VtuEncoding::base64, VtuEncoding::ascii),
                         [](const auto& info) {
                           return std::string(info.param == VtuEncoding::compressed ? "compressed"
                                              : info.param == VtuEncoding::base64   ? "base64"
                                                                                    : "ascii");
                         });

TEST(Vtu, CompressedIsSmallerThanBase64AndAscii) {
  const VtuMesh mesh = sampled_mesh(64);
  const std::size_t compressed = vtu_document(mesh, VtuEncoding::compressed).size();
  const std::size_t base64 = vtu_document(mesh, VtuEncoding::base64).size();
  const std::size_t ascii = vtu_document(mesh, VtuEncoding::ascii).size();
  RecordProperty("bytes_compressed", std::to_string(compressed));
  RecordProperty("bytes_base64", std::to_string(base64));
  RecordProperty("bytes_ascii", std::to_string(ascii));
  EXPECT_LT(compressed, base64);
  EXPECT_LT(base64, ascii);
}

// The block stream follows VTK's layout: [blocks, block size, partial last block size or 0, compressed
// sizes...], then the blocks, each of which zlib inflates back to its slice of the input.
TEST(Vtu, ZlibBlocksHaveVtksHeaderAndInflateBack) {
  for (const std::size_t size : {std::size_t{0}, std::size_t{100}, std::size_t{65536}, std::size_t{100000}}) {
    std::string raw(size, '\0');
    for (std::size_t i = 0; i < size; ++i) raw[i] = static_cast<char>((i * i / 7) % 251);
    const std::string stream = zlib_blocks(raw.data(), raw.size(), 32768);
    const std::size_t blocks = (size + 32767) / 32768;
    std::vector<std::uint64_t> header(3 + blocks);
    ASSERT_GE(stream.size(), header.size() * 8);
    std::memcpy(header.data(), stream.data(), header.size() * 8);
    EXPECT_EQ(header[0], blocks);
    EXPECT_EQ(header[1], 32768u);
    EXPECT_EQ(header[2], size % 32768);
    std::size_t at = header.size() * 8;
    std::string inflated;
    for (std::size_t b = 0; b < blocks; ++b) {
      std::string block(32768, '\0');
      uLongf length = block.size();
      ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(block.data()), &length,
                           reinterpret_cast<const Bytef*>(stream.data() + at), header[3 + b]), Z_OK);
      inflated.append(block.data(), length);
      at += header[3 + b];
    }
    EXPECT_EQ(at, stream.size());
    EXPECT_EQ(inflated, raw) << size;
  }
}

// The blocks are compressed side by side: the stream must be the same bytes on any number of threads
// (the files of a run do not depend on --threads). 40 blocks, so that every thread gets several.
TEST(Vtu, ZlibBlocksAreTheSameOnAnyNumberOfThreads) {
  std::string raw(40 * 32768 + 123, '\0');
  std::mt19937 random(7);
  for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = static_cast<char>(i % 97 < 60 ? random() % 4 : i % 13);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::string one = zlib_blocks(raw.data(), raw.size(), 32768);
  for (const int n : {2, 3, 8}) {
    omp_set_num_threads(n);
    EXPECT_EQ(zlib_blocks(raw.data(), raw.size(), 32768), one) << n << " threads";
  }
  omp_set_num_threads(threads);
  EXPECT_LT(one.size(), raw.size() / 2);  // the data compress: the blocks hold zlib's output, not copies
}

TEST(Vtu, BezierDegreesAndWeightsAreChecked) {
  VtuMesh mesh;
  for (int i = 0; i < 9; ++i) mesh.points.emplace_back(i % 3, i / 3, 0);
  mesh.add_cell(vtk_cell::bezier_quadrilateral, {0, 2, 8, 6, 1, 5, 7, 3, 4});
  mesh.point_data = {{vtk_bezier::weights, 1, std::vector<double>(9, 1.0)}};
  mesh.cell_data = {{vtk_bezier::degrees, 3, {2, 2, 0}}};
  EXPECT_NO_THROW(validate(mesh));
  EXPECT_NE(vtu_document(mesh).find("<PointData RationalWeights=\"RationalWeights\">"), std::string::npos);
  EXPECT_NE(vtu_document(mesh).find("<CellData HigherOrderDegrees=\"HigherOrderDegrees\">"), std::string::npos);
  VtuMesh wrong_degree = mesh;
  wrong_degree.cell_data[0].values = {3, 2, 0};  // needs 12 points
  EXPECT_THROW(validate(wrong_degree), std::invalid_argument);
  VtuMesh wrong_components = mesh;
  wrong_components.cell_data[0] = {vtk_bezier::degrees, 1, {2}};
  EXPECT_THROW(validate(wrong_components), std::invalid_argument);
}

TEST(Vtu, InconsistentMeshesAreRejected) {
  testing::ScratchDir dir;
  VtuMesh bad_field = sample_mesh();
  bad_field.point_data[0].values.pop_back();
  EXPECT_THROW(write_vtu(dir.file("a.vtu"), bad_field), std::invalid_argument);
  VtuMesh bad_index = sample_mesh();
  bad_index.connectivity[0] = 99;
  EXPECT_THROW(write_vtu(dir.file("b.vtu"), bad_index), std::invalid_argument);
  VtuMesh bad_offsets = sample_mesh();
  bad_offsets.offsets.back() = 3;
  EXPECT_THROW(write_vtu(dir.file("c.vtu"), bad_offsets), std::invalid_argument);
  EXPECT_EQ(dir.entry_count(), 0u);  // nothing written, not even a temporary
}

TEST(Vtu, Base64MatchesRfc4648Vectors) {
  EXPECT_EQ(base64_encode("", 0), "");
  EXPECT_EQ(base64_encode("f", 1), "Zg==");
  EXPECT_EQ(base64_encode("fo", 2), "Zm8=");
  EXPECT_EQ(base64_encode("foobar", 6), "Zm9vYmFy");
}

TEST(Pvd, CollectionIsWellFormedAfterEveryStep) {
  if (!testing::python_has("xml.etree.ElementTree")) GTEST_SKIP() << "/usr/bin/python3 not available";
  testing::ScratchDir dir;
  PvdCollection pvd(dir.file("run.pvd"));
  const std::string parse = "/usr/bin/python3 -c 'import sys, xml.etree.ElementTree as E; "
                            "r=E.parse(sys.argv[1]).getroot(); "
                            "open(sys.argv[2],\"w\").write(\"\\n\".join(\"%s|%s|%s\" % (d.get(\"timestep\"), "
                            "d.get(\"part\"), d.get(\"file\")) for d in r.find(\"Collection\")))' " +
                            dir.file("run.pvd") + " " + dir.file("parsed.txt");
  ASSERT_EQ(std::system(parse.c_str()), 0);  // valid even before the first step
  EXPECT_EQ(testing::read_text(dir.file("parsed.txt")), "");
  pvd.add(0.0, "steps/shell_0000.vtu");
  pvd.add(0.1, "steps/beam_0001.vtu", 1);
  pvd.add(1.0 / 3.0, "steps/a&b <\"c\">.vtu");
  ASSERT_EQ(std::system(parse.c_str()), 0);
  EXPECT_EQ(testing::read_text(dir.file("parsed.txt")),
            "0|0|steps/shell_0000.vtu\n0.1|1|steps/beam_0001.vtu\n0.3333333333333333|0|steps/a&b <\"c\">.vtu");
  EXPECT_EQ(pvd.size(), 3u);
  EXPECT_EQ(dir.entry_count(), 2u);  // run.pvd and parsed.txt: no temporaries left
}

}  // namespace
}  // namespace fibrane::io
