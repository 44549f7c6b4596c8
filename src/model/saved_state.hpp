#pragma once
// Flat arrays of doubles for the state contributions keep between steps (Contribution::save_state), and
// a reader that checks their length: a restart reads back exactly what a checkpoint wrote.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "beam/beam.hpp"

namespace fibrane::model {

// Appends values to a saved state.
class StateWriter {
 public:
  void add(double x) { values_.push_back(x); }
  void add(const Eigen::Ref<const Eigen::VectorXd>& v) { values_.insert(values_.end(), v.data(), v.data() + v.size()); }
  void add(const beam::BeamPointState& s);
  std::vector<double> take() { return std::move(values_); }

 private:
  std::vector<double> values_;
};

// Reads a saved state in the order StateWriter wrote it; throws InputError naming `owner` if the state
// is shorter than the reads or (finish()) longer.
class StateReader {
 public:
  StateReader(const std::vector<double>& values, std::string owner) : values_(values), owner_(std::move(owner)) {}
  double next();
  int next_int() { return static_cast<int>(next()); }
  Eigen::Vector3d next3();
  beam::BeamPointState next_point_state();
  void finish() const;

 private:
  const std::vector<double>& values_;
  std::string owner_;
  std::size_t pos_ = 0;
};

}  // namespace fibrane::model
