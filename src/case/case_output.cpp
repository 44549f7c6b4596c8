#include "case/case_output.hpp"

#include <fmt/format.h>

#include "case/case_limits.hpp"

namespace fibrane::casefile {

void read_output(OutputSettings& out, const std::optional<io::YamlNode>& node, const std::string& case_name) {
  out.directory = "out/" + case_name;
  if (!node) return;
  if (!node->is_map()) node->fail("a map of output settings (directory, vtk, ...)");
  if (auto d = node->optional("directory")) {
    out.directory = d->as_string();
    if (out.directory.empty() || out.directory.find('\0') != std::string::npos)
      d->fail("a non-empty directory path");
  }
  out.vtk = node->get("vtk", out.vtk);
  out.vtk_every = optional_int_in(*node, "vtk_every", 1, 100'000'000, out.vtk_every, "write VTK every n-th step");
  out.checkpoint_every = optional_int_in(*node, "checkpoint_every", 0, 100'000'000, out.checkpoint_every,
                                "write the restart checkpoint every n-th step (0: only on interruption)");
  out.samples = optional_int_in(*node, "samples", 1, kMaxSamples, out.samples, "sampling points per element edge");
  if (auto cells = node->optional("vtk_cells")) {
    const std::string which = cells->as_choice({"bezier", "sampled", "both"});
    out.bezier = which != "sampled";
    out.sampled = which != "bezier";
  }
  out.vtk_pieces = node->get("vtk_pieces", out.vtk_pieces);
  node->reject_unknown_keys();
}

}  // namespace fibrane::casefile
