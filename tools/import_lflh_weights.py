#!/usr/bin/env python3
"""Converts your own copy of the published LfLH policy weights into a barnbench policy file.

    /usr/bin/python3 tools/import_lflh_weights.py model_1000 --out lflh_published_1m.policy
    build/barn run --controller lflh_published --config my_lflh.yaml --worlds test50
    (my_lflh.yaml: type: lflh, lflh: {policy: lflh_published_1m.policy}; for the 2 m/s model
    also max_speed: 2.0)

The published LfLH network (LearningUAV/hallucination, LfD_2D) is a PyTorch state_dict saved by torch.save in
the legacy (non-zip) format: keys fcs.0.weight [256, 722], fcs.0.bias [256], fcs.1.weight
[256, 256], fcs.1.bias, action_fc.weight [2, 256], action_fc.bias [2]; hidden layers leaky ReLU
(slope 0.01); inputs 720 ranges (ROS order, -135 to +135 deg) then the unit goal (x forward,
y left); outputs (v, w). The published deployment clipped the ranges at 2.0 m (for the 2 m/s
model too), hence --range-clip 2.0.

Reading: the legacy format is read with Python's own pickle (an unpickler that resolves only the
few names such a file uses, so nothing else in the file can run) and numpy; torch is not needed.
A file in the newer zip format is read with torch.load when torch is importable; otherwise the
script says how to install it (Debian: apt-get install python3-torch).

Writing: barnbench's policy format version 3 (configs/policies/README.md): a text header, then
float32 little-endian blocks w1 b1 w2 b2 w3 b3, matrices column-major.

The published weights have no licence: convert your own copy for your own use; never commit it
or the converted file to this repository.
"""

import argparse
import collections
import io
import os
import pickle
import re
import struct
import sys
import zipfile

try:
    import numpy as np
except ImportError:  # an interpreter without numpy (Debian's /usr/bin/python3 has it with python3-numpy)
    sys.exit("import_lflh_weights: needs numpy: run it with /usr/bin/python3 (apt-get install python3-numpy)")

LEGACY_MAGIC = 0x1950A86A20F9469CFC6C  # torch.serialization's MAGIC_NUMBER
LEGACY_PROTOCOL = 1001                 # torch.serialization's PROTOCOL_VERSION

KEYS = ["fcs.0.weight", "fcs.0.bias", "fcs.1.weight", "fcs.1.bias", "action_fc.weight", "action_fc.bias"]

# Storage classes of a legacy file -> numpy dtype (little-endian, as torch writes on x86 and ARM).
STORAGE_DTYPES = {
    "FloatStorage": "<f4",
    "DoubleStorage": "<f8",
    "HalfStorage": "<f2",
    "LongStorage": "<i8",
    "IntStorage": "<i4",
    "ShortStorage": "<i2",
    "CharStorage": "i1",
    "ByteStorage": "u1",
    "BoolStorage": "?",
}

# The fixed texts of the policy header (src/learning/policy.cpp); a reader refuses others.
POLICY_INPUT = "ranges[beams] clipped to [0, range_clip] (+inf -> range_clip), goal_x, goal_y"
POLICY_GOAL = "unit vector to the local goal in the robot frame, x forward, y left"
POLICY_OUTPUT = "v [m/s], w [rad/s]"
POLICY_LAYOUT = "float32 little-endian; w1 b1 w2 b2 w3 b3; matrices column-major"

TORCH_HINT = ("install PyTorch to read it (Debian: apt-get install python3-torch), "
              "or save it again with torch.save(state_dict, path, _use_new_zipfile_serialization=False)")


class ImportError_(Exception):
    """A file this script cannot convert; the message says why."""


class _StorageType:
    """Stands for a torch.*Storage class named in the file."""

    def __init__(self, name):
        if name not in STORAGE_DTYPES:
            raise ImportError_("storage type torch.%s is not supported" % name)
        self.name = name
        self.dtype = np.dtype(STORAGE_DTYPES[name])


class _Storage:
    """A storage of the file: its data is read after the pickles, by key."""

    def __init__(self, key, dtype, numel):
        self.key = key
        self.dtype = dtype
        self.numel = numel
        self.data = None


class _Tensor:
    """A tensor to be made once its storage's data is read (torch._utils._rebuild_tensor_v2)."""

    def __init__(self, storage, offset, size, stride):
        self.storage = storage
        self.offset = int(offset)
        self.size = tuple(int(s) for s in size)
        self.stride = tuple(int(s) for s in stride)

    def array(self):
        data = self.storage.data
        if not self.size:
            return np.array(data[self.offset])
        last = self.offset + sum((n - 1) * s for n, s in zip(self.size, self.stride) if n > 0)
        if any(n == 0 for n in self.size):
            return np.zeros(self.size, dtype=data.dtype)
        if self.offset < 0 or last >= data.size:
            raise ImportError_("a tensor reaches beyond its storage (%d elements)" % data.size)
        view = np.lib.stride_tricks.as_strided(
            data[self.offset:], shape=self.size, strides=tuple(s * data.itemsize for s in self.stride))
        return np.array(view)


def _rebuild_tensor_v2(storage, storage_offset, size, stride, requires_grad=False, backward_hooks=None, *rest):
    if not isinstance(storage, _Storage):
        raise ImportError_("a tensor without a storage")
    return _Tensor(storage, storage_offset, size, stride)


def _rebuild_tensor(storage, storage_offset, size, stride):
    return _rebuild_tensor_v2(storage, storage_offset, size, stride)


def _rebuild_parameter(data, requires_grad=False, backward_hooks=None, *rest):
    return data


class _LegacyUnpickler(pickle.Unpickler):
    """Resolves only the names a legacy state_dict uses; anything else is refused."""

    def __init__(self, file, storages):
        super().__init__(file, encoding="latin1")
        self.storages = storages

    def find_class(self, module, name):
        if module == "collections" and name == "OrderedDict":
            return collections.OrderedDict
        if module == "torch._utils" and name == "_rebuild_tensor_v2":
            return _rebuild_tensor_v2
        if module == "torch._utils" and name == "_rebuild_tensor":
            return _rebuild_tensor
        if module == "torch._utils" and name == "_rebuild_parameter":
            return _rebuild_parameter
        if module == "torch" and name.endswith("Storage"):
            return _StorageType(name)
        raise ImportError_("the file names %s.%s, which a saved state_dict does not (refused)" % (module, name))

    def persistent_load(self, saved_id):
        # ('storage', storage_type, key, location, numel[, view_metadata])
        if not isinstance(saved_id, tuple) or not saved_id or saved_id[0] != "storage":
            raise ImportError_("unknown persistent id %r" % (saved_id,))
        storage_type, key, _location, numel = saved_id[1:5]
        view = saved_id[5] if len(saved_id) > 5 else None
        if view is not None:
            raise ImportError_("storage views (torch before 0.4) are not supported")
        if not isinstance(storage_type, _StorageType):
            raise ImportError_("persistent id without a storage type")
        key = str(key)
        if key not in self.storages:
            self.storages[key] = _Storage(key, storage_type.dtype, int(numel))
        return self.storages[key]


def read_legacy(data):
    """The state_dict of a legacy torch.save file (bytes) as {name: numpy array}."""
    f = io.BytesIO(data)
    try:
        magic = pickle.load(f, encoding="latin1")
    except Exception as e:  # noqa: BLE001 - any failure here means: not this format
        raise ImportError_("not a legacy torch file (%s)" % e) from None
    if magic != LEGACY_MAGIC:
        raise ImportError_("not a legacy torch file (wrong magic number)")
    protocol = pickle.load(f, encoding="latin1")
    if protocol != LEGACY_PROTOCOL:
        raise ImportError_("legacy torch file of protocol version %r; expected %d" % (protocol, LEGACY_PROTOCOL))
    sys_info = pickle.load(f, encoding="latin1")
    if isinstance(sys_info, dict) and not sys_info.get("little_endian", True):
        raise ImportError_("the file was written on a big-endian machine (not supported)")
    storages = {}
    state = _LegacyUnpickler(f, storages).load()
    keys = pickle.load(f, encoding="latin1")
    for key in keys:
        key = str(key)
        if key not in storages:
            raise ImportError_("storage %s is listed but no tensor uses it" % key)
        storage = storages[key]
        header = f.read(8)
        if len(header) != 8:
            raise ImportError_("truncated: storage %s has no element count" % key)
        (numel,) = struct.unpack("<q", header)
        if numel != storage.numel:
            raise ImportError_("storage %s holds %d elements, the pickle says %d" % (key, numel, storage.numel))
        nbytes = numel * storage.dtype.itemsize
        raw = f.read(nbytes)
        if len(raw) != nbytes:
            raise ImportError_("truncated: storage %s needs %d bytes, the file has %d" % (key, nbytes, len(raw)))
        storage.data = np.frombuffer(raw, dtype=storage.dtype)
    missing = [k for k, s in storages.items() if s.data is None]
    if missing:
        raise ImportError_("storages %s have no data" % ", ".join(missing))
    if not isinstance(state, dict):
        raise ImportError_("the file holds a %s, not a state_dict" % type(state).__name__)
    return {name: (value.array() if isinstance(value, _Tensor) else value) for name, value in state.items()}


def read_zip_with_torch(path):
    try:
        import torch  # noqa: PLC0415 - optional
    except ImportError:
        raise ImportError_("%s is in torch's zip format and torch is not installed: %s" % (path, TORCH_HINT)) from None
    state = torch.load(path, map_location="cpu")
    if hasattr(state, "state_dict") and not isinstance(state, dict):
        state = state.state_dict()
    if not isinstance(state, dict):
        raise ImportError_("%s holds a %s, not a state_dict" % (path, type(state).__name__))
    return {k: (v.detach().cpu().numpy() if hasattr(v, "detach") else v) for k, v in state.items()}


def read_state_dict(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"PK\x03\x04" or zipfile.is_zipfile(io.BytesIO(data)):
        return read_zip_with_torch(path)
    if data[:1] != b"\x80":
        raise ImportError_("%s is neither a legacy torch file (a pickle) nor a zip one: %s" % (path, TORCH_HINT))
    try:
        return read_legacy(data)
    except ImportError_ as e:
        raise ImportError_("%s: %s" % (path, e)) from None


def network(state):
    """(w1, b1, w2, b2, w3, b3) as float32, checked against the published shapes."""
    missing = [k for k in KEYS if k not in state]
    if missing:
        raise ImportError_("the state_dict lacks %s (it has %s)" % (", ".join(missing), ", ".join(state)))
    w1, b1, w2, b2, w3, b3 = (np.asarray(state[k], dtype=np.float64) for k in KEYS)
    hidden, inputs = w1.shape if w1.ndim == 2 else (0, 0)
    expected = {"fcs.0.weight": (hidden, inputs), "fcs.0.bias": (hidden,), "fcs.1.weight": (hidden, hidden),
                "fcs.1.bias": (hidden,), "action_fc.weight": (2, hidden), "action_fc.bias": (2,)}
    for key, array in zip(KEYS, (w1, b1, w2, b2, w3, b3)):
        if array.shape != expected[key] or hidden < 1 or inputs < 3:
            raise ImportError_("%s has shape %s; expected %s (inputs = beams + 2, hidden, 2 outputs)"
                               % (key, list(array.shape), list(expected[key])))
        if not np.all(np.isfinite(array)):
            raise ImportError_("%s holds a non-finite value" % key)
    return tuple(a.astype(np.float32) for a in (w1, b1, w2, b2, w3, b3))


def format_number(x):
    return repr(float(x))


def policy_bytes(weights, range_clip, slope, name, epochs):
    w1, b1, w2, b2, w3, b3 = weights
    hidden, inputs = w1.shape
    payload = b"".join(np.asarray(a, dtype="<f4").flatten(order="F").tobytes() for a in weights)
    lines = [
        ("format", "barnbench-lflh-policy"),
        ("version", "3"),
        ("architecture", "%d-%d-%d-2" % (inputs, hidden, hidden)),
        ("activation", "leaky_relu " + format_number(slope)),
        ("input", POLICY_INPUT),
        ("beams", str(inputs - 2)),
        ("range_clip", format_number(range_clip)),
        ("goal", POLICY_GOAL),
        ("output", POLICY_OUTPUT),
        ("layout", POLICY_LAYOUT),
        ("payload_bytes", str(len(payload))),
        ("name", name),
        ("config_hash", "0x0"),
        ("plant_hash", "unknown"),  # trained on a real or Gazebo robot, not a barnbench plant
        ("trained", "unknown"),
        ("seed", "0"),
        ("epochs", str(epochs)),
        ("train_loss", "unknown"),
        ("validation_loss", "unknown"),
        ("mean_predictor_loss", "unknown"),
    ]
    header = "".join("%s: %s\n" % kv for kv in lines) + "end_header\n"
    return header.encode("ascii") + payload


def forward(weights, x, slope=0.01):
    """The network in numpy (float64), for checking: x is (..., inputs)."""
    w1, b1, w2, b2, w3, b3 = (np.asarray(a, dtype=np.float64) for a in weights)

    def act(z):
        return np.where(z > 0, z, slope * z)

    return act(act(x @ w1.T + b1) @ w2.T + b2) @ w3.T + b3


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("weights", help="your copy of the published state_dict, e.g. model_1000")
    parser.add_argument("--out", required=True, help="policy file to write, e.g. lflh_published_1m.policy")
    parser.add_argument("--name", default=None, help="the policy's name in its header (default: from --out)")
    parser.add_argument("--range-clip", type=float, default=2.0,
                        help="[m] input clip (the published deployment: 2.0, for both models)")
    parser.add_argument("--slope", type=float, default=0.01, help="leaky ReLU slope (the published network: 0.01)")
    parser.add_argument("--epochs", type=int, default=None, help="epochs trained (default: N of model_N, else 0)")
    args = parser.parse_args(argv)
    if not args.range_clip > 0:
        parser.error("--range-clip must be > 0")
    if not 0 < args.slope < 1:
        parser.error("--slope must be in (0, 1)")
    name = args.name or os.path.splitext(os.path.basename(args.out))[0] or "lflh_imported"
    if re.search(r"[\r\n]", name):
        parser.error("--name must be one line")
    epochs = args.epochs
    if epochs is None:
        m = re.fullmatch(r"model_(\d+)", os.path.basename(args.weights))
        epochs = int(m.group(1)) if m else 0
    try:
        weights = network(read_state_dict(args.weights))
    except (ImportError_, OSError) as e:
        print("import_lflh_weights: %s" % e, file=sys.stderr)
        return 2
    data = policy_bytes(weights, args.range_clip, args.slope, name, epochs)
    tmp = args.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, args.out)
    hidden, inputs = weights[0].shape
    print("wrote %s: %d-%d-%d-2, leaky_relu %s, %d beams clipped at %s m (%d bytes)"
          % (args.out, inputs, hidden, hidden, format_number(args.slope), inputs - 2,
             format_number(args.range_clip), len(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
