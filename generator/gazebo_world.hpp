#pragma once
/// Worlds for the official Gazebo harness: a world as the SDF 1.6 .world file BARN's
/// world_writer.py writes for the competition (GEN world_writer.py and its boilerplate; NC22
/// jackal_helper/worlds/BARN/world_N.world), and the files that harness reads per world.

#include <string>
#include <vector>

#include "barn/core/text_io.hpp"
#include "barn/core/world.hpp"

namespace barn::generator {

/// The .world text: ODE physics at 1 kHz, real time, a sun, a 100 x 100 m ground plane, and one
/// static cylinder model (radius 0.075 m, length 1 m, standing on z = 0) per centre of
/// core::allCylinders(world.grid): containment walls blue, the obstacle field red.
std::string formatGazeboWorld(const core::WorldSpec& world);

/// "world_7.world": the harness's name for world 7.
std::string gazeboWorldFileName(int id);

/// What the harness reads for each world, named relative to its jackal_helper/worlds/BARN/
/// folder: world_N.world, and path_files/path_N.npy, the reference path run.py computes the
/// optimal time from (a path of another world would give a wrong score silently).
std::vector<core::FileContent> harnessFiles(const std::vector<core::WorldSpec>& worlds);

}  // namespace barn::generator
