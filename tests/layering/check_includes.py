#!/usr/bin/env python3
"""Checks that every #include "…" of the project's C++ follows the layering of DESIGN.md.

Data flows one way (JSON -> scene -> engine -> result -> writers / storage), so a folder may
include only the folders below it:

  sim/geometry, sim/blast, sim/occlusion      the ground floor: no other sim folder
  sim/dynamics, sim/fracture, sim/response    physics: the ground floor only
  sim/scene                                   the scene spec: physics and the ground floor
  sim/engine                                  ties them together: everything above
  sim/io                                      writers of results: the engine and below
  server/                                     sim/ and itself
  cli/                                        sim/, server/ and itself

Physics modules never include the engine or the scene, nothing in sim/ includes server/ or cli/,
and no product code includes tests/ or bench/. A sim folder not in the table is an error, so a
new folder must be placed in it.

  check_includes.py REPO_ROOT
"""
import pathlib
import re
import sys

SIM_LEVEL = {
    "geometry": 0,
    "blast": 0,
    "occlusion": 0,
    "dynamics": 1,
    "fracture": 1,
    "response": 1,
    "scene": 2,
    "engine": 3,
    "io": 4,
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def owner(path):
    """('sim', folder) | ('server', None) | ('cli', None) for a path relative to the root."""
    parts = path.parts
    if parts[0] == "sim" and len(parts) > 2:
        return ("sim", parts[1])
    if parts[0] in ("server", "cli"):
        return (parts[0], None)
    return None


def allowed(source, target):
    """None when `source` may include `target` (both owner() tuples or None), else why not."""
    if target is None:
        return None  # a system or third-party header, or a file beside it
    kind, folder = source
    target_kind, target_folder = target
    if kind == "sim":
        if target_kind != "sim":
            return "sim/ never includes " + target_kind + "/"
        if target_folder == folder:
            return None
        if SIM_LEVEL[target_folder] < SIM_LEVEL[folder]:
            return None
        return (f"sim/{folder} (level {SIM_LEVEL[folder]}) may not include sim/{target_folder} "
                f"(level {SIM_LEVEL[target_folder]})")
    if kind == "server":
        return None if target_kind in ("sim", "server") else "server/ never includes cli/"
    return None  # cli/ may include sim/ and server/


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    problems = []
    checked = 0
    for base in ("sim", "server", "cli"):
        for path in sorted((root / base).rglob("*")):
            if path.suffix not in (".hpp", ".cpp", ".h"):
                continue
            relative = path.relative_to(root)
            source = owner(relative)
            if source is None:
                continue
            if source[0] == "sim" and source[1] not in SIM_LEVEL:
                problems.append(f"{relative}: sim/{source[1]} is not in the layering table")
                continue
            for match in (INCLUDE.finditer(path.read_text(encoding="utf-8"))):
                name = pathlib.PurePosixPath(match.group(1))
                checked += 1
                if name.parts[0] in ("tests", "bench"):
                    problems.append(f"{relative}: includes {name} (tests and benchmarks only)")
                    continue
                target = owner(name)
                if target and target[0] == "sim" and target[1] not in SIM_LEVEL:
                    problems.append(f"{relative}: includes {name}, a folder not in the table")
                    continue
                why = allowed(source, target)
                if why:
                    problems.append(f"{relative}: includes {name}: {why}")
    for problem in problems:
        print(problem)
    print(f"{checked} includes checked, {len(problems)} against the layering")
    return 1 if problems or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
