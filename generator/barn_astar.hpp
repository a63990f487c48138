#pragma once
/// BARN's A* on the C-space grid (GEN gen_world_ca.py, AStarSearch), quirks included.
///
/// The original search is not a textbook A*, and the dataset's paths depend on every quirk:
/// - 8-connected moves, but after the first move only the current direction and its two
///   45-degree neighbours; the current direction is read from the node's parent when the node
///   is popped (so a re-parented node turns from its new parent);
/// - a diagonal move is refused only when both orthogonal side cells are blocked;
/// - the closed set and the open-list membership test compare positions only;
/// - a wall penalty 5 / d (d = distance to the nearest blocked cell, d <= 2) is added to the
///   priority of the child, never to g;
/// - a newly inserted node gets priority g + penalty with no heuristic, while a node re-parented
///   to a strictly lower g gets g + h + penalty (h = Euclidean distance to the goal);
/// - the open list is popped at its first strictly smallest priority (insertion order breaks ties);
/// - the returned path starts with the start cell twice.
/// These rules reproduce every path_N.npy of the BARN dataset.

#include <optional>
#include <vector>

#include "barn/core/grid.hpp"

namespace barn::generator {

/// The path from start to goal (start cell duplicated, as BARN stores it), or nullopt if the
/// quirky search finds none. `cspace` holds 1 for blocked cells.
std::optional<std::vector<core::Cell>> barnAStar(const core::Grid& cspace, core::Cell start, core::Cell goal);

}  // namespace barn::generator
