// barn config: the effective controller config of a run (or of a sweep cell) as a YAML file of
// its own, which `barn run --config FILE` takes back to run the same controller again.

#include <cstdio>
#include <filesystem>
#include <string>

#include "barn/bench/run_record.hpp"
#include "barn/bench/sweep_grid.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "commands.hpp"

namespace barn::cli {

namespace {

namespace fs = std::filesystem;

struct ConfigOptions {
  std::string record;
  std::string out;
};

// Why `dir` has no manifest to read, as a message that says what to give instead.
[[noreturn]] void throwNoManifest(const std::string& record) {
  const fs::path dir = record;
  if (!fs::exists(dir)) throw core::InputError(record + ": no such record folder");
  if (!fs::is_directory(dir)) throw core::InputError(record + ": is a file, expected a record folder");
  if (fs::exists(dir / bench::kSweepFile)) {
    std::string example = "CELL";
    try {
      const bench::SweepGrid grid = bench::readSweepFile(dir);
      if (!grid.cells.empty()) example = grid.cells.front();
    } catch (const core::InputError&) {
      // The hint is only a hint: a damaged sweep.yaml still gets the message below.
    }
    throw core::InputError(record + ": a sweep folder, whose cells have configs of their own; give a cell folder, e.g. " +
                           (dir / example).string());
  }
  throw core::InputError(record + ": no " + bench::kManifestFile + " (not a run record)");
}

}  // namespace

void addConfigCommand(CLI::App& app, CommandContext& /*context*/) {
  auto options = std::make_shared<ConfigOptions>();
  CLI::App* cmd = app.add_subcommand(
      "config", "Print a run's (or a sweep cell's) effective controller config, for barn run --config FILE");
  cmd->add_option("record", options->record, "Run record folder (a sweep's cell folder for a sweep)")->required();
  cmd->add_option("--out", options->out, "Write the config to this file instead of printing it");
  cmd->callback([options] {
    const fs::path manifest_file = fs::path(options->record) / bench::kManifestFile;
    if (!fs::exists(manifest_file)) throwNoManifest(options->record);
    const bench::RunManifest manifest = bench::readManifest(manifest_file);
    if (!manifest.source.empty())
      throw core::InputError(options->record + ": imported from " + manifest.source +
                             " (barn import-out): nothing was run, so it has no controller config");
    if (manifest.controller_config.empty())
      throw core::InputError(manifest_file.string() + ": controller_config: missing");
    // The text is the record's own, byte for byte; parsing it only makes sure a damaged
    // manifest is reported here rather than by the run it is given to.
    core::ConfigNode::parseString(manifest.controller_config, manifest_file.string() + " controller_config");
    if (options->out.empty()) {
      std::fputs(manifest.controller_config.c_str(), stdout);
      return;
    }
    if (fs::is_directory(options->out)) throw core::InputError("--out " + options->out + ": is a folder, expected a file");
    core::writeFileAtomic(options->out, manifest.controller_config);
    std::printf("wrote %s (controller config of %s)\n", options->out.c_str(), options->record.c_str());
  });
}

}  // namespace barn::cli
