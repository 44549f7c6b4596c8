#pragma once
// The spline layer's quadrature is the project's Gauss-Legendre rule (src/common/gauss_legendre.hpp).
#include "common/gauss_legendre.hpp"

namespace fibrane::spline {

using ::fibrane::gauss_legendre;
using ::fibrane::QuadratureRule;

}  // namespace fibrane::spline
