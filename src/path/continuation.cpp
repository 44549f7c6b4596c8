#include "path/continuation.hpp"

namespace fibrane::solve {

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::reached_end: return "reached_end";
    case Outcome::stopped: return "stopped";
    case Outcome::limit_point: return "limit_point";
    case Outcome::max_steps: return "max_steps";
    case Outcome::failed: return "failed";
    case Outcome::interrupted: return "interrupted";
  }
  return "unknown";
}

}  // namespace fibrane::solve
