#pragma once
/// The results of a sweep: sweep.csv, the printed table and the heat maps.

#include <filesystem>
#include <string>
#include <vector>

#include "barn/bench/report.hpp"

namespace barn::cli {

struct SweepCell {
  std::string name;                 // record folder
  std::vector<std::string> values;  // one per swept key
  bench::RunSummary summary;
};

struct SweepTable {
  std::string controller;
  std::vector<std::string> keys;  // swept keys
  std::vector<SweepCell> cells;   // odometer order, last key fastest
};

/// One row per cell: the parameter values, score, success/collision/timeout rates, avg time.
std::string sweepCsv(const SweepTable& table);
/// The same as a printed table, best score marked.
std::string sweepSummary(const SweepTable& table);
/// Heat maps of score, success and collision rate (two swept keys) or line plots (one key).
/// Returns the files written.
std::vector<std::filesystem::path> writeSweepPlots(const SweepTable& table, const std::filesystem::path& dir);

}  // namespace barn::cli
