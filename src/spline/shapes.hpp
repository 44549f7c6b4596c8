#pragma once
// Exact NURBS generators. Each returns the coarsest exact representation on the parameter domain
// [0,1] (curves) or [0,1]^2 (surfaces); callers refine (NurbsCurve::refine, NurbsSurface::refine).
//
// Circular arcs are quadratic rational B-splines without C0 knots below a full turn: an arc of up to 120
// degrees is one rational quadratic Bezier segment (middle weight cos(sweep/2)); an arc of more than 120
// and less than 360 degrees (a half cylinder, a hemisphere's meridian) is two segments joined C1 at the
// simple knot 0.5 (knots 0 0 0 0.5 1 1 1, weights 1, cos^2(sweep/4), cos^2(sweep/4), 1). Only a full
// circle (360 degrees) is four 90-degree segments joined C0 (knots 0.25, 0.5, 0.75 of multiplicity 2).
// The parameterisation is exact in geometry but not proportional to the angle (the speed varies by less
// than a factor 2 along each segment).
//
// Cylinder convention ("Scordelis-Lo / pinched cylinder" frame): the axis is the global x axis and the
// cross-sections are circles in the y-z plane,
//     S(u, v) = ( x(v), R cos th(u), R sin th(u) ),  x from 0 (v = 0) to length (v = 1),
//                                                   th from theta0 (u = 0) to theta1 (u = 1).
// th = 0 points along +y, th = pi/2 along +z (the "top" if z is up). Example: a Scordelis-Lo roof
// (40 degree half-angle, apex on top) is make_cylinder_patch(R, L, pi/2 - 40deg, pi/2 + 40deg); a
// pinched-cylinder octant is make_cylinder_patch(R, L/2, 0, pi/2).
// u is the circumferential (degree 2, rational) direction, v the axial (degree 1) direction.
//
// Sphere convention: longitude th about the z axis, latitude ph from the equator (ph = pi/2 is the
// north pole +z):
//     S(u, v) = R ( cos ph cos th, cos ph sin th, sin ph ),  th in [theta0, theta1] along u,
//                                                           ph in [phi0, phi1] along v.
// Both directions are degree 2 rational. A patch reaching a pole is degenerate there (a row of equal
// control points) but still exact.
#include <Eigen/Dense>

#include "spline/curve.hpp"
#include "spline/surface.hpp"

namespace fibrane::spline {

// Bilinear parallelogram: S(u, v) = origin + u edge_u + v edge_v.
NurbsSurface make_rectangle(Eigen::Vector3d origin, Eigen::Vector3d edge_u, Eigen::Vector3d edge_v);
// See the cylinder convention above. Needs radius > 0, length > 0, 0 < |theta1 - theta0| <= 2 pi.
NurbsSurface make_cylinder_patch(double radius, double length, double theta0, double theta1);
// See the sphere convention above. Needs radius > 0, 0 < |theta1 - theta0| <= 2 pi,
// -pi/2 <= phi0 < phi1 <= pi/2.
NurbsSurface make_sphere_patch(double radius, double theta0, double theta1, double phi0, double phi1);
// Straight segment, degree 1: C(u) = a + u (b - a).
NurbsCurve make_line(Eigen::Vector3d a, Eigen::Vector3d b);
// C(u) = center + radius (cos t e1 + sin t e2), t from angle0 (u = 0) to angle1 (u = 1); exact quadratic
// rational. e1, e2 should be orthonormal for a circle (otherwise an exact ellipse arc results).
NurbsCurve make_arc(Eigen::Vector3d center, Eigen::Vector3d e1, Eigen::Vector3d e2, double radius,
                    double angle0, double angle1);

// The unit-circle arc (cos t, sin t), t in [angle0, angle1], as a quadratic rational B-spline in
// homogeneous-free form: 2D control points (c_k, s_k) and weights. Building block of the generators.
struct UnitArc {
  KnotVector knots;
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;
};
UnitArc make_unit_arc(double angle0, double angle1);

}  // namespace fibrane::spline
