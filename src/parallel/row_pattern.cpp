#include "parallel/row_pattern.hpp"

#include <algorithm>

namespace fibrane::parallel {

namespace {

// Appends, for every column j of `a` in [first, end): j, the number of its rows, the rows (>= j when
// `upper`).
void pack_columns(const Eigen::SparseMatrix<double>& a, int first, int end, bool upper, std::vector<int>& out) {
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  for (int j = first; j < end; ++j) {
    const int* b = inner + outer[j];
    const int* e = inner + outer[j + 1];
    if (upper) b = std::lower_bound(b, e, j);
    if (b == e) continue;
    out.push_back(j);
    out.push_back(static_cast<int>(e - b));
    out.insert(out.end(), b, e);
  }
}

}  // namespace

RowPattern owned_rows(const Eigen::SparseMatrix<double>& summand, bool upper, const solve::UnknownOwnership& ownership,
                      const MpiDistribution& d) {
  const int p_count = d.size();
  // Columns of this summand, grouped by the process owning them (as rows).
  std::vector<int> send, send_counts(static_cast<size_t>(p_count)), send_offsets(static_cast<size_t>(p_count) + 1, 0);
  for (int p = 0; p < p_count; ++p) {
    pack_columns(summand, ownership.begin(p), ownership.begin(p + 1), upper, send);
    send_offsets[static_cast<size_t>(p) + 1] = static_cast<int>(send.size());
    send_counts[static_cast<size_t>(p)] = send_offsets[static_cast<size_t>(p) + 1] - send_offsets[static_cast<size_t>(p)];
  }
  std::vector<int> recv_counts(static_cast<size_t>(p_count)), recv_offsets(static_cast<size_t>(p_count) + 1, 0);
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, d.comm()), "MPI_Alltoall");
  for (int p = 0; p < p_count; ++p) recv_offsets[static_cast<size_t>(p) + 1] = recv_offsets[static_cast<size_t>(p)] + recv_counts[static_cast<size_t>(p)];
  std::vector<int> received(static_cast<size_t>(recv_offsets.back()));
  check_mpi(MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_INT, received.data(),
                          recv_counts.data(), recv_offsets.data(), MPI_INT, d.comm()),
            "MPI_Alltoallv");
  std::vector<int>().swap(send);
  // Merge: the rows of every owned column (= the columns of the owned row), sorted, without repeats.
  RowPattern out;
  out.first = ownership.begin(d.rank());
  const int rows = ownership.count(d.rank());
  std::vector<std::vector<int>> row_columns(static_cast<size_t>(rows));
  for (std::size_t k = 0; k < received.size();) {
    const int j = received[k], count = received[k + 1];
    auto& target = row_columns[static_cast<size_t>(j - out.first)];
    target.insert(target.end(), received.begin() + static_cast<long>(k) + 2, received.begin() + static_cast<long>(k) + 2 + count);
    k += 2 + static_cast<std::size_t>(count);
  }
  std::vector<int>().swap(received);
  out.begin.reserve(static_cast<size_t>(rows) + 1);
  for (auto& c : row_columns) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    out.columns.insert(out.columns.end(), c.begin(), c.end());
    out.begin.push_back(static_cast<int>(out.columns.size()));
    std::vector<int>().swap(c);
  }
  return out;
}

RowRounds::RowRounds(const Eigen::SparseMatrix<double>& a)
    : a_(a), cursor_(a.outerIndexPtr(), a.outerIndexPtr() + a.cols()) {
  rows_.first = 0;
}

const RowPattern& RowRounds::next(int end) {
  const int* outer = a_.outerIndexPtr();
  const int* inner = a_.innerIndexPtr();
  const double* values = a_.valuePtr();
  const int first = rows_.first + rows_.rows();
  const int columns = static_cast<int>(a_.cols());
  rows_.first = first;
  rows_.begin.assign(static_cast<size_t>(end - first) + 1, 0);
  for (int j = 0; j < columns; ++j)
    for (int k = cursor_[static_cast<size_t>(j)]; k < outer[j + 1] && inner[k] < end; ++k)
      ++rows_.begin[static_cast<size_t>(inner[k] - first) + 1];
  for (size_t r = 1; r < rows_.begin.size(); ++r) rows_.begin[r] += rows_.begin[r - 1];
  rows_.columns.resize(static_cast<size_t>(rows_.begin.back()));
  values_.resize(rows_.columns.size());
  fill_.assign(rows_.begin.begin(), rows_.begin.end() - 1);
  for (int j = 0; j < columns; ++j) {
    int& k = cursor_[static_cast<size_t>(j)];
    for (; k < outer[j + 1] && inner[k] < end; ++k) {
      const auto at = static_cast<size_t>(fill_[static_cast<size_t>(inner[k] - first)]++);
      rows_.columns[at] = j;
      values_[at] = values[k];
    }
  }
  return rows_;
}

}  // namespace fibrane::parallel
