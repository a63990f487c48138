#include "barn/viz/plots.hpp"

#include <cairo.h>

#include <algorithm>
#include <utility>
#include <initializer_list>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "barn/core/errors.hpp"
#include "drawing.hpp"
#include "font.hpp"

namespace barn::viz {
namespace {

// A value axis from 0 (or below, for negative values) to y_max, or 5 % above the finite data
// when y_max is 0 (automatic).
std::pair<double, double> valueAxisRange(std::initializer_list<const std::vector<double>*> series, double y_max) {
  double lo = 0.0;
  double top = -std::numeric_limits<double>::infinity();
  for (const std::vector<double>* values : series) {
    for (double v : *values) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      top = std::max(top, v);
    }
  }
  double hi = y_max;
  if (hi == 0.0) hi = std::isfinite(top) ? top + 0.05 * (top - lo) : 1.0;
  if (!(hi > lo)) hi = lo + 1.0;
  return {lo, hi};
}

using detail::centredBaseline;
using detail::xCentredBaseline;
using detail::drawCentred;
using detail::drawRightAligned;
using detail::drawText;
using detail::drawVertical;
using detail::niceStep;
using detail::tickText;
using detail::Rgb;
using detail::setColour;
using detail::textWidth;

// ---------------------------------------------------------------------------
// Style shared by the charts (device pixels)

constexpr Rgb kInk = detail::kInkColour;
constexpr Rgb kMutedInk{0.40, 0.40, 0.40};  // reference-line labels, legend headers
constexpr Rgb kGridLine{0.90, 0.90, 0.90};
constexpr Rgb kMissingFill{0.93, 0.93, 0.93};
constexpr Rgb kMissingHatch{0.70, 0.70, 0.70};
constexpr Rgb kBarColour{0.12, 0.47, 0.71};

// Okabe and Ito's colour-blind-safe qualitative palette (black aside): trajectory states and
// trials, and the outcomes of the score bars.
constexpr Rgb kOrange{0.902, 0.624, 0.000};
constexpr Rgb kSkyBlue{0.337, 0.706, 0.914};
constexpr Rgb kBluishGreen{0.000, 0.620, 0.451};
constexpr Rgb kYellow{0.941, 0.894, 0.259};
constexpr Rgb kBlue{0.000, 0.447, 0.698};
constexpr Rgb kVermillion{0.835, 0.369, 0.000};
constexpr Rgb kReddishPurple{0.800, 0.475, 0.655};

constexpr double kTitleSize = 20.0;  // [px]
constexpr double kLabelSize = 16.0;  // [px] axis labels
constexpr double kTickSize = 14.0;   // [px] heat-map ticks and cell values
constexpr double kSmallSize = 13.0;  // [px] colour bar, bar-chart ticks, legends

/// A title centred over [left, right], kept inside the image's side margins when it is wider.
void drawTitle(cairo_t* cr, const std::string& title, double left, double right, double image_width,
               double baseline) {
  const double width = textWidth(title, kTitleSize);
  const double x =
      std::clamp(0.5 * (left + right - width), 24.0, std::max(24.0, image_width - 24.0 - width));
  setColour(cr, kInk);
  drawText(cr, title, x, baseline, kTitleSize);
}

/// Image side [px] rounded up, or InputError if Cairo cannot make an image that large.
int imageSide(double side, const std::string& what, const std::string& where) {
  if (!(side >= 1.0 && side <= detail::kMaxImageSide)) {
    throw core::InputError(
        where + ": " + what + " of " + detail::formatNumber(side, std::chars_format::fixed, 0) +
        " px is out of range (1 ... " + std::to_string(detail::kMaxImageSide) + " px)");
  }
  return static_cast<int>(std::ceil(side));
}

// ---------------------------------------------------------------------------
// Ticks (all charts)

/// A labelled value on a colour scale.
struct ScaleTick {
  double value;
  std::string text;
};

/// Labels of a colour scale [lo, hi]: multiples of a nice step (1, 2 or 5 x 10^k, about 5
/// intervals) and both ends, so the reader sees where the scale stops. An end that is not a
/// multiple is written with `endText` and pushes out a multiple closer than 0.4 steps to it.
template <class EndText>
std::vector<ScaleTick> scaleTicks(double lo, double hi, const EndText& endText) {
  if (!(hi > lo)) return {{lo, endText(lo)}};
  const double step = niceStep(hi - lo, 5);
  const auto onStep = [&](double v) { return std::abs(v / step - std::round(v / step)) < 1e-6; };
  std::vector<ScaleTick> ticks;
  if (!onStep(lo)) ticks.push_back({lo, endText(lo)});
  for (double k = std::ceil(lo / step - 1e-6); k * step <= hi + 1e-6 * step; k += 1.0) {
    const double v = k * step;
    const bool crowds_lo = !onStep(lo) && v - lo < 0.4 * step;
    const bool crowds_hi = !onStep(hi) && hi - v < 0.4 * step;
    if (!crowds_lo && !crowds_hi) ticks.push_back({v, tickText(v, step)});
  }
  if (!onStep(hi)) ticks.push_back({hi, endText(hi)});
  return ticks;
}

// ---------------------------------------------------------------------------
// Heat map

// Viridis (matplotlib), sampled at 9 evenly spaced points. Linear interpolation between them
// stays within about 1 % of the full 256-entry table, and the map stays perceptually uniform,
// ordered in lightness and readable in grey scale and with colour-vision deficiencies.
constexpr std::array<Rgb, 9> kViridis{{{0.267, 0.005, 0.329},
                                       {0.279, 0.175, 0.483},
                                       {0.230, 0.322, 0.546},
                                       {0.173, 0.448, 0.558},
                                       {0.128, 0.567, 0.551},
                                       {0.153, 0.681, 0.502},
                                       {0.369, 0.789, 0.383},
                                       {0.678, 0.864, 0.190},
                                       {0.993, 0.906, 0.144}}};

Rgb viridis(double t) {
  t = std::clamp(t, 0.0, 1.0) * (kViridis.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(t), kViridis.size() - 2);
  const double f = t - static_cast<double>(i);
  const Rgb& a = kViridis[i];
  const Rgb& b = kViridis[i + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

/// WCAG relative luminance of an sRGB colour, [0, 1].
double luminance(const Rgb& c) {
  const auto linear = [](double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  };
  return 0.2126 * linear(c.r) + 0.7152 * linear(c.g) + 0.0722 * linear(c.b);
}

// Heat-map layout [px]; plots.hpp documents the resulting image size.
constexpr double kCellMinWidth = 80.0;
constexpr double kCellMinHeight = 48.0;
constexpr double kGridMinWidth = 400.0;   // cells grow until the grid is this wide ...
constexpr double kGridMinHeight = 240.0;  // ... and this tall, so a 2 x 2 sweep is not a stamp
constexpr double kCellPadding = 16.0;  // widest text + this = cell width, if over the min
constexpr double kYLabelBand = 40.0;   // left of the y ticks
constexpr double kYTickMinBand = 48.0;
constexpr double kBarBandFixed = 64.0;  // gap 24 + bar 18 + gap 8 + pad 14
constexpr double kBarLabelMinWidth = 56.0;
constexpr double kScaleLabelBand = 26.0;  // gap 8 + the scale label's 13 px glyphs, rotated, + pad
constexpr double kHeatTop = 60.0;
constexpr double kHeatBottom = 76.0;

/// value_format parsed: the text around one printf-style conversion. Parsed rather than handed
/// to snprintf, so a "%s" or "%d" cannot read a double as something else, and to_chars keeps
/// the decimal point a point in every locale.
struct ValueFormat {
  std::string prefix;
  std::string suffix;
  std::chars_format format = std::chars_format::fixed;
  int precision = 6;
  bool plus = false;
  bool upper = false;  // %E, %G
};

std::optional<ValueFormat> parseValueFormat(const std::string& text) {
  ValueFormat parsed;
  bool converted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    std::string& out = converted ? parsed.suffix : parsed.prefix;
    if (text[i] != '%') {
      out += text[i];
      continue;
    }
    if (++i == text.size()) return std::nullopt;
    if (text[i] == '%') {
      out += '%';
      continue;
    }
    if (converted) return std::nullopt;  // a second conversion
    if (text[i] == '+') {
      parsed.plus = true;
      ++i;
    }
    if (i < text.size() && text[i] == '.') {
      parsed.precision = 0;
      std::size_t digits = 0;
      while (++i < text.size() && text[i] >= '0' && text[i] <= '9' && digits < 2) {
        parsed.precision = 10 * parsed.precision + (text[i] - '0');
        ++digits;
      }
    }
    if (i == text.size()) return std::nullopt;
    switch (text[i]) {
      case 'f':
      case 'F':
        parsed.format = std::chars_format::fixed;
        break;
      case 'e':
      case 'E':
        parsed.format = std::chars_format::scientific;
        break;
      case 'g':
      case 'G':
        parsed.format = std::chars_format::general;
        break;
      default:
        return std::nullopt;
    }
    parsed.upper = text[i] == 'E' || text[i] == 'G';
    converted = true;
  }
  if (!converted) return std::nullopt;
  return parsed;
}

std::string formatValue(const ValueFormat& f, double value) {
  std::string number = detail::formatNumber(value, f.format, f.precision);
  if (f.upper) {
    for (char& c : number) c = c == 'e' ? 'E' : c;
  }
  if (f.plus && !std::signbit(value)) number.insert(number.begin(), '+');
  return f.prefix + number + f.suffix;
}

/// Five-pointed star centred on (x, y), outer radius r, filled white and outlined in ink.
void drawStar(cairo_t* cr, double x, double y, double r) {
  for (int k = 0; k < 10; ++k) {
    const double angle = -0.5 * std::numbers::pi + k * std::numbers::pi / 5.0;
    const double radius = k % 2 == 0 ? r : 0.45 * r;
    const double px = x + radius * std::cos(angle);
    const double py = y + radius * std::sin(angle);
    if (k == 0)
      cairo_move_to(cr, px, py);
    else
      cairo_line_to(cr, px, py);
  }
  cairo_close_path(cr);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_fill_preserve(cr);
  setColour(cr, kInk);
  cairo_set_line_width(cr, 1.3);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
  cairo_stroke(cr);
}

/// Light grey with diagonal hatching: the look of a missing value.
void drawMissing(cairo_t* cr, double x, double y, double w, double h) {
  cairo_save(cr);
  cairo_rectangle(cr, x, y, w, h);
  setColour(cr, kMissingFill);
  cairo_fill_preserve(cr);
  cairo_clip(cr);
  const double spacing = 8.0;
  for (double d = -h; d < w; d += spacing) {
    cairo_move_to(cr, x + d, y + h);
    cairo_line_to(cr, x + d + h, y);
  }
  setColour(cr, kMissingHatch);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  cairo_restore(cr);
}

// ---------------------------------------------------------------------------
// Bar chart

constexpr double kBarsMinPlotWidth = 720.0;
constexpr double kBarsPitch = 4.0;  // [px] per bar before the plot grows past the minimum
constexpr double kBarsPlotHeight = 320.0;
constexpr double kBarsLeft = 72.0, kBarsRight = 56.0, kBarsTop = 56.0, kBarsBottom = 72.0;
constexpr double kSubtitleBand = 22.0;    // added above the plot by a subtitle
constexpr double kSubtitleSize = 14.0;
constexpr double kChartLegendRow = 24.0;  // added above the plot per legend row
constexpr double kStripGap = 6.0;          // between the zero line and the outcome strip
constexpr double kStripHeight = 28.0;

/// An outcome as the strip and legend show it: green for success, the palette's red
/// (vermillion) for collision, orange for timeout, reddish purple for error.
struct OutcomeKind {
  const char* name;
  Rgb colour;
  int OutcomeCounts::*member;
  int count(const OutcomeCounts& counts) const { return counts.*member; }
};
constexpr std::array<OutcomeKind, 4> kOutcomeKinds{{{"success", kBluishGreen, &OutcomeCounts::success},
                                                    {"collision", kVermillion, &OutcomeCounts::collision},
                                                    {"timeout", kOrange, &OutcomeCounts::timeout},
                                                    {"error", kReddishPurple, &OutcomeCounts::error}}};

// A legend of small marks and texts in rows above a chart.
enum class LegendMark { Box, Whisker, Header };
struct LegendItem {
  LegendMark mark;
  Rgb colour;
  std::string text;
  double width() const { return (mark == LegendMark::Header ? 0.0 : 18.0) + textWidth(text, kSmallSize); }
};
constexpr double kChartLegendGap = 18.0;

/// The items in rows no wider than `room`.
std::vector<std::vector<const LegendItem*>> legendRows(const std::vector<LegendItem>& items, double room) {
  std::vector<std::vector<const LegendItem*>> rows;
  double used = 0.0;
  for (const LegendItem& item : items) {
    if (rows.empty() || (!rows.back().empty() && used + kChartLegendGap + item.width() > room)) {
      rows.emplace_back();
      used = -kChartLegendGap;
    }
    rows.back().push_back(&item);
    used += kChartLegendGap + item.width();
  }
  return rows;
}

/// Draws legend rows from `left`, the first row's top at `top`.
void drawLegendRows(cairo_t* cr, const std::vector<std::vector<const LegendItem*>>& rows, double left, double top) {
  double y = top + 0.5 * kChartLegendRow;
  for (const std::vector<const LegendItem*>& row : rows) {
    double x = left;
    for (const LegendItem* item : row) {
      if (item->mark == LegendMark::Box) {
        cairo_rectangle(cr, x, y - 6.0, 12.0, 12.0);
        setColour(cr, item->colour);
        cairo_fill(cr);
      } else if (item->mark == LegendMark::Whisker) {
        cairo_move_to(cr, x + 6.5, y - 6.0);
        cairo_line_to(cr, x + 6.5, y + 6.0);
        cairo_move_to(cr, x + 2.5, y - 5.5);
        cairo_line_to(cr, x + 10.5, y - 5.5);
        cairo_move_to(cr, x + 2.5, y + 5.5);
        cairo_line_to(cr, x + 10.5, y + 5.5);
        setColour(cr, item->colour);
        cairo_set_line_width(cr, 1.0);
        cairo_stroke(cr);
      }
      const double text_x = item->mark == LegendMark::Header ? x : x + 18.0;
      setColour(cr, item->mark == LegendMark::Header ? kMutedInk : kInk);
      drawText(cr, item->text, text_x, centredBaseline(y, kSmallSize), kSmallSize);
      x += item->width() + kChartLegendGap;
    }
    y += kChartLegendRow;
  }
}

// Horizontal grid lines and labelled y ticks at a nice step over [lo, hi], between the plot's
// left and right edges; `py` maps a value to its pixel row.
template <class ToPixel>
void drawValueGrid(cairo_t* cr, double lo, double hi, double left, double right, const ToPixel& py) {
  const double step = niceStep(hi - lo, 6);
  cairo_set_line_width(cr, 1.0);
  for (double y = std::ceil(lo / step - 1e-9) * step; y <= hi + 1e-9 * step; y += step) {
    const double yp = std::round(py(y)) + 0.5;
    setColour(cr, kGridLine);
    cairo_move_to(cr, left, yp);
    cairo_line_to(cr, right, yp);
    cairo_stroke(cr);
    setColour(cr, kInk);
    cairo_move_to(cr, left - 5.0, yp);
    cairo_line_to(cr, left, yp);
    cairo_stroke(cr);
    drawRightAligned(cr, tickText(y, step), left - 8.0, centredBaseline(py(y), kSmallSize), kSmallSize);
  }
}

/// Smallest label stride in 1, 2, 5, 10, 20, 25, 50, 100, 200, 250, 500, ... that leaves `gap`
/// px between neighbouring labels up to `label_width` px wide, with bars `pitch` px apart.
std::size_t labelStride(double pitch, double label_width, double gap) {
  const double needed = label_width + gap;  // [px]
  for (std::size_t k : {1, 2, 5}) {
    if (static_cast<double>(k) * pitch >= needed) return k;
  }
  for (std::size_t scale = 1;; scale *= 10) {
    for (std::size_t m : {10, 20, 25, 50}) {
      if (static_cast<double>(m * scale) * pitch >= needed) return m * scale;
    }
  }
}

// ---------------------------------------------------------------------------
// Trajectories

constexpr double kLegendBand = 2.6;         // [m] right of the world picture
constexpr double kTrajectoryWidth = 0.035;  // [m]
constexpr double kLegendText = 0.15;        // [m] font size
constexpr double kLegendRow = 0.30;         // [m] between legend rows
constexpr double kLegendDetailText = 0.12;  // [m] font size of an entry's second line
constexpr double kLegendDetailRow = 0.20;   // [m] from an entry's first line to its second
constexpr double kLegendSwatch = 0.40;      // [m] line length of a legend entry
constexpr Rgb kNoStateColour{0.30, 0.30, 0.30};
constexpr Rgb kCollisionColour{0.86, 0.0, 0.0};

// The state and trial colours: Okabe and Ito's palette without black (the ink) and with
// yellow last (weak on white). Vermillion sits late too: it is the nearest to the obstacles'
// red and the collision marks.
constexpr std::array<Rgb, 7> kStatePalette{{kOrange, kSkyBlue, kBluishGreen, kReddishPurple, kBlue, kVermillion, kYellow}};

// Dash patterns that tell trajectories apart; the colour is taken by the state. [m] on, off
struct DashPattern {
  std::array<double, 4> dashes;
  int count;  // 0 = solid
};
constexpr std::array<DashPattern, 4> kDashPatterns{{{{0.0, 0.0, 0.0, 0.0}, 0},
                                                    {{0.20, 0.10, 0.0, 0.0}, 2},
                                                    {{0.0, 0.09, 0.0, 0.0}, 2},
                                                    {{0.22, 0.09, 0.0, 0.09}, 4}}};

void setDash(cairo_t* cr, const DashPattern& pattern, double offset) {
  cairo_set_dash(cr, pattern.dashes.data(), pattern.count, offset);
}

/// An X of half-size `half`, in the current (world) coordinates, over a white halo.
void drawCollisionMark(cairo_t* cr, double x, double y, double half, double width) {
  cairo_move_to(cr, x - half, y - half);
  cairo_line_to(cr, x + half, y + half);
  cairo_move_to(cr, x - half, y + half);
  cairo_line_to(cr, x + half, y - half);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 2.2 * width);
  cairo_stroke_preserve(cr);
  setColour(cr, kCollisionColour);
  cairo_set_line_width(cr, width);
  cairo_stroke(cr);
}

/// The robot's collision rectangles (robot frame) at `pose`, in world coordinates: a light
/// red fill and a red outline over a white halo, so it reads on cylinders and trajectories.
void drawRobotOutline(cairo_t* cr, const core::Pose2& pose, const std::vector<core::Rect>& rects) {
  if (rects.empty()) return;
  cairo_save(cr);
  cairo_translate(cr, pose.x, pose.y);
  cairo_rotate(cr, pose.yaw);  // y up in world coordinates, so this turns counter-clockwise
  cairo_new_path(cr);
  for (const core::Rect& r : rects) {
    cairo_rectangle(cr, r.min_x, r.min_y, r.max_x - r.min_x, r.max_y - r.min_y);
  }
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
  cairo_set_source_rgba(cr, kCollisionColour.r, kCollisionColour.g, kCollisionColour.b, 0.18);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 0.045);
  cairo_stroke_preserve(cr);
  setColour(cr, kCollisionColour);
  cairo_set_line_width(cr, 0.02);
  cairo_stroke(cr);
  cairo_restore(cr);
}

}  // namespace

// ---------------------------------------------------------------------------
// Heat map

namespace {

/// Rejects a heat map that cannot be drawn (ragged rows, a bad format or scale), naming the file.
ValueFormat checkHeatMap(const HeatMap& map, const std::string& where) {
  const std::size_t rows = map.values.size();
  const std::size_t cols = map.x_ticks.size();
  if (rows == 0) throw core::InputError(where + ": heat map has no rows (values is empty)");
  if (cols == 0) throw core::InputError(where + ": heat map has no columns (x_ticks is empty)");
  if (map.y_ticks.size() != rows) {
    throw core::InputError(where + ": heat map has " + std::to_string(rows) +
                           " rows of values but " + std::to_string(map.y_ticks.size()) +
                           " y_ticks");
  }
  for (std::size_t r = 0; r < rows; ++r) {
    if (map.values[r].size() != cols) {
      throw core::InputError(where + ": heat map row " + std::to_string(r) + " has " +
                             std::to_string(map.values[r].size()) + " values but there are " +
                             std::to_string(cols) + " x_ticks");
    }
  }
  const std::optional<ValueFormat> format = parseValueFormat(map.value_format);
  if (!format) {
    throw core::InputError(where + ": value_format '" + map.value_format +
                           "' must hold one %f, %e or %g conversion (optionally %+.Nf)");
  }
  if (std::isinf(map.scale_min) || std::isinf(map.scale_max) || map.scale_max <= map.scale_min) {
    throw core::InputError(where + ": the colour scale " +
                           detail::formatNumber(map.scale_min, std::chars_format::general, 6) + " ... " +
                           detail::formatNumber(map.scale_max, std::chars_format::general, 6) +
                           " must have finite ends (or NaN for the data's) and a top above its bottom");
  }
  return *format;
}

/// What a heat map's drawing needs to know: its colour scale and where everything goes.
struct HeatMapLayout {
  ValueFormat format;
  std::size_t rows = 0, cols = 0;
  bool any_finite = false;   // some cell has a value
  bool any_missing = false;  // some cell has none
  double best = 0.0;         // the best value (every cell attaining it is marked)
  double lo = 0.0, hi = 0.0; // the colour scale's ends
  std::vector<ScaleTick> scale_ticks;
  double bar_label_width = 0.0;
  double cell_w = 0.0, cell_h = 0.0;
  double gx = 0.0, gy = 0.0;          // top-left corner of the grid
  double grid_w = 0.0, grid_h = 0.0;
  int width = 0, height = 0;          // the image

  Rgb colourOf(double v) const { return viridis(hi > lo ? (v - lo) / (hi - lo) : 0.5); }
  double cellX(std::size_t c) const { return gx + static_cast<double>(c) * cell_w; }
  double cellY(std::size_t r) const { return gy + static_cast<double>(r) * cell_h; }
};

HeatMapLayout layoutHeatMap(const HeatMap& map, const ValueFormat& format, const std::string& where) {
  HeatMapLayout l;
  l.format = format;
  l.rows = map.values.size();
  l.cols = map.x_ticks.size();
  // Range and best value over the finite cells; the colour scale is fixed where the map says.
  double data_lo = std::numeric_limits<double>::infinity();
  double data_hi = -data_lo;
  for (const std::vector<double>& row : map.values) {
    for (double v : row) {
      if (!std::isfinite(v)) continue;
      data_lo = std::min(data_lo, v);
      data_hi = std::max(data_hi, v);
    }
  }
  l.any_finite = std::isfinite(data_lo);
  l.best = map.higher_is_better ? data_hi : data_lo;
  l.lo = std::isnan(map.scale_min) ? data_lo : map.scale_min;
  l.hi = std::isnan(map.scale_max) ? data_hi : map.scale_max;
  const bool any_scale = std::isfinite(l.lo) && std::isfinite(l.hi);
  if (any_scale) l.scale_ticks = scaleTicks(l.lo, l.hi, [&](double v) { return formatValue(format, v); });

  // The widths of the texts decide the cell width and the side bands.
  double widest_cell = 0.0;
  for (const std::string& tick : map.x_ticks)
    widest_cell = std::max(widest_cell, textWidth(tick, kTickSize));
  for (const std::vector<double>& row : map.values) {
    for (double v : row) {
      if (std::isfinite(v))
        widest_cell = std::max(widest_cell, textWidth(formatValue(format, v), kTickSize));
      else
        l.any_missing = true;
    }
  }
  double widest_y_tick = 0.0;
  for (const std::string& tick : map.y_ticks)
    widest_y_tick = std::max(widest_y_tick, textWidth(tick, kTickSize));
  for (const ScaleTick& tick : l.scale_ticks) l.bar_label_width = std::max(l.bar_label_width, textWidth(tick.text, kSmallSize));

  l.cell_w = std::max({kCellMinWidth, widest_cell + kCellPadding, kGridMinWidth / static_cast<double>(l.cols)});
  l.cell_h = std::max(kCellMinHeight, kGridMinHeight / static_cast<double>(l.rows));
  const double left_band = kYLabelBand + std::max(kYTickMinBand, widest_y_tick + 16.0);
  const double right_band = kBarBandFixed + std::max(kBarLabelMinWidth, l.bar_label_width) +
                            (map.scale_label.empty() ? 0.0 : kScaleLabelBand);
  l.grid_w = static_cast<double>(l.cols) * l.cell_w;
  l.grid_h = static_cast<double>(l.rows) * l.cell_h;
  l.width = imageSide(std::max(left_band + l.grid_w + right_band, textWidth(map.title, kTitleSize) + 48.0),
                      "heat map width", where);
  l.height = imageSide(kHeatTop + l.grid_h + kHeatBottom, "heat map height", where);
  l.gx = left_band;
  l.gy = kHeatTop;
  return l;
}

/// Cells, value texts, then thin white separators.
void drawHeatCells(cairo_t* cr, const HeatMap& map, const HeatMapLayout& l) {
  for (std::size_t r = 0; r < l.rows; ++r) {
    for (std::size_t c = 0; c < l.cols; ++c) {
      const double x = l.cellX(c);
      const double y = l.cellY(r);
      const double v = map.values[r][c];
      if (!std::isfinite(v)) {
        drawMissing(cr, x, y, l.cell_w, l.cell_h);
        continue;
      }
      const Rgb colour = l.colourOf(v);
      setColour(cr, colour);
      cairo_rectangle(cr, x, y, l.cell_w, l.cell_h);
      cairo_fill(cr);
      // Black on light cells, white on dark ones: 0.18 is where both contrast ratios match.
      if (luminance(colour) > 0.18)
        cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
      else
        cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
      drawCentred(cr, formatValue(l.format, v), x + 0.5 * l.cell_w,
                  centredBaseline(y + 0.5 * l.cell_h, kTickSize), kTickSize);
    }
  }
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 1.5);
  for (std::size_t c = 1; c < l.cols; ++c) {
    cairo_move_to(cr, l.cellX(c), l.gy);
    cairo_line_to(cr, l.cellX(c), l.gy + l.grid_h);
  }
  for (std::size_t r = 1; r < l.rows; ++r) {
    cairo_move_to(cr, l.gx, l.cellY(r));
    cairo_line_to(cr, l.gx + l.grid_w, l.cellY(r));
  }
  cairo_stroke(cr);
}

/// Best cells (every cell attaining the best value): a thick ink outline inside the cell,
/// lined in white so it also reads on the darkest cells, and a star in the top-right corner.
void drawBestCells(cairo_t* cr, const HeatMap& map, const HeatMapLayout& l) {
  if (!l.any_finite) return;
  for (std::size_t r = 0; r < l.rows; ++r) {
    for (std::size_t c = 0; c < l.cols; ++c) {
      if (map.values[r][c] != l.best) continue;
      const double x = l.cellX(c);
      const double y = l.cellY(r);
      cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
      cairo_rectangle(cr, x + 4.5, y + 4.5, l.cell_w - 9.0, l.cell_h - 9.0);
      cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
      cairo_set_line_width(cr, 1.5);
      cairo_stroke(cr);
      cairo_rectangle(cr, x + 2.0, y + 2.0, l.cell_w - 4.0, l.cell_h - 4.0);
      setColour(cr, kInk);
      cairo_set_line_width(cr, 4.0);
      cairo_stroke(cr);
      drawStar(cr, x + l.cell_w - 14.0, y + 14.0, 6.0);
    }
  }
}

/// Ticks, axis labels and the title.
void drawHeatAxes(cairo_t* cr, const HeatMap& map, const HeatMapLayout& l) {
  setColour(cr, kInk);
  for (std::size_t c = 0; c < l.cols; ++c)
    drawCentred(cr, map.x_ticks[c], l.gx + (static_cast<double>(c) + 0.5) * l.cell_w, l.gy + l.grid_h + 22.0, kTickSize);
  for (std::size_t r = 0; r < l.rows; ++r) {
    drawRightAligned(cr, map.y_ticks[r], l.gx - 10.0,
                     centredBaseline(l.gy + (static_cast<double>(r) + 0.5) * l.cell_h, kTickSize), kTickSize);
  }
  const double x_label_width = textWidth(map.x_label, kLabelSize);
  drawText(cr, map.x_label,
           std::clamp(l.gx + 0.5 * l.grid_w - 0.5 * x_label_width, 8.0, std::max(8.0, l.width - 8.0 - x_label_width)),
           l.gy + l.grid_h + 56.0, kLabelSize);
  drawVertical(cr, map.y_label, 28.0, l.gy + 0.5 * l.grid_h, kLabelSize);
  drawTitle(cr, map.title, l.gx, l.gx + l.grid_w, l.width, 36.0);
}

/// Colour bar: the same anchors as a Cairo gradient (also linear in sRGB), the scale's top at
/// the top, so a fixed scale shows where the data sit within it; below it the key (the
/// best-cell star, and the missing-value look if there is one).
void drawColourBar(cairo_t* cr, const HeatMap& map, const HeatMapLayout& l) {
  const double gy = l.gy, grid_h = l.grid_h;
  const double bx = l.gx + l.grid_w + 24.0, bw = 18.0;
  cairo_pattern_t* gradient = cairo_pattern_create_linear(0.0, gy + grid_h, 0.0, gy);
  for (std::size_t i = 0; i < kViridis.size(); ++i) {
    cairo_pattern_add_color_stop_rgb(gradient, static_cast<double>(i) / (kViridis.size() - 1),
                                     kViridis[i].r, kViridis[i].g, kViridis[i].b);
  }
  cairo_rectangle(cr, bx, gy, bw, grid_h);
  cairo_set_source(cr, gradient);
  cairo_fill(cr);
  cairo_pattern_destroy(gradient);
  setColour(cr, kInk);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, bx + 0.5, gy + 0.5, bw - 1.0, grid_h - 1.0);
  cairo_stroke(cr);
  for (const ScaleTick& tick : l.scale_ticks) {
    // On pixel centres, so the 1 px marks are crisp; the ends half a pixel inside the bar.
    const double t = l.hi > l.lo ? (tick.value - l.lo) / (l.hi - l.lo) : (tick.value >= l.hi ? 1.0 : 0.0);
    const double y = std::clamp(std::floor(gy + grid_h - t * grid_h) + 0.5, gy + 0.5, gy + grid_h - 0.5);
    cairo_move_to(cr, bx + bw, y);
    cairo_line_to(cr, bx + bw + 4.0, y);
    cairo_stroke(cr);
    drawText(cr, tick.text, bx + bw + 8.0, centredBaseline(y, kSmallSize), kSmallSize);
  }
  if (!map.scale_label.empty()) {
    // Along the bar, right of its tick labels; shrunk to the bar's length if it is longer.
    const double room = grid_h;
    const double size = std::min(kSmallSize, kSmallSize * room / std::max(1.0, textWidth(map.scale_label, kSmallSize)));
    setColour(cr, kInk);
    drawVertical(cr, map.scale_label, bx + bw + 8.0 + l.bar_label_width + 10.0 + detail::kCapHeight * size, gy + 0.5 * grid_h, size);
  }
  if (l.any_finite) {
    drawStar(cr, bx + 7.0, gy + grid_h + 17.0, 6.5);
    setColour(cr, kInk);
    drawText(cr, "best", bx + 20.0, centredBaseline(gy + grid_h + 17.0, kSmallSize), kSmallSize);
  }
  if (l.any_missing) {
    drawMissing(cr, bx, gy + grid_h + 33.0, 14.0, 14.0);
    setColour(cr, kInk);
    drawText(cr, "missing", bx + 20.0, centredBaseline(gy + grid_h + 40.0, kSmallSize), kSmallSize);
  }
}

}  // namespace

void renderHeatMap(const HeatMap& map, const std::filesystem::path& output) {
  const std::string where = output.string();
  imageFormatFor(output);  // an unknown extension fails before any drawing
  const HeatMapLayout layout = layoutHeatMap(map, checkHeatMap(map, where), where);
  detail::OutputCanvas image = detail::createOutputCanvas(layout.width, layout.height, output);
  cairo_t* cr = image.cr();
  drawHeatCells(cr, map, layout);
  drawBestCells(cr, map, layout);
  drawHeatAxes(cr, map, layout);
  drawColourBar(cr, map, layout);
  detail::finishImage(image);
}

// ---------------------------------------------------------------------------
// Bar chart

namespace {

// ---- Pieces shared by the per-world charts (bars, pairs) ----

/// One column per world across a plot; `plot_top`/`plot_bottom` bound the value axis [lo, hi].
struct WorldColumns {
  double left = 0.0, right = 0.0, plot_top = 0.0, plot_bottom = 0.0;
  double lo = 0.0, hi = 1.0;
  double pitch = 0.0;  // [px] per world
  double py(double y) const { return plot_bottom - (y - lo) / (hi - lo) * (plot_bottom - plot_top); }
  double centre(std::size_t i) const { return left + (static_cast<double>(i) + 0.5) * pitch; }
};

bool onAxis(double y, const WorldColumns& c) { return std::isfinite(y) && y >= c.lo && y <= c.hi; }

constexpr double kReferenceDashes[] = {6.0, 4.0};

/// The reference lines across the plot, dashed, in `colour`.
void drawReferenceLines(cairo_t* cr, const std::vector<double>& lines, const WorldColumns& c, const Rgb& colour) {
  cairo_set_dash(cr, kReferenceDashes, 2, 0.0);
  cairo_set_line_width(cr, 1.5);
  setColour(cr, colour);
  for (double y : lines) {
    if (!onAxis(y, c)) continue;
    cairo_move_to(cr, c.left, c.py(y));
    cairo_line_to(cr, c.right, c.py(y));
  }
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0.0);
}

/// Each reference line's value right of the plot, in the current colour.
void drawReferenceValues(cairo_t* cr, const std::vector<double>& lines, const WorldColumns& c) {
  for (double y : lines) {
    if (!onAxis(y, c)) continue;
    drawText(cr, detail::formatNumber(y, std::chars_format::general, 4), c.right + 6.0,
             centredBaseline(c.py(y), kSmallSize), kSmallSize);
  }
}

/// The left spine and the zero line (or the axis end nearest zero).
void drawSpineAndZeroLine(cairo_t* cr, const WorldColumns& c) {
  const double base = c.py(std::clamp(0.0, c.lo, c.hi));
  setColour(cr, kInk);
  cairo_set_line_width(cr, 1.0);
  cairo_move_to(cr, c.left - 0.5, c.plot_top);
  cairo_line_to(cr, c.left - 0.5, c.plot_bottom);
  cairo_move_to(cr, c.left - 0.5, std::round(base) + 0.5);
  cairo_line_to(cr, c.right, std::round(base) + 0.5);
  cairo_stroke(cr);
}

/// World labels every few columns (as many as fit) hanging from `top`, then the x axis label.
void drawWorldLabels(cairo_t* cr, const std::vector<std::string>& labels, const std::string& x_label,
                     const WorldColumns& c, double top, int width) {
  double widest = 0.0;
  for (const std::string& label : labels) widest = std::max(widest, textWidth(label, kSmallSize));
  const std::size_t stride = labelStride(c.pitch, widest, 8.0);
  for (std::size_t i = 0; i < labels.size(); i += stride) {
    const double x = std::round(c.centre(i)) + 0.5;
    cairo_move_to(cr, x, top);
    cairo_line_to(cr, x, top + 4.0);
    cairo_stroke(cr);
    drawCentred(cr, labels[i], x, top + 20.0, kSmallSize);
  }
  const double x_label_width = textWidth(x_label, kLabelSize);
  drawText(cr, x_label,
           std::clamp(0.5 * (c.left + c.right - x_label_width), 8.0, std::max(8.0, width - 8.0 - x_label_width)),
           top + 54.0, kLabelSize);
}

// ---- Bar chart ----

void checkWorldBars(const WorldBars& bars, const std::string& where) {
  const std::size_t n = bars.values.size();
  if (bars.labels.size() != n) {
    throw core::InputError(where + ": bar chart has " + std::to_string(bars.labels.size()) +
                           " labels but " + std::to_string(n) + " values");
  }
  if (n == 0)
    throw core::InputError(where + ": bar chart has no bars (labels and values are empty)");
  if (!std::isfinite(bars.y_max) || bars.y_max < 0.0) {
    throw core::InputError(where + ": y_max must be 0 (automatic) or positive (got " +
                           detail::formatNumber(bars.y_max, std::chars_format::general, 6) + ")");
  }
  if ((!bars.low.empty() || !bars.high.empty()) && (bars.low.size() != n || bars.high.size() != n)) {
    throw core::InputError(where + ": bar chart has " + std::to_string(n) + " values but " +
                           std::to_string(bars.low.size()) + " low and " + std::to_string(bars.high.size()) +
                           " high whisker ends (both empty or one per bar)");
  }
  if (!bars.outcomes.empty() && bars.outcomes.size() != n) {
    throw core::InputError(where + ": bar chart has " + std::to_string(n) + " values but " +
                           std::to_string(bars.outcomes.size()) + " outcome counts (empty or one per bar)");
  }
}

/// The legend: the bar, the whiskers, then the outcomes that occur (success always).
std::vector<LegendItem> worldBarsLegend(const WorldBars& bars) {
  const bool whiskers = !bars.low.empty(), strip = !bars.outcomes.empty();
  std::vector<LegendItem> legend;
  if (whiskers || strip) legend.push_back({LegendMark::Box, kBarColour, bars.y_label});
  if (whiskers) legend.push_back({LegendMark::Whisker, kInk, bars.whisker_label});
  if (strip) {
    OutcomeCounts all;
    for (const OutcomeCounts& o : bars.outcomes) {
      all.success += o.success;
      all.collision += o.collision;
      all.timeout += o.timeout;
      all.error += o.error;
    }
    legend.push_back({LegendMark::Header, kMutedInk, "trials:"});
    for (std::size_t k = 0; k < kOutcomeKinds.size(); ++k) {
      if (k == 0 || kOutcomeKinds[k].count(all) > 0)
        legend.push_back({LegendMark::Box, kOutcomeKinds[k].colour, kOutcomeKinds[k].name});
    }
  }
  return legend;
}

/// Bar edges on whole pixels keep 300 narrow bars crisp; a 20 % gap separates them once they
/// are 4 px apart. The outcome strip uses the same columns.
struct BarEdges {
  const WorldColumns& c;
  double gap;
  explicit BarEdges(const WorldColumns& columns)
      : c(columns), gap(columns.pitch >= 4.0 ? std::max(1.0, 0.2 * columns.pitch) : 0.0) {}
  double x0(std::size_t i) const { return std::round(c.left + static_cast<double>(i) * c.pitch + 0.5 * gap); }
  double x1(std::size_t i) const {
    return std::max(x0(i) + 1.0, std::round(c.left + static_cast<double>(i + 1) * c.pitch - 0.5 * gap));
  }
};

/// Bars, whiskers and the reference lines over them, clipped to the plot area (a fixed y_max
/// may cut the tallest); the lines' values right of the plot.
void drawBarsAndWhiskers(cairo_t* cr, const WorldBars& bars, const WorldColumns& c) {
  const BarEdges edges(c);
  cairo_save(cr);
  cairo_rectangle(cr, c.left, c.plot_top, c.right - c.left, c.plot_bottom - c.plot_top);
  cairo_clip(cr);
  const double base = c.py(std::clamp(0.0, c.lo, c.hi));
  for (std::size_t i = 0; i < bars.values.size(); ++i) {
    const double v = bars.values[i];
    if (!std::isfinite(v)) continue;
    const double y0 = std::round(std::clamp(c.py(v), c.plot_top - 1.0, c.plot_bottom + 1.0));
    cairo_rectangle(cr, edges.x0(i), std::min(y0, std::round(base)), edges.x1(i) - edges.x0(i), std::abs(std::round(base) - y0));
  }
  setColour(cr, kBarColour);
  cairo_fill(cr);
  if (!bars.low.empty()) {
    // A 1 px line on the bar's centre, capped 0.6 of the bar wide once bars are 4 px apart.
    const double cap = c.pitch >= 4.0 ? std::min(4.0, 0.3 * c.pitch) : 0.0;
    for (std::size_t i = 0; i < bars.values.size(); ++i) {
      if (!std::isfinite(bars.low[i]) || !std::isfinite(bars.high[i])) continue;
      const double x = std::floor(0.5 * (edges.x0(i) + edges.x1(i))) + 0.5;
      const double y_low = std::round(c.py(bars.low[i])) + 0.5, y_high = std::round(c.py(bars.high[i])) + 0.5;
      detail::addIntervalBar(cr, x, y_low, y_high, cap);
    }
    setColour(cr, kInk);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
  }
  drawReferenceLines(cr, bars.reference_lines, c, kInk);
  cairo_restore(cr);
  setColour(cr, kMutedInk);
  drawReferenceValues(cr, bars.reference_lines, c);
}

/// Outcome strip between `top` and `bottom`: per world the shares of its trials stacked from
/// the bottom in the legend's order, so each column reads as the world's outcome mix whatever
/// its score (a world whose trials all collided has no bar, but a full vermillion column).
void drawOutcomeStrip(cairo_t* cr, const WorldBars& bars, const WorldColumns& c, double top, double bottom) {
  const BarEdges edges(c);
  for (std::size_t i = 0; i < bars.outcomes.size(); ++i) {
    const int total = bars.outcomes[i].total();
    if (total <= 0) continue;
    int below = 0;
    for (const OutcomeKind& kind : kOutcomeKinds) {
      const int count = kind.count(bars.outcomes[i]);
      if (count == 0) continue;
      const auto edge = [&](int trials) { return std::round(bottom - (bottom - top) * trials / total); };
      cairo_rectangle(cr, edges.x0(i), edge(below + count), edges.x1(i) - edges.x0(i), edge(below) - edge(below + count));
      setColour(cr, kind.colour);
      cairo_fill(cr);
      below += count;
    }
  }
  setColour(cr, kMutedInk);
  drawRightAligned(cr, "trials", c.left - 8.0, centredBaseline(0.5 * (top + bottom), kSmallSize), kSmallSize);
}

// ---- Paired per-world comparison ----

constexpr Rgb kPairColourA{0.12, 0.47, 0.71};  // blue
constexpr Rgb kPairColourB{0.90, 0.45, 0.05};  // orange
constexpr Rgb kPairJoin{0.70, 0.70, 0.70};

void checkPairedWorlds(const PairedWorlds& pairs, const std::string& where) {
  const std::size_t n = pairs.labels.size();
  if (pairs.a.size() != n || pairs.b.size() != n) {
    throw core::InputError(where + ": paired chart has " + std::to_string(n) + " labels, " +
                           std::to_string(pairs.a.size()) + " A values and " +
                           std::to_string(pairs.b.size()) + " B values");
  }
  if (n == 0) throw core::InputError(where + ": paired chart has no worlds");
  if (!std::isfinite(pairs.y_max) || pairs.y_max < 0.0) {
    throw core::InputError(where + ": y_max must be 0 (automatic) or positive (got " +
                           detail::formatNumber(pairs.y_max, std::chars_format::general, 6) + ")");
  }
}

/// A's marker (a dot) and B's (a diamond) as paths.
void addDotA(cairo_t* cr, double x, double y, double radius) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, x, y, radius, 0.0, 2.0 * std::numbers::pi);
}
void addDiamondB(cairo_t* cr, double x, double y, double radius) {
  const double r = 1.25 * radius;
  cairo_move_to(cr, x, y - r);
  cairo_line_to(cr, x + r, y);
  cairo_line_to(cr, x, y + r);
  cairo_line_to(cr, x - r, y);
  cairo_close_path(cr);
}

/// Per world a grey join between A and B, then B's diamond and A's dot, clipped to the plot
/// area (a fixed y_max may cut the largest).
void drawPairMarkers(cairo_t* cr, const PairedWorlds& pairs, const WorldColumns& c, double radius) {
  cairo_save(cr);
  cairo_rectangle(cr, c.left, c.plot_top - radius - 2.0, c.right - c.left, c.plot_bottom - c.plot_top + 2.0 * radius + 4.0);
  cairo_clip(cr);
  setColour(cr, kPairJoin);
  cairo_set_line_width(cr, std::max(1.0, 0.4 * radius));
  for (std::size_t i = 0; i < pairs.labels.size(); ++i) {
    if (!std::isfinite(pairs.a[i]) || !std::isfinite(pairs.b[i])) continue;
    cairo_move_to(cr, c.centre(i), c.py(pairs.a[i]));
    cairo_line_to(cr, c.centre(i), c.py(pairs.b[i]));
  }
  cairo_stroke(cr);
  cairo_set_line_width(cr, 1.0);
  // A marker filled in its series' colour and outlined in white, so overlapping ones stay apart.
  const auto mark = [&](auto add_path, double x, double y, Rgb colour) {
    add_path(cr, x, y, radius);
    setColour(cr, colour);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_stroke(cr);
  };
  for (std::size_t i = 0; i < pairs.labels.size(); ++i) {
    if (std::isfinite(pairs.b[i])) mark(addDiamondB, c.centre(i), c.py(pairs.b[i]), kPairColourB);
    if (std::isfinite(pairs.a[i])) mark(addDotA, c.centre(i), c.py(pairs.a[i]), kPairColourA);
  }
  cairo_restore(cr);
}

/// The legend above the plot, right-aligned: marker and name of A, then of B.
void drawPairLegend(cairo_t* cr, const std::string& legend_a, const std::string& legend_b, double legend_width,
                    const WorldColumns& c, double radius) {
  const double legend_y = 58.0;
  double x = std::max(c.left, c.right - legend_width);
  // One entry: the series' marker, then its name; returns where the next entry starts.
  const auto entry = [&](auto add_path, Rgb colour, const std::string& name) {
    add_path(cr, x + 6.0, legend_y, radius);
    setColour(cr, colour);
    cairo_fill(cr);
    setColour(cr, kInk);
    drawText(cr, name, x + 16.0, centredBaseline(legend_y, kSmallSize), kSmallSize);
    return x + 16.0 + textWidth(name, kSmallSize) + 28.0;
  };
  x = entry(addDotA, kPairColourA, legend_a);
  entry(addDiamondB, kPairColourB, legend_b);
}

}  // namespace

void renderWorldBars(const WorldBars& bars, const std::filesystem::path& output) {
  const std::string where = output.string();
  imageFormatFor(output);  // an unknown extension fails before any drawing
  checkWorldBars(bars, where);
  const std::size_t n = bars.values.size();
  const bool strip = !bars.outcomes.empty();

  // y range: from 0 (or below, for negative values) to y_max or 5 % above the data.
  WorldColumns c;
  std::tie(c.lo, c.hi) = valueAxisRange({&bars.values, &bars.high, &bars.reference_lines}, bars.y_max);
  const std::vector<LegendItem> legend = worldBarsLegend(bars);
  const double plot_w = std::max(kBarsMinPlotWidth, kBarsPitch * static_cast<double>(n));
  const std::vector<std::vector<const LegendItem*>> legend_rows = legendRows(legend, plot_w);
  const double legend_top = kBarsTop + (bars.subtitle.empty() ? 0.0 : kSubtitleBand);
  c.left = kBarsLeft;
  c.right = kBarsLeft + plot_w;
  c.plot_top = legend_top + kChartLegendRow * static_cast<double>(legend_rows.size());
  c.plot_bottom = c.plot_top + kBarsPlotHeight;
  c.pitch = plot_w / static_cast<double>(n);
  const double strip_top = c.plot_bottom + kStripGap, strip_bottom = strip_top + kStripHeight;
  const double ticks_top = strip ? strip_bottom : c.plot_bottom;  // x tick labels hang from here
  const int width = imageSide(std::max({plot_w + kBarsLeft + kBarsRight, textWidth(bars.title, kTitleSize) + 48.0,
                                        textWidth(bars.subtitle, kSubtitleSize) + 48.0}),
                              "bar chart width", where);
  const int height = static_cast<int>(ticks_top + kBarsBottom);
  detail::OutputCanvas image = detail::createOutputCanvas(width, height, output);
  cairo_t* cr = image.cr();

  drawValueGrid(cr, c.lo, c.hi, c.left, c.right, [&](double y) { return c.py(y); });
  drawBarsAndWhiskers(cr, bars, c);
  if (strip) drawOutcomeStrip(cr, bars, c, strip_top, strip_bottom);
  drawSpineAndZeroLine(cr, c);
  drawWorldLabels(cr, bars.labels, bars.x_label, c, ticks_top, width);
  drawVertical(cr, bars.y_label, 22.0, 0.5 * (c.plot_top + c.plot_bottom), kLabelSize);
  drawTitle(cr, bars.title, c.left, c.right, width, 34.0);
  if (!bars.subtitle.empty()) {
    const double w = textWidth(bars.subtitle, kSubtitleSize);
    setColour(cr, kMutedInk);
    drawText(cr, bars.subtitle, std::clamp(0.5 * (c.left + c.right - w), 24.0, std::max(24.0, width - 24.0 - w)),
             34.0 + kSubtitleBand, kSubtitleSize);
  }
  drawLegendRows(cr, legend_rows, c.left, legend_top - 6.0);
  detail::finishImage(image);
}

void renderPairedWorlds(const PairedWorlds& pairs, const std::filesystem::path& output) {
  const std::string where = output.string();
  checkPairedWorlds(pairs, where);
  imageFormatFor(output);  // an unknown extension fails before any drawing
  const std::size_t n = pairs.labels.size();
  constexpr double kLeft = 72.0, kRight = 56.0, kTop = 80.0, kBottom = 72.0;
  constexpr double kPlotHeight = 320.0;

  WorldColumns c;
  std::tie(c.lo, c.hi) = valueAxisRange({&pairs.a, &pairs.b, &pairs.reference_lines}, pairs.y_max);
  const std::string legend_a = "A: " + pairs.label_a;
  const std::string legend_b = "B: " + pairs.label_b;
  const double legend_width = textWidth(legend_a, kSmallSize) + textWidth(legend_b, kSmallSize) + 2 * 22.0 + 28.0;
  const double plot_w = std::max(720.0, 10.0 * static_cast<double>(n));
  const int width = imageSide(std::max({plot_w + kLeft + kRight, textWidth(pairs.title, kTitleSize) + 48.0,
                                        legend_width + 96.0}),
                              "paired chart width", where);
  const int height = static_cast<int>(kTop + kPlotHeight + kBottom);
  detail::OutputCanvas image = detail::createOutputCanvas(width, height, output);
  cairo_t* cr = image.cr();
  c.left = kLeft;
  c.right = kLeft + plot_w;
  c.plot_top = kTop;
  c.plot_bottom = kTop + kPlotHeight;
  c.pitch = plot_w / static_cast<double>(n);

  drawValueGrid(cr, c.lo, c.hi, c.left, c.right, [&](double y) { return c.py(y); });
  // Reference lines under the markers, labelled right of the plot.
  drawReferenceLines(cr, pairs.reference_lines, c, kMutedInk);
  drawReferenceValues(cr, pairs.reference_lines, c);
  const double radius = std::clamp(0.3 * c.pitch, 2.5, 5.0);
  drawPairMarkers(cr, pairs, c, radius);
  drawSpineAndZeroLine(cr, c);
  drawWorldLabels(cr, pairs.labels, pairs.x_label, c, c.plot_bottom, width);
  drawVertical(cr, pairs.y_label, 22.0, 0.5 * (c.plot_top + c.plot_bottom), kLabelSize);
  drawTitle(cr, pairs.title, c.left, c.right, width, 30.0);
  drawPairLegend(cr, legend_a, legend_b, legend_width, c, radius);
  detail::finishImage(image);
}

// ---------------------------------------------------------------------------
// Trajectories on a world: the world layer (drawing.cpp, as renderWorld draws it), the
// trajectories over it, and the legend built as a list of rows, then drawn.

namespace {

/// How trajectories are coloured and dashed: by state (a colour per state, in order of first
/// appearance; a dash pattern per trajectory) or by trial (a palette colour per trajectory,
/// dashed once the colours repeat).
struct TrajectoryPalette {
  bool by_trial = false;
  std::vector<std::string> states;  // in order of first appearance across all trajectories
  bool any_stateless = false;       // some point has no state
  bool any_collision = false;       // some trajectory touched a cylinder
  bool any_outline = false;         // some trajectory has a pose of contact and an outline to draw

  Rgb stateColour(const std::string& state) const {
    if (state.empty()) return kNoStateColour;
    const auto it = std::find(states.begin(), states.end(), state);
    return kStatePalette[static_cast<std::size_t>(it - states.begin()) % kStatePalette.size()];
  }
  Rgb trialColour(std::size_t t) const { return kStatePalette[t % kStatePalette.size()]; }
  const DashPattern& trialDash(std::size_t t) const {
    return kDashPatterns[(by_trial ? t / kStatePalette.size() : t) % kDashPatterns.size()];
  }
};

TrajectoryPalette trajectoryPalette(const std::vector<TrajectoryOverlay>& trajectories, const TrajectoryStyle& style) {
  TrajectoryPalette palette;
  palette.by_trial = style.colouring == TrajectoryColouring::ByTrial;
  for (const TrajectoryOverlay& trajectory : trajectories) {
    palette.any_collision = palette.any_collision || trajectory.collided;
    palette.any_outline = palette.any_outline || (trajectory.collision_pose && !style.robot_outline.empty());
    for (const TrajectoryPoint& point : trajectory.points) {
      if (point.state.empty())
        palette.any_stateless = true;
      else if (std::find(palette.states.begin(), palette.states.end(), point.state) == palette.states.end())
        palette.states.push_back(point.state);
    }
  }
  return palette;
}

// The A* path on a trajectory picture: thin and light (a reference, not the subject).
const detail::PathStyle kReferencePathStyle{{0.55, 0.80, 0.60}, 0.02, 0.0};

/// The trajectories, clipped to the map, then the robot's outline and the mark at each contact,
/// in world coordinates (the caller has set worldToPixels). Each run of points in one colour is
/// one polyline that ends at the next run's first point, so the line has no gaps and dashes
/// run on across runs.
void drawTrajectories(cairo_t* cr, const std::vector<TrajectoryOverlay>& trajectories, const TrajectoryPalette& palette,
                      const detail::ViewBox& view, const std::vector<core::Rect>& robot_outline) {
  cairo_rectangle(cr, view.min_x - detail::kWorldMargin, view.min_y - detail::kWorldMargin,
                  view.max_x - view.min_x + 2.0 * detail::kWorldMargin,
                  view.max_y - view.min_y + 2.0 * detail::kWorldMargin);
  cairo_clip(cr);
  cairo_set_line_width(cr, kTrajectoryWidth);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  const auto finite = [](const TrajectoryPoint& p) {
    return std::isfinite(p.x) && std::isfinite(p.y);
  };
  for (std::size_t t = 0; t < trajectories.size(); ++t) {
    const std::vector<TrajectoryPoint>& points = trajectories[t].points;
    const auto sameRun = [&](const TrajectoryPoint& a, const TrajectoryPoint& b) {
      return palette.by_trial || a.state == b.state;
    };
    double travelled = 0.0;  // [m] along the drawn line, for the dash phase
    std::size_t i = 0;
    while (i < points.size()) {
      if (!finite(points[i])) {
        ++i;
        continue;
      }
      std::size_t end = i + 1;  // one past the run's last point
      while (end < points.size() && finite(points[end]) && sameRun(points[end], points[i])) ++end;
      const std::size_t last = end < points.size() && finite(points[end]) ? end : end - 1;
      setDash(cr, palette.trialDash(t), travelled);
      cairo_move_to(cr, points[i].x, points[i].y);
      for (std::size_t k = i + 1; k <= last; ++k) {
        cairo_line_to(cr, points[k].x, points[k].y);
        travelled += std::hypot(points[k].x - points[k - 1].x, points[k].y - points[k - 1].y);
      }
      if (last == i) cairo_line_to(cr, points[i].x, points[i].y);  // a lone point: a round dot
      setColour(cr, palette.by_trial ? palette.trialColour(t) : palette.stateColour(points[i].state));
      cairo_stroke(cr);
      i = end;
    }
  }
  // The robot where it touched, over the trajectories: its collision outline at the pose of
  // contact, so the reader sees which part hit.
  for (const TrajectoryOverlay& trajectory : trajectories) {
    if (trajectory.collision_pose) drawRobotOutline(cr, *trajectory.collision_pose, robot_outline);
  }
  for (const TrajectoryOverlay& trajectory : trajectories) {
    if (trajectory.collided && std::isfinite(trajectory.collision_x) && std::isfinite(trajectory.collision_y)) {
      drawCollisionMark(cr, trajectory.collision_x, trajectory.collision_y, 0.13, 0.045);
    }
  }
}

/// What stands left of a legend row's text.
enum class LegendSwatch {
  None,           // a group's header: muted text at the swatch's place
  Line,           // a trajectory's or state's line, in its colour and dash pattern
  ReferencePath,  // the A* path's thin line
  CollisionMark,  // the mark at a contact
  RobotOutline,   // a small robot, heading right
};

/// One row of the trajectory legend.
struct TrajectoryLegendRow {
  LegendSwatch swatch = LegendSwatch::Line;
  std::string text;
  Rgb colour{};                                // of a Line swatch
  const DashPattern* dash = &kDashPatterns[0];  // of a Line swatch
  std::string detail;                          // a second, smaller line under the text; none if empty
  bool group_end = false;                      // half a row of space follows
};

/// The legend's rows: the states (by state), the trajectories (when there is more than one,
/// they are coloured by trial, or one has a label), the A* path, and the contact marks shown.
std::vector<TrajectoryLegendRow> buildTrajectoryLegend(const std::vector<TrajectoryOverlay>& trajectories,
                                                       const TrajectoryPalette& palette) {
  std::vector<TrajectoryLegendRow> rows;
  if (!palette.by_trial && !palette.states.empty()) {
    rows.push_back({LegendSwatch::None, "state", {}, nullptr, {}, false});
    for (const std::string& state : palette.states)
      rows.push_back({LegendSwatch::Line, state, palette.stateColour(state), &kDashPatterns[0], {}, false});
    if (palette.any_stateless)
      rows.push_back({LegendSwatch::Line, "no state", kNoStateColour, &kDashPatterns[0], {}, false});
    rows.back().group_end = true;
  }
  const bool label_trajectories =
      palette.by_trial || trajectories.size() > 1 ||
      std::any_of(trajectories.begin(), trajectories.end(),
                  [](const TrajectoryOverlay& t) { return !t.label.empty() || !t.detail.empty(); });
  if (label_trajectories && !trajectories.empty()) {
    rows.push_back({LegendSwatch::None, "trajectory", {}, nullptr, {}, false});
    for (std::size_t t = 0; t < trajectories.size(); ++t) {
      rows.push_back({LegendSwatch::Line,
                      trajectories[t].label.empty() ? "trajectory " + std::to_string(t) : trajectories[t].label,
                      palette.by_trial ? palette.trialColour(t) : kInk, &palette.trialDash(t), trajectories[t].detail,
                      false});
    }
    rows.back().group_end = true;
  }
  rows.push_back({LegendSwatch::ReferencePath, "A* path", {}, nullptr, {}, false});
  if (palette.any_collision) rows.push_back({LegendSwatch::CollisionMark, "cylinder hit", {}, nullptr, {}, false});
  if (palette.any_outline) rows.push_back({LegendSwatch::RobotOutline, "robot at contact", {}, nullptr, {}, false});
  return rows;
}

/// Draws the legend's rows in the band right of the map, which starts at `x0` [px] and ends at
/// `right` [px], in device pixels; sizes scale with the map (`ppm`). A text too long for the
/// band is shrunk to fit.
void drawTrajectoryLegend(cairo_t* cr, const std::vector<TrajectoryLegendRow>& rows, double x0, double right,
                          double ppm, const std::vector<core::Rect>& robot_outline) {
  const double text_size = kLegendText * ppm;
  const double detail_size = kLegendDetailText * ppm;
  const double row = kLegendRow * ppm;
  const double text_x = x0 + (kLegendSwatch + 0.12) * ppm;
  const double text_room = right - text_x - 0.15 * ppm;
  double y = (detail::kWorldMargin + 0.2) * ppm;
  const auto entryText = [&](const std::string& text, const Rgb& colour, double font_size, double at_y) {
    const double fit =
        std::min(font_size, font_size * text_room / std::max(1e-9, textWidth(text, font_size)));
    setColour(cr, colour);
    drawText(cr, text, text_x, xCentredBaseline(at_y, fit), fit);
  };
  for (const TrajectoryLegendRow& r : rows) {
    switch (r.swatch) {
      case LegendSwatch::None:
        setColour(cr, kMutedInk);
        drawText(cr, r.text, x0, xCentredBaseline(y, text_size), text_size);
        break;
      case LegendSwatch::Line: {
        cairo_move_to(cr, x0, y);
        cairo_line_to(cr, x0 + kLegendSwatch * ppm, y);
        setColour(cr, r.colour);
        cairo_set_line_width(cr, kTrajectoryWidth * ppm);
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
        std::array<double, 4> dashes = r.dash->dashes;
        for (double& d : dashes) d *= ppm;
        cairo_set_dash(cr, dashes.data(), r.dash->count, 0.0);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
        break;
      }
      case LegendSwatch::ReferencePath:
        cairo_move_to(cr, x0, y);
        cairo_line_to(cr, x0 + kLegendSwatch * ppm, y);
        setColour(cr, kReferencePathStyle.colour);
        cairo_set_line_width(cr, kReferencePathStyle.width * ppm);
        cairo_stroke(cr);
        break;
      case LegendSwatch::CollisionMark:
        cairo_save(cr);
        cairo_translate(cr, x0 + 0.5 * kLegendSwatch * ppm, y);
        cairo_scale(cr, ppm, ppm);
        drawCollisionMark(cr, 0.0, 0.0, 0.09, 0.045);
        cairo_restore(cr);
        break;
      case LegendSwatch::RobotOutline:
        // y flipped back to the world's up.
        cairo_save(cr);
        cairo_translate(cr, x0 + 0.5 * kLegendSwatch * ppm, y);
        cairo_scale(cr, 0.7 * ppm, -0.7 * ppm);
        drawRobotOutline(cr, core::Pose2{}, robot_outline);
        cairo_restore(cr);
        break;
    }
    if (r.swatch != LegendSwatch::None) entryText(r.text, kInk, text_size, y);
    if (!r.detail.empty()) {
      y += kLegendDetailRow * ppm;
      entryText(r.detail, kMutedInk, detail_size, y);
    }
    y += row;
    if (r.group_end) y += 0.5 * row;
  }
}

}  // namespace

void renderTrajectories(const core::WorldSpec& world, const core::Protocol& protocol,
                        const std::vector<TrajectoryOverlay>& trajectories, const std::filesystem::path& output,
                        const TrajectoryStyle& style) {
  const std::string where = output.string();
  imageFormatFor(output);  // an unknown extension fails before any drawing
  const double ppm = style.pixels_per_metre;
  const detail::ViewBox view = detail::viewBox(protocol);
  const detail::ImageSize size = detail::worldImageSize(view, ppm, kLegendBand, where);
  const double map_width_px = (view.max_x - view.min_x + 2.0 * detail::kWorldMargin) * ppm;
  const TrajectoryPalette palette = trajectoryPalette(trajectories, style);

  detail::OutputCanvas image = detail::createOutputCanvas(size.width, size.height, output);
  cairo_t* cr = image.cr();
  const cairo_matrix_t world_to_px = detail::worldToPixels(view, ppm);
  cairo_save(cr);
  cairo_set_matrix(cr, &world_to_px);
  detail::drawWorldLayer(cr, world, protocol, true, kReferencePathStyle);
  drawTrajectories(cr, trajectories, palette, view, style.robot_outline);
  cairo_restore(cr);
  detail::drawWorldFrame(cr, world, protocol, view, ppm, map_width_px);
  drawTrajectoryLegend(cr, buildTrajectoryLegend(trajectories, palette), map_width_px, size.width, ppm,
                       style.robot_outline);
  detail::finishImage(image);
}

}  // namespace barn::viz
