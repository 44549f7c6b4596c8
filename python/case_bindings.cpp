// Cases: YAML text to Python data (for editing a case as a dict) and the reader's checks on case text.
// The package turns dicts back into YAML text (fibrane/case.py), so that every case goes through
// casefile::read_case_text, the reader of the CLI.
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <climits>
#include <cmath>
#include <string_view>

#include "bindings.hpp"
#include "case/case_reader.hpp"
#include "io/yaml_guard.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::python {
namespace {

// A plain scalar as the reader takes it: an integer, a finite number, a boolean, null, or else a string
// (quoted scalars are always strings).
py::object scalar(const YAML::Node& n) {
  const std::string& s = n.Scalar();
  if (n.Tag() == "!") return py::str(s);
  std::string_view t = s;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  long long i = 0;
  if (const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), i);
      !t.empty() && ec == std::errc() && end == t.data() + t.size() && i >= INT_MIN && i <= INT_MAX)
    return py::int_(i);
  double x = 0;
  if (const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
      !t.empty() && ec == std::errc() && end == t.data() + t.size() && std::isfinite(x))
    return py::float_(x);
  if (s == "true") return py::bool_(true);
  if (s == "false") return py::bool_(false);
  if (s == "null" || s == "~") return py::none();
  return py::str(s);
}

py::object to_python(const YAML::Node& n) {
  if (n.IsMap()) {
    py::dict d;
    for (const auto& kv : n) d[py::str(kv.first.Scalar())] = to_python(kv.second);
    return d;
  }
  if (n.IsSequence()) {
    py::list l;
    for (const auto& x : n) l.append(to_python(x));
    return l;
  }
  if (n.IsNull()) return py::none();
  return scalar(n);
}

}  // namespace

void bind_case(py::module_& m) {
  m.def(
      "yaml_to_data",
      [](const std::string& text, const std::string& source) {
        // The reader's refusals first (size, encoding, structure, syntax), with its messages.
        io::YamlNode::load_string(text, source);
        return to_python(YAML::Load(text));
      },
      py::arg("text"), py::arg("source"),
      "The YAML text as dicts, lists and scalars (int, float, bool, None, str) as the case reader reads them.");
  m.def(
      "read_text_file", [](const std::string& path) { return io::read_text_limited(path); }, py::arg("path"),
      "A case file's text, with the reader's refusals (missing, not a regular file, too large).");
  m.def(
      "check_case",
      [](const std::string& text, const std::string& source, const std::string& name) {
        casefile::Case c;
        {
          py::gil_scoped_release release;
          c = casefile::read_case_text(text, source, name);
        }
        py::dict info;
        info["title"] = c.model->title;
        info["dofs"] = c.model->dofs.size();
        info["free_dofs"] = c.model->constraints.num_free();
        info["elements"] = c.model->num_elements();
        py::list shells, beams;
        for (const auto& s : c.model->shells) shells.append(s.name());
        for (const auto& b : c.model->beams) beams.append(b.name());
        info["shells"] = shells;
        info["beams"] = beams;
        info["method"] = c.run.method;
        info["output_directory"] = c.output.directory;
        return info;
      },
      py::arg("text"), py::arg("source"), py::arg("name"),
      "Reads and checks a case as the CLI does; InputError for bad input; returns a dict of its model's size.");
}

}  // namespace fibrane::python
