#pragma once
// Linear multi-point constraints and prescribed values, eliminated exactly.
//
// Every constraint reads  u[slave] = sum_k c_k u[master_k] + value * curve(t).
// After finalize() the full displacement vector is an affine function of the free unknowns q:
//   u = T q + g(t),
// where row d of T is the identity for a free DOF and the resolved master combination for a slave.
// The discrete equilibrium equations (paper Eq. (7) after discretisation), r(u) = 0, become
// T^T r(T q + g) = 0 with tangent T^T K T: no penalty, no Lagrange multipliers, exact to round-off.
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "common/error.hpp"

namespace fibrane::solve {

// A constraint set that cannot be resolved (conflict, cycle, DOF out of range). `dofs` are the DOFs it is
// about, `constraints` the indices (in the order added) of the constraints involved, so that a reader can
// name them in its own terms (bodies, control points, lines of a case file).
class ConstraintError : public InputError {
 public:
  ConstraintError(const std::string& message, std::vector<int> dofs, std::vector<std::size_t> constraints)
      : InputError(message), dofs(std::move(dofs)), constraints(std::move(constraints)) {}
  std::vector<int> dofs;
  std::vector<std::size_t> constraints;
};

// Load curve evaluator: curve id and quasi-time -> factor. Curve id < 0 means "constant 1".
using CurveEval = std::function<double(int curve, double t)>;

struct LinearConstraint {
  int slave = -1;
  std::vector<std::pair<int, double>> masters;  // (dof, coefficient)
  double value = 0.0;
  int curve = -1;
};

class ConstraintSet {
 public:
  void add(LinearConstraint c);
  void fix(int dof, double value = 0.0, int curve = -1);

  // Resolves chains (a master that is itself a slave is substituted), rejects conflicting duplicate
  // constraints on one slave and cycles (throws ConstraintError naming the DOFs) and numbers the
  // free DOFs in increasing DOF order. Identical duplicates are allowed (a corner fixed by two edges).
  // May be called again after further add()/fix() calls.
  void finalize(int n_dofs);
  bool finalized() const { return finalized_; }

  int num_free() const { return static_cast<int>(free_to_dof_.size()); }
  int num_dofs() const { return n_dofs_; }
  bool is_constrained(int dof) const;
  int free_index(int dof) const;   // -1 for a constrained DOF
  int free_dof(int i) const { return free_to_dof_[static_cast<size_t>(i)]; }

  // Row `dof` of T as (free index, coefficient) pairs; empty for a DOF with a prescribed value only.
  const std::vector<std::pair<int, double>>& expansion(int dof) const;
  // Inhomogeneous part of row `dof` as (curve id, amplitude) pairs: g_dof(t) = sum amplitude*curve(t).
  const std::vector<std::pair<int, double>>& prescribed_terms(int dof) const;

  Eigen::VectorXd expand(const Eigen::VectorXd& q, double t, const CurveEval& curves) const;  // T q + g
  // dg/dt: the prescribed part's rate, given the curves' derivatives (constant terms have none).
  Eigen::VectorXd prescribed_rate(double t, const CurveEval& curve_derivatives) const;
  Eigen::VectorXd restrict_vector(const Eigen::VectorXd& full) const;                            // T^T r
  Eigen::VectorXd free_values(const Eigen::VectorXd& u) const;  // q from a consistent full u
  std::vector<int> constrained_dofs() const;                   // increasing order

  // The constraints added so far, in order (slaves and masters as given, before resolution).
  int num_added() const { return static_cast<int>(raw_.size()); }
  const LinearConstraint& added(int i) const { return raw_[static_cast<size_t>(i)]; }
  // `dofs` and every DOF linked to them through constraints (a slave and its masters are linked; the
  // closure is transitive), sorted. The full residual summed over such a set is the force its supports
  // exert: at equilibrium the free DOFs of the set balance among themselves.
  std::vector<int> linked_dofs(const std::vector<int>& dofs) const;

 private:
  struct Resolved {
    std::vector<std::pair<int, double>> masters;  // free DOFs (global numbers) before numbering
    std::vector<std::pair<int, double>> terms;    // (curve, amplitude)
  };
  void check_ready(int dof) const;
  // Appends coef * (master, or master's resolved expansion if it is a slave already resolved) to out.
  void substitute(int master, double coef, Resolved& out) const;
  void check_agrees(std::size_t index) const;
  void resolve(int dof, std::vector<int>& state, std::vector<int>& path);

  std::vector<LinearConstraint> raw_;
  std::vector<int> slave_of_;                 // dof -> index into raw_ or -1
  std::vector<Resolved> resolved_;            // per dof (only meaningful for constrained ones)
  std::vector<std::vector<std::pair<int, double>>> rows_;   // T rows, free indices
  std::vector<int> dof_to_free_, free_to_dof_;
  int n_dofs_ = 0;
  bool finalized_ = false;
};

}  // namespace fibrane::solve
