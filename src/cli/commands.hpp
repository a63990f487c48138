#pragma once
/// The `barn` subcommands. Each add*Command registers its options and a callback on `app`;
/// callbacks throw core::InputError for bad input (exit 2) and set `exit_code` to 1 when the
/// work itself fails (a verification mismatch, a failed run).

#include <filesystem>
#include <vector>

#include <CLI/CLI.hpp>

#include "barn/bench/run_record.hpp"

namespace barn::cli {

struct CommandContext {
  int exit_code = 0;  // 0 ok, 1 run failure (2 is raised as an InputError)
};

void addGenerateCommand(CLI::App& app, CommandContext& context);
void addImportCommand(CLI::App& app, CommandContext& context);
void addWorldCommand(CLI::App& app, CommandContext& context);
void addRunCommand(CLI::App& app, CommandContext& context);
void addMergeCommand(CLI::App& app, CommandContext& context);
void addLflhCommand(CLI::App& app, CommandContext& context);

/// Prints a complete record's summary table and difficulty breakdown.
void printRecordSummary(const std::filesystem::path& dir, const bench::RunManifest& manifest,
                        const std::vector<core::WorldSpec>& worlds);

}  // namespace barn::cli
