"""tools/import_applr_weights.py: the file it writes, the state_dicts it refuses, and barnbench's
forward pass on what it imports against torch's.

The format tests need numpy only. The tests through the importer's command line need torch
(they write the original's pickle files; Debian: apt-get install python3-torch) and build/barn
(or BARN_BINARY); they skip, saying which, without them. The test of the published actor needs
your own copy: BARN_APPLR_WEIGHTS=/path/to/policy_actor.
"""

import collections
import importlib.util
import os
import pickle
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPT = os.path.join(ROOT, "tools", "import_applr_weights.py")

spec = importlib.util.spec_from_file_location("import_applr_weights", SCRIPT)
importer = importlib.util.module_from_spec(spec)
spec.loader.exec_module(importer)

TINY = {"beams": 8, "hidden": 5}
ACTIONS = importer.PUBLISHED_ACTIONS


def barn_binary():
    path = os.environ.get("BARN_BINARY", os.path.join(ROOT, "build", "barn"))
    if not os.path.exists(path):
        pytest.skip("no barn binary at %s (build it, or set BARN_BINARY)" % path)
    return path


def need_torch():
    if importlib.util.find_spec("torch") is None:
        pytest.skip("torch is not installed (Debian: apt-get install python3-torch)")
    import torch  # noqa: PLC0415
    return torch


def random_state(arch, outputs=7, seed=1):
    """A state_dict of the actor `arch` as numpy float32 arrays."""
    rng = np.random.default_rng(seed)
    return {key: rng.normal(0, 0.3, shape).astype(np.float32) for key, shape in importer.file_tensors(arch, outputs)}


def decode(data):
    """(header dict, payload bytes) of a policy file."""
    head, payload = data.split(b"end_header\n", 1)
    header = dict(line.split(": ", 1) for line in head.decode().splitlines())
    return header, payload


def reference(state, scans, angle, clip=2.0, actions=ACTIONS):
    """The original's parameters: its observation, the actor in float32, tanh * scale + bias in
    float32 (TD3.select_action with no exploration noise), np.clip to the range."""
    obs = np.concatenate([(np.minimum(scans, clip) - clip / 2.0) / clip,
                          np.full((len(scans), 1), angle / (2.0 * np.pi))], axis=1).astype(np.float32)
    h = np.maximum(obs @ state["head.mlp.0.weight"].T + state["head.mlp.0.bias"], 0)
    h = np.maximum(h @ state["head.mlp.2.weight"].T + state["head.mlp.2.bias"], 0)
    u = np.tanh(h @ state["fc.weight"].T + state["fc.bias"]).astype(np.float32)
    low = np.array([lo for _, lo, _ in actions], dtype=np.float32)
    high = np.array([hi for _, _, hi in actions], dtype=np.float32)
    a = u * ((high - low) / 2.0) + (high + low) / 2.0
    return np.clip(a.astype(np.float64), [lo for _, lo, _ in actions], [hi for _, _, hi in actions])


def act(barn, policy, scans, angle):
    """barn policy act's parameters for each scan, the goal at `angle`."""
    lines = "\n".join(" ".join("inf" if np.isinf(r) else repr(float(r)) for r in scan) for scan in scans) + "\n"
    goal = "%r,%r" % (float(np.cos(angle)), float(np.sin(angle)))
    result = subprocess.run([barn, "policy", "act", "--policy", str(policy), "--goal", goal],
                            input=lines, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return np.array([[float(v) for v in line.split()] for line in result.stdout.splitlines()])


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def pickle_state_dict(torch, state, path):
    """What the original's TD3.save wrote: pickle.dump of the actor's state_dict (an OrderedDict)."""
    ordered = collections.OrderedDict((k, torch.from_numpy(np.ascontiguousarray(v))) for k, v in state.items())
    with open(path, "wb") as f:
        pickle.dump(ordered, f)


# ---- The format (numpy only) ----

def test_the_file_holds_the_three_layers_column_major_and_the_seven_ranges():
    state = random_state(TINY)
    data = importer.policy_bytes(importer.checked_tensors(state, TINY, 7), TINY, ACTIONS, 2.0, "tiny", "test")
    header, payload = decode(data)
    assert header["format"] == "barnbench-applr-policy"
    assert (header["architecture"], header["beams"], header["range_clip"]) == ("9-5-5-7", "8", "2")
    assert header["actions"] == ("max_vel_x 0.2 2; max_vel_theta 0.314 3.14; vx_samples 4 12; vtheta_samples 8 40; "
                                 "path_distance_bias 0.1 1.5; goal_distance_bias 0.1 2; inflation_radius 0.1 0.6")
    assert header["weights_fnv1a64"] == "0x%x" % importer.fnv1a64(payload)
    # 5 x 9 + 5 + 5 x 5 + 5 + 7 x 5 + 7 = 122 floats.
    assert int(header["payload_bytes"]) == len(payload) == 4 * 122
    floats = np.frombuffer(payload, dtype="<f4")
    offset = 0
    for key, shape in importer.file_tensors(TINY, 7):
        n = int(np.prod(shape))
        np.testing.assert_array_equal(floats[offset:offset + n].reshape(shape, order="F"), state[key], err_msg=key)
        offset += n
    assert offset == floats.size
    assert importer.policy_bytes(importer.checked_tensors(state, TINY, 7), TINY, ACTIONS, 2.0, "tiny", "test") == data


def test_a_state_dict_of_another_network_is_refused_naming_the_key():
    state = random_state(TINY)
    del state["fc.bias"]
    with pytest.raises(importer.ImportError_, match="lacks fc.bias"):
        importer.checked_tensors(state, TINY, 7)

    state = random_state(TINY)
    state["state_preprocess.net.0.weight"] = np.zeros((5, 9), np.float32)  # the e2e branch's encoder
    with pytest.raises(importer.ImportError_, match="has keys .* does not: state_preprocess.net.0.weight"):
        importer.checked_tensors(state, TINY, 7)

    state = random_state(TINY, outputs=2)  # a motion-control actor: (v, w)
    with pytest.raises(importer.ImportError_, match=r"fc.weight has shape \[2, 5\]; expected \[7, 5\]"):
        importer.checked_tensors(state, TINY, 7)

    state = random_state(TINY)
    state["head.mlp.2.bias"] = state["head.mlp.2.bias"].astype(np.float64)
    with pytest.raises(importer.ImportError_, match="head.mlp.2.bias is float64; expected float32"):
        importer.checked_tensors(state, TINY, 7)

    state = random_state(TINY)
    state["head.mlp.0.weight"][1, 2] = np.inf
    with pytest.raises(importer.ImportError_, match="head.mlp.0.weight holds a non-finite value"):
        importer.checked_tensors(state, TINY, 7)


# ---- Through the command line (torch, and build/barn) ----

def test_a_random_actor_round_trips_into_barnbench(tmp_path):
    # An actor of the published shape with random weights, pickled as the original pickles it;
    # barnbench's parameters for it equal the original's arithmetic (float32 both sides).
    torch = need_torch()
    barn = barn_binary()
    state = random_state(importer.PUBLISHED, seed=3)
    pickle_state_dict(torch, state, tmp_path / "policy_actor")
    out = tmp_path / "random.policy"
    result = run_script(str(tmp_path / "policy_actor"), "--out", str(out))
    assert result.returncode == 0, result.stderr
    header, _ = decode(out.read_bytes())
    assert (header["name"], header["source"], header["architecture"]) == ("random", "policy_actor", "721-512-512-7")

    rng = np.random.default_rng(5)
    scans = rng.uniform(0.1, 4.0, (4, 720))
    scans[0, ::4] = np.inf
    for angle in (0.0, 0.7, -2.5):
        got = act(barn, out, scans, angle)
        expected = reference(state, scans, angle)
        assert got.shape == (4, 7)
        assert np.max(np.abs(got - expected)) < 1e-4
        assert np.all(got >= [lo for _, lo, _ in ACTIONS]) and np.all(got <= [hi for _, _, hi in ACTIONS])


def test_the_zip_format_reads_the_same(tmp_path):
    torch = need_torch()
    state = random_state(TINY)
    torch.save({k: torch.from_numpy(v) for k, v in state.items()}, str(tmp_path / "zip.pth"))
    arrays = importer.read_state_dict(str(tmp_path / "zip.pth"))
    for key in state:
        np.testing.assert_array_equal(arrays[key], state[key])


def test_the_command_refuses_other_files_with_exit_two(tmp_path):
    torch = need_torch()
    renamed = random_state(importer.PUBLISHED)
    renamed["head.mlp.1.weight"] = renamed.pop("head.mlp.2.weight")
    pickle_state_dict(torch, renamed, tmp_path / "renamed")
    result = run_script(str(tmp_path / "renamed"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "lacks head.mlp.2.weight" in result.stderr
    assert not (tmp_path / "x.policy").exists()

    # A pickle that names any other class (a pickled module, say) is refused without running it.
    with open(tmp_path / "module", "wb") as f:
        pickle.dump(collections.Counter(a=1), f)
    result = run_script(str(tmp_path / "module"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "refers to collections.Counter" in result.stderr

    (tmp_path / "garbage").write_bytes(b"not a pickle")
    result = run_script(str(tmp_path / "garbage"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "cannot be read as a state_dict" in result.stderr


def test_the_published_actor_runs_in_barnbench_as_in_its_own_arithmetic(tmp_path):
    path = os.environ.get("BARN_APPLR_WEIGHTS")
    if not path or not os.path.exists(path):
        pytest.skip("set BARN_APPLR_WEIGHTS to your copy of the published APPLR policy_actor to check it")
    need_torch()
    barn = barn_binary()
    out = tmp_path / "applr_dwa.policy"
    result = run_script(path, "--out", str(out))
    assert result.returncode == 0, result.stderr
    state = importer.read_state_dict(path)

    # Clutter, open space, a corridor, ranges past the 2 m clip; goals ahead, aside and behind.
    rng = np.random.default_rng(11)
    corridor = np.where(np.abs(np.arange(720) - 360) < 90, 1.8, 0.5)
    scans = np.array([rng.uniform(0.2, 3.0, 720), np.full(720, np.inf), rng.uniform(0.1, 1.0, 720), corridor])
    worst = 0.0
    for angle in (0.0, 1.2, -0.6, 3.0):
        got = act(barn, out, scans, angle)
        worst = max(worst, float(np.max(np.abs(got - reference(state, scans, angle)))))
    print("published actor: max |barnbench - reference| = %.3g over %d cases" % (worst, 4 * len(scans)))
    assert worst < 1e-4
