#include "barn/bench/sweep_grid.hpp"

#include <sstream>

#include "barn/core/errors.hpp"

namespace barn::bench {

namespace {

constexpr std::size_t kMaxCells = 10000;

std::string cellName(std::size_t index, const SweepGrid& grid) {
  const std::vector<std::string> values = cellValues(grid, index);
  std::string name = "cell_" + std::to_string(index);
  for (std::size_t k = 0; k < grid.parameters.size(); ++k) name += "_" + grid.parameters[k].key + "=" + values[k];
  for (char& ch : name)
    if (ch == '/' || ch == ' ') ch = '_';
  return name;
}

}  // namespace

SweepParameter parseSweepParameter(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw core::InputError("--param '" + text + "': expected KEY=V1,V2,...");
  SweepParameter p;
  p.key = text.substr(0, eq);
  std::stringstream values(text.substr(eq + 1));
  for (std::string v; std::getline(values, v, ',');) {
    if (v.empty()) throw core::InputError("--param '" + text + "': empty value");
    p.values.push_back(v);
  }
  return p;
}

SweepGrid makeSweepGrid(const std::string& controller, std::vector<SweepParameter> parameters) {
  for (std::size_t i = 0; i < parameters.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (parameters[k].key == parameters[i].key)
        throw core::InputError("--param " + parameters[i].key + ": given twice (list every value in one --param)");
  std::size_t cells = 1;
  for (const auto& p : parameters) cells *= p.values.size();
  if (cells > kMaxCells)
    throw core::InputError("sweep: " + std::to_string(cells) + " cells is too many (at most " + std::to_string(kMaxCells) + ")");
  SweepGrid grid;
  grid.controller = controller;
  grid.parameters = std::move(parameters);
  for (std::size_t c = 0; c < cells; ++c) grid.cells.push_back(cellName(c, grid));
  return grid;
}

std::vector<std::string> cellValues(const SweepGrid& grid, std::size_t index) {
  std::vector<std::string> values(grid.parameters.size());
  for (std::size_t k = grid.parameters.size(); k-- > 0;) {  // odometer, last parameter fastest
    const auto& options = grid.parameters[k].values;
    values[k] = options[index % options.size()];
    index /= options.size();
  }
  return values;
}

core::ConfigNode cellConfig(const SweepGrid& grid, const core::ConfigNode& base, std::size_t index) {
  std::string type;
  base.child("type").read(type);
  core::ConfigNode node = core::ConfigNode::parseString(base.toYaml(), base.source().empty() ? "sweep" : base.source());
  const std::vector<std::string> values = cellValues(grid, index);
  for (std::size_t k = 0; k < grid.parameters.size(); ++k) {
    const std::string& key = grid.parameters[k].key;
    node.set(key.rfind(type + ".", 0) == 0 ? key : type + "." + key, values[k]);
  }
  return node;
}

std::string formatSweepFile(const SweepGrid& grid) {
  return "# barnbench sweep: one run record per cell in the folders below\n" + core::writeConfig(grid);
}

SweepGrid readSweepFile(const std::filesystem::path& sweep_dir) {
  return core::readConfig<SweepGrid>(core::ConfigNode::parseFile(sweep_dir / kSweepFile));
}

}  // namespace barn::bench
