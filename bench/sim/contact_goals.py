#!/usr/bin/env python3
"""The speed goals of contacts between bodies (issue 13), from one step_bench invocation.

Runs the benchmarks the goals name in one invocation (ratios, not absolute times: the machines
are noisy), medians of --repetitions, and prints each goal with what was measured and whether
it is met. Bullet's side-by-side runs need the bench packages (make bench-deps); without them
the goals against Bullet print as not measured.

  python3 bench/sim/contact_goals.py --step-bench build/release/bench/step_bench
  python3 bench/sim/contact_goals.py --report saved.json   (a saved --benchmark_format=json run)
"""
import argparse
import json
import subprocess
import sys

FILTER = ("BM_BrickWall/collisions:[01]$|BM_BrickWallToHandover/collisions:1|"
          "BM_BrickWalls16/collisions:1/apart_m:1000|BM_BrickWalls16ToHandover/collisions:1|"
          "BM_BulletBrickWall/hz:60|BM_BulletBrickWalls16/hz:60|BM_Window/")

UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def results(report):
    """Each benchmark's median (its one run when there were no repetitions), by name."""
    found, runs = {}, {}
    for bench in report.get("benchmarks", []):
        if bench.get("error_occurred"):
            continue
        name = bench.get("run_name", bench["name"])
        if bench.get("run_type") != "aggregate":
            runs.setdefault(name, bench)
        elif bench.get("aggregate_name") == "median":
            found[name] = bench
    for name, bench in runs.items():
        found.setdefault(name, bench)
    return found


def overlaps(report):
    """The overlap counters (deepest between bodies, into the ground), mm, by name."""
    return {name: (bench["deepest_overlap_mm"], bench.get("below_ground_mm", 0.0))
            for name, bench in results(report).items() if "deepest_overlap_mm" in bench}


def medians(report):
    """Median CPU time of each benchmark, ms, by name."""
    return {name: bench["cpu_time"] * UNIT_MS[bench.get("time_unit", "ns")]
            for name, bench in results(report).items()}


def against_bullet(times, label, whole, handover, bullet):
    """The goal of `label` from 0.1 s (the run less its part up to the handover) at least 3x
    faster than Bullet's run, which starts there: a row of goals()."""
    goal = f"{label} from 0.1 s at least 3x faster than Bullet at 60 Hz"
    whole, handover, bullet = times.get(whole), times.get(handover), times.get(bullet)
    if whole is None or handover is None or bullet is None:
        return (goal, "not measured (a run missing; Bullet's needs make bench-deps)", None)
    part = whole - handover
    return (goal, f"{whole:.3g} - {handover:.3g} = {part:.3g} ms against {bullet:.3g} ms: "
            f"{part / bullet:.2f}x Bullet's time (goal: at most 0.33x)", 3.0 * part <= bullet)


def goals(times):
    """Rows of (goal, measured, met): met is None where a benchmark is missing."""
    rows = [against_bullet(times, "brick wall", "BM_BrickWall/collisions:1",
                           "BM_BrickWallToHandover/collisions:1", "BM_BulletBrickWall/hz:60")]
    wall = times.get("BM_BrickWall/collisions:1")
    if wall is not None:
        rows.append(("brick wall with contacts under 5 ms", f"{wall:.3g} ms", wall < 5.0))
    rows.append(against_bullet(times, "16 walls", "BM_BrickWalls16/collisions:1/apart_m:1000",
                               "BM_BrickWalls16ToHandover/collisions:1/apart_m:1000",
                               "BM_BulletBrickWalls16/hz:60"))
    without = times.get("BM_Window/collisions:0")
    for mode, arg in (("auto", 1), ("on", 2)):
        with_contacts = times.get(f"BM_Window/collisions:{arg}")
        if without is None or with_contacts is None:
            continue
        ratio = with_contacts / without
        rows.append((f"window.json with {mode} at most 1.5x its run without contacts",
                     f"{with_contacts:.4g} / {without:.4g} ms = {ratio:.2f}x", ratio <= 1.5))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--step-bench", help="path of the step_bench binary to run")
    source.add_argument("--report", help="a saved step_bench report (--benchmark_format=json)")
    parser.add_argument("--repetitions", type=int, default=3)
    args = parser.parse_args()
    if args.repetitions < 1:
        parser.error("--repetitions must be at least 1")
    try:
        if args.report:
            with open(args.report, encoding="utf-8") as saved:
                text = saved.read()
        else:
            command = [args.step_bench, f"--benchmark_filter={FILTER}",
                       f"--benchmark_repetitions={args.repetitions}",
                       "--benchmark_report_aggregates_only=true", "--benchmark_format=json"]
            print("$ " + " ".join(command), flush=True)
            text = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as error:
        print(f"contact_goals: cannot get step_bench's report: {error}", file=sys.stderr)
        return 2
    try:
        report = json.loads(text)
        times = medians(report)
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        print(f"contact_goals: cannot read step_bench's report: {error}", file=sys.stderr)
        return 2
    for name in sorted(times):
        print(f"  {name:<55} {times[name]:10.4g} ms")
    rows = goals(times)
    if all(met is None for _, _, met in rows):
        print("contact_goals: none of the goals' benchmarks ran", file=sys.stderr)
        return 2
    print()
    for goal, measured, met in rows:
        status = "not measured" if met is None else ("met" if met else "not met")
        print(f"{status:>12}  {goal}: {measured}")
    # The wall's goal is at no more visible overlap than Bullet's: both, at the end of the run.
    found = overlaps(report)
    for name in ("BM_BrickWall/collisions:1", "BM_BulletBrickWall/hz:60"):
        if name in found:
            deepest, ground = found[name]
            print(f"{'':>12}  {name}: deepest overlap of two bodies {deepest:.3g} mm, "
                  f"into the ground {ground:.3g} mm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
