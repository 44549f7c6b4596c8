#pragma once
// solve::Distribution over an MPI communicator: the processes of `mpirun -np N fibrane run`.
#include <mpi.h>

#include "linalg/distribution.hpp"

namespace fibrane::parallel {

class MpiDistribution final : public solve::Distribution {
 public:
  explicit MpiDistribution(MPI_Comm comm);
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  // MPI_Allreduce: every process gets the same bits (PETSc's Krylov methods rely on that for the norms
  // they test, too).
  void sum(std::span<double> values) const override;
  bool all(bool value) const override;
  std::vector<double> gather(std::span<const double> values) const override;
  std::string first_text(const std::string& text) const override;
  // PT-Scotch through PETSc's MatPartitioning (graph_partition.hpp).
  std::vector<int> partition(const solve::Graph& graph, std::string& why) const override;
  MPI_Comm comm() const { return comm_; }

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

// Throws std::runtime_error naming `what` when an MPI call did not return MPI_SUCCESS.
void check_mpi(int code, const char* what);

}  // namespace fibrane::parallel
