#pragma once
// Newton-Raphson for the reduced equilibrium equations r(q, t) = 0 (paper Sec. 2.3: the discretised
// Eq. (7) is solved by Newton's method inside each continuation increment).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/linear_solver.hpp"
#include "linalg/rank_one_terms.hpp"

namespace fibrane::solve {

// What Newton and continuation need from a model.
class NonlinearSystem {
 public:
  virtual ~NonlinearSystem() = default;
  virtual int size() const = 0;                                    // number of free unknowns q
  virtual void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) = 0;
  virtual const Eigen::VectorXd& residual() const = 0;             // reduced residual at the last evaluate
  // Reduced tangent d residual / dq. In a distributed system (distributed() true) it is this process's
  // summand: the tangent is the sum of the processes' matrices, which only a distributed LinearSolver
  // factorises as a whole (src/parallel).
  virtual const Eigen::SparseMatrix<double>& tangent() const = 0;
  // Evaluates at (q, t) what the tangent's entries with row and column among `rows` (sorted unknowns) need,
  // and may leave out the rest: afterwards tangent()'s principal submatrix on `rows` is the whole
  // evaluation's, while residual() and the other entries are unspecified until the next evaluate().
  // Systems that cannot restrict their work evaluate everything (the default). With `apart`, a system may
  // hold dense symmetric rank-one terms of the tangent apart (cleared first, then filled): the tangent's
  // principal submatrix on `rows` is then tangent()'s plus those terms' (RankOneTerms::on_rows), and
  // tangent() holds exact zeros where only the terms would write. The default holds none apart.
  virtual void evaluate_tangent_on(const Eigen::VectorXd& q, double t, const std::vector<int>& /*rows*/,
                                   RankOneTerms* apart) {
    if (apart) apart->clear();
    evaluate(q, t, true);
  }
  // The unknowns a local Newton solve always takes in beside the residual's own rows
  // (NewtonOptions::local_newton), sorted: a part of the system whose nonlinearity a global update does not
  // get past and whose neighbours must move with it (fibrane's model: its beams' free unknowns). Empty (the
  // default): the residual's rows alone.
  virtual std::vector<int> local_solve_rows() const { return {}; }
  // Whether every entry of the tangent is finite; the same answer on every process.
  virtual bool tangent_finite() const;
  // The tangent times x (x and the product replicated on every process).
  virtual Eigen::VectorXd tangent_times(const Eigen::VectorXd& x) const { return tangent() * x; }
  // Whether tangent() is one process's summand of a tangent shared by several processes.
  virtual bool distributed() const { return false; }
  // Collective in a distributed system: `flags` (one per unknown, 0 or 1) set wherever they are set on
  // any process (local_rows's RowUnion). A serial system has nothing to unite.
  virtual void unite_flags(std::vector<char>& /*flags*/) const {}
  // Collective in a distributed system: the sum over the processes of their matrices of one size (each
  // process's part, such as its summand's principal submatrix), the same bits on every process. A serial
  // system's part is the whole.
  virtual Eigen::SparseMatrix<double> sum_over_processes(Eigen::SparseMatrix<double> part) const { return part; }
  // d residual / d t at fixed q, exact, from the last evaluate() with the tangent: the load vector that
  // arc-length continuation borders the tangent with (prescribed values and loads both scale with t).
  // Systems that do not provide it return an empty vector.
  virtual const Eigen::VectorXd& load_derivative() const;
  virtual int pattern_version() const = 0;                         // solver re-analyses when it changes
  // Why the state of the last evaluate() lies outside the system's domain (e.g. a beam inside the plate,
  // where the interaction law has no value); empty when it does not. Newton treats such an iterate like
  // one with a non-finite residual (backtracking, then failure with this reason).
  virtual std::string invalid_state() const { return {}; }
  virtual bool symmetric() const { return true; }
  // The rows (sorted) the tangent's skew part (K - K^T) / 2 can touch at the current pattern: the
  // tangent is symmetric in pattern and values outside them. nullopt where the system does not know.
  virtual std::optional<std::vector<int>> skew_candidates() const { return std::nullopt; }
  virtual void accept(const Eigen::VectorXd& /*q*/, double /*t*/) {}  // converged step (history update)
  virtual void reject() {}  // failed attempt: state that depends on past evaluations returns to the last step
  // A converged attempt that the continuation discards (it went past an event by more than the event
  // tolerance): like reject(), but without what a failed attempt teaches the system (e.g. switches).
  virtual void withdraw() { reject(); }
  // Events: changes of the model itself after a converged step (a beam point switching to the soft
  // minimum). The margins of the last evaluate()'s state to each possible event, a fixed number of them:
  // > 0 before it, <= 0 at or past it (it then happens at accept()), smooth in the state where the
  // event's criterion is; +infinity where an event has no margin now, NaN once it has happened. Empty
  // for a system without events. Load stepping locates where they cross 0 (StepControl::event_tolerance),
  // so that each change happens at the same state whatever the steps.
  virtual std::vector<double> event_margins() const { return {}; }
  // How many changes of the model's equations have happened so far (events at accept(), switches after a
  // failed attempt); it never decreases. Converged states from before a change lie on another path than
  // those after it, so a predictor does not extrapolate through both as they are.
  virtual long model_changes() const { return 0; }
  virtual double residual_scale() const { return 1.0; }  // reference force level for relative tolerances
  // The round-off floor of the residual at the last evaluate() with the tangent: the size of the residual
  // that rounding the current configuration to double precision alone causes, eps * sqrt(sum_ij
  // (K_ij x_j)^2) with x_j the magnitude of the coordinate behind unknown j. Newton cannot push |r| below
  // it; 0 (the default) when the system does not know it.
  virtual double roundoff_floor() const { return 0.0; }
  // What the system saw in the last failed attempt that may explain it (empty: nothing); appended to the
  // message of a continuation that stops.
  virtual std::string failure_hint() const { return {}; }
};

struct NewtonOptions {
  int max_iterations = 20;
  double tol_relative = 1e-9;
  double tol_absolute = 1e-12;
  // Also converged when an update is this small relative to |q| and the residual it leads to is at most
  // twice the previous one:
  // the residual has then reached its round-off floor (fine meshes, stiff parts next to weak interaction
  // forces), where a purely relative residual test can never be met. 0 disables it.
  double tol_increment = 1e-10;
  // Backtracking: an update after which |r| rose is halved, at most this many times per update, before
  // Newton goes on from there (0: plain Newton). Each halving costs one evaluation (with the tangent
  // unless a factorisation is being reused).
  int line_search = 0;
  // Factorisation reuse (modified Newton; 0: off). Once an update has cut |r| to this fraction or less,
  // the next updates reuse the latest factorisation with residual-only evaluations, as long as each cuts
  // |r| by at least 4; otherwise the tangent is assembled and factorised again. Where Newton converges
  // quadratically this replaces the last factorisations of a step by solves. For exact (direct) solvers:
  // a Krylov solver multiplies by the system's tangent, which residual-only evaluations leave stale and a
  // local solve's partial evaluation replaces (the case reader refuses reuse_factorization with them).
  double reuse_below = 0;
  // With reuse_below: the factorisation of a step's first iterate is reused from the next update on, under
  // the same rule (each update must cut |r| by 4, else the tangent is factorised), where Newton's first
  // update already lands in the fast regime (a good predictor) and its second factorisation would be
  // spent on a contraction the first one gives as well.
  bool reuse_first = false;
  // Local first update (0: off): a solve's first update solves only on the rows where its residual
  // concentrates, grown through the tangent's graph to this share of the unknowns
  // (path/local_correction.hpp), with the tangent's entries on those rows alone
  // (NonlinearSystem::evaluate_tangent_on); its next iterate gets the global factorisation. An update
  // that does not lower |r| is taken back, and the first iterate then takes Newton's global update. With
  // reuse_below, the factorisation after a kept local update that cut |r| by 4 is reused from the next
  // update on (under the reuse rule). Where no local update can be made (rows that would be half the
  // unknowns or more, a failed factorisation), the first iterate is evaluated once more, with its tangent.
  // In a distributed system the rows grow through the processes' summands together, K_SS is their sum, and
  // every process solves it (NonlinearSystem::unite_flags, sum_over_processes).
  double local_share = 0;
  // Local Newton solves (0: off; serial systems only). After a global update whose residual lies at least
  // 99 % (of |r|) on a local set (the rows of local_rows at local_share, 0.01 where that is 0, and
  // NonlinearSystem::local_solve_rows), up to this many updates on that set alone, each from the tangent's
  // entries on its rows at the set's current iterate (evaluate_tangent_on), until |r| on the set has fallen
  // to 2 % of where it began, or stops falling (that update is taken back). The next evaluation keeps the
  // local solve's result where |r| fell and takes it back otherwise; the update after it is global: with
  // reuse_below, after a kept local solve, a chord with the factorisation in hand where that was made at an
  // iterate whose |r| was at most reuse_below of the solve's first and no reused update with it has failed
  // to cut |r| by 4, else from this iterate's own factorisation. Where a
  // part of the system (a finely meshed fiber's end) is more nonlinear than the rest, this replaces
  // global factorisations by factorisations of the set (docs/performance.md, "Where Newton stalls").
  int local_newton = 0;
  // Inexact Newton for iterative solves (LinearSolver::solve_to; direct solvers solve exactly anyway): an
  // update solves K dq = -r only to |K dq + r| <= eta |r|, with Eisenstat and Walker's second forcing term
  // eta = 0.9 (|r_k| / |r_k-1|)^2 (forcing_max for the first update), at most forcing_max, and never
  // stricter than 0.5 tol / |r| (what reaching the tolerance with this update needs). 0: exact solves.
  double forcing_max = 0.01;
  bool verbose = false;               // one line per iteration on stderr
  double divergence_factor = 1e8;     // fail once ||r|| exceeds this multiple of the reference scale
  // Fail once this many updates in a row have not halved the smallest |r| of the solve (0: off): Newton
  // that has wandered for as long outside its region of convergence is cut back instead of spending the
  // rest of max_iterations (GiveUpRules).
  int stall_iterations = 8;
};

struct NewtonReport {
  bool converged = false;
  int iterations = 0;          // number of linear solves (updates of q)
  int backtracks = 0;          // halvings of updates by the line search
  int factorizations = 0;      // updates with a fresh factorisation (the others reused one)
  int local_updates = 0;       // of the updates, local ones (local_share) and local solves (local_newton),
                               // taken back or not
  double residual_norm = 0;    // at the last evaluation
  std::vector<double> history; // ||r|| at every evaluation, the first before any update
  std::string failure;         // empty when converged
  // Negative eigenvalues of the last factorised tangent (LinearSolver::negative_eigenvalues), -1 unknown.
  int negative_eigenvalues = -1;
  // Converged at the system's round-off floor (NonlinearSystem::roundoff_floor) rather than at the tolerance.
  bool at_roundoff_floor = false;
};

// Newton accepts an iterate whose |r| is at most this multiple of the round-off floor: a floor estimate is
// a statistical size (random rounding errors), and the residual there wanders around it by a small factor.
inline constexpr double kRoundoffFloorFactor = 2.0;

// When an iteration toward a small residual gives up, checked after each evaluation that has not
// converged, in this order: |r| above divergence_factor x the scale; a two-state cycle (the residual
// repeats every second iteration to 1e-3: a beam point whose closest point jumps between two branches at
// each update, docs/examples.md); stall_iterations updates in a row that did not halve the smallest |r|
// (counted again from an update that raised |r| tenfold above it: Newton's first update from a penetrating
// contact often overshoots by 10^2-10^3 and then converges steadily); max_iterations. (The arc-length corrector gives up on divergence and max_iterations only: its
// iterations, bound to the constraint, can wander for 8-20 updates and still converge, as on the
// crossed-fibers and peeling examples.)
class GiveUpRules {
 public:
  explicit GiveUpRules(const NewtonOptions& options) : options_(options) {}
  // Why to give up after the evaluation whose |r| is history.back() (history: |r| of every evaluation of
  // the solve, the first before any update); empty to go on.
  std::string check(const std::vector<double>& history, double scale);

 private:
  const NewtonOptions& options_;
  double best_;     // the reference |r|: the first, then each that halves it or exceeds it tenfold
  int best_at_ = 0; // its iteration
};

// solver.analyze_if_needed(k, sys.pattern_version()), telling the solver the system's skew candidates
// first where it analyses.
bool analyze_if_needed(LinearSolver& solver, const NonlinearSystem& sys, const Eigen::SparseMatrix<double>& k);

// Converged when ||r|| <= max(tol_relative * scale, tol_absolute), scale = max(||r_0||, residual_scale()),
// or when ||r|| <= kRoundoffFloorFactor * roundoff_floor() of the last tangent (the tolerance is below what
// double precision allows for this configuration), or at the increment-based floor of tol_increment.
// Fails (converged = false, message in failure) on: GiveUpRules, non-finite residual or update, failed
// factorisation. q then holds the last iterate; the caller restores it if needed.
// factor_in_hand: the solver holds a factorisation of this system's tangent at a nearby state (the last
// converged solve's), and with reuse_below > 0 the solve's first global update (after the local first
// update, where there is one) is a chord with it instead of a factorisation of its own iterate; the next
// update keeps reusing it while each cuts |r| by 4 (the reuse rule), else factorises its own tangent.
NewtonReport newton_solve(NonlinearSystem& sys, Eigen::VectorXd& q, double t, const NewtonOptions& opt,
                          LinearSolver& solver, bool factor_in_hand = false);

}  // namespace fibrane::solve
