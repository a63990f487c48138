#!/usr/bin/env python3
"""Trains BARN's End-to-End baseline (TD3) on barnbench.VecEnv and exports the actor.

    PYTHONPATH=build/python nice /usr/bin/python3 tools/train_e2e.py \\
        --config configs/policies/e2e_train.yaml --out results/e2e_train [--hours 3]

`--out` gets checkpoint/ (the networks, optimisers, replay buffer and counters: run the same
command again to go on from it), curve.csv (one row per iteration), e2e.policy (the actor in
barnbench's MLP policy format, rewritten at every checkpoint) and the config. `--hours` (or
`--max-steps`) stops after the first checkpoint past that much wall time (or that many
environment steps); without them the config's training.max_steps (4 M) is the end.

The method (docs/rl.md): the ros_jackal `e2e` specification. The observation of a step is four
stacked frames of the e2e controller's encoding (barnbench._core.e2e_frames, the C++ code the
controller runs); TD3 with the published hyper-parameters, n-step returns, an update-to-data
ratio of 1024 updates per 4096 steps. Needs Debian's python3-torch (CPU): a tool, never a
dependency of barnbench. Debian's torch multiplies matrices with the reference BLAS unless an
optimised one is installed (`apt-get install libopenblas0-serial`, about 20 times faster here).
"""

import argparse
import collections
import copy
import datetime
import json
import math
import os
import sys
import time

import numpy as np

try:
    import torch
    import torch.nn as nn
    import torch.nn.functional as F
except ImportError:  # pragma: no cover - depends on the machine
    sys.exit("train_e2e.py needs PyTorch: apt-get install python3-torch (Debian's, CPU)")
import yaml

import barnbench
from barnbench import _core

CURVE_COLUMNS = ["iteration", "steps", "episodes", "wall_s", "return", "success", "collision", "timeout", "length",
                 "critic_loss", "actor_loss", "q", "exploration_noise"]


def load_config(path):
    with open(path) as f:
        config = yaml.safe_load(f)
    for section in ("env", "encoding", "network", "td3", "training"):
        if not isinstance(config.get(section), dict):
            raise barnbench.InputError(f"{path}: section '{section}' missing")
    return config


def training_worlds(env_config):
    """The world ids: env.worlds minus env.exclude_worlds (specs as barn run's --worlds)."""
    world_dir = env_config.get("world_dir") or os.path.join(_core.SOURCE_DIR, "worlds")
    ids, _ = _core.select_worlds(str(env_config["worlds"]), world_dir)
    excluded = set()
    if env_config.get("exclude_worlds"):
        excluded, _ = _core.select_worlds(str(env_config["exclude_worlds"]), world_dir)
    ids = [w for w in ids if w not in set(excluded)]
    if not ids:
        raise barnbench.InputError("env.worlds: no world left after exclude_worlds")
    return ids, world_dir


# ---------------------------------------------------------------------------------------------
# Networks (td3/net.py, td3/rl.py: an MLP encoder of the flattened stack, an MLP head, a linear
# output; the actor squashes with tanh, the critic is twin Q)


def mlp(inputs, layers, hidden):
    modules = []
    for k in range(layers):
        modules += [nn.Linear(inputs if k == 0 else hidden, hidden), nn.ReLU()]
    return nn.Sequential(*modules)


class Actor(nn.Module):
    def __init__(self, inputs, net):
        super().__init__()
        self.encoder = mlp(inputs, net["encoder_layers"], net["hidden"])
        self.head = mlp(net["hidden"], net["head_layers"], net["hidden"])
        self.out = nn.Linear(net["hidden"], 2)

    def forward(self, state):
        return torch.tanh(self.out(self.head(self.encoder(state))))

    def linear_layers(self):
        return [m for m in self.modules() if isinstance(m, nn.Linear)]


class Critic(nn.Module):
    def __init__(self, inputs, net):
        super().__init__()
        hidden = net["hidden"]
        self.encoders = nn.ModuleList([mlp(inputs, net["encoder_layers"], hidden) for _ in range(2)])
        self.heads = nn.ModuleList([mlp(hidden + 2, net["head_layers"], hidden) for _ in range(2)])
        self.outs = nn.ModuleList([nn.Linear(hidden, 1) for _ in range(2)])

    def q(self, k, state, action):
        return self.outs[k](self.heads[k](torch.cat([self.encoders[k](state), action], 1)))

    def forward(self, state, action):
        return self.q(0, state, action), self.q(1, state, action)


# ---------------------------------------------------------------------------------------------
# Replay: frames stored once (a ring), transitions hold the frame ids of their stacks


class Replay:
    """n-step transitions (state stack, action in [-1, 1], discounted reward, next stack,
    not_done, discount) over a ring of frames. Each sub-environment's last n steps wait in
    `pending` until their n-step return is known (or the episode ends)."""

    def __init__(self, capacity, frames, frame_size, num_envs, n_step, gamma):
        self.capacity = capacity
        self.frame_capacity = 2 * capacity + 64 * num_envs * frames
        self.frames = np.zeros((self.frame_capacity, frame_size), dtype=np.float32)  # lazily paged
        self.next_frame = 0
        self.frames_written = 0
        self.state = np.zeros((capacity, frames), dtype=np.int64)
        self.next_state = np.zeros((capacity, frames), dtype=np.int64)
        self.action = np.zeros((capacity, 2), dtype=np.float32)
        self.reward = np.zeros(capacity, dtype=np.float32)
        self.not_done = np.zeros(capacity, dtype=np.float32)
        self.discount = np.zeros(capacity, dtype=np.float32)
        self.size = 0
        self.pointer = 0
        self.added = 0
        self.n_step = n_step
        self.gamma = gamma
        self.pending = [collections.deque() for _ in range(num_envs)]

    def add_frames(self, rows):
        """Stores frames (k x frame_size); returns their ids."""
        ids = (self.next_frame + np.arange(len(rows))) % self.frame_capacity
        self.frames[ids] = rows
        self.next_frame = int((self.next_frame + len(rows)) % self.frame_capacity)
        self.frames_written += len(rows)
        return ids

    def _emit(self, state, action, rewards, next_state, not_done):
        ret = 0.0
        for k, r in enumerate(rewards):
            ret += (self.gamma ** k) * r
        i = self.pointer
        self.state[i] = state
        self.action[i] = action
        self.reward[i] = ret
        self.next_state[i] = next_state
        self.not_done[i] = not_done
        self.discount[i] = self.gamma ** len(rewards)
        self.pointer = (i + 1) % self.capacity
        self.size = min(self.size + 1, self.capacity)
        self.added += 1

    def step(self, env, state, action, reward, next_state, end, bootstrap):
        """One step of sub-environment `env`; `end` when its episode ended (then `bootstrap`
        says whether the target bootstraps from next_state, i.e. a truncation treated so)."""
        pending = self.pending[env]
        pending.append((state, action, reward))
        if end:
            while pending:
                rewards = [p[2] for p in pending]
                self._emit(pending[0][0], pending[0][1], rewards, next_state, 1.0 if bootstrap else 0.0)
                pending.popleft()
        elif len(pending) == self.n_step:
            self._emit(pending[0][0], pending[0][1], [p[2] for p in pending], next_state, 1.0)
            pending.popleft()

    def sample(self, rng, batch):
        idx = rng.integers(0, self.size, size=batch)
        state = self.frames[self.state[idx]].reshape(batch, -1)
        next_state = self.frames[self.next_state[idx]].reshape(batch, -1)
        return (torch.from_numpy(state), torch.from_numpy(self.action[idx]), torch.from_numpy(self.reward[idx, None]),
                torch.from_numpy(next_state), torch.from_numpy(self.not_done[idx, None]),
                torch.from_numpy(self.discount[idx, None]))

    def state_dict(self):
        used = self.frame_capacity if self.frames_written >= self.frame_capacity else self.next_frame
        return {"frames": self.frames[:used], "state": self.state, "next_state": self.next_state, "action": self.action,
                "reward": self.reward, "not_done": self.not_done, "discount": self.discount,
                "counters": np.array([self.next_frame, self.size, self.pointer, self.added, self.frames_written])}

    def load_state_dict(self, d):
        self.frames[:len(d["frames"])] = d["frames"]
        for key in ("state", "next_state", "action", "reward", "not_done", "discount"):
            getattr(self, key)[...] = d[key]
        self.next_frame, self.size, self.pointer, self.added, self.frames_written = (int(x) for x in d["counters"])


# ---------------------------------------------------------------------------------------------


class Trainer:
    def __init__(self, config, out):
        self.config = config
        self.out = out
        env, enc, td3, net = config["env"], config["encoding"], config["td3"], config["network"]
        self.encoding = {k: enc[k] for k in ("frames", "range_clip", "goal_scale", "min_v", "max_v", "min_w", "max_w")}
        self.worlds, world_dir = training_worlds(env)
        self.env = barnbench.VecEnv(env["num_envs"], worlds=self.worlds, world_dir=world_dir, dt=env["dt"],
                                    max_steps=env["max_steps"], success_radius=env["success_radius"],
                                    reward=env["reward"], global_plan=env["global_plan"], threads=env["threads"],
                                    copy=False)
        self.n = env["num_envs"]
        self.frames_per_state = enc["frames"]
        self.frame_size = _core.e2e_frames(np.zeros((1, self.env._batch.beams), np.float32), np.zeros((1, 3)),
                                           np.zeros((1, 2)), np.zeros((1, 2)), self.encoding).shape[1]
        self.inputs = self.frames_per_state * self.frame_size
        low = np.array([enc["min_v"], enc["min_w"]])
        high = np.array([enc["max_v"], enc["max_w"]])
        self.action_bias, self.action_scale = (high + low) / 2, (high - low) / 2
        torch.manual_seed(config["seed"])
        self.rng = np.random.default_rng(config["seed"])
        self.actor = Actor(self.inputs, net)
        self.critic = Critic(self.inputs, net)
        self.actor_target = copy.deepcopy(self.actor)
        self.critic_target = copy.deepcopy(self.critic)
        self.actor_optim = torch.optim.Adam(self.actor.parameters(), lr=td3["actor_lr"])
        self.critic_optim = torch.optim.Adam(self.critic.parameters(), lr=td3["critic_lr"])
        self.replay = Replay(td3["buffer_size"], self.frames_per_state, self.frame_size, self.n, td3["n_step"],
                             td3["gamma"])
        self.updates = 0
        self.steps = 0
        self.episodes = 0
        self.iteration = 0
        self.wall = 0.0
        self.episode_log = collections.deque(maxlen=300)  # the published log window
        self.stacks = None

    # -- acting --------------------------------------------------------------------------------

    def exploration_noise(self):
        t = self.config["td3"]
        fraction = self.steps / self.config["training"]["max_steps"]
        return t["exploration_noise_start"] - (t["exploration_noise_start"] - t["exploration_noise_end"]) * fraction

    def start_episodes(self, seed):
        obs, _ = self.env.reset(seed=seed)
        first = _core.e2e_frames(obs["scan"], obs["pose"], obs["global_plan_end"], np.zeros((self.n, 2)), self.encoding)
        ids = self.replay.add_frames(first)
        self.stacks = np.repeat(ids[:, None], self.frames_per_state, axis=1)

    def collect(self, steps):
        noise = self.exploration_noise()
        bootstrap = self.config["td3"]["bootstrap_truncated"]
        done_steps = 0
        while done_steps < steps:
            state = self.replay.frames[self.stacks].reshape(self.n, -1)
            with torch.no_grad():
                mean = self.actor(torch.from_numpy(state)).numpy().astype(np.float64)
            # Ours: the noisy action is clipped to the action box (the published actors sent it
            # unclipped and the Jackal's drive limited it).
            normalised = np.clip(mean + self.rng.normal(0.0, noise, size=mean.shape), -1.0, 1.0)
            action = normalised * self.action_scale + self.action_bias
            obs, reward, terminated, truncated, infos = self.env.step(action)
            ended = infos["_final_observation"]
            # The new frame of every row: for an ended episode, the next episode's first (previous
            # action 0), and its final frame separately.
            previous = np.where(ended[:, None], 0.0, action)
            new = self.replay.add_frames(_core.e2e_frames(obs["scan"], obs["pose"], obs["global_plan_end"], previous,
                                                          self.encoding))
            next_stacks = np.concatenate([self.stacks[:, 1:], new[:, None]], axis=1)
            if ended.any():
                final = infos["final_observation"]
                rows = np.flatnonzero(ended)
                final_ids = self.replay.add_frames(_core.e2e_frames(final["scan"][rows], final["pose"][rows],
                                                                    final["global_plan_end"][rows], action[rows],
                                                                    self.encoding))
                for row, fid in zip(rows, final_ids):
                    next_stacks[row] = np.concatenate([self.stacks[row, 1:], [fid]])
                info = infos["final_info"]
                for row in rows:
                    self.episode_log.append((float(info["episode_return"][row]), int(info["length"][row]),
                                             info["outcome"][row]))
                    self.episodes += 1
            for i in range(self.n):
                end = bool(ended[i])
                self.replay.step(i, self.stacks[i].copy(), normalised[i].astype(np.float32), float(reward[i]),
                                 next_stacks[i].copy(), end, end and bool(truncated[i]) and bootstrap)
                if end:
                    next_stacks[i] = new[i]  # the next episode's stack: its first frame repeated
            self.stacks = next_stacks
            self.steps += self.n
            done_steps += self.n
        return done_steps

    # -- learning ------------------------------------------------------------------------------

    def update(self, batch):
        t = self.config["td3"]
        state, action, reward, next_state, not_done, discount = self.replay.sample(self.rng, batch)
        with torch.no_grad():
            smoothing = (torch.randn_like(action) * t["policy_noise"]).clamp(-t["noise_clip"], t["noise_clip"])
            next_action = (self.actor_target(next_state) + smoothing).clamp(-1.0, 1.0)
            q1, q2 = self.critic_target(next_state, next_action)
            target = reward + not_done * discount * torch.min(q1, q2)
        c1, c2 = self.critic(state, action)
        critic_loss = F.mse_loss(c1, target) + F.mse_loss(c2, target)
        self.critic_optim.zero_grad()
        critic_loss.backward()
        self.critic_optim.step()
        self.updates += 1
        actor_loss = None
        if self.updates % t["update_actor_freq"] == 0:
            actor_loss = -self.critic.q(0, state, self.actor(state)).mean()
            self.actor_optim.zero_grad()
            actor_loss.backward()
            self.actor_optim.step()
            with torch.no_grad():
                for net, target_net in ((self.critic, self.critic_target), (self.actor, self.actor_target)):
                    for p, tp in zip(net.parameters(), target_net.parameters()):
                        tp.mul_(1.0 - t["tau"]).add_(p, alpha=t["tau"])
            actor_loss = actor_loss.item()
        return critic_loss.item(), actor_loss, c1.mean().item()

    # -- records -------------------------------------------------------------------------------

    def export(self, path):
        enc = self.encoding
        layers = [(m.weight.detach().numpy(), m.bias.detach().numpy()) for m in self.actor.linear_layers()]
        sim_config = os.path.join(_core.SOURCE_DIR, "configs", "sim", "barn.yaml")
        header = {"output": "tanh", "output_low": [enc["min_v"], enc["min_w"]],
                  "output_high": [enc["max_v"], enc["max_w"]], "input": _core.e2e_input_text(enc),
                  "output_text": "v [m/s], w [rad/s]", "dtype": self.config["training"]["policy_dtype"],
                  "name": self.config["name"], "config_hash": int(_core.digest(self.config_text.encode()), 16),
                  "plant_hash": _core.plant_hash(sim_config),
                  "trained": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
                  "seed": self.config["seed"], "steps": self.steps}
        _core.write_mlp_policy(path, layers, header)

    def save(self):
        folder = os.path.join(self.out, "checkpoint")
        os.makedirs(folder, exist_ok=True)
        torch.save({"actor": self.actor.state_dict(), "critic": self.critic.state_dict(),
                    "actor_target": self.actor_target.state_dict(), "critic_target": self.critic_target.state_dict(),
                    "actor_optim": self.actor_optim.state_dict(), "critic_optim": self.critic_optim.state_dict(),
                    "counters": {"updates": self.updates, "steps": self.steps, "episodes": self.episodes,
                                 "iteration": self.iteration, "wall": self.wall},
                    "episode_log": list(self.episode_log), "torch_rng": torch.get_rng_state(),
                    "numpy_rng": self.rng.bit_generator.state}, os.path.join(folder, "networks.pt.tmp"))
        np.savez(os.path.join(folder, "replay.tmp.npz"), **self.replay.state_dict())
        os.replace(os.path.join(folder, "replay.tmp.npz"), os.path.join(folder, "replay.npz"))
        os.replace(os.path.join(folder, "networks.pt.tmp"), os.path.join(folder, "networks.pt"))
        self.export(os.path.join(self.out, "e2e.policy"))

    def load(self):
        folder = os.path.join(self.out, "checkpoint")
        path = os.path.join(folder, "networks.pt")
        if not os.path.exists(path):
            return False
        d = torch.load(path)
        for key in ("actor", "critic", "actor_target", "critic_target", "actor_optim", "critic_optim"):
            getattr(self, key).load_state_dict(d[key])
        c = d["counters"]
        self.updates, self.steps, self.episodes, self.iteration, self.wall = (
            c["updates"], c["steps"], c["episodes"], c["iteration"], c["wall"])
        self.episode_log.extend(tuple(e) for e in d["episode_log"])
        torch.set_rng_state(d["torch_rng"])
        self.rng.bit_generator.state = d["numpy_rng"]
        with np.load(os.path.join(folder, "replay.npz")) as replay:
            self.replay.load_state_dict(replay)
        return True

    def log_row(self, losses):
        log = list(self.episode_log)
        rate = lambda outcome: float(np.mean([e[2] == outcome for e in log])) if log else float("nan")
        critic = [l[0] for l in losses]
        actor = [l[1] for l in losses if l[1] is not None]
        return {"iteration": self.iteration, "steps": self.steps, "episodes": self.episodes,
                "wall_s": round(self.wall, 1),
                "return": float(np.mean([e[0] for e in log])) if log else float("nan"),
                "success": rate("success"), "collision": rate("collision"), "timeout": rate("timeout"),
                "length": float(np.mean([e[1] for e in log])) if log else float("nan"),
                "critic_loss": float(np.mean(critic)) if critic else float("nan"),
                "actor_loss": float(np.mean(actor)) if actor else float("nan"),
                "q": float(np.mean([l[2] for l in losses])) if losses else float("nan"),
                "exploration_noise": self.exploration_noise()}

    # -- the loop ------------------------------------------------------------------------------

    def run(self, config_text, hours=None, max_steps=None):
        self.config_text = config_text
        training = self.config["training"]
        resumed = self.load()
        curve = os.path.join(self.out, "curve.csv")
        if not resumed:
            with open(curve, "w") as f:
                f.write(",".join(CURVE_COLUMNS) + "\n")
        # A resumed run starts fresh episodes (their seed follows the iteration).
        self.start_episodes(self.config["seed"] * 1000003 + self.iteration)
        limit = min(training["max_steps"], max_steps or training["max_steps"])
        started = time.monotonic()
        wall0 = self.wall
        if not resumed:
            self.collect(training["pre_collect"])
        while self.steps < limit:
            tick = time.monotonic()
            self.collect(training["collect_per_iteration"])
            collected = time.monotonic() - tick
            losses = [self.update(self.config["td3"]["batch_size"]) for _ in range(training["updates_per_iteration"])]
            self.iteration += 1
            self.wall = wall0 + time.monotonic() - started
            row = self.log_row(losses)
            with open(curve, "a") as f:
                f.write(",".join(_fmt(row[c]) for c in CURVE_COLUMNS) + "\n")
            print(f"iteration {self.iteration}: {self.steps} steps, {self.episodes} episodes, "
                  f"return {row['return']:.2f}, success {row['success']:.2f}, collision {row['collision']:.2f}, "
                  f"timeout {row['timeout']:.2f}, length {row['length']:.0f}, critic loss {row['critic_loss']:.4f}, "
                  f"actor loss {row['actor_loss']:.3f}, replay {self.replay.size}, collect {collected:.1f} s, "
                  f"iteration {time.monotonic() - tick:.1f} s, {self.wall / 3600:.2f} h", flush=True)
            out_of_time = hours is not None and (time.monotonic() - started) >= hours * 3600
            if self.iteration % training["checkpoint_every"] == 0 or out_of_time or self.steps >= limit:
                self.save()
            if out_of_time:
                break
        return self.steps


def _fmt(value):
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.6g}"
    return str(value)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--config", default=os.path.join(_core.SOURCE_DIR, "configs", "policies", "e2e_train.yaml"))
    parser.add_argument("--out", required=True, help="folder for the checkpoint, curve.csv and e2e.policy")
    parser.add_argument("--hours", type=float, help="stop after this much wall time (at a checkpoint)")
    parser.add_argument("--max-steps", type=int, help="stop after this many environment steps")
    parser.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override a config value (YAML), e.g. --set training.collect_per_iteration=256")
    parser.add_argument("--threads", type=int, default=1, help="torch threads (default 1)")
    args = parser.parse_args(argv)
    torch.set_num_threads(args.threads)
    config = load_config(args.config)
    for item in args.set:
        key, _, value = item.partition("=")
        section, _, name = key.partition(".")
        if section not in config or not name:
            raise barnbench.InputError(f"--set {item}: SECTION.KEY=VALUE with a section of the config")
        config[section][name] = yaml.safe_load(value)
    os.makedirs(args.out, exist_ok=True)
    config_text = yaml.safe_dump(config, sort_keys=True)
    saved = os.path.join(args.out, "config.yaml")
    if os.path.exists(os.path.join(args.out, "checkpoint", "networks.pt")) and os.path.exists(saved):
        with open(saved) as f:
            if f.read() != config_text:
                raise barnbench.InputError(f"{args.out}: holds a run of another config ({saved}); use another --out")
    with open(saved, "w") as f:
        f.write(config_text)
    trainer = Trainer(config, args.out)
    print(f"train_e2e: {len(trainer.worlds)} worlds, {trainer.n} environments, actor "
          f"{sum(p.numel() for p in trainer.actor.parameters())} parameters, out {args.out}", flush=True)
    trainer.run(config_text, hours=args.hours, max_steps=args.max_steps)
    print(json.dumps({"steps": trainer.steps, "episodes": trainer.episodes, "updates": trainer.updates,
                      "wall_s": round(trainer.wall, 1)}))


if __name__ == "__main__":
    main()
