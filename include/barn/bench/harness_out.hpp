#pragma once
/// The official BARN harness's results file (run.py --out): one line per episode,
///
///     world_idx success collided timeout time nav_metric
///
/// whitespace separated, written by run.py as "%d %d %d %d %.4f %.4f". run.py sets the flags
/// as: collided if a contact was seen; timeout = (time >= 100); success = neither collided nor
/// timed out (its status checks the collision first). So success excludes both other flags,
/// while collided and timeout can both be 1 (a contact seen at the 100 s check): that episode
/// is a collision. A line with no flag set cannot come from run.py; it is read as a timeout
/// (a failure without contact, the only other failure run.py knows) and counted in
/// HarnessImport::unflagged so the caller can warn. `time` is AT [s]; `nav_metric` is whatever
/// the harness version computed (the score at k = 4 in 2023; some earlier files hold other
/// quantities), so barnbench recomputes the score and only checks the column.

#include <string>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/core/protocol.hpp"
#include "barn/core/world.hpp"

namespace barn::bench {

/// One parsed line.
struct HarnessLine {
  int line = 0;  // 1-based line number in the file
  int world_id = 0;
  bool success = false;
  bool collided = false;
  bool timeout = false;
  double time = 0.0;        // [s] AT
  double nav_metric = 0.0;  // as written by the harness
};

/// Parses a results file's text. Blank lines are skipped. InputError "<where>:<line>: <field>:
/// <problem>" for a line without 6 fields, a non-integer or negative world id, a flag other
/// than 0/1, success together with another flag, or a time/nav_metric that is not a finite
/// number (time must also be >= 0). An empty file is an InputError too.
std::vector<HarnessLine> parseHarnessOut(const std::string& text, const std::string& where);

/// The outcome the line's flags mean (see the header comment).
Outcome harnessOutcome(const HarnessLine& line);

/// How the file's nav_metric column compares with barnbench's recomputation.
struct NavMetricCheck {
  int lines = 0;                 // lines checked
  int score_mismatches = 0;      // |nav_metric - score at k = 4| > 1e-3
  double max_score_difference = 0.0;
  int worst_line = 0;            // line of the largest difference (0 if none)
  int ratio_matches = 0;         // of the mismatches: nav_metric = success * AT / OT within 0.1 %
};

/// A results file as barnbench episodes.
struct HarnessImport {
  std::vector<EpisodeResult> results;  // file order; trials numbered per world in file order
  std::vector<int> world_ids;          // ascending
  int max_trials = 0;                  // most trials of one world
  int min_trials = 0;                  // fewest trials of one world
  int unflagged = 0;                   // lines with no flag set (read as timeouts)
  NavMetricCheck check;
};

/// Turns parsed lines into episodes on `worlds` (the world files of the run, by id): AT =
/// time, OT from the world's A* path under `protocol`, score recomputed with the protocol's
/// clip; path length, mean speed and simulated time are unknown (NaN), seed 0. The check
/// compares nav_metric with the score at k = 4 (clip 4..8 x OT, this protocol's OT).
/// InputError "<where>:<line>: world_idx: ..." for a world not in `worlds`.
HarnessImport importHarnessLines(const std::vector<HarnessLine>& lines, const std::vector<core::WorldSpec>& worlds,
                                 const core::Protocol& protocol, const std::string& where);

/// One results line for an episode, as run.py writes it: flags from the outcome (an Error
/// episode has none set), time = AT and nav_metric = the recorded score, "%.4f".
std::string harnessLine(const EpisodeResult& result);
/// Every episode's line, in the given order.
std::string harnessOut(const std::vector<EpisodeResult>& results);

}  // namespace barn::bench
