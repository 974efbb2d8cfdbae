#!/usr/bin/env python3
"""The large jobs of bench/results/result_storage.md: 83 boxes of 1 kg falling freely (no ground,
no air, so never at rest and every frame is recorded) after a 5 kg charge, at 1 000 fps.

    large_job_scene.py DURATION_S > scene.json     # 60: 4 980 083 frame samples, 24: 1 992 083"""
import json
import sys

duration = float(sys.argv[1])
duration = int(duration) if duration.is_integer() else duration
objects = [{"name": "box%d" % i, "shape": {"type": "box", "size": [0.2, 0.2, 0.2]},
            "position": [0.3 * (i % 10), 1.0 + 0.3 * (i // 10), 8], "mass": 1} for i in range(83)]
json.dump({"charges": [{"position": [0, 1, 0], "mass": 5}],
           "environment": {"ground": None, "air_density": 0}, "objects": objects,
           "simulation": {"duration": duration, "frame_rate": 1000}}, sys.stdout)
