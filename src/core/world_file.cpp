#include "barn/core/world_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/text_io.hpp"

namespace barn::core {

std::string_view toString(WorldSource source) {
  switch (source) {
    case WorldSource::Generated: return "generated";
    case WorldSource::BarnDataset: return "barn-dataset";
  }
  return "unknown";
}

std::string worldFileName(int id) {
  char name[32];
  std::snprintf(name, sizeof(name), "world_%03d.yaml", id);
  return name;
}

// ---------------------------------------------------------------------------------------------
// The file's fields
//
// WorldFileFields lists the fields once, in file order; WorldSpec holds what they describe. The
// fields that are not plain scalars are small types that read themselves (readConfigValue,
// called by the config reader) and are written by WorldFileWriter in the file's flow style.

namespace {

struct GeneratorFields {
  double fill_pct = 0.0;  // [-]
  int smooth_iter = 0;    // [-]
  template <class V> void visit(V& v) { v("fill_pct", fill_pct); v("smooth_iter", smooth_iter); }
};

struct SeedField {
  std::optional<std::uint64_t> value;  // null for imported worlds
};

// Cells and the grid remember whether they read, so the cross-field checks run only on
// fields that hold something.
struct CellField {
  Cell cell;
  bool read = false;
};

struct PathField {
  std::vector<Cell> cells;
  bool read = false;
};

struct GridField {
  Grid grid;
  bool read = false;
};

struct MetricsField {
  DifficultyMetrics metrics;
};

struct WorldFileFields {
  std::string format;
  int id = 0;
  std::string source;
  SeedField seed;
  GeneratorFields generator;
  CellField start_cell;
  CellField goal_cell;
  // Derived from the path under barn2023 and stored for readers of the file; NaN until read.
  double path_length_m = std::numeric_limits<double>::quiet_NaN();   // [m]
  double optimal_time_s = std::numeric_limits<double>::quiet_NaN();  // [s]
  MetricsField metrics;
  MetricsField norm_metrics;
  PathField path;
  GridField grid;

  template <class V> void visit(V& v) {
    v("format", format); v("id", id); v("source", source); v("seed", seed); v("generator", generator);
    v("start_cell", start_cell); v("goal_cell", goal_cell); v("path_length_m", path_length_m);
    v("optimal_time_s", optimal_time_s); v("metrics", metrics); v("norm_metrics", norm_metrics);
    v("path", path); v("grid", grid);
  }
};

WorldFileFields fieldsOf(const WorldSpec& world) {
  const Protocol protocol = protocolPreset(ProtocolName::Barn2023);
  WorldFileFields f;
  f.format = kWorldFormat;
  f.id = world.id;
  f.source = std::string(toString(world.source));
  f.seed.value = world.seed;
  f.generator = {world.fill_pct, world.smooth_iter};
  f.start_cell = {world.start_cell, true};
  f.goal_cell = {world.goal_cell, true};
  f.path_length_m = referencePathLength(world.path, protocol);
  f.optimal_time_s = optimalTime(world.path, protocol);
  f.metrics.metrics = world.metrics;
  f.norm_metrics.metrics = world.norm_metrics;
  f.path = {world.path, true};
  f.grid = {world.grid, true};
  return f;
}

// ---------------------------------------------------------------------------------------------
// Writing

// One "key: value" line per field; maps and cells in flow style, the grid as a block list of
// quoted rows (one line per row, so a diff shows the changed row).
class WorldFileWriter {
 public:
  template <class T>
  void operator()(const char* key, const T& value) {
    text_ += std::string(key) + ":" + valueText(value) + "\n";
  }

  const std::string& text() const { return text_; }

 private:
  // A flow map "{key: value, ...}" of a field list.
  class FlowMap {
   public:
    template <class T>
    void operator()(const char* key, const T& value) {
      text_ += std::string(text_.size() > 1 ? ", " : "") + key + ":" + valueText(value);
    }
    std::string text() const { return text_ + "}"; }

   private:
    std::string text_ = "{";
  };

  static std::string valueText(const std::string& value) { return " " + value; }
  static std::string valueText(int value) { return " " + std::to_string(value); }
  static std::string valueText(double value) { return " " + formatDouble(value); }
  static std::string valueText(const SeedField& seed) {
    return " " + (seed.value ? std::to_string(*seed.value) : std::string("null"));
  }
  static std::string cellText(Cell cell) { return "[" + std::to_string(cell.row) + ", " + std::to_string(cell.col) + "]"; }
  static std::string valueText(const CellField& cell) { return " " + cellText(cell.cell); }
  static std::string valueText(const PathField& path) {
    std::string text = " [";
    for (std::size_t i = 0; i < path.cells.size(); ++i) text += (i ? ", " : "") + cellText(path.cells[i]);
    return text + "]";
  }
  static std::string valueText(const GridField& grid) {
    std::string text;
    for (const std::string& row : grid.grid.toRowStrings()) text += "\n  - \"" + row + "\"";
    return text;
  }
  static std::string valueText(const GeneratorFields& generator) {
    FlowMap map;
    visitConst(generator, map);
    return " " + map.text();
  }
  static std::string valueText(const MetricsField& field) {
    FlowMap map;
    const auto values = field.metrics.toArray();
    for (std::size_t k = 0; k < values.size(); ++k) map(std::string(DifficultyMetrics::kNames[k]).c_str(), values[k]);
    return " " + map.text();
  }

  std::string text_;
};

}  // namespace

std::string formatWorldFile(const WorldSpec& world) {
  WorldFileWriter writer;
  fieldsOf(world).visit(writer);
  return "# barnbench world file. Grid row r runs along world x, column c along y (the driving\n"
         "# direction); '1' = obstacle cell of 0.15 m, centred at (-4.425 + 0.15 r, 5.175 + 0.15 c) m.\n"
         "# path: A* cells (row, col) on the C-space, start duplicated as in BARN.\n"
         "# path_length_m / optimal_time_s: run.py's reference under the barn2023 protocol\n"
         "# (start (-2, 3) -> path cells at (-4.575 + 0.15 r, 5.075 + 0.15 c) -> goal (-2, 13); OT = L / 2 m/s).\n" +
         writer.text();
}

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

bool readWholeNumber(const ConfigNode& node, Errors& errors, int& value) {
  if (node.read(value)) return true;
  std::string text;
  errors.add(node.where(), "expected an integer" + (node.read(text) ? ", got '" + text + "'" : std::string()));
  return false;
}

// [row, col] inside the 30 x 30 grid.
bool readCell(const ConfigNode& node, Errors& errors, Cell& cell) {
  if (!node.isSequence() || node.size() != 2) {
    errors.add(node.where(), "expected [row, col]");
    return false;
  }
  int r = 0, c = 0;
  if (!readWholeNumber(node.element(0), errors, r) || !readWholeNumber(node.element(1), errors, c)) return false;
  if (!errors.check(r >= 0 && r < kBarnGridSize && c >= 0 && c < kBarnGridSize, node.where(),
                    "cell [" + std::to_string(r) + ", " + std::to_string(c) + "] is outside the 30 x 30 grid"))
    return false;
  cell = {r, c};
  return true;
}

void readConfigValue(const ConfigNode& node, CellField& field, Errors& errors) {
  field.read = readCell(node, errors, field.cell);
}

void readConfigValue(const ConfigNode& node, PathField& field, Errors& errors) {
  if (!node.isSequence()) {
    errors.add(node.where(), "expected a list of [row, col] cells");
    return;
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    Cell cell;
    if (!readCell(node.element(i), errors, cell)) return;  // the first bad cell is enough
    field.cells.push_back(cell);
  }
  field.read = true;
}

void readConfigValue(const ConfigNode& node, SeedField& field, Errors& errors) {
  if (node.isNull()) return;  // an imported world
  std::uint64_t seed = 0;
  if (errors.check(node.read(seed), node.where(), "expected an unsigned integer or null")) field.value = seed;
}

void readConfigValue(const ConfigNode& node, MetricsField& field, Errors& errors) {
  if (!node.isMap()) {
    errors.add(node.where(), "expected a map of the five metrics");
    return;
  }
  ConfigReader reader(node, errors, MissingKeys::Error);
  std::array<double, 5> values{};
  for (std::size_t k = 0; k < values.size(); ++k) reader(std::string(DifficultyMetrics::kNames[k]).c_str(), values[k]);
  reader.finish();
  field.metrics = DifficultyMetrics::fromArray(values);
}

// The grid row `r` ("0101..."), or false with the problem recorded.
bool readGridRow(const ConfigNode& node, Errors& errors, Grid& grid, int r) {
  std::string text;
  if (!node.read(text)) {
    errors.add(node.where(), "expected a string of 30 '0'/'1' characters");
    return false;
  }
  if (!errors.check(text.size() == static_cast<std::size_t>(kBarnGridSize), node.where(),
                    "expected 30 characters, got " + std::to_string(text.size())))
    return false;
  for (int c = 0; c < kBarnGridSize; ++c) {
    const char ch = text[static_cast<std::size_t>(c)];
    if (ch != '0' && ch != '1')
      return errors.check(false, node.where(), std::string("character '") + ch + "' at column " + std::to_string(c) + " is not 0 or 1");
    grid.at(r, c) = ch == '1';
  }
  return true;
}

void readConfigValue(const ConfigNode& node, GridField& field, Errors& errors) {
  if (!node.isSequence()) {
    errors.add(node.where(), "expected a list of 30 row strings");
    return;
  }
  if (!errors.check(node.size() == static_cast<std::size_t>(kBarnGridSize), node.where(),
                    "expected 30 rows, got " + std::to_string(node.size())))
    return;
  field.grid = Grid(kBarnGridSize, kBarnGridSize);
  bool ok = true;
  for (int r = 0; r < kBarnGridSize; ++r) ok = readGridRow(node.element(static_cast<std::size_t>(r)), errors, field.grid, r) && ok;
  field.read = ok;
}

void readConfigValue(const ConfigNode& node, GeneratorFields& generator, Errors& errors) {
  if (!node.isMap()) {
    errors.add(node.where(), "expected {fill_pct, smooth_iter}");
    return;
  }
  ConfigReader reader(node, errors, MissingKeys::Error);
  generator.visit(reader);
  reader.finish();
}
bool isAdjacentStep(Cell a, Cell b) {
  return std::abs(a.row - b.row) <= 1 && std::abs(a.col - b.col) <= 1 && !(a == b);
}

// Range checks of the scalar fields.
void validateScalars(const WorldFileFields& f, const ConfigNode& root, Errors& errors) {
  if (root.has("format")) errors.check(f.format == kWorldFormat, root.where("format"), std::string("expected '") + kWorldFormat + "'");
  if (root.has("id")) errors.check(f.id >= 0 && f.id < 1000000, root.where("id"), "must be in [0, 1000000)");
  if (root.has("source"))
    errors.check(f.source == toString(WorldSource::Generated) || f.source == toString(WorldSource::BarnDataset),
                 root.where("source"), "expected 'generated' or 'barn-dataset'");
  if (root.has("seed"))
    errors.check(f.source != toString(WorldSource::Generated) || f.seed.value.has_value(), root.where("seed"),
                 "a generated world must record its seed");
  if (root.child("generator").has("fill_pct"))
    errors.check(f.generator.fill_pct >= 0.0 && f.generator.fill_pct <= 1.0, root.where("generator.fill_pct"),
                 "must be in [0, 1]");
  if (root.child("generator").has("smooth_iter"))
    errors.check(f.generator.smooth_iter >= 0 && f.generator.smooth_iter <= 100, root.where("generator.smooth_iter"),
                 "must be in [0, 100]");
}

// Cross-field checks, on a grid, cells, path and numbers that all read.
void validateWorld(const WorldSpec& world, double stored_length, double stored_time, const ConfigNode& root, Errors& errors) {
  errors.check(world.grid.at(world.start_cell) == 0, root.where("start_cell"), "lies inside an obstacle cell");
  errors.check(world.grid.at(world.goal_cell) == 0, root.where("goal_cell"), "lies inside an obstacle cell");
  if (!errors.check(world.path.size() >= 2, root.where("path"), "needs at least the duplicated start cell and the goal"))
    return;
  errors.check(world.path.front() == world.start_cell && world.path[1] == world.start_cell, root.where("path"),
               "must begin with start_cell twice (BARN's duplicated start)");
  errors.check(world.path.back() == world.goal_cell, root.where("path"), "must end at goal_cell");
  for (std::size_t i = 2; i < world.path.size(); ++i) {
    if (!isAdjacentStep(world.path[i - 1], world.path[i])) {
      errors.add(root.where("path[" + std::to_string(i) + "]"), "is not a neighbour of the previous cell");
      break;
    }
    if (world.grid.at(world.path[i])) {
      errors.add(root.where("path[" + std::to_string(i) + "]"), "lies inside an obstacle cell");
      break;
    }
  }
  // The derived numbers must agree with the path: a mismatch means a hand-edited file.
  const Protocol protocol = protocolPreset(ProtocolName::Barn2023);
  const double length = referencePathLength(world.path, protocol);
  errors.check(std::abs(length - stored_length) <= 1e-9 * std::max(1.0, length), root.where("path_length_m"),
               "is " + formatDouble(stored_length) + " but the path gives " + formatDouble(length));
  const double time = optimalTime(world.path, protocol);
  errors.check(std::abs(time - stored_time) <= 1e-9 * std::max(1.0, time), root.where("optimal_time_s"),
               "is " + formatDouble(stored_time) + " but the path gives " + formatDouble(time));
}

WorldSpec worldOf(const WorldFileFields& f) {
  WorldSpec world;
  world.id = f.id;
  world.source = f.source == toString(WorldSource::BarnDataset) ? WorldSource::BarnDataset : WorldSource::Generated;
  world.seed = f.seed.value;
  world.fill_pct = f.generator.fill_pct;
  world.smooth_iter = f.generator.smooth_iter;
  world.grid = f.grid.grid;
  world.start_cell = f.start_cell.cell;
  world.goal_cell = f.goal_cell.cell;
  world.path = f.path.cells;
  world.metrics = f.metrics.metrics;
  world.norm_metrics = f.norm_metrics.metrics;
  return world;
}

// Every field is required: a world file is data, not a config with defaults.
WorldSpec readWorld(const ConfigNode& root) {
  if (!root.isMap()) throw InputError(root.source() + ": expected a YAML map (a barnbench world file)");
  Errors errors;
  WorldFileFields fields;
  ConfigReader reader(root, errors, MissingKeys::Error);
  fields.visit(reader);
  reader.finish();
  validateScalars(fields, root, errors);
  const WorldSpec world = worldOf(fields);
  const bool geometry_read = fields.grid.read && fields.start_cell.read && fields.goal_cell.read && fields.path.read &&
                             std::isfinite(fields.path_length_m) && std::isfinite(fields.optimal_time_s);
  if (geometry_read) validateWorld(world, fields.path_length_m, fields.optimal_time_s, root, errors);
  errors.throwIfAny();
  return world;
}

}  // namespace

WorldSpec parseWorldFile(const std::string& text, const std::string& source_name) {
  return readWorld(ConfigNode::parseString(text, source_name));
}

WorldSpec readWorldFile(const std::filesystem::path& path) {
  return parseWorldFile(readTextFile(path), path.string());
}

std::vector<WorldSpec> readWorldSet(const std::filesystem::path& dir, std::vector<std::string>* skipped) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw InputError(dir.string() + ": not a folder of world files");
  checkNoInterruptedWrite(dir);
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.rfind("world_", 0) == 0 && entry.path().extension() == ".yaml")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());  // so the first problem reported does not depend on the file system
  if (files.empty()) throw InputError(dir.string() + ": no world_*.yaml files");
  std::vector<WorldSpec> worlds;
  for (const auto& file : files) {
    try {
      WorldSpec world = readWorldFile(file);
      // world_NNN.yaml names world NNN: a file renamed by hand would run as another world.
      const std::string stem = file.stem().string().substr(6);
      long long named = -1;
      const auto [end, error] = std::from_chars(stem.data(), stem.data() + stem.size(), named);
      if (!stem.empty() && error == std::errc() && end == stem.data() + stem.size() && named != world.id)
        throw InputError(file.string() + ": id: " + std::to_string(world.id) + ", but the file's name says world " +
                         std::to_string(named));
      worlds.push_back(std::move(world));
    } catch (const InputError& e) {
      if (!skipped) throw;
      skipped->push_back(e.what());
    }
  }
  std::sort(worlds.begin(), worlds.end(), [](const WorldSpec& a, const WorldSpec& b) { return a.id < b.id; });
  for (std::size_t i = 1; i < worlds.size(); ++i) {
    if (worlds[i].id == worlds[i - 1].id)
      throw InputError(dir.string() + ": two world files have id " + std::to_string(worlds[i].id));
  }
  return worlds;
}

std::string formatWorldIndex(const std::vector<WorldSpec>& worlds) {
  const Protocol protocol = protocolPreset(ProtocolName::Barn2023);
  std::ostringstream out;
  out << "id,file,source,seed,fill_pct,smooth_iter,filled_cells,start_row,goal_row,path_cells,"
         "path_length_m,optimal_time_s";
  for (auto name : DifficultyMetrics::kNames) out << "," << name;
  for (auto name : DifficultyMetrics::kNames) out << ",norm_" << name;
  out << "\n";
  for (const WorldSpec& w : worlds) {
    out << w.id << "," << worldFileName(w.id) << "," << toString(w.source) << ","
        << (w.seed ? std::to_string(*w.seed) : std::string()) << "," << formatDouble(w.fill_pct) << ","
        << w.smooth_iter << "," << w.grid.countFilled() << "," << w.start_cell.row << "," << w.goal_cell.row << ","
        << w.path.size() << "," << formatDouble(referencePathLength(w.path, protocol)) << ","
        << formatDouble(optimalTime(w.path, protocol));
    for (double v : w.metrics.toArray()) out << "," << formatDouble(v);
    for (double v : w.norm_metrics.toArray()) out << "," << formatDouble(v);
    out << "\n";
  }
  return out.str();
}

std::vector<FileContent> worldSetFiles(const std::vector<WorldSpec>& worlds) {
  std::vector<FileContent> files;
  files.reserve(worlds.size() + 1);
  for (const WorldSpec& w : worlds) files.push_back({worldFileName(w.id), formatWorldFile(w)});
  files.push_back({"index.csv", formatWorldIndex(worlds)});
  return files;
}

}  // namespace barn::core
