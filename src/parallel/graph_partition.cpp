#include "parallel/graph_partition.hpp"

#include <petscmat.h>

#include <algorithm>

namespace fibrane::parallel {

namespace {

// PETSc objects of one partitioning, destroyed in any case; PETSc's errors are returned, not printed.
struct Partitioner {
  Mat adjacency = nullptr;
  MatPartitioning partitioning = nullptr;
  IS local = nullptr, all = nullptr;
  Partitioner() { PetscPushErrorHandler(PetscReturnErrorHandler, nullptr); }
  ~Partitioner() {
    ISDestroy(&all);
    ISDestroy(&local);
    MatPartitioningDestroy(&partitioning);
    MatDestroy(&adjacency);
    PetscPopErrorHandler();
  }
};

}  // namespace

std::vector<int> partition_graph(const solve::Graph& graph, MPI_Comm comm, std::string& why) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int n = graph.vertices();
  if (size == 1) return std::vector<int>(static_cast<std::size_t>(n), 0);
  if (n < size) {
    why = "fewer elements than processes";
    return {};
  }
  // This process's vertices [first, end), as PETSc's default split.
  const int first = rank * (n / size) + std::min(rank, n % size);
  const int end = first + n / size + (rank < n % size ? 1 : 0);
  Partitioner p;
  // MatCreateMPIAdj and the vertex weights take arrays allocated by PETSc, which it frees. The edges'
  // weights (shared unknowns) make PT-Scotch cut where elements share few unknowns.
  PetscInt *rows = nullptr, *columns = nullptr, *edges = nullptr, *weights = nullptr;
  const int offset = graph.begin[static_cast<std::size_t>(first)];
  const int entries = graph.begin[static_cast<std::size_t>(end)] - offset;
  bool ok = PetscMalloc1(end - first + 1, &rows) == 0 && PetscMalloc1(std::max(entries, 1), &columns) == 0 &&
            PetscMalloc1(std::max(entries, 1), &edges) == 0 && PetscMalloc1(std::max(end - first, 1), &weights) == 0;
  if (ok) {
    for (int v = first; v <= end; ++v) rows[v - first] = graph.begin[static_cast<std::size_t>(v)] - offset;
    std::copy_n(graph.adjacency.begin() + offset, entries, columns);
    std::copy_n(graph.edge_weight.begin() + offset, entries, edges);
    std::copy_n(graph.weight.begin() + first, end - first, weights);
    ok = MatCreateMPIAdj(comm, end - first, n, rows, columns, edges, &p.adjacency) == 0;
  }
  if (!ok) {
    why = "PETSc could not hold the element graph";
    return {};
  }
  if (MatPartitioningCreate(comm, &p.partitioning) != 0 || MatPartitioningSetAdjacency(p.partitioning, p.adjacency) != 0 ||
      MatPartitioningSetType(p.partitioning, MATPARTITIONINGPTSCOTCH) != 0) {
    PetscFree(weights);
    why = "PETSc offers no PT-Scotch partitioner (MatPartitioningSetType ptscotch failed)";
    return {};
  }
  if (MatPartitioningSetNParts(p.partitioning, size) != 0 || MatPartitioningSetUseEdgeWeights(p.partitioning, PETSC_TRUE) != 0 || MatPartitioningSetVertexWeights(p.partitioning, weights) != 0 ||
      MatPartitioningApply(p.partitioning, &p.local) != 0 || ISAllGather(p.local, &p.all) != 0) {
    why = "PT-Scotch failed to partition the element graph";
    return {};
  }
  const PetscInt* parts = nullptr;
  PetscInt count = 0;
  std::vector<int> out;
  if (ISGetLocalSize(p.all, &count) == 0 && count == n && ISGetIndices(p.all, &parts) == 0) {
    out.assign(parts, parts + n);
    ISRestoreIndices(p.all, &parts);
  }
  if (out.empty()) why = "PT-Scotch's partition could not be gathered";
  return out;
}

}  // namespace fibrane::parallel
