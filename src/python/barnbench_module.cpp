// barnbench._core: the C++ side of the Python package (src/python/barnbench/__init__.py wraps it
// into Env and run()). One BARN episode that Python steps, and the pieces of the experiment
// record that must be written exactly as `barn run` writes them.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <memory>
#include <string>

#include "barn/bench/batch.hpp"
#include "barn/bench/episode.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/controllers/external_protocol.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/world_file.hpp"

namespace py = pybind11;
using namespace barn;

namespace {

// A world given as an id (looked up in `world_dir`) or as a world file.
core::WorldSpec loadWorld(const py::object& world, const std::string& world_dir) {
  if (py::isinstance<py::int_>(world)) {
    const bench::LoadedWorlds loaded = bench::loadWorlds(std::to_string(world.cast<int>()), world_dir);
    return loaded.worlds.front();
  }
  return core::readWorldFile(py::str(world).cast<std::string>());
}

bench::EpisodeConfig loadEpisodeConfig(const std::string& sim_config, const std::string& protocol) {
  core::ConfigNode node = core::ConfigNode::parseFile(sim_config);
  if (!protocol.empty()) node.set("protocol", protocol);
  return bench::validatedEpisodeConfig(node, sim_config);
}

// One episode Python steps. The obstacle field lives here, as long as the episode that
// refers to it.
class PyEpisode {
 public:
  PyEpisode(const py::object& world, const std::string& world_dir, const std::string& sim_config,
            const std::string& protocol, std::uint64_t seed, double dt)
      : world_(loadWorld(world, world_dir)),
        field_(std::make_unique<sim::ObstacleField>(sim::ObstacleField::fromWorld(world_))),
        config_(loadEpisodeConfig(sim_config, protocol)),
        episode_(std::make_unique<bench::Episode>(world_, *field_, config_, seed, dt)),
        dt_(dt) {}

  // The tick's observation; the scan as float32 (the Gymnasium convention) or, with
  // `full_precision`, as the doubles every other route gives a controller.
  py::dict observation(bool full_precision) const {
    const controllers::Observation& o = episode_->observation();
    const std::vector<double>& ranges = o.scan->ranges;
    py::dict d;
    if (full_precision) {
      d["scan"] = py::array_t<double>(static_cast<py::ssize_t>(ranges.size()), ranges.data());
    } else {
      py::array_t<float> scan(static_cast<py::ssize_t>(ranges.size()));
      float* out = scan.mutable_data();
      for (std::size_t i = 0; i < ranges.size(); ++i) out[i] = static_cast<float>(ranges[i]);
      d["scan"] = scan;
    }
    d["pose"] = py::array_t<double>(3, std::array<double, 3>{o.odom_pose.x, o.odom_pose.y, o.odom_pose.yaw}.data());
    d["twist"] = py::array_t<double>(2, std::array<double, 2>{o.odom_twist.linear, o.odom_twist.angular}.data());
    d["goal"] = py::array_t<double>(2, std::array<double, 2>{o.goal.x(), o.goal.y()}.data());
    d["time"] = o.time;
    return d;
  }

  // What a controller is told before the first tick: the fields of the external protocol's
  // reset message (docs/external_controller.md), so every route tells the same.
  py::dict info() const {
    py::dict d = py::module_::import("json").attr("loads")(
        controllers::external::resetMessage(episode_->info(), dt_));
    d.attr("pop")("type");
    d.attr("pop")("protocol");
    d["world"] = world_.id;
    d["optimal_time"] = episode_->result().optimal_time;
    return d;
  }

  void step(double v, double w, const std::string& state) {
    py::gil_scoped_release release;  // other Python threads run while the physics steps
    episode_->step({v, w}, state);
  }
  void fail(const std::string& message) { episode_->fail(message); }
  bool done() const { return episode_->done(); }
  double time() const { return episode_->time(); }

  py::dict result() const {
    const bench::EpisodeResult r = episode_->result();
    py::dict d;
    d["world"] = r.world_id;
    d["outcome"] = episode_->done() ? std::string(bench::toString(r.outcome)) : std::string("running");
    d["score"] = r.score;
    d["actual_time"] = r.actual_time;
    d["optimal_time"] = r.optimal_time;
    d["path_length"] = r.path_length;
    d["sim_time"] = r.sim_time;
    d["error"] = r.error;
    return d;
  }

  // The episodes.csv row `barn run` writes for this episode as trial `trial`.
  std::string csvRow(int trial) const {
    bench::EpisodeResult r = episode_->result();
    r.trial = trial;
    return bench::episodeCsvRow(r);
  }

 private:
  core::WorldSpec world_;
  std::unique_ptr<sim::ObstacleField> field_;
  bench::EpisodeConfig config_;
  std::unique_ptr<bench::Episode> episode_;
  double dt_;
};

// Writes the complete record of a Python controller's run, as barn run writes one: the
// manifest (what was run), episodes.csv (sorted) and summary.json. `rows` are the episodes'
// csv_row() lines; they are checked against the record (seeds, no episode twice, none missing).
void writeRecord(const std::string& out, const std::string& controller, const std::string& controller_config,
                 const std::string& worlds_spec, const std::string& world_dir, const std::string& sim_config,
                 const std::string& protocol, int trials, std::uint64_t seed, const std::vector<std::string>& rows,
                 int jobs, double wall_time_s) {
  const bench::LoadedWorlds loaded = bench::loadWorlds(worlds_spec, world_dir);
  bench::RunManifest m = bench::newManifest(controller, controller_config, loadEpisodeConfig(sim_config, protocol), loaded,
                                            worlds_spec, trials, seed);
  m.episodes_total = rows.size();
  m.threads = jobs;
  m.wall_time_s = wall_time_s;
  std::vector<bench::EpisodeResult> results;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::string line = rows[i];
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    results.push_back(bench::parseEpisodeRow(line, out + " row " + std::to_string(i + 1)));
  }
  bench::checkRows(m, results, out, {}, true);
  bench::writeCompleteRecord(out, m, results, loaded.worlds);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "barnbench's C++ core: a steppable BARN episode and the run record's format";
  py::register_exception<core::InputError>(m, "InputError", PyExc_ValueError);

  py::class_<PyEpisode>(m, "Episode")
      .def(py::init<const py::object&, const std::string&, const std::string&, const std::string&, std::uint64_t, double>(),
           py::arg("world"), py::arg("world_dir"), py::arg("sim_config"), py::arg("protocol"), py::arg("seed"), py::arg("dt"))
      .def("observation", &PyEpisode::observation, py::arg("full_precision") = false)
      .def("info", &PyEpisode::info)
      .def("step", &PyEpisode::step, py::arg("v"), py::arg("w"), py::arg("state") = "")
      .def("fail", &PyEpisode::fail)
      .def_property_readonly("done", &PyEpisode::done)
      .def_property_readonly("time", &PyEpisode::time)
      .def("result", &PyEpisode::result)
      .def("csv_row", &PyEpisode::csvRow, py::arg("trial"));

  m.def("select_worlds", [](const std::string& spec, const std::string& world_dir) {
    const bench::LoadedWorlds loaded = bench::loadWorlds(spec, world_dir);
    std::vector<int> ids;
    for (const auto& w : loaded.worlds) ids.push_back(w.id);
    return py::make_tuple(ids, loaded.folder.string());
  }, py::arg("spec"), py::arg("world_dir"), "The world ids a --worlds spec names and the folder they are in");
  m.def("episode_seed", &bench::episodeSeed, py::arg("run_seed"), py::arg("world_id"), py::arg("trial"),
        "The seed `barn run --seed run_seed` gives this episode");
  m.def("episodes_csv_header", &bench::episodesCsvHeader);
  m.def("write_record", &writeRecord, py::arg("out"), py::arg("controller"), py::arg("controller_config"),
        py::arg("worlds_spec"), py::arg("world_dir"), py::arg("sim_config"), py::arg("protocol"), py::arg("trials"),
        py::arg("seed"), py::arg("rows"), py::arg("jobs"), py::arg("wall_time_s"),
        "Writes a complete run record (manifest.yaml, episodes.csv, summary.json) as barn run does");
  m.attr("SOURCE_DIR") = BARN_SOURCE_DIR;
}
