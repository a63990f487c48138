#include "barn/bench/run_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "barn/bench/batch.hpp"
#include "barn/bench/report.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"

namespace barn::bench {

namespace {

// A YAML literal block, indented under its key.
std::string block(const std::string& text) {
  std::string out = "|\n";
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    out += "  " + text.substr(start, end == std::string::npos ? std::string::npos : end - start) + "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

// Paths in a manifest are written relative to the record's folder ("./x", "../../x"), so a
// record holds no path of the machine that wrote it, and reads back wherever it is (a clone,
// a copy, a cluster node) as long as what it names kept its place relative to it.
bool plainPathText(std::string_view text) {
  return !text.empty() && text.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./+-") ==
                              std::string_view::npos;
}

std::string withoutTrailingSeparator(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

/// An absolute path as seen from `dir`, starting with "./" or "../"; anything else unchanged.
std::string relativeTo(const std::string& path, const std::filesystem::path& dir) {
  if (path.empty() || path.front() != '/' || dir.empty()) return path;
  const std::filesystem::path base = std::filesystem::absolute(dir).lexically_normal();
  const std::string relative = std::filesystem::path(path).lexically_normal().lexically_relative(base).generic_string();
  if (relative.empty()) return path;
  if (relative == ".") return "./";
  return relative.starts_with("..") ? withoutTrailingSeparator(relative) : "./" + withoutTrailingSeparator(relative);
}

/// relativeTo undone: a "./" or "../" path made absolute from `dir`; anything else unchanged.
std::string absoluteFrom(const std::string& path, const std::filesystem::path& dir) {
  if (!(path.starts_with("./") || path.starts_with("../"))) return path;
  return withoutTrailingSeparator((std::filesystem::absolute(dir) / path).lexically_normal().string());
}

/// Applies `convert` to every plain path-like value ("key: value" lines) of a config's text.
template <class Convert>
std::string convertPathValues(const std::string& config_text, Convert convert) {
  std::string out;
  std::size_t start = 0;
  while (start < config_text.size()) {
    std::size_t end = config_text.find('\n', start);
    if (end == std::string::npos) end = config_text.size();
    std::string line = config_text.substr(start, end - start);
    const std::size_t colon = line.find(": ");
    if (colon != std::string::npos && plainPathText(std::string_view(line).substr(colon + 2)))
      line = line.substr(0, colon + 2) + convert(line.substr(colon + 2));
    out += line;
    if (end < config_text.size()) out += '\n';
    start = end + 1;
  }
  return out;
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char ch : text) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

// The manifest's fields, read through the strict config reader.
struct ManifestFields {
  std::string controller, controller_config, episode_config, worlds_spec, worlds_folder, worlds_digest;
  std::string source, source_digest;
  std::vector<double> world_ids;
  int trials = 0;
  std::uint64_t seed = 0;
  int shard_index = 0, shard_count = 0;
  int episodes_total = 0, episodes_done = 0;
  bool complete = false;
  std::string barnbench_version, git_commit, host, started;
  int threads = 0;
  double wall_time_s = 0.0, sim_time_s = 0.0;
  template <class V> void visit(V& v) {
    v("controller", controller); v("controller_config", controller_config); v("episode_config", episode_config);
    v("worlds_spec", worlds_spec); v("worlds_folder", worlds_folder); v("world_ids", world_ids);
    v("worlds_digest", worlds_digest); v("trials", trials); v("seed", seed); v("source", source);
    v("source_digest", source_digest); v("shard_index", shard_index);
    v("shard_count", shard_count); v("episodes_total", episodes_total); v("episodes_done", episodes_done);
    v("complete", complete); v("barnbench_version", barnbench_version); v("git_commit", git_commit); v("host", host);
    v("threads", threads); v("started", started); v("wall_time_s", wall_time_s); v("sim_time_s", sim_time_s);
  }
};

}  // namespace

std::string formatManifest(const RunManifest& m, const std::filesystem::path& record_dir) {
  const auto relative = [&](const std::string& path) { return relativeTo(path, record_dir); };
  std::ostringstream out;
  out << "# barnbench run record; `barn run --resume` and `barn merge` read it back.\n";
  out << "controller: " << quoted(m.controller) << "\n";
  const bool imported = !m.source.empty();
  if (!imported) out << "controller_config: " << block(convertPathValues(m.controller_config, relative));
  out << "episode_config: " << block(m.episode_config);
  out << "worlds_spec: " << quoted(m.worlds_spec) << "\n";
  out << "worlds_folder: " << quoted(relative(m.worlds_folder)) << "\n";
  out << "world_ids: [";
  for (std::size_t i = 0; i < m.world_ids.size(); ++i) out << (i ? ", " : "") << m.world_ids[i];
  out << "]\n";
  out << "worlds_digest: " << quoted(m.worlds_digest) << "\n";
  out << "trials: " << m.trials << "\n";
  if (imported) {
    out << "source: " << quoted(m.source) << "\n";
    out << "source_digest: " << quoted(m.source_digest) << "\n";
  } else {
    out << "seed: " << m.seed << "\n";
  }
  out << "shard_index: " << m.shard_index << "\n";
  out << "shard_count: " << m.shard_count << "\n";
  out << "episodes_total: " << m.episodes_total << "\n";
  out << "episodes_done: " << m.episodes_done << "\n";
  out << "complete: " << (m.complete ? "true" : "false") << "\n";
  out << "barnbench_version: " << quoted(m.barnbench_version) << "\n";
  out << "git_commit: " << quoted(m.git_commit) << "\n";
  out << "host: " << quoted(m.host) << "\n";
  out << "threads: " << m.threads << "\n";
  out << "started: " << quoted(m.started) << "\n";
  out << "wall_time_s: " << core::formatDouble(m.wall_time_s) << "\n";
  if (std::isfinite(m.sim_time_s)) out << "sim_time_s: " << core::formatDouble(m.sim_time_s) << "\n";
  return out.str();
}

RunManifest readManifest(const std::filesystem::path& path) {
  const ManifestFields f = core::readConfig<ManifestFields>(core::ConfigNode::parseFile(path));
  core::Errors errors(path.string());
  errors.check(!f.controller.empty(), "controller", "missing");
  errors.check(f.trials >= 1, "trials", "must be >= 1");
  errors.check(!f.world_ids.empty(), "world_ids", "missing");
  // Read as numbers, so an id like 1e300 must be caught here: converting it to int would be
  // undefined behaviour.
  for (const double id : f.world_ids)
    errors.check(std::isfinite(id) && id >= 0.0 && id <= 1e9 && id == std::floor(id), "world_ids",
                 core::formatDouble(id) + " is not a world id (a whole number from 0)");
  errors.check(f.episodes_total >= 0 && f.episodes_done >= 0, "episodes_done", "must be >= 0");
  errors.check(f.shard_count >= 0 && f.shard_index >= 0 && f.shard_index <= f.shard_count, "shard_index",
               "must be within 1..shard_count (or both 0)");
  errors.throwIfAny();
  const std::filesystem::path record_dir = path.parent_path().empty() ? "." : path.parent_path();
  const auto absolute = [&](const std::string& text) { return absoluteFrom(text, record_dir); };
  RunManifest m;
  m.controller = f.controller;
  m.controller_config = convertPathValues(f.controller_config, absolute);
  m.episode_config = f.episode_config;
  m.worlds_spec = f.worlds_spec;
  m.worlds_folder = absolute(f.worlds_folder);
  for (double id : f.world_ids) m.world_ids.push_back(static_cast<int>(id));
  m.worlds_digest = f.worlds_digest;
  m.trials = f.trials;
  m.seed = f.seed;
  m.source = f.source;
  m.source_digest = f.source_digest;
  m.shard_index = f.shard_index;
  m.shard_count = f.shard_count;
  m.episodes_total = static_cast<std::size_t>(f.episodes_total);
  m.episodes_done = static_cast<std::size_t>(f.episodes_done);
  m.complete = f.complete;
  m.barnbench_version = f.barnbench_version;
  m.git_commit = f.git_commit;
  m.host = f.host;
  m.threads = f.threads;
  m.started = f.started;
  m.wall_time_s = f.wall_time_s;
  m.sim_time_s = f.sim_time_s;
  return m;
}

core::ProtocolName recordProtocol(const RunManifest& manifest, const std::string& where) {
  return core::readConfig<EpisodeConfig>(core::ConfigNode::parseString(manifest.episode_config, where)).protocol;
}

std::string experimentDifference(const RunManifest& a, const RunManifest& b) {
  if (a.controller != b.controller) return "controller";
  if (a.controller_config != b.controller_config) return "controller_config";
  if (a.episode_config != b.episode_config) return "episode_config";
  if (a.world_ids != b.world_ids) return "world_ids";
  if (a.worlds_digest != b.worlds_digest) return "worlds_digest";
  if (a.trials != b.trials) return "trials";
  if (a.seed != b.seed) return "seed";
  if (a.source != b.source) return "source";
  if (a.source_digest != b.source_digest) return "source_digest";
  return "";
}

std::string worldsDigest(const std::vector<core::WorldSpec>& worlds) {
  std::uint64_t hash = core::fnv1a64("");
  for (const auto& w : worlds) hash = core::fnv1a64(core::formatWorldFile(w), hash);
  char text[32];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
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

std::vector<EpisodeResult> writeCompleteRecord(const std::filesystem::path& dir, RunManifest manifest,
                                               std::vector<EpisodeResult> results,
                         const std::vector<core::WorldSpec>& worlds) {
  sortResults(results, manifest.world_ids);
  const RunSummary summary = summarise(results);
  manifest.complete = true;
  manifest.episodes_done = results.size();
  manifest.sim_time_s = summary.sim_time;
  core::writeFilesAtomic(dir, {{kEpisodesFile, episodesCsv(results)},
                               {kSummaryFile, summaryJson(worldSetName(worlds), summary, perWorldStats(results),
                                                          difficultyBreakdown(results, worlds))},
                               {kManifestFile, formatManifest(manifest, dir)}});
  std::error_code ec;
  std::filesystem::remove(dir / kJournalFile, ec);
  return results;
}

}  // namespace barn::bench
