#include "model/observables.hpp"

#include "model/model.hpp"

namespace fibrane::model {

std::vector<Observable> observables(const Model& m) {
  std::vector<Observable> out;
  out.push_back({"strain_energy", [](const Model& x) { return x.strain_energy(); }});
  for (std::size_t i = 0; i < m.couplings.size(); ++i) {
    const std::string& name = m.couplings[i].name();
    out.push_back({name + "_energy", [i](const Model& x) { return x.couplings[i].energy(); }});
    for (int c = 0; c < 3; ++c)
      out.push_back({name + "_force_" + std::string(1, static_cast<char>('x' + c)),
                     [i, c](const Model& x) { return x.couplings[i].total_force()[c]; }});
    out.push_back({name + "_lost_points",
                   [i](const Model& x) { return static_cast<double>(x.couplings[i].lost_points()); }});
  }
  for (std::size_t i = 0; i < m.monitors.size(); ++i)
    out.push_back({m.monitors[i]->name(), [i](const Model& x) { return x.monitors[i]->value(x); }});
  return out;
}

}  // namespace fibrane::model
