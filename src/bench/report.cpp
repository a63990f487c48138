#include "barn/bench/report.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "barn/core/text_io.hpp"

namespace barn::bench {

RunSummary summarise(const std::vector<EpisodeResult>& results) {
  struct PerWorld {
    int trials = 0, successes = 0, collisions = 0, timeouts = 0, errors = 0;
    double score = 0.0, success_time = 0.0;
  };
  std::map<int, PerWorld> worlds;
  RunSummary summary;
  for (const auto& r : results) {
    PerWorld& w = worlds[r.world_id];
    ++w.trials;
    w.score += r.score;
    w.successes += r.outcome == Outcome::Success;
    w.collisions += r.outcome == Outcome::Collision;
    w.timeouts += r.outcome == Outcome::Timeout;
    w.errors += r.outcome == Outcome::Error;
    if (r.outcome == Outcome::Success) w.success_time += r.actual_time;
    summary.sim_time += r.sim_time;
  }
  summary.worlds = static_cast<int>(worlds.size());
  summary.episodes = static_cast<int>(results.size());
  if (worlds.empty()) return summary;
  int worlds_with_success = 0;
  double time_sum = 0.0;
  for (const auto& [id, w] : worlds) {
    const double n = w.trials;
    summary.score += w.score / n;
    summary.success_rate += w.successes / n;
    summary.collision_rate += w.collisions / n;
    summary.timeout_rate += w.timeouts / n;
    summary.error_rate += w.errors / n;
    if (w.successes > 0) {
      time_sum += w.success_time / w.successes;
      ++worlds_with_success;
    }
  }
  const double n = static_cast<double>(worlds.size());
  summary.score /= n;
  summary.success_rate /= n;
  summary.collision_rate /= n;
  summary.timeout_rate /= n;
  summary.error_rate /= n;
  summary.avg_success_time = worlds_with_success ? time_sum / worlds_with_success : std::numeric_limits<double>::quiet_NaN();
  return summary;
}

std::string episodesCsv(const std::vector<EpisodeResult>& results) {
  std::ostringstream out;
  out << "world,trial,seed,outcome,time_s,score,optimal_time_s,path_length_m,mean_speed_mps,sim_time_s,"
         "collision_x,collision_y,error\n";
  for (const auto& r : results) {
    out << r.world_id << "," << r.trial << "," << r.seed << "," << toString(r.outcome) << ","
        << core::formatDouble(r.actual_time) << "," << core::formatDouble(r.score) << ","
        << core::formatDouble(r.optimal_time) << "," << core::formatDouble(r.path_length) << ","
        << core::formatDouble(r.mean_speed) << "," << core::formatDouble(r.sim_time) << ",";
    if (r.collision) out << core::formatDouble(r.collision->point.x()) << "," << core::formatDouble(r.collision->point.y());
    else out << ",";
    std::string error = r.error;
    for (char& ch : error)
      if (ch == ',' || ch == '\n' || ch == '"') ch = ';';
    out << "," << error << "\n";
  }
  return out.str();
}

std::string trajectoryCsv(const EpisodeResult& result) {
  std::ostringstream out;
  out << "time_s,x,y,yaw,cmd_linear,cmd_angular,state\n";
  for (const auto& s : result.trajectory) {
    out << core::formatDouble(s.time) << "," << core::formatDouble(s.pose.x) << "," << core::formatDouble(s.pose.y) << ","
        << core::formatDouble(s.pose.yaw) << "," << core::formatDouble(s.command.linear) << ","
        << core::formatDouble(s.command.angular) << "," << s.state << "\n";
  }
  return out.str();
}

std::string summaryTable(const RunSummary& s, const std::string& title) {
  char buffer[1024];
  std::snprintf(buffer, sizeof(buffer),
                "%s\n"
                "  worlds %d, episodes %d\n"
                "  Avg Score      %.4f\n"
                "  Avg Success    %.4f\n"
                "  Avg Collision  %.4f\n"
                "  Avg Timeout    %.4f\n"
                "  Avg Error      %.4f\n"
                "  Avg Time       %.4f s (successful trials)\n",
                title.c_str(), s.worlds, s.episodes, s.score, s.success_rate, s.collision_rate, s.timeout_rate,
                s.error_rate, s.avg_success_time);
  return buffer;
}

}  // namespace barn::bench
