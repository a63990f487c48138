#pragma once
// Runs an example controller the way a researcher can try one before registering it in
// src/controllers/registry.cpp: every world once with barn run's episode seeds and the shipped
// sim config, writing OUT/episodes.csv in barn run's format.
//
//   build/examples/NAME WORLDS OUT [SEED]     e.g.  build/examples/gap_follower 0:300:30 /tmp/gap

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "barn/bench/batch.hpp"
#include "barn/bench/episode.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/sim/obstacle_field.hpp"

namespace barn::examples {

inline int runExample(int argc, char** argv, const std::function<std::unique_ptr<controllers::Controller>()>& make) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: %s WORLDS OUT [SEED]\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path root = BARN_SOURCE_DIR, out = argv[2];
    const std::uint64_t seed = argc == 4 ? std::stoull(argv[3]) : 0;
    const bench::LoadedWorlds loaded = bench::loadWorlds(argv[1], root / "worlds");
    const bench::EpisodeConfig config =
        bench::validatedEpisodeConfig(core::ConfigNode::parseFile(root / "configs" / "sim" / "barn.yaml"), "barn.yaml");
    std::vector<bench::EpisodeResult> results;
    for (const core::WorldSpec& world : loaded.worlds) {
      const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
      const auto controller = make();
      results.push_back(bench::runEpisode(world, field, *controller, config, bench::episodeSeed(seed, world.id, 0)));
      results.back().trial = 0;
    }
    std::filesystem::create_directories(out);
    std::ofstream(out / "episodes.csv") << bench::episodesCsv(results);
    double score = 0.0;
    for (const auto& r : results) score += r.score;
    std::printf("%zu episodes, mean score %.4f -> %s\n", results.size(), score / static_cast<double>(results.size()),
                (out / "episodes.csv").c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}

}  // namespace barn::examples
