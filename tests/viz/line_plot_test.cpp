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

}  // namespace
}  // namespace barn::viz
