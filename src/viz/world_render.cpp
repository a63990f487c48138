#include "barn/viz/world_render.hpp"

#include <cairo.h>

#include <string>

#include "drawing.hpp"

namespace barn::viz {

// The layers, the view box and the title live in drawing.cpp, shared with the trajectory
// overlay of plots.cpp, so both pictures of a world look the same.

void renderWorldPng(const core::WorldSpec& world, const core::Protocol& protocol,
                    const std::filesystem::path& png_path, const RenderOptions& options) {
  const std::string where = png_path.string();
  const double ppm = options.pixels_per_metre;
  const detail::ViewBox view = detail::viewBox(protocol);
  const detail::ImageSize size = detail::worldImageSize(view, ppm, 0.0, where);
  const detail::Canvas canvas = detail::createCanvas(size.width, size.height, where);
  cairo_t* cr = canvas.cr();

  const cairo_matrix_t world_to_px = detail::worldToPixels(view, ppm);
  cairo_save(cr);
  cairo_set_matrix(cr, &world_to_px);
  detail::drawOccupiedCells(cr, world.grid);
  detail::drawCylinders(cr, world.grid, options.show_containment);
  if (options.show_path) detail::drawPath(cr, world.path, protocol, detail::PathStyle{});
  detail::drawGoal(cr, protocol);
  detail::drawStartPose(cr, protocol);
  cairo_restore(cr);

  detail::drawWorldTitle(cr, detail::worldTitle(world, protocol), ppm, size.width);
  // The scale bar sits in the bottom margin, left-aligned with the view box.
  detail::drawScaleBar(cr, detail::kWorldMargin * ppm,
                       (view.max_y - view.min_y + 1.5 * detail::kWorldMargin) * ppm, ppm);
  detail::writePng(canvas, where);
}

}  // namespace barn::viz
