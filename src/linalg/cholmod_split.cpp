// CHOLMOD's supernodal LL^T in domains side by side below a tree of dense separator fronts (the algebra is
// in cholmod_split.hpp).
#include "linalg/cholmod_split.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include "linalg/cholmod_domain.hpp"
#include "linalg/dense_front.hpp"
#include "linalg/direct_solvers.hpp"
#include "linalg/separator_tree.hpp"
#include "linalg/side_by_side.hpp"

namespace fibrane::solve {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// The solver: domains and fronts where the matrix is split, make_cholmod_llt's solver where it is not.
class CholmodSplitSolver final : public LinearSolver {
 public:
  explicit CholmodSplitSolver(const CholmodSplitOptions& o) : options_(o) {}

  void analyze(const SpMat& a) override {
    std::vector<std::unique_ptr<CholmodDomain>> last = std::move(domains_);  // offered to split() for reuse
    for (auto& d : last) d->release();  // their numeric factors, freed before the analyses as the rest is
    clear_parts();
    hand_back_freed_memory();
    threads_ = omp_get_max_threads();
    split_ = a.rows() >= options_.min_unknowns && threads_ >= 2 && a.isCompressed() && split(a, last);
    if (split_) return;
    last.clear();
    tree_.clear();  // a tree that did not serve is not kept: the next pattern is divided anew
    clear_parts();
    if (!whole_) whole_ = make_cholmod_llt(options_.memory_limit_megabytes);
    whole_->analyze(a);
  }
  bool factorize_numeric(const SpMat& a) override {
    factored_ = false;
    if (!split_) return whole_->factorize(a);
    if (const std::string refusal = memory_refusal(); !refusal.empty()) {
      refusal_ = refusal;
      return false;
    }
    refusal_.clear();
    updates_.assign(domains_.size(), {});
    const auto t0 = std::chrono::steady_clock::now();
    const bool domains_ok = side_by_side(domain_order_, threads_, [&](int d) {
      CholmodDomain& domain = *domains_[static_cast<std::size_t>(d)];
      if (!domain.factorise(a)) return false;
      updates_[static_cast<std::size_t>(d)] = domain.update(a);
      return true;
    }, options_.share_idle_cores);
    const auto t1 = std::chrono::steady_clock::now();
    factored_ = domains_ok && factorise_fronts(a);
    if (!factored_) ++failures_;
    for (const auto& d : domains_) domain_ldlt_ += d->indefinite;
    if (factored_)
      for (const auto& f : fronts_) front_ldlt_ += f.ldlt();
    updates_.clear();
    domain_seconds_ += std::chrono::duration<double>(t1 - t0).count();
    front_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    ++factorisations_;
    return factored_;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override {
    if (!split_) return whole_->solve(b);
    return solve_columns(b);
  }
  // All columns together: one pass through each factor (the rank-m correction of "auto" solves m).
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const override {
    if (!split_) return whole_->solve_columns(b);
    std::vector<Eigen::MatrixXd> y(domains_.size()), r(fronts_.size());
    forward_domains(b, y);
    forward_fronts(b, y, r);
    Eigen::MatrixXd x(b.rows(), b.cols());
    for (auto k = static_cast<int>(fronts_.size()) - 1; k >= 0; --k) {  // the fronts backward, top down
      const SeparatorTree::Node& node = front_node(k);
      Eigen::MatrixXd y_s = r[static_cast<std::size_t>(k)].topRows(node.rows.size());
      fronts_[static_cast<std::size_t>(k)].backward(y_s, x(node.boundary, Eigen::all));
      x(node.rows, Eigen::all) = y_s;
    }
    std::vector<int> all(domains_.size());
    std::iota(all.begin(), all.end(), 0);
    side_by_side(all, threads_, [&](int d) {  // the domains backward
      CholmodDomain& domain = *domains_[static_cast<std::size_t>(d)];
      const Eigen::MatrixXd local = domain.backward(y[static_cast<std::size_t>(d)], x(domain_node(d).boundary, Eigen::all));
      for (int i = 0; i < domain.interior; ++i) x.row(domain.rows[static_cast<std::size_t>(i)]) = local.row(i);
      return true;
    });
    return x;
  }
  std::string name() const override { return "cholmod"; }
  long factor_nonzeros() const override {
    if (!split_) return whole_ ? whole_->factor_nonzeros() : 0;
    long entries = 0;
    for (const auto& d : domains_) entries += static_cast<long>(d->factor->xsize);
    for (const auto& f : fronts_) entries += f.factor_entries();
    return entries;
  }
  std::string analysis_summary() const override {
    if (!split_) return whole_ ? whole_->analysis_summary() : std::string();
    char text[300];
    if (domains_.size() == 2) {
      std::snprintf(text, sizeof text, "in two halves at a separator of %ld (%.3g and %.3g GFlop)",
                    tree_.separator_rows(), domains_[0]->flops / 1e9, domains_[1]->flops / 1e9);
    } else {
      double total = 0, largest = 0, fronts = 0;
      for (const auto& d : domains_) total += d->flops, largest = std::max(largest, d->flops);
      for (const auto& f : fronts_) fronts += f.flops();
      std::snprintf(text, sizeof text,
                    "in %zu domains below %zu separators of %ld rows (domains %.3g GFlop, the largest %.3g; "
                    "fronts %.3g GFlop)",
                    domains_.size(), fronts_.size(), tree_.separator_rows(), total / 1e9, largest / 1e9,
                    fronts / 1e9);
    }
    std::string summary = text;
    if (factorisations_ > 0) {  // the solver's whole life, over all patterns
      std::snprintf(text, sizeof text,
                    "; %ld split factorisations: domains %.1f s, fronts %.1f s; LDL^T where not positive definite: "
                    "%ld in a domain, %ld in a front; failed: %ld; domains' analyses kept: %ld of %ld",
                    factorisations_, domain_seconds_, front_seconds_, domain_ldlt_, front_ldlt_, failures_,
                    kept_analyses_, domain_analyses_);
      summary += text;
    }
    return summary;
  }
  // Sylvester's law on the block elimination: the domains' K_DD and the fronts' F_SS after their updates.
  int negative_eigenvalues() const override {
    if (!split_) return whole_ ? whole_->negative_eigenvalues() : -1;
    if (!factored_) return -1;
    int negative = 0;
    for (const auto& d : domains_) negative += d->negative;
    for (const auto& f : fronts_) negative += f.negative();
    return negative;
  }
  std::string failure_detail() const override { return split_ ? refusal_ : whole_ ? whole_->failure_detail() : ""; }
  void release_factor() override {
    factored_ = false;
    if (!split_) {
      if (whole_) whole_->release_factor();
      return;
    }
    for (auto& d : domains_) d->release();
    for (auto& f : fronts_) f.release();
  }
  long held_factor_entries() const override {
    if (!split_) return whole_ ? whole_->held_factor_entries() : 0;
    long held = 0;
    for (const auto& d : domains_) held += d->factor_entries();
    for (const auto& f : fronts_)
      if (f.factored()) held += f.factor_entries();
    return held;
  }
  long separator() const { return split_ ? tree_.separator_rows() : 0; }
  int domain_count() const { return split_ ? static_cast<int>(domains_.size()) : 0; }
  std::pair<long, long> kept_analyses() const { return {kept_analyses_, domain_analyses_}; }
  // The tree's nodes in postorder, each domain's interior in its factor's order.
  std::vector<int> pivot_order() const {
    if (!split_) return whole_ ? cholmod_pivot_order(*whole_) : std::vector<int>();
    std::vector<int> order;
    const auto& nodes = tree_.nodes();
    for (std::size_t t = 0; t < nodes.size(); ++t) {
      if (!nodes[t].domain()) {
        order.insert(order.end(), nodes[t].rows.begin(), nodes[t].rows.end());
        continue;
      }
      const CholmodDomain& d = *domains_[static_cast<std::size_t>(part_of_[t])];
      const auto* perm = static_cast<const int*>(d.factor->Perm);
      for (int k = 0; k < d.interior; ++k) order.push_back(d.rows[static_cast<std::size_t>(perm[k])]);
    }
    return order;
  }

 private:
  int levels() const {
    if (options_.levels > 0) return options_.levels;
    int levels = 1;
    while ((1 << levels) < threads_) ++levels;
    return levels;
  }
  void clear_parts() {
    domains_.clear();
    fronts_.clear();
    part_of_.clear();
    domain_nodes_.clear();
    front_nodes_.clear();
    heights_.clear();
    domain_order_.clear();
    updates_.clear();
    factored_ = false;
  }
  const SeparatorTree::Node& front_node(int k) const {
    return tree_.nodes()[static_cast<std::size_t>(front_nodes_[static_cast<std::size_t>(k)])];
  }
  const SeparatorTree::Node& domain_node(int d) const {
    return tree_.nodes()[static_cast<std::size_t>(domain_nodes_[static_cast<std::size_t>(d)])];
  }

  // The tree (kept where it still divides a's graph, refined where one domain holds too much of the work)
  // and the analyses of its domains; false where the split does not serve.
  bool split(const SpMat& a, std::vector<std::unique_ptr<CholmodDomain>>& last) {
    const SeparatorTree::Options tree_options{.levels = levels(), .min_rows = 1000, .max_separator = options_.max_separator};
    if (tree_.divides(a))
      tree_.update_boundaries(a);
    else if (!tree_.build(a, tree_options))
      return false;
    if (!set_domains(a, last, false)) return false;
    // With the depth from the threads, a domain with more than refine_above times an even share of the
    // domains' work on the threads is bisected again, the heaviest first, at most as many times as there
    // are threads in one analysis (a kept tree keeps its refinements, and may take more as the work
    // gathers). A failed analysis of the new domains leaves the matrix to the whole factorisation.
    for (int refined = 0; options_.levels == 0 && refined < threads_; ++refined) {
      const auto heaviest = std::max_element(domains_.begin(), domains_.end(),
                                             [](const auto& x, const auto& y) { return x->flops < y->flops; });
      const double total = std::accumulate(domains_.begin(), domains_.end(), 0.0,
                                           [](double sum, const auto& d) { return sum + d->flops; });
      if ((*heaviest)->flops <= options_.refine_above * total / threads_) break;
      const int node = domain_nodes_[static_cast<std::size_t>(heaviest - domains_.begin())];
      if (!tree_.refine(a, node, tree_options)) break;
      std::vector<std::unique_ptr<CholmodDomain>> analysed = std::move(domains_);
      clear_parts();
      if (!set_domains(a, analysed, true)) return false;
    }
    std::vector<double> work;
    for (const auto& d : domains_) work.push_back(d->flops);
    domain_order_.resize(domains_.size());
    std::iota(domain_order_.begin(), domain_order_.end(), 0);
    std::stable_sort(domain_order_.begin(), domain_order_.end(),
                     [&](int x, int y) { return work[static_cast<std::size_t>(x)] > work[static_cast<std::size_t>(y)]; });
    set_fronts(a);
    // Side by side, the domain that finishes last sets the time; the whole factorisation runs at little
    // more than one core's speed on any number of threads (docs/performance.md, "The factorisation's
    // input"): the split pays until the schedule is nearly one thread's.
    const double total = std::accumulate(work.begin(), work.end(), 0.0);
    return makespan(work, threads_) <= options_.max_work_share * total;
  }
  // The tree's domains and fronts, the domains analysed side by side. A domain of `last` with the same rows
  // serves again (the others are freed first): after the last analysis (its numeric factor freed) it keeps
  // its analysis where its pattern is the same (CholmodDomain::analyse); after a refinement of the tree
  // (`refinement`: `last` was analysed for `a`) it is not analysed again.
  bool set_domains(const SpMat& a, std::vector<std::unique_ptr<CholmodDomain>>& last, bool refinement) {
    const auto& nodes = tree_.nodes();
    domains_.clear();
    domain_nodes_.clear();
    front_nodes_.clear();
    part_of_.assign(nodes.size(), -1);
    for (std::size_t t = 0; t < nodes.size(); ++t) {
      std::vector<int>& list = nodes[t].domain() ? domain_nodes_ : front_nodes_;
      part_of_[t] = static_cast<int>(list.size());
      list.push_back(static_cast<int>(t));
    }
    // the top bisection leaves each side a fifth of the rows at least (SeparatorTree::Options)
    std::vector<int> to_analyse;
    for (std::size_t t = 0; t < domain_nodes_.size(); ++t) {
      const SeparatorTree::Node& node = nodes[static_cast<std::size_t>(domain_nodes_[t])];
      std::vector<int> rows = node.rows;
      rows.insert(rows.end(), node.boundary.begin(), node.boundary.end());
      const auto same = std::find_if(last.begin(), last.end(), [&](const auto& d) {
        return d && d->interior == static_cast<int>(node.rows.size()) && d->rows == rows;
      });
      const bool again = same != last.end();
      std::unique_ptr<CholmodDomain> d = again ? std::move(*same) : std::make_unique<CholmodDomain>();
      d->rows = std::move(rows);
      d->interior = static_cast<int>(node.rows.size());
      domains_.push_back(std::move(d));
      if (!again || !refinement) to_analyse.push_back(static_cast<int>(t));
    }
    last.clear();
    if (!side_by_side(to_analyse, threads_, [&](int d) { return domains_[static_cast<std::size_t>(d)]->analyse(a); }))
      return false;
    for (const int d : to_analyse) kept_analyses_ += domains_[static_cast<std::size_t>(d)]->kept_analysis;
    domain_analyses_ += static_cast<long>(to_analyse.size());
    return true;
  }
  // Each separator's front: K's entries with a row or column in it, its children's maps; the fronts grouped
  // by height.
  void set_fronts(const SpMat& a) {
    const auto& nodes = tree_.nodes();
    std::vector<int> local(static_cast<std::size_t>(a.rows()), -1);
    fronts_.assign(front_nodes_.size(), DenseFront());
    for (std::size_t k = 0; k < front_nodes_.size(); ++k) {
      const SeparatorTree::Node& node = nodes[static_cast<std::size_t>(front_nodes_[k])];
      const int s = static_cast<int>(node.rows.size()), b = static_cast<int>(node.boundary.size());
      std::vector<int> rows(node.rows);
      rows.insert(rows.end(), node.boundary.begin(), node.boundary.end());
      for (int i = 0; i < s + b; ++i) local[static_cast<std::size_t>(rows[static_cast<std::size_t>(i)])] = i;
      std::vector<std::pair<int, long>> entries;
      for (const int j : rows) {
        const int lj = local[static_cast<std::size_t>(j)];
        for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p) {
          const int i = a.innerIndexPtr()[p], li = local[static_cast<std::size_t>(i)];
          if (i < j || li < 0 || (li >= s && lj >= s)) continue;  // a's lower triangle, not K_BB
          entries.emplace_back(p, static_cast<long>(std::max(li, lj)) + static_cast<long>(std::min(li, lj)) * (s + b));
        }
      }
      std::vector<std::vector<int>> maps;
      for (const int c : node.children) {
        std::vector<int> map;
        for (const int r : nodes[static_cast<std::size_t>(c)].boundary) map.push_back(local[static_cast<std::size_t>(r)]);
        maps.push_back(std::move(map));
      }
      fronts_[k].set(s, b, std::move(entries), std::move(maps));
      for (const int r : rows) local[static_cast<std::size_t>(r)] = -1;
      if (heights_.size() < static_cast<std::size_t>(node.height)) heights_.resize(static_cast<std::size_t>(node.height));
      heights_[static_cast<std::size_t>(node.height - 1)].push_back(static_cast<int>(k));
    }
  }
  // The fronts from the tree's bottom up, those of one height side by side.
  bool factorise_fronts(const SpMat& a) {
    for (const std::vector<int>& level : heights_)
      if (!side_by_side(level, threads_, [&](int k) {
            DenseFront& front = fronts_[static_cast<std::size_t>(k)];
            front.assemble(a.valuePtr());
            const SeparatorTree::Node& node = front_node(k);
            for (int i = 0; i < 2; ++i) {
              const int c = node.children[i], part = part_of_[static_cast<std::size_t>(c)];
              if (tree_.nodes()[static_cast<std::size_t>(c)].domain()) {
                front.add(i, updates_[static_cast<std::size_t>(part)]);
                updates_[static_cast<std::size_t>(part)].resize(0, 0);
              } else {
                front.add(i, fronts_[static_cast<std::size_t>(part)].update());
                fronts_[static_cast<std::size_t>(part)].drop_update();
              }
            }
            return front.factorise();
          }))
        return false;
    return true;
  }
  // y[d] = L_d^-1 P_d [b_D; 0] for every domain, side by side.
  void forward_domains(const Eigen::MatrixXd& b, std::vector<Eigen::MatrixXd>& y) const {
    std::vector<int> all(domains_.size());
    std::iota(all.begin(), all.end(), 0);
    side_by_side(all, threads_, [&](int d) {
      CholmodDomain& domain = *domains_[static_cast<std::size_t>(d)];
      Eigen::MatrixXd local = Eigen::MatrixXd::Zero(domain.size(), b.cols());
      for (int i = 0; i < domain.interior; ++i) local.row(i) = b.row(domain.rows[static_cast<std::size_t>(i)]);
      y[static_cast<std::size_t>(d)] = domain.forward(local);
      return true;
    });
  }
  // r[k] for every front, bottom up: b's rows of the separator, the children's parts added, forward solved.
  void forward_fronts(const Eigen::MatrixXd& b, const std::vector<Eigen::MatrixXd>& y,
                      std::vector<Eigen::MatrixXd>& r) const {
    for (std::size_t k = 0; k < fronts_.size(); ++k) {
      const DenseFront& front = fronts_[k];
      const SeparatorTree::Node& node = front_node(static_cast<int>(k));
      Eigen::MatrixXd& rk = r[k];
      rk.setZero(front.separator() + front.boundary(), b.cols());
      rk.topRows(front.separator()) = b(node.rows, Eigen::all);
      for (int i = 0; i < 2; ++i) {
        const int c = node.children[i], part = part_of_[static_cast<std::size_t>(c)];
        Eigen::MatrixXd up;
        if (tree_.nodes()[static_cast<std::size_t>(c)].domain()) {
          up = domains_[static_cast<std::size_t>(part)]->boundary_share(y[static_cast<std::size_t>(part)]);
        } else {
          const DenseFront& child = fronts_[static_cast<std::size_t>(part)];
          up = r[static_cast<std::size_t>(part)].bottomRows(child.boundary());
        }
        const std::vector<int>& map = front.child_map(i);
        for (std::size_t q = 0; q < map.size(); ++q) rk.row(map[q]) += up.row(static_cast<Eigen::Index>(q));
      }
      front.forward(rk);
    }
  }
  std::string memory_refusal() const {
    const double limit = factorization_memory_limit(options_.memory_limit_megabytes);
    if (limit <= 0) return {};
    double needed = 0;
    for (const auto& d : domains_) {
      const double b = d->boundary();
      needed += 2 * b * b;  // C and the update
      if (!d->factored()) needed += static_cast<double>(d->factor->xsize + d->factor->maxcsize);
    }
    for (const auto& f : fronts_) needed += std::pow(f.separator() + f.boundary(), 2);
    needed *= sizeof(double);
    if (needed <= limit) return {};
    return "CHOLMOD's domain factors and the separators' fronts would need " +
           std::to_string(std::lround(needed / (1 << 20))) + " MB, more than the limit of " +
           std::to_string(std::lround(limit / (1 << 20))) + " MB";
  }

  CholmodSplitOptions options_;
  int threads_ = 1;
  bool split_ = false, factored_ = false;
  SeparatorTree tree_;
  std::vector<int> domain_nodes_, front_nodes_;  // the tree's nodes of the domains and of the fronts
  std::vector<int> part_of_;  // of each tree node: its index in domains_ or fronts_
  std::vector<std::unique_ptr<CholmodDomain>> domains_;
  std::vector<int> domain_order_;  // the domains by their flops, the largest first (the schedule)
  std::vector<Eigen::MatrixXd> updates_;  // the domains' updates, between the domains and the fronts
  std::vector<DenseFront> fronts_;  // in postorder
  std::vector<std::vector<int>> heights_;  // the fronts of height 1, 2, ...
  std::unique_ptr<LinearSolver> whole_;
  std::string refusal_;
  long factorisations_ = 0;  // split factorisations, and the wall time of their two phases
  // the domains' and fronts' LDL^T factorisations (where LL^T found the matrix not positive definite), and
  // the split factorisations that failed
  long domain_ldlt_ = 0, front_ldlt_ = 0, failures_ = 0;
  long domain_analyses_ = 0, kept_analyses_ = 0;  // the domains' analyses, and those that kept the last one
  double domain_seconds_ = 0, front_seconds_ = 0;
};

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_split_llt(const CholmodSplitOptions& options) {
  return std::make_unique<CholmodSplitSolver>(options);
}

long cholmod_split_separator(const LinearSolver& solver) {
  const auto* split = dynamic_cast<const CholmodSplitSolver*>(&solver);
  return split ? split->separator() : 0;
}

int cholmod_split_domains(const LinearSolver& solver) {
  const auto* split = dynamic_cast<const CholmodSplitSolver*>(&solver);
  return split ? split->domain_count() : 0;
}

std::pair<long, long> cholmod_split_kept_analyses(const LinearSolver& solver) {
  const auto* split = dynamic_cast<const CholmodSplitSolver*>(&solver);
  return split ? split->kept_analyses() : std::pair<long, long>{0, 0};
}

std::vector<int> cholmod_split_pivot_order(const LinearSolver& solver) {
  const auto* split = dynamic_cast<const CholmodSplitSolver*>(&solver);
  return split ? split->pivot_order() : std::vector<int>();
}

}  // namespace fibrane::solve
