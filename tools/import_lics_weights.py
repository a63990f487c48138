#!/usr/bin/env python3
"""Converts your own copy of the published LiCS-KI network into a barnbench transformer policy file.

    /usr/bin/python3 tools/import_lics_weights.py transformer_99.pth --out lics_transformer_99.policy

The published network (damanikjosh/the-barn-challenge, lics/models/transformer_99.pth, MIT
licence) is a PyTorch state_dict in torch's zip format: a transformer of 720 LiDAR ranges in
36 patches of 20, width 32, 4 heads, feed-forward 256, 3 encoder and 3 decoder blocks
(docs/systems/lics.md has every tensor). The state_dict must have exactly the published keys
and shapes; anything else is refused (exit 2) naming the key. The decoder blocks'
self_attn_layer_norm tensors, which the network's forward pass never uses, are checked and
left out of the file.

Reading needs PyTorch (Debian: apt-get install python3-torch); torch.load reads with
weights_only=True, so nothing in the file but tensors is run.

Writing: barnbench's transformer policy format, version 1 (docs/systems/lics.md): a text
header with the hyper-parameters and the FNV-1a 64 digest of the weights, then the tensors as
float32 little-endian, each column-major in its PyTorch shape, in the documented order. The same
input gives the same bytes.

barnbench does not ship the weights: convert your own copy for your own use; never commit it
or the converted file to this repository.
"""

import argparse
import decimal
import os
import re
import sys

try:
    import numpy as np
except ImportError:  # an interpreter without numpy (Debian's /usr/bin/python3 has it with python3-numpy)
    sys.exit("import_lics_weights: needs numpy: run it with /usr/bin/python3 (apt-get install python3-numpy)")

# The published hyper-parameters (lics/scripts/run.py's config_dict) and input clip
# (lics/config/config.yaml, laser_clip).
PUBLISHED = {
    "beams": 720,
    "patches": 36,
    "model_dim": 32,
    "heads": 4,
    "ffn_dim": 256,
    "encoder_layers": 3,
    "decoder_layers": 3,
    "layer_norm_eps": 1e-5,
}
PUBLISHED_RANGE_CLIP = 5.0

# The fixed texts of the header (src/learning/transformer_policy.cpp); a reader refuses others.
FORMAT = "barnbench-transformer-policy"
VERSION = 1
FIXED = [
    ("input", "ranges[beams] clipped to [0, range_clip] (+inf -> range_clip), "
              "beams / patches consecutive beams per patch; goal_x, goal_y"),
    ("goal", "local goal in the robot frame, x forward, y left, as given; one token per component"),
    ("output", "v_hat, w_hat before the controller's scaling"),
    ("attention", "no bias; scores q.k / sqrt(model_dim); decoder: cross-attention to the encoder only"),
    ("block", "post-norm: x = norm1(x + attention); x = norm2(x + w2 relu(w1 x + b1) + b2)"),
    ("layout", "float32 little-endian; tensors in the documented order, named as the published state_dict; "
               "matrices column-major"),
]
SHAPE_KEYS = ["beams", "patches", "model_dim", "heads", "ffn_dim", "encoder_layers", "decoder_layers"]

TORCH_HINT = "install PyTorch to read it (Debian: apt-get install python3-torch)"


class ImportError_(Exception):
    """A file this script cannot convert; the message says why."""


def check_arch(arch):
    """The bounds the C++ reader enforces (TransformerShape::problem)."""
    a = arch
    ok = (1 <= a["beams"] <= 100000 and 1 <= a["patches"] <= a["beams"] and a["beams"] % a["patches"] == 0
          and 1 <= a["model_dim"] <= 4096 and 1 <= a["heads"] <= a["model_dim"] and a["model_dim"] % a["heads"] == 0
          and 1 <= a["ffn_dim"] <= 65536 and 0 <= a["encoder_layers"] <= 64 and 0 <= a["decoder_layers"] <= 64
          and a["layer_norm_eps"] > 0)
    if not ok:
        raise ImportError_("hyper-parameters %r are outside what barnbench reads" % (arch,))


def _block(prefix, attention, norm1, d, ffn):
    return [
        (prefix + attention + ".q_proj.weight", (d, d)),
        (prefix + attention + ".k_proj.weight", (d, d)),
        (prefix + attention + ".v_proj.weight", (d, d)),
        (prefix + attention + ".out_proj.weight", (d, d)),
        (prefix + norm1 + ".weight", (d,)),
        (prefix + norm1 + ".bias", (d,)),
        (prefix + "PositionWiseFeedForward.w_1.weight", (ffn, d)),
        (prefix + "PositionWiseFeedForward.w_1.bias", (ffn,)),
        (prefix + "PositionWiseFeedForward.w_2.weight", (d, ffn)),
        (prefix + "PositionWiseFeedForward.w_2.bias", (d,)),
        (prefix + "final_layer_norm.weight", (d,)),
        (prefix + "final_layer_norm.bias", (d,)),
    ]


def file_tensors(arch):
    """[(state_dict key, shape)] of the tensors barnbench's file holds, in its order."""
    d, ffn = arch["model_dim"], arch["ffn_dim"]
    tensors = [
        ("encoder.embedding.linear.weight", (d, arch["beams"] // arch["patches"])),
        ("encoder.embedding.linear.bias", (d,)),
        ("encoder.embedding.pos_embed", (arch["patches"], d)),
    ]
    for layer in range(arch["encoder_layers"]):
        tensors += _block("encoder.layers.%d." % layer, "self_attn", "self_attn_layer_norm", d, ffn)
    tensors += [("decoder.linear.weight", (d, 1)), ("decoder.linear.bias", (d,))]
    for layer in range(arch["decoder_layers"]):
        tensors += _block("decoder.layers.%d." % layer, "encoder_attn", "encoder_attn_layer_norm", d, ffn)
    tensors += [("prediction_head.weight", (2, 2 * d)), ("prediction_head.bias", (2,))]
    return tensors


def unused_tensors(arch):
    """[(key, shape)] in the state_dict that the forward pass never reads (left out of the file)."""
    d = arch["model_dim"]
    return [("decoder.layers.%d.self_attn_layer_norm.%s" % (layer, part), (d,))
            for layer in range(arch["decoder_layers"]) for part in ("weight", "bias")]


def checked_tensors(state, arch):
    """The file's tensors as float32 arrays in file order, after checking `state` (a mapping of
    key -> array) has exactly the keys and shapes of `arch` and finite values."""
    expected = dict(file_tensors(arch) + unused_tensors(arch))
    missing = [k for k in expected if k not in state]
    extra = [k for k in state if k not in expected]
    if missing:
        raise ImportError_("the state_dict lacks %s: not the LiCS-KI network of %s"
                           % (", ".join(missing), _arch_text(arch)))
    if extra:
        raise ImportError_("the state_dict has keys the LiCS-KI network of %s does not: %s"
                           % (_arch_text(arch), ", ".join(extra)))
    arrays = {}
    for key, shape in expected.items():
        array = np.asarray(state[key])
        if tuple(array.shape) != shape:
            raise ImportError_("%s has shape %s; expected %s (the LiCS-KI network of %s)"
                               % (key, list(array.shape), list(shape), _arch_text(arch)))
        if array.dtype != np.float32:
            raise ImportError_("%s is %s; expected float32" % (key, array.dtype))
        if not np.all(np.isfinite(array)):
            raise ImportError_("%s holds a non-finite value" % key)
        arrays[key] = array
    return [(key, arrays[key]) for key, _ in file_tensors(arch)]


def _arch_text(arch):
    return ", ".join("%s %s" % (k, format_number(arch[k]) if k == "layer_norm_eps" else arch[k]) for k in PUBLISHED)


def format_number(x):
    """The shortest text that reads back as x, as std::to_chars writes a double (core::formatDouble):
    fixed or scientific, whichever is shorter (fixed on a tie); an exponent of at least two digits."""
    x = float(x)
    if x == 0:
        return "-0" if str(x).startswith("-") else "0"
    sign, digits, exponent = decimal.Decimal(repr(x)).normalize().as_tuple()
    text = "".join(str(digit) for digit in digits)
    n = len(text)
    e = exponent + n - 1  # of the first digit
    if exponent >= 0:
        fixed = text + "0" * exponent
    elif e >= 0:
        fixed = text[:e + 1] + "." + text[e + 1:]
    else:
        fixed = "0." + "0" * (-e - 1) + text
    scientific = text[0] + ("." + text[1:] if n > 1 else "") + "e%s%02d" % ("-" if e < 0 else "+", abs(e))
    return ("-" if sign else "") + (fixed if len(fixed) <= len(scientific) else scientific)


def fnv1a64(data):
    """64-bit FNV-1a of bytes (core::fnv1a64)."""
    h = 0xCBF29CE484222325
    for byte in data:
        h = ((h ^ byte) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def policy_bytes(tensors, arch, range_clip, name, source):
    """The file: header and payload. `tensors` as checked_tensors returns them."""
    check_arch(arch)
    if not range_clip > 0:
        raise ImportError_("range_clip must be > 0")
    for field, text in (("name", name), ("source", source)):
        if re.search(r"[\r\n]", text):
            raise ImportError_("%s must be one line" % field)
    payload = b"".join(np.asarray(array, dtype="<f4").flatten(order="F").tobytes() for _, array in tensors)
    lines = [("format", FORMAT), ("version", str(VERSION))]
    lines += [(key, str(int(arch[key]))) for key in SHAPE_KEYS]
    lines += [("layer_norm_eps", format_number(arch["layer_norm_eps"])), ("range_clip", format_number(range_clip))]
    lines += FIXED
    lines += [("payload_bytes", str(len(payload))), ("weights_fnv1a64", "0x%x" % fnv1a64(payload)),
              ("name", name), ("source", source)]
    header = "".join("%s: %s\n" % kv for kv in lines) + "end_header\n"
    return header.encode("utf-8") + payload


def read_state_dict(path):
    """The state_dict in `path` (torch.save) as {key: numpy array}."""
    try:
        import torch  # noqa: PLC0415 - needed only here
    except ImportError:
        raise ImportError_("%s: reading a PyTorch file needs torch: %s" % (path, TORCH_HINT)) from None
    try:
        state = torch.load(path, map_location="cpu", weights_only=True)
    except (OSError, IsADirectoryError):
        raise
    except Exception as e:  # noqa: BLE001 - torch raises many kinds for a file it cannot read
        raise ImportError_("%s: torch cannot read it as a state_dict: %s" % (path, str(e).splitlines()[0] if str(e) else e)) \
            from None
    return state_dict_arrays(state, path, ImportError_)


def state_dict_arrays(state, path, error):
    """A loaded state_dict's tensors as numpy arrays by key; `error` (naming `path`) if `state`
    is not a dict of tensors. Shared by the weight importers."""
    if not isinstance(state, dict):
        raise error("%s holds a %s, not a state_dict" % (path, type(state).__name__))
    arrays = {}
    for key, value in state.items():
        if not hasattr(value, "detach"):
            raise error("%s: %s is not a tensor" % (path, key))
        arrays[str(key)] = value.detach().cpu().numpy()
    return arrays


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("weights", help="your copy of the published state_dict, e.g. transformer_99.pth")
    parser.add_argument("--out", required=True, help="policy file to write, e.g. lics_transformer_99.policy")
    parser.add_argument("--name", default=None, help="the policy's name in its header (default: from --out)")
    parser.add_argument("--source", default=None,
                        help="where the weights came from, one line (default: the input file's name)")
    parser.add_argument("--range-clip", type=float, default=PUBLISHED_RANGE_CLIP,
                        help="[m] input clip (the published laser_clip: 5.0)")
    args = parser.parse_args(argv)
    if not args.range_clip > 0:
        parser.error("--range-clip must be > 0")
    name = args.name or os.path.splitext(os.path.basename(args.out))[0] or "lics_imported"
    source = args.source if args.source is not None else os.path.basename(args.weights)
    try:
        tensors = checked_tensors(read_state_dict(args.weights), PUBLISHED)
        data = policy_bytes(tensors, PUBLISHED, args.range_clip, name, source)
    except (ImportError_, OSError) as e:
        print("import_lics_weights: %s" % e, file=sys.stderr)
        return 2
    tmp = args.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, args.out)
    print("wrote %s: the LiCS-KI transformer (%s), ranges clipped at %s m, %d bytes"
          % (args.out, _arch_text(PUBLISHED), format_number(args.range_clip), len(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
