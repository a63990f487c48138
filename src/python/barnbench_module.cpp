// barnbench._core: the C++ side of the Python package (src/python/barnbench/__init__.py wraps it
// into Env and run()). One BARN episode that Python steps, and the pieces of the experiment
// record that must be written exactly as `barn run` writes them.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <string>
#include <set>
#include <tuple>
#include <utility>
#include <unistd.h>

#include "barn/bench/batch.hpp"
#include "barn/bench/progress.hpp"
#include "barn/bench/episode.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/controllers/external_protocol.hpp"
#include "barn/controllers/global_plan_feed.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
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
  // A protocol given as an argument is the argument's fault, not the sim config file's.
  if (!protocol.empty()) {
    const auto names = enumNames(core::ProtocolName{});
    if (std::find(names.begin(), names.end(), protocol) == names.end()) {
      std::string known;
      for (const std::string_view name : names) known += (known.empty() ? "" : ", ") + std::string(name);
      throw core::InputError("protocol: '" + protocol + "' is not one of " + known);
    }
  }
  core::ConfigNode node = core::ConfigNode::parseFile(sim_config);
  if (!protocol.empty()) node.set("protocol", protocol);
  return bench::validatedEpisodeConfig(node, sim_config);
}

// A `global_plan` block given as YAML (or JSON) text, read and validated as a controller
// config's block is; nullopt for "".
std::optional<controllers::GlobalPlanConfig> parseGlobalPlan(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const core::ConfigNode block = core::ConfigNode::parseString(text, "global_plan");
  auto config = core::readConfig<controllers::GlobalPlanConfig>(block);
  core::Errors errors;
  controllers::validate(config, errors, block.where());
  errors.throwIfAny();
  return config;
}

// The effective text of a global_plan block (every field), as a manifest records it.
std::string effectiveGlobalPlan(const std::string& text) {
  const auto config = parseGlobalPlan(text);
  if (!config) return "";
  core::ConfigWriter writer(2);
  auto copy = *config;
  copy.visit(writer);
  return "global_plan:\n" + writer.text();
}

// What a record of a Python class holds beyond the class name (its manifest's controller
// config, as barnbench/__init__.py writes it): the constructor's keyword arguments as JSON
// text and the global_plan block as YAML text ("" if none).
py::dict recordedPythonConfig(const std::string& controller_config) {
  const core::ConfigNode root = core::ConfigNode::parseString(controller_config, "record controller_config");
  std::string params;
  if (root.has("python") && root.child("python").has("params")) root.child("python").child("params").read(params);
  py::dict d;
  d["params"] = params;
  d["global_plan"] = root.has("global_plan") ? root.child("global_plan").toYaml() : std::string();
  return d;
}

// The episode config a record holds (its manifest's episode_config text).
bench::EpisodeConfig parseEpisodeConfig(const std::string& yaml) {
  return bench::validatedEpisodeConfig(core::ConfigNode::parseString(yaml, "record episode_config"), "record episode_config");
}

// One episode Python steps. The obstacle field lives here, as long as the episode that
// refers to it.
class PyEpisode {
 public:
  PyEpisode(const py::object& world, const std::string& world_dir, const bench::EpisodeConfig& config,
            std::uint64_t seed, double dt, const std::string& global_plan, bool record_trajectory)
      : world_(loadWorld(world, world_dir)),
        field_(std::make_unique<sim::ObstacleField>(sim::ObstacleField::fromWorld(world_))),
        config_(config),
        episode_(std::make_unique<bench::Episode>(world_, *field_, config_, seed, dt)),
        dt_(dt),
        record_trajectory_(record_trajectory) {
    if (const auto plan = parseGlobalPlan(global_plan)) {
      feed_.emplace(*plan);
      feed_->reset(episode_->info());
    }
    arriveAtTick();
  }

  // The tick's observation; the scan as float32 (the Gymnasium convention) or, with
  // `full_precision`, as the doubles every other route gives a controller.
  py::dict observation(bool full_precision) {
    const controllers::Observation& o = fed_;
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
    d["scan_pose"] = py::array_t<double>(
        3, std::array<double, 3>{o.scan_odom_pose.x, o.scan_odom_pose.y, o.scan_odom_pose.yaw}.data());
    d["twist"] = py::array_t<double>(2, std::array<double, 2>{o.odom_twist.linear, o.odom_twist.angular}.data());
    d["goal"] = py::array_t<double>(2, std::array<double, 2>{o.goal.x(), o.goal.y()}.data());
    d["time"] = o.time;
    if (o.global_plan) {
      const std::vector<core::Pose2>& poses = o.global_plan->poses;
      py::array_t<double> plan({static_cast<py::ssize_t>(poses.size()), py::ssize_t{3}});
      double* out = plan.mutable_data();
      for (const core::Pose2& p : poses) {
        *out++ = p.x;
        *out++ = p.y;
        *out++ = p.yaw;
      }
      d["global_plan"] = plan;
      d["global_plan_stamp"] = o.global_plan->stamp;
    }
    if (o.local_costmap) d["local_costmap"] = costmapDict(*o.local_costmap, local_costmap_);
    if (o.global_costmap) d["global_costmap"] = costmapDict(*o.global_costmap, global_costmap_);
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

  // Applies the command and any stack parameters (`params`: {key: value}; an unknown key or a
  // bad value ends the episode as an error naming it, as in every other route).
  void step(double v, double w, const std::string& state, const std::optional<py::dict>& params) {
    if (params && !params->empty()) {
      if (!feed_) {
        episode_->fail("controller threw: params given, but the run has no global_plan block whose parameters they could set");
        return;
      }
      try {
        for (const auto& [key, value] : *params) feed_->set(py::str(key).cast<std::string>(), value.cast<double>());
      } catch (const std::exception& e) {
        episode_->fail(std::string("controller threw: ") + e.what());
        return;
      }
    }
    const core::Twist command{v, w};
    if (record_trajectory_ && std::isfinite(v) && std::isfinite(w))
      trajectory_.push_back({fed_.time, episode_->tickPose(), command, state, feed_ ? std::string(feed_->changes()) : ""});
    {
      py::gil_scoped_release release;  // other Python threads run while the physics steps
      episode_->step(command, state);
      arriveAtTick();
    }
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

  // The trajectory file `barn run --trajectories` writes for this episode (recorded if asked).
  std::string trajectoryCsv() const {
    bench::EpisodeResult r;
    r.trajectory = trajectory_;
    return bench::trajectoryCsv(r);
  }

  // The episodes.csv row `barn run` writes for this episode as trial `trial`.
  std::string csvRow(int trial) const {
    bench::EpisodeResult r = episode_->result();
    r.trial = trial;
    return bench::episodeCsvRow(r);
  }

 private:
  // The tick's observation, fed the global plan when there is a feed (once per tick: the feed
  // folds in the scan and may replan).
  void arriveAtTick() {
    fed_ = episode_->observation();
    if (feed_ && !episode_->done()) feed_->update(fed_);
  }

  // A costmap as a dict of numpy values; the same dict object while its version is unchanged,
  // so an unchanged map costs nothing.
  struct CachedCostmap {
    std::optional<std::uint64_t> version;
    py::dict dict;
  };
  static py::dict costmapDict(const controllers::CostGrid& grid, CachedCostmap& cache) {
    if (cache.version == grid.version) return cache.dict;
    py::array_t<std::uint8_t> costs({static_cast<py::ssize_t>(grid.height), static_cast<py::ssize_t>(grid.width)});
    std::copy_n(grid.costs, static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height), costs.mutable_data());
    py::dict d;
    d["costs"] = costs;
    d["origin"] = py::array_t<double>(2, std::array<double, 2>{grid.origin.x(), grid.origin.y()}.data());
    d["resolution"] = grid.resolution;
    d["version"] = grid.version;
    cache = {grid.version, d};
    return d;
  }

  core::WorldSpec world_;
  std::unique_ptr<sim::ObstacleField> field_;
  bench::EpisodeConfig config_;
  std::unique_ptr<bench::Episode> episode_;
  double dt_;
  bool record_trajectory_;
  std::optional<controllers::GlobalPlanFeed> feed_;
  controllers::Observation fed_;
  CachedCostmap local_costmap_, global_costmap_;
  std::vector<bench::TrajectorySample> trajectory_;
};

// A run record written from Python through bench's record life (record_session.hpp), so it
// is created, journaled, resumed and completed exactly as `barn run` does it. Python runs the
// pending episodes (in processes) and hands back each one's episodes.csv row as it finishes.
class PyRecord {
 public:
  explicit PyRecord(bench::RecordSession session) : session_(std::move(session)) {}

  static std::unique_ptr<PyRecord> create(const std::string& out, const std::string& controller,
                                          const std::string& controller_config, const std::string& worlds_spec,
                                          const std::string& world_dir, const std::string& sim_config,
                                          const std::string& protocol, int trials, std::uint64_t seed, int shard_index,
                                          int shard_count, bool trajectories) {
    bench::checkNoRecord(out);
    if (trials < 1) throw core::InputError("trials: " + std::to_string(trials) + " (must be >= 1)");
    if (shard_count < 0 || (shard_count > 0 && (shard_index < 1 || shard_index > shard_count)))
      throw core::InputError("shard: " + std::to_string(shard_index) + "/" + std::to_string(shard_count) +
                             " (K/N with 1 <= K <= N)");
    const bench::LoadedWorlds loaded = bench::loadWorlds(worlds_spec, world_dir);
    bench::RunManifest m = bench::newManifest(controller, controller_config, loadEpisodeConfig(sim_config, protocol),
                                              loaded, worlds_spec, trials, seed);
    m.shard_index = shard_index;
    m.shard_count = shard_count;
    m.trajectories = trajectories;
    return std::make_unique<PyRecord>(bench::createRecord(std::move(m), loaded.worlds, out));
  }

  static std::unique_ptr<PyRecord> open(const std::string& dir) {
    return std::make_unique<PyRecord>(bench::openRecord(dir));
  }

  // (world id, trial, seed) of every episode still to run, in run order.
  std::vector<std::tuple<int, int, std::uint64_t>> pending() const {
    std::vector<std::tuple<int, int, std::uint64_t>> out;
    const int trials = session_.manifest.trials;
    for (std::size_t i : bench::pendingEpisodes(session_)) {
      const int world = session_.worlds[i / static_cast<std::size_t>(trials)].id;
      const int trial = static_cast<int>(i % static_cast<std::size_t>(trials));
      out.emplace_back(world, trial, bench::episodeSeed(session_.manifest.seed, world, trial));
    }
    return out;
  }

  // Starts a session of `threads` workers; `progress` prints barn run's progress lines on
  // stderr (a bar when it is a terminal).
  void begin(int threads, bool progress) {
    pending_ = bench::pendingEpisodes(session_);
    journal_ = std::make_unique<bench::RecordJournal>(session_, pending_.size(), threads);
    finished_.clear();
    done_.clear();
    if (progress)
      progress_ = std::make_unique<bench::ProgressReporter>(session_.previous.size() + pending_.size(),
                                                            session_.previous.size(), ::isatty(STDERR_FILENO), stderr);
  }

  // A finished episode's csv_row(), checked against the record before it is journaled.
  void append(std::string row, const std::optional<std::string>& trajectory) {
    if (!journal_) throw core::InputError("record: begin() first");
    while (!row.empty() && (row.back() == '\n' || row.back() == '\r')) row.pop_back();
    bench::EpisodeResult r = bench::parseEpisodeRow(row, (session_.dir / bench::kJournalFile).string());
    // The record journals each trajectory with its row (a record that keeps them wants them all).
    if (session_.manifest.trajectories != trajectory.has_value())
      throw core::InputError(session_.dir.string() + ": a trajectory is " + (trajectory ? "given" : "missing") +
                             " for world " + std::to_string(r.world_id) + " trial " + std::to_string(r.trial) +
                             (session_.manifest.trajectories ? ": the record keeps trajectories" : ": the record keeps none"));
    if (trajectory) r.trajectory = bench::parseTrajectoryCsv(*trajectory, "trajectory of world " + std::to_string(r.world_id));
    bench::checkRows(session_.manifest, {r}, session_.dir.string(), pending_, false);
    if (!done_.insert({r.world_id, r.trial}).second)
      throw core::InputError(session_.dir.string() + ": world " + std::to_string(r.world_id) + " trial " +
                             std::to_string(r.trial) + " given twice");
    if (!journal_->append(r)) throw core::IoError(journal_->error());
    if (progress_) progress_->update(r.outcome == bench::Outcome::Success, r.sim_time);
    r.trajectory.clear();  // written; the record's rows do not keep it
    finished_.push_back(std::move(r));
  }

  // True if the record is complete now; else it is left to resume.
  bool finish(double wall_time_s) {
    if (!journal_) throw core::InputError("record: begin() first");
    if (progress_) progress_->finish();
    progress_.reset();
    const bool complete = journal_->finish(std::move(finished_), wall_time_s).has_value();
    journal_.reset();
    finished_.clear();
    return complete;
  }

  const bench::RunManifest& manifest() const { return session_.manifest; }
  std::string dir() const { return session_.dir.string(); }

 private:
  bench::RecordSession session_;
  std::unique_ptr<bench::RecordJournal> journal_;
  std::vector<bench::EpisodeResult> finished_;
  std::unique_ptr<bench::ProgressReporter> progress_;
  std::vector<std::size_t> pending_;     // what begin() found left to run: only these may come
  std::set<std::pair<int, int>> done_;   // (world, trial) appended since begin()
};

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "barnbench's C++ core: a steppable BARN episode and the run record's format";
  py::register_exception<core::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<core::IoError>(m, "IoError", PyExc_OSError);

  py::class_<PyEpisode>(m, "Episode")
      .def(py::init([](const py::object& world, const std::string& world_dir, const std::string& sim_config,
                       const std::string& protocol, std::uint64_t seed, double dt, const std::string& global_plan,
                       bool record_trajectory) {
             return std::make_unique<PyEpisode>(world, world_dir, loadEpisodeConfig(sim_config, protocol), seed, dt,
                                                global_plan, record_trajectory);
           }),
           py::arg("world"), py::arg("world_dir"), py::arg("sim_config"), py::arg("protocol"), py::arg("seed"), py::arg("dt"),
           py::arg("global_plan") = "", py::arg("record_trajectory") = false)
      .def_static("from_record_config",
                  [](const py::object& world, const std::string& world_dir, const std::string& episode_config,
                     std::uint64_t seed, double dt, const std::string& global_plan, bool record_trajectory) {
                    return std::make_unique<PyEpisode>(world, world_dir, parseEpisodeConfig(episode_config), seed, dt,
                                                       global_plan, record_trajectory);
                  },
                  py::arg("world"), py::arg("world_dir"), py::arg("episode_config"), py::arg("seed"), py::arg("dt"),
                  py::arg("global_plan") = "", py::arg("record_trajectory") = false,
                  "The episode of a record: its worlds folder and episode_config text")
      .def("observation", &PyEpisode::observation, py::arg("full_precision") = false)
      .def("info", &PyEpisode::info)
      .def("step", &PyEpisode::step, py::arg("v"), py::arg("w"), py::arg("state") = "", py::arg("params") = py::none())
      .def("trajectory_csv", &PyEpisode::trajectoryCsv)
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
  m.def("protocols", [] {
        std::vector<std::string> names;
        for (const std::string_view name : enumNames(core::ProtocolName{})) names.emplace_back(name);
        return names;
      }, "The protocol presets' names");
  m.def("digest", [](const py::bytes& data) { return core::formatHex(core::fnv1a64(std::string(data))); },
        py::arg("data"), "FNV-1a 64 of the bytes as 16 hex digits, as the manifest's digests");
  m.def("recorded_python_config", &recordedPythonConfig, py::arg("controller_config"),
        "params (JSON text) and global_plan (YAML text) of a Python class's record");
  m.def("effective_global_plan", &effectiveGlobalPlan, py::arg("text"),
        "A global_plan block (YAML or JSON text) checked, with every field, as a manifest records it");
  py::class_<PyRecord>(m, "Record")
      .def_static("create", &PyRecord::create, py::arg("out"), py::arg("controller"), py::arg("controller_config"),
                  py::arg("worlds_spec"), py::arg("world_dir"), py::arg("sim_config"), py::arg("protocol"),
                  py::arg("trials"), py::arg("seed"), py::arg("shard_index") = 0, py::arg("shard_count") = 0,
                  py::arg("trajectories") = false,
                  "A new run record in `out` (checked and locked; written by begin())")
      .def_static("open", &PyRecord::open, py::arg("dir"), "The run record in `dir`, to finish")
      .def("pending", &PyRecord::pending, "(world, trial, seed) of the episodes still to run")
      .def("begin", &PyRecord::begin, py::arg("threads"), py::arg("progress") = true,
           "Writes the manifest and the journal of earlier rows; progress lines on stderr")
      .def("append", &PyRecord::append, py::arg("row"), py::arg("trajectory") = py::none(),
           "Journals a finished episode's csv_row() (and keeps its trajectory_csv())")
      .def("finish", &PyRecord::finish, py::arg("wall_time_s"),
           "Completes the record (True) or leaves it to resume (False)")
      .def_property_readonly("dir", &PyRecord::dir)
      .def_property_readonly("controller", [](const PyRecord& r) { return r.manifest().controller; })
      .def_property_readonly("worlds_folder", [](const PyRecord& r) { return r.manifest().worlds_folder; })
      .def_property_readonly("episode_config", [](const PyRecord& r) { return r.manifest().episode_config; })
      .def_property_readonly("controller_config", [](const PyRecord& r) { return r.manifest().controller_config; })
      .def_property_readonly("complete", [](const PyRecord& r) { return r.manifest().complete; })
      .def_property_readonly("trajectories", [](const PyRecord& r) { return r.manifest().trajectories; });
  m.def("merge", [](const std::vector<std::string>& shards, const std::string& out) {
        bench::mergeShardRecords(std::vector<std::filesystem::path>(shards.begin(), shards.end()), out);
      }, py::arg("shards"), py::arg("out"), "Merges the shard records of one run into `out`, as barn merge does");
  m.attr("SOURCE_DIR") = BARN_SOURCE_DIR;
}
