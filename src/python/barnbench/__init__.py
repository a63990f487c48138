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
heading): "scan" (720 float32, inf for no return), "pose" (x, y, yaw), "scan_pose" (the pose
when the scan was taken, up to one LiDAR period earlier: place the scan's returns with it),
"twist" (v, w), "goal" (x, y), and "time" (simulated seconds). One step is one control period (Env.dt).
"""

import json
import math
import multiprocessing
import os
import subprocess
import time

import numpy as np

from . import _core
from ._core import InputError, IoError

__all__ = ["Env", "run", "merge", "default_reward", "InputError", "IoError"]

_SOURCE_DIR = _core.SOURCE_DIR
_DEFAULT_SIM_CONFIG = os.path.join(_SOURCE_DIR, "configs", "sim", "barn.yaml")
_DEFAULT_WORLD_DIR = os.path.join(_SOURCE_DIR, "worlds")

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


class Env:
    """One BARN world as an environment. `world` is an id (in `world_dir`, default the
    repository's worlds/) or a world file; `sim_config` a sim config file (default
    configs/sim/barn.yaml); `dt` the control period [s]; `reward` a function
    (previous_distance, distance, outcome) -> float, default default_reward."""

    def __init__(self, world, world_dir=None, protocol="barn2023", sim_config=None, dt=0.05, reward=default_reward):
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise InputError(f"dt: must be a positive number of seconds (got {dt!r})")
        self.world = world
        self.world_dir = world_dir or _DEFAULT_WORLD_DIR
        self.protocol = protocol
        self.sim_config = sim_config or _DEFAULT_SIM_CONFIG
        self.dt = float(dt)
        self.reward = reward
        self._episode = None
        self._distance = None
        if _gym is not None:
            inf = np.inf
            self.observation_space = _gym.spaces.Dict({
                "scan": _gym.spaces.Box(0.0, inf, shape=(720,), dtype=np.float32),
                "pose": _gym.spaces.Box(-inf, inf, shape=(3,), dtype=np.float64),
                "scan_pose": _gym.spaces.Box(-inf, inf, shape=(3,), dtype=np.float64),
                "twist": _gym.spaces.Box(-inf, inf, shape=(2,), dtype=np.float64),
                "goal": _gym.spaces.Box(-inf, inf, shape=(2,), dtype=np.float64),
                "time": _gym.spaces.Box(0.0, inf, shape=(), dtype=np.float64),
            })
            self.action_space = _gym.spaces.Box(np.array([-2.0, -4.0]), np.array([2.0, 4.0]), dtype=np.float64)

    def reset(self, seed=None, options=None):
        """Starts a new episode; the same seed gives the same episode bit for bit."""
        del options
        self._episode = _core.Episode(self.world, self.world_dir, self.sim_config, self.protocol,
                                      int(seed or 0), self.dt)
        obs = self._episode.observation()
        self._distance = _goal_distance(obs)
        info = self._episode.info()
        info.update(self._episode.result())
        return obs, info

    def step(self, action):
        """Applies (v, w) for one control period. Returns obs, reward, terminated,
        truncated, info; info["outcome"] is running, success, collision or timeout."""
        if self._episode is None:
            raise RuntimeError("call reset() before step()")
        v, w = (float(a) for a in action)
        self._episode.step(v, w)
        obs = self._episode.observation()
        info = self._episode.result()
        distance = _goal_distance(obs)
        reward = self.reward(self._distance, distance, info["outcome"])
        self._distance = distance
        terminated = info["outcome"] in ("success", "collision", "error")
        truncated = info["outcome"] == "timeout"
        return obs, reward, terminated, truncated, info


def _goal_distance(obs):
    return float(np.hypot(*(obs["goal"] - obs["pose"][:2])))


def _barn_binary():
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.join(here, os.pardir, os.pardir, "barn")


def run(controller, worlds="test50", world_dir=None, trials=1, jobs=2, seed=0, protocol="barn2023", out=None,
        sim_config=None, config=None, resume=False, shard=None):
    """Scores `controller` on `worlds` x `trials` and writes the experiment record to `out`.

    `controller` is a built-in name ("dwa", "inventec_fi", ...: run by `barn run`, the same
    record) or a Python class with reset(info) and act(obs) -> (v, w) or (v, w, state label)
    and an optional `period` [s] (default 0.05); one instance per worker process, reset every
    episode. `info` holds what the external protocol's reset message holds
    (docs/external_controller.md); `obs` is Env's observation with the scan as float64, the
    exact doubles C++ and external controllers see.
    `config` is a controller config file for a built-in run (barn run --config; e.g. an
    `external` controller). Either way `out` holds barn run's record (manifest.yaml,
    episodes.csv, summary.json; `barn compare` and `barn plot scores` read it) and its summary
    is returned.
    The record is journaled as episodes finish, as barn run does: after an interruption
    (Ctrl-C, a killed job) `run(controller, out=DIR, resume=True)` runs only what is left (the
    experiment's settings come from the record). `shard=(k, n)` runs every n-th episode from
    the k-th (barn run --shard k/n); merge() puts the shards together."""
    if out is None:
        raise InputError("out: a folder for the record is required")
    shard_index, shard_count = _shard(shard)
    if isinstance(controller, str):
        if resume:
            command = [_barn_binary(), "run", "--resume", str(out), "--jobs", str(jobs)]
        else:
            command = [_barn_binary(), "run", "--controller", controller, "--worlds", str(worlds), "--trials",
                       str(trials), "--jobs", str(jobs), "--seed", str(seed), "--protocol", protocol, "--out", str(out)]
            if world_dir:
                command += ["--world-dir", str(world_dir)]
            if sim_config:
                command += ["--sim-config", str(sim_config)]
            if config:
                command += ["--config", str(config)]
            if shard_count:
                command += ["--shard", f"{shard_index}/{shard_count}"]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise InputError(done.stderr.strip() or done.stdout.strip())
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)
    return _run_python(controller, worlds, world_dir or _DEFAULT_WORLD_DIR, trials, jobs, seed, protocol, out,
                       sim_config or _DEFAULT_SIM_CONFIG, resume, shard_index, shard_count)


def merge(shards, out):
    """Merges the shard records of one run (run(..., shard=(k, n)) or barn run --shard) into
    `out`, the record a single run writes, as `barn merge` does; returns its summary."""
    _core.merge([str(s) for s in shards], str(out))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


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


def _run_one(task):
    controller_class, world, world_dir, episode_config, seed, trial = task
    global _worker_controller
    if _worker_controller is None or type(_worker_controller) is not controller_class:
        _worker_controller = controller_class()
    controller = _worker_controller
    episode = _core.Episode.from_record_config(world, world_dir, episode_config, seed,
                                               float(getattr(controller, "period", 0.05)))
    try:
        controller.reset(episode.info())
    except Exception as e:  # a failing controller ends its own episode only
        episode.fail(f"controller reset threw: {e}")
    while not episode.done:
        try:
            answer = controller.act(episode.observation(full_precision=True))
            v, w, state = float(answer[0]), float(answer[1]), str(answer[2]) if len(answer) > 2 else ""
        except Exception as e:
            episode.fail(f"controller threw: {e}")
            break
        episode.step(v, w, state)
    return episode.csv_row(trial)


_worker_controller = None


def _run_python(controller_class, worlds, world_dir, trials, jobs, seed, protocol, out, sim_config, resume,
                shard_index, shard_count):
    if not isinstance(controller_class, type):
        raise InputError("controller: a built-in name or a class with reset(info) and act(obs)")
    name = f"{controller_class.__module__}.{controller_class.__qualname__}"
    if resume:
        record = _core.Record.open(str(out))
        if record.controller != name:
            raise InputError(f"{out}: a record of {record.controller}, not of {name}")
    else:
        record = _core.Record.create(str(out), name, f"type: python\npython:\n  class: {name}\n", str(worlds),
                                     str(world_dir), sim_config, protocol, trials, seed, shard_index, shard_count)
    if not record.complete:
        tasks = [(controller_class, w, record.worlds_folder, record.episode_config, s, t)
                 for w, t, s in record.pending()]
        record.begin(jobs)
        started = time.monotonic()
        complete = False
        try:
            if jobs == 1:
                for task in tasks:
                    record.append(_run_one(task))
            else:
                # Processes, so Python controllers run in parallel; each episode is deterministic
                # given (world, seed), so the record does not depend on the number of jobs.
                with multiprocessing.get_context("fork").Pool(jobs) as pool:
                    for row in pool.imap_unordered(_run_one, tasks):
                        record.append(row)
        finally:  # an interruption leaves a record to resume
            complete = record.finish(time.monotonic() - started)
        if not complete:
            raise InputError(f"{out}: not complete; finish it with run(..., out={str(out)!r}, resume=True)")
    with open(os.path.join(out, "summary.json")) as f:  # a shard's covers its episodes only
        return json.load(f)
