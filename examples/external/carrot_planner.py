#!/usr/bin/env python3
"""examples/python/carrot_planner.py's CarrotPlanner as an `external` program: the protocol's
JSON lines on stdin and stdout (docs/external_controller.md), with the global plan in every
observation (the `global_plan` block of carrot_planner.yaml)."""

import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))
from carrot_planner import CarrotPlanner  # noqa: E402  (the path above first)

planner = CarrotPlanner()
for line in sys.stdin:
    message = json.loads(line)
    if message["type"] == "reset":
        planner.reset(message)
        print('{"ok": true}', flush=True)
        continue
    message["scan"] = [math.inf if r is None else r for r in message["scan"]]
    message["global_plan"] = message["global_plan"]["poses"]
    v, w = planner.act(message)
    print(json.dumps({"v": v, "w": w}), flush=True)
