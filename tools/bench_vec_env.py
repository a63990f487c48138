#!/usr/bin/env python3
"""Speed of barnbench.VecEnv against the simulator's own cost (docs/rl.md, "Speed").

    PYTHONPATH=build/python /usr/bin/python3 tools/bench_vec_env.py [--envs 8] [--threads 2]

For each action repeat dt (0.05 and 0.2 s) it steps `--envs` sub-environments with a trivial
policy (the constant command (0.5, 0)) on barnbench's 300 worlds for `--seconds` simulated
seconds per sub-environment, three ways, and prints the median wall time of `--repeats` runs:

  bare     the same episodes (worlds, seeds, restarts) stepped by bench::Episode alone in C++
           threads: the simulator's own cost (no arrays, rewards, infos, no Python)
  vec      VecEnv from a Python loop, copy=False (views) and copy=True (fresh arrays)

and the overhead ratio vec / bare - 1 (the goal: at most 20 %). Then the Python overhead of one
step: Env.step and VecEnv.step with one sub-environment, each minus the bare cost of the same
steps, on one thread. Speed is measured here, never in the tests.
"""

import argparse
import os
import statistics
import time

import numpy as np

import barnbench
from barnbench import _core

SIM_CONFIG = os.path.join(_core.SOURCE_DIR, "configs", "sim", "barn.yaml")
WORLD_DIR = os.path.join(_core.SOURCE_DIR, "worlds")
ACTION = (0.5, 0.0)


def median_time(function, repeats):
    """Median wall time of `function()`; a function that returns a number times itself."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        own = function()
        times.append(own if own is not None else time.perf_counter() - start)
    return statistics.median(times)


def bare(worlds, envs, dt, threads, steps, simulated=None, seed=1):
    """The wall seconds of the stepping (timed in C++: the worlds' preparation excluded, as
    VecEnv's construction is excluded below)."""
    sim, wall = _core.run_bare_episodes(worlds, WORLD_DIR, SIM_CONFIG, barnbench.default_protocol, envs, dt, 0,
                                        threads, seed, ACTION[0], ACTION[1], steps)
    if simulated is not None:
        simulated.append(sim)
    return wall


def vec_loop(worlds, envs, dt, threads, steps, copy, seed=1):
    env = barnbench.VecEnv(envs, worlds=worlds, dt=dt, threads=threads, copy=copy)
    actions = np.tile(ACTION, (envs, 1))

    def run():
        env.reset(seed=seed)
        for _ in range(steps):
            env.step(actions)
    return run


def env_loop(world, dt, steps, resets):
    """Env.step alone timed (its resets, which load the world, are timed into `resets`)."""
    env = barnbench.Env(world=world, dt=dt)

    def run():
        done = 0
        seed = 0
        stepping = 0.0
        while done < steps:
            start = time.perf_counter()
            env.reset(seed=seed)
            resets.append(time.perf_counter() - start)
            seed += 1
            while done < steps:
                done += 1
                start = time.perf_counter()
                _, _, terminated, truncated, _ = env.step(ACTION)
                stepping += time.perf_counter() - start
                if terminated or truncated:
                    break
        return stepping
    return run


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", type=int, default=8, help="sub-environments (default 8)")
    parser.add_argument("--threads", type=int, default=2, help="threads (default 2: the 2-core machine)")
    parser.add_argument("--worlds", default="all")
    parser.add_argument("--seconds", type=float, default=60.0, help="simulated seconds per sub-environment")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{args.envs} sub-environments, {args.threads} threads, worlds {args.worlds}, command {ACTION}, "
          f"{args.seconds:g} simulated s each, median of {args.repeats}")
    print(f"{'dt':>5} {'bare steps/s':>13} {'vec steps/s':>12} {'copy steps/s':>13} {'sim-s/s':>8} "
          f"{'overhead':>9} {'with copy':>10}")
    for dt in (0.05, 0.2):
        steps = int(round(args.seconds / dt))
        env_steps = steps * args.envs
        simulated = []
        t_bare = median_time(lambda: bare(args.worlds, args.envs, dt, args.threads, steps, simulated), args.repeats)
        t_vec = median_time(vec_loop(args.worlds, args.envs, dt, args.threads, steps, False), args.repeats)
        t_copy = median_time(vec_loop(args.worlds, args.envs, dt, args.threads, steps, True), args.repeats)
        print(f"{dt:>5g} {env_steps / t_bare:>13.0f} {env_steps / t_vec:>12.0f} {env_steps / t_copy:>13.0f} "
              f"{simulated[0] / t_vec:>8.0f} {t_vec / t_bare - 1:>8.1%} {t_copy / t_bare - 1:>9.1%}")
    print("Python overhead of one step (one sub-environment, one thread, dt 0.05 s, world 0):")
    steps = int(round(args.seconds / 0.05))
    resets = []
    t_bare = median_time(lambda: bare("0", 1, 0.05, 1, steps), args.repeats) / steps
    t_env = median_time(env_loop(0, 0.05, steps, resets), args.repeats) / steps
    t_vec = median_time(vec_loop("0", 1, 0.05, 1, steps, True), args.repeats) / steps
    print(f"  bare step {t_bare * 1e6:.1f} us (its episodes' construction included); "
          f"VecEnv.step {t_vec * 1e6:.1f} us (+{(t_vec - t_bare) * 1e6:.1f} us, the same episodes); "
          f"Env.step {t_env * 1e6:.1f} us (+{(t_env - t_bare) * 1e6:.1f} us; its resets apart: "
          f"{statistics.median(resets) * 1e3:.0f} ms each)")


if __name__ == "__main__":
    main()
