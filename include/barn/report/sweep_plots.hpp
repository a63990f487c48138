#pragma once
/// The results of a sweep: sweep.csv, the printed table and the figures.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/compare.hpp"
#include "barn/bench/report.hpp"
#include "barn/core/protocol.hpp"

namespace barn::report {

struct SweepCell {
  std::string name;                       // record folder
  std::vector<std::string> values;        // one per swept key
  bench::RunSummary summary;
  std::vector<bench::WorldStats> worlds;  // per world (bench::perWorldStats), for intervals over worlds
};

struct SweepTable {
  std::string controller;
  std::vector<std::string> keys;   // swept keys
  std::vector<std::string> units;  // per key, from the controller config's schema; "" = none
  core::ProtocolName protocol = core::ProtocolName::Barn2023;  // the cells' protocol: fixes the score scale
  int trials = 0;                  // per world, in every cell
  std::vector<SweepCell> cells;    // odometer order, last key fastest
};

/// The unit of swept `key` in a cell's controller config (its manifest's text): the unit the
/// config struct's schema states (controllers::controllerKeyUnit); "" if none.
std::string sweptKeyUnit(const std::string& controller_config, const std::string& key);

/// The table of a finished sweep folder: its grid (sweep.yaml) and every cell's episodes.csv;
/// units from the controller's config schema (sweptKeyUnit). InputError if a cell is not
/// complete.
SweepTable readSweepTable(const std::filesystem::path& dir);

/// One row per cell: the parameter values, score, success/collision/timeout rates, avg time.
std::string sweepCsv(const SweepTable& table);
/// The same as a printed table, best score marked.
std::string sweepSummary(const SweepTable& table);

/// The sweep's figures in `dir`, in the format of `extension` (".png", ".pdf" or ".svg"):
/// - two keys: heat maps of score (colour scale 0 to the protocol's maximum score), success
///   and collision rate (0 to 1): heatmap_score, heatmap_success, heatmap_collision;
/// - one key: line plots of the same three against the key's values, each point the mean over
///   worlds of the per-world means with a 95 % percentile bootstrap interval (worlds
///   resampled, fixed seed): line_score, line_success, line_collision;
/// - three or more keys: none.
/// Returns the files written.
std::vector<std::filesystem::path> writeSweepPlots(const SweepTable& table, const std::filesystem::path& dir,
                                                   const std::string& extension = ".png");

}  // namespace barn::report
