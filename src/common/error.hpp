#pragma once
// Errors that reach the user. InputError is bad input (exit code 2); anything else is a bug or a
// numerical failure (exit code 1). Messages name the file, the key and what was expected.
#include <stdexcept>
#include <string>

namespace fibrane {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fibrane
