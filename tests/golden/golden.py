#!/usr/bin/env python3
"""Pins what `brisance run` produces for every example scene and every guard scene.

For each scene it writes the JSON and the glb result, reduces the JSON to a canonical form (keys
sorted; `stats.wall_time_s` dropped, the one field that measures the machine rather than the
physics) and compares SHA-256 digests with the committed list. A refactoring must leave every
digest unchanged; a deliberate change of results updates the list in the same commit, with
`--update`, and says why in the commit message.

  golden.py --brisance BIN --expected tests/golden/results.sha256 SCENE.json... [--update]
"""
import argparse
import hashlib
import json
import os
import concurrent.futures
import subprocess
import sys
import tempfile


def canonical_json_digest(path):
    with open(path, encoding="utf-8") as f:
        result = json.load(f)
    result.get("stats", {}).pop("wall_time_s", None)
    text = json.dumps(result, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def file_digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def run(binary, scene, output):
    done = subprocess.run([binary, "run", scene, "-o", output], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        sys.exit(f"{scene}: brisance run exited {done.returncode}:\n{done.stdout}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--brisance", required=True)
    parser.add_argument("--expected", required=True)
    parser.add_argument("--update", action="store_true")
    parser.add_argument("scenes", nargs="+")
    args = parser.parse_args()

    actual = {}
    with tempfile.TemporaryDirectory() as tmp:
        # Every run is its own process: two at a time halve the wall time on two cores (the
        # facade scene under the sanitizers takes minutes on its own).
        jobs = []
        for scene in sorted(args.scenes):
            name = os.path.splitext(os.path.basename(scene))[0]
            for extension in (".json", ".glb"):
                jobs.append((scene, name + extension, os.path.join(tmp, name + extension)))
        with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
            list(pool.map(lambda job: run(args.brisance, job[0], job[2]), jobs))
        for _, key, path in jobs:
            actual[key] = canonical_json_digest(path) if key.endswith(".json") else file_digest(path)

    if args.update:
        with open(args.expected, "w", encoding="utf-8") as f:
            for key in sorted(actual):
                f.write(f"{actual[key]}  {key}\n")
        print(f"wrote {len(actual)} digests to {args.expected}")
        return 0

    expected = {}
    with open(args.expected, encoding="utf-8") as f:
        for line in f:
            if line.strip():
                digest, key = line.split()
                expected[key] = digest
    failed = 0
    for key in sorted(set(actual) | set(expected)):
        if key not in expected:
            print(f"FAIL {key}: no committed digest (run with --update and commit it)")
        elif key not in actual:
            print(f"FAIL {key}: committed digest but no such scene was run")
        elif actual[key] != expected[key]:
            print(f"FAIL {key}: result changed ({expected[key][:12]} -> {actual[key][:12]})")
        else:
            print(f"ok   {key}")
            continue
        failed += 1
    print(f"{len(actual) - failed if failed <= len(actual) else 0} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
