#include "barn/viz/line_plot.hpp"

#include <cairo.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>

#include "barn/core/errors.hpp"
#include "drawing.hpp"
#include "font.hpp"

namespace barn::viz {
namespace {

using detail::Rgb;
using detail::setColour;

// Series colours (blue, orange, green, purple), then the reference lines' grey.
constexpr Rgb kPalette[] = {{0.12, 0.47, 0.71}, {0.95, 0.50, 0.10}, {0.17, 0.63, 0.17}, {0.58, 0.40, 0.74}};
constexpr Rgb kReferenceColour{0.45, 0.45, 0.45};
constexpr Rgb kInk = detail::kInkColour;
constexpr Rgb kGrid{0.90, 0.90, 0.90};

// Margins around the plot area, legend rows and text sizes, in pixels.
constexpr double kLeft = 80.0, kRight = 24.0, kTitleBand = 44.0, kBottom = 58.0;
constexpr double kLegendRow = 20.0, kLegendSwatch = 28.0, kLegendGap = 22.0;
constexpr double kTitleSize = 18.0, kLabelSize = 14.0, kTickSize = 12.0;
constexpr double kMarkerRadius = 4.0;
constexpr double kCapHalfWidth = 5.0;  // of an interval bar's caps

const Rgb& seriesColour(std::size_t k) { return kPalette[k % std::size(kPalette)]; }

std::string lengthsText(const LineSeries& s) {
  return std::to_string(s.x.size()) + " x, " + std::to_string(s.y.size()) + " y, " + std::to_string(s.low.size()) +
         " low, " + std::to_string(s.high.size()) + " high";
}

/// A dot with a white rim, so overlapping markers stay apart.
void drawMarker(cairo_t* cr, double x, double y, const Rgb& colour) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, x, y, kMarkerRadius, 0.0, 2.0 * std::numbers::pi);
  setColour(cr, colour);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

/// A vertical bar from y0 to y1 at x with short caps; on a pixel centre, so it is crisp.
void drawIntervalBar(cairo_t* cr, double x, double y0, double y1, const Rgb& colour) {
  detail::addIntervalBar(cr, std::floor(x) + 0.5, y0, y1, kCapHalfWidth);
  setColour(cr, colour);
  cairo_set_line_width(cr, 1.5);
  cairo_stroke(cr);
}

/// One legend entry: what it shows and how wide it is.
struct LegendEntry {
  std::string label;
  Rgb colour;
  bool dashed = false;
  bool marker = false;
  bool interval = false;
  double width() const { return kLegendSwatch + 6.0 + detail::textWidth(label, kLabelSize); }
};

}  // namespace

namespace {

/// The axes' data ranges, padded as the plot draws them.
struct PlotRanges {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
};

/// Ranges over every finite point, interval end, reference line and x tick; throws if a series'
/// columns differ in length or nothing is finite.
PlotRanges plotRanges(const LinePlot& plot, const std::string& where) {
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_lo = 0.0, y_hi = -std::numeric_limits<double>::infinity();
  bool any_marker = false;
  const auto takeY = [&](double y) {
    if (!std::isfinite(y)) return;
    y_lo = std::min(y_lo, y);
    y_hi = std::max(y_hi, y);
  };
  for (const LineSeries& s : plot.series) {
    const bool intervals = !s.low.empty() || !s.high.empty();
    if (s.x.size() != s.y.size() || (intervals && (s.low.size() != s.y.size() || s.high.size() != s.y.size())))
      throw core::InputError(where + ": series '" + s.label + "' has x, y, low and high of different lengths (" +
                             lengthsText(s) + "; low and high are both empty or as long as y)");
    any_marker = any_marker || s.markers || intervals;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_min = std::min(x_min, s.x[i]);
      x_max = std::max(x_max, s.x[i]);
      takeY(s.y[i]);
      if (intervals) {
        takeY(s.low[i]);
        takeY(s.high[i]);
      }
    }
  }
  for (const ReferenceLine& r : plot.references) takeY(r.y);
  if (!std::isfinite(x_min) || !std::isfinite(y_hi)) throw core::InputError(where + ": nothing finite to plot");
  for (const AxisTick& tick : plot.x_ticks) {
    if (!std::isfinite(tick.x)) continue;
    x_min = std::min(x_min, tick.x);
    x_max = std::max(x_max, tick.x);
  }
  // Room beside the outermost points: half a tick spacing on a ticked axis (as a category axis
  // has), 5 % with markers, none for a plain curve (a loss curve starts at the first epoch).
  double x_pad = 0.0;
  if (!plot.x_ticks.empty())
    x_pad = x_max > x_min ? 0.5 * (x_max - x_min) / std::max<double>(1.0, static_cast<double>(plot.x_ticks.size()) - 1.0) : 0.5;
  else if (any_marker)
    x_pad = x_max > x_min ? 0.05 * (x_max - x_min) : 0.5;
  PlotRanges r;
  r.x_min = x_min - x_pad;
  r.x_max = x_max + x_pad;
  if (r.x_max <= r.x_min) r.x_max = r.x_min + 1.0;
  r.y_min = std::isnan(plot.y_min) ? y_lo : plot.y_min;
  r.y_max = std::isnan(plot.y_max) ? y_hi + 0.05 * (y_hi - y_lo) : plot.y_max;
  if (std::isnan(plot.y_min) && r.y_min >= r.y_max) r.y_min = r.y_max - 1.0;
  if (r.y_max <= r.y_min) r.y_max = r.y_min + 1.0;
  return r;
}

using LegendRows = std::vector<std::vector<const LegendEntry*>>;

/// The series' then the reference lines' legend entries; one without a label has none.
std::vector<LegendEntry> legendEntries(const LinePlot& plot) {
  std::vector<LegendEntry> entries;
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const LineSeries& s = plot.series[k];
    if (!s.label.empty()) entries.push_back({s.label, seriesColour(k), false, s.markers, !s.low.empty()});
  }
  for (const ReferenceLine& r : plot.references)
    if (!r.label.empty()) entries.push_back({r.label, kReferenceColour, true, false, false});
  return entries;
}

/// The entries in rows, each at most `width` pixels wide.
LegendRows legendRows(const std::vector<LegendEntry>& entries, double width) {
  LegendRows rows(1);
  double row_width = 0.0;
  for (const LegendEntry& entry : entries) {
    const double w = entry.width() + (rows.back().empty() ? 0.0 : kLegendGap);
    if (!rows.back().empty() && row_width + w > width) {
      rows.emplace_back();
      row_width = 0.0;
    }
    row_width += rows.back().empty() ? entry.width() : w;
    rows.back().push_back(&entry);
  }
  return rows;
}

/// The plot area [px] and the data ranges it shows.
struct PlotFrame {
  double left = 0.0, right = 0.0, top = 0.0, bottom = 0.0;
  PlotRanges data;
  double px(double x) const { return left + (x - data.x_min) / (data.x_max - data.x_min) * (right - left); }
  double py(double y) const { return bottom - (y - data.y_min) / (data.y_max - data.y_min) * (bottom - top); }
};

constexpr double kDashes[] = {8.0, 5.0};

/// Grid lines, tick labels (an x label that would overlap the previous one is left out) and
/// the frame.
void drawGrid(cairo_t* cr, const PlotFrame& f, const std::vector<AxisTick>& given_x_ticks) {
  std::vector<AxisTick> x_ticks = given_x_ticks;
  if (x_ticks.empty()) {
    const double x_step = detail::niceStep(f.data.x_max - f.data.x_min, 8);
    for (double x = std::ceil(f.data.x_min / x_step - 1e-9) * x_step; x <= f.data.x_max + 1e-9 * x_step; x += x_step)
      x_ticks.push_back({x, detail::tickText(x, x_step)});
  }
  cairo_set_line_width(cr, 1.0);
  double last_label_right = -std::numeric_limits<double>::infinity();
  for (const AxisTick& tick : x_ticks) {
    if (!std::isfinite(tick.x)) continue;
    const double x = std::round(f.px(tick.x)) + 0.5;
    setColour(cr, kGrid);
    cairo_move_to(cr, x, f.top);
    cairo_line_to(cr, x, f.bottom);
    cairo_stroke(cr);
    const double w = detail::textWidth(tick.text, kTickSize);
    if (x - 0.5 * w < last_label_right + 6.0) continue;  // the grid line stays
    setColour(cr, kInk);
    detail::drawCentred(cr, tick.text, x, f.bottom + 18.0, kTickSize);
    last_label_right = x + 0.5 * w;
  }
  const double y_step = detail::niceStep(f.data.y_max - f.data.y_min, 6);
  for (double y = std::ceil(f.data.y_min / y_step - 1e-9) * y_step; y <= f.data.y_max + 1e-9 * y_step; y += y_step) {
    setColour(cr, kGrid);
    cairo_move_to(cr, f.left, std::round(f.py(y)) + 0.5);
    cairo_line_to(cr, f.right, std::round(f.py(y)) + 0.5);
    cairo_stroke(cr);
    setColour(cr, kInk);
    detail::drawRightAligned(cr, detail::tickText(y, y_step), f.left - 8.0, detail::centredBaseline(f.py(y), kTickSize),
                             kTickSize);
  }
  setColour(cr, kInk);
  cairo_rectangle(cr, f.left + 0.5, f.top + 0.5, f.right - f.left, f.bottom - f.top);
  cairo_stroke(cr);
}

/// Reference lines (dashed), then each series' intervals, line and markers; clipped to the plot,
/// with room above and below for a marker or cap on the axis's end (a rate of 0 or 1).
void drawData(cairo_t* cr, const PlotFrame& f, const LinePlot& plot) {
  cairo_save(cr);
  const double overhang = kMarkerRadius + 2.0;
  cairo_rectangle(cr, f.left, f.top - overhang, f.right - f.left, f.bottom - f.top + 2.0 * overhang);
  cairo_clip(cr);
  cairo_set_line_width(cr, 2.0);
  for (const ReferenceLine& r : plot.references) {
    if (!std::isfinite(r.y)) continue;
    setColour(cr, kReferenceColour);
    cairo_set_dash(cr, kDashes, 2, 0.0);
    cairo_move_to(cr, f.left, f.py(r.y));
    cairo_line_to(cr, f.right, f.py(r.y));
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const LineSeries& s = plot.series[k];
    const auto finite = [&](std::size_t i) { return std::isfinite(s.x[i]) && std::isfinite(s.y[i]); };
    for (std::size_t i = 0; i < s.low.size(); ++i) {
      if (finite(i) && std::isfinite(s.low[i]) && std::isfinite(s.high[i]))
        drawIntervalBar(cr, f.px(s.x[i]), f.py(s.low[i]), f.py(s.high[i]), seriesColour(k));
    }
    setColour(cr, seriesColour(k));
    cairo_set_line_width(cr, 2.0);
    bool pen_down = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!finite(i)) {
        pen_down = false;
        continue;
      }
      if (pen_down) cairo_line_to(cr, f.px(s.x[i]), f.py(s.y[i]));
      else cairo_move_to(cr, f.px(s.x[i]), f.py(s.y[i]));
      pen_down = true;
    }
    cairo_stroke(cr);
    if (!s.markers) continue;
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (finite(i)) drawMarker(cr, f.px(s.x[i]), f.py(s.y[i]), seriesColour(k));
  }
  cairo_restore(cr);
}

/// The legend rows under the title band, from `left`.
void drawLegend(cairo_t* cr, const LegendRows& rows, double left) {
  double row_y = kTitleBand + 0.5 * kLegendRow;
  for (const std::vector<const LegendEntry*>& row : rows) {
    double x = left;
    for (const LegendEntry* entry : row) {
      const double mid = x + 0.5 * kLegendSwatch;
      if (entry->interval) drawIntervalBar(cr, mid, row_y - 7.0, row_y + 7.0, entry->colour);
      setColour(cr, entry->colour);
      cairo_set_line_width(cr, 2.0);
      if (entry->dashed) cairo_set_dash(cr, kDashes, 2, 0.0);
      cairo_move_to(cr, x, row_y);
      cairo_line_to(cr, x + kLegendSwatch, row_y);
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0.0);
      if (entry->marker) drawMarker(cr, mid, row_y, entry->colour);
      setColour(cr, kInk);
      detail::drawText(cr, entry->label, x + kLegendSwatch + 6.0, detail::xCentredBaseline(row_y, kLabelSize),
                       kLabelSize);
      x += entry->width() + kLegendGap;
    }
    row_y += kLegendRow;
  }
}

}  // namespace

namespace {

/// A plot checked and laid out: its frame and legend rows (the rows point into `entries`).
struct PlotLayout {
  PlotFrame frame;
  std::vector<LegendEntry> entries;
  LegendRows rows;
};

/// Checks `plot` (renderLinePlot's InputErrors, `where` naming the file) and lays it out.
std::unique_ptr<PlotLayout> layOut(const LinePlot& plot, const std::string& where) {
  if (plot.width < 200 || plot.width > 8000 || plot.height < 150 || plot.height > 8000)
    throw core::InputError(where + ": plot size " + std::to_string(plot.width) + " x " + std::to_string(plot.height) +
                           " px is outside 200..8000 x 150..8000");
  if (std::isinf(plot.y_min) || std::isinf(plot.y_max) || plot.y_max <= plot.y_min)
    throw core::InputError(where + ": the fixed y range " + detail::formatNumber(plot.y_min, std::chars_format::general, 6) +
                           " ... " + detail::formatNumber(plot.y_max, std::chars_format::general, 6) +
                           " must have finite ends (NaN = automatic) and a top above its bottom");
  auto layout = std::make_unique<PlotLayout>();
  PlotFrame& frame = layout->frame;
  frame.data = plotRanges(plot, where);
  frame.left = kLeft;
  frame.right = plot.width - kRight;
  layout->entries = legendEntries(plot);
  layout->rows = legendRows(layout->entries, frame.right - frame.left);
  const double legend_height = layout->entries.empty() ? 0.0 : kLegendRow * static_cast<double>(layout->rows.size()) + 6.0;
  frame.top = kTitleBand + legend_height;
  frame.bottom = plot.height - kBottom;
  if (frame.bottom - frame.top < 40.0)
    throw core::InputError(where + ": a " + std::to_string(plot.height) + " px tall plot leaves no room below its " +
                           std::to_string(layout->rows.size()) + " legend rows");
  return layout;
}

/// Draws a laid-out plot with its top-left corner at the context's origin.
void drawPlot(cairo_t* cr, const LinePlot& plot, const PlotLayout& layout) {
  const PlotFrame& frame = layout.frame;
  drawGrid(cr, frame, plot.x_ticks);
  drawData(cr, frame, plot);
  setColour(cr, kInk);
  detail::drawText(cr, plot.title, frame.left, 0.6 * kTitleBand, kTitleSize);
  detail::drawCentred(cr, plot.x_label, 0.5 * (frame.left + frame.right), plot.height - 12.0, kLabelSize);
  detail::drawVertical(cr, plot.y_label, 22.0, 0.5 * (frame.top + frame.bottom), kLabelSize);
  drawLegend(cr, layout.rows, frame.left);
}

}  // namespace

void renderLinePlot(const LinePlot& plot, const std::filesystem::path& output) {
  const std::string where = output.string();
  imageFormatFor(output);  // an unknown extension fails before any drawing
  const std::unique_ptr<PlotLayout> layout = layOut(plot, where);
  detail::OutputCanvas image = detail::createOutputCanvas(plot.width, plot.height, output);
  drawPlot(image.cr(), plot, *layout);
  detail::finishImage(image);
}

void renderLinePlots(const std::vector<LinePlot>& plots, const std::filesystem::path& output) {
  const std::string where = output.string();
  imageFormatFor(output);
  if (plots.empty()) throw core::InputError(where + ": no plots to draw");
  std::vector<std::unique_ptr<PlotLayout>> layouts;
  int height = 0;
  for (const LinePlot& plot : plots) {
    if (plot.width != plots.front().width)
      throw core::InputError(where + ": stacked plots must be equally wide (" + std::to_string(plot.width) + " px and " +
                             std::to_string(plots.front().width) + " px)");
    layouts.push_back(layOut(plot, where));
    height += plot.height;
  }
  if (height > 8000) throw core::InputError(where + ": the stacked plots are " + std::to_string(height) + " px tall (at most 8000)");
  detail::OutputCanvas image = detail::createOutputCanvas(plots.front().width, height, output);
  cairo_t* cr = image.cr();
  double top = 0.0;
  for (std::size_t i = 0; i < plots.size(); ++i) {
    cairo_save(cr);
    cairo_translate(cr, 0.0, top);
    drawPlot(cr, plots[i], *layouts[i]);
    cairo_restore(cr);
    top += plots[i].height;
  }
  detail::finishImage(image);
}

}  // namespace barn::viz
