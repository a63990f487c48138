#include "report_figures.hpp"

#include <map>
#include <string>

#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/report/record_figures.hpp"

namespace barn::report {

namespace fs = std::filesystem;

std::vector<HtmlFigure> scoreFigures(const fs::path& record, const fs::path& scratch) {
  const fs::path file = scratch / "scores.png";
  renderScoreBars(record, "difficulty", file);
  return {{"Mean score per world, easiest to hardest; whiskers: min to max over trials; strip: the trials' outcomes", file}};
}

FailureFigures failureFigures(const fs::path& record, const fs::path& scratch, std::size_t max_episodes) {
  std::vector<int> world_order;
  std::map<int, std::vector<int>> failed;  // world -> failed trials
  std::size_t taken = 0;
  const RecordReplay replay(record);
  for (const auto& r : bench::readCompleteRecord(record).episodes) {
    if (r.outcome == bench::Outcome::Success || taken >= max_episodes || !replay.canDraw(r.world_id, r.trial)) continue;
    if (!failed.count(r.world_id)) world_order.push_back(r.world_id);
    failed[r.world_id].push_back(r.trial);
    ++taken;
  }
  FailureFigures out;
  out.episodes = taken;
  for (int world : world_order) {
    const fs::path file = scratch / ("failed_world_" + std::to_string(world) + ".png");
    replay.renderWorld(world, failed[world], viz::TrajectoryColouring::ByState, file);
    std::string trials;
    for (int t : failed[world]) trials += (trials.empty() ? "" : ", ") + std::to_string(t);
    out.figures.push_back({"World " + std::to_string(world) + ", failed trial(s) " + trials, file});
  }
  return out;
}

std::vector<HtmlFigure> sweepFigures(const SweepTable& sweep, const fs::path& scratch) {
  std::vector<HtmlFigure> figures;
  for (const fs::path& file : writeSweepPlots(sweep, scratch, ".png")) figures.push_back({file.stem().string(), file});
  return figures;
}

}  // namespace barn::report
