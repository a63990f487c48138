// barnbench._core: the C++ side of the Python package (src/python/barnbench/__init__.py wraps it
// into Env and run()). One BARN episode that Python steps, and the pieces of the experiment
// record that must be written exactly as `barn run` writes them.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <mutex>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <string>
#include <set>
#include <thread>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>
#include <unistd.h>

#include "barn/bench/batch.hpp"
#include "barn/bench/episode_batch.hpp"
#include "barn/bench/progress.hpp"
#include "barn/bench/controller_lookup.hpp"
#include "barn/bench/episode.hpp"
#include "barn/bench/record_session.hpp"
#include "barn/bench/results_io.hpp"
#include "barn/bench/run_record.hpp"
#include "barn/bench/world_selection.hpp"
#include "barn/controllers/e2e.hpp"
#include "barn/controllers/global_plan_feed.hpp"
#include "barn/controllers/registry.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "barn/core/world_file.hpp"
#include "barn/external/external_protocol.hpp"
#include "barn/learning/mlp_policy.hpp"
#include "barn/report/report.hpp"
#include "barn/sim/simulator.hpp"

namespace py = pybind11;
using namespace barn;

namespace {

// A world given as an id (looked up in `world_dir`) or as a world file.
// An id reads its own file (world_007.yaml) when that file holds it, which costs a millisecond
// where reading and checking the whole set costs some 0.2 s (every Env.reset makes an episode);
// otherwise (another naming, a missing id) the set decides, with its messages.
core::WorldSpec loadWorld(const py::object& world, const std::string& world_dir) {
  if (py::isinstance<py::int_>(world)) {
    const int id = world.cast<int>();
    const std::filesystem::path file = std::filesystem::path(world_dir) / core::worldFileName(id);
    std::error_code ec;
    if (id >= 0 && std::filesystem::is_regular_file(file, ec)) {
      try {
        core::WorldSpec spec = core::readWorldFile(file);
        if (spec.id == id) return spec;
      } catch (const core::InputError&) {
        // the set's reading reports it
      }
    }
    const bench::LoadedWorlds loaded = bench::loadWorlds(std::to_string(id), world_dir);
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

// ---------------------------------------------------------------------------------------------
// A Python controller's side of an episode, for Env (PyEpisode) and run_episode (PyController)
// alike: the observation and reset dicts it is handed and the stack parameters it may send.

// A costmap as a dict of numpy values; the same dict object while its version is unchanged,
// so an unchanged map costs nothing.
struct CachedCostmap {
  std::optional<std::uint64_t> version;
  py::dict dict;
};

py::dict costmapDict(const controllers::CostGrid& grid, CachedCostmap& cache) {
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

// A tick's observation as a dict of numpy values; the scan as float32 (the Gymnasium
// convention) or, with `full_precision`, as the doubles every other route gives a controller.
py::dict observationDict(const controllers::Observation& o, bool full_precision, CachedCostmap& local_costmap,
                         CachedCostmap& global_costmap) {
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
  if (o.local_costmap) d["local_costmap"] = costmapDict(*o.local_costmap, local_costmap);
  if (o.global_costmap) d["global_costmap"] = costmapDict(*o.global_costmap, global_costmap);
  return d;
}

// What a controller is told before the first tick: the fields of the external protocol's
// reset message (docs/external_controller.md), so every route tells the same, and the world's
// id and optimal time.
py::dict infoDict(const controllers::EpisodeInfo& info, double period, int world_id, double optimal_time) {
  py::dict d = py::module_::import("json").attr("loads")(external::resetMessage(info, period));
  d.attr("pop")("type");
  d.attr("pop")("protocol");
  d["world"] = world_id;
  d["optimal_time"] = optimal_time;
  return d;
}

// Python's text of `value` for a message, cut to a few dozen characters.
std::string shown(const py::handle& value) {
  constexpr std::size_t kShown = 60;  // [characters]
  std::string text;
  try {
    text = py::repr(value).cast<std::string>();
  } catch (const py::error_already_set&) {
    text = "<" + std::string(Py_TYPE(value.ptr())->tp_name) + ">";
  }
  return text.size() > kShown ? text.substr(0, kShown) + "..." : text;
}

// The stack parameters of one command checked as the external protocol checks its "params"
// member (external_protocol.hpp): a dict of at most kMaxParams entries, each a str key of at
// most kMaxNameBytes bytes and a finite number (not a bool). Fills `checked` in the dict's
// order and returns "", or returns what is wrong, naming the key or the count.
std::string paramsProblem(const py::object& params, std::vector<std::pair<std::string, double>>& checked) {
  namespace ext = external;
  if (!py::isinstance<py::dict>(params))
    return "a dict {key: number} (got " + std::string(Py_TYPE(params.ptr())->tp_name) + ")";
  const py::dict dict = params.cast<py::dict>();
  if (dict.size() > ext::kMaxParams)
    return "more than " + std::to_string(ext::kMaxParams) + " parameters in one command (" +
           std::to_string(dict.size()) + ")";
  for (const auto& [key, value] : dict) {
    if (!py::isinstance<py::str>(key))
      return "the key " + shown(key) + " is not a string (" + std::string(Py_TYPE(key.ptr())->tp_name) + ")";
    std::string name;
    try {
      name = key.cast<std::string>();
    } catch (const std::exception&) {  // a lone surrogate has no UTF-8
      return "the key " + shown(key) + " is not valid text";
    }
    if (name.size() > ext::kMaxNameBytes)
      return "the key " + shown(key) + " is longer than " + std::to_string(ext::kMaxNameBytes) + " bytes";
    double number = std::numeric_limits<double>::quiet_NaN();
    if (!py::isinstance<py::bool_>(value)) {
      try {
        number = value.cast<double>();
      } catch (const py::cast_error&) {  // not a number, or an int beyond a double's range
      }
    }
    if (!std::isfinite(number)) return name + ": must be a finite number (got " + shown(value) + ")";
    checked.emplace_back(std::move(name), number);
  }
  return "";
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

  // The tick's observation (observationDict): the scan as float32 (the Gymnasium convention)
  // or, with `full_precision`, as the doubles every other route gives a controller.
  py::dict observation(bool full_precision) {
    return observationDict(fed_, full_precision, local_costmap_, global_costmap_);
  }

  // What a controller is told before the first tick (infoDict).
  py::dict info() const { return infoDict(episode_->info(), dt_, world_.id, episode_->result().optimal_time); }

  // Applies the command and any stack parameters (`params`: {key: value}). Parameters out of
  // the external protocol's bounds (paramsProblem), an unknown key or a bad value end the
  // episode as an error naming the key or the count, as in every other route.
  void step(double v, double w, const std::string& state, const py::object& params) {
    if (!params.is_none()) {
      std::vector<std::pair<std::string, double>> checked;
      if (const std::string problem = paramsProblem(params, checked); !problem.empty()) {
        episode_->fail("controller's params: " + problem);
        return;
      }
      if (!checked.empty() && !feed_) {
        episode_->fail("controller threw: params given, but the run has no global_plan block whose parameters they could set");
        return;
      }
      try {
        for (const auto& [key, value] : checked) feed_->set(key, value);
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

// What a Python exception says in an error row: its text, with its type's name when that is
// all there is or when it is an exit (SystemExit: 3, KeyboardInterrupt: ).
std::string describe(const py::error_already_set& error) {
  const py::object value = error.value();
  std::string text;
  try {
    text = static_cast<std::string>(py::str(value));
  } catch (const py::error_already_set&) {  // its str() raised too
    text = "<unprintable " + std::string(Py_TYPE(value.ptr())->tp_name) + ">";
  }
  if (text.empty() || error.matches(PyExc_SystemExit) || error.matches(PyExc_KeyboardInterrupt))
    text = static_cast<std::string>(py::str(py::type::handle_of(value).attr("__name__"))) + ": " + text;
  return text;
}

// A Python controller as bench's controller, so bench::runEpisode (the loop of barn run)
// runs it: reset(info) with infoDict's dict, act(obs) with observationDict's (the scan as
// doubles), answering (v, w), (v, w, state) or {"v", "w", optional "state", optional
// "params": {key: value}}. What the Python object raises becomes a std::runtime_error with
// describe()'s text, so the episode ends as an error naming it. The loop runs without the
// GIL; each call into Python takes it. It is made, and dies, with the GIL held.
class PyController : public controllers::Controller {
 public:
  PyController(py::object controller, double period, int world_id, double optimal_time)
      : controller_(std::move(controller)), period_(period), world_id_(world_id), optimal_time_(optimal_time) {}
  void reset(const controllers::EpisodeInfo& info) override {
    std::string failure;
    {
      py::gil_scoped_acquire gil;
      try {
        local_costmap_ = {};
        global_costmap_ = {};
        state_.clear();
        controller_.attr("reset")(infoDict(info, period_, world_id_, optimal_time_));
        return;
      } catch (const py::error_already_set& e) {
        failure = describe(e);
      }
    }
    throw std::runtime_error(failure);
  }

  core::Twist act(const controllers::Observation& observation) override {
    std::string failure;
    {
      py::gil_scoped_acquire gil;
      try {
        const py::object answer =
            controller_.attr("act")(observationDict(observation, true, local_costmap_, global_costmap_));
        return command(answer, observation);
      } catch (const py::error_already_set& e) {
        failure = describe(e);
      }
    }
    throw std::runtime_error(failure);
  }

  double period() const override { return period_; }
  std::string_view stateLabel() const override { return state_; }

 private:
  // The answer read as Python reads it (float(), str(), the same messages on bad values);
  // its stack parameters checked (paramsProblem) and set.
  core::Twist command(const py::object& answer, const controllers::Observation& observation) {
    py::object params = py::none();
    double v = 0.0, w = 0.0;
    if (py::isinstance<py::dict>(answer)) {
      const py::object unknown = py::set(answer).attr("__sub__")(py::set(py::make_tuple("v", "w", "state", "params")));
      if (py::len(unknown) > 0) {
        const py::object names = py::str(", ").attr("join")(py::module_::import("builtins").attr("sorted")(unknown));
        throw std::runtime_error("unknown keys in the command: " + static_cast<std::string>(py::str(names)));
      }
      v = py::float_(answer[py::str("v")]).cast<double>();
      w = py::float_(answer[py::str("w")]).cast<double>();
      state_ = static_cast<std::string>(py::str(answer.attr("get")("state", "")));
      params = answer.attr("get")("params");
    } else {
      v = py::float_(answer[py::int_(0)]).cast<double>();
      w = py::float_(answer[py::int_(1)]).cast<double>();
      state_ = py::len(answer) > 2 ? static_cast<std::string>(py::str(answer[py::int_(2)])) : std::string();
    }
    if (!params.is_none()) {
      std::vector<std::pair<std::string, double>> checked;
      if (const std::string problem = paramsProblem(params, checked); !problem.empty())
        throw std::runtime_error("params: " + problem);
      if (!checked.empty() && !observation.stack_parameters)
        throw std::runtime_error("params given, but the run has no global_plan block whose parameters they could set");
      for (const auto& [key, value] : checked) observation.stack_parameters->set(key, value);
    }
    return {v, w};
  }

  py::object controller_;
  double period_;  // [s]
  int world_id_;
  double optimal_time_;  // [s]
  std::string state_;    // the last answer's state label
  CachedCostmap local_costmap_, global_costmap_;
};

// One episode of a Python controller through bench::runEpisode: (the episodes.csv row barn
// run writes for it as trial `trial`, its trajectory CSV or None).
py::tuple runPythonEpisode(const py::object& controller, const py::object& world, const std::string& world_dir,
                           const std::string& episode_config, std::uint64_t seed, int trial,
                           const std::string& global_plan, bool record_trajectory) {
  const core::WorldSpec spec = loadWorld(world, world_dir);
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(spec);
  const bench::EpisodeConfig config = parseEpisodeConfig(episode_config);
  const double period = py::float_(py::getattr(controller, "period", py::float_(0.05))).cast<double>();
  std::unique_ptr<controllers::Controller> adapter = std::make_unique<PyController>(
      controller, period, spec.id, core::optimalTime(spec.path, bench::episodeProtocol(config)));
  if (const auto plan = parseGlobalPlan(global_plan))
    adapter = std::make_unique<controllers::GlobalPlanFedController>(*plan, std::move(adapter));
  bench::EpisodeResult result;
  {
    py::gil_scoped_release release;
    result = bench::runEpisode(spec, field, *adapter, config, seed, record_trajectory);
  }
  result.trial = trial;
  py::object trajectory = py::none();
  if (record_trajectory) trajectory = py::str(bench::trajectoryCsv(result));
  return py::make_tuple(bench::episodeCsvRow(result), trajectory);
}

// A built-in controller for barnbench.run(NAME, config=FILE): its config (FILE, else
// configs/controllers/NAME.yaml, else the type NAME with its defaults, as barn run
// --controller NAME reads it), checked against the episode config as barn run checks it before
// a record is made. Returns its effective config, as the manifest records it.
std::string builtinController(const std::string& name, const std::string& config_file, const std::string& sim_config,
                            const std::string& protocol) {
  const core::ConfigNode node =
      bench::controllerConfigNode(name, config_file, std::filesystem::path(BARN_SOURCE_DIR) / "configs" / "controllers",
                                  {"controller", "config=FILE"});
  const bench::EpisodeConfig episode = loadEpisodeConfig(sim_config, protocol);
  const controllers::PreparedController prepared = controllers::prepareController(node);
  bench::checkControllerFits(*prepared.factory(), episode);
  return prepared.effective_config;
}

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

  // Runs the pending episodes of a record of a C++ controller (its manifest's controller
  // config, made as barn run --resume makes it) in `threads` threads of bench's batch,
  // journaling each as it ends: what barn run does, in this process. Ctrl-C (Python's
  // KeyboardInterrupt) starts no new episode; the running ones finish and are kept, then the
  // KeyboardInterrupt is raised (finish() leaves the record to resume). A controller trained on
  // another plant is warned of on stderr, as barn run warns.
  void runController(int threads) {
    if (!journal_) throw core::InputError("record: begin() first");
    const bench::RunManifest& m = session_.manifest;
    bench::BatchSpec batch;
    batch.worlds = session_.worlds;
    batch.trials = m.trials;
    batch.seed = m.seed;
    batch.episode = parseEpisodeConfig(m.episode_config);
    batch.make_controller =
        controllers::makeControllerFactory(core::ConfigNode::parseString(m.controller_config, "record controller_config"));
    batch.record_trajectories = m.trajectories;
    batch.selected = pending_;
    try {
      if (const std::string warning = bench::plantMismatch(*batch.make_controller(), batch.episode); !warning.empty())
        std::fprintf(stderr, "warning: %s: %s\n", m.controller.c_str(), warning.c_str());
    } catch (const std::exception&) {
      // A controller that cannot be made (its policy file gone) fails every episode, as in barn run.
    }

    std::atomic<bool> stop{false};
    std::string journal_error;  // the first failed journal write: the run stops there
    std::vector<bench::EpisodeResult> results;
    std::exception_ptr failure;
    std::mutex mutex;
    std::condition_variable ended;
    bool done = false;
    std::optional<py::error_already_set> interrupt;
    {
      py::gil_scoped_release release;
      std::thread runner([&] {
        try {
          results = bench::runBatch(batch, {threads, &stop}, [&](const bench::EpisodeResult& r, std::size_t, std::size_t) {
            if (journal_error.empty() && !journal_->append(r)) {
              journal_error = journal_->error();
              stop.store(true);  // nothing more can be kept: start no new episode
            }
            if (progress_) progress_->update(r.outcome == bench::Outcome::Success, r.sim_time);
          });
        } catch (...) {
          failure = std::current_exception();
        }
        const std::lock_guard<std::mutex> lock(mutex);
        done = true;
        ended.notify_one();
      });
      // Python sees a Ctrl-C only when it checks its signals, holding the GIL.
      std::unique_lock<std::mutex> lock(mutex);
      constexpr std::chrono::milliseconds kSignalCheck{100};
      while (!ended.wait_for(lock, kSignalCheck, [&] { return done; })) {
        if (interrupt) continue;
        lock.unlock();
        {
          py::gil_scoped_acquire gil;
          if (PyErr_CheckSignals() != 0) {
            interrupt.emplace();  // takes the KeyboardInterrupt, to raise once the batch has stopped
            stop.store(true);
          }
        }
        lock.lock();
      }
      lock.unlock();
      runner.join();
    }
    for (bench::EpisodeResult& r : results) {
      r.trajectory.clear();  // written; the record's rows do not keep it
      finished_.push_back(std::move(r));
    }
    if (failure) std::rethrow_exception(failure);
    if (interrupt) throw std::move(*interrupt);
    if (!journal_error.empty())
      throw core::IoError(journal_error + " (the episodes journaled before it are kept; resume=True when the disk has room)");
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


// N episodes stepped together (bench::EpisodeBatch) with numpy views onto its arrays: the
// arrays live as long as the batch, and every step overwrites them in place.
class PyEpisodeBatch {
 public:
  PyEpisodeBatch(const std::string& worlds_spec, const std::string& world_dir, const std::string& sim_config,
                 const std::string& protocol, double success_radius, bench::EpisodeBatchConfig config,
                 const std::string& global_plan) {
    const bench::LoadedWorlds loaded = bench::loadWorlds(worlds_spec, world_dir);
    config.episode = loadEpisodeConfig(sim_config, protocol);
    if (success_radius > 0.0) {
      config.episode.success_radius = success_radius;
      core::Errors errors("success_radius");
      bench::validate(config.episode, errors);
      errors.throwIfAny();
    }
    config.global_plan = parseGlobalPlan(global_plan);
    batch_ = std::make_unique<bench::EpisodeBatch>(loaded.worlds, config);
  }

  void reset(const std::optional<std::uint64_t>& seed) {
    py::gil_scoped_release release;
    if (seed) batch_->reset(*seed);
    else if (batch_->started()) batch_->resetNext();
    else batch_->reset(0);
  }

  void step(const py::array_t<double, py::array::c_style | py::array::forcecast>& actions) {
    const py::ssize_t n = batch_->size();
    if (actions.ndim() != 2 || actions.shape(0) != n || actions.shape(1) != 2)
      throw core::InputError("actions: an array of shape (" + std::to_string(n) + ", 2) of (v, w) (got shape " +
                             shapeText(actions) + ")");
    const double* data = actions.data();
    py::gil_scoped_release release;
    batch_->step(data);
  }

  // Views onto the arrays (valid after the first reset; the same memory for the batch's life).
  py::dict arrays(const py::object& self) {
    if (!batch_->started()) throw core::InputError("reset the batch first");
    py::dict d;
    d["observation"] = observationViews(batch_->observation, self);
    d["final_observation"] = observationViews(batch_->final_observation, self);
    d["info"] = infoViews(batch_->info, self);
    d["final_info"] = infoViews(batch_->final_info, self);
    d["reward"] = view(batch_->reward, {n()}, self);
    d["terminated"] = boolView(batch_->terminated, self);
    d["truncated"] = boolView(batch_->truncated, self);
    d["ended"] = boolView(batch_->ended, self);
    return d;
  }

  int size() const { return batch_->size(); }
  int beams() const { return batch_->beams(); }
  std::vector<int> worldIds() const {
    std::vector<int> ids;
    for (const auto& w : batch_->worlds()) ids.push_back(w.id);
    return ids;
  }
  py::dict facts() const {
    const bench::EpisodeConfig& e = batch_->config().episode;
    py::dict d;
    d["beams"] = e.lidar.beams;
    d["max_linear_speed"] = e.robot.max_linear_speed;
    d["max_angular_speed"] = e.robot.max_angular_speed;
    d["success_radius"] = e.success_radius;
    d["local_costmap_shape"] = py::make_tuple(batch_->localCostmapShape().first, batch_->localCostmapShape().second);
    d["global_costmap_shape"] = py::make_tuple(batch_->globalCostmapShape().first, batch_->globalCostmapShape().second);
    return d;
  }

 private:
  py::ssize_t n() const { return batch_->size(); }
  static std::string shapeText(const py::array& a) {
    std::string text = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) text += (k ? ", " : "") + std::to_string(a.shape(k));
    return text + (a.ndim() == 1 ? ",)" : ")");
  }
  template <class T>
  static py::array view(std::vector<T>& data, std::vector<py::ssize_t> shape, const py::object& self) {
    return py::array_t<T>(shape, data.data(), self);
  }
  static py::array boolView(std::vector<std::uint8_t>& data, const py::object& self) {
    return py::array(py::dtype("bool"), {static_cast<py::ssize_t>(data.size())}, {py::ssize_t{1}}, data.data(), self);
  }
  py::dict observationViews(bench::BatchObservation& o, const py::object& self) {
    py::dict d;
    d["scan"] = view(o.scan, {n(), batch_->beams()}, self);
    d["pose"] = view(o.pose, {n(), 3}, self);
    d["scan_pose"] = view(o.scan_pose, {n(), 3}, self);
    d["twist"] = view(o.twist, {n(), 2}, self);
    d["goal"] = view(o.goal, {n(), 2}, self);
    d["time"] = view(o.time, {n()}, self);
    if (batch_->config().global_plan) {
      d["global_plan_end"] = view(o.plan_end, {n(), 2}, self);
      d["global_plan_stamp"] = view(o.plan_stamp, {n()}, self);
      if (batch_->config().plan_points > 0) d["global_plan"] = view(o.plan, {n(), batch_->config().plan_points, 3}, self);
      const auto [lh, lw] = batch_->localCostmapShape();
      if (lh > 0) {
        d["local_costmap"] = view(o.local_costmap, {n(), lh, lw}, self);
        d["local_costmap_origin"] = view(o.local_costmap_origin, {n(), 2}, self);
      }
      const auto [gh, gw] = batch_->globalCostmapShape();
      if (gh > 0) {
        d["global_costmap"] = view(o.global_costmap, {n(), gh, gw}, self);
        d["global_costmap_origin"] = view(o.global_costmap_origin, {n(), 2}, self);
      }
    }
    return d;
  }
  py::dict infoViews(bench::BatchInfo& info, const py::object& self) {
    py::dict d;
    d["outcome"] = view(info.outcome, {n()}, self);
    d["score"] = view(info.score, {n()}, self);
    d["actual_time"] = view(info.actual_time, {n()}, self);
    d["world"] = view(info.world, {n()}, self);
    d["seed"] = view(info.seed, {n()}, self);
    d["length"] = view(info.length, {n()}, self);
    d["episode_return"] = view(info.episode_return, {n()}, self);
    return d;
  }

  std::unique_ptr<bench::EpisodeBatch> batch_;
};

// The End-to-End encoding from a dict of E2eEncoding's keys (missing keys: the defaults).
controllers::E2eEncoding e2eEncoding(const py::dict& d) {
  controllers::E2eEncoding e;
  for (const auto& [key, value] : d) {
    const std::string k = py::str(key);
    if (k == "frames") e.frames = value.cast<int>();
    else if (k == "range_clip") e.range_clip = value.cast<double>();
    else if (k == "goal_scale") e.goal_scale = value.cast<double>();
    else if (k == "min_v") e.min_v = value.cast<double>();
    else if (k == "max_v") e.max_v = value.cast<double>();
    else if (k == "min_w") e.min_w = value.cast<double>();
    else if (k == "max_w") e.max_w = value.cast<double>();
    else throw core::InputError("encoding: unknown key '" + k + "'");
  }
  core::Errors errors;
  controllers::validate(e, errors, "encoding");
  errors.throwIfAny();
  return e;
}

// One e2e frame per row: scans (N x beams), odometry poses (N x 3), plan ends in the odom frame
// (N x 2), previous actions (N x 2) -> N x (beams + 4) float32, exactly as the e2e controller
// encodes a tick.
py::array_t<float> e2eFrames(const py::array_t<float, py::array::c_style | py::array::forcecast>& scans,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& poses,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& plan_ends,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& actions,
                             const py::dict& encoding) {
  const controllers::E2eEncoding e = e2eEncoding(encoding);
  if (scans.ndim() != 2) throw core::InputError("scans: an array of shape (N, beams)");
  const py::ssize_t n = scans.shape(0), beams = scans.shape(1);
  const auto check = [&](const py::array& a, py::ssize_t cols, const char* name) {
    if (a.ndim() != 2 || a.shape(0) != n || a.shape(1) != cols)
      throw core::InputError(std::string(name) + ": an array of shape (" + std::to_string(n) + ", " +
                             std::to_string(cols) + ")");
  };
  check(poses, 3, "poses");
  check(plan_ends, 2, "plan_ends");
  check(actions, 2, "actions");
  const py::ssize_t size = controllers::e2eFrameSize(static_cast<int>(beams));
  py::array_t<float> out({n, size});
  float* o = out.mutable_data();
  const float* s = scans.data();
  const double* p = poses.data();
  const double* g = plan_ends.data();
  const double* a = actions.data();
  for (py::ssize_t i = 0; i < n; ++i) {
    const core::Pose2 pose{p[3 * i], p[3 * i + 1], p[3 * i + 2]};
    controllers::encodeE2eFrame(s + i * beams, static_cast<int>(beams), pose.inverseTransform({g[2 * i], g[2 * i + 1]}),
                                core::Twist{a[2 * i], a[2 * i + 1]}, e, o + i * size);
  }
  return out;
}

// An MLP policy file for Python: written from a list of (weight, bias) numpy arrays (weight
// out x in, as torch's nn.Linear holds it) and read back for inference.
void writeMlpPolicy(const std::string& path, const std::vector<std::pair<py::array_t<float, py::array::c_style | py::array::forcecast>,
                                                              py::array_t<float, py::array::c_style | py::array::forcecast>>>& layers,
                    const py::dict& header) {
  learning::MlpPolicyInfo info;
  std::vector<learning::MlpLayer> out;
  for (const auto& [w, b] : layers) {
    if (w.ndim() != 2 || b.ndim() != 1) throw core::InputError("layers: (weight (out, in), bias (out,)) pairs");
    learning::MlpLayer layer;
    // Row-major (out, in) into Eigen's column-major out x in.
    layer.weight = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        w.data(), w.shape(0), w.shape(1));
    layer.bias = Eigen::Map<const Eigen::VectorXf>(b.data(), b.shape(0));
    if (info.layers.empty()) info.layers.push_back(static_cast<int>(w.shape(1)));
    info.layers.push_back(static_cast<int>(w.shape(0)));
    out.push_back(std::move(layer));
  }
  for (const auto& [key, value] : header) {
    const std::string k = py::str(key);
    if (k == "output") info.output = value.cast<std::string>() == "tanh" ? learning::MlpOutput::Tanh : learning::MlpOutput::Linear;
    else if (k == "output_low") info.output_low = value.cast<std::vector<double>>();
    else if (k == "output_high") info.output_high = value.cast<std::vector<double>>();
    else if (k == "input") info.input = value.cast<std::string>();
    else if (k == "output_text") info.output_text = value.cast<std::string>();
    else if (k == "dtype") info.half = value.cast<std::string>() == "float16";
    else if (k == "name") info.name = value.cast<std::string>();
    else if (k == "config_hash") info.config_hash = value.cast<std::uint64_t>();
    else if (k == "plant_hash") info.plant_hash = value.cast<std::uint64_t>();
    else if (k == "trained") info.trained = value.cast<std::string>();
    else if (k == "seed") info.seed = value.cast<std::uint64_t>();
    else if (k == "steps") info.steps = value.cast<long long>();
    else throw core::InputError("header: unknown key '" + k + "'");
  }
  learning::writeMlpPolicyFile(path, info, out);
}

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

  m.def("run_episode", &runPythonEpisode, py::arg("controller"), py::arg("world"), py::arg("world_dir"),
        py::arg("episode_config"), py::arg("seed"), py::arg("trial"), py::arg("global_plan") = "",
        py::arg("record_trajectory") = false,
        "Runs one episode of a Python controller (reset(info), act(obs), optional period) through "
        "bench::runEpisode, barn run's loop: (its episodes.csv row, its trajectory CSV or None)");
  m.def("builtin_controller", &builtinController, py::arg("name"), py::arg("config_file"), py::arg("sim_config"),
        py::arg("protocol"), "A built-in controller's effective config, checked as barn run checks it");
  m.def("select_worlds", [](const std::string& spec, const std::string& world_dir) {
    const bench::LoadedWorlds loaded = bench::loadWorlds(spec, world_dir);
    std::vector<int> ids;
    for (const auto& w : loaded.worlds) ids.push_back(w.id);
    return py::make_tuple(ids, loaded.folder.string());
  }, py::arg("spec"), py::arg("world_dir"), "The world ids a --worlds spec names and the folder they are in");
  m.def("episode_seed", &bench::episodeSeed, py::arg("run_seed"), py::arg("world_id"), py::arg("trial"),
        "The seed `barn run --seed run_seed` gives this episode");
  m.def("episodes_csv_header", &bench::episodesCsvHeader);
  // episodes.csv's column names in order, from the one table barn writes and reads them by.
  m.attr("EPISODE_COLUMNS") = py::tuple(py::cast(bench::episodeColumnNames()));
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
      .def("run_controller", &PyRecord::runController, py::arg("threads"),
           "Runs the pending episodes of a built-in controller's record in C++ threads, as barn run does")
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
  m.def("report", [](const std::string& input, const std::string& out, int max_failures) {
        report::ReportOptions options;
        options.max_failures = max_failures;
        py::gil_scoped_release release;  // failed episodes of a built-in controller are re-simulated in C++
        report::writeReport(input, out, options);
      }, py::arg("input"), py::arg("out"), py::arg("max_failures"),
      "The HTML page of a run record or sweep, as barn report writes it");
  py::class_<PyEpisodeBatch>(m, "EpisodeBatch")
      .def(py::init([](const std::string& worlds, const std::string& world_dir, const std::string& sim_config,
                       const std::string& protocol, int num_envs, double dt, long max_steps, const py::dict& reward,
                       double success_radius, const std::string& global_plan, int plan_points, double plan_spacing,
                       int threads) {
             bench::EpisodeBatchConfig c;
             c.num_envs = num_envs;
             c.dt = dt;
             c.max_steps = max_steps;
             c.plan_points = plan_points;
             c.plan_spacing = plan_spacing;
             c.threads = threads;
             for (const auto& [key, value] : reward) {
               const std::string k = py::str(key);
               double* field = k == "progress" ? &c.reward.progress : k == "step" ? &c.reward.step
                             : k == "success" ? &c.reward.success : k == "collision" ? &c.reward.collision
                             : k == "timeout" ? &c.reward.timeout : nullptr;
               if (!field) throw core::InputError("reward: unknown key '" + k + "' (progress, step, success, collision, timeout)");
               *field = value.cast<double>();
             }
             return std::make_unique<PyEpisodeBatch>(worlds, world_dir, sim_config, protocol, success_radius, c, global_plan);
           }),
           py::arg("worlds"), py::arg("world_dir"), py::arg("sim_config"), py::arg("protocol"), py::arg("num_envs"),
           py::arg("dt"), py::arg("max_steps") = 0, py::arg("reward") = py::dict(), py::arg("success_radius") = 0.0,
           py::arg("global_plan") = "", py::arg("plan_points") = 0, py::arg("plan_spacing") = 0.25, py::arg("threads") = 0)
      .def("reset", &PyEpisodeBatch::reset, py::arg("seed") = py::none())
      .def("step", &PyEpisodeBatch::step, py::arg("actions"))
      .def("arrays", [](py::object self) { return self.cast<PyEpisodeBatch&>().arrays(self); })
      .def("facts", &PyEpisodeBatch::facts)
      .def_property_readonly("size", &PyEpisodeBatch::size)
      .def_property_readonly("beams", &PyEpisodeBatch::beams)
      .def_property_readonly("world_ids", &PyEpisodeBatch::worldIds);
  m.def("run_bare_episodes",
        [](const std::string& worlds, const std::string& world_dir, const std::string& sim_config,
           const std::string& protocol, int num_envs, double dt, long max_steps, int threads, std::uint64_t seed,
           double v, double w, long steps) {
          bench::EpisodeBatchConfig c;
          c.num_envs = num_envs;
          c.dt = dt;
          c.max_steps = max_steps;
          c.threads = threads;
          c.episode = loadEpisodeConfig(sim_config, protocol);
          const bench::LoadedWorlds loaded = bench::loadWorlds(worlds, world_dir);
          bench::BareRun run;
          {
            py::gil_scoped_release release;
            run = bench::runBareEpisodes(loaded.worlds, c, seed, core::Twist{v, w}, steps);
          }
          return py::make_tuple(run.simulated, run.wall, run.cpu);
        },
        py::arg("worlds"), py::arg("world_dir"), py::arg("sim_config"), py::arg("protocol"), py::arg("num_envs"),
        py::arg("dt"), py::arg("max_steps"), py::arg("threads"), py::arg("seed"), py::arg("v"), py::arg("w"),
        py::arg("steps"), "VecEnv's episodes stepped by bench::Episode alone (the benchmark's reference): (simulated s, wall s, process CPU s)");
  m.def("vec_episode_seed", &bench::episodeSeedOf, py::arg("seed"), py::arg("index"), py::arg("count"),
        "The episode seed of a VecEnv sub-environment's episode `count` after reset(seed)");
  m.def("vec_world_index", &bench::worldIndexOf, py::arg("seed"), py::arg("index"), py::arg("count"), py::arg("worlds"),
        "The index into the world list of that episode's world");
  m.def("plant_hash", [](const std::string& sim_config) {
        const bench::EpisodeConfig c = loadEpisodeConfig(sim_config, "");
        return sim::plantHash(c.robot, c.physics);
      }, py::arg("sim_config"), "sim::plantHash of a sim config's robot and physics (what a policy trained on it records)");
  m.def("e2e_frames", &e2eFrames, py::arg("scans"), py::arg("poses"), py::arg("plan_ends"), py::arg("actions"),
        py::arg("encoding") = py::dict(), "The e2e controller's frame for each row, as it encodes a tick");
  m.def("e2e_input_text", [](const py::dict& encoding) { return controllers::e2eInputText(e2eEncoding(encoding)); },
        py::arg("encoding") = py::dict(), "The input text of an e2e actor trained on this encoding");
  m.def("write_mlp_policy", &writeMlpPolicy, py::arg("path"), py::arg("layers"), py::arg("header"),
        "Writes an MLP policy file (barnbench-mlp-policy) from (weight, bias) pairs");
  py::class_<learning::MlpPolicy>(m, "MlpPolicy")
      .def_static("load", [](const std::string& path) { return learning::MlpPolicy::load(path); }, py::arg("path"))
      .def("forward", [](const learning::MlpPolicy& p, const py::array_t<float, py::array::c_style | py::array::forcecast>& x) {
             if (x.ndim() != 1 || x.shape(0) != p.inputs())
               throw core::InputError("input: a vector of " + std::to_string(p.inputs()) + " floats");
             const Eigen::VectorXd y = p.forward(x.data());
             return std::vector<double>(y.data(), y.data() + y.size());
           }, py::arg("x"))
      .def_property_readonly("inputs", &learning::MlpPolicy::inputs)
      .def_property_readonly("outputs", &learning::MlpPolicy::outputs)
      .def_property_readonly("input_text", [](const learning::MlpPolicy& p) { return p.info().input; })
      .def_property_readonly("steps", [](const learning::MlpPolicy& p) { return p.info().steps; })
      .def_property_readonly("dtype", [](const learning::MlpPolicy& p) { return p.info().half ? "float16" : "float32"; });
  m.attr("SOURCE_DIR") = BARN_SOURCE_DIR;
}
