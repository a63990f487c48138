#pragma once
/// A small line plot (PNG, PDF or SVG by the output's extension; image_format.hpp): a few series of (x, y) points and dashed horizontal reference
/// lines, with axes, ticks and a legend (e.g. training loss curves).
///
/// The y axis runs from 0 (or the smallest value, if negative) to 5 % above the largest value of
/// any series or reference line; the x axis spans the series' x range. Text uses the built-in
/// stroke font (digits, lower-case letters, ". - +"), so labels should be lower-case.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/viz/image_format.hpp"

namespace barn::viz {

struct LineSeries {
  std::string label;      // legend text
  std::vector<double> x;  // same length as y
  std::vector<double> y;
};

struct ReferenceLine {
  std::string label;  // legend text
  double y = 0.0;     // drawn dashed across the plot
};

struct LinePlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<LineSeries> series;        // drawn in order, colours from a fixed palette
  std::vector<ReferenceLine> references;
  int width = 900;   // [px] 200..8000
  int height = 560;  // [px] 150..8000
};

/// Draws the plot to `output`; the file appears complete or not at all. InputError naming the
/// file if the extension is unknown, the size is out of range, a series has x and y of
/// different lengths, there is nothing finite to draw, or the file cannot be written.
void renderLinePlot(const LinePlot& plot, const std::filesystem::path& output);

}  // namespace barn::viz
