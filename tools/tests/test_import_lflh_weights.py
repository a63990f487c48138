"""tools/import_lflh_weights.py on tiny state_dicts this test writes in torch's legacy format.

The writer below lays a file out as torch.save(..., _use_new_zipfile_serialization=False) does:
the magic-number pickle, the protocol-version pickle, the sys-info pickle, the pickled dict whose
tensors refer to their storages by persistent id, the pickled list of storage keys, then per
storage an int64 element count and its raw little-endian data. torch itself is not needed: the
names a real file refers to (torch.FloatStorage, torch._utils._rebuild_tensor_v2) are stood in
for by stub modules while pickling.
"""

import collections
import importlib.util
import io
import os
import pickle
import struct
import subprocess
import sys
import types
import zipfile

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPT = os.path.join(ROOT, "tools", "import_lflh_weights.py")

spec = importlib.util.spec_from_file_location("import_lflh_weights", SCRIPT)
importer = importlib.util.module_from_spec(spec)
spec.loader.exec_module(importer)


def barn_binary():
    path = os.environ.get("BARN_BINARY", os.path.join(ROOT, "build", "barn"))
    if not os.path.exists(path):
        pytest.skip("no barn binary at %s (build it, or set BARN_BINARY)" % path)
    return path


# ---- A minimal writer of torch's legacy format ----

class _Storage:
    def __init__(self, key, values):
        self.key = key
        self.values = np.ascontiguousarray(values, dtype="<f4").ravel()


class _Tensor:
    def __init__(self, storage, offset, shape, stride):
        self.storage, self.offset, self.shape, self.stride = storage, offset, tuple(shape), tuple(stride)

    def __reduce_ex__(self, protocol):
        return (_STUBS["rebuild"], (self.storage, self.offset, self.shape, self.stride, False, collections.OrderedDict()))


_STUBS = {}


def _stub_modules(monkeypatch, extra_global=None):
    """torch and torch._utils as stubs holding just what a legacy state_dict names."""
    torch = types.ModuleType("torch")
    utils = types.ModuleType("torch._utils")

    class FloatStorage:
        pass

    FloatStorage.__module__ = "torch"
    FloatStorage.__qualname__ = FloatStorage.__name__ = "FloatStorage"

    def _rebuild_tensor_v2(*args):
        raise AssertionError("only pickled here")

    _rebuild_tensor_v2.__module__ = "torch._utils"
    _rebuild_tensor_v2.__qualname__ = _rebuild_tensor_v2.__name__ = "_rebuild_tensor_v2"
    torch.FloatStorage = FloatStorage
    torch._utils = utils
    utils._rebuild_tensor_v2 = _rebuild_tensor_v2
    monkeypatch.setitem(sys.modules, "torch", torch)
    monkeypatch.setitem(sys.modules, "torch._utils", utils)
    _STUBS["rebuild"] = extra_global or _rebuild_tensor_v2
    _STUBS["FloatStorage"] = FloatStorage


class _LegacyPickler(pickle.Pickler):
    def persistent_id(self, obj):
        if isinstance(obj, _Storage):
            return ("storage", _STUBS["FloatStorage"], obj.key, "cpu", obj.values.size, None)
        return None


def write_legacy(path, tensors, storages, monkeypatch, extra_global=None):
    """tensors: OrderedDict name -> _Tensor; storages: the _Storage objects, written in key order."""
    _stub_modules(monkeypatch, extra_global)
    out = io.BytesIO()
    pickle.dump(0x1950A86A20F9469CFC6C, out, protocol=2)
    pickle.dump(1001, out, protocol=2)
    pickle.dump({"protocol_version": 1001, "little_endian": True,
                 "type_sizes": {"short": 2, "int": 4, "long": 4}}, out, protocol=2)
    state = collections.OrderedDict(tensors)
    state._metadata = collections.OrderedDict([("", {"version": 1})])  # as a real state_dict has
    _LegacyPickler(out, protocol=2).dump(state)
    used = {t.storage.key for t in tensors.values()}  # torch writes the storages its tensors use
    keys = sorted(s.key for s in storages if s.key in used)
    pickle.dump(keys, out, protocol=2)
    by_key = {s.key: s for s in storages}
    for key in keys:
        out.write(struct.pack("<q", by_key[key].values.size))
        out.write(by_key[key].values.tobytes())
    for name in ("torch", "torch._utils"):
        monkeypatch.delitem(sys.modules, name)
    with open(path, "wb") as f:
        f.write(out.getvalue())


BEAMS, HIDDEN = 10, 4


def tiny_network(seed=1):
    rng = np.random.default_rng(seed)
    w1 = rng.normal(0, 0.5, (HIDDEN, BEAMS + 2)).astype(np.float32)
    b1 = rng.normal(0, 0.5, HIDDEN).astype(np.float32)
    w2 = rng.normal(0, 0.5, (HIDDEN, HIDDEN)).astype(np.float32)
    b2 = rng.normal(0, 0.5, HIDDEN).astype(np.float32)
    w3 = rng.normal(0, 0.5, (2, HIDDEN)).astype(np.float32)
    b3 = rng.normal(0, 0.5, 2).astype(np.float32)
    return w1, b1, w2, b2, w3, b3


def tiny_state_dict(weights):
    """The six tensors as a torch state_dict would store them, with the layouts a real file can
    have: contiguous weights, the two hidden biases sharing one storage at different offsets,
    and the output weight stored transposed (column-major strides)."""
    w1, b1, w2, b2, w3, b3 = weights
    s_w1 = _Storage("100", w1)
    s_bias = _Storage("101", np.concatenate([b1, b2]))
    s_w2 = _Storage("102", w2)
    s_w3 = _Storage("103", w3.T)  # memory holds w3 column by column
    s_b3 = _Storage("104", b3)
    tensors = collections.OrderedDict([
        ("fcs.0.weight", _Tensor(s_w1, 0, w1.shape, (w1.shape[1], 1))),
        ("fcs.0.bias", _Tensor(s_bias, 0, (HIDDEN,), (1,))),
        ("fcs.1.weight", _Tensor(s_w2, 0, w2.shape, (HIDDEN, 1))),
        ("fcs.1.bias", _Tensor(s_bias, HIDDEN, (HIDDEN,), (1,))),
        ("action_fc.weight", _Tensor(s_w3, 0, (2, HIDDEN), (1, 2))),
        ("action_fc.bias", _Tensor(s_b3, 0, (2,), (1,))),
    ])
    return tensors, [s_w1, s_bias, s_w2, s_w3, s_b3]


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


# ---- Tests ----

def test_reads_the_legacy_layout_back_exactly(tmp_path, monkeypatch):
    weights = tiny_network()
    path = tmp_path / "model_1000"
    write_legacy(str(path), *tiny_state_dict(weights), monkeypatch)
    state = importer.read_state_dict(str(path))
    assert list(state) == importer.KEYS
    for key, expected in zip(importer.KEYS, weights):
        np.testing.assert_array_equal(state[key], expected, err_msg=key)


def test_converted_policy_loads_in_barnbench_and_computes_the_numpy_forward_pass(tmp_path, monkeypatch):
    barn = barn_binary()
    weights = tiny_network()
    src = tmp_path / "model_1000"
    write_legacy(str(src), *tiny_state_dict(weights), monkeypatch)
    out = tmp_path / "tiny.policy"
    result = run_script(str(src), "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert "leaky_relu 0.01" in result.stdout

    header = out.read_bytes().split(b"end_header\n")[0].decode()
    assert "version: 3\n" in header
    assert "plant_hash: unknown\n" in header
    assert "activation: leaky_relu 0.01\n" in header
    assert "range_clip: 2.0\n" in header
    assert "beams: %d\n" % BEAMS in header
    assert "epochs: 1000\n" in header  # from the file name model_1000

    # Scans with ranges below, at and beyond the 2.0 m clip and no returns; two goal directions.
    rng = np.random.default_rng(7)
    scans = [rng.uniform(0.1, 3.5, BEAMS) for _ in range(4)]
    scans[1][::3] = np.inf
    lines = "\n".join(" ".join("inf" if np.isinf(r) else repr(float(r)) for r in scan) for scan in scans) + "\n"
    for goal in ((1.0, 0.0), (0.6, -0.8)):
        act = subprocess.run([barn, "lflh", "act", "--policy", str(out), "--goal", "%r,%r" % goal],
                             input=lines, capture_output=True, text=True)
        assert act.returncode == 0, act.stderr
        got = np.array([[float(v) for v in line.split()] for line in act.stdout.splitlines()])
        x = np.array([np.concatenate([np.clip(scan, 0.0, 2.0), goal]) for scan in scans])
        expected = importer.forward(weights, x, slope=0.01)
        assert got.shape == expected.shape
        np.testing.assert_allclose(got, expected, rtol=1e-5, atol=1e-6)
        # And not what relu would give: the leaky slope is in effect.
        relu = importer.forward(weights, x, slope=0.0)
        assert np.max(np.abs(relu - expected)) > 1e-4


def test_a_file_naming_anything_else_is_refused_not_run(tmp_path, monkeypatch):
    weights = tiny_network()
    tensors, storages = tiny_state_dict(weights)
    # A file whose tensors are rebuilt by os.system instead: refused before anything is called.
    write_legacy(str(tmp_path / "evil"), tensors, storages, monkeypatch, extra_global=os.system)
    result = run_script(str(tmp_path / "evil"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "names posix.system" in result.stderr or "names os.system" in result.stderr
    assert not (tmp_path / "x.policy").exists()


def test_wrong_shapes_and_missing_keys_are_named(tmp_path, monkeypatch):
    w1, b1, w2, b2, w3, b3 = tiny_network()
    tensors, storages = tiny_state_dict((w1, b1, w2, b2, w3, b3))
    del tensors["action_fc.bias"]
    write_legacy(str(tmp_path / "partial"), tensors, storages, monkeypatch)
    result = run_script(str(tmp_path / "partial"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "lacks action_fc.bias" in result.stderr

    tensors, storages = tiny_state_dict((w1, b1, w2, b2, w3, b3))
    tensors["fcs.1.weight"] = _Tensor(storages[2], 0, (2, 8), (8, 1))
    write_legacy(str(tmp_path / "shape"), tensors, storages, monkeypatch)
    result = run_script(str(tmp_path / "shape"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "fcs.1.weight has shape [2, 8]; expected [4, 4]" in result.stderr


def test_truncated_file_is_named(tmp_path, monkeypatch):
    path = tmp_path / "model_1000"
    write_legacy(str(path), *tiny_state_dict(tiny_network()), monkeypatch)
    path.write_bytes(path.read_bytes()[:-5])
    result = run_script(str(path), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "truncated: storage 104" in result.stderr


def test_zip_format_without_torch_says_how_to_get_it(tmp_path):
    if importlib.util.find_spec("torch") is not None:
        pytest.skip("torch is installed: the zip format is read with torch.load")
    path = tmp_path / "model_zip"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("archive/data.pkl", b"\x80\x02}q\x00.")
    result = run_script(str(path), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "zip format" in result.stderr
    assert "apt-get install python3-torch" in result.stderr
