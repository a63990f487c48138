#include "barn/viz/line_plot.hpp"

#include <cairo.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <memory>

#include "barn/core/errors.hpp"
#include "drawing.hpp"
#include "stroke_font.hpp"

namespace barn::viz {
namespace {

struct Rgb {
  double r, g, b;  // [0, 1]
};
// Series colours (blue, orange, green, purple), then the reference lines' grey.
constexpr Rgb kPalette[] = {{0.12, 0.47, 0.71}, {0.95, 0.50, 0.10}, {0.17, 0.63, 0.17}, {0.58, 0.40, 0.74}};
constexpr Rgb kReferenceColour{0.45, 0.45, 0.45};
constexpr Rgb kInk{0.10, 0.10, 0.10};
constexpr Rgb kGrid{0.90, 0.90, 0.90};

// Margins around the plot area and text sizes, in pixels.
constexpr double kLeft = 80.0, kRight = 24.0, kTop = 44.0, kBottom = 58.0;
constexpr double kTitleSize = 18.0, kLabelSize = 14.0, kTickSize = 12.0;

void setColour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

// Tick spacing of 1, 2 or 5 x 10^k giving about `target` intervals over `span`.
double niceStep(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

// Shortest text of a tick value (rounded to the step's precision).
std::string tickText(double value, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, std::abs(value) < 1e-12 * step ? 0.0 : value,
                                    std::chars_format::fixed, decimals);
  return std::string(buffer, result.ptr);
}

}  // namespace

void renderLinePlot(const LinePlot& plot, const std::filesystem::path& output) {
  const std::string where = output.string();
  imageFormatFor(output);  // an unknown extension fails before any drawing
  if (plot.width < 200 || plot.width > 8000 || plot.height < 150 || plot.height > 8000)
    throw core::InputError(where + ": plot size " + std::to_string(plot.width) + " x " + std::to_string(plot.height) +
                           " px is outside 200..8000 x 150..8000");
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = 0.0, y_max = -std::numeric_limits<double>::infinity();
  for (const LineSeries& s : plot.series) {
    if (s.x.size() != s.y.size()) throw core::InputError(where + ": series '" + s.label + "' has x and y of different lengths");
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_min = std::min(x_min, s.x[i]);
      x_max = std::max(x_max, s.x[i]);
      y_min = std::min(y_min, s.y[i]);
      y_max = std::max(y_max, s.y[i]);
    }
  }
  for (const ReferenceLine& r : plot.references) {
    if (std::isfinite(r.y)) {
      y_min = std::min(y_min, r.y);
      y_max = std::max(y_max, r.y);
    }
  }
  if (!std::isfinite(x_min) || !std::isfinite(y_max)) throw core::InputError(where + ": nothing finite to plot");
  if (x_max <= x_min) x_max = x_min + 1.0;
  y_max += 0.05 * (y_max - y_min);
  if (y_max <= y_min) y_max = y_min + 1.0;

  detail::OutputCanvas image = detail::createOutputCanvas(plot.width, plot.height, output);
  cairo_t* cr = image.cr();

  const double left = kLeft, right = plot.width - kRight, top = kTop, bottom = plot.height - kBottom;
  const auto px = [&](double x) { return left + (x - x_min) / (x_max - x_min) * (right - left); };
  const auto py = [&](double y) { return bottom - (y - y_min) / (y_max - y_min) * (bottom - top); };

  // Grid and ticks.
  const double x_step = niceStep(x_max - x_min, 8), y_step = niceStep(y_max - y_min, 6);
  cairo_set_line_width(cr, 1.0);
  for (double x = std::ceil(x_min / x_step) * x_step; x <= x_max + 1e-9 * x_step; x += x_step) {
    setColour(cr, kGrid);
    cairo_move_to(cr, std::round(px(x)) + 0.5, top);
    cairo_line_to(cr, std::round(px(x)) + 0.5, bottom);
    cairo_stroke(cr);
    setColour(cr, kInk);
    const std::string text = tickText(x, x_step);
    detail::drawText(cr, text, px(x) - 0.5 * detail::textWidth(text, kTickSize), bottom + 18.0, kTickSize);
  }
  for (double y = std::ceil(y_min / y_step) * y_step; y <= y_max + 1e-9 * y_step; y += y_step) {
    setColour(cr, kGrid);
    cairo_move_to(cr, left, std::round(py(y)) + 0.5);
    cairo_line_to(cr, right, std::round(py(y)) + 0.5);
    cairo_stroke(cr);
    setColour(cr, kInk);
    const std::string text = tickText(y, y_step);
    detail::drawText(cr, text, left - 8.0 - detail::textWidth(text, kTickSize), py(y) + 0.5 * 0.5 * kTickSize, kTickSize);
  }
  setColour(cr, kInk);
  cairo_rectangle(cr, left + 0.5, top + 0.5, right - left, bottom - top);
  cairo_stroke(cr);

  // Reference lines (dashed), then the series, clipped to the plot area.
  cairo_save(cr);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_clip(cr);
  const double dashes[] = {8.0, 5.0};
  cairo_set_line_width(cr, 2.0);
  for (const ReferenceLine& r : plot.references) {
    setColour(cr, kReferenceColour);
    cairo_set_dash(cr, dashes, 2, 0.0);
    cairo_move_to(cr, left, py(r.y));
    cairo_line_to(cr, right, py(r.y));
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const LineSeries& s = plot.series[k];
    setColour(cr, kPalette[k % std::size(kPalette)]);
    bool pen_down = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        pen_down = false;
        continue;
      }
      if (pen_down) cairo_line_to(cr, px(s.x[i]), py(s.y[i]));
      else cairo_move_to(cr, px(s.x[i]), py(s.y[i]));
      pen_down = true;
    }
    cairo_stroke(cr);
  }
  cairo_restore(cr);

  // Title, axis labels, legend (top right, inside the plot area).
  setColour(cr, kInk);
  detail::drawText(cr, plot.title, left, 0.6 * kTop, kTitleSize);
  detail::drawText(cr, plot.x_label, 0.5 * (left + right) - 0.5 * detail::textWidth(plot.x_label, kLabelSize),
                   plot.height - 12.0, kLabelSize);
  cairo_save(cr);
  cairo_translate(cr, 22.0, 0.5 * (top + bottom) + 0.5 * detail::textWidth(plot.y_label, kLabelSize));
  cairo_rotate(cr, -0.5 * 3.14159265358979323846);
  detail::drawText(cr, plot.y_label, 0.0, 0.0, kLabelSize);
  cairo_restore(cr);
  double legend_width = 0.0;
  for (const LineSeries& s : plot.series) legend_width = std::max(legend_width, detail::textWidth(s.label, kLabelSize));
  for (const ReferenceLine& r : plot.references) legend_width = std::max(legend_width, detail::textWidth(r.label, kLabelSize));
  const double entries = static_cast<double>(plot.series.size() + plot.references.size());
  const double box_x = right - legend_width - 60.0, box_y = top + 10.0;
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_rectangle(cr, box_x, box_y, legend_width + 50.0, 22.0 * entries + 8.0);
  cairo_fill_preserve(cr);
  setColour(cr, kGrid);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  double row = box_y + 20.0;
  const auto legendEntry = [&](const std::string& label, const Rgb& colour, bool dashed) {
    setColour(cr, colour);
    cairo_set_line_width(cr, 2.0);
    if (dashed) cairo_set_dash(cr, dashes, 2, 0.0);
    cairo_move_to(cr, box_x + 8.0, row - 5.0);
    cairo_line_to(cr, box_x + 36.0, row - 5.0);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0.0);
    setColour(cr, kInk);
    detail::drawText(cr, label, box_x + 42.0, row, kLabelSize);
    row += 22.0;
  };
  for (std::size_t k = 0; k < plot.series.size(); ++k) legendEntry(plot.series[k].label, kPalette[k % std::size(kPalette)], false);
  for (const ReferenceLine& r : plot.references) legendEntry(r.label, kReferenceColour, true);

  detail::finishImage(image);
}

}  // namespace barn::viz
