#pragma once
/// A small line plot (PNG, PDF or SVG by the output's extension; image_format.hpp): a few series
/// of (x, y) points, optionally with markers and interval bars, and dashed horizontal reference
/// lines, with axes, ticks and a legend above the plot (e.g. training loss curves, a sweep's
/// score against its parameter).
///
/// The y axis runs from y_min to y_max where they are set, else from 0 (or the smallest value,
/// if negative) to 5 % above the largest value of any series, interval or reference line. The x
/// axis spans the series' x range (and the x ticks', if given); with x ticks or markers it is
/// widened so the outermost points and their bars stay inside. Text is set in DejaVu Sans
/// (Debian's fonts-dejavu-core; InputError naming the font file if it is missing).

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "barn/viz/image_format.hpp"

namespace barn::viz {

struct LineSeries {
  std::string label;      // legend text ("": not in the legend)
  std::vector<double> x;  // same length as y
  std::vector<double> y;  // non-finite points break the line
  // An interval per point, drawn as a capped vertical bar (e.g. a 95 % confidence interval);
  // both empty, or both as long as y. A non-finite end draws no bar at that point.
  std::vector<double> low;
  std::vector<double> high;
  bool markers = false;  // a dot at every point
};

struct ReferenceLine {
  std::string label;  // legend text ("": not in the legend)
  double y = 0.0;     // drawn dashed across the plot
};

/// A labelled position on the x axis.
struct AxisTick {
  double x = 0.0;
  std::string text;
};

struct LinePlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<LineSeries> series;        // drawn in order, colours from a fixed palette
  std::vector<ReferenceLine> references;
  std::vector<AxisTick> x_ticks;  // where the x axis is labelled; empty = multiples of a nice step
  double y_min = std::numeric_limits<double>::quiet_NaN();  // fixed bottom of the y axis; NaN = automatic
  double y_max = std::numeric_limits<double>::quiet_NaN();  // fixed top; NaN = automatic
  int width = 900;   // [px] 200..8000
  int height = 560;  // [px] 150..8000
};

/// Draws the plot to `output`; the file appears complete or not at all. The legend is a row
/// (or rows, if it is wider than the plot) of entries between the title and the plot, so it
/// never covers a point. InputError naming the file if the extension is unknown, the size is
/// out of range, a series has x, y, low and high of mismatched lengths, a fixed y end is
/// infinite or y_max <= y_min, there is nothing finite to draw, or the file cannot be written.
void renderLinePlot(const LinePlot& plot, const std::filesystem::path& output);

/// Several plots stacked top to bottom in one image, each drawn as renderLinePlot draws it
/// alone (e.g. one panel per quantity over a shared time axis). renderLinePlot's InputErrors
/// for each plot, and for no plots, plots of different widths or more than 8000 px in all.
void renderLinePlots(const std::vector<LinePlot>& plots, const std::filesystem::path& output);

}  // namespace barn::viz
