// The final state of a run as arrays: the bodies' control-point displacements, the deformed geometry and
// the shells' section forces at parametric points, from the model evaluated at the last converged state
// (run_bindings.cpp).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "spline/curve.hpp"
#include "spline/surface.hpp"

namespace fibrane::python {

BodyRef find_body(const model::Model& m, const std::string& name) {
  for (const auto& s : m.shells)
    if (s.name() == name) return {&s, nullptr};
  for (const auto& b : m.beams)
    if (b.name() == name) return {nullptr, &b};
  std::string known;
  for (const auto& s : m.shells) known += (known.empty() ? "'" : ", '") + s.name() + "'";
  for (const auto& b : m.beams) known += (known.empty() ? "'" : ", '") + b.name() + "'";
  throw py::key_error("no body '" + name + "' in this case (bodies: " + known + ")");
}

py::object body_displacements(const model::Model& m, const std::string& name, const Eigen::VectorXd& u) {
  const BodyRef b = find_body(m, name);
  const int block = b.shell ? b.shell->block : b.beam->block;
  const int n = m.dofs.num_nodes(block), per = m.dofs.dofs_per_node(block);
  py::array_t<double> out({n, per});
  auto a = out.mutable_unchecked<2>();
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < per; ++c) a(i, c) = u[m.dofs.dof(block, i, c)];
  return out;
}

namespace {

// Reference control points x_a + u_a: the deformed geometry has the same knots and weights.
std::vector<Eigen::Vector3d> moved(const std::vector<Eigen::Vector3d>& reference, const model::Model& m, int block) {
  std::vector<Eigen::Vector3d> x = reference;
  const Eigen::VectorXd& u = m.displacement();
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int c = 0; c < 3; ++c) x[i][c] += u[m.dofs.dof(block, static_cast<int>(i), c)];
  return x;
}

void check_range(double x, const spline::KnotVector& k, const char* what) {
  if (!(x >= k.front() && x <= k.back()))
    throw py::value_error(std::string(what) + " = " + std::to_string(x) + " lies outside the parameter domain [" +
                          std::to_string(k.front()) + ", " + std::to_string(k.back()) + "]");
}

// Points of the deformed (or, with `deformed` false, the reference) body at parametric points: for a
// shell an (n, 2) array of (u, v), for a beam an (n,) array of xi; the result has shape (n, 3).
py::array_t<double> geometry(const RunState& s, const std::string& name, const py::array_t<double>& params,
                             bool deformed) {
  const model::Model& m = *s.c.model;
  const BodyRef b = find_body(m, name);
  const auto p = params.unchecked();
  std::vector<Eigen::Vector3d> points;
  if (b.shell) {
    if (p.ndim() != 2 || p.shape(1) != 2) throw py::value_error("a shell's parametric points: an array of shape (n, 2)");
    const auto& r = b.shell->surface;
    const spline::NurbsSurface surface(r.knots(0), r.knots(1),
                                       deformed ? moved(r.control_points(), m, b.shell->block) : r.control_points(),
                                       r.weights());
    for (py::ssize_t i = 0; i < p.shape(0); ++i) {
      check_range(p(i, 0), r.knots(0), "u");
      check_range(p(i, 1), r.knots(1), "v");
      points.push_back(surface.point(p(i, 0), p(i, 1)));
    }
  } else {
    if (p.ndim() != 1) throw py::value_error("a beam's parametric points: an array of shape (n,)");
    const auto& r = b.beam->curve;
    const spline::NurbsCurve curve(r.knots(), deformed ? moved(r.control_points(), m, b.beam->block) : r.control_points(),
                                   r.weights());
    for (py::ssize_t i = 0; i < p.shape(0); ++i) {
      check_range(p(i), r.knots(), "xi");
      points.push_back(curve.point(p(i)));
    }
  }
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < 3; ++c) a(static_cast<py::ssize_t>(i), c) = points[i][c];
  return out;
}

// The section forces and moments of a shell at parametric points (n, 2) of (u, v), as the sampled VTK
// output gives them (11, 22, 12 each): per current length in the frame e1 = g1/|g1|, e2 = n x e1
// (N_local, M_local) and the contravariant components N^ab, M^ab (N, M).
py::dict section_forces(const RunState& s, const std::string& name, const py::array_t<double>& params) {
  const model::Model& m = *s.c.model;
  const BodyRef b = find_body(m, name);
  if (!b.shell)
    throw py::value_error("section_forces: '" + name + "' is a beam; beams' section forces (N, M) are in the sampled "
                          "VTK output");
  const auto p = params.unchecked();
  if (p.ndim() != 2 || p.shape(1) != 2) throw py::value_error("a shell's parametric points: an array of shape (n, 2)");
  const model::ShellBody& shell = *b.shell;
  const char* names[] = {"N_local", "M_local", "N", "M"};
  std::vector<py::array_t<double>> out;
  for (int k = 0; k < 4; ++k) out.emplace_back(std::vector<py::ssize_t>{p.shape(0), 3});
  for (py::ssize_t i = 0; i < p.shape(0); ++i) {
    check_range(p(i, 0), shell.surface.knots(0), "u");
    check_range(p(i, 1), shell.surface.knots(1), "v");
    const auto basis = shell.surface.basis(p(i, 0), p(i, 1));
    const auto f = shell::section_forces(shell.section, basis.R, shell.reference(basis.indices),
                                         shell.current(basis.indices, m.displacement(), m.dofs));
    const Eigen::Matrix2d* values[] = {&f.N_local, &f.M_local, &f.N, &f.M};
    for (int k = 0; k < 4; ++k) {
      out[k].mutable_at(i, 0) = (*values[k])(0, 0);
      out[k].mutable_at(i, 1) = (*values[k])(1, 1);
      out[k].mutable_at(i, 2) = (*values[k])(0, 1);
    }
  }
  py::dict d;
  for (int k = 0; k < 4; ++k) d[names[k]] = out[k];
  return d;
}

}  // namespace

void bind_results(py::module_& m) {
  py::class_<RunState>(m, "RunState", "A finished run: its summary and its model at the last converged state.")
      .def_property_readonly("outcome", [](const RunState& s) { return solve::outcome_name(s.summary.result.outcome); })
      .def_property_readonly("completed", [](const RunState& s) { return s.summary.result.completed(); })
      .def_property_readonly("message", [](const RunState& s) { return s.summary.result.message; })
      .def_property_readonly("t_reached", [](const RunState& s) { return s.summary.result.t_reached; })
      .def_property_readonly("steps", [](const RunState& s) { return s.summary.result.steps; })
      .def_property_readonly("directory", [](const RunState& s) { return s.summary.directory; })
      .def_property_readonly("interrupted_by", [](const RunState& s) { return s.summary.interrupted_by; })
      .def_property_readonly("wall_seconds", [](const RunState& s) { return s.summary.wall_seconds; })
      .def("bodies", [](const RunState& s) {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& x : s.c.model->shells) out.emplace_back(x.name(), "shell");
        for (const auto& x : s.c.model->beams) out.emplace_back(x.name(), "beam");
        return out;
      })
      .def("displacements", [](const RunState& s, const std::string& body) {
        return body_displacements(*s.c.model, body, s.c.model->displacement());
      })
      .def("unknowns", [](const RunState& s) { return py::array_t<double>(s.summary.q.size(), s.summary.q.data()); })
      .def("geometry", &geometry, py::arg("body"), py::arg("params"), py::arg("deformed") = true)
      .def("section_forces", &section_forces, py::arg("body"), py::arg("params"));
}

}  // namespace fibrane::python
