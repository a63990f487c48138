#include "barn/viz/line_plot.hpp"

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "image_check.hpp"

namespace barn::viz {
namespace {

namespace fs = std::filesystem;

LinePlot lossPlot() {
  LinePlot plot;
  plot.title = "validation loss";
  plot.x_label = "epoch";
  plot.y_label = "loss";
  LineSeries validation;
  validation.label = "validation";
  validation.x = {1, 2, 3, 4};
  validation.y = {0.4, 0.3, 0.25, 0.22};
  plot.series = {validation};
  plot.references = {{"mean", 0.5}};
  return plot;
}

TEST(LinePlot, WritesAPngOfTheRequestedSize) {
  const fs::path png = fs::temp_directory_path() / "barn_line_plot_test.png";
  fs::remove(png);
  LinePlot plot = lossPlot();
  plot.width = 640;
  plot.height = 400;
  renderLinePlot(plot, png);
  const std::string bytes = core::readTextFile(png);
  ASSERT_GT(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  // IHDR: width and height as big-endian 32-bit integers at bytes 16 and 20. 640 = 0x280, 400 = 0x190.
  EXPECT_EQ(static_cast<unsigned char>(bytes[18]), 0x02);
  EXPECT_EQ(static_cast<unsigned char>(bytes[19]), 0x80);
  EXPECT_EQ(static_cast<unsigned char>(bytes[22]), 0x01);
  EXPECT_EQ(static_cast<unsigned char>(bytes[23]), 0x90);
}

TEST(LinePlot, BadInputIsAnInputErrorNamingTheFile) {
  const fs::path png = fs::temp_directory_path() / "barn_line_plot_bad.png";
  LinePlot uneven = lossPlot();
  uneven.series[0].y.pop_back();
  EXPECT_THAT([&] { renderLinePlot(uneven, png); },
              ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("different lengths")));
  LinePlot empty;
  EXPECT_THROW(renderLinePlot(empty, png), core::InputError);
  LinePlot tiny = lossPlot();
  tiny.width = 10;
  EXPECT_THROW(renderLinePlot(tiny, png), core::InputError);
  // A file that cannot be written is a failed write (exit 1), not bad input.
  EXPECT_THROW(renderLinePlot(lossPlot(), "/nonexistent/dir/plot.png"), core::IoError);
}

// One series of three points on categories 0, 1, 2 with 95 % intervals, y fixed to 0 ... 1.
LinePlot intervalPlot() {
  LinePlot plot;
  plot.title = "success rate";
  plot.x_label = "speed [m/s]";
  plot.y_label = "success rate, mean over worlds";
  plot.width = 640;
  plot.height = 400;
  plot.y_min = 0.0;
  plot.y_max = 1.0;
  plot.x_ticks = {{0.0, "0.3"}, {1.0, "0.5"}, {2.0, "fast"}};
  LineSeries s;
  s.label = "mean over 3 worlds; bars: 95 % interval";
  s.x = {0.0, 1.0, 2.0};
  s.y = {0.9, 0.5, 0.1};
  s.low = {0.8, 0.2, 0.0};
  s.high = {1.0, 0.8, 0.3};
  s.markers = true;
  plot.series = {s};
  return plot;
}

// Layout of intervalPlot: the plot area runs x 80 ... 616 and, below the 44 px title band and
// one 20 px legend row (+ 6), y 70 ... 342. Ticked x axis: half a tick spacing of room each
// side, so x spans -0.5 ... 2.5 and x = 1 is at 80 + 1.5 / 3 x 536 = 348 px; y = v is at
// 342 - 272 v px.
constexpr double kBlueR = 0.12, kBlueG = 0.47, kBlueB = 0.71;

TEST(LinePlot, DrawsIntervalsOnAFixedAxisAndALegendAboveThePlot) {
  const fs::path png = fs::temp_directory_path() / "barn_line_plot_intervals.png";
  renderLinePlot(intervalPlot(), png);
  const test::Image image(png);
  ASSERT_TRUE(image.ok());
  ASSERT_EQ(image.width(), 640);
  const auto blue = test::isColour(kBlueR, kBlueG, kBlueB);
  // The middle point's bar runs from 0.2 (y 287.6) to 0.8 (y 124.4): blue at 0.7 (y 151.6),
  // nothing blue at 0.9 (y 97.2), above the bar's cap.
  EXPECT_TRUE(image.any(346, 149, 351, 155, blue));
  EXPECT_FALSE(image.any(340, 90, 357, 104, blue));
  // The marker: a filled dot at (348, 206).
  EXPECT_TRUE(blue(image.at(348, 206)));
  // The legend swatch: a line from x 80 to 108 at y 54 with the marker in its middle, above
  // the plot area.
  EXPECT_TRUE(blue(image.at(84, 54)));
  EXPECT_TRUE(blue(image.at(94, 54)));
  fs::remove(png);
}

TEST(LinePlot, RejectsMismatchedIntervalsAndABadFixedRange) {
  const fs::path png = fs::temp_directory_path() / "barn_line_plot_bad_interval.png";
  LinePlot plot = intervalPlot();
  plot.series[0].high.pop_back();
  EXPECT_THAT([&] { renderLinePlot(plot, png); },
              ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("2 high")));
  plot = intervalPlot();
  plot.y_max = plot.y_min;
  EXPECT_THAT([&] { renderLinePlot(plot, png); },
              ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("fixed y range")));
  EXPECT_FALSE(fs::exists(png));
}

TEST(LinePlots, StackEachPlotAsItIsDrawnAloneOneBelowTheOther) {
  const fs::path alone = fs::temp_directory_path() / "barn_line_plot_alone.png";
  const fs::path stacked = fs::temp_directory_path() / "barn_line_plot_stacked.png";
  renderLinePlot(intervalPlot(), alone);
  LinePlot second = lossPlot();
  second.width = 640;
  second.height = 300;
  renderLinePlots({intervalPlot(), second}, stacked);
  const test::Image one(alone), both(stacked);
  ASSERT_TRUE(one.ok());
  ASSERT_TRUE(both.ok());
  // 640 wide, 400 + 300 tall; the top 400 rows are the first plot's, pixel for pixel (its
  // marker at (348, 206) is blue in both).
  EXPECT_EQ(both.width(), 640);
  EXPECT_EQ(both.height(), 700);
  const auto blue = test::isColour(kBlueR, kBlueG, kBlueB);
  EXPECT_TRUE(blue(both.at(348, 206)));
  bool same = true;
  for (int y = 0; y < 400 && same; y += 3)
    for (int x = 0; x < 640 && same; x += 3) {
      const test::Pixel a = one.at(x, y), b = both.at(x, y);
      same = a.r == b.r && a.g == b.g && a.b == b.b;
    }
  EXPECT_TRUE(same);
  // The second plot's legend swatch sits at y 54 of its own panel: 400 + 54.
  EXPECT_TRUE(blue(both.at(94, 454)));
  fs::remove(alone);
  fs::remove(stacked);
}

TEST(LinePlots, RefuseNoPlotsUnequalWidthsAndABadPanel) {
  const fs::path png = fs::temp_directory_path() / "barn_line_plots_bad.png";
  EXPECT_THAT([&] { renderLinePlots({}, png); }, ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("no plots")));
  EXPECT_THAT([&] { renderLinePlots({intervalPlot(), lossPlot()}, png); },
              ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("equally wide")));
  LinePlot uneven = intervalPlot();
  uneven.series[0].y.pop_back();
  EXPECT_THAT([&] { renderLinePlots({intervalPlot(), uneven}, png); },
              ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("different lengths")));
  EXPECT_FALSE(fs::exists(png));
}

TEST(LinePlot, ASeriesWithoutALabelHasNoLegendRow) {
  // 150 px tall: the 44 px title band and 58 px below leave 48 px of plot without a legend, but
  // only 22 px under a 26 px legend row (less than the 40 px minimum).
  const fs::path png = fs::temp_directory_path() / "barn_line_plot_unlabelled.png";
  LinePlot plot = lossPlot();
  plot.references.clear();
  plot.height = 150;
  EXPECT_THAT([&] { renderLinePlot(plot, png); }, ::testing::ThrowsMessage<core::InputError>(::testing::HasSubstr("legend rows")));
  plot.series[0].label.clear();
  renderLinePlot(plot, png);
  EXPECT_TRUE(fs::exists(png));
  fs::remove(png);
}

}  // namespace
}  // namespace barn::viz
