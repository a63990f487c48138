#include "barn/core/grid.hpp"

namespace barn::core {

int Grid::countFilled() const {
  int n = 0;
  for (auto v : cells_) n += (v != 0);
  return n;
}

std::vector<std::string> Grid::toRowStrings() const {
  std::vector<std::string> rows;
  rows.reserve(static_cast<std::size_t>(rows_));
  for (int r = 0; r < rows_; ++r) {
    std::string line(static_cast<std::size_t>(cols_), '0');
    for (int c = 0; c < cols_; ++c) line[static_cast<std::size_t>(c)] = at(r, c) ? '1' : '0';
    rows.push_back(std::move(line));
  }
  return rows;
}

}  // namespace barn::core
