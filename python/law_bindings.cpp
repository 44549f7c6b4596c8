// Interaction laws of the registry (as a case's `law:` map names them) evaluated against the separation,
// and the error study of paper Sec. 4 as CSV text.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bindings.hpp"
#include "case/case_laws.hpp"
#include "common/error.hpp"
#include "io/yaml_input.hpp"
#include "laws/study.hpp"

namespace fibrane::python {
namespace {

// The law `law_yaml` (a YAML map {model: NAME, ...}) for a disk of `radius` and a plate of `thickness`
// at the distances `distance` and the orientation cos alpha = `cosine`: a dict of arrays (value and
// derivatives), with the law's name, its contact distance and, where it has one, its equilibrium distance.
py::dict evaluate_law(const std::string& law_yaml, const std::string& source, double radius, double thickness,
                      const py::array_t<double>& distance, double cosine) {
  if (!(radius > 0) || !(thickness > 0) || !std::isfinite(radius) || !std::isfinite(thickness))
    throw InputError(source + ": radius and thickness must be positive finite numbers");
  if (!(cosine >= 0 && cosine <= 1)) throw InputError(source + ": cos must lie in [0, 1]");
  const io::YamlNode spec = io::YamlNode::load_string(law_yaml, source);
  const auto law = casefile::make_law(spec, {radius, thickness});
  const double contact = law->contact_distance(cosine);
  const auto d = distance.unchecked<1>();
  const py::ssize_t n = d.shape(0);
  const char* names[] = {"value", "d_distance", "d_cos", "d2_distance", "d2_cos", "d2_distance_cos"};
  std::vector<py::array_t<double>> columns;
  for (int k = 0; k < 6; ++k) columns.emplace_back(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    if (!(d(i) > contact) || !std::isfinite(d(i)))
      throw InputError(source + ": distance[" + std::to_string(i) + "] = " + std::to_string(d(i)) +
                       ": expected a distance above the contact distance cos * radius + thickness / 2 = " +
                       std::to_string(contact) + " (positive gap)");
    laws::LawValue v;
    try {
      v = law->evaluate(d(i), cosine);
    } catch (const std::domain_error& e) {
      throw InputError(source + ": " + e.what());
    }
    const double values[] = {v.value, v.d_d, v.d_c, v.d_dd, v.d_cc, v.d_dc};
    for (int k = 0; k < 6; ++k) columns[k].mutable_at(i) = values[k];
  }
  py::dict out;
  out["law"] = law->name();
  out["distance"] = py::array_t<double>(n, d.data(0));
  for (int k = 0; k < 6; ++k) out[names[k]] = columns[k];
  out["contact_distance"] = contact;
  try {
    out["equilibrium_distance"] = law->equilibrium_distance(cosine);
  } catch (const std::runtime_error&) {  // a purely attractive or repulsive law has none
    out["equilibrium_distance"] = py::none();
  }
  return out;
}

}  // namespace

void bind_laws(py::module_& m) {
  m.def("law", &evaluate_law, py::arg("law_yaml"), py::arg("source"), py::arg("radius"), py::arg("thickness"),
        py::arg("distance"), py::arg("cos"), "An interaction law of the registry evaluated at the given distances.");
  m.def("study_figures", &laws::study::figure_names, "The error study's figures (fig6, ..., fig12).");
  m.def(
      "study_csv",
      [](const std::string& name, bool coarse) {
        const auto names = laws::study::figure_names();
        if (std::find(names.begin(), names.end(), name) == names.end()) {
          std::string known;
          for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
          throw InputError("study: expected one of " + known + ", got '" + name + "'");
        }
        std::ostringstream out;
        {
          py::gil_scoped_release release;
          laws::study::write_figure(name, out, coarse);
        }
        return out.str();
      },
      py::arg("name"), py::arg("coarse"), "The CSV text of one figure of the error study.");
}

}  // namespace fibrane::python
