#include "barn/bench/run_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <type_traits>
#include <utility>

#include "barn/bench/batch.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"
#include "barn/controllers/registry.hpp"

namespace barn::bench {

namespace {

// Paths in a manifest are written relative to the record's folder ("./x", "../../x"), so a
// record holds no path of the machine that wrote it, and reads back wherever it is (a clone,
// a copy, a cluster node) as long as what it names kept its place relative to it.

std::string withoutTrailingSeparator(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

/// `path` made absolute with its folder's symlinks resolved (the folder as the file system has
/// it), so paths relative to a record work whichever name the record was reached by.
std::filesystem::path physical(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec).lexically_normal();
  if (ec || !absolute.has_relative_path()) return absolute;
  const fs::path name = absolute.filename().empty() ? absolute.parent_path().filename() : absolute.filename();
  const fs::path parent = fs::weakly_canonical(absolute.filename().empty() ? absolute.parent_path().parent_path()
                                                                           : absolute.parent_path(), ec);
  return ec ? absolute : parent / name;
}

/// An absolute path as seen from `dir`, starting with "./" or "../"; anything else unchanged.
std::string relativeTo(const std::string& path, const std::filesystem::path& dir) {
  if (path.empty() || path.front() != '/' || dir.empty()) return path;
  std::error_code ec;
  const std::filesystem::path base = std::filesystem::weakly_canonical(std::filesystem::absolute(dir), ec);
  if (ec) return path;
  const std::string relative = physical(path).lexically_relative(base).generic_string();
  if (relative.empty()) return path;
  if (relative == ".") return "./";
  return relative.starts_with("..") ? withoutTrailingSeparator(relative) : "./" + withoutTrailingSeparator(relative);
}

/// relativeTo undone: a "./" or "../" path made absolute from `dir` (as the file system has
/// it: a record reached through a symlink at another depth reads as at its own place);
/// anything else unchanged.
std::string absoluteFrom(const std::string& path, const std::filesystem::path& dir) {
  if (!(path.starts_with("./") || path.starts_with("../"))) return path;
  std::error_code ec;
  std::filesystem::path base = std::filesystem::weakly_canonical(std::filesystem::absolute(dir), ec);
  if (ec) base = std::filesystem::absolute(dir);
  return withoutTrailingSeparator((base / path).lexically_normal().string());
}

// A YAML double-quoted scalar that reads back as exactly `text`: quotes, backslashes, control
// characters and the characters YAML takes for line breaks (NEL, LS, PS) escaped.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const std::string_view rest = std::string_view(text).substr(i);
    char escape[8];
    if (byte == '"' || byte == '\\') {
      out += '\\';
      out += text[i];
    } else if (byte == '\n') {
      out += "\\n";
    } else if (byte == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7f) {
      std::snprintf(escape, sizeof escape, "\\x%02x", byte);
      out += escape;
    } else if (byte == 0xc2 && rest.size() >= 2 && static_cast<unsigned char>(rest[1]) <= 0x9f) {
      std::snprintf(escape, sizeof escape, "\\x%02x", static_cast<unsigned char>(rest[1]));  // U+0080..U+009F
      out += escape;
      ++i;
    } else if (rest.starts_with("\xe2\x80\xa8") || rest.starts_with("\xe2\x80\xa9") || rest.starts_with("\xef\xbb\xbf")) {
      out += rest.starts_with("\xe2\x80\xa8") ? "\\L" : rest.starts_with("\xe2\x80\xa9") ? "\\P" : "\\uFEFF";
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out + "\"";
}

// ---------------------------------------------------------------------------------------------
// The manifest's fields, written, read and compared through RunManifest::visit.

using namespace manifest_field;

// A field's value as the manifest writes it (a YAML scalar or flow list).
std::string valueText(const std::string& value) { return quoted(value); }
std::string valueText(bool value) { return value ? "true" : "false"; }
std::string valueText(double value) { return core::formatDouble(value); }
template <class Integer>
  requires std::is_integral_v<Integer>
std::string valueText(Integer value) {
  return std::to_string(value);
}
std::string valueText(const std::vector<int>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + std::to_string(values[i]);
  return text + "]";
}
std::string valueText(const std::vector<ConfigFile>& files) {
  std::string text = "[";
  for (std::size_t i = 0; i < files.size(); ++i) text += (i ? ", " : "") + files[i].path + " " + files[i].digest;
  return text + "]";
}

bool omitted(unsigned flags, bool imported) {
  return ((flags & kRunOnly) && imported) || ((flags & kImportOnly) && !imported);
}

class ManifestWriter {
 public:
  ManifestWriter(const std::filesystem::path& record_dir, bool imported) : record_dir_(record_dir), imported_(imported) {}

  template <class T>
  void operator()(const char* key, const T& value, unsigned flags) {
    if (omitted(flags, imported_)) return;
    if ((flags & kOmitDefault) && value == T{}) return;
    if constexpr (std::is_same_v<T, double>) {
      if (!std::isfinite(value)) return;  // unknown: left out, reads back as the default
    }
    if constexpr (std::is_same_v<T, std::string>) {
      if (flags & kConfigMap)
        text_ += std::string(key) + ":\n" + nested(configText(value, key, flags));
      else
        text_ += std::string(key) + ": " + quoted((flags & kPath) ? relativeTo(value, record_dir_) : value) + "\n";
    } else if constexpr (std::is_same_v<T, std::vector<ConfigFile>>) {
      text_ += std::string(key) + ":" + (value.empty() ? " []" : "") + "\n";
      for (const ConfigFile& file : value)
        text_ += "  - path: " + quoted(relativeTo(file.path, record_dir_)) + "\n    digest: " + quoted(file.digest) + "\n";
    } else {
      text_ += std::string(key) + ": " + valueText(value) + "\n";
    }
  }

  const std::string& text() const { return text_; }

 private:
  // A config as the file holds it: its YAML re-emitted, a controller's path fields relative
  // to the record.
  std::string configText(const std::string& value, const char* key, unsigned flags) const {
    const core::ConfigNode config = core::ConfigNode::parseString(value, key);
    if (!(flags & kControllerPaths) || config.isNull()) return config.isNull() ? "{}\n" : config.toYaml();
    const auto relative = [&](const std::string& path) { return relativeTo(path, record_dir_); };
    return core::ConfigNode::parseString(controllers::mapControllerPaths(config, relative), key).toYaml();
  }

  // YAML block text indented under its key.
  static std::string nested(const std::string& yaml) {
    std::string out;
    std::size_t start = 0;
    while (start < yaml.size()) {
      std::size_t end = yaml.find('\n', start);
      if (end == std::string::npos) end = yaml.size();
      out += "  " + yaml.substr(start, end - start) + "\n";
      start = end + 1;
    }
    return out;
  }

  std::filesystem::path record_dir_;
  bool imported_;
  std::string text_ = "# barnbench run record; `barn run --resume` and `barn merge` read it back.\n";
};

// A config field of the manifest as the config reader finds it (SelfReading, config.hpp): a map
// (or null), or a string holding YAML text (older records), parsed.
struct ConfigText {
  core::ConfigNode node;
};
void readConfigValue(const core::ConfigNode& node, ConfigText& value, core::Errors& errors) {
  std::string text;
  if (node.isMap() || node.isNull()) {
    value.node = node;
  } else if (node.read(text)) {
    try {
      value.node = core::ConfigNode::parseString(text, node.where());
    } catch (const core::InputError& e) {
      errors.add(node.where(), e.what());
    }
    if (!value.node.isNull() && !value.node.isMap()) errors.add(node.where(), "expected a map");
  } else {
    errors.add(node.where(), "expected a map");
  }
}

// Reads the fields through the strict config reader (unknown keys are errors, missing ones keep
// their defaults) and makes relative paths absolute again.
class ManifestReader {
 public:
  ManifestReader(const core::ConfigNode& root, core::Errors& errors, const std::filesystem::path& record_dir)
      : root_(root), errors_(errors), reader_(root, errors), record_dir_(record_dir) {}

  template <class T>
  void operator()(const char* key, T& value, unsigned flags) {
    if constexpr (std::is_same_v<T, std::string>) {
      if (flags & kConfigMap) {
        readConfig(key, value, flags);
        return;
      }
    }
    if constexpr (std::is_same_v<T, std::vector<int>>) {
      readWorldIds(key, value);
    } else if constexpr (std::is_same_v<T, std::size_t>) {
      std::uint64_t count = value;  // the config reader's unsigned type
      reader_(key, count);
      value = static_cast<std::size_t>(count);
    } else {
      reader_(key, value);
    }
    if constexpr (std::is_same_v<T, std::string>) {
      const auto absolute = [&](const std::string& text) { return absoluteFrom(text, record_dir_); };
      if (flags & kPath) value = absolute(value);
    }
    if constexpr (std::is_same_v<T, std::vector<ConfigFile>>) {
      for (ConfigFile& file : value) file.path = absoluteFrom(file.path, record_dir_);
    }
  }

  void finish() { reader_.finish(); }

 private:
  // A config: a nested map, or (records written before configs were maps) its YAML text as a
  // string. Held as YAML text; a controller's path fields absolute again.
  void readConfig(const char* key, std::string& value, unsigned flags) {
    ConfigText config;
    reader_(key, config);
    if (config.node.isNull() || (config.node.isMap() && config.node.keys().empty())) return;
    try {
      if (flags & kControllerPaths) {
        const auto absolute = [&](const std::string& path) { return absoluteFrom(path, record_dir_); };
        value = controllers::mapControllerPaths(config.node, absolute);
      } else {
        value = config.node.toYaml();
      }
    } catch (const core::InputError& e) {
      errors_.add(root_.where(key), e.what());
    }
  }

  // Read as numbers, so an id like 1e300 is caught here: converting it to int would be
  // undefined behaviour. A record without worlds is an error too (unless the list is already
  // reported as malformed).
  void readWorldIds(const char* key, std::vector<int>& ids) {
    std::vector<double> numbers;
    const std::size_t errors_before = errors_.messages().size();
    reader_(key, numbers);
    if (numbers.empty() && errors_.messages().size() == errors_before) errors_.add(root_.where(key), "missing");
    for (const double id : numbers) {
      if (std::isfinite(id) && id >= 0.0 && id <= 1e9 && id == std::floor(id))
        ids.push_back(static_cast<int>(id));
      else
        errors_.add(root_.where(key), core::formatDouble(id) + " is not a world id (a whole number from 0)");
    }
  }

  core::ConfigNode root_;
  core::Errors& errors_;
  core::ConfigReader reader_;
  std::filesystem::path record_dir_;
};

// The experiment fields as (key, written value), in list order.
struct ExperimentFields {
  std::vector<std::pair<std::string, std::string>> fields;

  template <class T>
  void operator()(const char* key, const T& value, unsigned flags) {
    if (flags & kExperiment) fields.emplace_back(key, valueText(value));
  }
};

ExperimentFields experimentFields(const RunManifest& m) {
  ExperimentFields fields;
  const_cast<RunManifest&>(m).visit(fields);  // visit only reads through this visitor
  return fields;
}

void validate(const RunManifest& m, const core::ConfigNode& root, core::Errors& errors) {
  errors.check(!m.controller.empty(), root.where("controller"), "missing");
  errors.check(m.trials >= 1, root.where("trials"), "must be >= 1");
  errors.check(m.shard_count >= 0 && m.shard_index >= 0 && m.shard_index <= m.shard_count &&
                   (m.shard_count == 0) == (m.shard_index == 0),
               root.where("shard_index"), "must be within 1..shard_count (or both 0)");
  const std::size_t episodes = m.world_ids.size() * static_cast<std::size_t>(std::max(m.trials, 0));
  errors.check(episodes <= kMaxEpisodesPerRecord, root.where("trials"),
               std::to_string(m.world_ids.size()) + " worlds x " + std::to_string(m.trials) +
                   " trials is more episodes than a record holds (" + std::to_string(kMaxEpisodesPerRecord) + ")");
  errors.check(std::set<int>(m.world_ids.begin(), m.world_ids.end()).size() == m.world_ids.size(), root.where("world_ids"),
               "a world is listed twice");
  errors.check(m.episodes_done <= m.episodes_total && m.episodes_total <= episodes, root.where("episodes_done"),
               "must be <= episodes_total <= worlds x trials");
  for (std::size_t i = 0; i < m.config_files.size(); ++i) {
    std::uint64_t digest = 0;
    errors.check(m.config_files[i].digest.size() == 16 && core::parseHex(m.config_files[i].digest, digest) &&
                     !m.config_files[i].path.empty(),
                 root.where("config_files[" + std::to_string(i) + "]"), "expected a path and a 16-digit hex digest");
  }
}

std::string hexDigest(std::uint64_t hash) {
  char text[32];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace

std::string formatManifest(const RunManifest& m, const std::filesystem::path& record_dir) {
  ManifestWriter writer(record_dir, /*imported=*/!m.source.empty());
  const_cast<RunManifest&>(m).visit(writer);  // visit only reads through this visitor
  return writer.text();
}

RunManifest readManifest(const std::filesystem::path& path) {
  return parseManifest(core::readTextFile(path), path.parent_path().empty() ? "." : path.parent_path(), path.string());
}

RunManifest parseManifest(const std::string& text, const std::filesystem::path& record_dir, const std::string& source) {
  const core::ConfigNode root = core::ConfigNode::parseString(text, source);
  RunManifest m;
  core::Errors errors;
  if (!root.isNull() && !root.isMap()) {
    errors.add(root.where(), "expected a map");
  } else {
    ManifestReader reader(root, errors, record_dir);
    m.visit(reader);
    reader.finish();
    validate(m, root, errors);
  }
  errors.throwIfAny();
  return m;
}

core::ProtocolName recordProtocol(const RunManifest& manifest, const std::string& where) {
  return core::readConfig<EpisodeConfig>(core::ConfigNode::parseString(manifest.episode_config, where)).protocol;
}

std::string experimentDifference(const RunManifest& a, const RunManifest& b) {
  const ExperimentFields fields_a = experimentFields(a);
  const ExperimentFields fields_b = experimentFields(b);
  for (std::size_t i = 0; i < fields_a.fields.size(); ++i)
    if (fields_a.fields[i].second != fields_b.fields[i].second) return fields_a.fields[i].first;
  return "";
}

std::string worldsDigest(const std::vector<core::WorldSpec>& worlds) {
  std::uint64_t hash = core::fnv1a64("");
  for (const auto& w : worlds) hash = core::fnv1a64(core::formatWorldFile(w), hash);
  return hexDigest(hash);
}

std::vector<ConfigFile> configFileDigests(const std::string& controller_config) {
  std::vector<ConfigFile> files;
  if (controller_config.empty()) return files;
  std::set<std::string> seen;
  for (const std::string& value : core::ConfigNode::parseString(controller_config, "controller_config").scalarValues()) {
    std::error_code ec;
    if (value.empty() || value.front() != '/' || !std::filesystem::is_regular_file(value, ec) || !seen.insert(value).second)
      continue;
    files.push_back({value, hexDigest(core::fnv1a64File(value))});
  }
  return files;
}

void checkConfigFiles(const RunManifest& manifest, const std::string& what) {
  for (const ConfigFile& file : manifest.config_files) {
    std::error_code ec;
    if (!std::filesystem::exists(file.path, ec))
      throw core::InputError(file.path + ": missing; the run's controller config names it (" + what +
                             " needs the file the run started with)");
    const std::string now = hexDigest(core::fnv1a64File(file.path));
    if (now != file.digest)
      throw core::InputError(file.path + ": changed since the run started (digest " + now + ", the run recorded " +
                             file.digest + "); " + what + " with it would mix two versions of the controller");
  }
}

void sortResults(std::vector<EpisodeResult>& results, const std::vector<int>& world_ids) {
  std::map<int, std::size_t> position;
  for (std::size_t i = 0; i < world_ids.size(); ++i) position.emplace(world_ids[i], i);
  std::stable_sort(results.begin(), results.end(), [&](const EpisodeResult& a, const EpisodeResult& b) {
    const std::size_t pa = position.count(a.world_id) ? position.at(a.world_id) : world_ids.size();
    const std::size_t pb = position.count(b.world_id) ? position.at(b.world_id) : world_ids.size();
    return pa != pb ? pa < pb : a.trial < b.trial;
  });
}

std::vector<core::WorldSpec> loadManifestWorlds(const RunManifest& manifest) {
  // Files of the folder that are not part of the run may be broken (a --keep-going run);
  // only the run's own worlds must load.
  LoadedWorlds loaded = loadWorlds(manifest.worlds_folder, manifest.worlds_folder, /*keep_going=*/true);
  std::map<int, std::size_t> by_id;
  for (std::size_t i = 0; i < loaded.worlds.size(); ++i) by_id.emplace(loaded.worlds[i].id, i);
  std::vector<core::WorldSpec> worlds;
  for (int id : manifest.world_ids) {
    if (!by_id.count(id)) {
      std::string why;
      for (const auto& message : loaded.skipped) why += "\n  " + message;
      throw core::InputError(manifest.worlds_folder + ": world " + std::to_string(id) + " of the run is missing or unreadable" + why);
    }
    worlds.push_back(loaded.worlds[by_id.at(id)]);
  }
  if (worldsDigest(worlds) != manifest.worlds_digest)
    throw core::InputError(manifest.worlds_folder + ": the world files changed since the run started (digest " +
                           worldsDigest(worlds) + ", run recorded " + manifest.worlds_digest + ")");
  return worlds;
}

RunManifest newManifest(const std::string& controller, const std::string& controller_config, const EpisodeConfig& episode,
                        const LoadedWorlds& worlds, const std::string& worlds_spec, int trials, std::uint64_t seed) {
  RunManifest m;
  m.controller = controller;
  m.controller_config = controller_config;
  m.episode_config = core::writeConfig(episode);
  m.worlds_spec = worlds_spec;
  m.worlds_folder = withoutTrailingSeparator(std::filesystem::absolute(worlds.folder).lexically_normal().string());
  for (const auto& w : worlds.worlds) m.world_ids.push_back(w.id);
  m.worlds_digest = worldsDigest(worlds.worlds);
  m.config_files = configFileDigests(controller_config);
  m.trials = trials;
  m.seed = seed;
  return m;
}

void checkRows(const RunManifest& manifest, const std::vector<EpisodeResult>& rows, const std::string& where,
               const std::vector<std::size_t>& allowed, bool complete) {
  const std::size_t trials = static_cast<std::size_t>(std::max(manifest.trials, 0));
  const std::size_t total = manifest.world_ids.size() * trials;
  std::vector<char> wanted(total, allowed.empty() ? 1 : 0);
  for (const std::size_t i : allowed)
    if (i < total) wanted[i] = 1;
  std::map<int, std::size_t> position;
  for (std::size_t i = 0; i < manifest.world_ids.size(); ++i) position.emplace(manifest.world_ids[i], i);
  std::vector<char> seen(total, 0);
  for (const EpisodeResult& r : rows) {
    const std::string row = where + ": world " + std::to_string(r.world_id) + " trial " + std::to_string(r.trial);
    const auto at = position.find(r.world_id);
    if (at == position.end()) throw core::InputError(row + ": the world is not in this record");
    if (r.trial < 0 || static_cast<std::size_t>(r.trial) >= trials) throw core::InputError(row + ": trial out of range");
    const std::size_t index = at->second * trials + static_cast<std::size_t>(r.trial);
    if (!wanted[index]) throw core::InputError(row + ": not an episode of this record (another shard's?)");
    if (manifest.source.empty() && r.seed != episodeSeed(manifest.seed, r.world_id, r.trial))
      throw core::InputError(row + ": seed " + std::to_string(r.seed) + " is not this run's (another run's row?)");
    if (seen[index]) throw core::InputError(row + ": given twice");
    seen[index] = 1;
  }
  if (!complete) return;
  for (std::size_t index = 0; index < total; ++index)
    if (wanted[index] && !seen[index])
      throw core::InputError(where + ": world " + std::to_string(manifest.world_ids[index / trials]) + " trial " +
                             std::to_string(index % trials) + " is missing");
}

CompleteRecordFiles completeRecordFiles(const std::filesystem::path& dir, RunManifest manifest,
                                        std::vector<EpisodeResult> results, const std::vector<core::WorldSpec>& worlds) {
  sortResults(results, manifest.world_ids);
  const RunSummary summary = summarise(results);
  manifest.complete = true;
  manifest.episodes_done = results.size();
  manifest.sim_time_s = summary.sim_time;
  CompleteRecordFiles out;
  out.files = {{kEpisodesFile, episodesCsv(results)},
               {kSummaryFile, summaryJson(worldSetName(worlds), summary, perWorldStats(results, core::protocolPreset(recordProtocol(manifest, dir.string())).maxScore()),
                                          difficultyBreakdown(results, worlds))},
               {kManifestFile, formatManifest(manifest, dir)}};
  out.episodes = std::move(results);
  return out;
}

std::vector<EpisodeResult> writeCompleteRecord(const RecordWriter& writer, RunManifest manifest,
                                               std::vector<EpisodeResult> results,
                                               const std::vector<core::WorldSpec>& worlds) {
  CompleteRecordFiles record = completeRecordFiles(writer.dir(), std::move(manifest), std::move(results), worlds);
  writer.write(record.files, {kJournalFile});
  return std::move(record.episodes);
}

void checkCompleteRows(const RunManifest& m, const std::vector<EpisodeResult>& rows, const std::string& file) {
  const std::size_t trials = static_cast<std::size_t>(std::max(m.trials, 0));
  const std::size_t total = m.world_ids.size() * trials;
  std::vector<std::size_t> wanted;  // the episodes the record holds (run records)
  if (m.source.empty()) {
    if (m.shard_count > 0) {
      wanted = shardEpisodes(total, m.shard_index, m.shard_count);
    } else {
      wanted.resize(total);
      for (std::size_t i = 0; i < total; ++i) wanted[i] = i;
    }
  }
  // Every row valid and once; an imported record holds the trials its file had. (checkRows
  // reads an empty list as every episode: a shard of none is checked here.)
  if (m.source.empty() && wanted.empty() && !rows.empty())
    throw core::InputError(file + ": world " + std::to_string(rows.front().world_id) + " trial " +
                           std::to_string(rows.front().trial) + ": not an episode of this record");
  checkRows(m, rows, file, wanted, false);
  const std::size_t expected = m.source.empty() ? wanted.size() : m.episodes_done;
  if (m.episodes_done != expected)
    throw core::InputError(file + ": the manifest says " + std::to_string(m.episodes_done) + " episodes done, but its " +
                           std::to_string(m.world_ids.size()) + " worlds x " + std::to_string(m.trials) +
                           " trials give " + std::to_string(expected));
  if (rows.size() == expected) return;
  std::string missing;
  if (m.source.empty()) {
    std::map<int, std::size_t> position;
    for (std::size_t i = 0; i < m.world_ids.size(); ++i) position.emplace(m.world_ids[i], i);
    std::vector<char> seen(total, 0);
    for (const EpisodeResult& r : rows) seen[position.at(r.world_id) * trials + static_cast<std::size_t>(r.trial)] = 1;
    for (const std::size_t index : wanted)
      if (!seen[index]) {
        missing = " (world " + std::to_string(m.world_ids[index / trials]) + " trial " + std::to_string(index % trials) +
                  " missing)";
        break;
      }
  }
  throw core::InputError(file + ": " + std::to_string(rows.size()) + " rows, the manifest says " +
                         std::to_string(expected) + missing);
}

CompleteRecord readCompleteRecord(const std::filesystem::path& dir) {
  const std::filesystem::path manifest_file = dir / kManifestFile;
  std::error_code ec;
  if (!std::filesystem::exists(manifest_file, ec))
    throw core::InputError(dir.string() + ": no run record here (no " + std::string(kManifestFile) + ")");
  core::checkNoInterruptedWrite(dir);
  CompleteRecord record;
  record.manifest = readManifest(manifest_file);
  const RunManifest& m = record.manifest;
  if (!m.complete)
    throw core::InputError(dir.string() + ": not complete (" + std::to_string(m.episodes_done) + " of " +
                           std::to_string(m.episodes_total) + " episodes); finish it with barn run --resume " +
                           dir.string());
  const std::filesystem::path file = dir / kEpisodesFile;
  record.episodes = parseEpisodesCsv(core::readTextFile(file), file.string(), /*journal=*/false);
  checkCompleteRows(m, record.episodes, file.string());
  return record;
}

}  // namespace barn::bench
