#include "barn/viz/world_render.hpp"

#include <cairo.h>

#include <string>

#include "drawing.hpp"

namespace barn::viz {

// The world layer and the frame (title, scale bar) live in drawing.cpp, shared with the
// trajectory picture of plots.cpp, so both pictures of a world look the same.

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
  detail::drawWorldLayer(cr, world, protocol, options.show_containment,
                         options.show_path ? std::optional<detail::PathStyle>(detail::PathStyle{}) : std::nullopt);
  cairo_restore(cr);
  detail::drawWorldFrame(cr, world, protocol, view, ppm, size.width);
  detail::finishImage(image);
}

}  // namespace barn::viz
