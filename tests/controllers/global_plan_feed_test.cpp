#include "barn/controllers/global_plan_feed.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "barn/bench/episode.hpp"
#include "barn/controllers/dwa.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/world_file.hpp"

namespace barn::controllers {
namespace {

using ::testing::HasSubstr;

// The built-in DWA, with a feed configured as DWA's own stack running beside it: at every tick
// the feed's plan is compared with the path DWA plans with.
class DwaWithFeed : public Controller {
 public:
  explicit DwaWithFeed(const DwaConfig& config) : dwa_(config), feed_(GlobalPlanConfig{config.nav, true, true}) {}
  void reset(const EpisodeInfo& info) override {
    dwa_.reset(info);
    feed_.reset(info);
  }
  core::Twist act(const Observation& observation) override {
    Observation fed = observation;
    feed_.update(fed);
    const core::Twist command = dwa_.act(observation);
    const nav::Path& path = dwa_.navStack().path();
    EXPECT_EQ(fed.global_plan->poses.size(), path.size()) << "t = " << observation.time;
    if (fed.global_plan->poses.size() == path.size())
      for (std::size_t i = 0; i < path.size(); ++i) {
        EXPECT_EQ(fed.global_plan->poses[i].x, path[i].x()) << "t = " << observation.time;
        EXPECT_EQ(fed.global_plan->poses[i].y, path[i].y()) << "t = " << observation.time;
      }
    // The costmaps are the ones DWA reads.
    EXPECT_EQ(fed.local_costmap->version, dwa_.navStack().localCostmap().version());
    EXPECT_EQ(fed.global_costmap->version, dwa_.navStack().globalCostmap().version());
    compared_ += !path.empty();
    return command;
  }
  double period() const override { return dwa_.period(); }
  int compared() const { return compared_; }

 private:
  DwaController dwa_;
  GlobalPlanFeed feed_;
  int compared_ = 0;
};

TEST(GlobalPlanFeed, GivesThePlanTheBuiltInDwaPlansWithAtEveryTick) {
  const std::string root = BARN_SOURCE_DIR;
  const core::WorldSpec world = core::readWorldFile(root + "/worlds/world_000.yaml");
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  DwaWithFeed controller{DwaConfig{}};
  const bench::EpisodeResult result = bench::runEpisode(world, field, controller, bench::EpisodeConfig{}, 7);
  EXPECT_EQ(result.outcome, bench::Outcome::Success);  // no recovery cleared DWA's costmaps
  EXPECT_GT(controller.compared(), 200);               // over 10 s of 20 Hz ticks
}

TEST(GlobalPlanFeed, RecordsTheParametersAControllerSets) {
  GlobalPlanFeed feed{GlobalPlanConfig{}};
  EpisodeInfo info;
  info.goal = {0.0, 10.0};
  feed.reset(info);
  core::LaserScan scan;
  scan.angle_increment = 0.01;
  scan.range_max = 30.0;
  scan.ranges.assign(10, 1e9);
  Observation obs;
  obs.scan = &scan;
  feed.update(obs);
  ASSERT_EQ(obs.stack_parameters, &feed);
  obs.stack_parameters->set("global_costmap.inflation_radius", 0.55);
  obs.stack_parameters->set("planner.rate", 10.0);
  EXPECT_EQ(feed.changes(), "global_costmap.inflation_radius=0.55;planner.rate=10");
  EXPECT_THROW(obs.stack_parameters->set("max_vel_x", 1.0), std::invalid_argument);
  feed.update(obs);
  EXPECT_EQ(feed.changes(), "");  // a new tick
  // Without the request, no costmap.
  EXPECT_EQ(obs.local_costmap, nullptr);
  EXPECT_EQ(obs.global_costmap, nullptr);
}

core::ConfigNode yaml(const std::string& text) { return core::ConfigNode::parseString(text, "ctrl.yaml"); }

TEST(GlobalPlanFeed, AnyControllerConfigTakesTheBlock) {
  const PreparedController prepared =
      prepareController(yaml("type: straight\nglobal_plan: {send_local_costmap: true, planner: {rate: 5}}\n"));
  // The effective config records the whole block (defaults included) for the manifest.
  EXPECT_THAT(prepared.effective_config, HasSubstr("global_plan:\n  footprint_length: 0.42"));
  EXPECT_THAT(prepared.effective_config, HasSubstr("send_local_costmap: true"));
  EXPECT_THAT(prepared.effective_config, HasSubstr("algorithm: navfn"));
  const auto controller = prepared.factory();
  EXPECT_NE(dynamic_cast<GlobalPlanFedController*>(controller.get()), nullptr);
  // Unknown keys in the block are errors naming them.
  try {
    prepareController(yaml("type: straight\nglobal_plan: {send_costmap: true}\n"));
    ADD_FAILURE() << "accepted an unknown key";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("global_plan.send_costmap"));
  }
}

}  // namespace
}  // namespace barn::controllers
