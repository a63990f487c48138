#include "barn/bench/sweep_grid.hpp"

#include <sstream>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"

namespace barn::bench {

namespace {

constexpr std::size_t kMaxCells = 10000;

std::string cellName(std::size_t index, const SweepGrid& grid) {
  const std::vector<std::string> values = cellValues(grid, index);
  std::string name = "cell_" + std::to_string(index);
  for (std::size_t k = 0; k < grid.parameters.size(); ++k) name += "_" + grid.parameters[k].key + "=" + values[k];
  for (char& ch : name)
    if (ch == '/' || ch == ' ' || static_cast<unsigned char>(ch) < 0x20) ch = '_';
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
  for (const auto& p : parameters) {
    cells *= p.values.size();  // stops before it could overflow: each factor is below 2^32
    if (cells > kMaxCells || p.values.size() > kMaxCells)
      throw core::InputError("sweep: more than " + std::to_string(kMaxCells) + " cells (too many)");
  }
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

SweepGrid parseSweepFile(const std::string& text, const std::string& source) {
  const SweepGrid read = core::readConfig<SweepGrid>(core::ConfigNode::parseString(text, source));
  core::Errors errors(source);
  errors.check(!read.controller.empty(), "controller", "missing");
  errors.check(!read.parameters.empty(), "parameters", "missing (a sweep has at least one)");
  for (std::size_t k = 0; k < read.parameters.size(); ++k)
    errors.check(!read.parameters[k].key.empty() && !read.parameters[k].values.empty(),
                 "parameters[" + std::to_string(k) + "]", "needs a key and at least one value");
  errors.throwIfAny();
  SweepGrid grid;
  try {
    grid = makeSweepGrid(read.controller, read.parameters);
  } catch (const core::InputError& e) {
    throw core::InputError(source + ": parameters: " + e.what());
  }
  if (grid.cells != read.cells)
    throw core::InputError(source + ": cells: not the cells of its parameters (the file was changed by hand?)");
  return grid;
}

SweepGrid readSweepFile(const std::filesystem::path& sweep_dir) {
  core::checkNoInterruptedWrite(sweep_dir);
  const std::filesystem::path file = sweep_dir / kSweepFile;
  return parseSweepFile(core::readTextFile(file), file.string());
}

}  // namespace barn::bench
