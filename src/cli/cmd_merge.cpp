// barn merge: the shards of a run (barn run --shard K/N, e.g. a Slurm job array) put back
// together into the record a single run would have written (bench::mergeShardRecords).

#include <cstdio>

#include "barn/bench/record_session.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

struct MergeOptions {
  std::vector<std::string> shards;
  std::string out;
};

}  // namespace

void addMergeCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<MergeOptions>();
  CLI::App* cmd = app.add_subcommand("merge", "Combine the shard records of one run into one record");
  cmd->add_option("shards", options->shards, "Shard record folders (barn run --shard K/N --out DIR)")->required();
  cmd->add_option("--out", options->out, "Folder for the merged record")->required();
  cmd->callback([options] {
    const std::vector<std::filesystem::path> shards(options->shards.begin(), options->shards.end());
    const std::filesystem::path out = options->out;
    checkOutFolder(out, "--out");
    const bench::MergedRecord merged = bench::mergeShardRecords(shards, out);
    std::printf("merged %zu shards, %zu episodes\n", shards.size(), merged.manifest.episodes_total);
    printRecordSummary(out, merged.manifest, bench::loadManifestWorlds(merged.manifest), merged.episodes,
                       bench::recordProtocol(merged.manifest, "manifest"));
    std::printf("wrote %s\n", options->out.c_str());
  });
}

}  // namespace barn::cli
