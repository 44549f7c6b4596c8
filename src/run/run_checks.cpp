#include "run/run_checks.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "case/case_checks.hpp"
#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane::run {

void check_output_directory(const casefile::Case& c, const std::string& directory, const std::string& origin) {
  namespace fs = std::filesystem;
  const std::string where = c.path + ": " + origin + " '" + directory + "'";
  std::error_code ec;
  fs::path p = fs::absolute(directory, ec);
  if (ec) throw InputError(where + ": " + ec.message());
  // The directory itself, or the nearest ancestor that exists (create_directories makes the rest).
  fs::path missing;  // the first directory the run would create, if any
  while (!fs::exists(p, ec)) {
    if (ec && ec != std::errc::no_such_file_or_directory) throw InputError(where + ": " + ec.message());
    if (!p.has_parent_path() || p.parent_path() == p) throw InputError(where + ": no existing parent directory");
    missing = p;
    p = p.parent_path();
  }
  if (!fs::is_directory(p, ec))
    throw InputError(where + ": '" + p.string() + "' exists and is not a directory");
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError(where + ": '" + p.string() + "' is not writable");
  // Permissions do not tell everything (/proc, /sys, full or read-only file systems): create and remove what
  // the run would create first, the output directory or a file in it.
  if (!missing.empty()) {
    if (::mkdir(missing.c_str(), 0755) == 0) ::rmdir(missing.c_str());
    else if (errno != EEXIST)  // EEXIST: another process of a distributed run probes at the same time
      throw InputError(where + ": cannot create the directory '" + missing.string() + "': " + std::strerror(errno));
    return;
  }
  const fs::path probe = p / (".fibrane-probe-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) throw InputError(where + ": cannot create a file in it: " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

namespace {

// "<file>:<line>: <entry>: " of the body that holds `dof` (the case file alone if none is known).
std::string located(const casefile::Case& c, int dof) {
  const model::Model& m = *c.model;
  for (int b = 0; b < m.dofs.num_blocks(); ++b) {
    const int local = dof - m.dofs.block_offset(b);
    if (local < 0 || local >= m.dofs.block_size(b)) continue;
    const auto it = c.body_origins.find(m.dofs.block_name(b));
    if (it != c.body_origins.end()) return c.path + ":" + std::to_string(it->second.line) + ": " + it->second.path + ": ";
  }
  return c.path + ": ";
}

[[noreturn]] void not_finite(const std::string& where, const std::string& what) {
  throw InputError(where + what +
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
          not_finite(c.path + ": ", "the load on " + casefile::describe_dof(m, load.dofs[static_cast<std::size_t>(k)]) +
                                        " at t = " + format_number(t));
    }
  m.evaluate(m.initial_unknowns(), t0, true);
  if (!m.invalid_state().empty()) return;  // reported by the run, like any state outside the domain
  const Eigen::VectorXd& r = m.full_residual();
  for (Eigen::Index d = 0; d < r.size(); ++d)
    if (!std::isfinite(r[d]))
      not_finite(located(c, static_cast<int>(d)), "the reference residual (internal minus external forces at t = " +
                                                      format_number(t0) + ") at " +
                                                      casefile::describe_dof(m, static_cast<int>(d)));
  if (m.tangent_finite()) return;  // agreed over the processes of a distributed run
  const auto& k = m.tangent();
  for (int col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
      if (!std::isfinite(it.value()))
        not_finite(located(c, m.constraints.free_dof(col)),
                   "the reference stiffness at " + casefile::describe_dof(m, m.constraints.free_dof(col)));
  not_finite(c.path + ": ", "the reference stiffness (of another process's elements)");
}

}  // namespace fibrane::run
