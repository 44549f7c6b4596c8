#pragma once
// CHOLMOD's supernodal LL^T of a large matrix in domains below a tree of separators, the domains factorised
// side by side.
#include <memory>
#include <utility>
#include <vector>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

/// A symmetric K divided by nested dissection (SeparatorTree: METIS's node bisector,
/// `levels` rounds) into domains that no entry joins, below a tree of separators. Each domain D with its
/// boundary B (the separators' rows its elimination couples), H = K(D + B, D + B) with B last, is
/// factorised by CHOLMOD's supernodal LL^T (CholmodDomain), the domains side by side on threads of their
/// own (one BLAS thread each); the trailing block C of each factor gives the domain's update of its
/// boundary, C C^T - K_BB. The separators' dense fronts (DenseFront) then take their children's updates and
/// are factorised in turn from the tree's bottom up, those of one height side by side: a multifrontal
/// factorisation whose subtrees below the separators are CHOLMOD's. With one level (two domains and one
/// separator S) the Schur complement on S is T = C_0 C_0^T + C_1 C_1^T - K_SS.
///
/// A solve runs forward through the domains (with the boundary's right-hand side 0, the domain passes
/// C v up, v the boundary part of L^-1 P [b_D; 0]) and the fronts, then back through the fronts and the
/// domains (with C^T x_B in the boundary's place).
///
/// An indefinite matrix stays split where the build has MUMPS: a domain whose H is not positive definite is
/// factorised by MUMPS's LDL^T with B as its Schur complement (CholmodDomain, MumpsSchur), a front whose
/// F_SS is not by LAPACK's Bunch-Kaufman LDL^T (DenseFront), and negative_eigenvalues() sums their counts
/// (Sylvester's law on the block elimination). The summary counts the domains and fronts that took it.
///
/// CHOLMOD's supernodal code factorises one supernode at a time, its parallelism only within the BLAS
/// calls, where more cores add little; the domains side by side keep the cores busy (docs/performance.md,
/// "The factorisation's input"). `levels` 0 takes the threads' count, rounded up to a power of two, as
/// the domains' count, and bisects a domain again where it holds far more than its share of the work
/// (`refine_above`; SeparatorTree::refine). Matrices below `min_unknowns`, a single thread, or a split that does not serve (the
/// top separator above `max_separator`, a part below a fifth of its piece, CHOLMOD's ordering not keeping a
/// boundary last, the domains side by side on the threads taking more than `max_work_share` of their
/// flops on one thread) are factorised whole by make_cholmod_llt's solver. The name is "cholmod" either
/// way. A new pattern keeps the last tree where it still divides the graph (a model's patterns differ by
/// its coupling's entries, which mostly stay within a domain); only the domains are then analysed anew.
struct CholmodSplitOptions {
  long memory_limit_megabytes = -1;  // as make_cholmod_llt's (kAvailableMemory)
  long min_unknowns = 100'000;
  long max_separator = 5'000;
  double max_work_share = 0.75;
  // With `levels` 0, a domain whose CHOLMOD analysis counts more than refine_above times an even share of
  // the domains' flops on the threads (their sum over the threads' count) is bisected once more, the
  // heaviest first, as long as one is (at most once per thread in one analysis; a kept tree keeps its
  // refinements): where the work gathers (the soft windows' dense blocks), the domain holding it would
  // otherwise set the time. At 2 threads no domain can hold twice an even share.
  double refine_above = 2.0;
  int levels = 0;
  // The last domain still being factorised gets the BLAS threads of those that have finished. Off by
  // default: OpenBLAS's results depend on its thread count, and the point at which the count changes
  // depends on timing, so two factorisations of one matrix differ (the paper mesh's solution by 1.5e-6
  // relative, where one BLAS thread each to the end gives the same bits every time) for ~2 % of a
  // refactorisation (docs/performance.md, "Idle cores to the last domain").
  bool share_idle_cores = false;
};
std::unique_ptr<LinearSolver> make_cholmod_split_llt(const CholmodSplitOptions& options = {});

/// The rows of all separators of `solver`'s (from make_cholmod_split_llt) last analysis where it split the
/// matrix, 0 otherwise.
long cholmod_split_separator(const LinearSolver& solver);

/// The domains of `solver`'s last analysis where it split the matrix, 0 otherwise.
int cholmod_split_domains(const LinearSolver& solver);

/// Over `solver`'s life (from make_cholmod_split_llt): the domains' analyses that kept the one before (a
/// domain whose rows and pattern stayed), and all of them; {0, 0} for another solver.
std::pair<long, long> cholmod_split_kept_analyses(const LinearSolver& solver);

/// The pivot order of `solver`'s last analysis (as cholmod_pivot_order gives it) where it is from
/// make_cholmod_split_llt: the tree's nodes in postorder, each domain's interior in its factor's order;
/// empty otherwise.
std::vector<int> cholmod_split_pivot_order(const LinearSolver& solver);

}  // namespace fibrane::solve
