"""barnbench.VecEnv: N episodes stepped together in C++ threads (docs/rl.md)."""

import numpy as np
import pytest

import barnbench
from barnbench import _core


def weave(step, n):
    """A fixed policy: forward with a weave that differs per sub-environment."""
    i = np.arange(n)
    return np.stack([np.full(n, 0.8), 0.6 * np.sin(0.3 * step + i)], axis=1)


def test_one_sub_environment_gives_the_same_episode_as_env():
    # Sub-environment 0's first episode after reset(seed=5) is Env's episode of the seed
    # VecEnv.episode_seed(5, 0, 0) on the same world, step for step: observations, rewards,
    # flags, and at the end the final observation and outcome.
    plan = {"send_local_costmap": True}
    vec = barnbench.VecEnv(1, worlds=[17], dt=0.1, global_plan=plan)
    env = barnbench.Env(world=17, dt=0.1, global_plan=plan)
    obs_v, infos = vec.reset(seed=5)
    obs_e, info_e = env.reset(seed=barnbench.VecEnv.episode_seed(5, 0, 0))
    assert infos["seed"][0] == barnbench.VecEnv.episode_seed(5, 0, 0) and infos["world"][0] == 17

    def same(v, e, row=0):
        for key in ("scan", "pose", "scan_pose", "twist", "goal"):
            assert np.array_equal(v[key][row], e[key]), key
        assert v["time"][row] == e["time"]
        if "global_plan" in e:  # Env's observation at the end has none; VecEnv keeps the last plan
            assert np.array_equal(v["global_plan_end"][row], e["global_plan"][-1][:2])
            assert v["global_plan_stamp"][row] == e["global_plan_stamp"]
        if "local_costmap" in e:
            assert np.array_equal(v["local_costmap"][row], e["local_costmap"]["costs"])
            assert np.array_equal(v["local_costmap_origin"][row], e["local_costmap"]["origin"])

    same(obs_v, obs_e)
    for step in range(2000):
        action = weave(step, 1)
        obs_v, reward_v, term_v, trunc_v, infos = vec.step(action)
        obs_e, reward_e, term_e, trunc_e, info_e = env.step(action[0])
        assert reward_v[0] == pytest.approx(reward_e, abs=1e-12)
        assert (term_v[0], trunc_v[0]) == (term_e, trunc_e)
        if term_e or trunc_e:
            assert infos["_final_observation"][0]
            same(infos["final_observation"], obs_e)
            assert infos["final_info"]["outcome"][0] == info_e["outcome"]
            assert infos["final_info"]["score"][0] == info_e["score"]
            assert infos["final_info"]["length"][0] == step + 1
            break
        same(obs_v, obs_e)
    else:
        raise AssertionError("the episode did not end")


def run(threads, steps=60):
    vec = barnbench.VecEnv(8, worlds="1:30", dt=0.2, max_steps=40, global_plan={}, threads=threads)
    seen = []
    obs, _ = vec.reset(seed=9)
    seen.append(obs)
    for step in range(steps):
        obs, reward, term, trunc, infos = vec.step(weave(step, 8))
        seen.append((obs, reward, term, trunc, infos))
    return seen


def equal(a, b):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(equal(a[k], b[k]) for k in a)
    if isinstance(a, tuple):
        return all(equal(x, y) for x, y in zip(a, b))
    return np.array_equal(a, b)


def test_eight_sub_environments_give_identical_batches_on_one_or_two_threads():
    one, two = run(1), run(2)
    assert all(equal(a, b) for a, b in zip(one, two))
    # 60 steps with episodes cut at 40: every sub-environment was reset at least once.
    ended = sum(int(s[4]["_final_observation"].sum()) for s in one[1:])
    assert ended >= 8


def test_an_autoreset_keeps_the_final_observation_and_info():
    vec = barnbench.VecEnv(4, worlds="1:30", dt=0.2, max_steps=15)
    obs, _ = vec.reset(seed=2)
    for step in range(40):
        previous = obs
        obs, reward, term, trunc, infos = vec.step(weave(step, 4))
        rows = np.flatnonzero(infos["_final_observation"])
        if rows.size:
            break
    else:
        raise AssertionError("no episode ended")
    final, info = infos["final_observation"], infos["final_info"]
    for row in rows:
        assert term[row] or trunc[row]
        assert obs["time"][row] == 0.0 and infos["length"][row] == 0      # the new episode's start
        assert final["time"][row] > 0.0 and info["length"][row] > 0       # the ended one's end
        assert info["outcome"][row] in ("success", "collision", "timeout")
        assert (info["outcome"][row] == "timeout") == bool(trunc[row])
        assert not np.array_equal(final["pose"][row], obs["pose"][row])
        # The final observation is the ended episode's last tick: its time follows the previous one.
        assert final["time"][row] >= previous["time"][row]


def test_world_sampling_is_reproducible_and_stays_in_the_list():
    worlds = [3, 8, 13, 21, 34]

    def draws(seed):
        vec = barnbench.VecEnv(3, worlds=worlds, dt=0.2, max_steps=2)
        _, infos = vec.reset(seed=seed)
        out = [infos["world"].copy()]
        for step in range(8):
            _, _, _, _, infos = vec.step(np.zeros((3, 2)))
            out.append(infos["world"].copy())
        return np.array(out)

    a, b, c = draws(4), draws(4), draws(5)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert set(a.ravel()) <= set(worlds)
    # Sub-environment 1's third episode (two cut at 2 steps each) has the sampler's world.
    assert a[4, 1] == worlds[_core.vec_world_index(4, 1, 2, len(worlds))]


def test_copy_false_gives_views_the_next_step_overwrites():
    vec = barnbench.VecEnv(2, worlds=[1, 2], dt=0.1, copy=False)
    obs, _ = vec.reset(seed=1)
    first = obs["pose"]
    obs, reward, _, _, _ = vec.step(np.array([[1.0, 0.0], [1.0, 0.0]]))
    assert np.shares_memory(first, obs["pose"])
    copied = barnbench.VecEnv(2, worlds=[1, 2], dt=0.1)
    a, _ = copied.reset(seed=1)
    b, _, _, _, _ = copied.step(np.array([[1.0, 0.0], [1.0, 0.0]]))
    assert not np.shares_memory(a["pose"], b["pose"]) and np.array_equal(b["pose"], obs["pose"])


def test_the_reward_terms_are_options():
    # progress 0, step -0.5: every step costs exactly 0.5 until an episode ends.
    vec = barnbench.VecEnv(2, worlds=[1], dt=0.1, reward={"progress": 0.0, "step": -0.5, "collision": -7.0})
    vec.reset(seed=3)
    _, reward, term, trunc, _ = vec.step(np.zeros((2, 2)))
    assert np.array_equal(reward, [-0.5, -0.5]) and not term.any() and not trunc.any()


def test_bad_arguments_are_input_errors():
    with pytest.raises(barnbench.InputError, match="num_envs"):
        barnbench.VecEnv(0)
    with pytest.raises(barnbench.InputError, match="dt"):
        barnbench.VecEnv(2, dt=-1.0)
    with pytest.raises(barnbench.InputError, match="physics"):
        barnbench.VecEnv(2, worlds=[1], dt=0.013)
    with pytest.raises(barnbench.InputError, match="reward"):
        barnbench.VecEnv(2, worlds=[1], reward={"speed": 1.0})
    with pytest.raises(barnbench.InputError, match="99999"):
        barnbench.VecEnv(2, worlds=[99999])
    with pytest.raises(barnbench.InputError, match="worlds"):
        barnbench.VecEnv(2, worlds=[])
    with pytest.raises(barnbench.InputError, match="plan_points"):
        barnbench.VecEnv(2, worlds=[1], plan_points=4)
    with pytest.raises(barnbench.InputError, match="max_steps"):
        barnbench.VecEnv(2, worlds=[1], max_steps=0)
    vec = barnbench.VecEnv(2, worlds=[1], dt=0.1)
    with pytest.raises(RuntimeError):
        vec.step(np.zeros((2, 2)))
    vec.reset(seed=0)
    with pytest.raises(barnbench.InputError, match="actions"):
        vec.step(np.zeros((3, 2)))
    with pytest.raises(barnbench.InputError, match="seed"):
        vec.reset(seed=-1)


def test_the_e2e_frames_binding_encodes_as_the_controller_does():
    # The worked example of tests/controllers/e2e_test.cpp: ranges 0.5, 5, inf, 7.5, NaN, 2.5
    # clipped at 5 m -> -0.8, 1, 1, 1, 1, 0; the robot at (1, 2) facing +y and the plan ending at
    # (1, 7): 5 m ahead -> (0, -1); the previous action (0.5, 1.57) -> (0, 0.5).
    scan = np.array([[0.5, 5.0, np.inf, 7.5, np.nan, 2.5]], dtype=np.float32)
    frame = _core.e2e_frames(scan, np.array([[1.0, 2.0, np.pi / 2]]), np.array([[1.0, 7.0]]),
                             np.array([[0.5, 1.57]]))
    assert frame.dtype == np.float32
    assert np.allclose(frame[0], [-0.8, 1, 1, 1, 1, 0, 0, -1, 0, 0.5], atol=1e-6)
    assert _core.e2e_input_text({}) == "e2e frames=4 range_clip=5 goal_scale=5 v=-1,2 w=-3.14,3.14"


def test_an_mlp_policy_written_from_python_reads_back_in_cpp(tmp_path):
    # The exporter's path (tools/train_e2e.py): torch-layout (out, in) weights -> the file ->
    # C++ inference, against the same network in numpy.
    rng = np.random.default_rng(0)
    shapes = [(6, 5), (4, 6), (2, 4)]
    layers = [(rng.normal(size=s).astype(np.float32), rng.normal(size=s[0]).astype(np.float32)) for s in shapes]
    header = {"output": "tanh", "output_low": [-1.0, -3.14], "output_high": [2.0, 3.14], "input": "test",
              "output_text": "v [m/s], w [rad/s]", "dtype": "float32", "name": "t", "steps": 42}
    _core.write_mlp_policy(str(tmp_path / "t.policy"), layers, header)
    policy = _core.MlpPolicy.load(str(tmp_path / "t.policy"))
    x = rng.normal(size=5).astype(np.float32)
    h = x
    for k, (w, b) in enumerate(layers):
        h = w @ h + b
        if k < len(layers) - 1:
            h = np.maximum(h, 0.0)
    expected = np.tanh(h) * np.array([1.5, 3.14]) + np.array([0.5, 0.0])
    assert np.allclose(policy.forward(x), expected, atol=1e-5)
    assert (policy.inputs, policy.outputs, policy.steps, policy.input_text) == (5, 2, 42, "test")
    header["dtype"] = "float16"
    _core.write_mlp_policy(str(tmp_path / "h.policy"), layers, header)
    half = _core.MlpPolicy.load(str(tmp_path / "h.policy"))
    assert half.dtype == "float16" and np.allclose(half.forward(x), expected, atol=2e-2)
    assert (tmp_path / "h.policy").stat().st_size < (tmp_path / "t.policy").stat().st_size
