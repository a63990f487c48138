#!/usr/bin/env python3
"""A reactive gap follower for barnbench's `external` controller (protocol v1).

barn writes one JSON object per line to stdin: a "reset" at the start of every episode, then
an "observation" every control period. This program answers each line with one JSON line on
stdout: {"ok": true} to a reset, {"v": ..., "w": ..., "state": ...} to an observation.
Anything it prints to stderr shows up in barn's error message if it fails.

The controller: every few degrees ahead it measures how far a corridor as wide as the robot
(plus a margin) stays free of scan points, then steers along the free direction closest to
the goal, and slows down as the free distance ahead shrinks. When nothing ahead is free it
turns on the spot toward the most open side. No map, no memory beyond the last heading.

Only the standard library; run with `python3 gap_follower.py [--max-speed 1.0] ...`.
"""

import argparse
import json
import math
import sys


class GapFollower:
    def __init__(self, reset, args):
        self.args = args
        lidar = reset["lidar"]
        robot = reset["robot"]
        self.angle_min = lidar["angle_min"]
        self.angle_increment = lidar["angle_increment"]
        self.offset_x, self.offset_y = lidar["offset"]
        self.range_max = lidar["range_max"]
        self.max_w = min(args.max_turn_rate, robot["max_angular_speed"])
        self.max_v = min(args.max_speed, robot["max_linear_speed"])
        # Half the corridor the robot needs: half its planning footprint plus a margin.
        self.half_width = robot["footprint_width"] / 2 + args.margin
        self.front = robot["footprint_length"] / 2
        self.heading = 0.0  # [rad] the direction chosen last tick, robot frame
        # Candidate directions [rad], robot frame: every `step` degrees within +-90 degrees.
        step = math.radians(args.step)
        count = int(math.pi / 2 / step)
        self.candidates = [i * step for i in range(-count, count + 1)]

    def points(self, scan):
        """Scan returns within the horizon as (x, y) in the robot frame (every 2nd beam)."""
        horizon = self.args.horizon
        pts = []
        for i in range(0, len(scan), 2):
            r = scan[i]
            if r is None or r > horizon:
                continue
            a = self.angle_min + i * self.angle_increment
            pts.append((self.offset_x + r * math.cos(a), self.offset_y + r * math.sin(a)))
        return pts

    def free_distance(self, pts, angle):
        """How far a corridor of half_width along `angle` stays free of points [m]."""
        c, s = math.cos(angle), math.sin(angle)
        free = self.args.horizon
        hw = self.half_width
        for x, y in pts:
            along = x * c + y * s
            if along <= 0.0 or along >= free:
                continue
            if abs(-x * s + y * c) < hw:
                free = along
        return free

    def act(self, obs):
        x, y, yaw = obs["pose"]
        gx, gy = obs["goal"]
        dx, dy = gx - x, gy - y
        goal_distance = math.sqrt(dx * dx + dy * dy)  # not hypot: sqrt rounds the same in every language
        goal_angle = math.atan2(dy, dx) - yaw
        goal_angle = math.atan2(math.sin(goal_angle), math.cos(goal_angle))

        pts = self.points(obs["scan"])
        need = min(goal_distance, self.args.lookahead)
        best, best_cost, best_free = None, math.inf, 0.0
        fallback, fallback_free = 0.0, -1.0
        for angle in self.candidates:
            free = self.free_distance(pts, angle)
            if free > fallback_free:
                fallback, fallback_free = angle, free
            if free < need:
                continue
            # Closest to the goal, with a little hysteresis so the robot does not dither
            # between two gaps of almost equal cost.
            cost = abs(angle - goal_angle) + 0.3 * abs(angle - self.heading)
            if cost < best_cost:
                best, best_cost, best_free = angle, cost, free

        if best is None:
            if fallback_free < self.front + 0.15:
                # Boxed in: turn on the spot toward the most open direction.
                self.heading = fallback
                return 0.0, math.copysign(self.max_w * 0.6, fallback or 1.0), "turn"
            best, best_free = fallback, fallback_free

        self.heading = best
        w = max(-self.max_w, min(self.max_w, self.args.turn_gain * best))
        # Slow down for sharp turns and when the free distance ahead is short.
        ahead = self.free_distance(pts, 0.0)
        room = max(0.0, min(1.0, (min(best_free, ahead + 0.5) - self.front) / self.args.slow_distance))
        v = self.max_v * room * max(0.0, math.cos(best)) ** 2
        return v, w, "gap"


def argument_parser():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-speed", type=float, default=1.0, help="[m/s]")
    parser.add_argument("--max-turn-rate", type=float, default=2.0, help="[rad/s]")
    parser.add_argument("--margin", type=float, default=0.1, help="[m] added to the robot's half width")
    parser.add_argument("--horizon", type=float, default=2.5, help="[m] scan points farther away are ignored")
    parser.add_argument("--lookahead", type=float, default=1.5, help="[m] free distance a direction needs")
    parser.add_argument("--slow-distance", type=float, default=1.0, help="[m] full speed beyond this much room")
    parser.add_argument("--turn-gain", type=float, default=2.0, help="[1/s] yaw rate per radian of heading")
    parser.add_argument("--step", type=float, default=3.0, help="[deg] between candidate directions")
    return parser


def main():
    args = argument_parser().parse_args()

    controller = None
    for line in sys.stdin:  # end of file: barn is done with this process
        message = json.loads(line)
        if message["type"] == "reset":
            if message["protocol"] != 1:
                reply = {"ok": False, "error": "gap_follower.py speaks protocol 1 only"}
            else:
                controller = GapFollower(message, args)
                reply = {"ok": True}
        else:
            v, w, state = controller.act(message)
            reply = {"v": v, "w": w, "state": state}
        sys.stdout.write(json.dumps(reply) + "\n")
        sys.stdout.flush()  # lockstep: barn waits for this line


if __name__ == "__main__":
    main()
