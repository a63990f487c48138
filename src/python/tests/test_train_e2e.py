"""tools/train_e2e.py: a few hundred steps of TD3 on VecEnv (the CI smoke test of the trainer)."""

import csv
import importlib.util
import math
import os

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="python3-torch is not installed (tools/setup.sh --with-torch): "
                                            "the training smoke test is skipped")
pytest.importorskip("yaml", reason="python3-yaml is not installed: the training smoke test is skipped")

import barnbench  # noqa: E402
from barnbench import _core  # noqa: E402


def load_trainer():
    path = os.path.join(_core.SOURCE_DIR, "tools", "train_e2e.py")
    spec = importlib.util.spec_from_file_location("train_e2e", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# Small networks and short iterations: the published recipe's loop, cut down to seconds.
SMALL = ["--set", "network.hidden=32", "--set", "env.num_envs=4", "--set", "training.pre_collect=64",
         "--set", "training.collect_per_iteration=64", "--set", "training.updates_per_iteration=16",
         "--set", "td3.buffer_size=1000", "--set", "td3.batch_size=32", "--set", "td3.actor_lr=0.001",
         "--set", "td3.critic_lr=0.001", "--set", "training.checkpoint_every=1", "--set", "training.policy_dtype=float32"]


def test_a_short_training_run_fills_the_replay_moves_the_networks_and_exports_the_actor(tmp_path):
    train = load_trainer()
    out = str(tmp_path / "run")
    train.main(["--out", out, "--max-steps", "256"] + SMALL)
    with open(os.path.join(out, "curve.csv")) as f:
        rows = list(csv.DictReader(f))
    # 64 steps of pre-collection, then iterations of 64 steps and 16 updates up to 256 steps.
    assert [int(r["steps"]) for r in rows] == [128, 192, 256]
    losses = [float(r["critic_loss"]) for r in rows]
    assert all(math.isfinite(x) for x in losses) and len(set(losses)) == 3  # the loss moves
    with np.load(os.path.join(out, "checkpoint", "replay.npz")) as replay:
        next_frame, size, pointer, added, frames_written = (int(x) for x in replay["counters"])
    # Every environment step becomes one transition (the last n - 1 of a running episode wait).
    assert 256 - 4 * 3 <= size <= 256 and size == added and frames_written >= 256
    # The actor moved away from its initialisation (the same seed builds the same initial actor).
    config = train.load_config(os.path.join(out, "config.yaml"))
    torch.manual_seed(config["seed"])
    initial = train.Actor(4 * 724, config["network"])
    trained = train.Actor(4 * 724, config["network"])
    trained.load_state_dict(torch.load(os.path.join(out, "checkpoint", "networks.pt"))["actor"])
    assert not torch.equal(initial.out.weight, trained.out.weight)
    # The exported policy file is that actor: barnbench's C++ inference gives its actions.
    policy = _core.MlpPolicy.load(os.path.join(out, "e2e.policy"))
    assert (policy.inputs, policy.outputs, policy.steps) == (4 * 724, 2, 256)
    assert policy.input_text == _core.e2e_input_text({})
    x = np.random.default_rng(1).uniform(-1, 1, 4 * 724).astype(np.float32)
    with torch.no_grad():
        y = trained(torch.from_numpy(x)[None])[0].numpy()
    assert np.allclose(policy.forward(x), y * np.array([1.5, 3.14]) + np.array([0.5, 0.0]), atol=1e-5)
    # Resumable: the same command goes on from the checkpoint.
    train.main(["--out", out, "--max-steps", "320"] + SMALL)
    with open(os.path.join(out, "curve.csv")) as f:
        assert [int(r["steps"]) for r in csv.DictReader(f)] == [128, 192, 256, 320]
    # Another config in the same folder is refused.
    with pytest.raises(barnbench.InputError, match="another config"):
        train.main(["--out", out, "--max-steps", "400", "--set", "td3.gamma=0.9"] + SMALL)
