// The pair pattern of the beam-beam interaction (model/beam_beam.hpp): which (element, element) pairs
// are assembler elements, and their DOF lists.
#include <algorithm>
#include <utility>
#include <vector>

#include "linalg/dof_map.hpp"
#include "model/beam_beam.hpp"
#include "model/beam_body.hpp"

namespace fibrane::model {

bool BeamBeamInteraction::keep_pair(int e0, int e1) const {
  if (e0 < 0 || e1 < 0 || e0 >= static_cast<int>(fiber_[0]->elements.size()) ||
      e1 >= static_cast<int>(fiber_[1]->elements.size()))
    return false;
  if (!self_) return true;
  // Self-interaction: a source element e0 may use e1 if they share no control point and e0's farthest
  // point is at least the exclusion length from e1 along the fiber.
  const auto& a = fiber_[0]->elements[e0].control_points;
  for (int cp : fiber_[0]->elements[e1].control_points)
    if (std::find(a.begin(), a.end(), cp) != a.end()) return false;
  const auto& s = element_start_[0];
  const double gap = std::max(s[e1] - s[e0 + 1], s[e0] - s[e1 + 1]);
  return gap + (s[e0 + 1] - s[e0]) >= exclusion_;
}

bool BeamBeamInteraction::collect_pairs() {
  // The pairs of the points that may interact: a closest point was found and the lower bound of the gap,
  // axis distance - R_A - R_B, is below the cut-off. The others keep that bound as their gap.
  const double reach = law_->radius_a() + law_->radius_b() + law_->cutoff_gap();
  std::vector<std::pair<int, int>> required;
  for (int p = 0; p < static_cast<int>(passes_.size()); ++p) {
    const int source = passes_[p].source;
    for (std::size_t i = 0; i < quad_[source].size(); ++i) {
      FiberPoint& point = points_[source][i];
      in_pair_[source][i] = point.found && point.distance < reach;
      if (point.found && !in_pair_[source][i]) point.gap = point.distance - law_->radius_a() - law_->radius_b();
      if (!in_pair_[source][i]) continue;
      const int t = target_element_[source][i], e = quad_[source][i].element;
      required.push_back(source == 0 ? std::make_pair(e, t) : std::make_pair(t, e));
    }
  }
  std::sort(required.begin(), required.end());
  required.erase(std::unique(required.begin(), required.end()), required.end());
  bool changed = false;
  for (const auto& key : required)
    if (!std::binary_search(pairs_.begin(), pairs_.end(), key)) changed = true;
  if (changed) {
    // A margin of the target's neighbouring elements (on both fibers) keeps the pattern while closest
    // points slide along the other fiber.
    pairs_.clear();
    for (const auto& [e0, e1] : required)
      for (int d0 = -1; d0 <= 1; ++d0)
        for (int d1 = -1; d1 <= 1; ++d1)
          if ((d0 == 0 || d1 == 0) && keep_pair(e0 + d0, e1 + d1)) pairs_.emplace_back(e0 + d0, e1 + d1);
    pairs_.insert(pairs_.end(), required.begin(), required.end());
    std::sort(pairs_.begin(), pairs_.end());
    pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  }
  pair_points_.assign(pairs_.size(), {});
  for (int p = 0; p < static_cast<int>(passes_.size()); ++p) {
    const int source = passes_[p].source;
    for (int i = 0; i < static_cast<int>(quad_[source].size()); ++i) {
      if (!in_pair_[source][i]) continue;
      const int t = target_element_[source][i], e = quad_[source][i].element;
      const auto key = source == 0 ? std::make_pair(e, t) : std::make_pair(t, e);
      pair_points_[std::lower_bound(pairs_.begin(), pairs_.end(), key) - pairs_.begin()].emplace_back(p, i);
    }
  }
  return changed;
}

std::vector<std::vector<int>> BeamBeamInteraction::element_dofs(const solve::DofMap& dofs) const {
  std::vector<std::vector<int>> out;
  for (const auto& [e0, e1] : pairs_) {
    std::vector<int> d;
    for (int f = 0; f < 2; ++f) {
      const BeamBody& body = *fiber_[f];
      for (int cp : body.elements[f == 0 ? e0 : e1].control_points)
        for (int c = 0; c < 4; ++c) d.push_back(dofs.dof(body.block, cp, c));
    }
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace fibrane::model
