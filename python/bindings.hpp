#pragma once
// The extension fibrane._core: one binding file per concept (case_bindings.cpp: case text to data and
// checks; run_bindings.cpp: runs and the step callback; result_bindings.cpp: the final state's arrays;
// law_bindings.cpp: interaction laws and the error study). The Python package (fibrane/*.py) wraps them
// in its public API (docs/python.md).
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "case/case.hpp"
#include "run/run.hpp"

namespace fibrane::python {

namespace py = pybind11;

// A case read for a run and, after the run, its model at the last converged state (fibrane.Result).
struct RunState {
  casefile::Case c;
  run::RunSummary summary;
};

void bind_case(py::module_& m);
void bind_run(py::module_& m);
void bind_results(py::module_& m);
void bind_laws(py::module_& m);

// A body of the model: the shell or the beam of that name (the other pointer is null).
struct BodyRef {
  const model::ShellBody* shell = nullptr;
  const model::BeamBody* beam = nullptr;
};
// KeyError (listing the bodies) if the model has no body of that name.
BodyRef find_body(const model::Model& m, const std::string& name);

// The control-point displacements of a body in the displacement vector u: rows of (x, y, z) for a shell,
// (x, y, z, twist) for a beam.
py::object body_displacements(const model::Model& m, const std::string& name, const Eigen::VectorXd& u);

}  // namespace fibrane::python
