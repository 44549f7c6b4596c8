#pragma once
// One domain of the split Cholesky (cholmod_split.hpp): CHOLMOD's supernodal LL^T of the domain's rows with
// its boundary rows ordered last, and the trailing boundary block of that factor.
#include <cholmod.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "linalg/cholmod_permuted_lower.hpp"
#include "linalg/mumps_schur.hpp"
#include "linalg/principal_lower.hpp"

namespace fibrane::solve {

/// A domain D with its boundary B (rows of separators above it), H = K(D + B, D + B) ordered D, then B:
///   P H P^T = L L^T,  L = [L_DD 0; L_BD C],  C C^T = K_BB - L_BD L_BD^T,
/// so that the domain's update of the boundary, -K_BD K_DD^-1 K_DB = C C^T - K_BB, and its share of a
/// forward solve, -K_BD K_DD^-1 b_D = C v with [w; v] = L^-1 P [b_D; 0], come from this one factor. Each
/// domain has its own CHOLMOD workspace, so that domains factorise side by side on threads of their own.
/// Where H is not positive definite (an iterate past a limit point, a soft contact), MUMPS's LDL^T with
/// threshold pivoting factorises K_DD and gives the Schur complement S = K_BB - K_BD K_DD^-1 K_DB, whose
/// update is S - K_BB (MumpsSchur), and the forward share by its reduction of [b_D; 0]; `negative` counts
/// K_DD's negative eigenvalues.
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
  std::unique_ptr<MumpsSchur> ldlt;  // where H was not positive definite; analysed at its first use
  bool indefinite = false;  // the last factorisation is ldlt's
  int negative = 0;         // negative eigenvalues of K_DD in the last factorisation
  bool kept_analysis = false;  // the last analyse() kept the analysis before it

  CholmodDomain();
  ~CholmodDomain();
  CholmodDomain(const CholmodDomain&) = delete;
  CholmodDomain& operator=(const CholmodDomain&) = delete;
  int size() const { return static_cast<int>(rows.size()); }
  int boundary() const { return size() - interior; }

  /// Analyses H of `a` (rows as set) with the interior in CHOLMOD's fill-reducing order and the boundary
  /// after it; false where CHOLMOD fails or its factor does not keep the boundary last. Where H's pattern
  /// is the last analysis's (a model's new entries elsewhere in the matrix), that analysis is kept
  /// (`kept_analysis`) and only the entries' places in a's values are taken anew; the next factorisation
  /// then starts as after a fresh analysis.
  bool analyse(const Eigen::SparseMatrix<double>& a);
  /// Factorises H from a's values: LL^T (and C), or where H is not positive definite and the build has
  /// MUMPS, LDL^T with the Schur complement; false where neither succeeds. After an indefinite K_DD, the
  /// next factorisation tries LDL^T first (until one finds K_DD positive definite).
  bool factorise(const Eigen::SparseMatrix<double>& a);
  /// The update of the boundary, C C^T - K_BB or S - K_BB (lower triangle, the boundary's order).
  Eigen::MatrixXd update(const Eigen::SparseMatrix<double>& a) const;
  /// A solve's forward part for the right-hand side [b_D; 0] (`local`, the domain's rows): what
  /// boundary_share() and backward() take (L^-1 P local; with LDL^T, MUMPS's intermediate state and below
  /// it the reduced right-hand side).
  Eigen::MatrixXd forward(const Eigen::MatrixXd& local);
  /// The domain's share of the boundary's right-hand side, -K_BD K_DD^-1 b_D.
  Eigen::MatrixXd boundary_share(const Eigen::MatrixXd& y) const;
  /// The interior's solution x_D = K_DD^-1 (b_D - K_DB x_B), from forward()'s y (which it consumes).
  Eigen::MatrixXd backward(Eigen::MatrixXd& y, const Eigen::MatrixXd& x_b);
  /// One of CHOLMOD's solves (sys: CHOLMOD_P, CHOLMOD_L, CHOLMOD_Lt, CHOLMOD_Pt) with the LL^T factor.
  Eigen::MatrixXd solve(int sys, const Eigen::MatrixXd& b);
  /// Frees the numeric factors and C (CHOLMOD's analysis stays).
  void release();
  /// Whether a numeric factor is held.
  bool factored() const { return indefinite || (factor && factor->xtype != CHOLMOD_PATTERN); }
  /// Entries of the numeric factors held (CHOLMOD's and MUMPS's; one of them after a factorisation).
  long factor_entries() const;

 private:
  bool boundary_last();
  bool factorise_llt(const Eigen::SparseMatrix<double>& a);
  bool factorise_ldlt(const Eigen::SparseMatrix<double>& a);
  bool ldlt_first_ = false;
};

}  // namespace fibrane::solve
