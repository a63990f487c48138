#pragma once
/// Pictures of BARN worlds: a top-down view of the grid, the cylinders, the start pose, the goal
/// and the A* reference path, in the world frame, as PNG, PDF or SVG (image_format.hpp).
///
/// Layout. World x (across the corridor) runs to the right, world y (the driving direction) runs
/// up the image, at one scale for both axes. The view box is the union of
///   - the corridor: x in [-4.5, 0], y in [0, 9.6] m (the outer edges of the containment and
///     field cylinders), and
///   - the goal disc: protocol.goal() +- protocol.success_radius in x and y,
/// grown by a margin of 0.6 m on every side (the title sits in the top margin, the 1 m scale bar
/// in the bottom one). The image size is therefore
///   width  = lround((x_max - x_min + 2 * 0.6) * pixels_per_metre)  [px]
///   height = lround((y_max - y_min + 2 * 0.6) * pixels_per_metre)  [px]
/// e.g. 684 x 1824 px for either preset at 120 px/m (x in [-4.5, 0], y in [0, 14]); in a PDF or
/// SVG, pt instead of px.
/// The view box does not depend on `show_containment` or `show_path`.

#include <filesystem>

#include "barn/core/protocol.hpp"
#include "barn/core/world.hpp"
#include "barn/viz/image_format.hpp"

namespace barn::viz {

/// What to draw and at which scale.
struct RenderOptions {
  double pixels_per_metre = 120.0;  // [px/m] > 0, and at most 32767 px a side (else InputError)
  bool show_containment = true;     // draw the walls behind the field and the start area
  bool show_path = true;            // draw start -> A* path cells (at their centres) -> goal
};

/// Draws the world to `output` in the format of its extension (.png, .pdf, .svg): cells,
/// cylinders, start pose, goal, A* path. The file appears complete or not at all. Throws
/// core::InputError naming the file for an unknown extension, an image size out of range, or a
/// file that cannot be written.
void renderWorld(const core::WorldSpec& world, const core::Protocol& protocol, const std::filesystem::path& output,
                 const RenderOptions& options = {});

}  // namespace barn::viz
