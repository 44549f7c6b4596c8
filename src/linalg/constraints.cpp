#include "linalg/constraints.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/error.hpp"

namespace fibrane::solve {
namespace {

using Terms = std::vector<std::pair<int, double>>;

// Sorts by key, sums equal keys and drops exact zeros, so equal combinations compare equal.
void normalize(Terms& terms) {
  std::sort(terms.begin(), terms.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Terms merged;
  for (const auto& [key, coef] : terms) {
    if (!merged.empty() && merged.back().first == key)
      merged.back().second += coef;
    else
      merged.emplace_back(key, coef);
  }
  std::erase_if(merged, [](const auto& kc) { return kc.second == 0.0; });
  terms = std::move(merged);
}

bool nearly_equal(double a, double b) {
  return std::abs(a - b) <= 1e-12 * std::max({1.0, std::abs(a), std::abs(b)});
}

bool same_terms(const Terms& a, const Terms& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].first != b[i].first || !nearly_equal(a[i].second, b[i].second)) return false;
  return true;
}

Terms prescribed_of(const LinearConstraint& c) {
  Terms t;
  if (c.value != 0.0) t.emplace_back(c.curve < 0 ? -1 : c.curve, c.value);
  return t;
}

const Terms kEmpty;

}  // namespace

void ConstraintSet::add(LinearConstraint c) {
  normalize(c.masters);
  raw_.push_back(std::move(c));
  finalized_ = false;
}

std::vector<int> ConstraintSet::linked_dofs(const std::vector<int>& dofs) const {
  // Union-find over the relation "appear in one constraint" (usable before finalize()).
  int n = n_dofs_;
  for (const auto& c : raw_) {
    n = std::max(n, c.slave + 1);
    for (const auto& [m, coef] : c.masters) n = std::max(n, m + 1);
  }
  for (int d : dofs) n = std::max(n, d + 1);
  std::vector<int> parent(static_cast<size_t>(n));
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int d) {
    while (parent[static_cast<size_t>(d)] != d) d = parent[static_cast<size_t>(d)] = parent[static_cast<size_t>(parent[static_cast<size_t>(d)])];
    return d;
  };
  for (const auto& c : raw_)
    for (const auto& [m, coef] : c.masters) parent[static_cast<size_t>(find(m))] = find(c.slave);
  std::vector<char> wanted(parent.size(), 0);
  for (int d : dofs) wanted[static_cast<size_t>(find(d))] = 1;
  std::vector<int> out;
  for (int d = 0; d < n; ++d)
    if (wanted[static_cast<size_t>(find(d))]) out.push_back(d);
  return out;
}

void ConstraintSet::fix(int dof, double value, int curve) {
  add(LinearConstraint{dof, {}, value, curve});
}

void ConstraintSet::finalize(int n_dofs) {
  n_dofs_ = n_dofs;
  slave_of_.assign(static_cast<size_t>(n_dofs), -1);
  std::vector<int> deferred;  // raw constraints on an already-constrained DOF, checked after resolution
  auto check_range = [&](int dof, int slave, size_t i) {
    if (dof < 0 || dof >= n_dofs)
      throw ConstraintError("constraint on DOF " + std::to_string(slave) + " refers to DOF " + std::to_string(dof) +
                                ", outside [0, " + std::to_string(n_dofs) + ")",
                            {slave}, {i});
  };
  for (size_t i = 0; i < raw_.size(); ++i) {
    const LinearConstraint& c = raw_[i];
    check_range(c.slave, c.slave, i);
    for (const auto& [m, coef] : c.masters) {
      check_range(m, c.slave, i);
      if (m == c.slave)
        throw ConstraintError("constraint on DOF " + std::to_string(c.slave) + " refers to itself (cycle)",
                              {c.slave}, {i});
    }
    int& owner = slave_of_[static_cast<size_t>(c.slave)];
    if (owner >= 0) {
      const LinearConstraint& first = raw_[static_cast<size_t>(owner)];
      if (same_terms(first.masters, c.masters) && same_terms(prescribed_of(first), prescribed_of(c)))
        continue;  // identical duplicate: keep the first
      // A second, different constraint on the same DOF is accepted only if it agrees with the first once
      // every chain is resolved (e.g. a corner fixed by one edge and tied to its neighbour by another).
      // The one with fewer masters is kept as the definition; the other is checked after resolution.
      if (c.masters.size() < first.masters.size()) {
        deferred.push_back(owner);
        owner = static_cast<int>(i);
      } else {
        deferred.push_back(static_cast<int>(i));
      }
      continue;
    }
    owner = static_cast<int>(i);
  }

  // Resolve chains depth-first; state 0 = unvisited, 1 = on the current path, 2 = done.
  resolved_.assign(static_cast<size_t>(n_dofs), Resolved{});
  std::vector<int> state(static_cast<size_t>(n_dofs), 0), path;
  for (int d = 0; d < n_dofs; ++d)
    if (slave_of_[static_cast<size_t>(d)] >= 0 && state[static_cast<size_t>(d)] == 0)
      resolve(d, state, path);

  for (int i : deferred) check_agrees(static_cast<size_t>(i));

  dof_to_free_.assign(static_cast<size_t>(n_dofs), -1);
  free_to_dof_.clear();
  for (int d = 0; d < n_dofs; ++d)
    if (slave_of_[static_cast<size_t>(d)] < 0) {
      dof_to_free_[static_cast<size_t>(d)] = static_cast<int>(free_to_dof_.size());
      free_to_dof_.push_back(d);
    }
  rows_.assign(static_cast<size_t>(n_dofs), {});
  for (int d = 0; d < n_dofs; ++d) {
    auto& row = rows_[static_cast<size_t>(d)];
    if (slave_of_[static_cast<size_t>(d)] < 0) {
      row.emplace_back(dof_to_free_[static_cast<size_t>(d)], 1.0);
    } else {
      for (const auto& [m, coef] : resolved_[static_cast<size_t>(d)].masters)
        row.emplace_back(dof_to_free_[static_cast<size_t>(m)], coef);  // increasing: numbering is monotone
    }
  }
  finalized_ = true;
}

void ConstraintSet::substitute(int master, double coef, Resolved& out) const {
  if (slave_of_[static_cast<size_t>(master)] < 0) {
    out.masters.emplace_back(master, coef);
    return;
  }
  const Resolved& sub = resolved_[static_cast<size_t>(master)];
  for (const auto& [mm, cc] : sub.masters) out.masters.emplace_back(mm, coef * cc);
  for (const auto& [curve, amp] : sub.terms) out.terms.emplace_back(curve, coef * amp);
}

void ConstraintSet::check_agrees(size_t index) const {
  const LinearConstraint& c = raw_[index];
  Resolved r;
  r.terms = prescribed_of(c);
  for (const auto& [m, coef] : c.masters) substitute(m, coef, r);
  normalize(r.masters);
  normalize(r.terms);
  const Resolved& kept = resolved_[static_cast<size_t>(c.slave)];
  if (!same_terms(kept.masters, r.masters) || !same_terms(kept.terms, r.terms))
    throw ConstraintError("conflicting constraints on DOF " + std::to_string(c.slave) +
                              " (it is constrained twice, and the two constraints disagree)",
                          {c.slave}, {static_cast<size_t>(slave_of_[static_cast<size_t>(c.slave)]), index});
}

void ConstraintSet::resolve(int dof, std::vector<int>& state, std::vector<int>& path) {
  state[static_cast<size_t>(dof)] = 1;
  path.push_back(dof);
  const LinearConstraint& c = raw_[static_cast<size_t>(slave_of_[static_cast<size_t>(dof)])];
  Resolved out;
  out.terms = prescribed_of(c);
  for (const auto& [m, coef] : c.masters) {
    if (slave_of_[static_cast<size_t>(m)] >= 0 && state[static_cast<size_t>(m)] == 1) {
      std::string cycle;
      std::vector<int> dofs;
      std::vector<size_t> involved;
      auto start = std::find(path.begin(), path.end(), m);
      for (auto it = start; it != path.end(); ++it) {
        cycle += std::to_string(*it) + " -> ";
        dofs.push_back(*it);
        involved.push_back(static_cast<size_t>(slave_of_[static_cast<size_t>(*it)]));
      }
      throw ConstraintError("cyclic constraints: DOF " + cycle + std::to_string(m), dofs, involved);
    }
    if (slave_of_[static_cast<size_t>(m)] >= 0 && state[static_cast<size_t>(m)] == 0) resolve(m, state, path);
    substitute(m, coef, out);
  }
  normalize(out.masters);
  normalize(out.terms);
  resolved_[static_cast<size_t>(dof)] = std::move(out);
  path.pop_back();
  state[static_cast<size_t>(dof)] = 2;
}

void ConstraintSet::check_ready(int dof) const {
  if (!finalized_) throw std::logic_error("ConstraintSet used before finalize()");
  if (dof < 0 || dof >= n_dofs_)
    throw std::out_of_range("ConstraintSet: DOF " + std::to_string(dof) + " out of range");
}

bool ConstraintSet::is_constrained(int dof) const {
  check_ready(dof);
  return slave_of_[static_cast<size_t>(dof)] >= 0;
}

int ConstraintSet::free_index(int dof) const {
  check_ready(dof);
  return dof_to_free_[static_cast<size_t>(dof)];
}

const std::vector<std::pair<int, double>>& ConstraintSet::expansion(int dof) const {
  check_ready(dof);
  return rows_[static_cast<size_t>(dof)];
}

const std::vector<std::pair<int, double>>& ConstraintSet::prescribed_terms(int dof) const {
  check_ready(dof);
  return slave_of_[static_cast<size_t>(dof)] < 0 ? kEmpty : resolved_[static_cast<size_t>(dof)].terms;
}

Eigen::VectorXd ConstraintSet::expand(const Eigen::VectorXd& q, double t, const CurveEval& curves) const {
  if (!finalized_) throw std::logic_error("ConstraintSet used before finalize()");
  if (q.size() != num_free()) throw std::invalid_argument("ConstraintSet::expand: wrong size of q");
  Eigen::VectorXd u(n_dofs_);
  for (int d = 0; d < n_dofs_; ++d) {
    double value = 0.0;
    for (const auto& [i, coef] : rows_[static_cast<size_t>(d)]) value += coef * q[i];
    if (slave_of_[static_cast<size_t>(d)] >= 0)
      for (const auto& [curve, amp] : resolved_[static_cast<size_t>(d)].terms)
        value += amp * (curve < 0 ? 1.0 : curves(curve, t));
    u[d] = value;
  }
  return u;
}

Eigen::VectorXd ConstraintSet::prescribed_rate(double t, const CurveEval& curve_derivatives) const {
  if (!finalized_) throw std::logic_error("ConstraintSet used before finalize()");
  Eigen::VectorXd g_t = Eigen::VectorXd::Zero(n_dofs_);
  for (int d = 0; d < n_dofs_; ++d)
    if (slave_of_[static_cast<size_t>(d)] >= 0)
      for (const auto& [curve, amp] : resolved_[static_cast<size_t>(d)].terms)
        if (curve >= 0) g_t[d] += amp * curve_derivatives(curve, t);
  return g_t;
}

Eigen::VectorXd ConstraintSet::restrict_vector(const Eigen::VectorXd& full) const {
  if (!finalized_) throw std::logic_error("ConstraintSet used before finalize()");
  if (full.size() != n_dofs_) throw std::invalid_argument("ConstraintSet::restrict_vector: wrong size");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(num_free());
  for (int d = 0; d < n_dofs_; ++d)
    for (const auto& [i, coef] : rows_[static_cast<size_t>(d)]) out[i] += coef * full[d];
  return out;
}

Eigen::VectorXd ConstraintSet::free_values(const Eigen::VectorXd& u) const {
  if (!finalized_) throw std::logic_error("ConstraintSet used before finalize()");
  if (u.size() != n_dofs_) throw std::invalid_argument("ConstraintSet::free_values: wrong size");
  Eigen::VectorXd q(num_free());
  for (int i = 0; i < num_free(); ++i) q[i] = u[free_to_dof_[static_cast<size_t>(i)]];
  return q;
}

std::vector<int> ConstraintSet::constrained_dofs() const {
  std::vector<int> out;
  for (int d = 0; d < n_dofs_; ++d)
    if (slave_of_[static_cast<size_t>(d)] >= 0) out.push_back(d);
  return out;
}

}  // namespace fibrane::solve
