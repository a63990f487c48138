#include "barn/viz/line_plot.hpp"

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::viz {
namespace {

namespace fs = std::filesystem;

LinePlot lossPlot() {
  LinePlot plot;
  plot.title = "validation loss";
  plot.x_label = "epoch";
  plot.y_label = "loss";
  plot.series = {{"validation", {1, 2, 3, 4}, {0.4, 0.3, 0.25, 0.22}}};
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
  EXPECT_THROW(renderLinePlot(lossPlot(), "/nonexistent/dir/plot.png"), core::InputError);
}

}  // namespace
}  // namespace barn::viz
