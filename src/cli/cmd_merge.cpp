// barn merge: the shards of a run (barn run --shard K/N, e.g. a Slurm job array) put back
// together into the record a single run would have written.

#include <cstdio>
#include <set>

#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/core/errors.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

struct MergeOptions {
  std::vector<std::string> shards;
  std::string out;
};

}  // namespace

void mergeRecords(const std::vector<std::string>& shards, const std::filesystem::path& out, bool print) {
  namespace fs = std::filesystem;
    if (fs::exists(fs::path(out.string()) / bench::kManifestFile))
      throw core::InputError(out.string() + ": already holds a run record");
    std::vector<bench::RunManifest> manifests;
    for (const auto& dir : shards) manifests.push_back(bench::readManifest(fs::path(dir) / bench::kManifestFile));
    const bench::RunManifest& first = manifests.front();
    std::set<int> seen;
    double wall = 0.0;
    std::vector<bench::EpisodeResult> results;
    for (std::size_t i = 0; i < manifests.size(); ++i) {
      const bench::RunManifest& m = manifests[i];
      const std::string& dir = shards[i];
      if (m.shard_count == 0) throw core::InputError(dir + ": not a shard (run without --shard)");
      if (m.shard_count != first.shard_count)
        throw core::InputError(dir + ": shard of " + std::to_string(m.shard_count) + ", the first is of " +
                               std::to_string(first.shard_count));
      if (const std::string field = bench::experimentDifference(first, m); !field.empty())
        throw core::InputError(dir + ": a different experiment from " + shards.front() + " (" + field + " differs)");
      if (!seen.insert(m.shard_index).second) throw core::InputError(dir + ": shard " + std::to_string(m.shard_index) + " given twice");
      if (!m.complete) throw core::InputError(dir + ": shard " + std::to_string(m.shard_index) + " is not complete (barn run --resume " + dir + ")");
      const auto rows = bench::readEpisodesCsv(fs::path(dir) / bench::kEpisodesFile);
      results.insert(results.end(), rows.begin(), rows.end());
      wall += m.wall_time_s;
    }
    if (static_cast<int>(seen.size()) != first.shard_count) {
      std::string missing;
      for (int k = 1; k <= first.shard_count; ++k)
        if (!seen.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
      throw core::InputError("merge: shards " + missing + " of " + std::to_string(first.shard_count) + " are missing");
    }
    const std::size_t expected = first.world_ids.size() * static_cast<std::size_t>(first.trials);
    bench::RunManifest merged = first;
    merged.shard_index = 0;
    merged.shard_count = 0;
    // Every episode once, each with its own seed: counts alone would take world 0 twice for a
    // missing world 1.
    bench::checkRows(merged, results, "merge", {}, true);
    merged.episodes_total = expected;
    merged.wall_time_s = wall;
    const auto worlds = bench::loadManifestWorlds(merged);
    bench::writeCompleteRecord(out.string(), merged, results, worlds);
    if (print) std::printf("merged %zu shards, %zu episodes\n", manifests.size(), results.size());
    if (print) printRecordSummary(out.string(), merged, worlds);
    if (print) std::printf("wrote %s\n", out.string().c_str());
}

void addMergeCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<MergeOptions>();
  CLI::App* cmd = app.add_subcommand("merge", "Combine the shard records of one run into one record");
  cmd->add_option("shards", options->shards, "Shard record folders (barn run --shard K/N --out DIR)")->required();
  cmd->add_option("--out", options->out, "Folder for the merged record")->required();
  cmd->callback([options] { mergeRecords(options->shards, options->out, true); });
}

}  // namespace barn::cli
