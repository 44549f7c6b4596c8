// Pieces of a .vtu for the parallel format (io/pvtu.hpp): the pieces of a grid together hold exactly its
// cells, in order, with every cell's point coordinates and point and cell fields; the cell ranges cover
// the grid without overlap for even and uneven splits; the .pvtu names the pieces and declares the fields
// with the Bezier attributes. (tests/parallel/mpi_pieces.py reads a run's pieces back with VTK.)
#include <gtest/gtest.h>

#include <cmath>

#include "io/pvtu.hpp"

namespace fibrane::io {
namespace {

// Quads sharing edges, a line, a vertex and an unused point, with point, cell and field data.
VtuMesh sample() {
  VtuMesh mesh;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) mesh.points.emplace_back(i / 3.0, j * std::sqrt(2.0), -0.1 * i * j);
  mesh.points.emplace_back(9, 9, 9);  // used by no cell
  mesh.add_cell(vtk_cell::quad, {0, 1, 5, 4});
  mesh.add_cell(vtk_cell::quad, {1, 2, 6, 5});
  mesh.add_cell(vtk_cell::quad, {2, 3, 7, 6});
  mesh.add_cell(vtk_cell::line, {0, 7});
  mesh.add_cell(vtk_cell::vertex, {3});
  VtuMesh::Field u{"displacement", 3, {}}, w{vtk_bezier::weights, 1, {}}, c{"strain", 2, {}};
  for (std::size_t p = 0; p < mesh.points.size(); ++p) {
    u.values.insert(u.values.end(), {0.1 * p, -0.2 * p, std::exp(-double(p))});
    w.values.push_back(1.0 + p / 7.0);
  }
  for (int k = 0; k < 5; ++k) c.values.insert(c.values.end(), {k + 0.5, -k / 3.0});
  mesh.point_data = {u, w};
  mesh.cell_data = {c};
  mesh.field_data = {{"t", 1, {0.25}}};
  return mesh;
}

// The points of cell `c` of `m` as listed by the connectivity.
std::vector<int> cell_points(const VtuMesh& m, int c) {
  const int begin = c == 0 ? 0 : m.offsets[c - 1];
  return {m.connectivity.begin() + begin, m.connectivity.begin() + m.offsets[c]};
}

TEST(Pvtu, PieceCellRangesCoverTheCellsInOrder) {
  for (int cells : {0, 1, 5, 12, 100})
    for (int pieces : {1, 2, 3, 7}) {
      int next = 0;
      for (int p = 0; p < pieces; ++p) {
        const auto [begin, end] = piece_cells(cells, p, pieces);
        EXPECT_EQ(begin, next) << cells << " cells, piece " << p << " of " << pieces;
        EXPECT_LE(end - begin, (cells + pieces - 1) / pieces);
        EXPECT_GE(end - begin, cells / pieces);
        next = end;
      }
      EXPECT_EQ(next, cells);
    }
  EXPECT_THROW(piece_cells(5, 3, 3), std::invalid_argument);
}

TEST(Pvtu, PiecesTogetherHoldTheWholeGridCellByCell) {
  const VtuMesh whole = sample();
  for (int pieces : {1, 2, 3, 5, 6}) {
    int cell = 0;
    for (int p = 0; p < pieces; ++p) {
      const auto [begin, end] = piece_cells(5, p, pieces);
      const VtuMesh piece = vtu_piece(whole, begin, end);
      EXPECT_NO_THROW(validate(piece));
      ASSERT_EQ(piece.types.size(), static_cast<std::size_t>(end - begin));
      EXPECT_EQ(piece.field_data[0].values, whole.field_data[0].values);
      for (int k = 0; k < end - begin; ++k, ++cell) {
        EXPECT_EQ(piece.types[k], whole.types[cell]);
        const auto mine = cell_points(piece, k), theirs = cell_points(whole, cell);
        ASSERT_EQ(mine.size(), theirs.size());
        for (std::size_t i = 0; i < mine.size(); ++i) {
          EXPECT_EQ(piece.points[mine[i]], whole.points[theirs[i]]);
          for (std::size_t f = 0; f < whole.point_data.size(); ++f) {
            const int n = whole.point_data[f].components;
            for (int j = 0; j < n; ++j)
              EXPECT_EQ(piece.point_data[f].values[mine[i] * n + j], whole.point_data[f].values[theirs[i] * n + j]);
          }
        }
        EXPECT_EQ(piece.cell_data[0].values[2 * k], whole.cell_data[0].values[2 * cell]);
        EXPECT_EQ(piece.cell_data[0].values[2 * k + 1], whole.cell_data[0].values[2 * cell + 1]);
      }
      // Only the points its cells use.
      for (const auto& x : piece.points) EXPECT_NE(x, Eigen::Vector3d(9, 9, 9));
    }
    EXPECT_EQ(cell, 5);
  }
  EXPECT_THROW(vtu_piece(whole, 3, 6), std::invalid_argument);
}

TEST(Pvtu, DocumentNamesThePiecesAndDeclaresTheFields) {
  const std::string xml = pvtu_document(sample(), {"a_000001_0000.vtu", "a_000001_0001.vtu"});
  for (const char* part : {"type=\"PUnstructuredGrid\"", "<PPointData RationalWeights=\"RationalWeights\">",
                           "Name=\"displacement\" NumberOfComponents=\"3\"", "<PCellData>",
                           "Name=\"strain\" NumberOfComponents=\"2\"", "<Piece Source=\"a_000001_0000.vtu\"/>",
                           "<Piece Source=\"a_000001_0001.vtu\"/>", "Name=\"Points\" NumberOfComponents=\"3\""})
    EXPECT_NE(xml.find(part), std::string::npos) << part << " not in\n" << xml;
}

}  // namespace
}  // namespace fibrane::io
