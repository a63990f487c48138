#include "barn/bench/controller_lookup.hpp"

#include <algorithm>

#include "barn/controllers/registry.hpp"
#include "barn/core/errors.hpp"

namespace barn::bench {

namespace fs = std::filesystem;

namespace {

// Levenshtein distance, for "did you mean".
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

void checkControllerName(const std::string& name, const ControllerLookupWords& words) {
  // A path would read any file as a config and write outside results/.
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == ".." || name.front() == '-')
    throw core::InputError(words.name_option + " " + name +
                           ": a name (of configs/controllers/NAME.yaml or a controller type), not a path; give a "
                           "config file with " + words.file_option);
}

std::vector<std::string> controllerNames(const fs::path& configs_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(configs_dir, ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  for (const auto& type : controllers::controllerTypes())
    if (std::find(names.begin(), names.end(), type) == names.end()) names.push_back(type);
  return names;
}

fs::path controllerConfigFile(const std::string& name, const fs::path& config_file, const fs::path& configs_dir) {
  if (!config_file.empty()) return config_file;
  const fs::path file = configs_dir / (name + ".yaml");
  return fs::exists(file) ? file : fs::path();
}

core::ConfigNode controllerConfigNode(const std::string& name, const fs::path& config_file, const fs::path& configs_dir,
                                      const ControllerLookupWords& words) {
  checkControllerName(name, words);
  const fs::path file = controllerConfigFile(name, config_file, configs_dir);
  if (!file.empty()) return core::ConfigNode::parseFile(file);
  const std::vector<std::string> types = controllers::controllerTypes();
  if (std::find(types.begin(), types.end(), name) == types.end()) {
    std::string known, closest;
    std::size_t best = 3;  // suggest only a near miss
    for (const auto& known_name : controllerNames(configs_dir)) {
      known += (known.empty() ? "" : ", ") + known_name;
      if (const std::size_t d = editDistance(name, known_name); d < best) {
        best = d;
        closest = known_name;
      }
    }
    throw core::InputError(words.name_option + " " + name + ": unknown" +
                           (closest.empty() ? std::string() : "; did you mean " + closest + "?") + " (known: " + known +
                           "; or " + words.file_option + ")");
  }
  return core::ConfigNode::parseString("type: " + name, words.name_option + " " + name);
}

}  // namespace barn::bench
