#pragma once
// A graph partition by PETSc's MatPartitioning with PT-Scotch (the partitioner Debian's PETSc links).
#include <mpi.h>

#include <string>
#include <vector>

#include "linalg/distribution.hpp"

namespace fibrane::parallel {

// Collective over `comm`, whose processes all hold the same `graph`: the part (process of `comm`) of
// every vertex, the same on every process. Every process hands PT-Scotch a contiguous share of the
// vertices and gathers the parts of all. Empty, with `why` saying why, when PETSc has no PT-Scotch or the
// partitioner fails.
std::vector<int> partition_graph(const solve::Graph& graph, MPI_Comm comm, std::string& why);

}  // namespace fibrane::parallel
