#pragma once
// Test helper shared by the planner tests: a costmap drawn as a picture.

#include <string>
#include <vector>

#include "barn/nav/costmap.hpp"

namespace barn::nav {

// A costmap of 1 m cells built from a picture: '#' lethal, '.' free.
// Row 0 of the picture is the top (largest y).
inline Costmap pictureMap(const std::vector<std::string>& rows) {
  CostmapConfig c;
  c.resolution = 1.0;
  c.width = static_cast<double>(rows.front().size());
  c.height = static_cast<double>(rows.size());
  c.origin_x = 0.0;
  c.origin_y = 0.0;
  c.inflation_radius = 0.0;
  Costmap map(c, 0.0);
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t col = 0; col < rows[r].size(); ++col)
      if (rows[r][col] == '#')
        map.markObstacle({static_cast<double>(col) + 0.5, static_cast<double>(rows.size() - 1 - r) + 0.5});
  map.update();
  return map;
}

}  // namespace barn::nav
