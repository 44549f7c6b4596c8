#pragma once
// Sparse direct solvers behind one interface: CHOLMOD and UMFPACK (SuiteSparse, through Eigen's wrappers)
// and MUMPS (direct_solvers.hpp has them one by one). Symbolic analysis (fill-reducing ordering,
// elimination tree) is split from the numeric factorisation so Newton iterations on an unchanged
// sparsity pattern only refactorise.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace fibrane::solve {

// One sparse direct solver: analyze() a pattern, factorize() matrices of that pattern, solve().
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual void analyze(const Eigen::SparseMatrix<double>& a) = 0;    // symbolic; reused while the pattern is unchanged
  // Numeric factorisation (factorize_numeric); false on failure (singular / not PD).
  bool factorize(const Eigen::SparseMatrix<double>& a) {
    const bool ok = factorize_numeric(a);
    if (ok) ++factorizations_;
    return ok;
  }
  // The successful factorize() calls so far; a solver that answers some of them by reusing an earlier
  // factorisation (KrylovReuseSolver) counts the factorisations it made. summary.json reports it.
  virtual long factorizations() const { return factorizations_; }
  virtual Eigen::VectorXd solve(const Eigen::VectorXd& b) const = 0;
  // solve() for a caller that accepts |A x - b| <= relative_accuracy |b| (an inexact Newton method):
  // iterative solvers may stop there; direct ones solve as solve() does.
  virtual Eigen::VectorXd solve_to(const Eigen::VectorXd& b, double /*relative_accuracy*/) const { return solve(b); }
  // solve() for every column of b; solvers that can solve them together (one pass through the factor)
  // override it.
  virtual Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const {
    Eigen::MatrixXd x(b.rows(), b.cols());
    for (Eigen::Index j = 0; j < b.cols(); ++j) x.col(j) = solve(b.col(j));
    return x;
  }
  virtual std::string name() const = 0;
  virtual long factor_nonzeros() const = 0;
  // How the analyses went (how many, with which ordering method), for reports; may be empty.
  virtual std::string analysis_summary() const { return {}; }
  // Number of negative eigenvalues of the last factorised matrix (Sylvester's law of inertia applied to
  // the factorisation), or -1 where the factorisation does not tell (LU) or the last one failed.
  // "cholmod": 0 (split: the count of the LDL^T its indefinite domains and fronts took); "ldlt": negative entries of D; "mumps": negative pivots (INFOG(12)); "umfpack": -1;
  // "auto": that of the solver that made the last factorisation.
  virtual int negative_eigenvalues() const { return -1; }
  // Whether solve() gives the solution of the factorised matrix to round-off; false for approximate
  // factorisations (single precision, block low-rank), which KrylovReuseSolver refines.
  virtual bool exact() const { return true; }
  // Why the last analysis or factorisation failed, in the library's terms (empty: not known).
  virtual std::string failure_detail() const { return {}; }
  // factorize() without reusing a factorisation of another matrix: for callers that need the inertia of
  // exactly this matrix. Only solvers that reuse factorisations (KrylovReuseSolver) tell the two apart.
  virtual bool factorize_exactly(const Eigen::SparseMatrix<double>& a) { return factorize(a); }
  // Newton calls this before the first factorisation of each step attempt (the tangent at the predicted
  // state), for solvers whose choice among factorisations may follow what the steps' first tangents were.
  virtual void begin_step() {}
  // Frees the numeric factor and keeps the analysis, for a caller that will not solve() with this solver
  // before its next factorize() (solve() is undefined until then). Solvers without the distinction keep it.
  virtual void release_factor() {}
  // The numeric factor's entries that this solver holds now: CHOLMOD's are 0 before a factorisation and
  // after release_factor(); solvers without release_factor() give factor_nonzeros(); "auto": the sum
  // over both of its solvers.
  virtual long held_factor_entries() const { return factor_nonzeros(); }
  // The rows the next analyses' matrices can be unsymmetric in (sorted; NonlinearSystem::skew_candidates):
  // the matrices are symmetric in pattern and values outside them. nullopt: any row. Solvers that compare
  // a matrix with its transpose (the symmetry probe of "auto" for a model that cannot promise symmetry)
  // compare only those rows; the others ignore it.
  virtual void set_skew_candidates(std::optional<std::vector<int>> /*rows*/) {}

  // Whether analyze_if_needed() would analyse.
  bool needs_analysis(const Eigen::SparseMatrix<double>& a, int pattern_version) const;
  // Calls analyze() unless the last analysis was for the same pattern version and matrix shape.
  // Used by newton_solve(); returns true if it analysed.
  bool analyze_if_needed(const Eigen::SparseMatrix<double>& a, int pattern_version);

 protected:
  virtual bool factorize_numeric(const Eigen::SparseMatrix<double>& a) = 0;  // factorize()'s work

 private:
  long factorizations_ = 0;
  int analyzed_version_ = -1;
  Eigen::Index analyzed_rows_ = -1, analyzed_nonzeros_ = -1;
};

// The memory of make_linear_solver()'s factorisations.
struct SolverMemory {
  // The most one factorisation may take, in MB (direct_solvers.hpp's factorization_memory_limit): -1 (its
  // kAvailableMemory) what the process can still take when the factorisation begins, 0 no limit.
  long limit_megabytes = -1;
  // Non-empty (LinearSolverSettings::out_of_core_when_needed): MUMPS's factorisations (auto's LDL^T and LU,
  // mumps, mumps-lu) go out of core into this directory where an in-core one does not fit the limit
  // (MumpsOptions::out_of_core_when_needed), and auto's LL^T refused for memory goes to MUMPS.
  std::string spill_directory;
};

// How a run solves its linear systems (case files: steps.solver, steps.precision, steps.low_rank,
// steps.out_of_core, steps.krylov).
struct LinearSolverSettings {
  std::string kind = "auto";
  // "double", or "single": MUMPS factorisations in single precision (the symmetric chain's LL^T becomes
  // MUMPS's LDL^T), refined in double precision by the Krylov solves.
  std::string precision = "double";
  double low_rank = 0;   // > 0: MUMPS block low-rank factorisations with this dropping tolerance (CNTL(7))
  // Non-empty: MUMPS factorisations out of core, the factor in files in this directory (the symmetric
  // chain's LL^T becomes MUMPS's LDL^T, as for single precision); the solves are exact.
  std::string out_of_core_directory;
  // With out_of_core_directory: the in-memory path (CHOLMOD's LL^T first) whose factorisations go out of
  // core only where they do not fit the memory that is left (steps.out_of_core: when_needed; MumpsOptions::
  // out_of_core_when_needed): an LL^T refused for memory goes to MUMPS's LDL^T, and MUMPS's factor goes to
  // the files where its in-core estimate does not fit.
  bool out_of_core_when_needed = false;
  long memory_limit_megabytes = -1;  // SolverMemory::limit_megabytes
  // CHOLMOD's LL^T (kinds auto and cholmod) in domains side by side below METIS's separators, as many as
  // threads, from 100 000 unknowns on with two threads or more (linalg/cholmod_split.hpp); case key
  // steps.split.
  bool split = false;
  bool krylov = false;   // KrylovReuseSolver around the direct solver (always with single or low_rank)
  double krylov_tolerance = 1e-8;
  int krylov_max_iterations = 20;
  bool verbose = false;  // KrylovReuseSolver's line per solve (fibrane run --newton-log)
};

// "auto" solves an unsymmetric matrix whose skew part (A - A^T) / 2 lives on at most this many rows through
// its symmetric part's factorisation and an exact low-rank correction (linalg/skew_correction.hpp).
constexpr int kMaxSkewRows = 48;

// make_linear_solver(settings.kind, symmetric) and, for krylov, single precision or low rank, the
// KrylovReuseSolver around it (src/linalg/krylov_reuse.hpp). InputError for combinations this build
// cannot make (single precision or low rank without MUMPS, or with the CHOLMOD kinds or umfpack).
std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings, bool symmetric);

// kind: "cholmod" (supernodal LL^T, symmetric positive definite), "ldlt" (CHOLMOD simplicial LDL^T,
// symmetric indefinite without pivoting), "mumps" (MUMPS multifrontal LDL^T with pivoting, symmetric
// indefinite; only if mumps_available()), "umfpack" (unsymmetric LU), "auto" (cholmod LL^T; when it
// fails, mumps where available, otherwise ldlt up to 20 000 unknowns (larger ones skip the simplicial
// LDL^T) then umfpack; after a matrix that mumps or ldlt found indefinite, the next goes to them first,
// until they find one positive definite and LL^T is first again). When symmetric == false "auto" checks
// every matrix against its transpose and takes that chain while the values are symmetric to round-off
// (1e-12 of the largest entry), an LU otherwise: MUMPS's ("mumps-lu", with CHOLMOD's ordering) where
// the build has MUMPS, else UMFPACK's 64-bit interface; the name then reads "symmetric-auto(...)" or
// the LU's). "mumps-lu" (MUMPS LU with CHOLMOD's ordering, any square matrix) and "umfpack64" (UMFPACK
// through its 64-bit integer interface) may be asked for directly.
// Symmetric kinds read only the lower triangle, so they are refused (InputError) for symmetric == false;
// "mumps" without MUMPS in the build is an InputError too.
// split: CHOLMOD's LL^T of "auto" and "cholmod" in domains side by side (LinearSolverSettings::split); there
// an indefinite matrix stays in the split, its indefinite domains and fronts factorised by LDL^T
// (cholmod_split.hpp), where the build has MUMPS.
// memory: the factorisations' memory limit, and where they go when they do not fit (SolverMemory).
std::unique_ptr<LinearSolver> make_linear_solver(const std::string& kind, bool symmetric, bool split = false,
                                                 const SolverMemory& memory = {});

// Bounds every thread pool the solvers and the assembly use to n threads (n <= 0: no change): OpenMP's
// (omp_set_num_threads) and OpenBLAS's (openblas_set_num_threads, found at run time, so any BLAS
// links), which CHOLMOD and MUMPS call. `fibrane run --threads N` calls it.
void set_thread_count(int n);

// OpenBLAS's current thread count (openblas_get_num_threads), or -1 if the BLAS is not OpenBLAS.
int blas_thread_count();

// The kernel (a value of OPENBLAS_CORETYPE) that suits this processor where the loaded OpenBLAS chose an
// older one than the processor runs, as a DYNAMIC_ARCH OpenBLAS does for a processor its table does not
// know (Debian 12's 0.3.21 takes a virtual machine's "Intel(R) Xeon(R) Processor" with AVX-512 for a
// Prescott, at a third of the dense speed: docs/performance.md, "Threads on a 16-core machine"); empty
// where its choice is fitting or the BLAS is not OpenBLAS. OpenBLAS reads the variable when it is loaded:
// `fibrane` sets it in its re-execution (run/process_environment.cpp) unless the user has set it.
std::string blas_core_upgrade();
// The rule behind it: for OpenBLAS's chosen core (openblas_get_corename) and whether the processor and the
// system support AVX-512 (F, CD, DQ, BW and VL), and AVX2 with FMA: "SkylakeX", "Haswell" or empty.
std::string blas_core_upgrade(const std::string& chosen, bool avx512, bool avx2_fma);

// For its lifetime, one BLAS thread if a factorisation is small (`factor_nonzeros` below
// kSmallFactorEntries): its dense blocks are too small to share, and on a busy 2-core machine a second BLAS
// thread made the peeling example's factorisation (2.0 M factor entries) several times slower. Larger
// factorisations keep the configured count: the K_SS of the bending quarter's local updates (7-13 M factor
// entries) factorises in about half the time on two (docs/performance.md, "A local first update").
class BlasThreadsForFactor {
 public:
  static constexpr long kSmallFactorEntries = 4'000'000;
  explicit BlasThreadsForFactor(long factor_nonzeros);
  ~BlasThreadsForFactor();
  // Gives the BLAS its configured thread count back now (the destructor then has nothing to do).
  void restore();
  BlasThreadsForFactor(const BlasThreadsForFactor&) = delete;
  BlasThreadsForFactor& operator=(const BlasThreadsForFactor&) = delete;

 private:
  int restore_ = -1;
};

// For its lifetime, the OpenMP regions that libraries open on this thread run on this thread alone
// (max-active-levels 0; the BLAS's own threads are not affected). CHOLMOD's supernodal numeric factorisation
// opens regions of four threads for every supernode (clearing it, scattering the matrix and the
// descendants' updates into it); with idle threads asleep (OMP_WAIT_POLICY=passive) each region wakes them
// and waits for them, hundreds of thousands of times in a large factorisation, for short loops bound by
// memory. Called around a factorisation outside any parallel region; inside one, nested regions are serial
// already (docs/performance.md, "CHOLMOD's own threads").
class SerialLibraryRegions {
 public:
  SerialLibraryRegions();
  ~SerialLibraryRegions();
  SerialLibraryRegions(const SerialLibraryRegions&) = delete;
  SerialLibraryRegions& operator=(const SerialLibraryRegions&) = delete;

 private:
  int levels_;
};

}  // namespace fibrane::solve
