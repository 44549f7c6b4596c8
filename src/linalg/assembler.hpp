#pragma once
// Parallel assembly of element contributions DIRECTLY into the reduced system of exact constraint
// elimination (see constraints.hpp):  K_red = T^T K T,  r_red = T^T r.
// The full residual r is kept as well: at constrained DOFs it is the reaction force.
//
// The elements come in two groups. The fixed ones (shell, beam, loads) are set once with set_pattern(); the
// variable ones (the beam-shell coupling, which changes as points slide and switch) are replaced with
// set_variable_elements(), which merges their blocks into the fixed pattern without rebuilding it (the two
// are compared in docs/performance.md, "Sparse assembler"). For every element a table of positions into the
// matrix value array is kept, so add() is a pure scatter without searching. The positions are offsets within
// their column, so that a new variable part moves only the fixed entries of the columns where variable rows
// come before them (the shell's columns under soft-minimum windows; beam rows follow the shell's in every
// column).
// Concurrency, by strategy:
// - Colours (the default): the elements are coloured when they are set (greedily, in id order), so that
//   elements of one colour share no DOF and no reduced unknown and hence write no common matrix value,
//   residual or rate entry. A contribution's loop visits its elements colour by colour (coloured(), a
//   barrier between colours), and an add() of the visited element (Exclusive) writes straight into the
//   matrix: no per-thread copy of the values, and the sums come in colour order whatever the thread count.
//   Adds outside such a loop take the ThreadBuffers path.
// - ThreadBuffers: each OpenMP thread scatters into its own value/residual buffer (thread 0 straight into
//   the matrix, the others' buffers allocated at their first add), end() sums and clears them in one pass.
// - Atomic: `omp atomic` adds into the shared arrays.
// Callers inside nested parallel regions, where thread numbers are not unique, add atomically into a
// shared overflow buffer.
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/constraints.hpp"
#include "linalg/distribution.hpp"

namespace fibrane::solve {

class SparseAssembler {
 public:
  enum class Strategy { Colours, ThreadBuffers, Atomic };

  void set_strategy(Strategy s) { strategy_ = s; }
  Strategy strategy() const { return strategy_; }

  // The fixed elements, ids 0, 1, ...: one entry per element (any group of coupled DOFs), its full DOF list.
  // Removes the variable elements. The ConstraintSet must be finalized and must outlive the assembler's
  // use. Increments pattern_version().
  void set_pattern(const ConstraintSet& c, const std::vector<std::vector<int>>& element_dofs);
  // Replaces the variable elements (ids num_fixed_elements(), ...). Costs the variable elements' blocks
  // plus one pass over the fixed pattern. Increments pattern_version().
  void set_variable_elements(const std::vector<std::vector<int>>& element_dofs);
  int pattern_version() const { return version_; }
  int num_fixed_elements() const { return fixed_.size(); }
  int num_elements() const { return fixed_.size() + variable_.size(); }

  // Zeroes the values (keeps the pattern). With `prescribed_rate` (full size: dg/dt of u = T q + g(t), zero
  // at free DOFs) and the matrix, the assembler also forms d r / d t = T^T (K dg/dt + explicit terms): every
  // element matrix added is applied to the element's part of dg/dt, and add_rate() adds explicit terms.
  void begin(bool with_matrix, const Eigen::VectorXd* prescribed_rate = nullptr);
  // Thread-safe inside OpenMP parallel loops. r_local/k_local are ordered like the element's DOF list;
  // k_local may be null (residual only). Convention: r = internal - external forces.
  void add(int element, const Eigen::VectorXd& r_local, const Eigen::MatrixXd* k_local);
  // A sub-block of an element: r_local / k_local belong to the element's DOFs local[0], local[1], ...
  // (indices into its DOF list), the rest of the element is untouched.
  void add(int element, std::span<const int> local, const Eigen::VectorXd& r_local, const Eigen::MatrixXd* k_local);
  // T^T v for a vector v on a sub-block of an element's DOFs (as add()'s `local`): the reduced vector a
  // term c v v^T held apart from the matrix contributes as c (T^T v)(T^T v)^T (RankOneTerms).
  Eigen::SparseVector<double> reduce(int element, std::span<const int> local, const Eigen::VectorXd& v) const;
  // The reduced unknowns an element's DOFs reach, sorted: the rows and columns of its block in the matrix.
  std::span<const int> reduced_unknowns(int element) const;
  // Residual-only contributions at arbitrary DOFs (point loads etc.), thread-safe.
  void add_vector(std::span<const int> dofs, const Eigen::VectorXd& r_local);
  // Explicit d r / d t at arbitrary DOFs (loads scaled by functions of t), thread-safe; ignored unless
  // begin() was given a prescribed rate.
  void add_rate(std::span<const int> dofs, const Eigen::VectorXd& r_t);
  // Reduces the thread buffers and forms T^T r (and T^T dr/dt). With a distribution, collective: the full
  // residual (and rate) of this process's elements are first summed over the processes, so that every
  // process holds the whole residual; the matrix stays this process's summand.
  void end(const Distribution* distribution = nullptr);

  // The colouring: colours 0 .. num_colours() - 1 (the fixed elements' first, then the variable ones').
  // Elements of one colour share no DOF and no reduced unknown.
  int num_colours() const { return static_cast<int>(colour_begin_.size()) - 1; }
  // The elements of `colour` among first, ..., first + count - 1, ascending.
  std::span<const int> coloured(int colour, int first, int count) const;
  // While alive, the calling thread's add() of `element` writes straight into the matrix (Strategy::
  // Colours; ignored otherwise), and an add() of another element by this thread is a std::logic_error.
  // Only for a loop over one colour of coloured() that every thread of the team runs, with no other adds
  // to this assembler going on at the same time.
  class Exclusive {
   public:
    Exclusive(const SparseAssembler& a, int element);
    ~Exclusive();
    Exclusive(const Exclusive&) = delete;
    Exclusive& operator=(const Exclusive&) = delete;
  };

  // Bytes held by the per-thread and overflow buffers (their capacity).
  std::size_t buffer_bytes() const;

  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  const Eigen::VectorXd& reduced_residual() const { return reduced_residual_; }
  const Eigen::VectorXd& full_residual() const { return full_residual_; }
  // T^T d r / d t of the last begin()/end() with a prescribed rate (empty otherwise).
  const Eigen::VectorXd& reduced_rate() const { return reduced_rate_; }

 private:
  struct Buffer {
    std::vector<double> values, residual, rate;
    bool used = false;  // written only by the owning thread
  };
  // Flattened element maps. Element e owns local DOFs [dof_begin[e], dof_begin[e+1]) of dofs; local DOF j
  // expands into entries [entry_begin[j], entry_begin[j+1]) = (slot, coefficient), slot being the index in
  // the element's sorted list of reduced unknowns reduced[reduced_begin[e] ...] (m of them); the
  // value-array position of (row slot p, column slot s) is outer[reduced[s]] + offset[offset_begin[e] + s * m + p]
  // (outer: the matrix's column starts).
  struct ElementTable {
    std::vector<int> dof_begin{0}, dofs;
    std::vector<int> entry_begin{0}, entry_slot;
    std::vector<double> entry_coef;
    std::vector<int> reduced_begin{0}, reduced;
    std::vector<size_t> offset_begin{0};
    std::vector<int> offset;
    int size() const { return static_cast<int>(dof_begin.size()) - 1; }
    int reduced_count(int e) const { return reduced_begin[static_cast<size_t>(e) + 1] - reduced_begin[static_cast<size_t>(e)]; }
  };
  struct Pattern {  // compressed columns, sorted rows
    std::vector<int> outer, inner;
  };
  static ElementTable make_table(const ConstraintSet& c, const std::vector<std::vector<int>>& element_dofs, int first_id);
  // The table that holds element `element` and its index there; std::out_of_range naming `caller` where
  // there is no such element.
  std::pair<const ElementTable&, int> table_of(int element, const char* caller) const;
  // The union of `base` and the elements' blocks; base_position[k] = where base entry k went.
  static Pattern merge(int n, const Pattern& base, const ElementTable& t, std::vector<int>& base_position);
  static void locate(ElementTable& t, const Pattern& p);  // fills t.offset
  // Greedy colouring: each element gets the smallest colour that no earlier element sharing a DOF or a
  // reduced unknown has.
  static std::vector<int> colour_elements(const ElementTable& t, int num_dofs, int num_free);
  // Appends t's elements (ids first, first + 1, ...) as new colours to colour_order_ / colour_begin_.
  void append_colours(const ElementTable& t, int first);
  // Whether the calling thread holds an Exclusive for `element` (a logic_error for another element).
  bool exclusive(int element) const;
  void set_matrix(const Pattern& p);
  void reset_vectors();

  // Buffer of the calling thread (allocated or zeroed at its first use), or nullptr when the caller must use
  // atomics on the shared arrays.
  Buffer* thread_buffer();
  // Sizes `b` for the current begin() and zeroes it.
  void reset(Buffer& b) const;
  // The overflow buffer's matrix values, allocated (zeroed) by the first caller after a pattern change.
  double* overflow_values();
  // Scatters element e's sub-block local(0), ..., local(n - 1).
  template <class Local>
  void scatter(const ElementTable& t, int e, int n, Local local, const Eigen::VectorXd& r_local,
               const Eigen::MatrixXd* k_local, double* values, double* residual, double* rate, bool atomic) const;
  // rate[dof] += (k_local dg/dt)_a for an element that has prescribed DOFs.
  template <class Local>
  void scatter_rate(const ElementTable& t, int e, int n, Local local, const Eigen::MatrixXd& k_local, double* rate,
                    bool atomic) const;
  template <class Local>
  void add_block(int element, int n, Local local, const Eigen::VectorXd& r_local, const Eigen::MatrixXd* k_local);

  const ConstraintSet* constraints_ = nullptr;
  Strategy strategy_ = Strategy::Colours;
  int version_ = 0;
  bool with_matrix_ = false;

  ElementTable fixed_, variable_;
  Pattern fixed_pattern_;                // the fixed elements' blocks alone
  std::vector<int> fixed_in_matrix_;     // position in matrix_ of every fixed_pattern_ entry
  // Element ids by colour (ascending within a colour): colour c is colour_order_[colour_begin_[c] ...
  // colour_begin_[c + 1]); the fixed elements' colours are the first fixed_colours_.
  std::vector<int> colour_order_, colour_begin_{0};
  int fixed_colours_ = 0;

  Eigen::SparseMatrix<double> matrix_;
  Eigen::VectorXd full_residual_, reduced_residual_;
  const Eigen::VectorXd* prescribed_rate_ = nullptr;  // dg/dt while a rate is assembled, else null
  Eigen::VectorXd full_rate_, reduced_rate_;
  std::vector<Buffer> buffers_;  // index = OpenMP thread number; [0] unused (thread 0 writes directly)
  Buffer overflow_;              // atomically shared by callers without a private buffer
};

}  // namespace fibrane::solve
