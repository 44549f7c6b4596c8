#include "parallel/mpi_distribution.hpp"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <string>

#include "parallel/graph_partition.hpp"

namespace fibrane::parallel {

void check_mpi(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed (error " + std::to_string(code) + ")");
}

MpiDistribution::MpiDistribution(MPI_Comm comm) : comm_(comm) {
  check_mpi(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
  check_mpi(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
}

void MpiDistribution::sum(std::span<double> values) const {
  if (size_ == 1) return;
  // In pieces below INT_MAX entries (MPI counts are ints).
  for (std::size_t first = 0; first < values.size(); first += INT_MAX / 2) {
    const int count = static_cast<int>(std::min<std::size_t>(values.size() - first, INT_MAX / 2));
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, values.data() + first, count, MPI_DOUBLE, MPI_SUM, comm_), "MPI_Allreduce");
  }
}

bool MpiDistribution::all(bool value) const {
  int v = value ? 1 : 0;
  if (size_ > 1) check_mpi(MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_MIN, comm_), "MPI_Allreduce");
  return v == 1;
}

std::vector<double> MpiDistribution::gather(std::span<const double> values) const {
  if (size_ == 1) return {values.begin(), values.end()};
  if (values.size() > static_cast<std::size_t>(INT_MAX)) throw std::runtime_error("MPI: more than INT_MAX values to gather");
  const int count = static_cast<int>(values.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_) + 1, 0);
  check_mpi(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_), "MPI_Allgather");
  for (int p = 0; p < size_; ++p) {
    const auto k = static_cast<std::size_t>(p);
    if (offsets[k] > INT_MAX - counts[k]) throw std::runtime_error("MPI: more than INT_MAX values to gather");
    offsets[k + 1] = offsets[k] + counts[k];
  }
  std::vector<double> all(static_cast<std::size_t>(offsets.back()));
  check_mpi(MPI_Allgatherv(values.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm_),
            "MPI_Allgatherv");
  return all;
}

std::string MpiDistribution::first_text(const std::string& text) const {
  if (size_ == 1) return text;
  int first = text.empty() ? size_ : rank_;
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm_), "MPI_Allreduce");
  if (first == size_) return {};
  int length = static_cast<int>(text.size());
  check_mpi(MPI_Bcast(&length, 1, MPI_INT, first, comm_), "MPI_Bcast");
  std::string out = rank_ == first ? text : std::string(static_cast<std::size_t>(length), ' ');
  check_mpi(MPI_Bcast(out.data(), length, MPI_CHAR, first, comm_), "MPI_Bcast");
  return out;
}

std::vector<int> MpiDistribution::partition(const solve::Graph& graph, std::string& why) const {
  return partition_graph(graph, comm_, why);
}

}  // namespace fibrane::parallel
