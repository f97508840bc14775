#pragma once
// Errors at a boundary (file, device, config, wire) carry what went wrong and where, e.g.
// "imu.csv line 812: timestamp goes backwards by 5 ms". Numerical trouble inside the estimator
// is a tracking state, never an exception.

#include <stdexcept>
#include <string>

namespace vifusion {

/// Bad input or an unusable environment, reported with enough context for a person to act on.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace vifusion
