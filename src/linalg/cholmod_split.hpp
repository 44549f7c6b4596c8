#pragma once
// CHOLMOD's supernodal LL^T of a large matrix in two halves, factorised side by side.
#include <memory>
#include <vector>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

/// A symmetric positive definite K split at METIS's top node separator S into two interiors that do not
/// touch, K = [K00 0 K0S; 0 K11 K1S; KS0 KS1 KSS]. Each half H_k = [Kkk KkS; KSk KSS], ordered with S last,
/// is factorised by CHOLMOD's supernodal LL^T on a thread of its own (one BLAS thread each):
///   P_k H_k P_k^T = L_k L_k^T,  L_k = [Lkk 0; LSk C_k],  C_k C_k^T = KSS - LSk LSk^T,
/// so that K's Schur complement on S is T = KSS - sum_k LSk LSk^T = C_0 C_0^T + C_1 C_1^T - KSS, whose
/// dense LL^T (LAPACK) completes the factorisation. A solve runs forward through both halves with the
/// separator's right-hand side 0 (the separator part of L_k^{-1} [b_k; 0] is v_k = -C_k^{-1} LSk w_k), solves
/// T x_S = b_S + sum_k C_k v_k, and back through both halves with C_k^T x_S in the separator's place.
///
/// CHOLMOD's supernodal code factorises one supernode at a time, its parallelism only within the BLAS
/// calls, where a second core adds little; the halves side by side keep two cores busy (docs/performance.md,
/// "The factorisation's input"). Matrices below `min_unknowns`, a single thread, or a split that does not
/// serve (a separator above `max_separator`, a half below a fifth of the unknowns, one half with more than
/// `max_work_share` of the flops, CHOLMOD's ordering not keeping S last) are factorised whole by
/// make_cholmod_llt's solver. The name is "cholmod" either way. A new pattern keeps the last bisection
/// where it still separates the graph (a model's patterns differ by its coupling's entries, which mostly
/// stay within a half); only the halves are then analysed anew.
struct CholmodSplitOptions {
  long memory_limit_megabytes = -1;  // as make_cholmod_llt's (kAvailableMemory)
  long min_unknowns = 100'000;
  long max_separator = 5'000;
  double max_work_share = 0.75;  // the larger half's share of the two halves' flops at most
};
std::unique_ptr<LinearSolver> make_cholmod_split_llt(const CholmodSplitOptions& options = {});

/// Whether `solver` (from make_cholmod_split_llt) factorised its last matrix in two halves; the separator's
/// size then (0 otherwise).
long cholmod_split_separator(const LinearSolver& solver);

/// The pivot order of `solver`'s last analysis (as cholmod_pivot_order gives it) where it is from
/// make_cholmod_split_llt: the two interiors in their factors' orders, then the separator; empty otherwise.
std::vector<int> cholmod_split_pivot_order(const LinearSolver& solver);

}  // namespace fibrane::solve
