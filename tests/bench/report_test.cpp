#include "barn/bench/report.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "barn/bench/results_io.hpp"

namespace barn::bench {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

EpisodeResult episode(int world, int trial, Outcome outcome, double actual_time, double score, double sim_time) {
  EpisodeResult r;
  r.world_id = world;
  r.trial = trial;
  r.outcome = outcome;
  r.actual_time = actual_time;
  r.score = score;
  r.sim_time = sim_time;
  return r;
}

// Three worlds with different trial counts, listed interleaved:
//   world 3: 1 trial  -- success AT 10 s, score 0.5
//   world 8: 3 trials -- success AT 20 s (0.3), success AT 30 s (0.15), collision
//   world 1: 2 trials -- timeout, error
std::vector<EpisodeResult> unevenRun() {
  return {
      episode(8, 0, Outcome::Success, 20.0, 0.3, 20.5),
      episode(3, 0, Outcome::Success, 10.0, 0.5, 10.5),
      episode(1, 0, Outcome::Timeout, 100.0, 0.0, 102.0),
      episode(8, 1, Outcome::Success, 30.0, 0.15, 30.5),
      episode(1, 1, Outcome::Error, 0.0, 0.0, 1.0),
      episode(8, 2, Outcome::Collision, 4.0, 0.0, 4.5),
  };
}

TEST(Summarise, ScoreIsTheMeanOverWorldsOfThePerWorldMean) {
  const RunSummary s = summarise(unevenRun());
  EXPECT_EQ(s.worlds, 3);
  EXPECT_EQ(s.episodes, 6);
  // Per world: 3 -> 0.5; 8 -> (0.3 + 0.15 + 0) / 3 = 0.15; 1 -> 0.
  // (0.5 + 0.15 + 0) / 3 = 0.216667, not the per-episode mean 0.95 / 6 = 0.158333.
  EXPECT_NEAR(s.score, 0.65 / 3.0, 1e-12);
}

TEST(Summarise, RatesAreMeansOverWorldsOfThePerWorldRates) {
  const RunSummary s = summarise(unevenRun());
  // Success: (1 + 2/3 + 0) / 3 = 5/9 (per episode it would be 3/6 = 1/2).
  EXPECT_NEAR(s.success_rate, 5.0 / 9.0, 1e-12);
  // Collision: (0 + 1/3 + 0) / 3 = 1/9.
  EXPECT_NEAR(s.collision_rate, 1.0 / 9.0, 1e-12);
  // Timeout: (0 + 0 + 1/2) / 3 = 1/6; error likewise.
  EXPECT_NEAR(s.timeout_rate, 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(s.error_rate, 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(s.success_rate + s.collision_rate + s.timeout_rate + s.error_rate, 1.0, 1e-12);
}

TEST(Summarise, AverageTimeIsOverWorldsWithASuccessOnly) {
  const RunSummary s = summarise(unevenRun());
  // World 3: 10 s; world 8: (20 + 30) / 2 = 25 s; world 1 has no success and is left out.
  // (10 + 25) / 2 = 17.5 s (the per-episode mean of successful ATs would be 60 / 3 = 20 s;
  // counting world 1 as 0 would give 35 / 3 = 11.67 s).
  EXPECT_NEAR(s.avg_success_time, 17.5, 1e-12);
}

TEST(Summarise, SimTimeIsTheTotalOverEpisodes) {
  // 20.5 + 10.5 + 102 + 30.5 + 1 + 4.5 = 169 s.
  EXPECT_NEAR(summarise(unevenRun()).sim_time, 169.0, 1e-12);
}

TEST(Summarise, AverageTimeIsNanWithoutAnySuccess) {
  const RunSummary s = summarise({episode(4, 0, Outcome::Collision, 3.0, 0.0, 3.5),
                                  episode(4, 1, Outcome::Timeout, 100.0, 0.0, 100.5)});
  EXPECT_TRUE(std::isnan(s.avg_success_time));
  EXPECT_EQ(s.score, 0.0);
  EXPECT_EQ(s.success_rate, 0.0);
  EXPECT_DOUBLE_EQ(s.collision_rate, 0.5);
}

TEST(Summarise, EmptyRunGivesZeros) {
  const RunSummary s = summarise({});
  EXPECT_EQ(s.worlds, 0);
  EXPECT_EQ(s.episodes, 0);
  EXPECT_EQ(s.score, 0.0);
  EXPECT_EQ(s.sim_time, 0.0);
}

TEST(Summarise, OneTrialPerWorldEqualsThePlainMean) {
  const RunSummary s = summarise({episode(0, 0, Outcome::Success, 8.0, 0.25, 8.2),
                                  episode(6, 0, Outcome::Success, 12.0, 0.2, 12.2),
                                  episode(12, 0, Outcome::Collision, 2.0, 0.0, 2.2)});
  // (0.25 + 0.2 + 0) / 3 = 0.15.
  EXPECT_NEAR(s.score, 0.15, 1e-12);
  // (8 + 12) / 2 = 10 s.
  EXPECT_NEAR(s.avg_success_time, 10.0, 1e-12);
}

// ---------------------------------------------------------------------------------------------

constexpr char kEpisodesHeader[] =
    "world,trial,seed,outcome,time_s,score,optimal_time_s,path_length_m,mean_speed_mps,sim_time_s,"
    "collision_x,collision_y,states,error\n";

TEST(PerWorldStats, MeanScoreWithTheStudentTIntervalPerWorld) {
  const std::vector<WorldStats> worlds = perWorldStats(unevenRun(), 1.0);
  ASSERT_EQ(worlds.size(), 3u);
  EXPECT_EQ(worlds[0].world_id, 1);
  EXPECT_EQ(worlds[1].world_id, 3);
  EXPECT_EQ(worlds[2].world_id, 8);
  // World 8: scores 0.3, 0.15, 0 -> mean 0.15, sample sd 0.15, t(0.975, 2) = 4.303.
  const WorldStats& w8 = worlds[2];
  EXPECT_EQ(w8.trials, 3);
  EXPECT_NEAR(w8.mean_score, 0.15, 1e-12);
  // 0.15 +- 4.303 * 0.15 / sqrt(3) = 0.15 +- 0.3727: below 0, so the low bound is 0.
  const double half = 4.303 * 0.15 / std::sqrt(3.0);
  EXPECT_EQ(w8.score_ci_low, 0.0);
  EXPECT_NEAR(w8.score_ci_high, 0.15 + half, 1e-12);
  // At a maximum score of 0.5 (barn2024) the high bound 0.5227 is the maximum.
  EXPECT_EQ(perWorldStats(unevenRun(), 0.5)[2].score_ci_high, 0.5);
  EXPECT_EQ(w8.collisions, 1);
  // One trial: no interval.
  EXPECT_TRUE(std::isnan(worlds[1].score_ci_low) && std::isnan(worlds[1].score_ci_high));
}

TEST(SummaryJson, ParsedBackHoldsTheWorldSetAndEveryWorldInOrder) {
  const std::vector<EpisodeResult> run = unevenRun();
  const nlohmann::json json = nlohmann::json::parse(summaryJson("barnbench-generated", summarise(run), perWorldStats(run, 0.5), {}));
  EXPECT_EQ(json["world_set"], "barnbench-generated");
  // World 3's one trial: score 0.5, no interval (null, null); worlds in ascending id 1, 3, 8.
  ASSERT_EQ(json["per_world"].size(), 3u);
  EXPECT_EQ(json["per_world"][0]["world"], 1);
  const nlohmann::json& w3 = json["per_world"][1];
  EXPECT_EQ(w3["world"], 3);
  EXPECT_EQ(w3["trials"], 1);
  EXPECT_EQ(w3["score"], 0.5);
  EXPECT_EQ(w3["score_ci95"], nlohmann::json::array({nullptr, nullptr}));
  EXPECT_EQ(json["per_world"][2]["world"], 8);
  EXPECT_TRUE(json["breakdown"].is_array() && json["breakdown"].empty());
}

TEST(SummaryJson, EveryDoubleReadsBackExactlyAndNonFiniteOnesAreNull) {
  RunSummary s;
  s.worlds = 3;
  s.episodes = 6;
  s.score = 0.65 / 3.0;                 // 0.21666666666666667: 17 significant digits to read back
  s.success_rate = 5.0 / 9.0;
  s.collision_rate = 1e-300;            // tiny, written with an exponent
  s.timeout_rate = 0.1 + 0.2;           // 0.30000000000000004, not 0.3
  s.error_rate = 0.0;
  s.avg_success_time = std::numeric_limits<double>::quiet_NaN();
  s.sim_time = std::numeric_limits<double>::infinity();
  const nlohmann::json summary = nlohmann::json::parse(summaryJson("x", s, {}, {}))["summary"];
  EXPECT_EQ(summary["worlds"], 3);
  EXPECT_EQ(summary["episodes"], 6);
  EXPECT_EQ(summary["score"].get<double>(), 0.65 / 3.0);
  EXPECT_EQ(summary["success_rate"].get<double>(), 5.0 / 9.0);
  EXPECT_EQ(summary["collision_rate"].get<double>(), 1e-300);
  EXPECT_EQ(summary["timeout_rate"].get<double>(), 0.1 + 0.2);
  EXPECT_EQ(summary["error_rate"].get<double>(), 0.0);
  EXPECT_TRUE(summary["avg_success_time_s"].is_null());
  EXPECT_TRUE(summary["sim_time_s"].is_null());
}

TEST(SummaryJson, MembersKeepTheDocumentedOrder) {
  const std::vector<EpisodeResult> run = unevenRun();
  const BucketSummary bucket{"params", "fill 0.15 / smooth 2", summarise(run)};
  const nlohmann::ordered_json json =
      nlohmann::ordered_json::parse(summaryJson("barnbench-generated", summarise(run), perWorldStats(run, 0.5), {bucket}));
  const auto keys = [](const nlohmann::ordered_json& object) {
    std::vector<std::string> names;
    for (const auto& item : object.items()) names.push_back(item.key());
    return names;
  };
  const std::vector<std::string> summary_keys = {"worlds", "episodes", "score", "success_rate", "collision_rate",
                                                 "timeout_rate", "error_rate", "avg_success_time_s", "sim_time_s"};
  EXPECT_EQ(keys(json), (std::vector<std::string>{"world_set", "summary", "per_world", "breakdown"}));
  EXPECT_EQ(keys(json["summary"]), summary_keys);
  EXPECT_EQ(keys(json["per_world"][0]), (std::vector<std::string>{"world", "trials", "score", "score_ci95", "success_rate",
                                                                  "collision_rate", "timeout_rate", "avg_success_time_s"}));
  std::vector<std::string> bucket_keys = {"group", "bucket"};
  bucket_keys.insert(bucket_keys.end(), summary_keys.begin(), summary_keys.end());
  EXPECT_EQ(keys(json["breakdown"][0]), bucket_keys);
  EXPECT_EQ(json["breakdown"][0]["bucket"], "fill 0.15 / smooth 2");
}

TEST(SummaryJson, AWorldSetNameWithQuotesAndNewlinesReadsBack) {
  const std::string name = "a \"quoted\"\nname\twith \\ and \x01";
  const nlohmann::json json = nlohmann::json::parse(summaryJson(name, RunSummary{}, {}, {}));
  EXPECT_EQ(json["world_set"].get<std::string>(), name);
}

TEST(SummaryJson, IsTwoSpaceIndentedEndingInANewline) {
  const std::string text = summaryJson("s", RunSummary{}, {}, {});
  EXPECT_THAT(text, StartsWith("{\n  \"world_set\": \"s\",\n  \"summary\": {\n    \"worlds\": 0,\n"));
  EXPECT_EQ(text.back(), '\n');
}

TEST(WorldSetName, SaysWhereTheWorldsComeFrom) {
  core::WorldSpec generated, imported;
  imported.source = core::WorldSource::BarnDataset;
  EXPECT_EQ(worldSetName({generated, generated}), "barnbench-generated");
  EXPECT_EQ(worldSetName({imported}), "official BARN (imported)");
  EXPECT_EQ(worldSetName({imported, generated}), "mixed");
}

TEST(EpisodesCsv, HasTheHeaderAndOneRowPerResult) {
  const std::vector<EpisodeResult> results = unevenRun();
  const std::string csv = episodesCsv(results);
  EXPECT_THAT(csv, StartsWith(kEpisodesHeader));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + static_cast<long>(results.size()));
  EXPECT_EQ(episodesCsv({}), kEpisodesHeader);
  EXPECT_EQ(episodesCsvHeader(), kEpisodesHeader);
}

TEST(EpisodesCsv, WritesRowsInTheOrderGiven) {
  const std::string csv = episodesCsv(unevenRun());
  // The first row is world 8 trial 0, the second world 3 trial 0: no re-sorting.
  const std::size_t first = csv.find("\n8,0,");
  const std::size_t second = csv.find("\n3,0,");
  ASSERT_NE(first, std::string::npos);
  ASSERT_NE(second, std::string::npos);
  EXPECT_LT(first, second);
}

TEST(EpisodesCsv, FormatsASuccessRow) {
  EpisodeResult r = episode(3, 1, Outcome::Success, 10.0, 0.5, 10.25);
  r.seed = 99;
  r.optimal_time = 5.0;
  r.path_length = 9.5;
  r.mean_speed = 0.75;
  EXPECT_EQ(episodesCsv({r}), std::string(kEpisodesHeader) + "3,1,99,success,10,0.5,5,9.5,0.75,10.25,,,,\n");
}

TEST(EpisodesCsv, WritesTheCollisionPointStatesAndAQuotedError) {
  EpisodeResult hit = episode(5, 0, Outcome::Collision, 2.5, 0.0, 2.75);
  hit.collision = sim::CollisionInfo{2.75, {-2.175, 5.925}, 1, {}};
  hit.state_entries = {{"drive", 2}, {"recover", 1}};
  EpisodeResult broken = episode(5, 1, Outcome::Error, 0.0, 0.0, 1.0);
  broken.error = "controller threw: bad, worse\nworst";
  const std::string csv = episodesCsv({hit, broken});
  EXPECT_THAT(csv, HasSubstr("\n5,0,0,collision,2.5,0,0,0,0,2.75,-2.175,5.925,drive:2|recover:1,\n"));
  // The comma is kept inside quotes (RFC 4180); the newline would end the row: it becomes ';'.
  EXPECT_THAT(csv, HasSubstr("\n5,1,0,error,0,0,0,0,0,1,,,,\"controller threw: bad, worse;worst\"\n"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
}

TEST(TrajectoryCsv, HasOneRowPerSample) {
  EpisodeResult r;
  r.trajectory.push_back({0.0, {-2.0, 3.0, 1.57}, {1.0, 0.0}, "drive", ""});
  r.trajectory.push_back({0.05, {-2.0, 3.05, 1.57}, {1.0, -0.5}, "", "planner.rate=10;local_costmap.inflation_radius=0.5"});
  EXPECT_EQ(trajectoryCsv(r),
            "time_s,x,y,yaw,cmd_linear,cmd_angular,state,params\n"
            "0,-2,3,1.57,1,0,drive,\n"
            "0.05,-2,3.05,1.57,1,-0.5,,planner.rate=10;local_costmap.inflation_radius=0.5\n");
}

TEST(SummaryTable, ShowsTheTitleAndTheScore) {
  const std::string table = summaryTable(summarise(unevenRun()), "pure_pursuit on 3 worlds");
  EXPECT_THAT(table, StartsWith("pure_pursuit on 3 worlds\n"));
  EXPECT_THAT(table, HasSubstr("worlds 3, episodes 6"));
  EXPECT_THAT(table, HasSubstr("Avg Score      0.2167"));
  EXPECT_THAT(table, HasSubstr("Avg Time       17.5000 s"));
}

}  // namespace
}  // namespace barn::bench
