#pragma once
// Arc-length continuation: the load parameter t becomes an unknown next to q and every step adds one
// equation, a constraint on the length of the increment, so the path can be followed through limit
// points of t (snap-through) and of displacements (snap-back). Riks (1979) "An incremental approach to
// the solution of snapping and buckling problems", Int. J. Solids Struct. 15, 529-551; Crisfield (1981)
// "A fast incremental/iterative solution procedure that handles 'snap-through'", Comput. Struct. 13,
// 55-62; Crisfield (1991) "Non-linear finite element analysis of solids and structures", Vol. 1, Ch. 9.
//
// Step n -> n+1 from the converged (q_n, t_n), increments dq = q - q_n, dt = t - t_n:
//   r(q, t) = 0,    |dq|^2 + c^2 dt^2 = ds^2       (spherical for c > 0, cylindrical for c = 0)
// The scaling c converts the load parameter into the units of q. By default c = |dq/dt| of the first
// tangent predictor, so both terms of the constraint weigh the same at the start and the method does not
// depend on the units of t: scaling t by a factor scales c by its inverse and leaves c dt unchanged. A
// fixed c much larger than |dq/dt| makes the constraint nearly one on t alone (close to load control,
// with its trouble at limit points of t); c = 0 (Crisfield's cylindrical form, an option) makes it one on
// the norm of dq alone, which passes limit points of t and turning points of single displacements but
// takes huge load steps where the response is stiff (t changes while q hardly does, e.g. at contact).
// With the default, the first step has dt = ds / (sqrt(2) c); ds is always in the units of q.
//
// What a model must provide: after every evaluate() with the tangent, load_derivative() = d r / d t at
// fixed q, exact. With u = T q + g(t) and r = T^T (f_int(u) - f_ext(u, t)) this is
// T^T (K_u g'(t) - d f_ext / d t), K_u the full tangent d (f_int - f_ext) / d u (load stiffness of
// configuration-dependent loads included): prescribed displacements enter through K_u g', not only
// the load vector.
#include <memory>
#include <string>

#include "path/continuation.hpp"

namespace fibrane::solve {

// How the load increment of a corrector iteration is found from the two solves K a = -r, K b = -r_t
// (the iterate's update is dq = a + delta_t b).
enum class ArcLengthCorrector {
  // Crisfield (1981): delta_t solves the constraint exactly (a quadratic); of its two roots the one whose
  // new increment has the smaller angle with the current increment (largest scaled dot product). Every
  // iterate lies on the constraint surface, so a converged step has exactly the length ds. Where the
  // roots are complex (the line a + delta_t b misses the sphere, in strongly curved regions), that
  // iteration takes the linearised update below instead.
  quadratic,
  // Newton on the extended system [r; (|dq|^2 + c^2 dt^2 - ds^2) / 2] = 0 (consistent linearisation,
  // Schweizerhof & Wriggers 1986, Comput. Methods Appl. Mech. Eng. 59, 261-279): delta_t =
  // -(g + dq.a) / (dq.b + c^2 dt). On the constraint surface (g = 0) this is the updated normal plane of
  // Ramm (1981) "Strategies for tracing the nonlinear response near limit points", in Nonlinear Finite
  // Element Analysis in Structural Mechanics, Springer, 63-89, an iterative form of Riks (1979). Iterates
  // leave the surface by O(update^2).
  linearized,
};

// Options of ArcLength. Checked by check_arc_length_control().
struct ArcLengthControl {
  double t_start = 0.0;
  // The run ends at the first step that reaches or crosses t_end from either side (the starting point
  // does not count, so a path may leave t_end and come back to it). That step's arc-length solution is
  // discarded and the step is solved again by Newton at fixed t = t_end from the linear interpolation
  // between the two states, so the last point lies exactly on t_end; it is accepted only if it lies within
  // the discarded step's length of the interpolation (otherwise Newton found another branch at t_end:
  // the step is cut back like a failed one). The landing uses newton_solve with the method's NewtonOptions;
  // its report counts the corrector's and the landing's iterations and has the landing's history.
  double t_end = 1.0;
  // The run also ends after the first converged step outside [t_min, t_max] (that step is reported), or
  // once the path length (sum of the converged steps' ds) reaches max_path_length (the last step is
  // shortened to land on it).
  double t_min = -1e300, t_max = 1e300;
  double max_path_length = 1e300;
  double ds_initial = 0.1, ds_min = 1e-8, ds_max = 1.0;  // arc lengths, in the units of q
  // Step length control (Crisfield 1981): ds_next = ds * sqrt(desired_iterations / iterations), the
  // factor clamped to [cutback, growth] and ds to [ds_min, ds_max]; no growth after a cut-back step.
  int desired_iterations = 4;
  double growth = 2.0;
  double cutback = 0.5;  // factor of ds after a failed attempt
  int max_steps = 100000;
  // c of the constraint: < 0 automatic (|dq/dt| of the first tangent predictor; 1 if that vanishes),
  // 0 cylindrical (Crisfield 1981), > 0 a fixed value.
  double load_scale = -1.0;
  ArcLengthCorrector corrector = ArcLengthCorrector::quadratic;
  int initial_direction = +1;  // sign of dt of the first step
  // The predictor's direction is chosen by the sign of the scaled dot product of the tangent with the last
  // converged increment (Crisfield 1991, Ch. 9; it keeps the path from turning back at a limit point).
  // Where that is ambiguous (|cos| of the angle below this; 1: always) and the solver reports inertia at
  // both ends of the last step, the determinant rule decides instead: dt/ds keeps its sign unless the
  // number of negative eigenvalues changed parity (det K changed sign: a limit point of t was passed).
  // The determinant rule alone is wrong at bifurcation points (det K changes sign, t does not turn).
  double ambiguous_cosine = 0.05;
};

// Throws InputError unless 0 < ds_min <= ds_initial, ds_min <= ds_max, 0 < cutback < 1, growth >= 1,
// desired_iterations >= 1, t_min <= t_start <= t_max, max_path_length > 0, initial_direction = +-1,
// ambiguous_cosine in [0, 1].
void check_arc_length_control(const ArcLengthControl& control);

// Arc-length continuation as a ContinuationMethod (name "arc_length").
//
// Per step: the tangent predictor dq = v dt with K v = -r_t at the converged state (r_t =
// sys.load_derivative(), K = sys.tangent()), scaled to the length ds and oriented as described at
// ArcLengthControl::ambiguous_cosine; then corrector iterations, each one evaluation with the tangent, one
// factorisation of K and two solves with it (K a = -r, K b = -r_t: the bordering algorithm), the load
// increment from the constraint (ArcLengthCorrector). Convergence as in newton_solve: |r| <=
// max(tol_relative * max(|r_0|, sys.residual_scale()), tol_absolute) with r_0 the residual at the
// predictor, or the round-off floor rule of NewtonOptions::tol_increment; the constraint is not part of
// the test (it only says where along the path the point lies). NewtonOptions::line_search and reuse_below
// are not used: every iteration factorises, and its factorisation is needed for b anyway.
//
// Singular tangent: at a limit point K is singular while the extended matrix [K r_t; dq^T c^2 dt] is
// regular (Keller 1977). Where the factorisation of K fails or its solutions are not finite, that
// iteration solves the extended system (linearised constraint) with UMFPACK instead; the tangent at a
// converged state likewise, bordered with the last increment. Near (not at) a limit point a and b are
// both large and nearly parallel; their combination loses about log10(cond K) digits, which the next
// iterations correct as long as the residual test can be met.
//
// After a converged step, before sys.accept(): the tangent at the converged state (from the corrector's
// last evaluation, or a new one after a landing on t_end) is factorised for the next predictor, so
// StepReport::negative_eigenvalues is the solver's count at the converged state itself (-1 if the solver
// does not report inertia or the extended system had to be used). on_step may evaluate the system.
//
// Failed attempts (Newton failure, landing failure) call sys.reject(), cut ds back and retry from the
// last converged state; below ds_min the run ends with Outcome::failed.
class ArcLength final : public ContinuationMethod {
 public:
  // Throws InputError (check_arc_length_control).
  ArcLength(ArcLengthControl control, NewtonOptions newton);
  std::string name() const override { return "arc_length"; }
  // Throws std::invalid_argument if q has the wrong size or the system provides no load derivative.
  ContinuationResult run(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                         const StepCallback& on_step) override;
  // t, ds, c, the last converged increment (dq, dt), the step count, the path length, what the sign
  // rules need and the tangent prepared at the last converged state; a run() after restore() continues
  // from the saved state with the q it is given, as the uninterrupted run would.
  MethodState save() const override;
  void restore(const MethodState& state) override;
  // The scaling c in use (< 0 before the first step with automatic scaling).
  double load_scale() const { return c_; }
  // Predictor directions where the angle rule and the determinant rule disagreed (the angle rule was
  // followed, or the determinant rule where the angle was ambiguous). Counted only where the solver
  // reports inertia.
  int sign_disagreements() const { return disagreements_; }

 private:
  // The path's tangent at a state: (dq, dt) and the solver's count of negative eigenvalues of K there.
  struct Tangent {
    Eigen::VectorXd dq;
    double dt = 1.0;
    int negative_eigenvalues = -1;  // of K at the state, from the solver (-1: unknown)
  };
  struct Attempt;
  bool start_in_equilibrium(NonlinearSystem& sys, Eigen::VectorXd& q, LinearSolver& solver,
                            const StepCallback& on_step, ContinuationResult& res);
  bool tangent_at_state(NonlinearSystem& sys, LinearSolver& solver, Tangent& tangent);
  int predictor_sign(const Tangent& tangent);
  bool step(NonlinearSystem& sys, const Eigen::VectorXd& q, const Tangent& tangent, LinearSolver& solver,
            Attempt& attempt, double& ds, int& cutbacks, ContinuationResult& res);
  Attempt correct(NonlinearSystem& sys, const Eigen::VectorXd& q0, double t0, const Tangent& tangent,
                  int sign, double ds, LinearSolver& solver);
  bool corrector_update(NonlinearSystem& sys, LinearSolver& solver, const Eigen::VectorXd& dq, double dt,
                        double ds, Eigen::VectorXd& delta_q, double& delta_t, std::string& failure);
  StepReport advance(NonlinearSystem& sys, Eigen::VectorXd& q, const Attempt& attempt, double ds, int cutbacks,
                     LinearSolver& solver, Tangent& tangent, bool& have_tangent);
  bool end_reached(bool landed, ContinuationResult& res) const;
  bool land_on_t_end(NonlinearSystem& sys, const Eigen::VectorXd& q0, double t0, double ds, Attempt& attempt,
                     LinearSolver& solver);
  bool bordered_solve(const Eigen::SparseMatrix<double>& k, const Eigen::VectorXd& r_t,
                      const Eigen::VectorXd& row_q, double row_t, const Eigen::VectorXd& rhs_q, double rhs_t,
                      Eigen::VectorXd& x, double& y);

  ArcLengthControl control_;
  NewtonOptions newton_;
  std::unique_ptr<LinearSolver> extended_;  // UMFPACK for the extended system, made on first use
  // Path state carried between steps (and across a restart).
  double t_ = 0, ds_ = 0, c_ = -1, path_length_ = 0;
  int steps_ = 0;
  Eigen::VectorXd dq_prev_;  // last converged increment
  double dt_prev_ = 0;
  bool have_prev_ = false, restored_ = false;
  // The tangent at the last converged state, prepared before sys.accept() for the next predictor.
  Tangent tangent_;
  bool have_tangent_ = false;
  // dt/ds sign and negative eigenvalues at the state the last predictor started from, for the next
  // step's determinant rule (0, -1: unknown).
  int tangent_dt_sign_ = 0;
  int inertia_prev_ = -1;
  int disagreements_ = 0;
};

}  // namespace fibrane::solve
