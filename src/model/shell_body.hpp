#pragma once
// A Kirchhoff-Love shell body: a refined NURBS patch, its section, and the loops over its elements and
// quadrature points that feed the point kernel of src/shell into the sparse assembler.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "shell/kl_shell.hpp"
#include "interaction/soft_distance.hpp"
#include "spline/surface.hpp"
#include "solve/forward.hpp"

namespace fibrane::model {

struct ShellBody {
  std::string name;
  spline::NurbsSurface surface;  // reference geometry after refinement
  shell::ShellSection section;
  int block = -1;                // DOF block: 3 displacement components per control point
  int gauss_points[2] = {0, 0};  // per direction; 0 means degree + 1 (the paper's choice)
  std::vector<spline::SurfaceElement> elements;
  std::vector<std::vector<int>> element_control_points;
  // Mirror planes of the modelled part (its symmetry constraints): the soft minimum counts the images.
  std::vector<interaction::MirrorPlane> mirrors;

  ShellBody(std::string name, spline::NurbsSurface surface, shell::ShellSection section);
  int num_control_points() const { return surface.num_control_points(); }
  int gauss(int dir) const { return gauss_points[dir] > 0 ? gauss_points[dir] : surface.degree(dir) + 1; }
  // Full DOF lists of every element, in the order of `elements`.
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const;
  // Current control points x = X + u for the control points `cps`.
  Eigen::Matrix3Xd current(const std::vector<int>& cps, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;
  Eigen::Matrix3Xd reference(const std::vector<int>& cps) const;
  // Adds residual (and tangent) of every element, element ids starting at `first_element`. Returns the
  // strain energy.
  double assemble(const Eigen::VectorXd& u, const solve::DofMap& dofs, solve::SparseAssembler& a,
                  int first_element, bool with_tangent) const;
  // Displacement of the surface point (u, v).
  Eigen::Vector3d displacement(double pu, double pv, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;
};

}  // namespace fibrane::model
