#pragma once
// Limits on what a case file may ask for (docs/case-format.md, "Limits"), checked while it is read so that
// a request that cannot be met is refused with a located message before anything large is allocated:
// names that end up in file names, polynomial degrees, quadrature points, sampling points, element counts,
// and an estimate of the memory the model will need against the machine's memory.
#include <cstdint>
#include <string>

#include "io/yaml_input.hpp"
#include "model/model.hpp"
#include "linalg/linear_solver.hpp"
#include "spline/knot_vector.hpp"

namespace fibrane::casefile {

inline constexpr int kMaxDegree = 8;                   // per parametric direction (shell kernel: (p+1)(q+1) <= 100)
inline constexpr int kMaxElementsPerDirection = 65536;  // per refine direction
inline constexpr int kMaxGaussPoints = 20;             // per direction, and at most degree + 4
inline constexpr int kMaxSamples = 64;                 // output.samples
inline constexpr std::size_t kMaxNameLength = 64;

// A name used in output file names (bodies, interactions) or as a history.csv column (monitors):
// 1-64 characters of [A-Za-z0-9_.-], not starting with '.' or '-'. Returns it; InputError at `node`.
std::string read_safe_name(const io::YamlNode& node);

// An optional integer key of `map` in [lo, hi] (`what` names it in the message); `fallback` when absent.
int optional_int_in(const io::YamlNode& map, const std::string& key, int lo, int hi, int fallback,
                    const std::string& what);

// Polynomial degree read at `node`: an integer in [1, kMaxDegree].
int read_degree(const io::YamlNode& node);

// Gauss points per direction read at `node` for a body of polynomial degree `degree`.
int read_gauss_points(const io::YamlNode& node, int degree);

// The share of an out-of-core factorisation's factor memory that stays in memory (active fronts, the
// stack and MUMPS's buffers), relative to this estimate's factor phase: measured 0.16 for the 1.1 M full
// membrane's LU and 0.25 for its LDL^T (docs/performance.md, "The memory estimate"); and the factor
// scale of MUMPS's single-precision LDL^T out of core (1.1 x 0.5 x kOutOfCoreShare), the
// lightest path a case can take.
inline constexpr double kOutOfCoreShare = 0.25;
inline constexpr double kLightestFactorScale = 1.1 * 0.5 * kOutOfCoreShare;

// A size of the discrete model: DOFs, elements, quadrature points, matrix non-zeros and the factor's
// entries, from which bytes() estimates the run's peak memory (docs/case-format.md, "Limits").
struct ModelSize {
  double dofs = 0, elements = 0, points = 0, nonzeros = 0;
  double factor_nonzeros = 0;  // of a sparse Cholesky factorisation L (fill-in estimate)
  // The factorisation's memory relative to a double-precision Cholesky factor of factor_nonzeros entries,
  // and the work vectors per unknown of the solver's path (set_solver_path). The default is the lightest
  // path's (kLightestFactorScale): the checks while bodies are read refuse only what no path can hold;
  // the check of the whole case takes the case's path.
  double factor_scale = kLightestFactorScale, vectors = 0;
  // > 0: a factorisation that does not fit in memory goes out of core, at this factor scale
  // (steps.out_of_core: when_needed); 0: factor_scale holds for every factorisation.
  double spill_scale = 0;
  std::string path;  // the solver path, for messages (empty: not known yet)
  ModelSize& operator+=(const ModelSize& o);
  double bytes() const;  // estimated peak memory of the run (a central estimate, not a bound)
  // The least memory the run needs: bytes() at spill_scale where factorisations may go out of core.
  double least_bytes() const;
  // The estimated peak on a machine of `memory` bytes: bytes(), or, where factorisations go out of core
  // when they do not fit, no more than the machine has (and no less than least_bytes()).
  double peak_bytes(double memory) const;
};

// The peak memory of a factorisation's phase (analysis, numeric factorisation, the solver's copy of the
// matrix, fronts and stack) per byte of the Cholesky factor's values and indices, measured on the full
// bending membrane's runs (docs/performance.md, "The memory estimate"): 1.75 and 1.6 with CHOLMOD alone
// at 278 k and 1.1 M unknowns; 3.0 and 3.2 over whole runs where MUMPS's LDL^T takes turns with it at
// 278 k and 47 k; above 2.5 at 1.1 M, whose run in memory was ended by the system at 24.4 GB.
inline constexpr double kFactorPhase = 3.0;

// The linear solver path a case's settings take for a model whose tangent's skew part touches `skew_rows`
// rows (0: symmetric; -1: any number; up to solve::kMaxSkewRows: "auto" factorises the symmetric part):
// factor_scale 2.2 for an LU (L and U; MUMPS's LU of the bending tangent has 2.2 times the entries of
// CHOLMOD's LL^T), 1.1 for MUMPS's LDL^T, 1 for CHOLMOD, halved in single precision; block low-rank is
// taken as full rank (its compression depends on the problem); Krylov solves add GMRES's basis. Out of
// core only the active fronts and the stack stay in memory: kOutOfCoreShare of the factor; out of core
// where needed (when_needed), the in-memory path's scale and MUMPS's out-of-core one as spill_scale.
void set_solver_path(ModelSize& size, const solve::LinearSolverSettings& settings, int skew_rows);

// Block low-rank factorisations (steps.low_rank) are refused above this many unknowns (estimated) with a
// located message: Debian 12's sequential MUMPS (5.5.1 with SCOTCH 7.0) ends the process with a
// segmentation fault in its low-rank analysis (SCOTCH_graphBuild, called by the clustering of large
// separators, dmumps_lr_grouping_new) on the bending tangent at 155 k unknowns with SCOTCH's ordering and
// at 274 k with CHOLMOD's, while it ran at 18 k to 155 k with CHOLMOD's (docs/performance.md, "Unsymmetric
// tangents, Krylov reuse and approximate factorisations").
inline constexpr double kMaxLowRankUnknowns = 1.5e5;
void check_low_rank(const ModelSize& size, const solve::LinearSolverSettings& settings, const io::YamlNode& steps);

// One parametric direction of a spline body: its basis functions, and the ordered pairs of them whose
// supports share an element (a scalar field's matrix non-zeros in this direction; a tensor-product
// surface's are the product of its two directions'). Counted from the knot vector's element spans: the
// functions on the element of span s are s - p to s.
struct DirectionPattern {
  double functions = 0, pairs = 0;
};
DirectionPattern direction_pattern(const spline::KnotVector& knots);

// Size of a shell whose directions have patterns `u` and `v`, with `elements` elements of `points`
// quadrature points each (3 DOFs per control point); of a beam likewise (4 DOFs per control point).
ModelSize shell_size(const DirectionPattern& u, const DirectionPattern& v, double elements, double points);
ModelSize beam_size(const DirectionPattern& u, double elements, double points);
// Size of the bodies already in the model.
ModelSize model_size(const model::Model& m);

// The memory the checks compare with: memory_limit() (which a control group's limit bounds), or 64 GiB
// where /proc/meminfo cannot be read.
double machine_memory();

// InputError at `node` when `size` does not fit into machine_memory() (its least_bytes()), naming the
// estimate.
void check_fits(const ModelSize& size, const io::YamlNode& node);

}  // namespace fibrane::casefile
