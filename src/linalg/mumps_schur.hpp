#pragma once
// MUMPS's LDL^T of a symmetric matrix with its last rows kept out as a dense Schur complement: the factor of
// an indefinite domain in the split factorisation (cholmod_domain.hpp).
#include <Eigen/Dense>
#include <memory>
#include <vector>

namespace fibrane::solve {

/// H = [H_II H_IB; H_BI H_BB] (n rows, the last b of them B) factorised by MUMPS's multifrontal LDL^T with
/// threshold pivoting (SYM = 2) within I, B eliminated by nobody (MUMPS's Schur complement, ICNTL(19)):
///   S = H_BB - H_BI H_II^-1 H_IB (dense, both triangles),
/// with the inertia of H_II (INFOG(12): its negative pivots). A solve of H x = [b_I; b_B] is split in two
/// (ICNTL(26)): reduce() condenses the right-hand side to b_B - H_BI H_II^-1 b_I, and expand() takes the
/// solution x_B of the condensed system to x_I = H_II^-1 (b_I - H_IB x_B).
///
/// Debian's sequential MUMPS keeps state in Fortran modules and is not known to be safe for instances on
/// several threads at once: every call into it holds one lock for the process. Without MUMPS in the build
/// (FIBRANE_HAVE_MUMPS) available() is false and analyse() fails.
class MumpsSchur {
 public:
  MumpsSchur();
  ~MumpsSchur();
  MumpsSchur(const MumpsSchur&) = delete;
  MumpsSchur& operator=(const MumpsSchur&) = delete;
  static bool available();

  /// The pattern: the lower triangle's coordinates (0-based, row >= column), in the order factorise() will
  /// give the values, and the pivot order of I (0-based rows, B's rows after them); false where MUMPS fails.
  bool analyse(int n, int boundary, const std::vector<int>& rows, const std::vector<int>& columns,
               const std::vector<int>& pivot_order);
  /// Factorises the values of the analysed coordinates and fetches S; false where MUMPS fails (a singular
  /// H_II, memory).
  bool factorise(const double* values);
  /// S of the last factorisation, both triangles.
  const Eigen::MatrixXd& schur() const { return schur_; }
  /// INFOG(12) of the last factorisation.
  int negative_pivots() const;
  /// Entries of the factor of H_II (INFOG(29)).
  long factor_entries() const;

  /// rhs (n rows) to MUMPS's intermediate state, kept for expand(); returns b_B - H_BI H_II^-1 b_I (b rows).
  Eigen::MatrixXd reduce(Eigen::MatrixXd& rhs) const;
  /// rhs as reduce() left it, and x_B: rhs becomes the solution x (n rows, x_B in the last b).
  void expand(Eigen::MatrixXd& rhs, const Eigen::MatrixXd& x_b) const;

 private:
  struct Instance;
  bool solve_phase(int phase, Eigen::MatrixXd& rhs, Eigen::MatrixXd& reduced) const;
  std::unique_ptr<Instance> id_;
  Eigen::MatrixXd schur_;
  int boundary_ = 0;
  bool factored_ = false;
};

}  // namespace fibrane::solve
