#include "barn/viz/world_render.hpp"

#include <cairo.h>

#include <string>

#include "drawing.hpp"

namespace barn::viz {

// The layers, the view box and the title live in drawing.cpp, shared with the trajectory
// overlay of plots.cpp, so both pictures of a world look the same.

void renderWorld(const core::WorldSpec& world, const core::Protocol& protocol, const std::filesystem::path& output,
                 const RenderOptions& options) {
  const std::string where = output.string();
  imageFormatFor(output);  // an unknown extension fails before anything else
  const double ppm = options.pixels_per_metre;
  const detail::ViewBox view = detail::viewBox(protocol);
  const detail::ImageSize size = detail::worldImageSize(view, ppm, 0.0, where);
  detail::OutputCanvas image = detail::createOutputCanvas(size.width, size.height, output);
  cairo_t* cr = image.cr();

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
  detail::finishImage(image);
}

}  // namespace barn::viz
