#include "barn/core/world_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

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
// Writing

namespace {

std::string cellText(Cell cell) { return "[" + std::to_string(cell.row) + ", " + std::to_string(cell.col) + "]"; }

std::string metricsText(const DifficultyMetrics& m) {
  std::string text = "{";
  const auto values = m.toArray();
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k) text += ", ";
    text += std::string(DifficultyMetrics::kNames[k]) + ": " + formatDouble(values[k]);
  }
  return text + "}";
}

}  // namespace

std::string formatWorldFile(const WorldSpec& world) {
  const Protocol protocol = protocolPreset(ProtocolName::Barn2023);
  std::ostringstream out;
  out << "# barnbench world file. Grid row r runs along world x, column c along y (the driving\n"
         "# direction); '1' = obstacle cell of 0.15 m, centred at (-4.425 + 0.15 r, 5.175 + 0.15 c) m.\n"
         "# path: A* cells (row, col) on the C-space, start duplicated as in BARN.\n"
         "# path_length_m / optimal_time_s: run.py's reference under the barn2023 protocol\n"
         "# (start (-2, 3) -> path cells at (-4.575 + 0.15 r, 5.075 + 0.15 c) -> goal (-2, 13); OT = L / 2 m/s).\n";
  out << "format: " << kWorldFormat << "\n";
  out << "id: " << world.id << "\n";
  out << "source: " << toString(world.source) << "\n";
  out << "seed: " << (world.seed ? std::to_string(*world.seed) : std::string("null")) << "\n";
  out << "generator: {fill_pct: " << formatDouble(world.fill_pct) << ", smooth_iter: " << world.smooth_iter << "}\n";
  out << "start_cell: " << cellText(world.start_cell) << "\n";
  out << "goal_cell: " << cellText(world.goal_cell) << "\n";
  out << "path_length_m: " << formatDouble(referencePathLength(world.path, protocol)) << "\n";
  out << "optimal_time_s: " << formatDouble(optimalTime(world.path, protocol)) << "\n";
  out << "metrics: " << metricsText(world.metrics) << "\n";
  out << "norm_metrics: " << metricsText(world.norm_metrics) << "\n";
  out << "path: [";
  for (std::size_t i = 0; i < world.path.size(); ++i) out << (i ? ", " : "") << cellText(world.path[i]);
  out << "]\n";
  out << "grid:\n";
  for (const std::string& row : world.grid.toRowStrings()) out << "  - \"" << row << "\"\n";
  return out.str();
}

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

// "line 12" (1-based) for error messages; yaml-cpp counts lines from 0.
std::string lineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? std::string("unknown line") : "line " + std::to_string(mark.line + 1);
}

// "line 3, column 7: message" for a yaml-cpp exception, or just the message if it has no position.
std::string describeYamlError(const YAML::Exception& e) {
  if (e.mark.is_null()) return e.msg;
  return "line " + std::to_string(e.mark.line + 1) + ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg;
}

// Strict field access on a YAML map: every failure is recorded in `errors` with its key path.
class FieldReader {
 public:
  FieldReader(const YAML::Node& map, Errors& errors) : map_(map), errors_(errors) {}

  const YAML::Node* get(const std::string& key) {
    seen_.insert(key);
    const YAML::Node node = map_[key];
    if (!node) {
      errors_.add(key, "missing");
      return nullptr;
    }
    nodes_[key] = node;
    return &nodes_[key];
  }

  void markSeen(const std::string& key) { seen_.insert(key); }

  // yaml-cpp keeps the first of two equal keys and drops the second silently; both are errors.
  void rejectUnknownKeys(const std::string& prefix = {}) {
    std::set<std::string> listed;
    for (const auto& item : map_) {
      // A list or map as a key (`[1]: 2`, or a grid row written `? - "0101..."`, which ends the
      // grid list and makes the rows after it a key) has no name to look up or report;
      // yaml-cpp's as<std::string>() would throw a bare "bad conversion" naming neither file
      // nor line.
      if (!item.first.IsScalar()) {
        const std::string owner = prefix.empty() ? "a key" : "a key in " + prefix.substr(0, prefix.size() - 1);
        errors_.add(lineOf(item.first), owner + " is a list or a map, expected a plain name");
        continue;
      }
      const std::string key = item.first.Scalar();
      if (!listed.insert(key).second) errors_.add(prefix + key, "duplicate key");
      else if (!seen_.count(key)) errors_.add(prefix + key, "unknown key");
    }
  }

 private:
  YAML::Node map_;
  Errors& errors_;
  std::set<std::string> seen_;
  std::map<std::string, YAML::Node> nodes_;
};

bool readInt(const YAML::Node& node, const std::string& field, Errors& errors, long long& value) {
  if (!node.IsScalar()) return errors.check(false, field, "expected an integer");
  const std::string text = node.Scalar();
  std::size_t used = 0;
  try {
    value = std::stoll(text, &used);
  } catch (...) {
    used = 0;
  }
  return errors.check(used == text.size() && !text.empty(), field, "expected an integer, got '" + text + "'");
}

bool readDouble(const YAML::Node& node, const std::string& field, Errors& errors, double& value) {
  if (!node.IsScalar()) return errors.check(false, field, "expected a number");
  const std::string text = node.Scalar();
  return errors.check(parseDouble(text, value) && std::isfinite(value), field,
                      "expected a finite number, got '" + text + "'");
}

bool readCell(const YAML::Node& node, const std::string& field, Errors& errors, Cell& cell) {
  if (!node.IsSequence() || node.size() != 2) return errors.check(false, field, "expected [row, col]");
  long long r = 0, c = 0;
  if (!readInt(node[0], field + "[0]", errors, r) || !readInt(node[1], field + "[1]", errors, c)) return false;
  if (!errors.check(r >= 0 && r < kBarnGridSize && c >= 0 && c < kBarnGridSize, field,
                    "cell [" + std::to_string(r) + ", " + std::to_string(c) + "] is outside the 30 x 30 grid"))
    return false;
  cell = {static_cast<int>(r), static_cast<int>(c)};
  return true;
}

bool readMetrics(const YAML::Node& node, const std::string& field, Errors& errors, DifficultyMetrics& metrics) {
  if (!node.IsMap()) return errors.check(false, field, "expected a map of the five metrics");
  std::array<double, 5> values{};
  bool ok = true;
  FieldReader reader(node, errors);
  for (std::size_t k = 0; k < values.size(); ++k) {
    reader.markSeen(std::string(DifficultyMetrics::kNames[k]));
    const std::string key(DifficultyMetrics::kNames[k]);
    const YAML::Node value = node[key];
    if (!value) {
      errors.add(field + "." + key, "missing");
      ok = false;
      continue;
    }
    ok = readDouble(value, field + "." + key, errors, values[k]) && ok;
  }
  const std::size_t before = errors.messages().size();
  reader.rejectUnknownKeys(field + ".");
  ok = ok && errors.messages().size() == before;
  metrics = DifficultyMetrics::fromArray(values);
  return ok;
}

bool readGrid(const YAML::Node& node, Errors& errors, Grid& grid) {
  if (!node.IsSequence()) return errors.check(false, "grid", "expected a list of 30 row strings");
  if (!errors.check(node.size() == static_cast<std::size_t>(kBarnGridSize), "grid",
                    "expected 30 rows, got " + std::to_string(node.size())))
    return false;
  grid = Grid(kBarnGridSize, kBarnGridSize);
  bool ok = true;
  for (int r = 0; r < kBarnGridSize; ++r) {
    const std::string field = "grid[" + std::to_string(r) + "]";
    const YAML::Node row = node[static_cast<std::size_t>(r)];
    if (!row.IsScalar()) {
      ok = errors.check(false, field, "expected a string of 30 '0'/'1' characters");
      continue;
    }
    const std::string text = row.Scalar();
    if (!errors.check(text.size() == static_cast<std::size_t>(kBarnGridSize), field,
                      "expected 30 characters, got " + std::to_string(text.size()))) {
      ok = false;
      continue;
    }
    for (int c = 0; c < kBarnGridSize; ++c) {
      const char ch = text[static_cast<std::size_t>(c)];
      if (ch != '0' && ch != '1') {
        ok = errors.check(false, field, std::string("character '") + ch + "' at column " + std::to_string(c) + " is not 0 or 1");
        break;
      }
      grid.at(r, c) = ch == '1';
    }
  }
  return ok;
}

bool isAdjacentStep(Cell a, Cell b) {
  return std::abs(a.row - b.row) <= 1 && std::abs(a.col - b.col) <= 1 && !(a == b);
}

// Cross-field checks once every field parsed.
void validateWorld(const WorldSpec& world, double stored_length, double stored_time, Errors& errors) {
  errors.check(world.grid.at(world.start_cell) == 0, "start_cell", "lies inside an obstacle cell");
  errors.check(world.grid.at(world.goal_cell) == 0, "goal_cell", "lies inside an obstacle cell");
  if (!errors.check(world.path.size() >= 2, "path", "needs at least the duplicated start cell and the goal"))
    return;
  errors.check(world.path.front() == world.start_cell && world.path[1] == world.start_cell, "path",
               "must begin with start_cell twice (BARN's duplicated start)");
  errors.check(world.path.back() == world.goal_cell, "path", "must end at goal_cell");
  for (std::size_t i = 2; i < world.path.size(); ++i) {
    if (!isAdjacentStep(world.path[i - 1], world.path[i])) {
      errors.add("path[" + std::to_string(i) + "]", "is not a neighbour of the previous cell");
      break;
    }
    if (world.grid.at(world.path[i])) {
      errors.add("path[" + std::to_string(i) + "]", "lies inside an obstacle cell");
      break;
    }
  }
  // The derived numbers must agree with the path: a mismatch means a hand-edited file.
  const Protocol protocol = protocolPreset(ProtocolName::Barn2023);
  const double length = referencePathLength(world.path, protocol);
  errors.check(std::abs(length - stored_length) <= 1e-9 * std::max(1.0, length), "path_length_m",
               "is " + formatDouble(stored_length) + " but the path gives " + formatDouble(length));
  const double time = optimalTime(world.path, protocol);
  errors.check(std::abs(time - stored_time) <= 1e-9 * std::max(1.0, time), "optimal_time_s",
               "is " + formatDouble(stored_time) + " but the path gives " + formatDouble(time));
}

WorldSpec readWorldNode(const YAML::Node& root, const std::string& source_name) {
  Errors errors(source_name);
  if (!root.IsMap()) throw InputError(source_name + ": expected a YAML map (a barnbench world file)");

  WorldSpec world;
  FieldReader fields(root, errors);
  if (const auto* node = fields.get("format")) {
    const bool ok = node->IsScalar() && node->Scalar() == kWorldFormat;
    errors.check(ok, "format", std::string("expected '") + kWorldFormat + "'");
  }
  long long integer = 0;
  if (const auto* node = fields.get("id"); node && readInt(*node, "id", errors, integer)) {
    if (errors.check(integer >= 0 && integer < 1000000, "id", "must be in [0, 1000000)")) world.id = static_cast<int>(integer);
  }
  if (const auto* node = fields.get("source")) {
    const std::string value = node->IsScalar() ? node->Scalar() : "";
    if (value == "generated") {
      world.source = WorldSource::Generated;
    } else if (value == "barn-dataset") {
      world.source = WorldSource::BarnDataset;
    } else {
      errors.add("source", "expected 'generated' or 'barn-dataset'");
    }
  }
  if (const auto* node = fields.get("seed")) {
    if (!(node->IsNull())) {
      const std::string value = node->IsScalar() ? node->Scalar() : "";
      std::size_t used = 0;
      unsigned long long seed = 0;
      try {
        seed = std::stoull(value, &used);
      } catch (...) {
        used = 0;
      }
      if (errors.check(!value.empty() && used == value.size() && value[0] != '-', "seed",
                       "expected an unsigned integer or null"))
        world.seed = seed;
    }
    errors.check(world.source != WorldSource::Generated || world.seed.has_value(), "seed",
                 "a generated world must record its seed");
  }
  if (const auto* node = fields.get("generator")) {
    if (!node->IsMap()) {
      errors.add("generator", "expected {fill_pct, smooth_iter}");
    } else {
      FieldReader generator(*node, errors);
      double fill = 0.0;
      if (const YAML::Node f = (*node)["fill_pct"]; f && readDouble(f, "generator.fill_pct", errors, fill)) {
        if (errors.check(fill >= 0.0 && fill <= 1.0, "generator.fill_pct", "must be in [0, 1]")) world.fill_pct = fill;
      } else if (!f) {
        errors.add("generator.fill_pct", "missing");
      }
      if (const YAML::Node s = (*node)["smooth_iter"]; s && readInt(s, "generator.smooth_iter", errors, integer)) {
        if (errors.check(integer >= 0 && integer <= 100, "generator.smooth_iter", "must be in [0, 100]"))
          world.smooth_iter = static_cast<int>(integer);
      } else if (!s) {
        errors.add("generator.smooth_iter", "missing");
      }
      generator.markSeen("fill_pct");
      generator.markSeen("smooth_iter");
      generator.rejectUnknownKeys("generator.");
    }
  }
  const bool grid_ok = [&] { const auto* node = fields.get("grid"); return node && readGrid(*node, errors, world.grid); }();
  bool cells_ok = true;
  if (const auto* node = fields.get("start_cell")) cells_ok = readCell(*node, "start_cell", errors, world.start_cell) && cells_ok; else cells_ok = false;
  if (const auto* node = fields.get("goal_cell")) cells_ok = readCell(*node, "goal_cell", errors, world.goal_cell) && cells_ok; else cells_ok = false;
  if (const auto* node = fields.get("path")) {
    if (!node->IsSequence()) {
      errors.add("path", "expected a list of [row, col] cells");
      cells_ok = false;
    } else {
      for (std::size_t i = 0; i < node->size(); ++i) {
        Cell cell;
        if (!readCell((*node)[i], "path[" + std::to_string(i) + "]", errors, cell)) {
          cells_ok = false;
          break;
        }
        world.path.push_back(cell);
      }
    }
  } else {
    cells_ok = false;
  }
  double stored_length = 0.0;
  double stored_time = 0.0;
  bool numbers_ok = true;
  if (const auto* node = fields.get("path_length_m")) numbers_ok = readDouble(*node, "path_length_m", errors, stored_length) && numbers_ok; else numbers_ok = false;
  if (const auto* node = fields.get("optimal_time_s")) numbers_ok = readDouble(*node, "optimal_time_s", errors, stored_time) && numbers_ok; else numbers_ok = false;
  if (const auto* node = fields.get("metrics")) readMetrics(*node, "metrics", errors, world.metrics);
  if (const auto* node = fields.get("norm_metrics")) readMetrics(*node, "norm_metrics", errors, world.norm_metrics);
  fields.rejectUnknownKeys();

  if (grid_ok && cells_ok && numbers_ok) validateWorld(world, stored_length, stored_time, errors);
  errors.throwIfAny();
  return world;
}

}  // namespace

WorldSpec parseWorldFile(const std::string& text, const std::string& source_name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source_name + ": not valid YAML: " + describeYamlError(e));
  }
  // The reader checks every node's type before converting it, so yaml-cpp should not throw
  // here; if a document still trips it, the user gets the file and line, not a bare yaml-cpp
  // message and exit code 1.
  try {
    return readWorldNode(root, source_name);
  } catch (const YAML::Exception& e) {
    throw InputError(source_name + ": " + describeYamlError(e));
  }
}

WorldSpec readWorldFile(const std::filesystem::path& path) {
  return parseWorldFile(readTextFile(path), path.string());
}

std::vector<WorldSpec> readWorldSet(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw InputError(dir.string() + ": not a folder of world files");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.rfind("world_", 0) == 0 && entry.path().extension() == ".yaml")
      files.push_back(entry.path());
  }
  if (files.empty()) throw InputError(dir.string() + ": no world_*.yaml files");
  std::vector<WorldSpec> worlds;
  for (const auto& file : files) worlds.push_back(readWorldFile(file));
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

void writeWorldSet(const std::filesystem::path& dir, const std::vector<WorldSpec>& worlds) {
  std::vector<FileContent> files;
  files.reserve(worlds.size() + 1);
  for (const WorldSpec& w : worlds) files.push_back({worldFileName(w.id), formatWorldFile(w)});
  files.push_back({"index.csv", formatWorldIndex(worlds)});
  writeFilesAtomic(dir, files);
}

}  // namespace barn::core
