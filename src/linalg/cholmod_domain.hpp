#pragma once
// One domain of the split Cholesky (cholmod_split.hpp): CHOLMOD's supernodal LL^T of the domain's rows with
// its boundary rows ordered last, and the trailing boundary block of that factor.
#include <cholmod.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

#include "linalg/cholmod_permuted_lower.hpp"
#include "linalg/principal_lower.hpp"

namespace fibrane::solve {

/// A domain D with its boundary B (rows of separators above it), H = K(D + B, D + B) ordered D, then B:
///   P H P^T = L L^T,  L = [L_DD 0; L_BD C],  C C^T = K_BB - L_BD L_BD^T,
/// so that the domain's update of the boundary, -K_BD K_DD^-1 K_DB = C C^T - K_BB, and its share of a
/// forward solve, -K_BD K_DD^-1 b_D = C v with [w; v] = L^-1 P [b_D; 0], come from this one factor. Each
/// domain has its own CHOLMOD workspace, so that domains factorise side by side on threads of their own.
struct CholmodDomain {
  std::vector<int> rows;  // the whole matrix's rows of the domain's rows: the interior, then the boundary
  int interior = 0;
  PrincipalLower lower;  // the pattern of H's lower triangle, its sources in the whole matrix's values
  CholmodPermutedLower permuted;  // the permuted lower triangle, its source mapped into the whole
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  double flops = 0;  // of a factorisation, as CHOLMOD's analysis counts them
  std::vector<int> boundary_order;  // the boundary rows (0 ... b-1) in the factor's order
  Eigen::MatrixXd c;  // P^T C: the factor's trailing boundary block, its rows in the boundary's order

  CholmodDomain();
  ~CholmodDomain();
  CholmodDomain(const CholmodDomain&) = delete;
  CholmodDomain& operator=(const CholmodDomain&) = delete;
  int size() const { return static_cast<int>(rows.size()); }
  int boundary() const { return size() - interior; }

  /// Analyses H of `a` (rows as set) with the interior in CHOLMOD's fill-reducing order and the boundary
  /// after it; false where CHOLMOD fails or its factor does not keep the boundary last.
  bool analyse(const Eigen::SparseMatrix<double>& a);
  /// Factorises H from a's values and copies out C; false where H is not positive definite or CHOLMOD fails.
  bool factorise(const Eigen::SparseMatrix<double>& a);
  /// The update C C^T - K_BB (lower triangle, the boundary's order) of the last factorisation.
  Eigen::MatrixXd update(const Eigen::SparseMatrix<double>& a) const;
  /// One of CHOLMOD's solves (sys: CHOLMOD_P, CHOLMOD_L, CHOLMOD_Lt, CHOLMOD_Pt) with the factor.
  Eigen::MatrixXd solve(int sys, const Eigen::MatrixXd& b);
  /// Frees the numeric factor and C (the analysis stays).
  void release();
  /// Whether a numeric factor is held.
  bool factored() const { return factor && factor->xtype != CHOLMOD_PATTERN; }

 private:
  bool boundary_last();
};

}  // namespace fibrane::solve
