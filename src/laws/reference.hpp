#pragma once
// Reference integrators (adaptive Gauss-Kronrod cubature, default 1e-12 relative per level) for the
// pair potential r^-m between a disk and various bodies, used to verify the closed-form laws and as
// the "exact" side of the error study of paper Sec. 4. Each reduces the body integral to a known
// point-body law first; all the rest is numerical.
namespace fibrane::laws::reference {

// Disk (radius R, centre at distance d, c = cos alpha) vs half-space / plate (thickness h, d to the
// mid-plane): polar cubature over the disk of the point-half-space / point-plate laws.
double disk_halfspace(double m, double radius, double d, double c, double tol = 1e-12);
double disk_plate(double m, double radius, double thickness, double d, double c, double tol = 1e-12);

// The following are for m = 6 (van der Waals), as in paper Sec. 4.2-4.3.
// Point at distance t from the centre of a solid sphere: spherical cubature of r^-6 (checks F1).
double point_sphere(double sphere_radius, double t, double tol = 1e-12);
// Disk vs sphere, perpendicular orientation, centre distance d: Eq. (F3) by cubature.
double disk_sphere(double disk_radius, double sphere_radius, double d, double tol = 1e-12);
// int_0^pi (A - B cos b)^-5/2 db through complete elliptic integrals (A > B >= 0).
double angular_integral_five_halves(double a, double b);
// Point at distance rho from the axis of an infinite cylindrical shell (mid-surface radius R,
// thickness h): r^-6 integrated along the axis (3 pi / 8 rho^-5), then over the annulus.
double point_cylindrical_shell(double shell_radius, double thickness, double rho, double tol = 1e-11);
// Disk vs infinite cylindrical shell, disk centre at distance d from the axis (Fig. 5b).
// Parallel: disk plane perpendicular to the axis; perpendicular: disk plane contains the axis.
double disk_cylindrical_shell_parallel(double disk_radius, double shell_radius, double thickness,
                                       double d, double tol = 1e-11);
double disk_cylindrical_shell_perpendicular(double disk_radius, double shell_radius,
                                            double thickness, double d, double tol = 1e-12);

// Infinite cylinder (radius R_C) vs spherical shell (mid-surface R_SS, thickness h) at smallest gap
// g0 (Sec. 4.3, Fig. 10). Returns the force -dPi/dg0 (m = 6, unit constants).
double cylinder_spherical_shell_force(double cylinder_radius, double shell_radius, double thickness,
                                      double gap, double tol = 1e-12);
// The same force with the SBS approximation: the D-PT law (56) integrated along the cylinder axis,
// with the true orientation cos alpha(xi) (exact_orientation) or with cos alpha = 1.
double cylinder_spherical_shell_sbs_force(double cylinder_radius, double shell_radius,
                                          double thickness, double gap, bool exact_orientation,
                                          double tol = 1e-12);

// -d f / d x at x by a five-point central difference with step h (fourth order).
template <class F>
double negative_derivative(F f, double x, double h) {
  return -(f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h);
}

}  // namespace fibrane::laws::reference
