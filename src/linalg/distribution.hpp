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

namespace fibrane::solve {

class Distribution {
 public:
  virtual ~Distribution() = default;
  virtual int rank() const { return 0; }  // this process, 0 <= rank() < size()
  virtual int size() const { return 1; }  // the number of processes
  // Collective: replaces `values` by their sum over the processes; every process gets the same bits.
  virtual void sum(std::span<double> /*values*/) const {}
  // Collective: true on every process if `value` is true on every process.
  virtual bool all(bool value) const { return value; }
  // Collective: the `text` of the lowest-ranked process whose text is not empty (empty if none).
  virtual std::string first_text(const std::string& text) const { return text; }

  // The contiguous ranges of n reduced unknowns: process p owns [range_begin(p, n), range_begin(p + 1, n)),
  // n / size() each, the first n % size() processes one more (PETSc's default split).
  int range_begin(int p, int n) const;
  // The process whose range holds unknown i (0 <= i < n).
  int owner(int i, int n) const;
};

}  // namespace fibrane::solve
