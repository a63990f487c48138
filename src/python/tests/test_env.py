"""barnbench's Python front end: Env round trips, determinism, and records that match barn run."""

import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import barnbench

# The build tree's barn, beside build/python (the tests run in the build tree).


def drive(env, seed, command=(0.5, 0.0), limit=10000):
    """Steps `env` with a fixed command to the end; returns the observations and the last info."""
    obs, info = env.reset(seed=seed)
    seen = [obs]
    for _ in range(limit):
        obs, reward, terminated, truncated, info = env.step(command)
        seen.append(obs)
        if terminated or truncated:
            return seen, info
    raise AssertionError("episode did not end")


def test_reset_and_step_round_trip():
    env = barnbench.Env(world=0)
    obs, info = env.reset(seed=3)
    assert obs["scan"].shape == (720,) and obs["scan"].dtype == np.float32
    assert obs["pose"].shape == (3,) and obs["twist"].shape == (2,) and obs["goal"].shape == (2,)
    assert obs["time"] == 0.0 and info["outcome"] == "running"
    # The odom frame: the start at the origin facing +y, the goal 10 m ahead.
    assert np.allclose(obs["pose"][:2], 0.0) and obs["pose"][2] == pytest.approx(1.57) and obs["goal"][1] > 9.0
    obs, reward, terminated, truncated, info = env.step((0.5, 0.0))
    assert obs["time"] == pytest.approx(env.dt)
    assert reward > 0.0  # moved toward the goal
    assert not terminated and not truncated and info["outcome"] == "running"


def test_an_episode_ends_with_a_protocol_outcome_and_score():
    env = barnbench.Env(world=0)
    _, info = drive(env, seed=1, command=(0.5, 0.0))
    assert info["outcome"] in ("success", "collision", "timeout")
    assert (info["score"] > 0) == (info["outcome"] == "success")


def test_same_seed_same_episode_bit_for_bit_and_another_seed_differs():
    env = barnbench.Env(world=5)
    a, _ = drive(env, seed=11, command=(0.3, 0.1))
    b, _ = drive(env, seed=11, command=(0.3, 0.1))
    c, _ = drive(env, seed=12, command=(0.3, 0.1))
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert np.array_equal(x["scan"], y["scan"]) and np.array_equal(x["pose"], y["pose"])
    assert not np.array_equal(a[1]["scan"], c[1]["scan"])  # the LiDAR noise follows the seed


def test_bad_input_is_a_clear_error():
    with pytest.raises(barnbench.InputError, match="99999"):
        barnbench.Env(world=99999).reset()
    with pytest.raises(barnbench.InputError, match="dt"):
        barnbench.Env(world=0, dt=0.0)
    with pytest.raises(barnbench.InputError, match="protocol"):
        barnbench.Env(world=0, protocol="barn1999").reset()
    with pytest.raises(RuntimeError):
        barnbench.Env(world=0).step((0.0, 0.0))


class StraightTwin:
    """The built-in `straight` controller (configs/controllers/straight.yaml) in Python."""

    period = 1.0 / 20.0

    def reset(self, info):
        self.max_angular = info["robot"]["max_angular_speed"]

    def act(self, obs):
        x, y, yaw = (float(v) for v in obs["pose"])
        gx, gy = (float(v) for v in obs["goal"])
        error = math.atan2(gy - y, gx - x) - yaw
        error = math.fmod(error + math.pi, 2.0 * math.pi)
        if error < 0:
            error += 2.0 * math.pi
        error -= math.pi
        angular = min(max(2.0 * error, -self.max_angular), self.max_angular)
        return 1.0 * max(0.0, math.cos(error)), angular


def test_a_python_controller_and_its_cpp_twin_give_identical_records(tmp_path):
    worlds = "0:300:60"
    barnbench.run("straight", worlds=worlds, trials=2, jobs=2, seed=4, out=str(tmp_path / "cpp"))
    barnbench.run(StraightTwin, worlds=worlds, trials=2, jobs=2, seed=4, out=str(tmp_path / "py"))
    cpp = (tmp_path / "cpp" / "episodes.csv").read_text()
    py = (tmp_path / "py" / "episodes.csv").read_text()
    assert cpp == py
    assert cpp.count("\n") == 1 + 5 * 2
    # The whole record, as barn run writes it: the summary too, and a manifest naming the class.
    assert (tmp_path / "cpp" / "summary.json").read_text() == (tmp_path / "py" / "summary.json").read_text()
    assert "class: test_env.StraightTwin" in (tmp_path / "py" / "manifest.yaml").read_text()


def test_a_python_controllers_record_does_not_depend_on_jobs(tmp_path):
    one = barnbench.run(StraightTwin, worlds="0:300:100", jobs=1, seed=2, out=str(tmp_path / "one"))
    two = barnbench.run(StraightTwin, worlds="0:300:100", jobs=2, seed=2, out=str(tmp_path / "two"))
    assert one == two
    assert (tmp_path / "one" / "episodes.csv").read_bytes() == (tmp_path / "two" / "episodes.csv").read_bytes()


class Crashes:
    def reset(self, info):
        self.world = info["world"]

    def act(self, obs):
        if self.world == 100:
            raise ValueError("no map")
        return 0.0, 0.0


def test_a_failing_python_controller_fails_only_its_own_episodes(tmp_path):
    summary = barnbench.run(Crashes, worlds="0,100", jobs=2, out=str(tmp_path / "r"))
    rows = barnbench.read_episodes(tmp_path / "r")
    assert summary["summary"]["episodes"] == 2 and summary["summary"]["error_rate"] == 0.5
    assert rows[0]["outcome"] == "timeout"
    header = (tmp_path / "r" / "episodes.csv").read_text().splitlines()[0]
    assert header == ",".join(barnbench.EPISODE_COLUMNS) and barnbench.EPISODE_COLUMNS[3] == "outcome"
    assert rows[1]["outcome"] == "error" and "controller threw: no map" in rows[1]["error"]


class AnswersBadly:
    """Answers each world's first tick with something that is not a command."""

    answers = {0: None, 100: ("fast", 0.0), 200: {"v": 1.0}, 250: {"v": 1.0, "w": 0.0, "speed": 2, "mode": 1}}

    def reset(self, info):
        self.answer = AnswersBadly.answers[info["world"]]

    def act(self, obs):
        return self.answer


def test_a_python_controllers_bad_answers_end_its_episodes_with_pythons_own_messages(tmp_path):
    # The C++ loop reads an answer as Python's float(), [] and len() read it, so each error row
    # says what Python says: None[0], float("fast"), {"v": 1.0}["w"] (a KeyError's text is the
    # key's repr), and the unknown keys sorted.
    barnbench.run(AnswersBadly, worlds="0,100,200,250", jobs=1, out=str(tmp_path / "r"))
    errors = [row["error"] for row in barnbench.read_episodes(tmp_path / "r")]
    assert errors == ["controller threw: 'NoneType' object is not subscriptable",
                      "controller threw: could not convert string to float: 'fast'",
                      "controller threw: 'w'",
                      "controller threw: unknown keys in the command: mode, speed"]


def test_wrong_arguments_are_input_errors_naming_the_argument_before_any_record_is_made(tmp_path):
    # The arguments the 2026-11-27 audit found raising pybind11's or multiprocessing's own errors,
    # or blaming configs/sim/barn.yaml for a bad protocol argument.
    with pytest.raises(barnbench.InputError, match="world: 100000000000000000000 is not a world id"):
        barnbench.Env(world=10**20)
    with pytest.raises(barnbench.InputError, match=r"world: an id or a world file \(got 3.5\)"):
        barnbench.Env(world=3.5)
    with pytest.raises(barnbench.InputError, match="^protocol: 'x' is not one of"):
        barnbench.Env(world=0, protocol="x")
    env = barnbench.Env(world=0)
    for seed in (-1, 2**64, 1.5, True):
        with pytest.raises(barnbench.InputError, match=r"seed: an integer in \[0, 2\^64 - 1\]"):
            env.reset(seed=seed)
    out = tmp_path / "r"
    for bad, match in [({"jobs": -1}, "jobs: a number of worker processes"), ({"seed": -1}, "seed: an integer"),
                       ({"seed": 2**64}, "seed: an integer"), ({"protocol": "x"}, "^protocol: 'x' is not one of"),
                       ({"trials": 0}, "trials: an integer >= 1")]:
        for controller in (StraightTwin, "straight"):
            with pytest.raises(barnbench.InputError, match=match):
                barnbench.run(controller, worlds="0", out=str(out), **bad)
            assert not out.exists(), bad  # refused before the record was begun: no resume needed
    # Flags are booleans (a string raised pybind11's TypeError from a worker, or after the record
    # was begun), and what does not apply to the controller given is refused, not ignored.
    config = os.path.join(barnbench._SOURCE_DIR, "configs", "controllers", "straight.yaml")
    for controller, bad, match in [
            (StraightTwin, {"trajectories": "yes"}, r"trajectories: True or False \(got 'yes'\)"),
            (StraightTwin, {"progress": "no"}, r"progress: True or False \(got 'no'\)"),
            ("straight", {"resume": 1}, r"resume: True or False \(got 1\)"),
            (StraightTwin, {"episode_timeout": math.inf}, "episode_timeout: a positive number of seconds"),
            (StraightTwin, {"config": config}, "config: a controller config file, for a built-in name"),
            ("straight", {"params": {"speed": 1.0}}, "params: for a Python class"),
            ("straight", {"global_plan": {}}, "global_plan: for a Python class"),
            ("straight", {"episode_timeout": 5}, "episode_timeout: for a Python class")]:
        with pytest.raises(barnbench.InputError, match=match):
            barnbench.run(controller, worlds="0", out=str(out), **bad)
        assert not out.exists(), bad
    env.reset(seed=1)
    for action in (0.5, (0.5,), ("x", 0.0)):
        with pytest.raises(barnbench.InputError, match=r"action: \(v, w\), two numbers"):
            env.step(action)
    with pytest.raises(barnbench.InputError, match="shards: a list of shard record folders"):
        barnbench.merge(str(tmp_path / "shard_1"), out=str(tmp_path / "m"))
    # jobs=0 is one worker per core, as barn run --jobs 0.
    assert barnbench.run(StraightTwin, worlds="0", jobs=0, out=str(out))["summary"]["episodes"] == 1


def test_a_builtin_run_whose_episodes_errored_returns_its_summary_and_says_so(tmp_path, capfd):
    # An external program that exits at once: every episode ends as `error`, barn run exits 1 with
    # a complete record, and run() returns its summary (not barn's stdout as an exception).
    config = tmp_path / "dies.yaml"
    config.write_text('type: external\nexternal:\n  command: [python3, -c, "import sys; sys.exit(3)"]\n')
    summary = barnbench.run("dies", worlds="0,100", jobs=1, out=str(tmp_path / "r"), config=str(config))
    assert summary["summary"]["episodes"] == 2 and summary["summary"]["error_rate"] == 1.0
    assert "barnbench.run: dies: some episodes ended in error" in capfd.readouterr().err
    rows = barnbench.read_episodes(tmp_path / "r")
    assert len(rows) == 2 and all(row["outcome"] == "error" for row in rows)


def test_a_builtin_run_in_process_writes_barn_runs_record_and_resumes_after_ctrl_c(tmp_path, barn):
    # barnbench.run("inventec_fi") runs bench's C++ batch in this process: the bytes of barn run's
    # record. A Ctrl-C (sent once the first episode is journaled) starts no new episode, raises
    # KeyboardInterrupt and leaves the record to resume, which completes it to the same bytes.
    options = dict(worlds="0:300:50", seed=5)
    subprocess.run([barn, "run", "--controller", "inventec_fi", "--worlds", options["worlds"], "--seed", "5",
                    "--jobs", "1", "--out", str(tmp_path / "cli")], check=True, stdout=subprocess.DEVNULL)
    journal = tmp_path / "cut" / "episodes.partial.csv"

    def interrupt_after_the_first_episode():
        while not journal.exists() or len(journal.read_text().splitlines()) < 2:
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt_after_the_first_episode, daemon=True).start()
    with pytest.raises(KeyboardInterrupt):
        barnbench.run("inventec_fi", jobs=1, out=str(tmp_path / "cut"), progress=False, **options)
    assert 2 <= len(journal.read_text().splitlines()) < 1 + 6  # the header, some of the 6 episodes
    assert not (tmp_path / "cut" / "episodes.csv").exists()
    with pytest.raises(barnbench.InputError, match="a record of inventec_fi, not of dwa"):
        barnbench.run("dwa", out=str(tmp_path / "cut"), resume=True)
    barnbench.run("inventec_fi", jobs=2, out=str(tmp_path / "cut"), resume=True, progress=False)
    for name in ("episodes.csv", "summary.json"):
        assert (tmp_path / "cut" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    with pytest.raises(barnbench.InputError, match=r"controller inventec_fy: unknown; did you mean inventec_fi\?"):
        barnbench.run("inventec_fy", worlds="0", out=str(tmp_path / "unknown"))


def test_the_gap_follower_in_python_as_an_external_program_and_in_cpp_gives_one_record(tmp_path, barn):
    # The same controller three ways: a Python class in barnbench.run's worker processes, the
    # same Python code as barn's `external` program (JSON lines over a pipe), and its C++ port
    # (examples/cpp). The same doubles reach all three; the records are byte-identical.
    root = barnbench._SOURCE_DIR
    sys.path.insert(0, os.path.join(root, "examples", "python"))
    from gap_follower_class import GapFollowerController

    worlds = "0:300:100"
    barnbench.run(GapFollowerController, worlds=worlds, jobs=2, seed=1, out=str(tmp_path / "class"))
    barnbench.run("gap", worlds=worlds, jobs=2, seed=1, out=str(tmp_path / "external"),
                  config=os.path.join(root, "examples", "external", "gap_follower.yaml"))
    cpp = os.path.join(os.path.dirname(barn), "examples", "gap_follower")
    subprocess.run([cpp, worlds, str(tmp_path / "cpp"), "1"], check=True, capture_output=True)
    from_class = (tmp_path / "class" / "episodes.csv").read_text()
    assert from_class == (tmp_path / "external" / "episodes.csv").read_text()
    assert from_class == (tmp_path / "cpp" / "episodes.csv").read_text()
    assert "gap:" in from_class  # the state labels came through too


class InterruptedTwin(StraightTwin):
    """StraightTwin that presses Ctrl-C (SIGINT to the process running the batch) in its
    `stop_at`-th reset, and waits for the batch to stop it."""
    stop_at = None
    resets = 0

    def reset(self, info):
        InterruptedTwin.resets += 1
        if InterruptedTwin.resets == InterruptedTwin.stop_at:
            os.kill(os.getppid(), signal.SIGINT)
            time.sleep(30)
        super().reset(info)


def test_an_interrupted_python_run_resumes_to_the_record_of_an_uninterrupted_one(tmp_path):
    options = dict(worlds="0:300:60", trials=2, seed=3)
    whole = barnbench.run(InterruptedTwin, jobs=1, out=str(tmp_path / "whole"), **options)
    InterruptedTwin.resets, InterruptedTwin.stop_at = 0, 4
    with pytest.raises(KeyboardInterrupt):
        barnbench.run(InterruptedTwin, jobs=1, out=str(tmp_path / "cut"), **options)
    journal = (tmp_path / "cut" / "episodes.partial.csv").read_text().splitlines()
    assert len(journal) == 1 + 3  # the header and the three episodes before the interruption
    assert not (tmp_path / "cut" / "episodes.csv").exists()
    InterruptedTwin.stop_at = None
    # The settings come from the record: only the seven episodes left run, in two processes.
    resumed = barnbench.run(InterruptedTwin, jobs=2, out=str(tmp_path / "cut"), resume=True)
    assert resumed == whole
    for name in ("episodes.csv", "summary.json"):
        assert (tmp_path / "cut" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes()
    with pytest.raises(barnbench.InputError, match="not of test_env.StraightTwin"):
        barnbench.run(StraightTwin, out=str(tmp_path / "cut"), resume=True)
    with pytest.raises(barnbench.InputError, match="already holds a complete run"):
        barnbench.run(InterruptedTwin, jobs=1, out=str(tmp_path / "cut"), **options)


def test_python_shards_merge_into_the_record_of_one_run(tmp_path):
    options = dict(worlds="0:300:60", trials=2, seed=6, jobs=2)
    barnbench.run(StraightTwin, out=str(tmp_path / "whole"), **options)
    shards = [str(tmp_path / f"shard_{k}") for k in (1, 2, 3)]
    for k, shard in enumerate(shards, start=1):
        barnbench.run(StraightTwin, out=shard, shard=(k, 3), **options)
    merged = barnbench.merge(shards, out=str(tmp_path / "merged"))
    assert merged["summary"]["episodes"] == 10
    for name in ("episodes.csv", "summary.json"):
        assert (tmp_path / "merged" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes()
    with pytest.raises(barnbench.InputError, match="missing"):
        barnbench.merge(shards[:2], out=str(tmp_path / "partial"))
    with pytest.raises(barnbench.InputError, match="shard"):
        barnbench.run(StraightTwin, out=str(tmp_path / "bad"), shard=(4, 3), **options)
