#!/usr/bin/env python3
"""Runs the shell and Python blocks of a Markdown document against a real `brisance serve`, in
order, as a reader would paste them: every ```sh block in one bash session (variables carry over,
`set -eo pipefail`, each command's output checked only by its exit status and by the checks
below), every ```python block with python3, in a scratch folder that holds the repository's
`scenes` and `clients` as the documents assume. A block preceded by a line
`<!-- not run: REASON -->` is skipped (and listed), e.g. one that needs Blender.

usage: run_doc_blocks.py --brisance BINARY --doc docs/pipelines.md [--repo ROOT]
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BLOCK = re.compile(r"^```(\w+)\n(.*?)^```\n", re.S | re.M)
SKIP = re.compile(r"<!--\s*not run:\s*(.*?)\s*-->\s*$")


def blocks(text):
    """(language, code, skip reason or None, line number) for each fenced block."""
    for match in BLOCK.finditer(text):
        before = text[: match.start()].rstrip("\n").splitlines()
        reason = None
        if before:
            found = SKIP.search(before[-1])
            if found:
                reason = found.group(1)
        yield match.group(1), match.group(2), reason, text.count("\n", 0, match.start()) + 1


def start_server(binary, folder):
    log_path = folder / "serve.log"
    log = open(log_path, "wb")
    process = subprocess.Popen(
        [binary, "serve", "--port", "0", "--data", str(folder / "data"), "--workers", "2"],
        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=log)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        for line in log_path.read_text(errors="replace").splitlines():
            try:
                event = json.loads(line)
            except ValueError:
                continue
            if event.get("msg") == "listening":
                return process, int(event["port"])
        if process.poll() is not None:
            break
        time.sleep(0.05)
    process.kill()
    raise SystemExit("brisance serve did not start:\n" + log_path.read_text(errors="replace"))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--brisance", required=True)
    parser.add_argument("--doc", required=True)
    parser.add_argument("--repo", default=str(Path(__file__).resolve().parents[2]))
    args = parser.parse_args()
    repo = Path(args.repo)
    doc = Path(args.doc)
    text = doc.read_text(encoding="utf-8")

    scratch = Path(tempfile.mkdtemp(prefix="brisance-doc-"))
    work = scratch / "work"
    work.mkdir()
    for name in ("scenes", "clients"):
        os.symlink(repo / name, work / name)
    process, port = start_server(args.brisance, scratch)
    env = dict(os.environ, BRISANCE_URL="http://127.0.0.1:%d" % port,
               PYTHONPATH=str(repo / "clients" / "python"))
    env.pop("BRISANCE_API_KEY", None)
    failures = []
    ran = 0
    try:
        for language, code, reason, line in blocks(text):
            if language not in ("sh", "python"):
                continue
            where = "%s:%d" % (doc, line)
            if reason:
                print("SKIP %s (%s): %s" % (where, language, reason))
                continue
            # The document's own `export BRISANCE_URL=...` would point at the default port: the
            # session keeps the test server's.
            if language == "sh":
                code = re.sub(r"^export BRISANCE_URL=.*$", ": keep BRISANCE_URL", code, flags=re.M)
                script = work / ("block%d.sh" % line)
                state = work / "state.sh"
                script.write_text(
                    "set -eo pipefail\n[ -f %s ] && . %s\n%s\ndeclare -p | grep -E "
                    "'^declare -[-x]+ (B|AUTH|ID|ETAG|JOB|MTAG|NEXT)=' > %s || true\n"
                    % (state, state, code, state))
                command = ["bash", str(script)]
            else:
                script = work / ("block%d.py" % line)
                script.write_text(code)
                command = [sys.executable, str(script)]
            started = time.monotonic()
            result = subprocess.run(command, cwd=work, env=env, capture_output=True, text=True,
                                    timeout=300)
            ran += 1
            status = "PASS" if result.returncode == 0 else "FAIL"
            print("%s %s (%s, %.1f s)" % (status, where, language, time.monotonic() - started))
            if result.returncode != 0:
                failures.append(where)
                print(result.stdout[-3000:])
                print(result.stderr[-3000:])
    finally:
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
        # What the blocks promise to leave behind, and a server that never answered 5xx.
        expected = {"result.glb": b"glTF", "wall.glb": b"glTF", "frames.brf": b"BRF1",
                    "openapi.yaml": b"openapi"}
        if doc.name == "pipelines.md":
            for name, magic in expected.items():
                path = work / name
                if not path.exists() or not path.read_bytes().startswith(magic):
                    failures.append("%s: the blocks left no %s starting with %r" % (doc, name, magic))
            if not list(work.glob("j*.glb")):
                failures.append("%s: curl -OJ saved no ID.glb" % doc)
        for line in (scratch / "serve.log").read_text(errors="replace").splitlines():
            try:
                event = json.loads(line)
            except ValueError:
                continue
            if isinstance(event.get("status"), int) and event["status"] >= 500:
                failures.append("the server answered %d: %s" % (event["status"], line))
    print("%d blocks run, %d failed" % (ran, len(failures)))
    for failure in failures:
        print("FAILED:", failure)
    shutil.rmtree(scratch, ignore_errors=True)
    if ran == 0 or failures:
        sys.exit(1)


if __name__ == "__main__":
    main()
