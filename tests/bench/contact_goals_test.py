#!/usr/bin/env python3
"""bench/sim/contact_goals.py reads step_bench's report and judges issue 13's goals from it."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench", "sim",
                      "contact_goals.py")


def entry(name, ms, median=True, **counters):
    bench = {"name": name + ("_median" if median else ""), "run_name": name,
             "run_type": "aggregate" if median else "iteration", "cpu_time": ms * 1e6,
             "real_time": ms * 1e6, "time_unit": "ns"}
    if median:
        bench["aggregate_name"] = "median"
    bench.update(counters)
    return bench


def judge(benchmarks):
    """The script's output lines for a report of these entries, and its exit code."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as saved:
        json.dump({"context": {}, "benchmarks": benchmarks}, saved)
    try:
        run = subprocess.run([sys.executable, SCRIPT, "--report", saved.name],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    finally:
        os.unlink(saved.name)
    return run.stdout.splitlines(), run.returncode, run.stderr


def verdict(lines, goal):
    """The status printed for `goal` (right-aligned in the first 12 columns)."""
    found = [line[:12].strip() for line in lines if goal in line and line[:12].strip()]
    assert len(found) == 1, (goal, lines)
    return found[0]


class ContactGoals(unittest.TestCase):
    def test_verdicts_follow_the_ratios(self):
        lines, code, _ = judge([
            entry("BM_BrickWall/collisions:1", 4.0, deepest_overlap_mm=0.04, below_ground_mm=0.5),
            entry("BM_BrickWall/collisions:1", 9.0, median=False),  # not a median: ignored
            entry("BM_BrickWallToHandover/collisions:1", 2.0),
            entry("BM_BulletBrickWall/hz:60", 6.0, deepest_overlap_mm=0.0, below_ground_mm=47.0),
            entry("BM_BrickWalls16/collisions:1/apart_m:1000", 300.0),
            entry("BM_BrickWalls16ToHandover/collisions:1/apart_m:1000", 100.0),
            entry("BM_BulletBrickWalls16/hz:60", 110.0),
            entry("BM_Window/collisions:0", 100.0),
            entry("BM_Window/collisions:1", 140.0),
            entry("BM_Window/collisions:2", 160.0),
        ])
        self.assertEqual(code, 0)
        # 4 - 2 = 2 ms against 6 ms: exactly 3x faster, met; under 5 ms, met.
        self.assertEqual(verdict(lines, "brick wall from 0.1 s"), "met")
        self.assertEqual(verdict(lines, "under 5 ms"), "met")
        # 200 ms against 110 ms: slower.
        self.assertEqual(verdict(lines, "16 walls"), "not met")
        self.assertEqual(verdict(lines, "with auto"), "met")   # 1.4x
        self.assertEqual(verdict(lines, "with on"), "not met")  # 1.6x
        self.assertTrue(any("into the ground 47 mm" in line for line in lines), lines)

    def test_a_single_run_counts_and_missing_bullet_is_not_measured(self):
        lines, code, _ = judge([
            entry("BM_BrickWall/collisions:1", 16.0, median=False),
            entry("BM_BrickWallToHandover/collisions:1", 6.0, median=False),
        ])
        self.assertEqual(code, 0)
        self.assertEqual(verdict(lines, "brick wall from 0.1 s"), "not measured")
        self.assertEqual(verdict(lines, "under 5 ms"), "not met")

    def test_a_report_without_the_goals_benchmarks_fails(self):
        _, code, err = judge([entry("BM_Other", 1.0)])
        self.assertEqual(code, 2)
        self.assertIn("none of the goals", err)

    def test_an_unreadable_report_fails_with_a_message(self):
        run = subprocess.run([sys.executable, SCRIPT, "--report", "/nonexistent/report.json"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.assertEqual(run.returncode, 2)
        self.assertIn("cannot get step_bench's report", run.stderr)


if __name__ == "__main__":
    unittest.main()
