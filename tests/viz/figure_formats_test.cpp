// Every figure kind in every output format: the extension chooses PNG, PDF or SVG, the file is
// complete (magic bytes, a real size, the documented dimensions), and any other extension is an
// InputError naming the file and the allowed ones, with nothing written.

#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/world.hpp"
#include "barn/viz/image_format.hpp"
#include "barn/viz/line_plot.hpp"
#include "barn/viz/plots.hpp"
#include "barn/viz/world_render.hpp"
#include "image_check.hpp"

namespace barn::viz {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// ---------------------------------------------------------------------------
// One small input per figure kind

core::WorldSpec corridorWorld() {
  core::WorldSpec world;
  world.id = 12;
  world.grid = core::Grid(30, 30);
  for (int c = 0; c < 30; ++c) {
    world.grid.at(0, c) = 1;
    world.grid.at(29, c) = 1;
  }
  world.grid.at(14, 10) = 1;
  world.start_cell = {15, 0};
  world.goal_cell = {15, 29};
  world.path = {{15, 0}, {15, 0}, {15, 1}, {15, 2}};
  return world;
}

HeatMap heatMap() {
  HeatMap map;
  map.title = "BARN score";
  map.x_label = "lookahead [m]";
  map.y_label = "speed [m/s]";
  map.x_ticks = {"0.3", "0.6", "0.9"};
  map.y_ticks = {"0.5", "1.0"};
  map.values = {{0.10, 0.12, 0.15}, {0.17, 0.20, 0.19}};
  return map;
}

WorldBars worldBars() {
  WorldBars bars;
  bars.title = "score per world";
  bars.y_label = "score";
  bars.x_label = "worlds";
  for (int i = 0; i < 20; ++i) {
    bars.labels.push_back(std::to_string(i));
    bars.values.push_back(0.01 * i);
  }
  return bars;
}

PairedWorlds pairedWorlds() {
  PairedWorlds pairs;
  pairs.title = "mean score per world";
  pairs.label_a = "a";
  pairs.label_b = "b";
  for (int i = 0; i < 20; ++i) {
    pairs.labels.push_back(std::to_string(i));
    pairs.a.push_back(0.01 * i);
    pairs.b.push_back(0.012 * i);
  }
  return pairs;
}

std::vector<TrajectoryOverlay> trajectories() {
  TrajectoryOverlay trial;
  trial.label = "trial 0";
  for (int k = 0; k <= 20; ++k) trial.points.push_back({-2.0, 3.0 + 0.3 * k, k < 10 ? "forward" : "turn"});
  return {trial};
}

LinePlot linePlot() {
  LinePlot plot;
  plot.title = "validation loss";
  plot.x_label = "epoch";
  plot.y_label = "loss";
  LineSeries validation;
  validation.label = "validation";
  validation.x = {1, 2, 3, 4};
  validation.y = {0.4, 0.3, 0.25, 0.22};
  plot.series = {validation};
  return plot;
}

/// A figure kind: how to draw it to a file, its documented size [px] and a size its file must
/// exceed (a figure with text and marks, not a blank page). Its pixels are checked in
/// plots_test.cpp, world_render_test.cpp and line_plot_test.cpp.
struct FigureKind {
  std::string name;
  std::function<void(const fs::path&)> render;
  long width;
  long height;
  std::size_t min_bytes;
};

std::vector<FigureKind> figureKinds() {
  const core::Protocol protocol = core::protocolPreset("barn2023");
  return {
      // 3 x 2 cells grown to the 400 x 240 px minimum grid, 88 px left of it, 120 right, 60
      // above, 76 below (plots.hpp).
      {"heat map", [](const fs::path& f) { renderHeatMap(heatMap(), f); }, 88 + 400 + 120, 60 + 240 + 76, 3000},
      // 20 bars: the minimum plot area of 720 x 320 px and the margins, 72 + 56 and 56 + 72.
      {"world bars", [](const fs::path& f) { renderWorldBars(worldBars(), f); }, 720 + 128, 448, 3000},
      {"paired worlds", [](const fs::path& f) { renderPairedWorlds(pairedWorlds(), f); }, 720 + 128, 472, 3000},
      // The world picture at 40 px/m plus the 2.6 m legend band: (4.5 + 1.2 + 2.6) * 40 = 332,
      // (14 + 1.2) * 40 = 608.
      {"trajectories",
       [protocol](const fs::path& f) {
         TrajectoryStyle style;
         style.pixels_per_metre = 40.0;
         renderTrajectories(corridorWorld(), protocol, trajectories(), f, style);
       },
       332,
       608, 3000},
      // (4.5 + 1.2) * 40 = 228, (14 + 1.2) * 40 = 608.
      {"world", [protocol](const fs::path& f) { renderWorld(corridorWorld(), protocol, f, RenderOptions{40.0, true, true}); },
       228, 608, 3000},
      {"line plot", [](const fs::path& f) { renderLinePlot(linePlot(), f); }, 900, 560, 2000},
  };
}

class FigureFormats : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("barn_figure_formats_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  fs::path dir_;
};

TEST_F(FigureFormats, TheExtensionChoosesTheFormat) {
  EXPECT_EQ(imageFormatFor("a/b.png"), ImageFormat::Png);
  EXPECT_EQ(imageFormatFor("b.PDF"), ImageFormat::Pdf);
  EXPECT_EQ(imageFormatFor("b.Svg"), ImageFormat::Svg);
  EXPECT_THROW(imageFormatFor("b.jpg"), core::InputError);
  EXPECT_THROW(imageFormatFor("b"), core::InputError);
}

TEST_F(FigureFormats, EveryFigureIsWrittenAsPngPdfAndSvg) {
  for (const FigureKind& kind : figureKinds()) {
    SCOPED_TRACE(kind.name);
    test::Size png_size{0, 0};
    for (const std::string extension : {".png", ".pdf", ".svg"}) {
      const fs::path file = dir_ / ("figure" + extension);
      kind.render(file);
      test::expectFigureFile(file, kind.min_bytes);
      if (extension == ".png") png_size = test::pngSize(file);
      // An SVG page is as many pt as the PNG has px.
      if (extension == ".svg") {
        const test::Size svg = test::svgSize(file);
        EXPECT_EQ(svg.width, png_size.width);
        EXPECT_EQ(svg.height, png_size.height);
      }
      fs::remove(file);
    }
    EXPECT_EQ(png_size.width, kind.width);
    EXPECT_EQ(png_size.height, kind.height);
  }
}

TEST_F(FigureFormats, AnUnknownExtensionIsAnInputErrorNamingTheFileAndWritesNothing) {
  for (const FigureKind& kind : figureKinds()) {
    SCOPED_TRACE(kind.name);
    for (const std::string name : {"figure.jpg", "figure", "figure.png.txt"}) {
      const fs::path file = dir_ / name;
      try {
        kind.render(file);
        ADD_FAILURE() << "no InputError for " << file;
      } catch (const core::InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(file.string()));
        EXPECT_THAT(e.what(), HasSubstr(".png, .pdf or .svg"));
      }
    }
    EXPECT_TRUE(fs::is_empty(dir_)) << "nothing written, no temporary left";
  }
}

TEST_F(FigureFormats, AFileThatCannotBeWrittenLeavesNothingBehind) {
  for (const FigureKind& kind : figureKinds()) {
    SCOPED_TRACE(kind.name);
    for (const std::string extension : {".png", ".pdf", ".svg"}) {
      const fs::path file = dir_ / "missing" / ("figure" + extension);
      try {
        kind.render(file);
        ADD_FAILURE() << "no IoError for " << file;
      } catch (const core::IoError& e) {
        EXPECT_THAT(e.what(), HasSubstr(file.string()));
        EXPECT_THAT(e.what(), HasSubstr("cannot write"));
      }
    }
    EXPECT_TRUE(fs::is_empty(dir_));
  }
}

}  // namespace
}  // namespace barn::viz
