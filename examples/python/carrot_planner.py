#!/usr/bin/env python3
"""A local planner that brings its own nothing else: it follows move_base's global plan, which
barnbench hands it with a `global_plan` block. A carrot `lookahead` metres along the plan, a
turn rate toward it, and a speed that drops for sharp turns and for obstacles ahead.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/carrot_planner.py [WORLDS] [OUT]

The same class runs as an external program (examples/external/carrot_planner.yaml) and its C++
port as examples/cpp/carrot_planner.cpp: the three give byte-identical records.
"""

import math


class CarrotPlanner:
    period = 0.05  # [s] 20 Hz

    def __init__(self, lookahead=1.0, max_speed=1.0, turn_gain=2.0, slow_distance=1.0):
        self.lookahead, self.max_speed, self.turn_gain, self.slow_distance = lookahead, max_speed, turn_gain, slow_distance

    def reset(self, info):
        self.max_w = info["robot"]["max_angular_speed"]
        self.front = info["robot"]["footprint_length"] / 2  # [m] ahead of the centre
        lidar = info["lidar"]  # the beams within 0.35 rad of straight ahead
        self.first = math.ceil((-0.35 - lidar["angle_min"]) / lidar["angle_increment"])
        self.last = math.floor((0.35 - lidar["angle_min"]) / lidar["angle_increment"])

    def act(self, obs):
        x, y, yaw = (float(v) for v in obs["pose"])
        plan = obs["global_plan"]  # (x, y, yaw) rows, robot -> goal
        tx, ty = float(obs["goal"][0]), float(obs["goal"][1])  # no plan yet: the goal
        closest, nearest = 0, math.inf
        for i in range(len(plan)):
            dx, dy = float(plan[i][0]) - x, float(plan[i][1]) - y
            if dx * dx + dy * dy < nearest:
                closest, nearest = i, dx * dx + dy * dy
        for i in range(closest, len(plan)):
            tx, ty = float(plan[i][0]), float(plan[i][1])
            if (tx - x) * (tx - x) + (ty - y) * (ty - y) >= self.lookahead * self.lookahead:
                break
        error = math.atan2(ty - y, tx - x) - yaw
        error = math.atan2(math.sin(error), math.cos(error))
        w = max(-self.max_w, min(self.max_w, self.turn_gain * error))
        ahead = min(float(r) for r in obs["scan"][self.first:self.last + 1])
        room = max(0.0, min(1.0, (ahead - self.front - 0.2) / self.slow_distance))
        return self.max_speed * room * max(0.0, math.cos(error)), w


if __name__ == "__main__":
    import sys

    import barnbench

    worlds = sys.argv[1] if len(sys.argv) > 1 else "0:300:30"
    out = sys.argv[2] if len(sys.argv) > 2 else "results/carrot_python"
    summary = barnbench.run(CarrotPlanner, worlds=worlds, jobs=2, out=out, global_plan={})["summary"]
    print(f"score {summary['score']:.4f}, success {summary['success_rate']:.3f}, "
          f"collision {summary['collision_rate']:.3f}, timeout {summary['timeout_rate']:.3f}: {out}")
