#pragma once
/// Tables describing a world set: means per generator parameter set.

#include <string>
#include <vector>

#include "barn/core/world.hpp"

namespace barn::report {

/// One row per (fill_pct, smooth_iter) in order of first appearance: world count, mean
/// filled-cell fraction, mean path cells, mean reference length [m] and OT [s] (barn2023),
/// and the mean of each raw metric; a last row over the whole set.
std::string parameterSetTable(const std::vector<core::WorldSpec>& worlds);

}  // namespace barn::report
