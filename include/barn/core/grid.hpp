#pragma once
/// Cells and small occupancy grids (the BARN 30 x 30 lattice and its C-space).

#include <cstdint>
#include <string>
#include <vector>

namespace barn::core {

/// BARN's obstacle field: 30 x 30 cells of 0.15 m.
inline constexpr int kBarnGridSize = 30;
inline constexpr double kBarnCellSize = 0.15;  // [m]

/// A grid cell. Row r runs along world x, column c along world y (the driving direction).
struct Cell {
  int row = 0;  // [-]
  int col = 0;  // [-]
  friend bool operator==(const Cell&, const Cell&) = default;
};

/// A dense row-major grid of 0/1 (or small integer) values; 1 means blocked.
class Grid {
 public:
  Grid() = default;
  Grid(int rows, int cols, std::int8_t fill = 0) : rows_(rows), cols_(cols), cells_(static_cast<std::size_t>(rows * cols), fill) {}

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  bool inBounds(int r, int c) const { return r >= 0 && r < rows_ && c >= 0 && c < cols_; }
  bool inBounds(Cell cell) const { return inBounds(cell.row, cell.col); }

  std::int8_t at(int r, int c) const { return cells_[index(r, c)]; }
  std::int8_t& at(int r, int c) { return cells_[index(r, c)]; }
  std::int8_t at(Cell cell) const { return at(cell.row, cell.col); }

  /// Number of cells with a non-zero value.
  int countFilled() const;

  /// Rows as strings of '0' and '1' (row 0 first); the world-file representation.
  std::vector<std::string> toRowStrings() const;

  friend bool operator==(const Grid&, const Grid&) = default;

 private:
  std::size_t index(int r, int c) const { return static_cast<std::size_t>(r * cols_ + c); }

  int rows_ = 0;
  int cols_ = 0;
  std::vector<std::int8_t> cells_;  // (rows x cols), row-major
};

}  // namespace barn::core
