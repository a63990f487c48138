#pragma once
/// The figures `barn report` embeds, drawn as PNG into a scratch folder.

#include <cstddef>
#include <filesystem>
#include <vector>

#include "barn/report/html_report.hpp"
#include "barn/report/sweep_plots.hpp"

namespace barn::report {

/// The run record's per-world score bars.
std::vector<HtmlFigure> scoreFigures(const std::filesystem::path& record, const std::filesystem::path& scratch);

/// The failed episodes of the record that can be drawn (recorded trajectories, or re-simulated;
/// a Python class's only if recorded), one figure per world (its failed trials), at most
/// `max_episodes` episodes in all, in run order.
struct FailureFigures {
  std::vector<HtmlFigure> figures;  // one per world
  std::size_t episodes = 0;         // episodes drawn in them
};
FailureFigures failureFigures(const std::filesystem::path& record, const std::filesystem::path& scratch,
                              std::size_t max_episodes);

/// A sweep's heat maps (two keys) or line plots (one key).
std::vector<HtmlFigure> sweepFigures(const SweepTable& sweep, const std::filesystem::path& scratch);

}  // namespace barn::report
