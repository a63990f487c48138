#include "barn/core/world_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"

namespace barn::core {
namespace {

using ::testing::HasSubstr;

// A valid world: an empty field (wall rows only) and the straight path along row 15.
WorldSpec straightWorld() {
  WorldSpec w;
  w.id = 7;
  w.seed = 123;
  w.fill_pct = 0.15;
  w.smooth_iter = 2;
  w.grid = Grid(kBarnGridSize, kBarnGridSize);
  for (int c = 0; c < kBarnGridSize; ++c) w.grid.at(0, c) = w.grid.at(29, c) = 1;
  w.start_cell = {15, 0};
  w.goal_cell = {15, 29};
  w.path.push_back(w.start_cell);
  for (int c = 0; c < kBarnGridSize; ++c) w.path.push_back({15, c});
  w.metrics = {12.0, 8.0, 0.0, 23.0, 1.0};
  w.norm_metrics = {0.5, -0.25, 0.0, 1.5, -1.0};
  return w;
}

std::string errorOf(const std::string& text) {
  try {
    parseWorldFile(text, "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(WorldFile, RoundTripsByteForByte) {
  const WorldSpec w = straightWorld();
  const std::string text = formatWorldFile(w);
  const WorldSpec back = parseWorldFile(text, "test.yaml");
  EXPECT_EQ(formatWorldFile(back), text);
  EXPECT_EQ(back.seed, w.seed);
  EXPECT_EQ(back.path, w.path);
  EXPECT_EQ(back.grid, w.grid);
  EXPECT_EQ(back.metrics.characteristic_dimension, 23.0);
  EXPECT_EQ(back.norm_metrics.avg_visibility, -0.25);
}

TEST(WorldFile, EveryCommittedWorldReadsAndWritesBackByteForByte) {
  // The worlds/ files were written by earlier versions of the writer.
  int checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(BARN_SOURCE_DIR) / "worlds")) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    EXPECT_EQ(formatWorldFile(readWorldFile(entry.path())), text.str()) << entry.path();
    ++checked;
  }
  EXPECT_EQ(checked, 300);
}

TEST(WorldFile, AnImportedWorldRoundTripsWithoutASeed) {
  WorldSpec w = straightWorld();
  w.source = WorldSource::BarnDataset;
  w.seed.reset();
  const WorldSpec back = parseWorldFile(formatWorldFile(w), "test.yaml");
  EXPECT_EQ(back.source, WorldSource::BarnDataset);
  EXPECT_FALSE(back.seed.has_value());
}

TEST(WorldFile, NamesTheFieldOfEachMalformedValue) {
  const std::string text = formatWorldFile(straightWorld());
  EXPECT_THAT(errorOf(replaced(text, "source: generated", "source: gazebo")),
              HasSubstr("test.yaml: source: expected 'generated' or 'barn-dataset'"));
  EXPECT_THAT(errorOf(replaced(text, "seed: 123", "seed: -1")), HasSubstr("test.yaml: seed: expected an unsigned integer or null"));
  EXPECT_THAT(errorOf(replaced(text, "seed: 123", "seed: null")), HasSubstr("test.yaml: seed: a generated world must record its seed"));
  EXPECT_THAT(errorOf(replaced(text, "fill_pct: 0.15", "fill_pct: 1.5")), HasSubstr("test.yaml: generator.fill_pct: must be in [0, 1]"));
  EXPECT_THAT(errorOf(replaced(text, "generator: {fill_pct: 0.15, smooth_iter: 2}", "generator: 3")),
              HasSubstr("test.yaml: generator: expected {fill_pct, smooth_iter}"));
  EXPECT_THAT(errorOf(replaced(text, "start_cell: [15, 0]", "start_cell: [15, 30]")),
              HasSubstr("test.yaml: start_cell: cell [15, 30] is outside the 30 x 30 grid"));
  EXPECT_THAT(errorOf(replaced(text, "goal_cell: [15, 29]", "goal_cell: [15]")), HasSubstr("test.yaml: goal_cell: expected [row, col]"));
  EXPECT_THAT(errorOf(replaced(text, "goal_cell: [15, 29]", "goal_cell: [15, x]")), HasSubstr("test.yaml: goal_cell[1]: expected an integer"));
  EXPECT_THAT(errorOf(replaced(text, "path: [[15, 0], [15, 0]", "path: [[15, 0], [15]")), HasSubstr("test.yaml: path[1]: expected [row, col]"));
  EXPECT_THAT(errorOf(replaced(text, "[15, 0], [15, 1],", "[15, 0], [15, 3],")),
              HasSubstr("test.yaml: path[2]: is not a neighbour of the previous cell"));
  EXPECT_THAT(errorOf(replaced(text, "metrics: {", "metrics: 4\nunused: {")), HasSubstr("test.yaml: metrics: expected a map of the five metrics"));
  EXPECT_THAT(errorOf(replaced(text, "closest_wall: 12, ", "")), HasSubstr("test.yaml: metrics.closest_wall: missing"));
  EXPECT_THAT(errorOf(replaced(text, "format: barnbench-world/1", "format: barnbench-world/2")),
              HasSubstr("test.yaml: format: expected 'barnbench-world/1'"));
  const std::string row = "  - \"000000000000000000000000000000\"\n";
  EXPECT_THAT(errorOf(replaced(text, row, "  - \"0000000000000000000000000000x0\"\n")),
              HasSubstr("test.yaml: grid[1]: character 'x' at column 28 is not 0 or 1"));
  EXPECT_THAT(errorOf(replaced(text, row, "  - [0]\n")), HasSubstr("test.yaml: grid[1]: expected a string of 30 '0'/'1' characters"));
}

TEST(WorldFile, StoresTheBarn2023OptimalTime) {
  const std::string text = formatWorldFile(straightWorld());
  // Path cells along row 15 sit at x = -4.575 + 2.25 = -2.325, y = 5.075 ... 9.425.
  // start (-2, 3) -> (-2.325, 5.075): sqrt(0.325^2 + 2.075^2) = 2.10030
  // along the row: 29 * 0.15 = 4.35; (-2.325, 9.425) -> goal (-2, 13): sqrt(0.325^2 + 3.575^2) = 3.58974
  const double length = std::hypot(0.325, 2.075) + 4.35 + std::hypot(0.325, 3.575);
  EXPECT_NEAR(referencePathLength(straightWorld().path, protocolPreset("barn2023")), length, 1e-12);
  EXPECT_THAT(text, HasSubstr("optimal_time_s: "));
}

TEST(WorldFile, ImportedWorldsHaveNoSeed) {
  WorldSpec w = straightWorld();
  w.source = WorldSource::BarnDataset;
  w.seed.reset();
  const std::string text = formatWorldFile(w);
  EXPECT_THAT(text, HasSubstr("seed: null"));
  EXPECT_FALSE(parseWorldFile(text, "test.yaml").seed.has_value());
}

TEST(WorldFile, RejectsUnknownKeysNamingThem) {
  const std::string text = formatWorldFile(straightWorld()) + "colour: red\n";
  EXPECT_THAT(errorOf(text), HasSubstr("test.yaml: colour: unknown key"));
  const std::string nested = replaced(formatWorldFile(straightWorld()), "smooth_iter: 2}", "smooth_iter: 2, iters: 3}");
  EXPECT_THAT(errorOf(nested), HasSubstr("generator.iters: unknown key"));
}

TEST(WorldFile, RejectsDuplicateKeys) {
  const std::string text = formatWorldFile(straightWorld()) + "id: 5\n";
  EXPECT_THAT(errorOf(text), HasSubstr("test.yaml: id: duplicate key"));
  const std::string nested = replaced(formatWorldFile(straightWorld()), "tortuosity: 1}", "tortuosity: 1, tortuosity: 2}");
  EXPECT_THAT(errorOf(nested), HasSubstr("metrics.tortuosity: duplicate key"));
}

TEST(WorldFile, NamesAMissingNestedFieldOnce) {
  const std::string text = replaced(formatWorldFile(straightWorld()), "fill_pct: 0.15, ", "");
  const std::string message = errorOf(text);
  EXPECT_THAT(message, HasSubstr("generator.fill_pct: missing"));
  EXPECT_EQ(message.find("\ntest.yaml: fill_pct"), std::string::npos) << message;
}

TEST(WorldFile, RejectsWrongTypesNamingTheField) {
  EXPECT_THAT(errorOf(replaced(formatWorldFile(straightWorld()), "id: 7", "id: abc")), HasSubstr("id: expected an integer"));
  EXPECT_THAT(errorOf(replaced(formatWorldFile(straightWorld()), "closest_wall: 12", "closest_wall: far")),
              HasSubstr("metrics.closest_wall: expected a finite number"));
}

TEST(WorldFile, RejectsAGridOfTheWrongSize) {
  const std::string text = formatWorldFile(straightWorld());
  const std::string row = "  - \"000000000000000000000000000000\"\n";
  EXPECT_THAT(errorOf(replaced(text, row, "")), HasSubstr("grid: expected 30 rows, got 29"));
  EXPECT_THAT(errorOf(replaced(text, row, "  - \"00000\"\n")), HasSubstr("expected 30 characters, got 5"));
}

TEST(WorldFile, RejectsAStartCellInsideAnObstacle) {
  WorldSpec w = straightWorld();
  w.grid.at(15, 0) = 1;
  EXPECT_THAT(errorOf(formatWorldFile(w)), HasSubstr("start_cell: lies inside an obstacle cell"));
}

TEST(WorldFile, RejectsAPathThatDisagreesWithItsStoredLength) {
  const std::string text = formatWorldFile(straightWorld());
  const auto at = text.find("path_length_m: ");
  std::string edited = text;
  edited.replace(at, text.find('\n', at) - at, "path_length_m: 9.5");
  EXPECT_THAT(errorOf(edited), HasSubstr("path_length_m: is 9.5 but the path gives"));
}

TEST(WorldFile, ReportsEveryProblemAtOnce) {
  std::string text = replaced(formatWorldFile(straightWorld()), "id: 7", "id: -3");
  text = replaced(text, "format: barnbench-world/1\n", "");
  const std::string message = errorOf(text);
  EXPECT_THAT(message, HasSubstr("id: must be in"));
  EXPECT_THAT(message, HasSubstr("format: missing"));
}

TEST(WorldFile, RejectsTextThatIsNotAWorld) {
  EXPECT_THAT(errorOf("just a string"), HasSubstr("expected a YAML map"));
  EXPECT_THAT(errorOf("a: [unclosed"), HasSubstr("test.yaml: not valid YAML: line 1"));
}

// Line of `needle` in `text`, 1-based, as the error messages count.
int lineOf(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

TEST(WorldFile, AKeyThatIsAListIsAnInputErrorNamingTheLine) {
  const std::string text = formatWorldFile(straightWorld()) + "[1]: 2\n";
  const int line = lineOf(text, "[1]: 2");
  EXPECT_THAT(errorOf(text), HasSubstr("test.yaml: line " + std::to_string(line) +
                                       ": a key is a list or a map, expected a plain name"));
}

TEST(WorldFile, AKeyThatIsAListInsideMetricsNamesTheField) {
  const std::string text = replaced(formatWorldFile(straightWorld()), "norm_metrics: {", "norm_metrics: {[1]: 2, ");
  EXPECT_THAT(errorOf(text), HasSubstr("a key in norm_metrics is a list or a map"));
}

TEST(WorldFile, AGridRowPrefixedWithAQuestionMarkIsAnInputErrorNamingTheLine) {
  // Found by the world-file fuzzer: "? " in place of a row's indentation ends the grid list and
  // starts a top-level entry whose key is a list (the rest of the rows).
  const std::string text = formatWorldFile(straightWorld());
  const std::string row = "  - \"000000000000000000000000000000\"\n";  // rows 1 to 28 are empty
  const std::size_t row3 = text.find(row, text.find(row, text.find(row) + 1) + 1);
  ASSERT_NE(row3, std::string::npos);
  std::string broken = text;
  broken.replace(row3, 2, "? ");
  const int line = lineOf(broken, "? - ");
  const std::string message = errorOf(broken);
  EXPECT_THAT(message, HasSubstr("test.yaml: line " + std::to_string(line) + ": a key is a list or a map"));
  EXPECT_THAT(message, HasSubstr("test.yaml: grid: expected 30 rows"));
}

TEST(WorldFile, AGridBlockWrittenAsAComplexKeyIsAnInputErrorNamingTheLine) {
  // "? grid:" makes the grid block (a map) the key of an entry whose value is null.
  const std::string text = replaced(formatWorldFile(straightWorld()), "\ngrid:", "\n? grid:");
  const int line = lineOf(text, "? grid:");
  const std::string message = errorOf(text);
  EXPECT_THAT(message, HasSubstr("test.yaml: line " + std::to_string(line) + ": a key is a list or a map"));
  EXPECT_THAT(message, HasSubstr("test.yaml: grid: missing"));
  EXPECT_THAT(message, ::testing::Not(HasSubstr("bad conversion")));
}

}  // namespace
}  // namespace barn::core
