#include "common/format.hpp"

#include <cstdio>

namespace fibrane {

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

}  // namespace fibrane
