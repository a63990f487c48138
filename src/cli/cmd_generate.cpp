// barn generate: the canonical 300-world set from its recorded seeds.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "barn/bench/record_writer.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"
#include "commands.hpp"
#include "generator/world_generator.hpp"
#include "barn/report/set_summary.hpp"

namespace barn::cli {

namespace {

struct GenerateOptions {
  std::string out = "worlds";
  std::uint64_t seed = generator::SweepConfig{}.base_seed;
  int worlds_per_set = generator::SweepConfig{}.worlds_per_set;
  bool check = false;
  bool force = false;
};

// The world files and index already in `dir` (a world set written before).
std::vector<std::filesystem::path> existingWorldSetFiles(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name == "index.csv" || (name.starts_with("world_") && name.ends_with(".yaml"))) files.push_back(entry.path());
  }
  return files;
}

// Compares the freshly generated files with those in `dir`; prints every difference.
int checkAgainstFolder(const std::filesystem::path& dir, const std::vector<core::WorldSpec>& worlds) {
  int differing = 0;
  const auto compare = [&](const std::string& name, const std::string& expected) {
    std::string existing;
    try {
      existing = core::readTextFile(dir / name);
    } catch (const core::InputError&) {
      std::printf("missing: %s\n", (dir / name).c_str());
      ++differing;
      return;
    }
    if (existing != expected) {
      std::printf("differs: %s\n", (dir / name).c_str());
      ++differing;
    }
  };
  for (const auto& w : worlds) compare(core::worldFileName(w.id), core::formatWorldFile(w));
  compare("index.csv", core::formatWorldIndex(worlds));
  return differing;
}

}  // namespace

void addGenerateCommand(CLI::App& app, CommandContext& context) {
  auto options = std::make_shared<GenerateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "generate", "Generate the canonical world set (fill 0.15-0.30 x smoothing 2-4 x 25) from its seeds");
  cmd->add_option("--out", options->out, "Folder for the world files and index.csv")->capture_default_str();
  cmd->add_option("--seed", options->seed, "Base seed of the sweep (every attempt's seed derives from it)")
      ->capture_default_str()
      ->check(kUnsigned);
  cmd->add_option("--worlds-per-set", options->worlds_per_set, "Accepted worlds per parameter set")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_flag("--force", options->force,
                "Replace the world set already in --out (its world files not in the new set are deleted)");
  cmd->add_flag("--check", options->check,
                "Do not write: compare the generated files with those in --out byte for byte (exit 1 on a difference)");
  cmd->callback([options, &context] {
    generator::SweepConfig config;
    config.base_seed = options->seed;
    config.worlds_per_set = options->worlds_per_set;
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<core::WorldSpec> worlds = generator::generateSweep(config);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s", report::parameterSetTable(worlds).c_str());
    std::printf("generated %zu worlds in %.3f s (base seed %llu)\n", worlds.size(), seconds,
                static_cast<unsigned long long>(config.base_seed));
    if (options->check) {
      const int differing = checkAgainstFolder(options->out, worlds);
      if (differing) {
        std::printf("%d file(s) in %s differ from the regenerated set\n", differing, options->out.c_str());
        context.exit_code = 1;
      } else {
        std::printf("all %zu world files and index.csv in %s are identical to the regenerated set\n", worlds.size(),
                    options->out.c_str());
      }
      return;
    }
    // A set is written whole or not at all (one locked set write: a kill leaves the old set or
    // the new one): into a folder holding another set only with --force, and then none of the
    // old set's files stay behind (a smaller set written over a larger one would otherwise
    // leave a mixed folder that `--worlds all` runs).
    checkOutFolder(options->out, "--out");
    const bench::RecordWriter writer(options->out);
    const std::vector<std::filesystem::path> old_files = existingWorldSetFiles(options->out);
    if (!old_files.empty() && !options->force)
      throw core::InputError(options->out + ": already holds a world set (" + std::to_string(old_files.size()) +
                             " files); --force replaces it, or choose another --out");
    std::set<std::string> written = {"index.csv"};
    for (const auto& w : worlds) written.insert(core::worldFileName(w.id));
    std::vector<std::string> removals;
    for (const auto& file : old_files)
      if (!written.count(file.filename().string())) removals.push_back(file.filename().string());
    writer.write(core::worldSetFiles(worlds), removals);
    const std::size_t removed = removals.size();
    std::printf("wrote %zu world files and index.csv to %s%s\n", worlds.size(), options->out.c_str(),
                removed ? (" (removed " + std::to_string(removed) + " files of the old set)").c_str() : "");
  });
}

}  // namespace barn::cli
