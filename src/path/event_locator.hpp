#pragma once
// Locating a model's events in load stepping (NonlinearSystem::event_margins): the load t at which an
// event's margin g crosses 0 (a beam point's relative curvature reaching the soft minimum's threshold).
// The model changes after the converged step at which an event's margin is <= 0 first; this class shapes
// the steps so that such a step is at most `tolerance` long, so that each change happens at the same state,
// to the tolerance, whatever the steps.
//
// Each event's crossing is estimated from its own margins: by regula falsi between the last converged
// state (g > 0) and a withdrawn attempt past it (bisection where the last state has no margin for it), or
// else by extrapolating g linearly through the last two converged states. An event that has happened
// (NaN at the last converged state) no longer counts, though the withdrawn attempt's margin for it
// stays negative.
// - Before a step: where the earliest estimate lies within the step, the step ends half a tolerance, and
//   at least kEarly of the way, before it; where it lies within a tolerance, the step is one tolerance long.
// - After a converged attempt: one in which an event crossed in a step longer than the tolerance is
//   withdrawn and bounds the bracket.
// Where the near end of a bracket moves twice in a row, its far end's margins are halved (Illinois),
// which keeps the estimates from creeping along a curved g.
#include <vector>

#include "path/continuation.hpp"

namespace fibrane::solve {

/// The event location of one load-stepping run; its state carries across a restart (save, restore).
class EventLocator {
 public:
  /// `tolerance`: how far from its crossing (in t) an event may happen; 0 switches location off.
  explicit EventLocator(double tolerance = 0) : tolerance_(tolerance) {}

  /// How far from its crossing an event may happen (0: location off).
  double tolerance() const { return tolerance_; }
  /// A run from t with nothing known.
  void start(double t);
  /// The step to try from t (the last converged state) instead of the planned `dt`.
  double step(double t, double dt) const;
  /// After an attempt from t converged at t_new with margins g: true if it is to be withdrawn (an event
  /// crossed in a step longer than the tolerance); it then bounds the bracket.
  bool withdraw(double t, double t_new, const std::vector<double>& g);
  /// Whether location is on and an event crosses in the step to a converged state with margins g (a
  /// margin <= 0 that was > 0, or unknown, at the last converged state).
  bool located(const std::vector<double>& g) const;
  /// After the step to t is accepted: `g_next` the margins after the system's accept() (NaN for events
  /// that have happened).
  void accepted(double t, const std::vector<double>& g_next);

  void save(MethodState& s) const;
  // The state saved at t; without its keys (an older checkpoint) nothing is known but t.
  void restore(const MethodState& s, double t);

 private:
  double tolerance_;
  double t_last_ = 0, t_before_ = 0, t_far_ = 0;
  std::vector<double> g_last_, g_before_, g_far_;  // margins at those; empty: none known
  int near_moves_ = 0;                             // steps accepted in a row inside the bracket
  bool crossed(const std::vector<double>& g) const;
  // The earliest estimated crossing after the last converged state; NaN where none is expected.
  double earliest() const;
};

}  // namespace fibrane::solve
