#pragma once
// The processes of a run, as the model and the assembly see them: which process owns which reduced
// unknowns, and the collective operations that keep the replicated state (q, u, residuals, energies,
// closest points) identical on every process. A distributed run (src/parallel, mpirun) shares the
// elements among the processes: each assembles the elements it owns into its own summand of the tangent
// and residual, the residuals are summed over the processes, and only the matrix and its factorisation
// are distributed (a LinearSolver that factorises the sum of the processes' summands).
//
// `Distribution` itself is the serial run's: one process that owns everything and whose collectives
// return their argument. Every collective must be called by all processes in the same order.
#include <span>
#include <string>
#include <vector>

namespace fibrane::solve {

// How a distributed run shares its elements and unknowns (linalg/partition.hpp):
// contiguous: the unknowns in contiguous ranges, each element owned by the owner of its smallest unknown;
// graph: the elements by a partition of their adjacency graph, the unknowns by the elements that touch them.
enum class Partitioning { contiguous, graph };

// A graph replicated on every process, in compressed rows: the neighbours of vertex v are
// adjacency[begin[v]], ..., adjacency[begin[v + 1] - 1] (sorted, without v), the edges' weights
// edge_weight[begin[v]], ... (symmetric, >= 1); weight[v] >= 1 is the vertex's.
struct Graph {
  std::vector<int> begin{0}, adjacency, edge_weight, weight;
  int vertices() const { return static_cast<int>(begin.size()) - 1; }
};

class Distribution {
 public:
  virtual ~Distribution() = default;
  virtual int rank() const { return 0; }  // this process, 0 <= rank() < size()
  virtual int size() const { return 1; }  // the number of processes
  // Collective: replaces `values` by their sum over the processes; every process gets the same bits.
  virtual void sum(std::span<double> /*values*/) const {}
  // Collective: true on every process if `value` is true on every process.
  virtual bool all(bool value) const { return value; }
  // Collective: every process's `values` one after the other, in the order of the processes' ranks, on
  // every process (the processes may give different numbers of values).
  virtual std::vector<double> gather(std::span<const double> values) const { return {values.begin(), values.end()}; }
  // Collective: the `text` of the lowest-ranked process whose text is not empty (empty if none).
  virtual std::string first_text(const std::string& text) const { return text; }
  // Collective: the part (0 <= part < size()) of every vertex of `graph`, the same on every process, with
  // the parts' vertex weights balanced and little edge weight between parts. Empty, with `why` saying why,
  // where this distribution cannot partition graphs (the serial one has nothing to share).
  virtual std::vector<int> partition(const Graph& graph, std::string& why) const;

  // The partitioning the model applies (set before the model is finalised; default graph).
  Partitioning partitioning() const { return partitioning_; }
  void set_partitioning(Partitioning p) { partitioning_ = p; }

  // The contiguous ranges of n reduced unknowns: process p owns [range_begin(p, n), range_begin(p + 1, n)),
  // n / size() each, the first n % size() processes one more (PETSc's default split).
  int range_begin(int p, int n) const;
  // The process whose range holds unknown i (0 <= i < n).
  int owner(int i, int n) const;

 private:
  Partitioning partitioning_ = Partitioning::graph;
};

// The processes' shares of the n reduced unknowns: the owner of each, and the distributed solver's
// numbering (the rows of its matrix), in which every process's unknowns are contiguous: process 0's first,
// then process 1's, ..., each process's in the model's order.
class UnknownOwnership {
 public:
  UnknownOwnership() = default;  // no unknowns
  // Contiguous ranges (Distribution::range_begin): the solver's numbering is the model's.
  static UnknownOwnership contiguous(int n, int processes);
  // From the owner of every unknown (0 <= owner[i] < processes).
  static UnknownOwnership from_owners(std::vector<int> owner, int processes);

  int unknowns() const { return static_cast<int>(owner_.size()); }
  int processes() const { return static_cast<int>(begin_.size()) - 1; }
  int owner(int i) const { return owner_[static_cast<std::size_t>(i)]; }
  // The solver's row of unknown i, and the unknown of a solver row.
  int row(int i) const { return identity_ ? i : row_[static_cast<std::size_t>(i)]; }
  int unknown(int row) const { return identity_ ? row : unknown_[static_cast<std::size_t>(row)]; }
  // Process p's rows are [begin(p), begin(p + 1)).
  int begin(int p) const { return begin_[static_cast<std::size_t>(p)]; }
  int count(int p) const { return begin(p + 1) - begin(p); }
  // Whether row(i) == i for every unknown.
  bool identity() const { return identity_; }

 private:
  std::vector<int> owner_, row_, unknown_, begin_{0};
  bool identity_ = true;
};

}  // namespace fibrane::solve
