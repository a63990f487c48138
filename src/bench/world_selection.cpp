#include "barn/bench/world_selection.hpp"

#include <algorithm>
#include <set>

#include "barn/core/errors.hpp"
#include "barn/core/world_file.hpp"

namespace barn::bench {

namespace {

int parseId(const std::string& text, const std::string& spec) {
  std::size_t used = 0;
  int value = -1;
  try {
    value = std::stoi(text, &used);
  } catch (...) {
    used = 0;
  }
  if (text.empty() || used != text.size() || value < 0)
    throw core::InputError("--worlds '" + spec + "': '" + text + "' is not a world id");
  return value;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t at = text.find(separator, start);
    parts.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) return parts;
    start = at + 1;
  }
}

}  // namespace

std::vector<int> selectWorldIds(const std::string& spec, const std::vector<int>& available) {
  std::vector<int> wanted;
  if (spec == "all") {
    wanted = available;
  } else if (spec == "test50") {
    for (int id = 0; id < 300; id += 6) wanted.push_back(id);
  } else if (spec.find(':') != std::string::npos) {
    const auto parts = split(spec, ':');
    if (parts.size() > 3) throw core::InputError("--worlds '" + spec + "': expected A:B or A:B:STEP");
    const int first = parseId(parts[0], spec);
    const int end = parseId(parts[1], spec);
    const int stride = parts.size() == 3 ? parseId(parts[2], spec) : 1;
    if (stride < 1) throw core::InputError("--worlds '" + spec + "': the step must be >= 1");
    for (int id = first; id < end; id += stride) wanted.push_back(id);
  } else {
    for (const auto& part : split(spec, ',')) wanted.push_back(parseId(part, spec));
  }
  const std::set<int> have(available.begin(), available.end());
  std::vector<int> missing;
  for (int id : wanted)
    if (!have.count(id)) missing.push_back(id);
  if (!missing.empty()) {
    std::string list;
    for (std::size_t i = 0; i < missing.size() && i < 10; ++i) list += (i ? ", " : "") + std::to_string(missing[i]);
    if (missing.size() > 10) list += ", ...";
    throw core::InputError("--worlds '" + spec + "': unknown world id(s) " + list);
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  if (wanted.empty()) throw core::InputError("--worlds '" + spec + "': selects no world");
  return wanted;
}

LoadedWorlds loadWorlds(const std::string& spec, const std::filesystem::path& default_dir, bool keep_going) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool is_folder = fs::is_directory(spec, ec);
  LoadedWorlds loaded;
  loaded.folder = fs::absolute(is_folder ? fs::path(spec) : default_dir);
  if (!fs::is_directory(loaded.folder, ec)) throw core::InputError(loaded.folder.string() + ": no such folder of worlds");

  std::vector<core::WorldSpec> all = core::readWorldSet(loaded.folder, keep_going ? &loaded.skipped : nullptr);
  if (is_folder) {
    if (all.empty()) throw core::InputError(loaded.folder.string() + ": no readable world files");
    loaded.worlds = std::move(all);
    return loaded;
  }
  std::vector<int> available;
  for (const auto& w : all) available.push_back(w.id);
  const std::vector<int> ids = selectWorldIds(spec, available);
  std::size_t j = 0;
  for (int id : ids) {
    while (all[j].id != id) ++j;
    loaded.worlds.push_back(std::move(all[j]));
  }
  return loaded;
}

}  // namespace barn::bench
