"""The LiCS-KI policy network in PyTorch, for checking barnbench's C++ forward pass against torch.

Written for barnbench from the network's description (docs/systems/lics.md); the attribute
names follow the published state_dict's keys, so that its weights load into it with
load_state_dict(strict=True). Inference only (no dropout). Needs torch (Debian: apt-get install
python3-torch); used by tools/make_lics_test_data.py and tools/tests/test_import_lics_weights.py.
"""

import math

import torch
from torch import nn

# The published hyper-parameters (lics/scripts/run.py's config_dict).
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


class Attention(nn.Module):
    """Multi-head attention, no bias anywhere, scores scaled by 1/sqrt(model_dim)."""

    def __init__(self, d, heads):
        super().__init__()
        self.d, self.heads = d, heads
        self.scale = 1.0 / math.sqrt(d)  # the full width, not the head's: the published network's scaling
        self.q_proj = nn.Linear(d, d, bias=False)
        self.k_proj = nn.Linear(d, d, bias=False)
        self.v_proj = nn.Linear(d, d, bias=False)
        self.out_proj = nn.Linear(d, d, bias=False)

    def split(self, x):  # (batch, tokens, d) -> (batch, heads, tokens, d / heads)
        b, t, _ = x.shape
        return x.reshape(b, t, self.heads, self.d // self.heads).transpose(1, 2)

    def forward(self, queries, source):
        q = self.split(self.q_proj(queries))
        k = self.split(self.k_proj(source))
        v = self.split(self.v_proj(source))
        weights = torch.softmax(q @ k.transpose(-1, -2) * self.scale, dim=-1)
        mixed = (weights @ v).transpose(1, 2)
        return self.out_proj(mixed.reshape(queries.shape[0], queries.shape[1], self.d))


class FeedForward(nn.Module):
    """x + w_2(relu(w_1(x))): the residual is inside."""

    def __init__(self, d, ffn):
        super().__init__()
        self.w_1 = nn.Linear(d, ffn)
        self.w_2 = nn.Linear(ffn, d)

    def forward(self, x):
        return x + self.w_2(torch.relu(self.w_1(x)))


class EncoderBlock(nn.Module):
    def __init__(self, arch):
        super().__init__()
        d, eps = arch["model_dim"], arch["layer_norm_eps"]
        self.self_attn = Attention(d, arch["heads"])
        self.self_attn_layer_norm = nn.LayerNorm(d, eps=eps)
        self.PositionWiseFeedForward = FeedForward(d, arch["ffn_dim"])
        self.final_layer_norm = nn.LayerNorm(d, eps=eps)

    def forward(self, x):
        x = self.self_attn_layer_norm(x + self.self_attn(x, x))
        return self.final_layer_norm(self.PositionWiseFeedForward(x))


class DecoderBlock(nn.Module):
    def __init__(self, arch):
        super().__init__()
        d, eps = arch["model_dim"], arch["layer_norm_eps"]
        # In the published state_dict but never used by its forward pass (no self-attention).
        self.self_attn_layer_norm = nn.LayerNorm(d, eps=eps)
        self.encoder_attn = Attention(d, arch["heads"])
        self.encoder_attn_layer_norm = nn.LayerNorm(d, eps=eps)
        self.PositionWiseFeedForward = FeedForward(d, arch["ffn_dim"])
        self.final_layer_norm = nn.LayerNorm(d, eps=eps)

    def forward(self, tokens, encoded):
        tokens = self.encoder_attn_layer_norm(tokens + self.encoder_attn(tokens, encoded))
        return self.final_layer_norm(self.PositionWiseFeedForward(tokens))


class Embedding(nn.Module):
    def __init__(self, arch):
        super().__init__()
        self.patches = arch["patches"]
        self.pos_embed = nn.Parameter(torch.zeros(arch["patches"], arch["model_dim"]))
        self.linear = nn.Linear(arch["beams"] // arch["patches"], arch["model_dim"])

    def forward(self, ranges):  # (batch, beams) -> (batch, patches, d)
        return self.linear(ranges.reshape(ranges.shape[0], self.patches, -1)) + self.pos_embed


class Encoder(nn.Module):
    def __init__(self, arch):
        super().__init__()
        self.embedding = Embedding(arch)
        self.layers = nn.ModuleList(EncoderBlock(arch) for _ in range(arch["encoder_layers"]))

    def forward(self, ranges):
        x = self.embedding(ranges)
        for block in self.layers:
            x = block(x)
        return x


class Decoder(nn.Module):
    def __init__(self, arch):
        super().__init__()
        self.linear = nn.Linear(1, arch["model_dim"])  # both goal components, one token each
        self.layers = nn.ModuleList(DecoderBlock(arch) for _ in range(arch["decoder_layers"]))

    def forward(self, goal, encoded):  # goal (batch, 2)
        tokens = self.linear(goal.unsqueeze(-1))
        for block in self.layers:
            tokens = block(tokens, encoded)
        return tokens


class LicsTransformer(nn.Module):
    """forward(ranges (batch, beams) clipped, goal (batch, 2)) -> (batch, 2): (v_hat, w_hat)."""

    def __init__(self, arch=None):
        super().__init__()
        arch = dict(PUBLISHED if arch is None else arch)
        self.arch = arch
        self.encoder = Encoder(arch)
        self.decoder = Decoder(arch)
        self.prediction_head = nn.Linear(2 * arch["model_dim"], 2)

    def forward(self, ranges, goal):
        tokens = self.decoder(goal, self.encoder(ranges))
        return self.prediction_head(tokens.reshape(tokens.shape[0], -1))
