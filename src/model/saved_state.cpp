#include "model/saved_state.hpp"

#include "common/error.hpp"

namespace fibrane::model {

void StateWriter::add(const beam::BeamPointState& s) {
  for (double x : {s.ref_metric, s.ref_torsion, s.ref_bend2, s.ref_bend3}) add(x);
  for (const Eigen::Vector3d* v : {&s.frame_t, &s.frame_d2, &s.frame_d3, &s.frame_t_xi, &s.frame_d2_xi, &s.frame_d3_xi})
    add(*v);
  add(s.twist_offset);
  add(s.twist_offset_xi);
}

double StateReader::next() {
  if (pos_ >= values_.size()) throw InputError("checkpoint: the saved state of " + owner_ + " is too short for the case");
  return values_[pos_++];
}

Eigen::Vector3d StateReader::next3() {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = next();
  return v;
}

beam::BeamPointState StateReader::next_point_state() {
  beam::BeamPointState s;
  s.ref_metric = next();
  s.ref_torsion = next();
  s.ref_bend2 = next();
  s.ref_bend3 = next();
  for (Eigen::Vector3d* v : {&s.frame_t, &s.frame_d2, &s.frame_d3, &s.frame_t_xi, &s.frame_d2_xi, &s.frame_d3_xi})
    *v = next3();
  s.twist_offset = next();
  s.twist_offset_xi = next();
  return s;
}

void StateReader::finish() const {
  if (pos_ != values_.size())
    throw InputError("checkpoint: the saved state of " + owner_ + " is longer than the case needs");
}

}  // namespace fibrane::model
