// barn generate: the canonical 300-world set from its recorded seeds.

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"
#include "commands.hpp"
#include "generator/world_generator.hpp"
#include "set_summary.hpp"

namespace barn::cli {

namespace {

struct GenerateOptions {
  std::string out = "worlds";
  std::uint64_t seed = generator::SweepConfig{}.base_seed;
  int worlds_per_set = generator::SweepConfig{}.worlds_per_set;
  bool check = false;
};

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
      ->check(kNotNegative);
  cmd->add_option("--worlds-per-set", options->worlds_per_set, "Accepted worlds per parameter set")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_flag("--check", options->check,
                "Do not write: compare the generated files with those in --out byte for byte (exit 1 on a difference)");
  cmd->callback([options, &context] {
    generator::SweepConfig config;
    config.base_seed = options->seed;
    config.worlds_per_set = options->worlds_per_set;
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<core::WorldSpec> worlds = generator::generateSweep(config);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s", parameterSetTable(worlds).c_str());
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
    core::writeWorldSet(options->out, worlds);
    std::printf("wrote %zu world files and index.csv to %s\n", worlds.size(), options->out.c_str());
  });
}

}  // namespace barn::cli
