#include "barn/core/world_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "barn/core/npy.hpp"

namespace barn::core {
namespace {

namespace fs = std::filesystem;

const fs::path kDatasetDir = fs::path(BARN_SOURCE_DIR) / ".." / "shared" / "barn_dataset";

/// A grid from rows of '0'/'1' (blank lines and indentation ignored); row 0 first.
Grid gridFromText(const std::string& text) {
  std::vector<std::string> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    line.erase(std::remove_if(line.begin(), line.end(), [](char ch) { return ch != '0' && ch != '1'; }), line.end());
    if (!line.empty()) rows.push_back(line);
  }
  Grid grid(static_cast<int>(rows.size()), static_cast<int>(rows.front().size()));
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) grid.at(r, c) = rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] == '1';
  }
  return grid;
}

/// A 30 x 30 grid with rows [0, top) and [30 - bottom, 30) full and nothing else.
Grid bandGrid(int top, int bottom) {
  Grid grid(kBarnGridSize, kBarnGridSize);
  for (int c = 0; c < kBarnGridSize; ++c) {
    for (int r = 0; r < top; ++r) grid.at(r, c) = 1;
    for (int r = kBarnGridSize - bottom; r < kBarnGridSize; ++r) grid.at(r, c) = 1;
  }
  return grid;
}

int countWhere(const std::vector<Eigen::Vector2d>& centres, auto predicate) {
  return static_cast<int>(std::count_if(centres.begin(), centres.end(), predicate));
}

bool near(double a, double b) { return std::abs(a - b) < 1e-9; }

// ---------------------------------------------------------------------------------------------
// Cell centres

TEST(CellCentre, FirstAndLastCellsMatchTheBarnWorldFiles) {
  // (r, c) -> (-4.425 + 0.15 r, 5.175 + 0.15 c).
  EXPECT_NEAR(cellCentre({0, 0}).x(), -4.425, 1e-12);
  EXPECT_NEAR(cellCentre({0, 0}).y(), 5.175, 1e-12);
  // (29, 29): x = -4.425 + 4.35 = -0.075, y = 5.175 + 4.35 = 9.525.
  EXPECT_NEAR(cellCentre({29, 29}).x(), -0.075, 1e-12);
  EXPECT_NEAR(cellCentre({29, 29}).y(), 9.525, 1e-12);
}

TEST(CellCentre, NeighbouringCylindersTouch) {
  // Pitch 0.15 m = 2 * 0.075 m radius: neighbouring cylinders touch, leaving no gap.
  EXPECT_DOUBLE_EQ(2.0 * kCylinderRadius, 0.15);
  for (const Cell cell : {Cell{0, 0}, Cell{14, 7}, Cell{28, 28}}) {
    EXPECT_NEAR((cellCentre({cell.row + 1, cell.col}) - cellCentre(cell)).norm(), 2.0 * kCylinderRadius, 1e-12);
    EXPECT_NEAR((cellCentre({cell.row, cell.col + 1}) - cellCentre(cell)).norm(), 2.0 * kCylinderRadius, 1e-12);
  }
}

// ---------------------------------------------------------------------------------------------
// Containment walls

TEST(ContainmentCylinders, BackWallAndTwoSideWallsMake96) {
  const std::vector<Eigen::Vector2d> walls = containmentCylinders();
  // 30 back-wall cylinders + 2 side walls x 33 = 96.
  EXPECT_EQ(walls.size(), 96u);

  // Back wall: y = 0.075, x = -0.075, -0.225, ..., -0.075 - 0.15 * 29 = -4.425.
  std::vector<double> back_x;
  for (const auto& p : walls) {
    if (near(p.y(), 0.075)) back_x.push_back(p.x());
  }
  ASSERT_EQ(back_x.size(), 30u);
  std::sort(back_x.begin(), back_x.end());
  for (std::size_t i = 0; i < back_x.size(); ++i) EXPECT_NEAR(back_x[i], -4.425 + 0.15 * static_cast<double>(i), 1e-9);

  // Side walls: x = -0.075 and x = -4.425, y = 0.225 ... 0.225 + 0.15 * 32 = 5.025.
  for (const double x : {-0.075, -4.425}) {
    std::vector<double> side_y;
    for (const auto& p : walls) {
      if (near(p.x(), x) && !near(p.y(), 0.075)) side_y.push_back(p.y());
    }
    ASSERT_EQ(side_y.size(), 33u) << "side wall at x = " << x;
    std::sort(side_y.begin(), side_y.end());
    for (std::size_t i = 0; i < side_y.size(); ++i) EXPECT_NEAR(side_y[i], 0.225 + 0.15 * static_cast<double>(i), 1e-9);
  }
}

TEST(ContainmentCylinders, StopBelowTheObstacleFieldAndLeaveTheFarSideOpen) {
  const std::vector<Eigen::Vector2d> walls = containmentCylinders();
  // The field starts at y = 5.175 - 0.075 = 5.1; nothing of the containment goes past it.
  EXPECT_EQ(countWhere(walls, [](const Eigen::Vector2d& p) { return p.y() > 5.1; }), 0);
  // The side walls end one pitch before grid rows 0 and 29 take over: 5.025 + 0.15 = 5.175
  // = cellCentre(row, 0).y, at the same x as rows 0 and 29. The walls are continuous.
  EXPECT_NEAR(cellCentre({0, 0}).x(), -4.425, 1e-12);
  EXPECT_NEAR(cellCentre({29, 0}).x(), -0.075, 1e-12);
  EXPECT_EQ(countWhere(walls, [](const Eigen::Vector2d& p) { return near(p.y(), 5.025); }), 2);
  // Every containment cylinder lies inside the corridor's outer edge x in [-4.425, -0.075].
  EXPECT_EQ(countWhere(walls, [](const Eigen::Vector2d& p) { return p.x() < -4.425 - 1e-9 || p.x() > -0.075 + 1e-9; }), 0);
}

// ---------------------------------------------------------------------------------------------
// Which filled cells get a cylinder

TEST(HasCylinder, BlobInteriorIsHollowAndItsBorderIsNot) {
  const Grid grid = gridFromText(R"(
    00000
    01110
    01110
    01110
    00000
  )");
  EXPECT_FALSE(hasCylinder(grid, {2, 2}));  // all 8 neighbours filled
  EXPECT_TRUE(hasCylinder(grid, {1, 1}));   // corner of the blob
  EXPECT_TRUE(hasCylinder(grid, {1, 2}));   // edge of the blob
  EXPECT_TRUE(hasCylinder(grid, {3, 3}));
  EXPECT_FALSE(hasCylinder(grid, {0, 0}));  // empty cell
  EXPECT_FALSE(hasCylinder(grid, {4, 2}));
}

TEST(HasCylinder, OneMissingDiagonalNeighbourIsEnoughToShow) {
  const Grid grid = gridFromText(R"(
    011
    111
    111
  )");
  // (1, 1): 7 of 8 neighbours filled, the (0, 0) diagonal is open.
  EXPECT_TRUE(hasCylinder(grid, {1, 1}));
}

TEST(HasCylinder, OffMapNeighboursCountAsOpen) {
  const Grid grid = gridFromText(R"(
    11111
    11111
    11111
  )");
  // Every cell of row 0 (and row 2) has off-map neighbours, however full the grid.
  for (int c = 0; c < 5; ++c) {
    EXPECT_TRUE(hasCylinder(grid, {0, c})) << "col " << c;
    EXPECT_TRUE(hasCylinder(grid, {2, c})) << "col " << c;
  }
  // Row 1: the ends touch the left/right map edge; the middle three are hollow.
  EXPECT_TRUE(hasCylinder(grid, {1, 0}));
  EXPECT_TRUE(hasCylinder(grid, {1, 4}));
  for (int c = 1; c <= 3; ++c) EXPECT_FALSE(hasCylinder(grid, {1, c})) << "col " << c;
}

TEST(FieldCylinders, EmptyFieldHasOnlyTheTwoWallRows) {
  // Rows 0 and 29 full, the rest empty: every wall cell borders the empty rows 1 / 28,
  // so 2 x 30 = 60 cylinders.
  const Grid grid = bandGrid(1, 1);
  const std::vector<Eigen::Vector2d> field = fieldCylinders(grid);
  EXPECT_EQ(field.size(), 60u);
  EXPECT_EQ(countWhere(field, [](const Eigen::Vector2d& p) { return near(p.x(), -4.425); }), 30);
  EXPECT_EQ(countWhere(field, [](const Eigen::Vector2d& p) { return near(p.x(), -0.075); }), 30);
  // Field plus containment: 96 + 60 = 156.
  EXPECT_EQ(allCylinders(grid).size(), 156u);
}

TEST(FieldCylinders, ThickWallBandsAreHollowInside) {
  // Rows 0-2 and 27-29 full. Per band: the outer and inner rows show (30 + 30) and the middle
  // row shows only at columns 0 and 29 (off-map side) -> 62; two bands -> 124.
  EXPECT_EQ(fieldCylinders(bandGrid(3, 3)).size(), 124u);
}

TEST(FieldCylinders, BarnDatasetWorld0Has209CylindersInAll) {
  // The official world 0: 156 wall cylinders (96 containment + 60 in rows 0 and 29)
  // + 53 obstacle cylinders = 209.
  const fs::path file = kDatasetDir / "grid_files" / "grid_0.npy";
  if (!fs::exists(file)) GTEST_SKIP() << "BARN dataset not found at " << kDatasetDir << " (needs grid_files/grid_0.npy)";
  const NpyInt64Array array = readNpyInt64(file);
  ASSERT_EQ(array.values.size(), 900u);
  Grid grid(kBarnGridSize, kBarnGridSize);
  for (int r = 0; r < kBarnGridSize; ++r) {
    for (int c = 0; c < kBarnGridSize; ++c)
      grid.at(r, c) = static_cast<std::int8_t>(array.values[static_cast<std::size_t>(r * kBarnGridSize + c)]);
  }
  EXPECT_EQ(fieldCylinders(grid).size(), 60u + 53u);
  EXPECT_EQ(allCylinders(grid).size(), 209u);
}

}  // namespace
}  // namespace barn::core
