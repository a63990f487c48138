#pragma once
// Test fixture for controllers that run an LfLH policy: a policy with a fixed output.

#include <memory>

#include "barn/learning/policy.hpp"
#include "scan_fixtures.hpp"

namespace barn::controllers {

/// A policy that always says (v, w): zero weights, the output bias (v, w).
inline std::shared_ptr<const learning::Policy> constantPolicy(double v, double w) {
  learning::PolicyInfo info;
  info.hidden = 4;
  info.name = "constant";
  learning::MlpParameters<float> weights = learning::MlpParameters<float>::zeros(722, 4, 2);
  weights.b3 << static_cast<float>(v), static_cast<float>(w);
  return std::make_shared<const learning::Policy>(info, weights);
}

}  // namespace barn::controllers
