// Runs TowardGoal on the worlds WORLDS (barn run's --worlds syntax) of the folder WORLD_DIR
// with the sim config SIM_YAML, one episode each, and prints one line per episode:
//   run_toward_goal WORLD_DIR WORLDS SIM_YAML
#include <cstdio>
#include <exception>
#include <string>

#include "barn/bench/batch.hpp"
#include "barn/bench/episode.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/core/config.hpp"
#include "barn/sim/obstacle_field.hpp"
#include "toward_goal.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s WORLD_DIR WORLDS SIM_YAML\n", argv[0]);
    return 2;
  }
  try {
    const barn::bench::LoadedWorlds loaded = barn::bench::loadWorlds(argv[2], argv[1]);
    const barn::bench::EpisodeConfig config =
        barn::bench::validatedEpisodeConfig(barn::core::ConfigNode::parseFile(argv[3]), argv[3]);
    for (const barn::core::WorldSpec& world : loaded.worlds) {
      const barn::sim::ObstacleField field = barn::sim::ObstacleField::fromWorld(world);
      TowardGoal controller;
      const barn::bench::EpisodeResult r =
          barn::bench::runEpisode(world, field, controller, config, barn::bench::episodeSeed(0, world.id, 0));
      std::printf("world %d: %s after %.2f s, score %.4f\n", r.world_id, std::string(barn::bench::toString(r.outcome)).c_str(),
                  r.actual_time, r.score);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
