"""barnbench from Python: a BARN episode as a Gymnasium-style environment, and batch runs.

    import barnbench
    env = barnbench.Env(world=0)
    obs, info = env.reset(seed=1)
    while True:
        obs, reward, terminated, truncated, info = env.step((0.5, 0.0))
        if terminated or truncated:
            break
    print(info["outcome"], info["score"])

    summary = barnbench.run(MyController, worlds="test50", trials=1, jobs=2, out="results/mine")
    barnbench.run(MyController, out="results/mine", resume=True)   # after an interruption
    barnbench.merge(["shard_1", "shard_2"], out="merged")         # run(..., shard=(k, 2)) each

Observations are dicts of numpy arrays in the odom frame (the start, facing the protocol's
heading): "scan" (the LiDAR's beams, inf for no return), "pose" (x, y, yaw), "scan_pose" (the
pose when the scan was taken, up to one LiDAR period earlier: place the scan's returns with it),
"twist" (v, w), "goal" (x, y), and "time" (simulated seconds). With a global_plan block (a dict:
`Env(..., global_plan={...})`, `run(..., global_plan={...})`) they also carry move_base's plan,
"global_plan" (n x 3: x, y, yaw from the robot to the goal) made at "global_plan_stamp", and on
request "local_costmap" / "global_costmap" (dicts: "costs", a uint8 array indexed [y, x];
"origin", "resolution", "version"; the same object while the map is unchanged). One step is one
control period (Env.dt).

The protocol (the score's scale) is `barnbench.default_protocol` unless a call names one:
"barn2023" (k = 4, the 2022-23 editions) unless the environment variable BARN_PROTOCOL says
otherwise; set it once per session with `barnbench.default_protocol = "barn2024"`.
"""

import csv
import inspect
import json
import math
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import time

import numpy as np

from . import _core
from ._core import InputError, IoError

__all__ = ["Env", "VecEnv", "run", "merge", "report", "read_episodes", "default_reward", "default_protocol", "InputError",
           "IoError"]

_SOURCE_DIR = _core.SOURCE_DIR
_DEFAULT_SIM_CONFIG = os.path.join(_SOURCE_DIR, "configs", "sim", "barn.yaml")
_DEFAULT_WORLD_DIR = os.path.join(_SOURCE_DIR, "worlds")

default_protocol = os.environ.get("BARN_PROTOCOL", "barn2023")

# A Python controller's episode may take this much wall time before it is failed as hung.
DEFAULT_EPISODE_TIMEOUT = 300.0  # [s]

try:  # Gymnasium is optional: its spaces are offered when it is installed.
    import gymnasium as _gym
except ImportError:  # pragma: no cover - depends on the machine
    _gym = None


def default_reward(previous_distance, distance, outcome):
    """Progress toward the goal [m] this step, +10 on success, -10 on a collision."""
    reward = previous_distance - distance
    if outcome == "success":
        reward += 10.0
    elif outcome == "collision":
        reward -= 10.0
    return reward


def _protocol(protocol):
    protocol = default_protocol if protocol is None else protocol
    if protocol not in _core.protocols():
        raise InputError(f"protocol: {protocol!r} is not one of {', '.join(_core.protocols())}")
    return protocol


def _global_plan_text(global_plan):
    """A global_plan dict (or None) as the text _core reads; checked by C++."""
    if global_plan is None:
        return ""
    if not isinstance(global_plan, dict):
        raise InputError(f"global_plan: a dict of the block's keys (got {type(global_plan).__name__})")
    return json.dumps(global_plan)


def _flag(value, name):
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name}: True or False (got {value!r})")
    return bool(value)


def _seed(seed, name="seed"):
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**64:
        raise InputError(f"{name}: an integer in [0, 2^64 - 1] (got {seed!r})")
    return seed


class Env:
    """One BARN world as an environment. `world` is an id (in `world_dir`, default the
    repository's worlds/) or a world file; `sim_config` a sim config file (default
    configs/sim/barn.yaml); `protocol` barn2023 or barn2024 (default barnbench.default_protocol);
    `dt` the control period [s]; `reward` a function (previous_distance, distance, outcome) ->
    float, default default_reward; `global_plan` a dict of the global_plan block's keys
    (docs/controllers.md, "Bring your own local planner") to run move_base's stack beside the
    policy and observe its plan (and costmaps)."""

    def __init__(self, world, world_dir=None, protocol=None, sim_config=None, dt=0.05, reward=default_reward,
                 global_plan=None):
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise InputError(f"dt: must be a positive number of seconds (got {dt!r})")
        if isinstance(world, bool) or not isinstance(world, (int, str, os.PathLike)):
            raise InputError(f"world: an id or a world file (got {world!r})")
        if isinstance(world, int) and not 0 <= world < 2**31:
            raise InputError(f"world: {world} is not a world id")
        self.world = world
        self.world_dir = world_dir or _DEFAULT_WORLD_DIR
        self.protocol = _protocol(protocol)
        self.sim_config = sim_config or _DEFAULT_SIM_CONFIG
        self.dt = float(dt)
        self.reward = reward
        self.global_plan = global_plan
        self._plan_text = _global_plan_text(global_plan)
        self._episode = None
        self._distance = None
        if _gym is not None:
            # The spaces follow the configured LiDAR and robot (an episode's reset facts).
            facts = self._new_episode(0).info()
            inf = np.inf
            spaces = {
                "scan": _gym.spaces.Box(0.0, inf, shape=(facts["lidar"]["beams"],), dtype=np.float32),
                "pose": _gym.spaces.Box(-inf, inf, shape=(3,), dtype=np.float64),
                "scan_pose": _gym.spaces.Box(-inf, inf, shape=(3,), dtype=np.float64),
                "twist": _gym.spaces.Box(-inf, inf, shape=(2,), dtype=np.float64),
                "goal": _gym.spaces.Box(-inf, inf, shape=(2,), dtype=np.float64),
                "time": _gym.spaces.Box(0.0, inf, shape=(), dtype=np.float64),
            }
            self.observation_space = _gym.spaces.Dict(spaces)
            robot = facts["robot"]
            high = np.array([robot["max_linear_speed"], robot["max_angular_speed"]])
            self.action_space = _gym.spaces.Box(-high, high, dtype=np.float64)

    def _new_episode(self, seed):
        return _core.Episode(self.world, self.world_dir, self.sim_config, self.protocol, _seed(seed), self.dt,
                             self._plan_text)

    def reset(self, seed=None, options=None):
        """Starts a new episode; the same seed gives the same episode bit for bit."""
        del options
        self._episode = self._new_episode(0 if seed is None else seed)
        obs = self._episode.observation()
        self._distance = _goal_distance(obs)
        info = self._episode.info()
        info.update(self._episode.result())
        return obs, info

    def step(self, action, params=None):
        """Applies (v, w) for one control period, and `params` ({key: value}, stack parameters
        to set first, as dynamic_reconfigure; needs a global_plan block). Returns obs, reward,
        terminated, truncated, info; info["outcome"] is running, success, collision, timeout or
        error. Stepping an ended episode raises: call reset()."""
        if self._episode is None:
            raise RuntimeError("call reset() before step()")
        if self._episode.done:
            raise RuntimeError("the episode has ended; call reset() before step()")
        try:
            v, w = (float(a) for a in action)
        except (TypeError, ValueError):
            raise InputError(f"action: (v, w), two numbers (got {action!r})") from None
        self._episode.step(v, w, "", params)
        obs = self._episode.observation()
        info = self._episode.result()
        distance = _goal_distance(obs)
        reward = self.reward(self._distance, distance, info["outcome"])
        self._distance = distance
        terminated = info["outcome"] in ("success", "collision", "error")
        truncated = info["outcome"] == "timeout"
        return obs, reward, terminated, truncated, info


_OUTCOMES = np.array(["running", "success", "collision", "timeout", "error"])


def _worlds_spec(worlds):
    """A --worlds spec from a spec string or a list of world ids."""
    if isinstance(worlds, str):
        return worlds
    try:
        ids = [int(w) for w in worlds]
    except (TypeError, ValueError):
        raise InputError(f"worlds: a spec (all, test50, A:B[:STEP], 3,7,9, a folder) or a list of ids (got {worlds!r})")
    if not ids or any(isinstance(w, bool) or w < 0 for w in worlds):
        raise InputError("worlds: a non-empty list of world ids >= 0")
    return ",".join(str(w) for w in ids)


class VecEnv:
    """`num_envs` BARN episodes stepped together in C++ threads, as a Gymnasium-style vector
    environment (docs/rl.md): reset(seed=) -> (obs, infos); step(actions) -> (obs, rewards,
    terminations, truncations, infos), every value a numpy array with one row per
    sub-environment.

    `worlds`: a --worlds spec ("all", "test50", "A:B[:STEP]", "3,7,9", a folder) or a list of
    world ids (in `world_dir`, default the repository's worlds/); each episode's world is drawn
    uniformly from it by a seeded sampler. Sub-environment i's k-th episode after reset(seed=S)
    has the seed VecEnv.episode_seed(S, i, k) and its world from (S, i, k) too, so the batches do
    not depend on `threads` (0: all cores). `dt` [s] is the action repeat; `max_steps` truncates
    an episode after that many steps (None: the protocol's 100 s only); `success_radius` [m]
    overrides the protocol's 1 m; `reward` a dict of the reward terms (progress, step,
    success, collision, timeout; default Env's default_reward: 1, 0, 10, -10, 0); `global_plan`
    a dict of the global_plan block's keys (docs/controllers.md) to run move_base's stack beside
    every episode: then obs holds "global_plan_end" (the plan's last x, y; the goal until a plan
    is found), "global_plan_stamp", with `plan_points` > 0 "global_plan" (points x 3: x, y, yaw
    every `plan_spacing` m along the plan), and the costmaps the block asks for. Observations
    are Env's keys with a leading axis. An episode that ends is reset at once: obs holds the new
    episode's first observation, infos["final_observation"] (rows where
    infos["_final_observation"] is set) the ended one's last, and infos["final_info"] its
    outcome, score, world, seed, length and return. With copy=False the arrays are views onto
    the C++ batch's memory (no copy), overwritten by the next step or reset."""

    def __init__(self, num_envs, worlds="all", world_dir=None, protocol=None, sim_config=None, dt=0.05,
                 max_steps=None, success_radius=None, reward=None, global_plan=None, plan_points=0, plan_spacing=0.25,
                 threads=0, copy=True):
        if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
            raise InputError(f"num_envs: an integer >= 1 (got {num_envs!r})")
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise InputError(f"dt: must be a positive number of seconds (got {dt!r})")
        if max_steps is not None and (isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 1):
            raise InputError(f"max_steps: None or an integer >= 1 (got {max_steps!r})")
        if success_radius is not None and not (isinstance(success_radius, (int, float)) and success_radius > 0):
            raise InputError(f"success_radius: None or a positive number of metres (got {success_radius!r})")
        if reward is not None and not isinstance(reward, dict):
            raise InputError(f"reward: a dict of reward terms (got {type(reward).__name__})")
        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 0:
            raise InputError(f"threads: an integer >= 0, 0 for all cores (got {threads!r})")
        if isinstance(plan_points, bool) or not isinstance(plan_points, int) or plan_points < 0:
            raise InputError(f"plan_points: an integer >= 0 (got {plan_points!r})")
        self.num_envs = num_envs
        self.dt = float(dt)
        self.copy = bool(copy)
        self.protocol = _protocol(protocol)
        self._batch = _core.EpisodeBatch(_worlds_spec(worlds), world_dir or _DEFAULT_WORLD_DIR,
                                         sim_config or _DEFAULT_SIM_CONFIG, self.protocol, num_envs, self.dt,
                                         max_steps or 0, reward or {}, float(success_radius or 0.0),
                                         _global_plan_text(global_plan), plan_points, float(plan_spacing), threads)
        self.world_ids = list(self._batch.world_ids)
        self._views = None
        facts = self._batch.facts()
        self.single_action_high = np.array([facts["max_linear_speed"], facts["max_angular_speed"]])
        if _gym is not None:
            self.single_action_space = _gym.spaces.Box(-self.single_action_high, self.single_action_high,
                                                       dtype=np.float64)
            self.action_space = _gym.spaces.Box(np.tile(-self.single_action_high, (num_envs, 1)),
                                                np.tile(self.single_action_high, (num_envs, 1)), dtype=np.float64)

    @staticmethod
    def episode_seed(seed, index, count):
        """The seed of sub-environment `index`'s episode `count` (0, 1, ...) after reset(seed=seed):
        Env(world=...).reset(seed=VecEnv.episode_seed(...)) replays it."""
        return _core.vec_episode_seed(_seed(seed), index, count)

    def reset(self, seed=None, options=None):
        """Starts every sub-environment's next episode (episode 0 of `seed`'s streams when a seed is
        given). Returns (obs, infos)."""
        del options
        self._batch.reset(None if seed is None else _seed(seed))
        if self._views is None:
            self._views = self._batch.arrays()
        return self._out(self._views["observation"]), self._infos(False)

    def step(self, actions):
        """Applies actions[i] = (v, w) to sub-environment i for dt seconds."""
        if self._views is None:
            raise RuntimeError("call reset() before step()")
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape != (self.num_envs, 2):
            raise InputError(f"actions: shape ({self.num_envs}, 2) of (v, w) (got {actions.shape})")
        self._batch.step(actions)
        v = self._views
        return (self._out(v["observation"]), self._out(v["reward"]), self._out(v["terminated"]),
                self._out(v["truncated"]), self._infos(True))

    def close(self):
        self._batch = None
        self._views = None

    def _out(self, value):
        if isinstance(value, dict):
            return {k: (a.copy() if self.copy else a) for k, a in value.items()}
        return value.copy() if self.copy else value

    def _infos(self, stepped):
        v = self._views
        info = v["info"]
        infos = {"world": self._out(info["world"]), "seed": self._out(info["seed"]),
                 "length": self._out(info["length"])}
        if stepped:
            ended = v["ended"]
            infos["_final_observation"] = ended.copy()
            infos["_final_info"] = ended.copy()
            if ended.any():
                infos["final_observation"] = self._out(v["final_observation"])
                final = v["final_info"]
                infos["final_info"] = {"outcome": _OUTCOMES[final["outcome"]], "score": self._out(final["score"]),
                                       "actual_time": self._out(final["actual_time"]),
                                       "world": self._out(final["world"]), "seed": self._out(final["seed"]),
                                       "length": self._out(final["length"]),
                                       "episode_return": self._out(final["episode_return"])}
        return infos


def _goal_distance(obs):
    return float(np.hypot(*(obs["goal"] - obs["pose"][:2])))


def run(controller, worlds="test50", world_dir=None, trials=1, jobs=2, seed=0, protocol=None, out=None,
        sim_config=None, config=None, resume=False, shard=None, params=None, global_plan=None, trajectories=False,
        episode_timeout=DEFAULT_EPISODE_TIMEOUT, progress=True):
    """Scores `controller` on `worlds` x `trials` and writes the experiment record to `out`.

    `controller` is a built-in name ("dwa", "inventec_fi", ...: run in this process by barn run's
    C++ batch, the same record) or a Python class with reset(info) and act(obs) -> (v, w),
    (v, w, state label) or a dict {"v", "w", optional "state", optional "params": {key: value}}
    (stack parameters to set, with a global_plan block), and an optional `period` [s] (default
    0.05). One instance per worker process, made as `controller(**params)`, reset every episode;
    each episode runs in barn run's episode loop (C++), which calls the instance. `info` holds
    what the external protocol's reset message holds (docs/external_controller.md); `obs` is
    Env's observation with the scan as float64, the exact doubles C++ and external controllers
    see.
    `global_plan`: a dict of the global_plan block's keys (docs/controllers.md): move_base's
    plan (and costmaps) in every observation. `protocol`: barn2023 or barn2024, default
    barnbench.default_protocol. `config` is a controller config file for a built-in run (barn
    run --config; e.g. an `external` controller). `trajectories=True` also writes
    trajectories/ as barn run --trajectories does. Either way `out` holds barn run's record
    (manifest.yaml, episodes.csv, summary.json; every barn command reads it) and its summary is
    returned. Progress lines go to stderr unless `progress=False`.
    A Python controller that raises, crashes its worker process, or takes longer than
    `episode_timeout` wall seconds for one episode fails that episode only (`error`, with the
    reason); its worker is replaced and the run goes on, whatever `jobs`.
    The record is journaled as episodes finish, as barn run does: after an interruption
    (Ctrl-C, a killed job) `run(controller, out=DIR, resume=True)` runs only what is left (the
    experiment's settings come from the record). `shard=(k, n)` runs every n-th episode from
    the k-th (barn run --shard k/n); merge() puts the shards together. An argument that does
    not apply to the controller given (`config` with a class; `params`, `global_plan`,
    `episode_timeout` with a built-in name) is refused, not ignored."""
    if out is None:
        raise InputError("out: a folder for the record is required")
    shard_index, shard_count = _shard(shard)
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0:
        raise InputError(f"jobs: a number of worker processes >= 1, or 0 for one per core (got {jobs!r})")
    jobs = jobs or os.cpu_count() or 1
    if isinstance(trials, bool) or not isinstance(trials, int) or trials < 1:
        raise InputError(f"trials: an integer >= 1 (got {trials!r})")
    _seed(seed)
    resume, trajectories, progress = (_flag(resume, "resume"), _flag(trajectories, "trajectories"),
                                      _flag(progress, "progress"))
    if isinstance(episode_timeout, bool) or not (isinstance(episode_timeout, (int, float))
                                                 and math.isfinite(episode_timeout) and episode_timeout > 0):
        raise InputError(f"episode_timeout: a positive number of seconds (got {episode_timeout!r})")
    if isinstance(controller, str):
        # What only a Python class takes is refused, not ignored: a built-in's are in its config.
        for name, value in (("params", params), ("global_plan", global_plan)):
            if value is not None:
                raise InputError(f"{name}: for a Python class; the built-in {controller!r} reads its own from its "
                                 "config (config=FILE)")
        if episode_timeout != DEFAULT_EPISODE_TIMEOUT:
            raise InputError(f"episode_timeout: for a Python class; the built-in {controller!r} has none")
        return _run_builtin(controller, worlds, world_dir or _DEFAULT_WORLD_DIR, trials, jobs, seed, _protocol(protocol),
                            out, sim_config or _DEFAULT_SIM_CONFIG, config, resume, shard_index, shard_count, trajectories,
                            progress)
    if not isinstance(controller, type):
        raise InputError("controller: a built-in name or a class with reset(info) and act(obs)")
    if config is not None:
        raise InputError("config: a controller config file, for a built-in name; a Python class takes params= "
                         "and global_plan=")
    if params is not None and not isinstance(params, dict):
        raise InputError(f"params: a dict of keyword arguments for the controller (got {type(params).__name__})")
    return _run_python(controller, params or {}, worlds, world_dir or _DEFAULT_WORLD_DIR, trials, jobs, seed,
                       None if resume else _protocol(protocol), out, sim_config or _DEFAULT_SIM_CONFIG, resume,
                       shard_index, shard_count, global_plan, trajectories, float(episode_timeout), progress)


def merge(shards, out):
    """Merges the shard records of one run (run(..., shard=(k, n)) or barn run --shard) into
    `out`, the record a single run writes, as `barn merge` does; returns its summary."""
    if isinstance(shards, (str, os.PathLike)):
        raise InputError(f"shards: a list of shard record folders (got {shards!r})")
    _core.merge([str(s) for s in shards], str(out))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


EPISODE_COLUMNS = _core.EPISODE_COLUMNS  # episodes.csv's columns, as barn writes them


def read_episodes(record):
    """The rows of a record's episodes.csv as dicts keyed by EPISODE_COLUMNS (text values, as
    written: read quoted fields with the csv module, not by splitting at commas)."""
    path = os.path.join(record, "episodes.csv")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or tuple(rows[0]) != EPISODE_COLUMNS:
        raise InputError(f"{path}: not an episodes.csv (unexpected header)")
    return [dict(zip(EPISODE_COLUMNS, row)) for row in rows[1:]]


def report(record, out, max_failures=12):
    """Writes the HTML page of a finished run record or sweep folder `record` to `out` (a .html
    file), the same page `barn report <record> --out <out>` writes: the summary, per-world and
    difficulty tables, and the figures (failed episodes drawn from recorded trajectories, else
    re-simulated, at most `max_failures`). Returns `out`."""
    if isinstance(max_failures, bool) or not isinstance(max_failures, int) or not 0 <= max_failures <= 1000:
        raise InputError(f"max_failures: a whole number from 0 to 1000 (got {max_failures!r})")
    _core.report(str(record), str(out), max_failures)
    return str(out)


def _shard(shard):
    if shard is None:
        return 0, 0
    try:
        index, count = (int(x) for x in shard)
    except (TypeError, ValueError):
        raise InputError(f"shard: {shard!r} is not a pair (k, n)") from None
    if count < 1 or not 1 <= index <= count:
        raise InputError(f"shard: ({index}, {count}) needs 1 <= k <= n")
    return index, count


def _run_builtin(name, worlds, world_dir, trials, jobs, seed, protocol, out, sim_config, config, resume, shard_index,
                 shard_count, trajectories, progress):
    """A built-in controller's run in this process: the record as barn run makes it, its episodes
    in bench's C++ batch (record.run_controller), the same record bytes."""
    if resume:
        record = _core.Record.open(str(out))
        if record.controller != name:
            raise InputError(f"{out}: a record of {record.controller}, not of {name}")
    else:
        config_text = _core.builtin_controller(name, str(config or ""), sim_config, protocol)
        record = _core.Record.create(str(out), name, config_text, str(worlds), str(world_dir), sim_config, protocol,
                                     trials, seed, shard_index, shard_count, bool(trajectories))
    ran = not record.complete
    if ran:
        _run_record(record, out, jobs, progress, lambda: record.run_controller(jobs))
    with open(os.path.join(out, "summary.json")) as f:  # a shard's covers its episodes only
        summary = json.load(f)
    if ran and summary["summary"]["error_rate"] > 0:  # barn run exits 1 for this
        print(f"barnbench.run: {name}: some episodes ended in error (see {out}/episodes.csv)", file=sys.stderr)
    return summary


def _run_record(record, out, jobs, progress, run_pending):
    """Runs a record's pending episodes (`run_pending()` appends them) and completes it; an
    interruption leaves it to resume."""
    record.begin(jobs, progress)
    started = time.monotonic()
    complete = False
    try:
        run_pending()
    finally:  # an interruption leaves a record to resume
        complete = record.finish(time.monotonic() - started)
    if not complete:
        raise InputError(f"{out}: not complete; finish it with run(..., out={str(out)!r}, resume=True)")


# ---------------------------------------------------------------------------------------------
# Python controllers: worker processes, each running one episode at a time


class _Spec:
    """What every episode of a Python run needs besides (world, trial, seed)."""

    def __init__(self, controller_class, params, world_dir, episode_config, global_plan_text, trajectories):
        self.controller_class = controller_class
        self.params = params
        self.world_dir = world_dir
        self.episode_config = episode_config
        self.global_plan_text = global_plan_text
        self.trajectories = trajectories
        self.period = float(getattr(controller_class, "period", 0.05))

    def failed_row(self, world, trial, seed, reason):
        """The row of an episode its worker could not finish (crashed or hung)."""
        episode = _core.Episode.from_record_config(world, self.world_dir, self.episode_config, seed, self.period,
                                                   self.global_plan_text, self.trajectories)
        episode.fail(reason)
        return episode.csv_row(trial), (episode.trajectory_csv() if self.trajectories else None)


def _run_episode(controller, spec, world, trial, seed):
    """One episode in bench's loop (bench::runEpisode, as barn run runs it), calling the
    controller back for reset and every act; what it raises ends the episode as an error."""
    return _core.run_episode(controller, world, spec.world_dir, spec.episode_config, seed, trial,
                             spec.global_plan_text, spec.trajectories)


def _describe(error):
    text = str(error)
    return f"{type(error).__name__}: {text}" if isinstance(error, (SystemExit, KeyboardInterrupt)) or not text else text


def _worker_main(conn, spec):
    """A worker process: runs the episodes it is sent, one at a time, with one controller."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    controller = None
    while True:
        try:
            task = conn.recv()
        except EOFError:
            return
        if task is None:
            return
        world, trial, seed = task
        if controller is None:
            try:
                controller = spec.controller_class(**spec.params)
            except BaseException as e:
                conn.send(spec.failed_row(world, trial, seed, f"controller construction threw: {_describe(e)}"))
                continue
        conn.send(_run_episode(controller, spec, world, trial, seed))


class _Worker:
    def __init__(self, context, spec):
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_worker_main, args=(child, spec), daemon=True)
        self.process.start()
        child.close()
        self.task = None
        self.started = 0.0

    def give(self, task):
        self.task = task
        self.started = time.monotonic()
        self.conn.send(task)

    def stop(self, kill=False):
        if kill:
            self.process.kill()
        else:
            try:
                self.conn.send(None)
            except OSError:
                pass
        self.process.join(timeout=5)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()


def _ending(process):
    code = process.exitcode
    if code is None:
        return "did not end"
    if code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with status {code}"


def _run_workers(spec, tasks, jobs, record, timeout):
    """Runs `tasks` ((world, trial, seed)) on `jobs` watched worker processes and appends each
    finished episode's row to `record`. A worker that dies or overruns `timeout` fails its
    episode and is replaced."""
    context = multiprocessing.get_context("fork")
    pending = list(reversed(tasks))
    workers = [_Worker(context, spec) for _ in range(min(jobs, len(tasks)))]
    try:
        for worker in workers:
            if pending:
                worker.give(pending.pop())
        while any(w.task is not None for w in workers):
            busy = [w for w in workers if w.task is not None]
            now = time.monotonic()
            wait = max(0.0, min(w.started + timeout - now for w in busy))
            ready = multiprocessing.connection.wait([w.conn for w in busy] + [w.process.sentinel for w in busy],
                                                    timeout=wait)
            for i, worker in enumerate(workers):
                if worker.task is None:
                    continue
                world, trial, seed = worker.task
                result = None
                failure = None
                if worker.conn in ready:
                    try:
                        result = worker.conn.recv()
                    except (EOFError, OSError):
                        worker.process.join(timeout=5)
                        failure = f"the controller's worker process {_ending(worker.process)}"
                elif worker.process.sentinel in ready:
                    worker.process.join(timeout=5)
                    failure = f"the controller's worker process {_ending(worker.process)}"
                elif time.monotonic() - worker.started >= timeout:
                    failure = f"the episode took more than {timeout:g} s of wall time (episode_timeout)"
                else:
                    continue
                if failure is not None:
                    worker.stop(kill=True)
                    result = spec.failed_row(world, trial, seed, failure)
                    worker = workers[i] = _Worker(context, spec)
                worker.task = None
                record.append(*result)
                if pending:
                    worker.give(pending.pop())
    finally:
        for worker in workers:
            worker.stop(kill=worker.task is not None)


def _python_config(controller_class, params, global_plan_text):
    """The controller config a record of a Python class holds: the class, its keyword
    arguments, its source file and that file's digest, and the global_plan block."""
    name = f"{controller_class.__module__}.{controller_class.__qualname__}"
    try:
        source = inspect.getsourcefile(controller_class) or ""
    except TypeError:
        source = ""
    digest = ""
    if source and os.path.isfile(source):
        with open(source, "rb") as f:
            digest = _core.digest(f.read())
        source = os.path.abspath(source)
    try:
        params_text = json.dumps(params, sort_keys=True)
    except TypeError as e:
        raise InputError(f"params: keyword arguments a record can hold (numbers, strings, lists, dicts): {e}") from None
    quoted = "'" + params_text.replace("'", "''") + "'"  # JSON text as a YAML scalar
    text = (f"type: python\npython:\n  class: {name}\n  params: {quoted}\n  source: {json.dumps(source)}\n"
            f"  source_digest: {json.dumps(digest)}\n")
    return name, text + _core.effective_global_plan(global_plan_text)


def _run_python(controller_class, params, worlds, world_dir, trials, jobs, seed, protocol, out, sim_config, resume,
                shard_index, shard_count, global_plan, trajectories, timeout, progress):
    name = f"{controller_class.__module__}.{controller_class.__qualname__}"
    if resume:
        record = _core.Record.open(str(out))
        if record.controller != name:
            raise InputError(f"{out}: a record of {record.controller}, not of {name}")
        recorded = _core.recorded_python_config(record.controller_config)
        params, plan_text = json.loads(recorded["params"] or "{}"), recorded["global_plan"]
        trajectories = record.trajectories  # the record says whether it keeps them
    else:
        plan_text = _global_plan_text(global_plan)
        name, config_text = _python_config(controller_class, params, plan_text)
        record = _core.Record.create(str(out), name, config_text, str(worlds), str(world_dir), sim_config, protocol,
                                     trials, seed, shard_index, shard_count, bool(trajectories))
    if not record.complete:
        spec = _Spec(controller_class, params, record.worlds_folder, record.episode_config, plan_text, trajectories)
        tasks = record.pending()
        _run_record(record, out, jobs, progress, lambda: _run_workers(spec, tasks, jobs, record, timeout))
    with open(os.path.join(out, "summary.json")) as f:  # a shard's covers its episodes only
        return json.load(f)
