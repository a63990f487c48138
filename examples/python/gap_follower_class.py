#!/usr/bin/env python3
"""The gap follower of examples/external/gap_follower.py as a Python class for barnbench.run.

The same controller object code runs here inside barnbench's worker processes and there as
an `external` program over stdin/stdout; both routes hand it the same doubles, so the two give
byte-identical records (src/python/tests checks it).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/gap_follower_class.py [WORLDS] [OUT]
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "external"))
from gap_follower import GapFollower, argument_parser  # noqa: E402  (the path above first)


class GapFollowerController:
    """barnbench.run's controller interface: reset(info), act(obs) -> (v, w, state)."""

    period = 0.1  # [s] 10 Hz, as examples/external/gap_follower.yaml

    def __init__(self, argv=("--max-speed", "1.0")):
        self.args = argument_parser().parse_args(list(argv))
        self.inner = None

    def reset(self, info):
        self.inner = GapFollower(info, self.args)

    def act(self, obs):
        return self.inner.act(obs)


if __name__ == "__main__":
    import barnbench

    worlds = sys.argv[1] if len(sys.argv) > 1 else "0:300:30"
    out = sys.argv[2] if len(sys.argv) > 2 else "results/gap_python"
    summary = barnbench.run(GapFollowerController, worlds=worlds, trials=1, jobs=2, out=out)["summary"]
    print(f"score {summary['score']:.4f}, success {summary['success_rate']:.3f}, "
          f"collision {summary['collision_rate']:.3f}, timeout {summary['timeout_rate']:.3f}: {out}")
