#include "case/case_limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "common/system_memory.hpp"
#include "shell/kl_shell.hpp"

namespace fibrane::casefile {

static_assert((kMaxDegree + 1) * (kMaxDegree + 1) <= shell::kMaxShellNodes,
              "a shell element of the largest degree must fit the shell kernel");

std::string read_safe_name(const io::YamlNode& node) {
  const std::string name = node.as_string();
  const bool ok_chars = std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
           c == '-';
  });
  if (name.empty() || name.size() > kMaxNameLength || !ok_chars || name[0] == '.' || name[0] == '-')
    node.fail(fmt::format("a name of 1 to {} characters from A-Z a-z 0-9 _ . - not starting with '.' or '-' "
                          "(it becomes part of output file names)",
                          kMaxNameLength));
  return name;
}

int read_degree(const io::YamlNode& node) {
  const int p = node.as_int();
  if (p < 1 || p > kMaxDegree) node.fail(fmt::format("a polynomial degree in [1, {}]", kMaxDegree));
  return p;
}

int read_gauss_points(const io::YamlNode& node, int degree) {
  const int limit = std::min(kMaxGaussPoints, degree + 4);
  const int n = node.as_int();
  if (n < 1 || n > limit)
    node.fail(fmt::format("a number of Gauss points per direction in [1, {}] (at most degree + 4 = {}, and {})",
                          limit, degree + 4, kMaxGaussPoints));
  return n;
}

ModelSize& ModelSize::operator+=(const ModelSize& o) {
  dofs += o.dofs;
  elements += o.elements;
  points += o.points;
  nonzeros += o.nonzeros;
  factor_nonzeros += o.factor_nonzeros;
  return *this;
}

double ModelSize::bytes() const {
  // The program and its libraries' buffers; vectors and per-DOF bookkeeping; element pattern positions (one
  // int per element matrix entry, taken as 4 per non-zero); the matrix (value and index) twice (assembled
  // and the solver's copy); the factorisation's phase (kFactorPhase times the factor's value and index);
  // the Krylov vectors; per quadrature point state.
  return 0.3e9 + 400.0 * dofs + 4.0 * 4.0 * nonzeros + 2.0 * 12.0 * nonzeros +
         kFactorPhase * 12.0 * factor_scale * factor_nonzeros + 8.0 * vectors * dofs + 500.0 * points;
}

double ModelSize::least_bytes() const {
  if (!(spill_scale > 0)) return bytes();
  ModelSize spilled = *this;
  spilled.factor_scale = spill_scale;
  return spilled.bytes();
}

double ModelSize::peak_bytes(double memory) const {
  return spill_scale > 0 ? std::max(least_bytes(), std::min(bytes(), memory)) : bytes();
}

void set_solver_path(ModelSize& size, const solve::LinearSolverSettings& settings, int skew_rows) {
  const std::string& kind = settings.kind;
  const bool low_rank_skew = skew_rows > 0 && skew_rows <= solve::kMaxSkewRows;
  const bool lu = kind == "mumps-lu" || kind == "umfpack" || kind == "umfpack64" ||
                  (kind == "auto" && skew_rows != 0 && !low_rank_skew);
  const bool single = settings.precision == "single";
  const bool when_needed = settings.out_of_core_when_needed && !settings.out_of_core_directory.empty();
  const bool out_of_core = !settings.out_of_core_directory.empty() && !when_needed;
  const bool mumps = kind == "mumps" || (kind == "auto" && (single || settings.low_rank > 0 || out_of_core));
  size.factor_scale = lu ? 2.2 : mumps ? 1.1 : 1.0;
  if (single) size.factor_scale *= 0.5;
  if (out_of_core) size.factor_scale *= kOutOfCoreShare;
  // Spilled, the factorisation is MUMPS's (an LL^T that does not fit goes to its LDL^T).
  size.spill_scale = when_needed ? (lu ? 2.2 : 1.1) * (single ? 0.5 : 1.0) * kOutOfCoreShare : 0.0;
  const bool krylov = settings.krylov || single || settings.low_rank > 0;
  size.vectors = krylov ? 64.0 : 0.0;  // GMRES(restart) basis and work vectors
  size.path = std::string(lu ? "an LU" : "a symmetric factorisation") + (!lu && low_rank_skew ? " with a low-rank correction" : "") +
              (single ? " in single precision" : "") +
              (out_of_core ? " out of core" : "") +
              (when_needed ? ", out of core where a factorisation does not fit in memory" : "") +
              (krylov ? " with Krylov solves" : "");
}

void check_low_rank(const ModelSize& size, const solve::LinearSolverSettings& settings, const io::YamlNode& steps) {
  if (!(settings.low_rank > 0) || size.dofs <= kMaxLowRankUnknowns) return;
  steps["low_rank"].fail_message(fmt::format(
      "block low-rank factorisations are limited to {:.3g} unknowns, and this model has about {:.3g}: the "
      "low-rank analysis of Debian's MUMPS 5.5 crashes on larger tangents (docs/case-format.md); use "
      "precision: single for a smaller factor, or leave low_rank out",
      kMaxLowRankUnknowns, size.dofs));
}

DirectionPattern direction_pattern(const spline::KnotVector& knots) {
  const int p = knots.degree();
  const std::vector<int> spans = knots.element_spans();
  DirectionPattern d;
  d.functions = knots.num_basis();
  // Function i lives on the elements whose span s has s - p <= i <= s: a run of consecutive elements
  // first..last, and shares one with the functions spans[first] - p to spans[last].
  std::size_t first = 0, last = 0;
  for (int i = 0; i < knots.num_basis(); ++i) {
    while (first < spans.size() && spans[first] < i) ++first;
    while (last + 1 < spans.size() && spans[last + 1] - p <= i) ++last;
    if (first < spans.size() && first <= last && spans[last] - p <= i) d.pairs += spans[last] - (spans[first] - p) + 1;
  }
  return d;
}

namespace {

// The fill of a sparse Cholesky factor of a matrix from a two-dimensional mesh under nested dissection:
// L's entries per matrix non-zero grow like log n. CHOLMOD's factors of the bending membrane at 47 k,
// 278 k and 1.1 M unknowns had 0.25-0.27 log2(n / 100) per assembled non-zero (docs/performance.md, "The
// memory estimate"); 0.28 per non-zero of this count, which leaves out the interactions' coupling.
double surface_fill(double dofs) { return std::max(1.0, 0.28 * std::log2(std::max(2.0, dofs / 100.0))); }

}  // namespace

ModelSize shell_size(const DirectionPattern& u, const DirectionPattern& v, double elements, double points) {
  ModelSize s;
  s.dofs = 3.0 * u.functions * v.functions;
  s.elements = elements;
  s.points = elements * points;
  s.nonzeros = 9.0 * u.pairs * v.pairs;
  s.factor_nonzeros = s.nonzeros * surface_fill(s.dofs);
  return s;
}

ModelSize beam_size(const DirectionPattern& u, double elements, double points) {
  ModelSize s;
  s.dofs = 4.0 * u.functions;
  s.elements = elements;
  s.points = elements * points;
  s.nonzeros = 16.0 * u.pairs;
  // Banded: L fills the band's half, which for C1 and lower continuity is wider than the matrix's
  // half-count; taken as the matrix's count.
  s.factor_nonzeros = s.nonzeros;
  return s;
}

ModelSize model_size(const model::Model& m) {
  ModelSize total;
  for (const auto& s : m.shells)
    total += shell_size(direction_pattern(s.surface.knots(0)), direction_pattern(s.surface.knots(1)),
                        static_cast<double>(s.elements.size()), s.gauss(0) * s.gauss(1));
  for (const auto& b : m.beams)
    total += beam_size(direction_pattern(b.curve.knots()), static_cast<double>(b.elements.size()), b.gauss());
  return total;
}

double machine_memory() {
  const std::uint64_t memory = memory_limit();
  return memory > 0 ? static_cast<double>(memory) : 64.0 * (1ull << 30);
}

void check_fits(const ModelSize& size, const io::YamlNode& node) {
  const std::uint64_t memory = memory_limit();
  const double available = machine_memory();
  if (size.least_bytes() <= available) return;
  node.fail_message(fmt::format(
      "the model would be too large: about {:.3g} DOFs, {:.3g} elements, {:.3g} matrix non-zeros, estimated "
      "{:.3g} GiB of memory{}, more than the {:.3g} GiB this machine (or its control group) has{}: use fewer elements or a lower degree{}",
      size.dofs, size.elements, size.nonzeros, size.least_bytes() / (1ull << 30),
      size.path.empty() ? "" : " (" + size.path + ")", available / (1ull << 30),
      memory > 0 ? "" : " (assumed: /proc/meminfo unreadable)",
      size.path.empty() || size.path.find("out of core") != std::string::npos ? ""
                                                                               : ", or steps.out_of_core: when_needed"));
}

int optional_int_in(const io::YamlNode& map, const std::string& key, int lo, int hi, int fallback, const std::string& what) {
  const auto v = map.optional(key);
  if (!v) return fallback;
  const int x = v->as_int();
  if (x < lo || x > hi) v->fail(fmt::format("{}, an integer in [{}, {}]", what, lo, hi));
  return x;
}

}  // namespace fibrane::casefile
