"""A local planner given move_base's plan (the global_plan block) through every route, the
Python records' bookkeeping (constructor parameters, source digest, progress, trajectories),
and the Python route's promise that a crashing or hanging controller fails one episode only."""

import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import barnbench

ROOT = barnbench._SOURCE_DIR
# The build tree's barn, beside build/python (the tests run in the build tree).
sys.path.insert(0, os.path.join(ROOT, "examples", "python"))
from carrot_planner import CarrotPlanner  # noqa: E402  (the path above first)


def test_the_carrot_planner_in_python_as_an_external_program_and_in_cpp_gives_one_record(tmp_path, barn):
    # The example local planner three ways, each handed the plan by barnbench's stack: a Python
    # class (global_plan={}), an external program (its YAML's global_plan: {}) and the C++ port
    # (GlobalPlanFedController). Byte-identical records.
    worlds = "0:300:100"
    barnbench.run(CarrotPlanner, worlds=worlds, jobs=2, seed=1, out=str(tmp_path / "class"), global_plan={})
    barnbench.run("carrot", worlds=worlds, jobs=2, seed=1, out=str(tmp_path / "external"),
                  config=os.path.join(ROOT, "examples", "external", "carrot_planner.yaml"))
    cpp = os.path.join(os.path.dirname(barn), "examples", "carrot_planner")
    subprocess.run([cpp, worlds, str(tmp_path / "cpp"), "1"], check=True, capture_output=True)
    from_class = (tmp_path / "class" / "episodes.csv").read_text()
    assert from_class == (tmp_path / "external" / "episodes.csv").read_text()
    assert from_class == (tmp_path / "cpp" / "episodes.csv").read_text()
    assert "success" in from_class


def test_env_observes_the_plan_from_the_robot_to_the_goal_and_the_requested_costmaps():
    env = barnbench.Env(world=0, global_plan={"send_local_costmap": True})
    obs, _ = env.reset(seed=2)
    plan = obs["global_plan"]
    assert plan.ndim == 2 and plan.shape[1] == 3 and len(plan) > 100  # 10 m at half a cell
    assert np.hypot(*(plan[0, :2] - obs["pose"][:2])) < 0.1
    assert np.allclose(plan[-1, :2], obs["goal"])
    assert obs["global_plan_stamp"] == 0.0
    local = obs["local_costmap"]
    assert local["costs"].dtype == np.uint8 and local["costs"].shape == (200, 200)  # 10 m at 0.05 m
    assert local["resolution"] == 0.05 and local["costs"].max() >= 253  # obstacles seen already
    assert "global_costmap" not in obs
    # 20 Hz planning: a new plan each 0.05 s step; the costmap object is reused while unchanged.
    obs2, *_ = env.step((0.0, 0.0))
    assert obs2["global_plan_stamp"] == pytest.approx(0.05)
    same, *_ = env.step((0.0, 0.0))
    if same["local_costmap"]["version"] == obs2["local_costmap"]["version"]:
        assert same["local_costmap"] is obs2["local_costmap"]


def test_env_without_the_block_has_no_plan_and_params_need_it():
    env = barnbench.Env(world=0)
    obs, _ = env.reset(seed=1)
    assert "global_plan" not in obs
    _, _, terminated, _, info = env.step((0.0, 0.0), params={"planner.rate": 5})
    assert terminated and info["outcome"] == "error" and "global_plan block" in info["error"]


def test_a_parameter_set_while_running_with_a_bad_key_ends_the_episode_naming_it():
    env = barnbench.Env(world=0, global_plan={})
    env.reset(seed=1)
    _, _, terminated, _, info = env.step((0.0, 0.0), params={"global_costmap.inflation_radius": 0.5})
    assert not terminated
    _, _, terminated, _, info = env.step((0.0, 0.0), params={"global_costmap.inflation_radiu": 0.5})
    assert terminated and info["outcome"] == "error"
    assert "global_costmap.inflation_radiu: not a settable parameter" in info["error"]
    with pytest.raises(RuntimeError, match="ended"):
        env.step((0.0, 0.0))  # no repeated terminal reward after the end


def _ended_by(params):
    """The error of an Env episode (with a global_plan block) given `params` at its first step."""
    env = barnbench.Env(world=0, global_plan={})
    env.reset(seed=1)
    _, _, terminated, _, info = env.step((0.0, 0.0), params=params)
    assert terminated and info["outcome"] == "error", params
    return info["error"]


def test_env_params_out_of_the_protocols_bounds_end_the_episode_naming_the_key_or_count():
    # The external protocol's bounds: at most 64 parameters, str keys of at most 128 bytes,
    # finite numbers. 65 keys are refused by their count before any key is looked at.
    many = {f"k{i}": 0.5 for i in range(65)}
    assert "more than 64 parameters in one command (65)" in _ended_by(many)
    assert "the key 5 is not a string (int)" in _ended_by({5: 0.5})
    assert "the key ('planner', 'rate') is not a string (tuple)" in _ended_by({("planner", "rate"): 0.5})
    assert "is longer than 128 bytes" in _ended_by({"k" * 129: 0.5})
    assert "is not valid text" in _ended_by({"planner.rate\ud800": 1.0})
    assert "global_costmap.inflation_radius: must be a finite number (got nan)" in _ended_by(
        {"global_costmap.inflation_radius": float("nan")})
    assert "planner.rate: must be a finite number (got inf)" in _ended_by({"planner.rate": math.inf})
    assert "planner.rate: must be a finite number (got '2')" in _ended_by({"planner.rate": "2"})
    assert "planner.rate: must be a finite number (got True)" in _ended_by({"planner.rate": True})
    assert "planner.rate: must be a finite number (got 1000000" in _ended_by({"planner.rate": 10**400})
    assert "a dict {key: number} (got list)" in _ended_by([("planner.rate", 2.0)])
    # Inside the bounds: numpy numbers are numbers, an empty dict sets nothing.
    env = barnbench.Env(world=0, global_plan={})
    env.reset(seed=1)
    _, _, terminated, _, info = env.step((0.0, 0.0), params={"planner.rate": np.float32(2.0)})
    assert not terminated and info["outcome"] == "running"
    _, _, terminated, _, _ = env.step((0.0, 0.0), params={})
    assert not terminated


class SendsParams(CarrotPlanner):
    """CarrotPlanner whose first command carries `params` (a class attribute the test sets)."""

    params = None

    def act(self, obs):
        v, w = super().act(obs)
        return {"v": v, "w": w, "params": type(self).params}


@pytest.mark.parametrize("params,reason", [
    ({f"planner.rate{i}": 1.0 for i in range(65)}, "more than 64 parameters in one command (65)"),
    ({7: 1.0}, "the key 7 is not a string (int)"),
    ({"planner.rate": float("nan")}, "planner.rate: must be a finite number (got nan)"),
    ({"planner.rat": 1.0}, "planner.rat: not a settable parameter"),
    ("planner.rate=1", "a dict {key: number} (got str)"),
])
def test_a_python_controllers_params_out_of_bounds_fail_its_episode_naming_the_key_or_count(
        tmp_path, monkeypatch, params, reason):
    monkeypatch.setattr(SendsParams, "params", params)
    summary = barnbench.run(SendsParams, worlds="0,100", jobs=1, out=str(tmp_path / "r"), global_plan={})
    rows = barnbench.read_episodes(tmp_path / "r")
    assert len(rows) == 2 and summary["summary"]["episodes"] == 2
    for row in rows:
        assert row["outcome"] == "error" and reason in row["error"], row


def test_bad_global_plan_blocks_name_the_key():
    with pytest.raises(barnbench.InputError, match="global_plan: send_costmap"):
        barnbench.Env(world=0, global_plan={"send_costmap": True}).reset()
    with pytest.raises(barnbench.InputError, match="global_plan"):
        barnbench.Env(world=0, global_plan=["navfn"])


class Tunable(CarrotPlanner):
    """CarrotPlanner that widens the global inflation at its first tick."""

    def __init__(self, lookahead=1.0, inflation=0.6):
        super().__init__(lookahead=lookahead)
        self.inflation = inflation

    def reset(self, info):
        super().reset(info)
        self.ticks = 0

    def act(self, obs):
        v, w = super().act(obs)
        self.ticks += 1
        if self.ticks == 1:
            return {"v": v, "w": w, "state": "tuned", "params": {"global_costmap.inflation_radius": self.inflation}}
        return {"v": v, "w": w, "state": "carrot"}


def test_a_record_keeps_the_classs_parameters_source_digest_and_trajectories(tmp_path, barn, capfd):
    out = tmp_path / "r"
    barnbench.run(Tunable, worlds="0:300:150", jobs=2, out=str(out), params={"lookahead": 1.5, "inflation": 0.55},
                  global_plan={}, trajectories=True)
    manifest = (out / "manifest.yaml").read_text()
    assert "class: test_local_planner.Tunable" in manifest
    recorded = barnbench._core.recorded_python_config(barnbench._core.Record.open(str(out)).controller_config)
    assert recorded["params"] == '{"inflation": 0.55, "lookahead": 1.5}'
    assert "source_digest: " in manifest and "global_plan:" in manifest
    # Progress lines as barn run prints them, on stderr.
    assert "progress 2/2 episodes" in capfd.readouterr().err
    # The parameter change is in the trajectory file, at the first tick.
    trajectory = (out / "trajectories" / "world_0_trial_0.csv").read_text().splitlines()
    assert trajectory[0].endswith(",state,params")
    assert trajectory[1].endswith(",tuned,global_costmap.inflation_radius=0.55")
    assert trajectory[2].endswith(",carrot,")
    # The tools read the record: its trajectories are drawn without re-running the class.
    plot = subprocess.run([barn, "plot", "trajectory", str(out), "--world", "0", "-o", str(tmp_path / "t.png")],
                          capture_output=True, text=True)
    assert plot.returncode == 0, plot.stderr
    report = subprocess.run([barn, "report", str(out), "-o", str(tmp_path / "r.html")], capture_output=True, text=True)
    assert report.returncode == 0, report.stderr
    # Resume takes the class's parameters and the block from the record.
    assert barnbench.run(Tunable, out=str(out), resume=True)["summary"]


def test_the_protocol_is_set_once_for_a_session(monkeypatch):
    monkeypatch.setattr(barnbench, "default_protocol", "barn2024")
    assert barnbench.Env(world=0).protocol == "barn2024"
    assert barnbench.Env(world=0, protocol="barn2023").protocol == "barn2023"
    monkeypatch.setattr(barnbench, "default_protocol", "barn1999")
    with pytest.raises(barnbench.InputError, match="barn1999"):
        barnbench.Env(world=0)


class Misbehaves:
    """Fails in its own way on world 100, drives straight elsewhere."""

    how = None

    def reset(self, info):
        self.world = info["world"]

    def act(self, obs):
        if self.world == 100 and obs["time"] > 0.5:
            if Misbehaves.how == "exit":
                os._exit(1)
            if Misbehaves.how == "segfault":
                os.kill(os.getpid(), signal.SIGSEGV)
            if Misbehaves.how == "sys_exit":
                sys.exit(3)
            if Misbehaves.how == "interrupt":
                raise KeyboardInterrupt
            if Misbehaves.how == "hang":
                time.sleep(3600)
        return 0.5, 0.0


@pytest.mark.parametrize("jobs", [1, 2])
@pytest.mark.parametrize("how,reason", [("exit", "worker process exited with status 1"),
                                        ("segfault", "killed by SIGSEGV"),
                                        ("sys_exit", "SystemExit: 3"),
                                        ("interrupt", "KeyboardInterrupt"),
                                        ("hang", "more than 2 s of wall time")])
def test_a_crashing_or_hanging_controller_fails_only_its_episode(tmp_path, monkeypatch, how, reason, jobs):
    monkeypatch.setattr(Misbehaves, "how", how)
    summary = barnbench.run(Misbehaves, worlds="0,100,200", jobs=jobs, out=str(tmp_path / "r"), episode_timeout=2)
    rows = barnbench.read_episodes(tmp_path / "r")
    assert [row["outcome"] == "error" for row in rows] == [False, True, False]
    assert reason in rows[1]["error"]
    assert summary["summary"]["episodes"] == 3
