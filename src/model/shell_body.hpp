#pragma once
// A Kirchhoff-Love shell body (Sec. 3.1): a refined NURBS patch, its section, and the loops over its
// elements and quadrature points that feed the point kernel of src/shell into the sparse assembler. It is
// the contribution of the shell's strain energy, and it integrates the loads that act on it.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "model/contribution.hpp"
#include "shell/kl_shell.hpp"
#include "interaction/soft_distance.hpp"
#include "spline/surface.hpp"
#include "linalg/forward.hpp"

namespace fibrane::model {

class ShellBody final : public Contribution {
 public:
  spline::NurbsSurface surface;  // reference geometry after refinement
  shell::ShellSection section;
  int block = -1;                // DOF block: 3 displacement components per control point
  double density = 0;            // mass per unit volume (dynamics only)
  int gauss_points[2] = {0, 0};  // per direction; 0 means degree + 1 (the paper's choice)
  std::vector<spline::SurfaceElement> elements;
  std::vector<std::vector<int>> element_control_points;
  // Mirror planes of the modelled part (its symmetry constraints): the soft minimum counts the images.
  std::vector<interaction::MirrorPlane> mirrors;

  ShellBody(std::string name, spline::NurbsSurface surface, shell::ShellSection section);
  int num_control_points() const { return surface.num_control_points(); }
  int gauss(int dir) const { return gauss_points[dir] > 0 ? gauss_points[dir] : surface.degree(dir) + 1; }
  // Current control points x = X + u for the control points `cps`.
  Eigen::Matrix3Xd current(const std::vector<int>& cps, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;
  Eigen::Matrix3Xd reference(const std::vector<int>& cps) const;
  // The same into `x` / `X`, whose storage is kept where it has the size (an element loop's per-thread
  // arrays, without an allocation per element).
  void current(const std::vector<int>& cps, const Eigen::VectorXd& u, const solve::DofMap& dofs,
               Eigen::Matrix3Xd& x) const;
  void reference(const std::vector<int>& cps, Eigen::Matrix3Xd& X) const;
  // Displacement of the surface point (u, v).
  Eigen::Vector3d displacement(double pu, double pv, const Eigen::VectorXd& u, const solve::DofMap& dofs) const;

  // Contribution: the strain energy (Eq. 25) and its variations (Eq. 28, App. A), element by element.
  std::string name() const override { return name_; }
  std::vector<std::vector<int>> element_dofs(const solve::DofMap& dofs) const override;
  double evaluate(const State& s, ElementSink& sink, Status& status) override;

  // Consistent nodal forces (3 per control point, control-point major) of loads on this shell:
  // a force per unit reference area, or a pressure p along the reference normal (force = p J_S N);
  Eigen::VectorXd surface_load(const Eigen::Vector3d& force) const;
  Eigen::VectorXd pressure_load(double pressure) const;
  // a force per unit reference length along an edge (u0, u1, v0, v1).
  Eigen::VectorXd edge_load(const std::string& edge, const Eigen::Vector3d& force) const;
  // The elements along an edge (u0, u1, v0, v1).
  std::vector<int> edge_elements(const std::string& edge) const;

 private:
  std::string name_;
  Eigen::VectorXd area_load(const Eigen::Vector3d& force, bool pressure) const;
};

}  // namespace fibrane::model
