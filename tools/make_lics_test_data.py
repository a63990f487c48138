#!/usr/bin/env python3
"""Writes the committed test data for barnbench's LiCS transformer (no torch needed to use it):

    /usr/bin/python3 tools/make_lics_test_data.py          # needs torch: apt-get install python3-torch

- tests/data/lics_transformer_small.policy: a random network of the LiCS-KI architecture with
  the published input (720 ranges in 36 patches), width 32 and 4 heads (so the 1/sqrt(32) score
  scaling differs from 1/sqrt(8)), but a feed-forward width of 48 and 2 encoder and 2 decoder
  blocks, to keep the file small; written through tools/import_lics_weights.py's code;
- tests/data/lics_transformer_small_cases.txt: scans, goals and torch's (v_hat, w_hat) for them,
  which tests/learning/transformer_test.cpp compares with barnbench's forward pass;
- tests/fuzz/seeds/policy/tiny_transformer.policy: a tiny network (8 beams, width 4) seeding the
  policy reader's fuzzer.

Seeded: the same torch gives the same files. The script checks the cases would catch the
scaling quirk and a swapped goal (the outputs move by far more than the tests' tolerance).
"""

import copy
import math
import os
import sys

import numpy as np
import torch

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import import_lics_weights as importer  # noqa: E402
from lics_torch_model import LicsTransformer  # noqa: E402

SMALL = dict(importer.PUBLISHED, ffn_dim=48, encoder_layers=2, decoder_layers=2)
TINY = {"beams": 8, "patches": 2, "model_dim": 4, "heads": 2, "ffn_dim": 3, "encoder_layers": 1,
        "decoder_layers": 1, "layer_norm_eps": 1e-5}
SEED = 7
TOLERANCE = 1e-5  # the C++ test's


def random_model(arch, seed):
    """torch's default initialisation, with the parts it leaves plain made random too: LayerNorm
    gains around 1 and biases around 0, the position embedding, and query and key projections
    three times larger, so that attention is far from uniform and its scaling matters."""
    torch.manual_seed(seed)
    model = LicsTransformer(arch)
    with torch.no_grad():
        for name, p in model.named_parameters():
            if "layer_norm" in name and name.endswith("weight"):
                p.copy_(1.0 + 0.3 * torch.randn_like(p))
            elif "layer_norm" in name:
                p.copy_(0.2 * torch.randn_like(p))
            elif name.endswith("pos_embed"):
                p.copy_(torch.randn_like(p))
            elif "q_proj" in name or "k_proj" in name:
                p.mul_(3.0)
    return model.eval()


def cases(arch, rng):
    """(ranges as read, with +inf; goal) pairs: open space, clutter, ranges past the clip."""
    beams = arch["beams"]
    out = []
    clutter = rng.uniform(0.2, 6.5, beams)
    clutter[rng.random(beams) < 0.2] = np.inf
    out.append((clutter, (0.8, 0.6)))
    out.append((np.full(beams, np.inf), (1.0, 0.0)))
    near = rng.uniform(0.0, 1.2, beams)
    out.append((near, (0.6, -0.8)))
    out.append((rng.uniform(3.0, 8.0, beams), (0.0, 0.0)))  # before the first plan: LiCS feeds (0, 0)
    corridor = np.where(np.abs(np.arange(beams) - beams / 2) < beams / 8, 4.0, 0.6) + rng.uniform(0, 0.1, beams)
    out.append((corridor, (-0.28, 0.96)))
    out.append((rng.uniform(0.5, 5.0, beams), (2.0, 1.0)))  # a goal of length > 1, as given
    return [(np.asarray(r, dtype=np.float32), np.asarray(g, dtype=np.float32)) for r, g in out]


def run(model, ranges, goals):
    clipped = np.clip(ranges, 0.0, importer.PUBLISHED_RANGE_CLIP)  # +inf reads as the clip
    with torch.no_grad():
        return model(torch.from_numpy(clipped), torch.from_numpy(goals)).numpy()


def number(x):
    return "inf" if np.isinf(x) else "%.9g" % x


def write_model(model, arch, path, name):
    state = {k: v.detach().numpy() for k, v in model.state_dict().items()}
    tensors = importer.checked_tensors(state, arch)
    data = importer.policy_bytes(tensors, arch, importer.PUBLISHED_RANGE_CLIP, name,
                                 "random, tools/make_lics_test_data.py seed %d" % SEED)
    with open(path, "wb") as f:
        f.write(data)
    return len(data)


def main():
    rng = np.random.default_rng(SEED)
    model = random_model(SMALL, SEED)
    pairs = cases(SMALL, rng)
    ranges = np.stack([r for r, _ in pairs])
    goals = np.stack([g for _, g in pairs])
    expected = run(model, ranges, goals)

    # The cases must tell the published scaling from the per-head one, and the goal's x from its y.
    per_head = copy.deepcopy(model)
    for module in per_head.modules():
        if hasattr(module, "scale"):
            module.scale = 1.0 / math.sqrt(SMALL["model_dim"] // SMALL["heads"])
    scaling = np.max(np.abs(run(per_head, ranges, goals) - expected))
    swapped = np.max(np.abs(run(model, ranges, goals[:, ::-1].copy()) - expected))
    print("max |change| with 1/sqrt(d/heads): %.3g; with the goal swapped: %.3g" % (scaling, swapped))
    assert scaling > 100 * TOLERANCE and swapped > 100 * TOLERANCE, "the cases would not catch these"

    data = os.path.join(ROOT, "tests", "data")
    os.makedirs(data, exist_ok=True)
    size = write_model(model, SMALL, os.path.join(data, "lics_transformer_small.policy"), "lics_test_small")
    lines = [
        "# barnbench LiCS transformer test cases, written by tools/make_lics_test_data.py (seed %d, torch %s)"
        % (SEED, torch.__version__),
        "# for tests/data/lics_transformer_small.policy; one case per line:",
        "# goal_x goal_y v_hat w_hat, then the %d ranges as read (inf: no return; clipped to [0, 5] m first)"
        % SMALL["beams"],
    ]
    for r, g, y in zip(ranges, goals, expected):
        lines.append(" ".join(number(x) for x in (*g, *y, *r)))
    with open(os.path.join(data, "lics_transformer_small_cases.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")

    tiny = random_model(TINY, SEED)
    seed_path = os.path.join(ROOT, "tests", "fuzz", "seeds", "policy", "tiny_transformer.policy")
    tiny_size = write_model(tiny, TINY, seed_path, "tiny")
    print("wrote tests/data/lics_transformer_small.policy (%d bytes), lics_transformer_small_cases.txt (%d cases), "
          "tests/fuzz/seeds/policy/tiny_transformer.policy (%d bytes)" % (size, len(pairs), tiny_size))


if __name__ == "__main__":
    main()
