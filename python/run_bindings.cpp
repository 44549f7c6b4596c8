// Runs: the CLI's run driver (run::run_case) on a case read from text, with the GIL released while the
// C++ runs and the Python step callback called (with the GIL) after every converged step.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <omp.h>

#include <algorithm>
#include <optional>

#include "bindings.hpp"
#include "case/case_reader.hpp"
#include "model/observables.hpp"

namespace fibrane::python {
namespace {

// What the step callback sees of a converged step; valid only during the callback (afterwards its
// methods raise RuntimeError: the run has moved on).
class StepState {
 public:
  StepState(const solve::StepReport& r, const Eigen::VectorXd& q, const model::Model& m) : r_(&r), q_(&q), m_(&m) {}
  void expire() { r_ = nullptr; }
  const solve::StepReport& report() const { return (check(), *r_); }
  py::array_t<double> unknowns() const {
    check();
    return py::array_t<double>(q_->size(), q_->data());
  }
  py::object displacements(const std::string& body) const {
    check();
    return body_displacements(*m_, body, m_->displacement());
  }

 private:
  void check() const {
    if (!r_) throw std::runtime_error("this step state belongs to a step callback that has returned");
  }
  const solve::StepReport* r_;
  const Eigen::VectorXd* q_;
  const model::Model* m_;
};

// The history quantities of the model's current state (strain energy, interactions, monitors).
py::dict observable_values(const model::Model& m) {
  py::dict d;
  for (const auto& o : model::observables(m)) d[py::str(o.name)] = o.value(m);
  return d;
}

std::unique_ptr<RunState> run_text(const std::string& text, const std::string& source, const std::string& name,
                                   const std::string& output, int threads, bool restart, bool quiet,
                                   bool newton_log, int max_steps, const py::object& callback) {
  auto state = std::make_unique<RunState>();
  run::RunOptions options;
  options.output_directory = output;
  options.threads = threads;
  options.restart = restart;
  options.quiet = quiet;
  options.newton_log = newton_log;
  std::optional<py::error_already_set> callback_error;
  if (!callback.is_none())
    options.on_step = [&](const solve::StepReport& r, const Eigen::VectorXd& q, const model::Model& m) {
      py::gil_scoped_acquire gil;
      auto view = std::make_shared<StepState>(r, q, m);
      try {
        py::object result = callback(r.t, r.step, observable_values(m), view);
        view->expire();
        return !(py::isinstance<py::bool_>(result) && !result.cast<bool>());
      } catch (py::error_already_set& e) {
        view->expire();
        callback_error = std::move(e);
        return false;
      }
    };
  {
    py::gil_scoped_release release;
    state->c = casefile::read_case_text(text, source, name);
    if (max_steps > 0) state->c.run.steps.max_steps = std::min(state->c.run.steps.max_steps, max_steps);
    state->summary = run::run_case(state->c, options);
    // The model at the last converged state, for the results' arrays.
    state->c.model->evaluate(state->summary.q, state->summary.result.t_reached, false);
  }
  if (callback_error) throw std::move(*callback_error);
  return state;
}

}  // namespace

void bind_run(py::module_& m) {
  py::class_<StepState, std::shared_ptr<StepState>>(m, "StepState", "The state of a converged step, seen by a step callback (during the call only).")
      .def_property_readonly("t", [](const StepState& s) { return s.report().t; }, "the step's t (load parameter or time)")
      .def_property_readonly("step", [](const StepState& s) { return s.report().step; }, "the step number")
      .def_property_readonly("dt", [](const StepState& s) { return s.report().dt; }, "the step's increment of t")
      .def_property_readonly("iterations", [](const StepState& s) { return s.report().iterations; },
                             "Newton iterations of the step")
      .def_property_readonly("residual", [](const StepState& s) { return s.report().residual_norm; },
                             "norm of the final residual")
      .def_property_readonly("unknowns", &StepState::unknowns, "the free unknowns (a copy), shape (free_dofs,)")
      .def("displacements", &StepState::displacements, py::arg("body"),
           "Control-point displacements of a body: shape (n, 3) for a shell, (n, 4) (x, y, z, twist) for a beam.");
  m.def("max_threads", &omp_get_max_threads, "OpenMP's thread count for the next parallel region.");
  m.def("run", &run_text, py::arg("text"), py::arg("source"), py::arg("name"), py::arg("output"), py::arg("threads"),
        py::arg("restart"), py::arg("quiet"), py::arg("newton_log"), py::arg("max_steps"), py::arg("callback"),
        "Reads the case text and runs it into the output directory with the CLI's run driver.");
}

}  // namespace fibrane::python
