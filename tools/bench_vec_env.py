#!/usr/bin/env python3
"""Speed of barnbench.VecEnv against the simulator's own cost (docs/rl.md, "Speed").

    PYTHONPATH=build/python /usr/bin/python3 tools/bench_vec_env.py [--envs 8] [--threads 2]

For each action repeat dt (0.05 and 0.2 s) it steps `--envs` sub-environments with a trivial
policy (the constant command (0.5, 0)) on barnbench's 300 worlds for `--seconds` simulated
seconds per sub-environment, and prints the median of `--repeats` runs of:

  bare   the same episodes (worlds, seeds, restarts) stepped by bench::Episode alone in C++
         (OpenMP threads, one per sub-environment's whole run): the simulator's own cost, with
         no arrays, rewards, infos or Python
  vec    VecEnv stepped from a Python loop, copy=False (views) and copy=True (fresh arrays)

as environment steps per wall second and as process CPU time per simulated second (all
threads; the worlds' preparation and VecEnv's construction excluded). The overhead is VecEnv's
CPU cost per simulated second over bare's, minus 1 (the goal: at most 20 %). CPU time is the
measure that holds on a shared machine; the wall rates move with the machine's load. Then the
cost of one step with one sub-environment on one thread: bare, VecEnv.step and Env.step
(Env's resets timed apart). Speed is measured here, never in the tests.
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


def median_run(function, repeats):
    """Medians of the (wall, cpu, simulated) that `function()` returns."""
    runs = [function() for _ in range(repeats)]
    return tuple(statistics.median(r[k] for r in runs) for k in range(3))


def bare(worlds, envs, dt, threads, steps, seed=1):
    simulated, wall, cpu = _core.run_bare_episodes(worlds, WORLD_DIR, SIM_CONFIG, barnbench.default_protocol, envs,
                                                   dt, 0, threads, seed, ACTION[0], ACTION[1], steps)
    return wall, cpu, simulated


def vec(worlds, envs, dt, threads, steps, copy, seed=1):
    env = barnbench.VecEnv(envs, worlds=worlds, dt=dt, threads=threads, copy=copy)
    actions = np.tile(ACTION, (envs, 1))
    wall, cpu = time.perf_counter(), time.process_time()
    env.reset(seed=seed)
    for _ in range(steps):
        env.step(actions)
    return time.perf_counter() - wall, time.process_time() - cpu, float("nan")


def env_steps(world, dt, steps):
    """Env.step alone timed; its resets (which load the world) apart."""
    env = barnbench.Env(world=world, dt=dt)
    done, seed, stepping, resets = 0, 0, 0.0, []
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
    return stepping, statistics.median(resets), float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", type=int, default=8, help="sub-environments (default 8)")
    parser.add_argument("--threads", type=int, default=2, help="threads (default 2: the 2-core machine)")
    parser.add_argument("--worlds", default="all")
    parser.add_argument("--seconds", type=float, default=60.0, help="simulated seconds per sub-environment")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"{args.envs} sub-environments, {args.threads} threads, worlds {args.worlds}, command {ACTION}, "
          f"{args.seconds:g} simulated s each, median of {args.repeats}; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'dt':>5} | {'steps per wall s: bare':>22} {'vec':>7} {'copy':>7} | "
          f"{'CPU ms per sim-s: bare':>22} {'vec':>6} {'copy':>6} | {'overhead':>8} {'copy':>7}")
    for dt in (0.05, 0.2):
        steps = int(round(args.seconds / dt))
        n = steps * args.envs
        b_wall, b_cpu, simulated = median_run(lambda: bare(args.worlds, args.envs, dt, args.threads, steps),
                                              args.repeats)
        v_wall, v_cpu, _ = median_run(lambda: vec(args.worlds, args.envs, dt, args.threads, steps, False),
                                      args.repeats)
        c_wall, c_cpu, _ = median_run(lambda: vec(args.worlds, args.envs, dt, args.threads, steps, True),
                                      args.repeats)
        ms = lambda cpu: 1e3 * cpu / simulated
        print(f"{dt:>5g} | {n / b_wall:>22.0f} {n / v_wall:>7.0f} {n / c_wall:>7.0f} | "
              f"{ms(b_cpu):>22.3f} {ms(v_cpu):>6.3f} {ms(c_cpu):>6.3f} | "
              f"{v_cpu / b_cpu - 1:>8.1%} {c_cpu / b_cpu - 1:>7.1%}")
    steps = int(round(args.seconds / 0.05))
    b = median_run(lambda: bare("0", 1, 0.05, 1, steps), args.repeats)
    v = median_run(lambda: vec("0", 1, 0.05, 1, steps, True), args.repeats)
    e = median_run(lambda: env_steps(0, 0.05, steps), args.repeats)
    us = lambda seconds: 1e6 * seconds / steps
    print(f"one sub-environment, one thread, dt 0.05 s, world 0, wall time per step: bare {us(b[0]):.1f} us "
          f"(its episodes' construction included), VecEnv.step {us(v[0]):.1f} us (+{us(v[0] - b[0]):.1f} us, the "
          f"same episodes), Env.step {us(e[0]):.1f} us (+{us(e[0] - b[0]):.1f} us; Env.reset {e[1] * 1e3:.1f} ms)")


if __name__ == "__main__":
    main()
