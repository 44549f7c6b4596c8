#pragma once
// Numbers in messages for people: six significant digits ("1e-06", "0.125", "3.5e+47"), never the fixed
// six decimals of std::to_string, which print small step sizes and residuals as 0.000000.
#include <string>

namespace fibrane {

std::string format_number(double value);

}  // namespace fibrane
