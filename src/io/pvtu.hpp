#pragma once
// ParaView's parallel unstructured grid: a .pvtu file names the pieces (.vtu files) that together make one
// grid and declares the fields they carry. Pieces here are contiguous ranges of a grid's cells.
#include <string>
#include <utility>
#include <vector>

#include "io/vtk.hpp"

namespace fibrane::io {

// The cells [first, second) of piece `piece` of `pieces` over `cells` cells: cells * piece / pieces up to
// cells * (piece + 1) / pieces (the first pieces one cell fewer when they do not divide evenly).
std::pair<int, int> piece_cells(int cells, int piece, int pieces);

// The cells [begin, end) of `whole` with the points they use, in `whole`'s order and renumbered, their
// point and cell fields, and `whole`'s field data. A point that cells of two pieces share is in both.
VtuMesh vtu_piece(const VtuMesh& whole, int begin, int end);

// The .pvtu document of a grid whose pieces carry the fields of `like` (names, components; the Bezier
// attributes as write_vtu marks them); `sources`: the pieces' paths relative to the .pvtu's directory.
std::string pvtu_document(const VtuMesh& like, const std::vector<std::string>& sources);

}  // namespace fibrane::io
