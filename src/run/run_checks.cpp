#include "run/run_checks.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "case/case_checks.hpp"
#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane::run {

void check_output_directory(const casefile::Case& c, const std::string& directory) {
  namespace fs = std::filesystem;
  const std::string where = c.path + ": output directory '" + directory + "'";
  std::error_code ec;
  fs::path p = fs::absolute(directory, ec);
  if (ec) throw InputError(where + ": " + ec.message());
  // The directory itself, or the nearest ancestor that exists (create_directories makes the rest).
  while (!fs::exists(p, ec)) {
    if (ec && ec != std::errc::no_such_file_or_directory) throw InputError(where + ": " + ec.message());
    if (!p.has_parent_path() || p.parent_path() == p) throw InputError(where + ": no existing parent directory");
    p = p.parent_path();
  }
  if (!fs::is_directory(p, ec))
    throw InputError(where + ": '" + p.string() + "' exists and is not a directory");
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError(where + ": '" + p.string() + "' is not writable");
}

namespace {

[[noreturn]] void not_finite(const casefile::Case& c, const std::string& what) {
  throw InputError(c.path + ": " + what +
                   " is not finite: material constants, sizes or loads are too large for double precision "
                   "(keep the products of their magnitudes well below 1e300)");
}

}  // namespace

void check_finite_model(casefile::Case& c) {
  model::Model& m = *c.model;
  const double t0 = c.run.steps.t_start, t1 = c.run.steps.t_end;
  for (const auto& load : m.nodal_loads.loads)
    for (double t : {t0, t1}) {
      const double f = m.functions(load.function, t);
      for (Eigen::Index k = 0; k < load.values.size(); ++k)
        if (!std::isfinite(f * load.values[k]))
          not_finite(c, "the load on " + casefile::describe_dof(m, load.dofs[static_cast<std::size_t>(k)]) + " at t = " +
                            format_number(t));
    }
  m.evaluate(m.initial_unknowns(), t0, true);
  if (!m.invalid_state().empty()) return;  // reported by the run, like any state outside the domain
  const Eigen::VectorXd& r = m.full_residual();
  for (Eigen::Index d = 0; d < r.size(); ++d)
    if (!std::isfinite(r[d])) not_finite(c, "the reference residual at " + casefile::describe_dof(m, static_cast<int>(d)));
  if (m.tangent_finite()) return;  // agreed over the processes of a distributed run
  const auto& k = m.tangent();
  for (int col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
      if (!std::isfinite(it.value()))
        not_finite(c, "the reference stiffness at " + casefile::describe_dof(m, m.constraints.free_dof(col)));
  not_finite(c, "the reference stiffness (of another process's elements)");
}

}  // namespace fibrane::run
