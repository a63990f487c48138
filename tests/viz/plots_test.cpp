#include "barn/viz/plots.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/core/world.hpp"
#include "barn/core/world_file.hpp"
#include "barn/viz/world_render.hpp"
#include "image_check.hpp"

namespace barn::viz {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using test::Image;
using test::near;
using test::pngSize;
using test::Pixel;
using test::readBytes;
using test::Size;

class PlotsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Unique per test and per run, so parallel ctest jobs never share a file.
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    const std::string tag = std::to_string(std::random_device{}());
    png_ = fs::temp_directory_path() / ("barn_plots_" + name + "_" + tag + ".png");
    unwritable_ = fs::temp_directory_path() / ("barn_plots_missing_" + tag) / "plot.png";
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove(png_, ignored);
  }

  /// Runs `render`, which must throw InputError mentioning every one of `parts`.
  template <typename Render>
  void expectInputError(Render render, const std::vector<std::string>& parts) {
    try {
      render();
      ADD_FAILURE() << "no InputError";
    } catch (const core::InputError& e) {
      for (const std::string& part : parts) EXPECT_THAT(e.what(), HasSubstr(part));
    }
  }

  // A file that cannot be written is a failed write (exit 1), not bad input.
  template <class Render>
  void expectIoError(Render render, const std::vector<std::string>& parts) {
    try {
      render();
      ADD_FAILURE() << "no IoError";
    } catch (const core::IoError& e) {
      for (const std::string& part : parts) EXPECT_THAT(e.what(), HasSubstr(part));
    }
  }

  fs::path png_;         // output of the test
  fs::path unwritable_;  // in a directory that is never created
};

// ---------------------------------------------------------------------------
// Heat map

// 5 rows x 6 columns, value = 6 r + c (0 ... 29); the largest, 29, is missing, so the best
// (highest) cell is (4, 4) with 28, and the lowest is (0, 0) with 0.
HeatMap sweep() {
  HeatMap map;
  map.title = "BARN score (barn2023)";
  map.x_label = "safety.fi_offset [m]";
  map.y_label = "max_speed [m/s]";
  map.x_ticks = {"0.00", "0.05", "0.10", "0.15", "0.20", "0.25"};
  map.y_ticks = {"0.5", "1.0", "1.5", "2.0", "2.5"};
  for (int r = 0; r < 5; ++r) {
    map.values.emplace_back();
    for (int c = 0; c < 6; ++c) map.values.back().push_back(6.0 * r + c);
  }
  map.values[4][5] = kNaN;
  map.value_format = "%.1f";
  return map;
}

// The layout of plots.hpp with texts narrower than the minimum bands: 88 px left of the grid,
// 80 x 48 px cells, 120 px right of the grid, 60 above and 76 below.
constexpr int kGridLeft = 88, kGridTop = 60, kCellW = 80, kCellH = 48;

TEST_F(PlotsTest, HeatMapHasTheDocumentedSizeAndDrawsAMissingCell) {
  renderHeatMap(sweep(), png_);
  const Size size = pngSize(png_);
  EXPECT_EQ(size.width, 88 + 6 * 80 + 120);  // 688
  EXPECT_EQ(size.height, 60 + 5 * 48 + 76);  // 376

  const Image image(png_);
  ASSERT_TRUE(image.ok());
  // The missing cell (4, 5) is grey only: fill and hatching, no viridis colour, no text.
  const int x = kGridLeft + 5 * kCellW, y = kGridTop + 4 * kCellH;
  EXPECT_FALSE(image.any(x + 3, y + 3, x + kCellW - 3, y + kCellH - 3,
                         [](Pixel p) { return p.r != p.g || p.g != p.b || p.r < 150; }));
  EXPECT_TRUE(
      image.any(x + 3, y + 3, x + kCellW - 3, y + kCellH - 3, [](Pixel p) { return p.r < 200; }));
}

TEST_F(PlotsTest, HeatMapColoursRunFromDarkViridisToYellowWithReadableText) {
  renderHeatMap(sweep(), png_);
  const Image image(png_);
  ASSERT_TRUE(image.ok());
  // Away from the text (and inside the best cell's outline): the smallest value takes
  // viridis(0), the largest viridis(1).
  EXPECT_TRUE(near(image.at(kGridLeft + 4, kGridTop + 4), 0.267, 0.005, 0.329));
  EXPECT_TRUE(
      near(image.at(kGridLeft + 4 * kCellW + 40, kGridTop + 4 * kCellH + 8), 0.993, 0.906, 0.144));
  // Text: white on the dark cell (0, 0), black on the bright cell (4, 3).
  const auto centre = [&](int r, int c, const std::function<bool(Pixel)>& test) {
    const int x = kGridLeft + c * kCellW, y = kGridTop + r * kCellH;
    return image.any(x + 20, y + 14, x + kCellW - 20, y + kCellH - 14, test);
  };
  EXPECT_TRUE(centre(0, 0, [](Pixel p) { return p.r > 230 && p.g > 230 && p.b > 230; }));
  EXPECT_FALSE(centre(0, 0, [](Pixel p) { return p.r < 30 && p.g < 30 && p.b < 30; }));
  EXPECT_TRUE(centre(4, 3, [](Pixel p) { return p.r < 30 && p.g < 30 && p.b < 30; }));
  EXPECT_FALSE(centre(4, 3, [](Pixel p) { return p.r > 230 && p.g > 230 && p.b > 230; }));
}

TEST_F(PlotsTest, HeatMapOutlinesTheBestCellByItsDirection) {
  // The ink outline runs along the cell's inner edge, 0 ... 4 px in from its border.
  const auto outlined = [&](int r, int c) {
    const Image image(png_);
    return near(image.at(kGridLeft + c * kCellW + 2, kGridTop + r * kCellH + kCellH / 2), 0.1, 0.1,
                0.1);
  };
  HeatMap map = sweep();
  renderHeatMap(map, png_);
  EXPECT_TRUE(outlined(4, 4));
  EXPECT_FALSE(outlined(0, 0));
  EXPECT_FALSE(outlined(4, 3));

  map.higher_is_better = false;
  renderHeatMap(map, png_);
  EXPECT_TRUE(outlined(0, 0));
  EXPECT_FALSE(outlined(4, 4));
}

TEST_F(PlotsTest, HeatMapCellsWidenForLongValueTexts) {
  HeatMap map = sweep();
  map.value_format = "%.6f";
  renderHeatMap(map, png_);
  // DejaVu Sans width of "28.000000": 8 digits advancing 1303 units and a '.' 651, at 2048
  // units per font size (unhinted); cells use 14 px text, the colour bar's labels 13 px.
  const auto text_width = [](double size) { return (8 * 1303.0 + 651.0) * size / 2048.0; };
  ASSERT_GT(text_width(14.0) + 16.0, 80.0);
  const double cell_w = text_width(14.0) + 16.0;
  const double bar_band = 64.0 + std::max(56.0, text_width(13.0));
  EXPECT_EQ(pngSize(png_).width, static_cast<long>(std::ceil(88.0 + 6.0 * cell_w + bar_band)));
}

TEST_F(PlotsTest, HeatMapRejectsEmptyAndRaggedInput) {
  HeatMap map = sweep();
  map.values.clear();
  map.y_ticks.clear();
  expectInputError([&] { renderHeatMap(map, png_); }, {png_.string(), "no rows"});

  map = sweep();
  map.x_ticks.clear();
  expectInputError([&] { renderHeatMap(map, png_); }, {"no columns"});

  map = sweep();
  map.y_ticks.pop_back();
  expectInputError([&] { renderHeatMap(map, png_); }, {"5 rows", "4 y_ticks"});

  map = sweep();
  map.values[2].pop_back();
  expectInputError([&] { renderHeatMap(map, png_); }, {"row 2 has 5 values", "6 x_ticks"});

  map = sweep();
  map.value_format = "%d";
  expectInputError([&] { renderHeatMap(map, png_); }, {"value_format '%d'"});
  map.value_format = "%s";
  expectInputError([&] { renderHeatMap(map, png_); }, {"value_format"});
  map.value_format = "no conversion";
  expectInputError([&] { renderHeatMap(map, png_); }, {"value_format"});
  EXPECT_FALSE(fs::exists(png_));
}

TEST_F(PlotsTest, HeatMapAcceptsPrintfStyleFormats) {
  HeatMap map = sweep();
  for (const std::string format :
       {"%.3f", "%+.1f", "%.2e", "%g", "%.0f%%", "s = %.2f", "%.f", "%E"}) {
    map.value_format = format;
    EXPECT_NO_THROW(renderHeatMap(map, png_)) << format;
  }
}

TEST_F(PlotsTest, HeatMapWithEveryValueMissingStillRenders) {
  HeatMap map = sweep();
  for (std::vector<double>& row : map.values) std::fill(row.begin(), row.end(), kNaN);
  renderHeatMap(map, png_);
  EXPECT_EQ(pngSize(png_).height, 376);
}

// A 2 x 3 score map whose best value, 0.2, is below the barn2023 maximum 0.25.
HeatMap scoreMap() {
  HeatMap map;
  map.title = "BARN score";
  map.x_label = "lookahead [m]";
  map.y_label = "speed [m/s]";
  map.x_ticks = {"0.3", "0.6", "0.9"};
  map.y_ticks = {"0.5", "1.0"};
  map.values = {{0.05, 0.10, 0.15}, {0.12, 0.20, 0.18}};
  return map;
}

// Layout of scoreMap (plots.hpp): 3 columns x 2 rows grow to the 400 x 240 px minimum grid, so
// cells are 133.3 x 120 px from (88, 60); the colour bar is 18 px wide, 24 px right of the
// grid (x 512 ... 530), and spans the grid's height (y 60 ... 300).
constexpr int kScoreBarX = 88 + 400 + 24, kScoreGridTop = 60, kScoreGridHeight = 240;

TEST_F(PlotsTest, HeatMapGrowsASmallGridToAReadableSize) {
  renderHeatMap(scoreMap(), png_);
  const Size size = pngSize(png_);
  EXPECT_EQ(size.width, 88 + 400 + 120);  // 608: the minimum grid and bands
  EXPECT_EQ(size.height, 60 + 240 + 76);  // 376
  HeatMap labelled = scoreMap();
  labelled.scale_label = "score (barn2023 maximum 0.25)";
  renderHeatMap(labelled, png_);
  EXPECT_EQ(pngSize(png_).width, 608 + 26);  // the scale label's band
}

TEST_F(PlotsTest, HeatMapOnAFixedScaleColoursItsTopAsTheScaleMaxWhateverTheData) {
  HeatMap map = scoreMap();
  map.scale_min = 0.0;
  map.scale_max = 0.25;
  map.scale_label = "score (barn2023 maximum 0.25)";
  renderHeatMap(map, png_);
  const Image image(png_);
  ASSERT_TRUE(image.ok());
  const auto yellow = [](Pixel p) { return p.r > 235 && p.g > 215 && p.b < 60; };
  // The bar's top pixel row inside its 1 px border is viridis(1), the colour of 0.25 ...
  EXPECT_TRUE(yellow(image.at(kScoreBarX + 9, kScoreGridTop + 2)));
  // ... and its bottom viridis(0), the colour of 0.
  EXPECT_TRUE(near(image.at(kScoreBarX + 9, kScoreGridTop + kScoreGridHeight - 2), 0.267, 0.005, 0.329) ||
              image.any(kScoreBarX + 7, kScoreGridTop + kScoreGridHeight - 3, kScoreBarX + 11, kScoreGridTop + kScoreGridHeight - 1,
                        [](Pixel p) { return p.r < 80 && p.g < 20 && p.b > 70; }));
  // The best cell, 0.2 = 0.8 of the scale, is viridis(0.8): 6.4 of the 8 intervals, 0.4 of the
  // way from (0.369, 0.789, 0.383) to (0.678, 0.864, 0.190). Sampled inside its outline, off
  // the text: cell (1, 1) spans x 221 ... 355, y 180 ... 300.
  EXPECT_TRUE(near(image.at(221 + 14, 300 - 14), 0.369 + 0.4 * 0.309, 0.789 + 0.4 * 0.075, 0.383 - 0.4 * 0.193));
  EXPECT_FALSE(yellow(image.at(221 + 14, 300 - 14)));
  // The colour bar at 0.2's height (60 + 240 - 0.8 * 240 = 108) has the cell's colour.
  EXPECT_TRUE(image.any(kScoreBarX + 7, 106, kScoreBarX + 11, 110,
                        test::isColour(0.369 + 0.4 * 0.309, 0.789 + 0.4 * 0.075, 0.383 - 0.4 * 0.193)));

  // Without a fixed scale the same data stretch to the data's range: 0.2 becomes yellow.
  renderHeatMap(scoreMap(), png_);
  EXPECT_TRUE(yellow(Image(png_).at(221 + 14, 300 - 14)));
}

TEST_F(PlotsTest, HeatMapScaleTicksRunInNiceStepsBetweenItsEnds) {
  // Tick marks 4 px long right of the bar at 0, 0.05, ..., 0.25: six marks, 48 px apart
  // (0.05 / 0.25 x 240), the ends held half a pixel inside the bar.
  HeatMap map = scoreMap();
  map.scale_min = 0.0;
  map.scale_max = 0.25;
  renderHeatMap(map, png_);
  const Image image(png_);
  ASSERT_TRUE(image.ok());
  int marks = 0;
  for (int y = kScoreGridTop; y < kScoreGridTop + kScoreGridHeight; ++y)
    if (image.at(kScoreBarX + 18 + 2, y).r < 100 && image.at(kScoreBarX + 18 + 2, y - 1).r >= 100) ++marks;
  EXPECT_EQ(marks, 6);
}

TEST_F(PlotsTest, HeatMapRejectsABadFixedScale) {
  HeatMap map = scoreMap();
  map.scale_min = 0.3;
  map.scale_max = 0.25;
  expectInputError([&] { renderHeatMap(map, png_); }, {png_.string(), "colour scale"});
  map.scale_min = 0.0;
  map.scale_max = std::numeric_limits<double>::infinity();
  expectInputError([&] { renderHeatMap(map, png_); }, {"colour scale"});
  EXPECT_FALSE(fs::exists(png_));
}

// ---------------------------------------------------------------------------
// Bar chart

WorldBars threeHundredWorlds() {
  WorldBars bars;
  bars.title = "inventec_fi: score per world";
  bars.y_label = "score";
  bars.x_label = "worlds, easiest to hardest (by tortuosity)";
  for (int i = 0; i < 300; ++i) {
    bars.labels.push_back(std::to_string((7 * i) % 300));
    bars.values.push_back(0.45 - 0.001 * i);
  }
  bars.reference_lines = {0.25, 0.125};
  return bars;
}

TEST_F(PlotsTest, BarChartHasTheDocumentedSize) {
  renderWorldBars(threeHundredWorlds(), png_);
  Size size = pngSize(png_);
  EXPECT_EQ(size.width, 4 * 300 + 128);  // 1328
  EXPECT_EQ(size.height, 448);

  WorldBars few = threeHundredWorlds();
  few.labels.resize(12);
  few.values.resize(12);
  renderWorldBars(few, png_);
  size = pngSize(png_);
  EXPECT_EQ(size.width, 720 + 128);  // the minimum plot width
  EXPECT_EQ(size.height, 448);
}

TEST_F(PlotsTest, BarHeightsFollowTheYAxis) {
  // Plot area: x from 72, y from 56 (top) to 376 (bottom); y_max = 1 puts 0.5 at y = 216.
  WorldBars bars;
  bars.labels = {"0", "1", "2"};
  bars.values = {0.5, kNaN, 1.0};
  bars.y_max = 1.0;
  renderWorldBars(bars, png_);
  const Image image(png_);
  ASSERT_TRUE(image.ok());
  const int pitch = 240;  // 720 px / 3 bars
  const auto bar_x = [&](int i) { return 72 + pitch * i + pitch / 2; };
  const Pixel blue{31, 120, 181};  // (0.12, 0.47, 0.71)
  const auto is_bar = [&](int x, int y) {
    const Pixel p = image.at(x, y);
    return std::abs(p.r - blue.r) <= 2 && std::abs(p.g - blue.g) <= 2 &&
           std::abs(p.b - blue.b) <= 2;
  };
  EXPECT_TRUE(is_bar(bar_x(0), 220));
  EXPECT_FALSE(is_bar(bar_x(0), 212));
  EXPECT_FALSE(is_bar(bar_x(1), 370));  // NaN: no bar
  EXPECT_TRUE(is_bar(bar_x(2), 60));
}

// Three worlds of 3 trials: all successes at the maximum; one success in three; two collisions
// and a timeout (no bar: score 0).
WorldBars threeWorldsWithOutcomes() {
  WorldBars bars;
  bars.title = "lflh: mean score per world";
  bars.subtitle = "3 worlds of worlds/ (barnbench-generated) x 3 trials, barn2023 (max score 0.25)";
  bars.y_label = "mean score";
  bars.x_label = "worlds";
  bars.labels = {"0", "1", "2"};
  bars.values = {0.25, 0.25 / 3.0, 0.0};
  bars.low = {0.25, 0.0, 0.0};
  bars.high = {0.25, 0.25, 0.0};
  bars.whisker_label = "min to max of its 3 trials";
  bars.outcomes = {{3, 0, 0, 0}, {1, 2, 0, 0}, {0, 2, 1, 0}};
  bars.y_max = 0.25;
  return bars;
}

constexpr double kSuccess[] = {0.000, 0.620, 0.451};
constexpr double kCollision[] = {0.835, 0.369, 0.000};
constexpr double kTimeout[] = {0.902, 0.624, 0.000};
constexpr double kError[] = {0.800, 0.475, 0.655};
std::function<bool(Pixel)> is(const double (&rgb)[3]) { return test::isColour(rgb[0], rgb[1], rgb[2]); }

TEST_F(PlotsTest, BarChartShowsEachWorldsOutcomeMixWhiskersAndALegend) {
  renderWorldBars(threeWorldsWithOutcomes(), png_);
  // Layout (plots.hpp): a subtitle (+22) and one legend row (+24) put the plot at y 102 ... 422
  // (y = v is at 422 - 1280 v); the strip at 428 ... 456; 72 below. Bars are 240 px apart from
  // x 72 with 24 px of gap each side: bar 1 spans x 336 ... 528, bar 2 x 576 ... 768.
  const Size size = pngSize(png_);
  EXPECT_EQ(size.width, 720 + 128);
  EXPECT_EQ(size.height, 448 + 22 + 24 + 34);
  const Image image(png_);
  ASSERT_TRUE(image.ok());

  // Strip of bar 1, stacked from the bottom: 1 success in 3 (456 - 28 / 3 = 446.7, so rows
  // 447 ... 455), then 2 collisions (428 ... 446).
  EXPECT_TRUE(is(kSuccess)(image.at(430, 452)));
  EXPECT_TRUE(is(kCollision)(image.at(430, 435)));
  // Bar 2 has no bar, but its strip says why: 2 collisions (rows 437 ... 455), a timeout above.
  EXPECT_FALSE(image.any(580, 110, 760, 415, is({0.12, 0.47, 0.71})));
  EXPECT_TRUE(is(kCollision)(image.at(650, 450)));
  EXPECT_TRUE(is(kTimeout)(image.at(650, 431)));
  // Bar 0: all successes, a full green column.
  EXPECT_TRUE(is(kSuccess)(image.at(150, 430)));
  EXPECT_TRUE(is(kSuccess)(image.at(150, 454)));

  // Bar 1's whisker: an ink line on the bar's centre (x 432) from 0 up to 0.25 (y 102), above
  // the bar's top at 0.083 (y 315); nothing beside it.
  EXPECT_TRUE(test::isColour(0.1, 0.1, 0.1)(image.at(432, 150)));
  EXPECT_FALSE(image.any(437, 140, 445, 160, [](Pixel p) { return p.r < 100; }));

  // The legend row (y 78 ... 90): the bar's blue, green, vermillion and orange swatches; no
  // purple, since no trial ended in an error.
  const auto row = [&](const std::function<bool(Pixel)>& test) { return image.any(72, 78, size.width, 91, test); };
  EXPECT_TRUE(is({0.12, 0.47, 0.71})(image.at(78, 84)));
  EXPECT_TRUE(row(is(kSuccess)));
  EXPECT_TRUE(row(is(kCollision)));
  EXPECT_TRUE(row(is(kTimeout)));
  EXPECT_FALSE(row(is(kError)));
}

TEST_F(PlotsTest, BarChartRejectsWhiskersOrOutcomesOfTheWrongLength) {
  WorldBars bars = threeWorldsWithOutcomes();
  bars.high.pop_back();
  expectInputError([&] { renderWorldBars(bars, png_); }, {png_.string(), "3 low and 2 high"});
  bars = threeWorldsWithOutcomes();
  bars.outcomes.push_back({});
  expectInputError([&] { renderWorldBars(bars, png_); }, {"4 outcome counts"});
  EXPECT_FALSE(fs::exists(png_));
}

TEST_F(PlotsTest, BarChartRejectsEmptyOrMismatchedInput) {
  WorldBars bars = threeHundredWorlds();
  bars.labels.pop_back();
  expectInputError([&] { renderWorldBars(bars, png_); },
                   {png_.string(), "299 labels but 300 values"});

  bars.labels.clear();
  bars.values.clear();
  expectInputError([&] { renderWorldBars(bars, png_); }, {"no bars"});

  bars = threeHundredWorlds();
  bars.y_max = -1.0;
  expectInputError([&] { renderWorldBars(bars, png_); }, {"y_max"});

  bars = threeHundredWorlds();
  bars.labels.assign(9000, "1");
  bars.values.assign(9000, 0.1);
  expectInputError([&] { renderWorldBars(bars, png_); }, {"out of range"});
  EXPECT_FALSE(fs::exists(png_));
}

// ---------------------------------------------------------------------------
// Trajectories

// An empty field inside the corridor walls, with a straight A* path.
core::WorldSpec emptyWorld() {
  core::WorldSpec world;
  world.id = 3;
  world.grid = core::Grid(30, 30);
  for (int c = 0; c < 30; ++c) {
    world.grid.at(0, c) = 1;
    world.grid.at(29, c) = 1;
  }
  world.start_cell = {15, 0};
  world.goal_cell = {15, 29};
  world.path = {{15, 0}, {15, 0}, {15, 1}, {15, 2}};
  return world;
}

// barn2023 at 120 px/m: the view box is x [-4.5, 0], y [0, 14], so a world point maps to
// ((x + 5.1) * 120, (14.6 - y) * 120) px.
int pxX(double x) { return static_cast<int>(std::lround((x + 5.1) * 120.0)); }
int pxY(double y) { return static_cast<int>(std::lround((14.6 - y) * 120.0)); }

TrajectoryStyle scaled(double pixels_per_metre) {
  TrajectoryStyle style;
  style.pixels_per_metre = pixels_per_metre;
  return style;
}

TEST_F(PlotsTest, TrajectoryOverlayIsTheWorldPictureWithALegendBand) {
  const core::Protocol protocol = core::protocolPreset("barn2023");
  renderTrajectories(emptyWorld(), protocol, {}, png_);
  const Size size = pngSize(png_);
  EXPECT_EQ(size.width, std::lround((4.5 + 1.2 + 2.6) * 120.0));  // 996
  EXPECT_EQ(size.height, std::lround((14.0 + 1.2) * 120.0));      // 1824

  // Same height as renderWorld, 2.6 m wider.
  renderWorld(emptyWorld(), protocol, png_, RenderOptions{60.0, true, true});
  const Size world_size = pngSize(png_);
  renderTrajectories(emptyWorld(), protocol, {}, png_, scaled(60.0));
  EXPECT_EQ(pngSize(png_).width, world_size.width + 156);  // 2.6 m x 60 px/m
  EXPECT_EQ(pngSize(png_).height, world_size.height);
}

TEST_F(PlotsTest, TrajectorySegmentsTakeTheirStateColourAndCollisionsAreMarked) {
  // Trajectory 0 drives forward then recovers; trajectory 1 recovers, then backtracks into a
  // collision. Colours go by first appearance: forward orange, recovery sky blue, backtrack
  // bluish green, the same in both trajectories.
  TrajectoryOverlay first;
  first.label = "trial 0";
  for (int k = 0; k <= 20; ++k)
    first.points.push_back({-3.5, 1.0 + 0.1 * k, k < 10 ? "forward" : "recovery"});
  TrajectoryOverlay second;
  second.label = "trial 1";
  for (int k = 0; k <= 20; ++k)
    second.points.push_back({-1.0, 1.0 + 0.1 * k, k < 10 ? "recovery" : "backtrack"});
  second.collided = true;
  second.collision_x = -2.5;
  second.collision_y = 1.5;
  renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {first, second}, png_);

  const Image image(png_);
  ASSERT_TRUE(image.ok());
  EXPECT_TRUE(near(image.at(pxX(-3.5), pxY(1.45)), 0.902, 0.624, 0.0));    // forward
  EXPECT_TRUE(near(image.at(pxX(-3.5), pxY(2.55)), 0.337, 0.706, 0.914));  // recovery
  // Trajectory 1 is dashed 0.20 m on, 0.10 m off from its start: sample inside the dashes.
  EXPECT_TRUE(near(image.at(pxX(-1.0), pxY(1.1)), 0.337, 0.706, 0.914));  // recovery
  EXPECT_TRUE(near(image.at(pxX(-1.0), pxY(2.35)), 0.0, 0.620, 0.451));   // backtrack
  // The dashes run on across the state change at y = 2.0 (1.0 m in, phase 0.1 m): 0.15 m later
  // is a gap, where a pattern restarted at the change would still be on.
  EXPECT_TRUE(near(image.at(pxX(-1.0), pxY(2.15)), 1.0, 1.0, 1.0));
  EXPECT_TRUE(near(image.at(pxX(-2.5), pxY(1.5)), 0.86, 0.0, 0.0));  // collision X
  // Off the trajectories the field is white.
  EXPECT_TRUE(near(image.at(pxX(-2.5), pxY(2.5)), 1.0, 1.0, 1.0));
}

TEST_F(PlotsTest, ColouredByTrialEachTrajectoryHasOneColourAndALegendEntry) {
  // The same two paths as above, states and all: by trial, trajectory 0 is orange throughout
  // and trajectory 1 sky blue, whatever their states; both solid (7 colours before a repeat).
  TrajectoryOverlay first;
  first.label = "trial 0  success";
  first.detail = "23.4 s  score 0.212";
  for (int k = 0; k <= 20; ++k) first.points.push_back({-3.5, 1.0 + 0.1 * k, k < 10 ? "forward" : "recovery"});
  TrajectoryOverlay second;
  second.label = "trial 1  collision";
  second.detail = "12.0 s  score 0.000";
  for (int k = 0; k <= 20; ++k) second.points.push_back({-1.0, 1.0 + 0.1 * k, k < 10 ? "recovery" : "backtrack"});
  TrajectoryStyle style;
  style.colouring = TrajectoryColouring::ByTrial;
  renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {first, second}, png_, style);

  const Image image(png_);
  ASSERT_TRUE(image.ok());
  EXPECT_TRUE(near(image.at(pxX(-3.5), pxY(1.45)), 0.902, 0.624, 0.0));    // forward, trial 0
  EXPECT_TRUE(near(image.at(pxX(-3.5), pxY(2.55)), 0.902, 0.624, 0.0));    // recovery, trial 0
  EXPECT_TRUE(near(image.at(pxX(-1.0), pxY(1.15)), 0.337, 0.706, 0.914));  // recovery, trial 1
  EXPECT_TRUE(near(image.at(pxX(-1.0), pxY(2.15)), 0.337, 0.706, 0.914));  // backtrack, trial 1, solid
  // Legend, from x 684 (the map's width) and y 96 (0.8 m): the "trajectory" header, then one
  // 0.3 m row per entry plus 0.2 m for its detail line. Trial 0's swatch at y 132, trial 1's
  // at 132 + 24 + 36 = 192; no state section.
  EXPECT_TRUE(near(image.at(700, 132), 0.902, 0.624, 0.0));
  EXPECT_TRUE(near(image.at(700, 192), 0.337, 0.706, 0.914));
}

TEST_F(PlotsTest, TheRobotsOutlineIsDrawnAtThePoseOfContact) {
  // The Jackal's collision shape: chassis 0.42 x 0.31 m, wheels 0.196 x 0.04 m at x +-0.131,
  // y +-0.188 (core::RobotConfig). Facing up the page (yaw pi/2), a point 0.19 m ahead of the
  // centre is inside the chassis (half length 0.21) and one 0.18 m to its right is outside it
  // (half width 0.155) and between the wheels (x 0.033 ... 0.229 ahead).
  TrajectoryOverlay crash;
  crash.label = "trial 0  collision";
  for (int k = 0; k <= 10; ++k) crash.points.push_back({-2.5, 3.0 + 0.2 * k, ""});
  crash.collided = true;
  crash.collision_x = -2.5;
  crash.collision_y = 5.3;
  crash.collision_pose = core::Pose2{-2.5, 5.0, std::numbers::pi / 2};
  TrajectoryStyle style;
  style.robot_outline = core::RobotConfig{}.collisionRects();
  renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {crash}, png_, style);

  const Image image(png_);
  ASSERT_TRUE(image.ok());
  // Inside: the outline's light red fill (0.18 of (0.86, 0, 0) over white), off the
  // trajectory's line (x -2.5 +- 0.018 m).
  const auto pink = [](Pixel p) { return p.r > 240 && p.g > 195 && p.g < 222 && std::abs(p.g - p.b) <= 3; };
  EXPECT_TRUE(pink(image.at(pxX(-2.5 + 0.08), pxY(5.0 + 0.12))));
  // Outside the chassis beside its centre: white.
  EXPECT_TRUE(near(image.at(pxX(-2.5 + 0.18), pxY(5.0)), 1.0, 1.0, 1.0));
  // The chassis' front edge (0.21 m ahead) in the collision red.
  EXPECT_TRUE(image.any(pxX(-2.5 + 0.08) - 1, pxY(5.21) - 2, pxX(-2.5 + 0.08) + 2, pxY(5.21) + 3,
                        test::isColour(0.86, 0.0, 0.0)));
  // Without the shape, no outline.
  style.robot_outline.clear();
  renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {crash}, png_, style);
  EXPECT_TRUE(near(Image(png_).at(pxX(-2.5 + 0.08), pxY(5.0 + 0.12)), 1.0, 1.0, 1.0));
}

TEST_F(PlotsTest, TrajectoryOverlayRendersARealWorld) {
  const core::WorldSpec world =
      core::readWorldFile(fs::path(BARN_SOURCE_DIR) / "worlds" / "world_150.yaml");
  TrajectoryOverlay trial;
  trial.label = "trial 0";
  trial.points = {{-2.0, 3.0, ""},
                  {-2.0, 4.0, ""},
                  {kNaN, 4.5, ""},
                  {-1.9, 5.0, "forward"},
                  {-1.8, 6.0, "forward"}};
  renderTrajectories(world, core::protocolPreset("barn2024"), {trial}, png_, scaled(50.0));
  EXPECT_GT(pngSize(png_).width, 0);
}

TEST_F(PlotsTest, TrajectoryOverlayRejectsABadScale) {
  expectInputError(
      [&] { renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {}, png_, scaled(0.0)); },
      {png_.string(), "pixels_per_metre"});
  expectInputError(
      [&] { renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {}, png_, scaled(1e4)); },
      {"out of range"});
}

// ---------------------------------------------------------------------------
// Paired per-world chart

// 25 worlds; A rises from 0 to 0.24, B is A shifted by a wave; world 7 has no B value.
PairedWorlds pairedWorlds() {
  PairedWorlds pairs;
  pairs.title = "mean score per world";
  pairs.y_label = "mean score";
  pairs.x_label = "world id, ordered by A";
  pairs.label_a = "gazebo:dwa (barn2023)";
  pairs.label_b = "pure_pursuit (barn2023)";
  for (int i = 0; i < 25; ++i) {
    pairs.labels.push_back(std::to_string(6 * i));
    pairs.a.push_back(0.01 * i);
    pairs.b.push_back(std::clamp(0.01 * i + 0.05 * std::sin(i), 0.0, 0.25));
  }
  pairs.b[7] = kNaN;
  pairs.y_max = 0.25;
  pairs.reference_lines = {0.25, 0.125};
  return pairs;
}

TEST_F(PlotsTest, PairedChartPngHasTheDocumentedSizeAndBothMarkerColours) {
  renderPairedWorlds(pairedWorlds(), png_);
  const Size size = pngSize(png_);
  EXPECT_EQ(size.width, 720 + 128);
  EXPECT_EQ(size.height, 472);
  const Image image(png_);
  ASSERT_TRUE(image.ok());
  // Plot area: x 72 ... 792, y 80 ... 400. A is blue, B orange, on a white background.
  const auto blue = [](Pixel p) { return p.b > 150 && p.r < 80; };
  const auto orange = [](Pixel p) { return p.r > 200 && p.g > 80 && p.g < 160 && p.b < 60; };
  EXPECT_TRUE(image.any(72, 80, 792, 401, blue));
  EXPECT_TRUE(image.any(72, 80, 792, 401, orange));
  // The legend above the plot has both markers too.
  EXPECT_TRUE(image.any(0, 44, size.width, 72, blue));
  EXPECT_TRUE(image.any(0, 44, size.width, 72, orange));
  // The first world's A value is 0: its dot sits on the zero line, at the left.
  EXPECT_TRUE(image.any(72, 390, 92, 401, blue));
}

TEST_F(PlotsTest, PairedChartWritesPdfAndSvgByExtension) {
  for (const std::string& extension : {std::string(".pdf"), std::string(".svg"), std::string(".PDF")}) {
    fs::path out = png_;
    out.replace_extension(extension);
    renderPairedWorlds(pairedWorlds(), out);
    const std::string text = [&] {
      const std::vector<unsigned char> bytes = readBytes(out);
      return std::string(bytes.begin(), bytes.end());
    }();
    if (extension == ".svg") {
      EXPECT_THAT(text.substr(0, 200), HasSubstr("<svg")) << out;
      EXPECT_THAT(text, HasSubstr("0 0 848 472"));  // the viewBox: 1 unit per px
    } else {
      EXPECT_EQ(text.substr(0, 5), "%PDF-") << out;
    }
    EXPECT_GT(text.size(), 2000u) << "a chart of 25 worlds is more than a blank page";
    EXPECT_FALSE(fs::exists(fs::path(out.string() + ".partial")));
    std::error_code ignored;
    fs::remove(out, ignored);
  }
}

TEST_F(PlotsTest, PairedChartRejectsBadInputAndUnknownExtensions) {
  PairedWorlds pairs = pairedWorlds();
  pairs.b.pop_back();
  expectInputError([&] { renderPairedWorlds(pairs, png_); }, {png_.string(), "24 B values"});
  expectInputError([&] { renderPairedWorlds(PairedWorlds{}, png_); }, {"no worlds"});
  fs::path jpg = png_;
  jpg.replace_extension(".jpg");
  expectInputError([&] { renderPairedWorlds(pairedWorlds(), jpg); }, {jpg.string(), "'.jpg'"});
  EXPECT_FALSE(fs::exists(jpg));
  fs::path pdf = unwritable_;
  pdf.replace_extension(".pdf");
  expectIoError([&] { renderPairedWorlds(pairedWorlds(), pdf); }, {pdf.string(), "cannot write"});
  expectIoError([&] { renderPairedWorlds(pairedWorlds(), unwritable_); }, {unwritable_.string(), "cannot write"});
  EXPECT_FALSE(fs::exists(unwritable_.parent_path()));
}

// ---------------------------------------------------------------------------
// Output errors

TEST_F(PlotsTest, UnwritablePathThrowsIoErrorNamingThePath) {
  const std::vector<std::string> parts = {unwritable_.string(), "cannot write"};
  expectIoError([&] { renderHeatMap(sweep(), unwritable_); }, parts);
  expectIoError([&] { renderWorldBars(threeHundredWorlds(), unwritable_); }, parts);
  expectIoError(
      [&] {
        renderTrajectories(emptyWorld(), core::protocolPreset("barn2023"), {}, unwritable_, scaled(20.0));
      },
      parts);
  EXPECT_FALSE(fs::exists(unwritable_.parent_path()));
}

}  // namespace
}  // namespace barn::viz
