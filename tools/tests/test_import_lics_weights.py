"""tools/import_lics_weights.py: the file it writes, the state_dicts it refuses, and barnbench's
forward pass on what it imports against torch's.

The format tests need numpy only. The tests through the importer's command line need torch
(they write .pth files; Debian: apt-get install python3-torch) and build/barn (or BARN_BINARY);
they skip, saying which, without them. The test of the published network needs your own copy:
BARN_LICS_WEIGHTS=/path/to/transformer_99.pth.
"""

import importlib.util
import os
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TOOLS = os.path.join(ROOT, "tools")
SCRIPT = os.path.join(TOOLS, "import_lics_weights.py")

spec = importlib.util.spec_from_file_location("import_lics_weights", SCRIPT)
importer = importlib.util.module_from_spec(spec)
spec.loader.exec_module(importer)

TINY = {"beams": 8, "patches": 2, "model_dim": 4, "heads": 2, "ffn_dim": 3, "encoder_layers": 1,
        "decoder_layers": 2, "layer_norm_eps": 1e-5}


def barn_binary():
    path = os.environ.get("BARN_BINARY", os.path.join(ROOT, "build", "barn"))
    if not os.path.exists(path):
        pytest.skip("no barn binary at %s (build it, or set BARN_BINARY)" % path)
    return path


def need_torch():
    if importlib.util.find_spec("torch") is None:
        pytest.skip("torch is not installed (Debian: apt-get install python3-torch)")
    import torch  # noqa: PLC0415
    sys.path.insert(0, TOOLS)
    from lics_torch_model import LicsTransformer  # noqa: PLC0415
    return torch, LicsTransformer


def random_state(arch, seed=1):
    """A state_dict of `arch` as numpy float32 arrays, the unused tensors included."""
    rng = np.random.default_rng(seed)
    keys = importer.file_tensors(arch) + importer.unused_tensors(arch)
    return {key: rng.normal(0, 0.5, shape).astype(np.float32) for key, shape in keys}


def decode(data):
    """(header dict, payload bytes) of a policy file."""
    head, payload = data.split(b"end_header\n", 1)
    header = dict(line.split(": ", 1) for line in head.decode().splitlines())
    return header, payload


def act(barn, policy, scans, goal):
    """barn policy act's (v_hat, w_hat) for each scan."""
    lines = "\n".join(" ".join("inf" if np.isinf(r) else repr(float(r)) for r in scan) for scan in scans) + "\n"
    result = subprocess.run([barn, "policy", "act", "--policy", str(policy), "--goal", "%r,%r" % goal],
                            input=lines, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return np.array([[float(v) for v in line.split()] for line in result.stdout.splitlines()])


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


# ---- The format (numpy only) ----

def test_numbers_are_written_as_barnbench_writes_them():
    # std::to_chars's shortest form (core::formatDouble): fixed or scientific, the shorter.
    cases = {5.0: "5", 1e-5: "1e-05", 1e-4: "1e-04", 0.001: "0.001", 2.5: "2.5", 100.0: "100",
             1e15: "1e+15", 123456.0: "123456", -3.0: "-3", 0.0: "0", 1.5e-7: "1.5e-07"}
    for value, text in cases.items():
        assert importer.format_number(value) == text, value


def test_fnv1a64_is_the_reference_hash():
    # FNV-1a 64: the offset basis for no bytes; "a" from the algorithm's published test vectors.
    assert importer.fnv1a64(b"") == 0xCBF29CE484222325
    assert importer.fnv1a64(b"a") == 0xAF63DC4C8601EC8C


def test_the_file_holds_every_used_tensor_column_major_in_order():
    state = random_state(TINY)
    tensors = importer.checked_tensors(state, TINY)
    data = importer.policy_bytes(tensors, TINY, 5.0, "tiny", "test")
    header, payload = decode(data)
    assert header["format"] == "barnbench-transformer-policy"
    assert (header["beams"], header["patches"], header["model_dim"], header["heads"]) == ("8", "2", "4", "2")
    assert (header["encoder_layers"], header["decoder_layers"], header["layer_norm_eps"]) == ("1", "2", "1e-05")
    assert header["range_clip"] == "5"
    assert header["weights_fnv1a64"] == "0x%x" % importer.fnv1a64(payload)
    # embedding 4 x 4 + 4 + 2 x 4 = 28; 3 blocks of 4 x 16 + 2 x 8 + 3 x 4 + 3 + 4 x 3 + 4 = 111;
    # goal 8; head 2 x 8 + 2 = 18: 28 + 333 + 8 + 18 = 387 floats. The unused decoder norms
    # (2 blocks x 2 x 4) are left out.
    assert int(header["payload_bytes"]) == len(payload) == 4 * 387
    floats = np.frombuffer(payload, dtype="<f4")
    offset = 0
    for key, shape in importer.file_tensors(TINY):
        n = int(np.prod(shape))
        np.testing.assert_array_equal(floats[offset:offset + n].reshape(shape, order="F"), state[key], err_msg=key)
        offset += n
    assert offset == floats.size
    # The same input gives the same bytes.
    assert importer.policy_bytes(importer.checked_tensors(state, TINY), TINY, 5.0, "tiny", "test") == data


def test_a_state_dict_of_another_network_is_refused_naming_the_key():
    state = random_state(TINY)
    del state["decoder.layers.1.final_layer_norm.bias"]
    with pytest.raises(importer.ImportError_, match="lacks decoder.layers.1.final_layer_norm.bias"):
        importer.checked_tensors(state, TINY)

    state = random_state(TINY)
    state["decoder.layers.0.self_attn.q_proj.weight"] = np.zeros((4, 4), np.float32)  # a decoder self-attention
    with pytest.raises(importer.ImportError_, match="has keys .* does not: decoder.layers.0.self_attn.q_proj.weight"):
        importer.checked_tensors(state, TINY)

    state = random_state(TINY)
    state["encoder.embedding.pos_embed"] = state["encoder.embedding.pos_embed"].T.copy()
    with pytest.raises(importer.ImportError_, match=r"encoder.embedding.pos_embed has shape \[4, 2\]; expected \[2, 4\]"):
        importer.checked_tensors(state, TINY)

    state = random_state(TINY)
    state["prediction_head.bias"] = state["prediction_head.bias"].astype(np.float64)
    with pytest.raises(importer.ImportError_, match="prediction_head.bias is float64; expected float32"):
        importer.checked_tensors(state, TINY)

    state = random_state(TINY)
    state["decoder.linear.bias"][1] = np.nan
    with pytest.raises(importer.ImportError_, match="decoder.linear.bias holds a non-finite value"):
        importer.checked_tensors(state, TINY)


# ---- Through the command line (torch, and build/barn) ----

def save(torch, state, path):
    torch.save({k: torch.from_numpy(np.ascontiguousarray(v)) for k, v in state.items()}, str(path))


def test_an_imported_network_runs_in_barnbench_as_in_torch(tmp_path):
    torch, LicsTransformer = need_torch()
    barn = barn_binary()
    torch.manual_seed(3)
    model = LicsTransformer().eval()  # the published shape, torch's initialisation
    with torch.no_grad():
        for name, p in model.named_parameters():
            if name.endswith("pos_embed") or "layer_norm" in name:
                p.add_(0.3 * torch.randn_like(p))
    torch.save(model.state_dict(), str(tmp_path / "transformer_3.pth"))
    out = tmp_path / "random.policy"
    result = run_script(str(tmp_path / "transformer_3.pth"), "--out", str(out))
    assert result.returncode == 0, result.stderr
    header, _ = decode(out.read_bytes())
    assert (header["name"], header["source"]) == ("random", "transformer_3.pth")

    rng = np.random.default_rng(5)
    scans = rng.uniform(0.1, 7.0, (4, 720))
    scans[0, ::4] = np.inf
    for goal in ((1.0, 0.0), (0.6, -0.8)):
        got = act(barn, out, scans, goal)
        with torch.no_grad():
            expected = model(torch.from_numpy(np.clip(scans, 0, 5).astype(np.float32)),
                             torch.tensor([goal] * len(scans), dtype=torch.float32)).numpy()
        assert np.max(np.abs(got - expected)) < 1e-5


def test_the_command_refuses_another_state_dict_with_exit_two(tmp_path):
    torch, _ = need_torch()
    state = random_state(importer.PUBLISHED)
    renamed = dict(state)
    renamed["encoder.embedding.pos_embedding"] = renamed.pop("encoder.embedding.pos_embed")
    save(torch, renamed, tmp_path / "renamed.pth")
    result = run_script(str(tmp_path / "renamed.pth"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "lacks encoder.embedding.pos_embed" in result.stderr
    assert not (tmp_path / "x.policy").exists()

    wider = dict(state)
    wider["encoder.layers.1.PositionWiseFeedForward.w_1.weight"] = np.zeros((512, 32), np.float32)
    save(torch, wider, tmp_path / "wider.pth")
    result = run_script(str(tmp_path / "wider.pth"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "encoder.layers.1.PositionWiseFeedForward.w_1.weight has shape [512, 32]; expected [256, 32]" in result.stderr

    (tmp_path / "garbage.pth").write_bytes(b"not a torch file")
    result = run_script(str(tmp_path / "garbage.pth"), "--out", str(tmp_path / "x.policy"))
    assert result.returncode == 2
    assert "torch cannot read it" in result.stderr


def test_the_published_network_runs_in_barnbench_as_in_torch(tmp_path):
    path = os.environ.get("BARN_LICS_WEIGHTS")
    if not path or not os.path.exists(path):
        pytest.skip("set BARN_LICS_WEIGHTS to your copy of the published transformer_99.pth to check it")
    torch, LicsTransformer = need_torch()
    barn = barn_binary()
    out = tmp_path / "lics_transformer_99.policy"
    result = run_script(path, "--out", str(out))
    assert result.returncode == 0, result.stderr
    model = LicsTransformer().eval()
    model.load_state_dict(torch.load(path, map_location="cpu", weights_only=True), strict=True)

    # Clutter, open space, a corridor, ranges past the 5 m clip; goals ahead, aside and behind.
    rng = np.random.default_rng(11)
    scans = [rng.uniform(0.2, 6.0, 720), np.full(720, np.inf), rng.uniform(0.0, 1.5, 720), rng.uniform(2.0, 9.0, 720)]
    corridor = np.where(np.abs(np.arange(720) - 360) < 90, 4.5, 0.7)
    scans.append(corridor)
    scans = np.array(scans)
    scans[0, ::5] = np.inf
    worst = 0.0
    for goal in ((1.0, 0.0), (0.0, 1.0), (0.6, -0.8), (-1.0, 0.0), (0.0, 0.0)):
        got = act(barn, out, scans, goal)
        with torch.no_grad():
            expected = model(torch.from_numpy(np.clip(scans, 0, 5).astype(np.float32)),
                             torch.tensor([goal] * len(scans), dtype=torch.float32)).numpy()
        worst = max(worst, float(np.max(np.abs(got - expected))))
    print("published network: max |barnbench - torch| = %.3g over %d cases" % (worst, 5 * len(scans)))
    assert worst < 1e-5
