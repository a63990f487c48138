#pragma once
/// Figures for papers and reports: a heat map of a 2-parameter sweep, a per-world bar chart, a
/// paired per-world comparison, and trajectories overlaid on a world picture. White background,
/// labelled axes, a title; text is set in DejaVu Sans, loaded from its one file (Debian's
/// fonts-dejavu-core; InputError naming the file if it is missing).
///
/// Every function writes the format of the output's extension (.png, .pdf or .svg; see
/// image_format.hpp), and the file appears complete or not at all. Each throws
/// core::InputError "<file>: ..." naming the problem for an unknown extension, for input that
/// cannot be drawn (see each function), and "<file>: cannot write: ..." if the file cannot be
/// written. Sizes below are in px (pt in a PDF or SVG); text widths are those of DejaVu
/// Sans (textWidth in src/viz/font.hpp).

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "barn/core/protocol.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/types.hpp"
#include "barn/core/world.hpp"
#include "barn/viz/image_format.hpp"

namespace barn::viz {

// ---------------------------------------------------------------------------
// Heat map

/// A table of values over two swept parameters, one cell per (row, column).
struct HeatMap {
  std::string title;                        // e.g. "pure_pursuit: BARN score, 50 worlds x 2 trials"
  std::string x_label;                      // column parameter, e.g. "safety.fi_offset [m]"
  std::string y_label;                      // row parameter, e.g. "max_speed [m/s]"
  std::vector<std::string> x_ticks;         // (n_cols) column values as text
  std::vector<std::string> y_ticks;         // (n_rows) row values as text; row 0 at the top
  std::vector<std::vector<double>> values;  // (n_rows x n_cols) [row][column]; NaN, inf = missing
  bool higher_is_better = true;             // best cell = the max (true) or the min (false)
  std::string value_format = "%.3f";        // cell text: one %[+][.N]f/e/g/% conversion, plus text
  // The colour scale. Fixed ends keep maps comparable (a score map from 0 to the protocol's
  // maximum, a rate from 0 to 1); NaN takes the end from the finite values.
  double scale_min = std::numeric_limits<double>::quiet_NaN();  // value coloured dark violet
  double scale_max = std::numeric_limits<double>::quiet_NaN();  // value coloured yellow
  std::string scale_label;  // written along the colour bar, e.g. "score (barn2023, max 0.25)"; "" = none
};

/// Draws `map` as coloured cells (viridis, from scale_min, dark, to scale_max, yellow; values
/// beyond a fixed end take the end's colour) with each value printed in the cell, a colour bar
/// labelled at both ends and at nice steps between (multiples of 1, 2 or 5 x 10^k, about 5
/// intervals; an end off that step written with value_format), scale_label along it, missing
/// cells grey and hatched, and the best cell (every cell, if several tie) outlined with a star
/// in its corner. value_format is parsed, not passed to printf: "%.3f", "%+.1f", "%.2e", "%g",
/// "%.0f%%" and text around them work in any locale; precision at most 99.
///
/// Layout [px]: cells are cell_w x cell_h with cell_w = max(80, widest cell or x tick text at
/// 14 px + 16, 400 / n_cols) and cell_h = max(48, 240 / n_rows), so the grid is at least
/// 400 x 240; left of them a band of 40 + max(48, widest y tick at 14 px + 16) for the y label
/// and ticks; right of them a band of 64 + max(56, widest colour-bar label at 13 px), + 26 with
/// a scale_label, for the colour bar; 60 above (title), 76 below (x ticks and label). So
///   width  = max(left band + n_cols * cell_w + right band, title width at 20 px + 48)
///   height = 136 + n_rows * cell_h
/// e.g. 688 x 376 px for 6 columns, 5 rows, short texts ("0.123", "1.5") and no scale_label.
/// Throws InputError if there are no rows or no columns, the number of y ticks is not the number
/// of rows, a row's length is not the number of x ticks, value_format is not as above, a scale
/// end is infinite or scale_max <= scale_min, or an image side exceeds 32767 px.
void renderHeatMap(const HeatMap& map, const std::filesystem::path& output);

// ---------------------------------------------------------------------------
// Per-world bar chart

/// How a world's trials ended.
struct OutcomeCounts {
  int success = 0;
  int collision = 0;
  int timeout = 0;
  int error = 0;
  int total() const { return success + collision + timeout + error; }
};

/// One bar per world, in the given order (e.g. easiest to hardest).
struct WorldBars {
  std::string title;                    // e.g. "inventec_fi: mean score per world"
  std::string subtitle;                 // a second, smaller line, e.g. the world set and protocol; "" = none
  std::string y_label;                  // e.g. "mean score"; also the bars' legend entry
  std::string x_label;                  // e.g. "worlds, easiest to hardest (by tortuosity)"
  std::vector<std::string> labels;      // (n) world ids as text, in plotting order
  std::vector<double> values;           // (n) bar heights; NaN = no bar
  std::vector<double> low;              // (n or empty) whisker bottoms, e.g. the worst trial; NaN = no whisker
  std::vector<double> high;             // (n or empty) whisker tops, e.g. the best trial
  std::string whisker_label;            // the whiskers' legend entry, e.g. "min to max of the 10 trials"
  std::vector<OutcomeCounts> outcomes;  // (n or empty) each world's trials by outcome
  double y_max = 0.0;                   // top of the y axis; 0 = automatic (5 % above the data)
  std::vector<double> reference_lines;  // y values drawn as labelled horizontal dashed lines
};

/// Draws `bars` as a bar chart; the y axis starts at 0 (or the smallest value, if negative).
/// With whiskers, a 1 px ink line from low to high on each bar (capped once bars are 4 px
/// apart). With outcomes, a strip under the zero line shows each world's trials stacked from
/// the bottom by outcome (success green, collision vermillion, timeout orange, error purple;
/// the share of the strip's height is the share of trials), in the same column as its bar, so
/// a world that never succeeded, which has no bar, still shows why. With either, a legend above
/// the plot names the bar (y_label), the whiskers (whisker_label) and the outcomes that occur
/// (success always). Only every k-th bar gets a tick label, k in 1, 2, 5, 10, 20, 25, 50, 100,
/// ... the smallest that leaves 8 px between neighbouring labels.
///
/// Layout [px]: the plot area is plot_w = max(720, 4 * n) wide and 320 tall, with margins 72
/// left and 56 right (reference-line labels); above it 56 (title), + 22 with a subtitle, + 24
/// per legend row; below it, + 34 with outcomes (a gap of 6 and the 28 px strip), then 72 for
/// the x ticks and label. So
///   width  = max(plot_w + 128, title width at 20 px + 48, subtitle width at 14 px + 48)
///   height = 448 (+ 22 with a subtitle, + 24 per legend row, + 34 with outcomes)
/// e.g. 1328 x 448 px for 300 worlds and neither, 1328 x 528 px with whiskers, outcomes, a
/// subtitle and one legend row.
/// Throws InputError if there are no bars, labels and values differ in length, low, high or
/// outcomes are neither empty nor one per bar, y_max is negative or not finite, or the image
/// is wider than 32767 px.
void renderWorldBars(const WorldBars& bars, const std::filesystem::path& output);

// ---------------------------------------------------------------------------
// Paired per-world comparison

/// Two runs' values per world, in the given order (e.g. ordered by A).
struct PairedWorlds {
  std::string title;                    // e.g. "mean score per world"
  std::string y_label;                  // e.g. "mean score"
  std::string x_label;                  // e.g. "worlds, ordered by A"
  std::string label_a;                  // legend name of A
  std::string label_b;                  // legend name of B
  std::vector<std::string> labels;      // (n) world ids as text, in plotting order
  std::vector<double> a;                // (n) A's values; NaN = no marker
  std::vector<double> b;                // (n) B's values; NaN = no marker
  double y_max = 0.0;                   // top of the y axis; 0 = automatic (5 % above the data)
  std::vector<double> reference_lines;  // y values drawn as labelled horizontal dashed lines
};

/// Draws `pairs` as a dumbbell chart: per world a grey line joining A's value (blue dot) and
/// B's (orange diamond), a legend naming A and B above the plot, y ticks from 0 (or the
/// smallest value, if negative), x tick labels thinned as for the bar chart.
///
/// Layout [px]: the plot area is plot_w = max(720, 10 * n) wide and 320 tall, with margins 72
/// left, 56 right, 80 top (title and legend) and 72 bottom, so
///   width  = max(plot_w + 128, title width at 20 px + 48, legend width + 96)
///   height = 472
/// Throws InputError if there are no worlds, labels, a and b differ in length, y_max is negative
/// or not finite, or the image is wider than 32767 px.
void renderPairedWorlds(const PairedWorlds& pairs, const std::filesystem::path& output);

// ---------------------------------------------------------------------------
// Trajectories on a world

/// One recorded robot pose.
struct TrajectoryPoint {
  double x = 0.0;     // [m] world frame
  double y = 0.0;     // [m] world frame
  std::string state;  // controller state at this point (e.g. "forward"); empty = none
};

/// One trial's path through the world.
struct TrajectoryOverlay {
  std::string label;                    // legend text, e.g. "trial 0  success"
  std::string detail;                   // a second, smaller legend line, e.g. "23.4 s  score 0.212"; "" = none
  std::vector<TrajectoryPoint> points;  // in time order; non-finite points break the line
  bool collided = false;                // draw a red X at the collision point
  double collision_x = 0.0;             // [m] world frame, if collided: the cylinder hit
  double collision_y = 0.0;             // [m] world frame, if collided
  std::optional<core::Pose2> collision_pose;  // world frame: the robot's pose at contact, outlined there
};

/// What colours a trajectory's line.
enum class TrajectoryColouring {
  ByState,  ///< each segment its controller state's colour; trajectories told apart by dash pattern
  ByTrial,  ///< one colour per trajectory (a dash pattern too, once the 7 colours repeat)
};

/// How trajectories are drawn.
struct TrajectoryStyle {
  TrajectoryColouring colouring = TrajectoryColouring::ByState;
  double pixels_per_metre = 120.0;  // [px/m] (pt/m in a PDF or SVG)
  std::vector<core::Rect> robot_outline;  // robot frame, drawn at each collision_pose (e.g.
                                          // core::RobotConfig::collisionRects()); empty = none
};

/// Draws the world as renderWorld does (cells, cylinders, start pose, goal; the A* path thin
/// and light), then each trajectory as a polyline, the robot's outline (light red, outlined in
/// red) at each collision pose, a red X on each cylinder hit, and a legend on the right. By
/// state, each segment takes the colour of its start point's state and the legend lists the
/// states, then the trajectories (one dash pattern each); by trial, each trajectory has one
/// colour, listed under "trajectory". A trajectory's legend entry is its label (or "trajectory
/// <k>") with its detail on a second line; the A* path, the cylinder mark and the robot outline
/// follow when present. Colours come from a fixed colour-blind-safe palette (Okabe-Ito): states
/// in order of first appearance across all trajectories, trials in order (cycling after 7);
/// points without a state are dark grey.
///
/// Layout: the world picture of renderWorld at the same scale plus a 2.6 m legend band:
///   width  = lround((x_max - x_min + 2 * 0.6 + 2.6) * pixels_per_metre)  [px]
///   height = lround((y_max - y_min + 2 * 0.6) * pixels_per_metre)        [px]
/// e.g. 996 x 1824 px for either preset at 120 px/m. Legend text is 0.15 m (details 0.12 m)
/// tall, shrunk to fit the band.
/// Throws InputError if pixels_per_metre is not positive or an image side exceeds 32767 px.
void renderTrajectories(const core::WorldSpec& world, const core::Protocol& protocol,
                        const std::vector<TrajectoryOverlay>& trajectories, const std::filesystem::path& output,
                        const TrajectoryStyle& style = {});

}  // namespace barn::viz
