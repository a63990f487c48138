// barn compare: two run records (barnbench runs, or Gazebo results read by barn import-out)
// side by side over their common worlds. It reports; it does not judge (exit 0).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "barn/bench/compare.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/world_file.hpp"
#include "barn/viz/image_format.hpp"
#include "barn/viz/plots.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct CompareOptions {
  std::string a;
  std::string b;
  std::string output;
  std::string plot = "score";
  std::uint64_t seed = 0;
  int bootstrap = 10000;
  bool json = false;
};

struct Record {
  std::string dir;
  bench::RunManifest manifest;
  core::ProtocolName protocol = core::ProtocolName::Barn2023;
  std::vector<bench::EpisodeResult> results;
};

Record readRecord(const std::string& dir) {
  Record r;
  r.dir = dir;
  bench::CompleteRecord record = bench::readCompleteRecord(dir);
  r.manifest = std::move(record.manifest);
  r.protocol = bench::recordProtocol(r.manifest, dir + " manifest episode_config");
  r.results = std::move(record.episodes);
  return r;
}

// Worlds with the same id in both records but different files: the comparison of those is
// meaningless, so say so. Empty if every common world is the same (or the folders are gone).
std::vector<int> differentWorlds(const Record& a, const Record& b, const std::vector<int>& common, std::string& note) {
  std::vector<int> different;
  try {
    const auto wa = bench::loadManifestWorlds(a.manifest);
    const auto wb = bench::loadManifestWorlds(b.manifest);
    std::map<int, std::string> text_a;
    for (const auto& w : wa) text_a[w.id] = core::formatWorldFile(w);
    for (const auto& w : wb)
      if (std::binary_search(common.begin(), common.end(), w.id) && text_a.count(w.id) &&
          text_a[w.id] != core::formatWorldFile(w))
        different.push_back(w.id);
  } catch (const core::InputError& e) {
    note = std::string("world files not checked: ") + e.what();
  }
  return different;
}

// Members in the order written (nlohmann writes a non-finite double as null).
using Json = nlohmann::ordered_json;

void writeJson(const bench::Comparison& c, const Record& a, const Record& b, const std::vector<int>& different) {
  const auto side = [](const Record& r) {
    Json json{{"record", r.dir}, {"controller", r.manifest.controller}, {"protocol", std::string(core::toString(r.protocol))}};
    if (!r.manifest.source.empty()) json["source"] = r.manifest.source;
    return json;
  };
  const auto interval = [](const bench::BootstrapInterval& i) {
    return Json{{"estimate", i.estimate}, {"low", i.low}, {"high", i.high}};
  };
  const auto stats = [](const bench::WorldStats& w) {
    return Json{{"trials", w.trials},
                {"successes", w.successes},
                {"collisions", w.collisions},
                {"timeouts", w.timeouts},
                {"errors", w.errors},
                {"success_rate", w.success_rate},
                {"mean_success_time_s", w.mean_success_time},
                {"mean_score", w.mean_score}};
  };
  Json worlds = Json::array();
  for (std::size_t i = 0; i < c.a.size(); ++i)
    worlds.push_back(Json{{"world", c.a[i].world_id}, {"a", stats(c.a[i])}, {"b", stats(c.b[i])}});
  const Json json{
      {"a", side(a)},
      {"b", side(b)},
      {"common_worlds", static_cast<int>(c.a.size())},
      {"only_a", c.only_a},
      {"only_b", c.only_b},
      {"different_world_files", different},
      {"score_a", c.score_a},
      {"score_b", c.score_b},
      {"success_rate_a", c.success_a},
      {"success_rate_b", c.success_b},
      {"score_difference", interval(c.score_difference)},
      {"success_rate_difference", interval(c.success_difference)},
      {"collision_rate_a", c.collision_a},
      {"collision_rate_b", c.collision_b},
      {"collision_rate_difference", interval(c.collision_difference)},
      {"timeout_rate_a", c.timeout_a},
      {"timeout_rate_b", c.timeout_b},
      {"timeout_rate_difference", interval(c.timeout_difference)},
      {"mean_success_time_ratio", interval(c.time_ratio)},
      {"mean_success_time_ratio_worlds", c.time_ratio_worlds},
      {"bootstrap", {{"resamples", c.resamples}, {"seed", c.seed}, {"level", 0.95}}},
      {"agreement", {{"both_mostly_succeed", c.both_succeed}, {"both_mostly_fail", c.both_fail}, {"disagree", c.disagree}}},
      {"spearman_success_time", c.spearman_time},
      {"spearman_success_time_worlds", c.spearman_time_worlds},
      {"spearman_success_rate", c.spearman_success},
      {"worlds", std::move(worlds)}};
  // A record's path need not be UTF-8: such bytes are written as U+FFFD rather than refused.
  std::printf("%s\n", json.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
}

void plotComparison(const bench::Comparison& c, const Record& a, const Record& b, const CompareOptions& o) {
  const bool score = o.plot == "score";
  std::vector<std::size_t> order(c.a.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto value = [&](const bench::WorldStats& w) { return score ? w.mean_score : w.success_rate; };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t i, std::size_t j) { return value(c.a[i]) < value(c.a[j]); });
  viz::PairedWorlds pairs;
  char title[128];
  if (score)
    std::snprintf(title, sizeof title, "mean score per world, %zu worlds (B - A %+.4f)", c.a.size(),
                  c.score_difference.estimate);
  else
    std::snprintf(title, sizeof title, "success rate per world, %zu worlds (B - A %+.3f)", c.a.size(),
                  c.success_difference.estimate);
  pairs.title = title;
  pairs.y_label = score ? "mean score (OT / clipped AT)" : "success rate (fraction of trials)";
  pairs.x_label = "world id, ordered by A's " + std::string(score ? "mean score" : "success rate");
  pairs.label_a = a.manifest.controller + " (" + std::string(core::toString(a.protocol)) + ")";
  pairs.label_b = b.manifest.controller + " (" + std::string(core::toString(b.protocol)) + ")";
  for (std::size_t i : order) {
    pairs.labels.push_back(std::to_string(c.a[i].world_id));
    pairs.a.push_back(value(c.a[i]));
    pairs.b.push_back(value(c.b[i]));
  }
  if (score) {
    const core::Protocol pa = core::protocolPreset(a.protocol), pb = core::protocolPreset(b.protocol);
    pairs.y_max = std::max(pa.maxScore(), pb.maxScore());
    pairs.reference_lines = {pa.maxScore(), pa.minSuccessScore()};
  } else {
    pairs.y_max = 1.0;
  }
  viz::renderPairedWorlds(pairs, o.output);
  std::fprintf(o.json ? stderr : stdout, "wrote %s\n", o.output.c_str());  // stdout stays pure JSON
}

void compare(const CompareOptions& o) {
  const Record a = readRecord(o.a);
  const Record b = readRecord(o.b);
  const bench::Comparison c = bench::compareResults(a.results, b.results, o.bootstrap, o.seed);
  std::vector<int> common;
  for (const auto& w : c.a) common.push_back(w.world_id);
  std::string note;
  const std::vector<int> different = differentWorlds(a, b, common, note);
  if (o.json) {
    writeJson(c, a, b, different);
  } else {
    const auto label = [](const Record& r) {
      return r.manifest.controller + ", " + std::string(core::toString(r.protocol)) + ", " + r.dir + (r.manifest.source.empty() ? "" : " (imported)");
    };
    std::printf("%s", bench::comparisonReport(c, label(a), label(b)).c_str());
  }
  if (a.protocol != b.protocol)
    std::fprintf(stderr, "note: the records use different protocols (A %s, B %s): scores are on different scales\n",
                 std::string(core::toString(a.protocol)).c_str(), std::string(core::toString(b.protocol)).c_str());
  if (!different.empty()) {
    std::string list;
    for (int id : different) list += (list.empty() ? "" : ", ") + std::to_string(id);
    std::fprintf(stderr, "warning: %zu common world ids are different worlds in the two world folders (%s vs %s): %s\n",
                 different.size(), a.manifest.worlds_folder.c_str(), b.manifest.worlds_folder.c_str(), list.c_str());
  }
  if (!note.empty()) std::fprintf(stderr, "note: %s\n", note.c_str());
  if (!o.output.empty()) plotComparison(c, a, b, o);
}

}  // namespace

void addCompareCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare", "Compare two run records world by world (B - A); reports, never fails");
  cmd->add_option("a", options->a, "Record A (the reference, e.g. imported Gazebo results)")->required();
  cmd->add_option("b", options->b, "Record B")->required();
  cmd->add_option("-o,--output", options->output, "Paired per-world plot (.png, .pdf or .svg)");
  cmd->add_option("--plot", options->plot, "What the plot shows: score or success")
      ->check(CLI::IsMember({"score", "success"}))
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "Bootstrap seed")->capture_default_str()->check(kUnsigned);
  cmd->add_option("--bootstrap", options->bootstrap, "Bootstrap resamples of the worlds")
      ->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "Print the numbers as JSON instead of the table");
  cmd->callback([options] {
    // An unknown plot extension is bad input: refuse it before any work.
    if (!options->output.empty()) viz::imageFormatFor(options->output);
    compare(*options);
  });
}

}  // namespace barn::cli
