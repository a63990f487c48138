#!/usr/bin/env python3
"""Converts your own copy of the published APPLR actor into a barnbench APPLR policy file.

    /usr/bin/python3 tools/import_applr_weights.py policy_actor --out configs/policies/applr_dwa.policy

The published actor (Daffan/the-barn-challenge, branch applr, applr/data/param_policy/policy_actor,
MIT licence) is the TD3 actor's state_dict as the original saved it: pickle.dump of an
OrderedDict of tensors (no torch.save framing). It is an MLP: head.mlp.0 (721 -> 512), relu,
head.mlp.2 (512 -> 512), relu, fc (512 -> 7), tanh; the tanh outputs are scaled into the ranges of
the seven DWA parameters it sets (docs/systems/applr_dwa.md). The state_dict must have exactly
these keys and shapes; anything else is refused (exit 2) naming the key. A file in torch.save's
zip format holding the same state_dict is read too.

Reading needs PyTorch (Debian: apt-get install python3-torch). Nothing in the file but the
OrderedDict and its tensors is run: the pickle is read with an unpickler that refuses every other
class (a pickled module, for one), and each tensor's storage with torch.load(weights_only=True).

Writing: barnbench's APPLR policy format, version 1 (docs/systems/applr_dwa.md): a text header
with the architecture, the input clip, the seven parameters and their ranges, and the FNV-1a 64
digest of the weights, then the MLP's blocks w1 b1 w2 b2 w3 b3 as float32 little-endian, each
matrix column-major in its PyTorch shape. The same input gives the same bytes.

barnbench does not ship the weights: convert your own copy for your own use; never commit it or
the converted file to this repository.
"""

import argparse
import collections
import io
import os
import pickle
import re
import sys

try:
    import numpy as np
except ImportError:  # an interpreter without numpy (Debian's /usr/bin/python3 has it with python3-numpy)
    sys.exit("import_applr_weights: needs numpy: run it with /usr/bin/python3 (apt-get install python3-numpy)")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from import_lics_weights import fnv1a64, format_number, state_dict_arrays  # noqa: E402 - shared with that importer

# The published actor: 720 ranges + the goal angle, 2 x 512 hidden units (config.yaml
# hidden_layer_size, num_layers), the seven parameters of param_list with the ranges of
# envs/parameter_tuning_envs.py RANGE_DICT, and the input clip laser_clip.
PUBLISHED = {"beams": 720, "hidden": 512}
PUBLISHED_ACTIONS = [
    ("max_vel_x", 0.2, 2.0),
    ("max_vel_theta", 0.314, 3.14),
    ("vx_samples", 4.0, 12.0),
    ("vtheta_samples", 8.0, 40.0),
    ("path_distance_bias", 0.1, 1.5),
    ("goal_distance_bias", 0.1, 2.0),
    ("inflation_radius", 0.1, 0.6),
]
PUBLISHED_RANGE_CLIP = 2.0

# The fixed texts of the header (src/learning/applr_policy.cpp); a reader refuses others.
FORMAT = "barnbench-applr-policy"
VERSION = 1
ACTIVATION = "relu"
INPUT = ("ranges[beams] clipped at range_clip (+inf and NaN -> range_clip), each (r - range_clip / 2) / range_clip; "
         "then the local goal's angle in the robot frame / (2 pi)")
OUTPUT = ("tanh; float32 bias + scale * tanh with scale = (hi - lo) / 2, bias = (hi + lo) / 2; "
          "then clipped to [lo, hi]")
LAYOUT = "float32 little-endian; w1 b1 w2 b2 w3 b3 (state_dict head.mlp.0, head.mlp.2, fc); matrices column-major"

TORCH_HINT = "install PyTorch to read it (Debian: apt-get install python3-torch)"


class ImportError_(Exception):
    """A file this script cannot convert; the message says why."""


def file_tensors(arch, outputs):
    """[(state_dict key, shape)] in the file's block order w1 b1 w2 b2 w3 b3."""
    inputs, hidden = arch["beams"] + 1, arch["hidden"]
    return [
        ("head.mlp.0.weight", (hidden, inputs)),
        ("head.mlp.0.bias", (hidden,)),
        ("head.mlp.2.weight", (hidden, hidden)),
        ("head.mlp.2.bias", (hidden,)),
        ("fc.weight", (outputs, hidden)),
        ("fc.bias", (outputs,)),
    ]


def _arch_text(arch, outputs):
    return "%d-%d-%d-%d" % (arch["beams"] + 1, arch["hidden"], arch["hidden"], outputs)


def checked_tensors(state, arch, outputs):
    """The file's arrays in block order, after checking `state` (key -> array) has exactly the
    keys and shapes of the actor `arch` with `outputs` actions, float32 and finite."""
    expected = file_tensors(arch, outputs)
    missing = [k for k, _ in expected if k not in state]
    extra = [k for k in state if k not in dict(expected)]
    what = "the APPLR actor %s" % _arch_text(arch, outputs)
    if missing:
        raise ImportError_("the state_dict lacks %s: not %s" % (", ".join(missing), what))
    if extra:
        raise ImportError_("the state_dict has keys %s does not: %s" % (what, ", ".join(extra)))
    arrays = []
    for key, shape in expected:
        array = np.asarray(state[key])
        if tuple(array.shape) != shape:
            raise ImportError_("%s has shape %s; expected %s (%s)" % (key, list(array.shape), list(shape), what))
        if array.dtype != np.float32:
            raise ImportError_("%s is %s; expected float32" % (key, array.dtype))
        if not np.all(np.isfinite(array)):
            raise ImportError_("%s holds a non-finite value" % key)
        arrays.append((key, array))
    return arrays


def policy_bytes(tensors, arch, actions, range_clip, name, source):
    """The file: header and payload. `tensors` as checked_tensors returns them, `actions` a list
    of (name, lo, hi)."""
    if not range_clip > 0:
        raise ImportError_("range_clip must be > 0")
    for field, text in (("name", name), ("source", source)):
        if re.search(r"[\r\n]", text):
            raise ImportError_("%s must be one line" % field)
    for action, lo, hi in actions:
        if not re.fullmatch(r"[a-z0-9_]+", action) or not lo < hi:
            raise ImportError_("action %s [%r, %r]: needs a [a-z0-9_]+ name and lo < hi" % (action, lo, hi))
    payload = b"".join(np.asarray(array, dtype="<f4").flatten(order="F").tobytes() for _, array in tensors)
    lines = [
        ("format", FORMAT), ("version", str(VERSION)), ("architecture", _arch_text(arch, len(actions))),
        ("activation", ACTIVATION), ("beams", str(int(arch["beams"]))), ("range_clip", format_number(range_clip)),
        ("input", INPUT), ("output", OUTPUT),
        ("actions", "; ".join("%s %s %s" % (a, format_number(lo), format_number(hi)) for a, lo, hi in actions)),
        ("layout", LAYOUT), ("payload_bytes", str(len(payload))), ("weights_fnv1a64", "0x%x" % fnv1a64(payload)),
        ("name", name), ("source", source),
    ]
    header = "".join("%s: %s\n" % kv for kv in lines) + "end_header\n"
    return header.encode("utf-8") + payload


class _StateDictUnpickler(pickle.Unpickler):
    """Builds the OrderedDict of tensors of a pickle.dump(state_dict) file and nothing else."""

    def __init__(self, file, torch):
        super().__init__(file)
        self._torch = torch

    def find_class(self, module, name):
        torch = self._torch
        if (module, name) == ("collections", "OrderedDict"):
            return collections.OrderedDict
        if (module, name) == ("torch._utils", "_rebuild_tensor_v2"):
            return torch._utils._rebuild_tensor_v2
        if (module, name) == ("torch.storage", "_load_from_bytes"):
            # A tensor's storage, itself in torch.save's format: read with weights_only.
            return lambda data: torch.load(io.BytesIO(data), map_location="cpu", weights_only=True)
        raise ImportError_("the pickle refers to %s.%s: not a state_dict of tensors (a pickled module? save its "
                           "state_dict() instead)" % (module, name))


def read_state_dict(path):
    """The state_dict in `path` (pickle.dump of a state_dict, or torch.save) as {key: numpy array}."""
    try:
        import torch  # noqa: PLC0415 - needed only here
    except ImportError:
        raise ImportError_("%s: reading a PyTorch file needs torch: %s" % (path, TORCH_HINT)) from None
    with open(path, "rb") as f:
        magic = f.read(4)
        f.seek(0)
        try:
            if magic.startswith(b"PK"):  # torch.save's zip format
                state = torch.load(f, map_location="cpu", weights_only=True)
            else:
                state = _StateDictUnpickler(f, torch).load()
        except ImportError_:
            raise
        except Exception as e:  # noqa: BLE001 - pickle and torch raise many kinds for a file they cannot read
            message = str(e).splitlines()[0] if str(e) else type(e).__name__
            raise ImportError_("%s: cannot be read as a state_dict: %s" % (path, message)) from None
    return state_dict_arrays(state, path, ImportError_)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("weights", help="your copy of the published actor, e.g. policy_actor")
    parser.add_argument("--out", required=True, help="policy file to write, e.g. configs/policies/applr_dwa.policy")
    parser.add_argument("--name", default=None, help="the policy's name in its header (default: from --out)")
    parser.add_argument("--source", default=None,
                        help="where the weights came from, one line (default: the input file's name)")
    args = parser.parse_args(argv)
    name = args.name or os.path.splitext(os.path.basename(args.out))[0] or "applr_imported"
    source = args.source if args.source is not None else os.path.basename(args.weights)
    try:
        tensors = checked_tensors(read_state_dict(args.weights), PUBLISHED, len(PUBLISHED_ACTIONS))
        data = policy_bytes(tensors, PUBLISHED, PUBLISHED_ACTIONS, PUBLISHED_RANGE_CLIP, name, source)
    except (ImportError_, OSError) as e:
        print("import_applr_weights: %s" % e, file=sys.stderr)
        return 2
    tmp = args.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, args.out)
    print("wrote %s: the APPLR actor (%s), ranges clipped at %s m, %d bytes"
          % (args.out, _arch_text(PUBLISHED, len(PUBLISHED_ACTIONS)), format_number(PUBLISHED_RANGE_CLIP), len(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
