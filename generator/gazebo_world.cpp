#include "generator/gazebo_world.hpp"

#include <cstdio>

#include <Eigen/Core>

#include "barn/core/world_geometry.hpp"
#include "generator/dataset_export.hpp"
#include "generator/dataset_files.hpp"

namespace barn::generator {

namespace {

// The cylinder's height only matters to Gazebo (barnbench's simulation is planar); the inertia
// is Gazebo's unit cylinder's, which world_writer.py kept although it scaled the radius. The
// cylinders are static, so neither moves anything.
constexpr const char* kCylinderLength = "1";  // [m]
constexpr const char* kObstacleColour = "0.648 0.192 0.192 1";
constexpr const char* kWallColour = "0.152 0.379 0.720 1";

// Everything before the cylinders: what every competition world shares.
constexpr const char* kWorldStart = R"(<sdf version='1.6'>
  <world name='default'>
    <physics name='default_physics' default='0' type='ode'>
      <max_step_size>0.001</max_step_size>
      <real_time_factor>1</real_time_factor>
      <real_time_update_rate>1000</real_time_update_rate>
    </physics>
    <gravity>0 0 -9.8</gravity>
    <magnetic_field>6e-06 2.3e-05 -4.2e-05</magnetic_field>
    <atmosphere type='adiabatic'/>
    <scene>
      <ambient>0.4 0.4 0.4 1</ambient>
      <background>0.7 0.7 0.7 1</background>
      <shadows>1</shadows>
    </scene>
    <light name='sun' type='directional'>
      <cast_shadows>1</cast_shadows>
      <pose>0 0 10 0 0 0</pose>
      <diffuse>0.8 0.8 0.8 1</diffuse>
      <specular>0.2 0.2 0.2 1</specular>
      <attenuation>
        <range>1000</range>
        <constant>0.9</constant>
        <linear>0.01</linear>
        <quadratic>0.001</quadratic>
      </attenuation>
      <direction>-0.5 0.1 -0.9</direction>
    </light>
    <model name='ground_plane'>
      <static>1</static>
      <link name='link'>
        <collision name='collision'>
          <geometry>
            <plane>
              <normal>0 0 1</normal>
              <size>100 100</size>
            </plane>
          </geometry>
          <surface>
            <friction>
              <ode>
                <mu>100</mu>
                <mu2>50</mu2>
              </ode>
            </friction>
          </surface>
        </collision>
        <visual name='visual'>
          <cast_shadows>0</cast_shadows>
          <geometry>
            <plane>
              <normal>0 0 1</normal>
              <size>100 100</size>
            </plane>
          </geometry>
          <material>
            <script>
              <uri>file://media/materials/scripts/gazebo.material</uri>
              <name>Gazebo/Grey</name>
            </script>
          </material>
        </visual>
      </link>
    </model>
)";

constexpr const char* kWorldEnd = R"(  </world>
</sdf>
)";

// A coordinate as the competition worlds print it ("-4.425", "5.175"): every centre is a
// multiple of 0.075 m, so six decimals hold it exactly and the trailing zeros go.
std::string coordinate(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6f", value);
  std::string out = text;
  out.erase(out.find_last_not_of('0') + 1);
  if (out.back() == '.') out.pop_back();
  return out == "-0" ? "0" : out;
}

std::string cylinderGeometry(const std::string& indent) {
  return indent + "<geometry>\n" + indent + "  <cylinder>\n" + indent + "    <radius>" +
         core::formatDouble(core::kCylinderRadius) + "</radius>\n" + indent + "    <length>" + kCylinderLength +
         "</length>\n" + indent + "  </cylinder>\n" + indent + "</geometry>\n";
}

std::string cylinderModel(int index, const Eigen::Vector2d& centre, const char* colour) {
  std::string m;
  m += "    <model name='cylinder_" + std::to_string(index) + "'>\n";
  m += "      <static>1</static>\n";
  m += "      <pose>" + coordinate(centre.x()) + " " + coordinate(centre.y()) + " 0 0 0 0</pose>\n";
  m += "      <link name='link'>\n";
  m += "        <inertial>\n";
  m += "          <mass>1</mass>\n";
  m += "          <inertia>\n";
  m += "            <ixx>0.145833</ixx>\n            <ixy>0</ixy>\n            <ixz>0</ixz>\n";
  m += "            <iyy>0.145833</iyy>\n            <iyz>0</iyz>\n            <izz>0.125</izz>\n";
  m += "          </inertia>\n";
  m += "        </inertial>\n";
  m += "        <collision name='collision'>\n";
  m += cylinderGeometry("          ");
  m += "        </collision>\n";
  m += "        <visual name='visual'>\n";
  m += cylinderGeometry("          ");
  m += "          <material>\n";
  m += std::string("            <ambient>") + colour + "</ambient>\n";
  m += std::string("            <diffuse>") + colour + "</diffuse>\n";
  m += "          </material>\n";
  m += "        </visual>\n";
  m += "      </link>\n";
  m += "    </model>\n";
  return m;
}

}  // namespace

std::string formatGazeboWorld(const core::WorldSpec& world) {
  // The walls and the field are the two parts of core::allCylinders, in its order; they are
  // taken apart here only to colour them as the competition worlds do.
  const std::vector<Eigen::Vector2d> walls = core::containmentCylinders();
  const std::vector<Eigen::Vector2d> field = core::fieldCylinders(world.grid);
  std::string text = "<?xml version='1.0'?>\n";
  text += "<!-- barnbench world " + std::to_string(world.id) + " (" + std::string(core::toString(world.source)) +
          "): " + std::to_string(walls.size() + field.size()) + " cylinders -->\n";
  text += kWorldStart;
  int index = 0;
  for (const auto& centre : walls) text += cylinderModel(index++, centre, kWallColour);
  for (const auto& centre : field) text += cylinderModel(index++, centre, kObstacleColour);
  text += kWorldEnd;
  return text;
}

std::string gazeboWorldFileName(int id) { return "world_" + std::to_string(id) + ".world"; }

std::vector<core::FileContent> harnessFiles(const std::vector<core::WorldSpec>& worlds) {
  std::vector<core::FileContent> files;
  for (const core::WorldSpec& w : worlds) {
    files.push_back({gazeboWorldFileName(w.id), formatGazeboWorld(w)});
    files.push_back({datasetFile(kPathFiles, w.id).string(), pathNpy(w.path)});
  }
  return files;
}

}  // namespace barn::generator
