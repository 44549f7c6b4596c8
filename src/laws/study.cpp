#include "laws/study.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/error.hpp"
#include "laws/disk_plate.hpp"
#include "laws/disk_sphere.hpp"
#include "laws/reference.hpp"

namespace fibrane::laws::study {
namespace {

std::vector<double> log_grid(double low, double high, int per_decade) {
  std::vector<double> out;
  const int count = static_cast<int>(std::round(std::log10(high / low) * per_decade));
  for (int i = 0; i <= count; ++i) out.push_back(low * std::pow(10.0, double(i) / per_decade));
  return out;
}

std::string row(std::initializer_list<double> values) {
  std::string line;
  char buffer[40];
  for (double v : values) {
    std::snprintf(buffer, sizeof buffer, "%.12g", v);
    if (!line.empty()) line += ',';
    line += buffer;
  }
  return line + "\n";
}

// Force -dPi/dg of the disk-plate law at gap g, disk perpendicular to the plate (c = 1).
double plate_force(double disk_radius, double thickness, double gap) {
  return -DiskPlate(6, disk_radius, thickness).jet(disk_radius + 0.5 * thickness + gap, 1.0).d;
}

// Figs. 6 and 7: disk vs spherical shell (closed forms, App. F corrected), R_D = 1.
void disk_spherical_shell_figure(std::ostream& out, bool against_plate, bool coarse) {
  out << "shell_radius,thickness,gap,relative_error" << (against_plate ? ",eq58_limit" : "") << "\n";
  for (double rss : {2.0, 10.0, 100.0})
    for (double h : {0.1, 1.0})
      for (double g : log_grid(1e-4, 1e2, coarse ? 2 : 10)) {
        const double d = 1.0 + rss + 0.5 * h + g;
        const double shell = -disk_spherical_shell(1.0, rss, h, d).d1;
        const double other = against_plate ? plate_force(1.0, h, g) : -disk_sphere(1.0, rss + 0.5 * h, d).d1;
        const double error = (shell - other) / shell;
        if (against_plate)
          out << row({rss, h, g, error, 1 - std::sqrt(1 + 2.0 / (h + 2 * rss))});
        else
          out << row({rss, h, g, error});
      }
}

// Figs. 8 and 9: disk vs infinite cylindrical shell (reference cubature) against the D-PT law.
void disk_cylindrical_shell_figure(std::ostream& out, bool parallel, bool coarse) {
  out << "shell_radius,thickness,gap,relative_error\n";
  for (double rcs : {2.0, 10.0})
    for (double h : {0.1, 1.0})
      for (double g : log_grid(1e-3, 1e1, coarse ? 1 : 5)) {
        auto potential = [&](double d) {
          return parallel ? reference::disk_cylindrical_shell_parallel(1.0, rcs, h, d, 1e-10)
                          : reference::disk_cylindrical_shell_perpendicular(1.0, rcs, h, d, 1e-10);
        };
        const double d = 1.0 + rcs + 0.5 * h + g;
        const double exact = reference::negative_derivative(potential, d, 0.01 * g);
        out << row({rcs, h, g, (exact - plate_force(1.0, h, g)) / exact});
      }
}

template <class Force>
double log_slope(Force force, double gap) {
  // S = -d ln F / d ln g by a five-point stencil in ln g (step 0.01: truncation ~1e-9).
  const double step = 0.01;
  auto f = [&](double log_gap) { return std::log(force(std::exp(log_gap))); };
  return reference::negative_derivative(f, std::log(gap), step);
}

void scaling_figure(std::ostream& out, bool coarse) {
  out << "gap,scaling_exact,scaling_sbs,scaling_sbs_cos1\n";  // R_SS = 10, R_C = 1, h = 1
  for (double g : log_grid(1e-3, 1e4, coarse ? 1 : 8))
    out << row({g, scaling_factor_exact(1, 10, 1, g), scaling_factor_sbs(1, 10, 1, g, true),
                scaling_factor_sbs(1, 10, 1, g, false)});
}

void sbs_error_figure(std::ostream& out, bool coarse) {
  out << "shell_radius,thickness,gap,error_sbs,error_sbs_cos1,eq58_bound\n";  // R_C = 1
  for (double rss : {2.0, 10.0, 20.0, 100.0})
    for (double h : {0.1, 1.0})
      for (double g : log_grid(1e-3, 1e1, coarse ? 1 : 6)) {
        const double exact = reference::cylinder_spherical_shell_force(1, rss, h, g);
        const double sbs = reference::cylinder_spherical_shell_sbs_force(1, rss, h, g, true);
        const double sbs1 = reference::cylinder_spherical_shell_sbs_force(1, rss, h, g, false);
        out << row({rss, h, g, (exact - sbs) / exact, (exact - sbs1) / exact,
                    1 - std::sqrt(1 + 2.0 / (h + 2 * rss))});
      }
}

}  // namespace

std::vector<std::string> figure_names() { return {"fig6", "fig7", "fig8", "fig9", "fig11", "fig12"}; }

double scaling_factor_exact(double cylinder_radius, double shell_radius, double thickness, double gap) {
  return log_slope([&](double g) {
    return reference::cylinder_spherical_shell_force(cylinder_radius, shell_radius, thickness, g, 1e-13);
  }, gap);
}

double scaling_factor_sbs(double cylinder_radius, double shell_radius, double thickness, double gap,
                          bool exact_orientation) {
  return log_slope([&](double g) {
    return reference::cylinder_spherical_shell_sbs_force(cylinder_radius, shell_radius, thickness, g,
                                                         exact_orientation, 1e-13);
  }, gap);
}

void write_figure(const std::string& name, std::ostream& out, bool coarse) {
  if (name == "fig6") return disk_spherical_shell_figure(out, false, coarse);
  if (name == "fig7") return disk_spherical_shell_figure(out, true, coarse);
  if (name == "fig8") return disk_cylindrical_shell_figure(out, true, coarse);
  if (name == "fig9") return disk_cylindrical_shell_figure(out, false, coarse);
  if (name == "fig11") return scaling_figure(out, coarse);
  if (name == "fig12") return sbs_error_figure(out, coarse);
  throw InputError("unknown study '" + name + "' (fig6, fig7, fig8, fig9, fig11, fig12, all)");
}

}  // namespace fibrane::laws::study
