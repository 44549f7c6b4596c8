#pragma once
// The named scalar quantities a model reports after every step (history.csv columns after the step data,
// summary.json, stop rules): the strain energy, per interaction its quantities as <name>_<quantity>
// (model/interaction.hpp; the SBS coupling's are its energy, the components of its total force on the
// beam and its lost points), then the monitors.
#include <functional>
#include <string>
#include <vector>

namespace fibrane::model {

class Model;

struct Observable {
  std::string name;
  std::function<double(const Model&)> value;  // of the model's last evaluation
};

std::vector<Observable> observables(const Model& m);

}  // namespace fibrane::model
