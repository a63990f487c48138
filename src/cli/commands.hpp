#pragma once
/// The `barn` subcommands. Each add*Command registers its options and a callback on `app`;
/// callbacks throw core::InputError for bad input (exit 2) and set `exit_code` to 1 when the
/// work itself fails (a verification mismatch, a failed run).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "barn/bench/episode.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/core/config.hpp"

namespace barn::cli {

/// Option checks CLI11 does not make: CLI::Range lets NaN through (every comparison with it is
/// false), and an unsigned option reads "-1" as 2^64 - 1.
inline const CLI::Validator kFiniteNumber(
    [](std::string& text) {
      try {
        std::size_t used = 0;
        const double value = std::stod(text, &used);
        if (used == text.size() && std::isfinite(value)) return std::string();
      } catch (const std::exception&) {
      }
      return "'" + text + "' is not a finite number";
    },
    "FINITE");
/// A whole number written in decimal digits alone (no sign, "0x" or spaces) that fits 64 bits:
/// CLI11 alone saturates 2^64 at 2^64 - 1 and reads "0x10" as 16.
inline const CLI::Validator kUnsigned(
    [](std::string& text) {
      const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
      if (!digits) return "'" + text + "' is not a whole number (decimal digits only, from 0)";
      const std::string max = "18446744073709551615";  // 2^64 - 1
      const std::string value = text.substr(std::min(text.find_first_not_of('0'), text.size() - 1));
      if (value.size() > max.size() || (value.size() == max.size() && value > max))
        return "'" + text + "' is more than 2^64 - 1";
      return std::string();
    },
    "UNSIGNED");

struct CommandContext {
  int exit_code = 0;  // 0 ok, 1 run failure (2 is raised as an InputError)
};

void addGenerateCommand(CLI::App& app, CommandContext& context);
void addImportCommand(CLI::App& app, CommandContext& context);
void addWorldCommand(CLI::App& app, CommandContext& context);
void addRunCommand(CLI::App& app, CommandContext& context);
void addMergeCommand(CLI::App& app, CommandContext& context);
void addShowCommand(CLI::App& app, CommandContext& context);
void addReportCommand(CLI::App& app, CommandContext& context);
void addLflhCommand(CLI::App& app, CommandContext& context);
void addPolicyCommand(CLI::App& app, CommandContext& context);
/// `barn policy act` (and `barn lflh act`): runs the policy file on scans from stdin, one
/// printed command per line; InputError for a bad file, goal or scan line.
void runPolicyAct(const std::string& policy_path, const std::vector<double>& goal_xy);

void addRegressCommand(CLI::App& app, CommandContext& context);
void addSweepCommand(CLI::App& app, CommandContext& context);
void addPlotCommand(CLI::App& app, CommandContext& context);
void addHarnessOutCommands(CLI::App& app, CommandContext& context);  // import-out, export-out
void addCompareCommand(CLI::App& app, CommandContext& context);
void addExportWorldsCommand(CLI::App& app, CommandContext& context);
void addConfigCommand(CLI::App& app, CommandContext& context);

/// What `barn run` and `barn sweep` both ask: the controller, the simulation, the worlds and
/// the trials. Each command's options struct derives from it and adds its own.
struct ExperimentOptions {
  std::string controller;
  std::string config;
  std::string sim_config;
  std::string worlds = "all";
  std::string world_dir;
  int trials = 1;
  std::string protocol;
  int jobs = 0;
  std::uint64_t seed = 0;
};

/// Adds --controller, --config, --sim-config, --worlds, --world-dir, --trials, --protocol,
/// --jobs and --seed to `cmd`, bound to `options` (whose values are the defaults shown).
void addExperimentOptions(CLI::App* cmd, ExperimentOptions& options);

/// How a run session executes.
struct SessionOptions {
  int jobs = 0;                 // threads; 0 = all cores
  std::size_t stop_after = 0;   // stop after this many episodes (0 = never)
};

/// Runs the pending episodes of the record in `dir` (its manifest.yaml must exist; a fresh
/// record has no journal yet) and completes it. 0 complete, 1 interrupted or an episode error.
int runRecordFolder(const std::filesystem::path& dir, const SessionOptions& options);

/// The controller config `barn run` would use: --config FILE, else
/// configs/controllers/NAME.yaml, else the type NAME with its defaults.
core::ConfigNode controllerConfigFor(const std::string& controller, const std::string& config_file);
/// The file controllerConfigFor reads; empty for a bare type (no file).
std::filesystem::path controllerConfigFile(const std::string& controller, const std::string& config_file);
/// The validated simulation config (default configs/sim/barn.yaml), protocol overridden if given.
bench::EpisodeConfig episodeConfigFor(const std::string& sim_config, const std::string& protocol);

/// InputError naming `option` if `dir` is a file or a symlink to nothing (a folder is wanted).
void checkOutFolder(const std::filesystem::path& dir, const std::string& option);

/// Parses --shard K/N (1 <= K <= N); InputError otherwise.
void parseShard(const std::string& text, int& index, int& count);

/// Prints a complete record's summary table and difficulty breakdown (the groups whose buckets
/// all hold enough worlds to mean something, or every group with `every_bucket`): `results`
/// are its episodes as written, scored under `protocol`.
void printRecordSummary(const std::filesystem::path& dir, const bench::RunManifest& manifest,
                        const std::vector<core::WorldSpec>& worlds, const std::vector<bench::EpisodeResult>& results,
                        core::ProtocolName protocol, bool every_bucket = false);

}  // namespace barn::cli
