#include "config_units.hpp"

#include <fstream>
#include <utility>
#include <vector>

namespace barn::report {

namespace {

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

}  // namespace

// A line scan, not a YAML parse: yaml-cpp drops comments, and the files this reads (a
// controller's config) are block mappings of one key per line, nested by indentation.
std::string configKeyUnit(const std::filesystem::path& file, const std::string& key) {
  std::ifstream in(file);
  std::vector<std::pair<std::size_t, std::string>> open;  // (indent, key) of the enclosing blocks
  std::string type;
  for (std::string line; std::getline(in, line);) {
    const std::size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos || line[indent] == '#' || line[indent] == '-') continue;
    const std::size_t colon = line.find(':', indent);
    if (colon == std::string::npos) continue;
    while (!open.empty() && open.back().first >= indent) open.pop_back();
    std::string path;
    for (const auto& block : open) path += block.second + ".";
    const std::string name = line.substr(indent, colon - indent);
    path += name;
    open.emplace_back(indent, name);
    const std::size_t hash = line.find('#', colon);
    if (path == "type") type = trimmed(line.substr(colon + 1, hash == std::string::npos ? std::string::npos : hash - colon - 1));
    if (path != key && path != type + "." + key) continue;
    if (hash == std::string::npos) return {};
    const std::string comment = trimmed(line.substr(hash + 1));
    const std::size_t close = comment.find(']');
    if (comment.empty() || comment[0] != '[' || close == std::string::npos) return {};
    const std::string unit = trimmed(comment.substr(1, close - 1));
    return unit == "-" ? std::string() : unit;
  }
  return {};
}

}  // namespace barn::report
