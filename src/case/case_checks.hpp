#pragma once
// Whole-case checks of a case file, run once its parts have been read: output names that would clash,
// monitor names that would clash with history columns, constraint errors named in the case's own terms,
// and bodies that nothing holds.
#include <cstddef>
#include <string>
#include <vector>

#include "io/yaml_input.hpp"
#include "model/model.hpp"
#include "linalg/constraints.hpp"

namespace fibrane::casefile {

// Where the constraints of the model came from: entry k of the case's 'constraints' list added the
// constraints [first[k], first[k + 1]) of the model's ConstraintSet.
struct ConstraintOrigins {
  std::vector<std::size_t> first;
  std::vector<io::YamlNode> entries;
};

// Bodies (shells then beams) and the interactions' point series write files named after them: <name>.pvd,
// <name>_sampled.pvd, vtk/<name>_<step>.vtu, interaction/<name>_<step>.csv. InputError at the later name
// where two collide.
void check_output_names(const model::Model& m, const io::YamlNode& root);

// Monitors become history.csv columns: InputError at a monitor whose name is unsafe (case_limits.hpp) or
// equals a built-in column (step, t, load_factor, iterations, residual, negative_eigenvalues, limit_point,
// strain_energy, the interactions' <interaction>_<quantity>, the energy account of dynamic runs) or another
// monitor.
void check_monitor_names(const model::Model& m, const io::YamlNode& root);

// "body 'plate' control point [2, 0] component z" for a global DOF of the model.
std::string describe_dof(const model::Model& m, int dof);

// The ConstraintError of Model::finalize() as an InputError naming the case file, the constraint
// entries involved (line and path) and the DOFs as body, control point and component.
InputError explain_constraint_error(const solve::ConstraintError& e, const model::Model& m,
                                    const ConstraintOrigins& origins, const std::string& file);

// InputError for a body that no constraint and no interaction holds in some direction: a uniform
// translation of it costs no energy, so the stiffness is singular. Call after Model::finalize().
void check_free_bodies(const model::Model& m, const io::YamlNode& root);

}  // namespace fibrane::casefile
