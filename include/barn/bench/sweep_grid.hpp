#pragma once
/// A sweep's grid: controller config keys and their values, every combination one cell (one
/// run record in a folder of its own), and `sweep.yaml`, which names them so that a sweep can
/// be resumed, sharded and merged by any front end.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/config.hpp"

namespace barn::bench {

/// One swept parameter: a key of the controller config (relative to its type block, or with the
/// type's name in front) and its values, as YAML scalars.
struct SweepParameter {
  std::string key;
  std::vector<std::string> values;
  template <class V> void visit(V& v) { v("key", key); v("values", values); }
};

/// Parses "KEY=V1,V2,..." (--param); InputError naming the text if malformed.
SweepParameter parseSweepParameter(const std::string& text);

struct SweepGrid {
  std::string controller;                  // as given to --controller
  std::vector<SweepParameter> parameters;  // no key twice
  std::vector<std::string> cells;          // folder names, in grid order (last parameter fastest)
  /// sweep.yaml's fields.
  template <class V> void visit(V& v) { v("controller", controller); v("parameters", parameters); v("cells", cells); }
};

/// The grid of `parameters` (InputError if a key is given twice or there are too many cells).
SweepGrid makeSweepGrid(const std::string& controller, std::vector<SweepParameter> parameters);

/// The values of cell `index` of the grid, one per parameter.
std::vector<std::string> cellValues(const SweepGrid& grid, std::size_t index);

/// The controller config of cell `index`: `base` (whose `type` names the block) with the cell's
/// values set.
core::ConfigNode cellConfig(const SweepGrid& grid, const core::ConfigNode& base, std::size_t index);

inline constexpr const char* kSweepFile = "sweep.yaml";

/// sweep.yaml's text, and the grid read back from a sweep folder's sweep.yaml (InputError
/// naming the file and field if it is malformed, if its cells are not the grid of its
/// parameters — a cell folder is never taken from the file unchecked — or if a write into the
/// folder was interrupted).
std::string formatSweepFile(const SweepGrid& grid);
SweepGrid readSweepFile(const std::filesystem::path& sweep_dir);
/// readSweepFile of sweep.yaml's text, `source` naming it.
SweepGrid parseSweepFile(const std::string& text, const std::string& source);

}  // namespace barn::bench
