#!/usr/bin/env python3
"""Crash soak of `brisance serve` (issue 15): under a steady submit-and-poll load, the server is
killed with SIGKILL at random moments (and stopped with SIGTERM a few times), then restarted on
the same data folder, for each SQLite `--sync` mode. Afterwards:

  lost        accepted jobs (a 202, or a 200 for a retried Idempotency-Key) that did not reach
              `succeeded`, or whose result, frames or glb could not be read: must be 0;
  duplicated  jobs beyond one per idempotency key (every submission carries a fresh key, and a
              submission whose answer was lost in a crash is retried with the same key and body,
              so the store must hold exactly one job per key and the retry must name the same
              job), plus jobs run to completion twice (a second "job finished" log line, or a
              "job started" after one, in the server's logs): must be 0;
  integrity   PRAGMA integrity_check of the SQLite file once the server is stopped: must be "ok".

It prints cycles, accepted, lost, duplicated, the recovery time of each restart (spawn to the
first 200 from /readyz) and exits 1 if any check fails.

    soak.py --brisance build/release/cli/brisance [--kills 20] [--terms 5] [--sync normal full]
            [--validator tests/gltf/validate.mjs] [--seed 1]
"""
import argparse
import http.client
import json
import os
import random
import shutil
import signal
import sqlite3
import statistics
import struct
import subprocess
import sys
import tempfile
import threading
import time
import uuid

# A short job: two boxes, a third of a second of simulated time.
SCENE = {
    "charges": [{"position": [0, 0.25, 0], "mass": 10}],
    "objects": [
        {"name": "near", "shape": {"type": "box", "size": [0.5, 0.5, 0.5]},
         "position": [0.5, 0.25, 3], "material": "wood"},
        {"name": "far", "shape": {"type": "box", "size": [0.5, 0.5, 0.5]},
         "position": [2.0, 0.25, 4], "material": "wood"},
    ],
    "simulation": {"duration": 0.3, "frame_rate": 30},
}
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes",
                       "window.json")) as _window:
    WINDOW = json.load(_window)


class Server:
    """One `brisance serve` process on the data folder; its log goes to a file of its own."""

    def __init__(self, binary, data, sync, log_path, max_attempts):
        self.log_path = log_path
        self.log_file = open(log_path, "w")
        self.process = subprocess.Popen(
            [binary, "serve", "--data", data, "--port", "0", "--workers", "2", "--sync", sync,
             "--grace-s", "2", "--max-attempts", str(max_attempts), "--log-level", "info"],
            stdout=subprocess.DEVNULL, stderr=self.log_file)
        self.port = 0

    def wait_ready(self, limit_s=60):
        """Seconds from now until /readyz answers 200; raises if it never does."""
        start = time.monotonic()
        while time.monotonic() - start < limit_s:
            if self.process.poll() is not None:
                raise RuntimeError("server exited with %s: see %s" % (self.process.returncode,
                                                                      self.log_path))
            if not self.port:
                with open(self.log_path) as log:
                    for line in log:
                        if '"msg":"listening"' in line:
                            self.port = json.loads(line)["port"]
            if self.port:
                try:
                    if request(self.port, "GET", "/readyz", timeout=2)[0] == 200:
                        return time.monotonic() - start
                except OSError:
                    pass
            time.sleep(0.01)
        raise RuntimeError("server not ready within %s s: see %s" % (limit_s, self.log_path))

    def stop(self, sig, limit_s=60):
        self.process.send_signal(sig)
        code = self.process.wait(limit_s)
        self.log_file.close()
        return code


def request(port, method, path, body=None, headers=None, timeout=10):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        connection.request(method, path, body=body, headers=headers or {})
        response = connection.getresponse()
        return response.status, response.read(), dict(response.getheaders())
    finally:
        connection.close()


class Load:
    """Submitters and pollers against whichever server is up (`port`, 0 while it is down)."""

    def __init__(self, rate_hz, rng):
        self.port = 0
        self.rate_hz = rate_hz
        self.rng = rng
        self.lock = threading.Lock()
        self.accepted = {}  # idempotency key -> job id
        self.conflicts = []  # (key, first id, later id): a retried key that named another job
        self.retried = 0  # submissions sent again after a failed attempt
        self.retried_existing = 0  # ... whose retry found the job the lost attempt had made
        self.stop_event = threading.Event()
        self.answer_deadline = 0.0
        self.threads = []

    def start(self, submitters=2, pollers=2):
        self.submitters = submitters
        for _ in range(submitters):
            self.threads.append(threading.Thread(target=self.submit_loop, daemon=True))
        for _ in range(pollers):
            self.threads.append(threading.Thread(target=self.poll_loop, daemon=True))
        for thread in self.threads:
            thread.start()

    def stop(self, answer_s=60):
        # A submission whose answer was lost (the server killed between its commit and its
        # answer) is retried after the stop too, until answered or for answer_s: given up at
        # once, its job was in the store but not among the accepted, and counted a duplicate
        # (the last kill came just before the stop).
        self.answer_deadline = time.monotonic() + answer_s
        self.stop_event.set()
        for thread in self.threads:
            thread.join()

    def submit_loop(self):
        period = self.submitters / self.rate_hz
        while not self.stop_event.is_set():
            key = uuid.uuid4().hex
            # One job in six is the window scene (a breaking pane, about 2 s of work in a release
            # build), long enough to be running when a kill lands.
            scene = WINDOW if self.rng.random() < 1 / 6 else SCENE
            body = json.dumps({"scene": scene}).encode()
            # Until an answer arrives: a crash between the commit and the answer is retried with
            # the same key and body, and must give the same job back.
            tries = 0
            while not self.stop_event.is_set() or (
                    tries > 0 and time.monotonic() < self.answer_deadline):
                port = self.port
                if port:
                    tries += 1
                    try:
                        status, data, _ = request(port, "POST", "/v1/jobs", body,
                                                  {"Content-Type": "application/json",
                                                   "Idempotency-Key": key})
                        if status in (200, 202):
                            job = json.loads(data)["id"]
                            with self.lock:
                                if tries > 1:
                                    self.retried += 1
                                    self.retried_existing += status == 200
                                first = self.accepted.setdefault(key, job)
                                if first != job:
                                    self.conflicts.append((key, first, job))
                            break
                        if status not in (429, 503):
                            raise RuntimeError("POST /v1/jobs answered %d: %s" % (status, data))
                    except (OSError, http.client.HTTPException):
                        pass
                time.sleep(0.05)
            time.sleep(period)

    def poll_loop(self):
        while not self.stop_event.is_set():
            port = self.port
            with self.lock:
                ids = list(self.accepted.values())
            if port and ids:
                try:
                    request(port, "GET", "/v1/jobs/" + self.rng.choice(ids))
                    request(port, "GET", "/v1/queue")
                except (OSError, http.client.HTTPException):
                    pass
            time.sleep(0.02)


def check_glb(data):
    """None if `data` is a well-formed glb (header, JSON and BIN chunks fill it exactly)."""
    if len(data) < 28 or data[:4] != b"glTF":
        return "no glb header"
    version, length = struct.unpack_from("<II", data, 4)
    if version != 2 or length != len(data):
        return "header length %d, file %d" % (length, len(data))
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    if json_type != b"JSON" or 20 + json_length + 8 > len(data):
        return "bad JSON chunk"
    try:
        json.loads(data[20:20 + json_length])
    except ValueError as error:
        return "JSON chunk does not parse: %s" % error
    bin_length, bin_type = struct.unpack_from("<I4s", data, 20 + json_length)
    if bin_type != b"BIN\0" or 20 + json_length + 8 + bin_length != len(data):
        return "bad BIN chunk"
    return None


def run_mode(args, sync, rng, work):
    """The cycles of one sync mode; returns its figures."""
    data = os.path.join(work, "data-" + sync)
    logs = []
    load = Load(args.rate, rng)
    events = ["kill"] * args.kills + ["term"] * args.terms
    rng.shuffle(events)
    recoveries = []

    def start_server():
        log = os.path.join(work, "%s-%02d.log" % (sync, len(logs)))
        logs.append(log)
        server = Server(args.brisance, data, sync, log, args.max_attempts)
        recoveries.append(server.wait_ready())
        load.port = server.port
        return server

    server = start_server()
    load.start()
    for event in events:
        time.sleep(rng.uniform(args.min_uptime, args.max_uptime))
        load.port = 0 if event == "term" else load.port  # SIGTERM stops accepting first anyway
        code = server.stop(signal.SIGKILL if event == "kill" else signal.SIGTERM)
        load.port = 0
        expected = -signal.SIGKILL if event == "kill" else 0
        if code != expected:
            raise RuntimeError("%s: server exited %s, expected %s (see %s)" %
                               (event, code, expected, logs[-1]))
        server = start_server()
    load.stop()

    # Drain: every accepted job to a final status.
    with load.lock:
        accepted = dict(load.accepted)
    final = {}
    deadline = time.monotonic() + args.drain_timeout
    pending = set(accepted.values())
    while pending and time.monotonic() < deadline:
        for job in list(pending):
            status, body, _ = request(server.port, "GET", "/v1/jobs/" + job)
            record = json.loads(body) if status == 200 else {"status": "missing:%d" % status}
            if record["status"] not in ("queued", "running"):
                final[job] = record
                pending.discard(job)
        time.sleep(0.2)

    lost = []
    for job in accepted.values():
        record = final.get(job)
        if record is None or record["status"] != "succeeded":
            lost.append((job, record["status"] if record else "unfinished"))
            continue
        status, body, _ = request(server.port, "GET", "/v1/jobs/%s/result" % job, timeout=30)
        if status != 200:
            lost.append((job, "result %d" % status))
            continue
        json.loads(body)
        status, body, _ = request(server.port, "GET", "/v1/jobs/%s/frames" % job, timeout=30)
        if status != 200:
            lost.append((job, "frames %d" % status))
            continue
        status, glb, _ = request(server.port, "GET", "/v1/jobs/%s/result.glb" % job, timeout=30)
        problem = check_glb(glb) if status == 200 else "glb %d" % status
        if problem:
            lost.append((job, problem))

    # Duplicates: jobs in the store beyond one per accepted key, and runs completed twice.
    stored = []
    path = "/v1/jobs?limit=500"
    while path:
        status, body, _ = request(server.port, "GET", path)
        listed = json.loads(body)
        stored += [job["id"] for job in listed["jobs"]]
        cursor = listed.get("next_cursor")
        path = "/v1/jobs?limit=500&cursor=" + cursor if cursor else None
    extra_jobs = sorted(set(stored) - set(accepted.values()))
    finished_twice = runs_after_finish(logs)
    duplicated = len(load.conflicts) + len(extra_jobs) + len(finished_twice)

    # A sample of the glbs through the Khronos validator.
    validated = 0
    if args.validator and shutil.which("node"):
        sample_dir = os.path.join(work, "glb-" + sync)
        os.makedirs(sample_dir, exist_ok=True)
        sample = rng.sample(sorted(accepted.values()), min(args.validate_sample, len(accepted)))
        for job in sample:
            status, glb, _ = request(server.port, "GET", "/v1/jobs/%s/result.glb" % job)
            with open(os.path.join(sample_dir, job + ".glb"), "wb") as out:
                out.write(glb)
        checked = subprocess.run(["node", args.validator, sample_dir], capture_output=True,
                                 text=True)
        if checked.returncode != 0:
            print(checked.stdout + checked.stderr, file=sys.stderr)
            lost.append(("glb validator", "exit %d" % checked.returncode))
        validated = len(sample)

    attempts = [final[j].get("attempts", 0) for j in accepted.values() if j in final]
    code = server.stop(signal.SIGTERM)
    if code != 0:
        raise RuntimeError("final SIGTERM: server exited %s" % code)
    with sqlite3.connect(os.path.join(data, "brisance.sqlite3")) as db:
        integrity = db.execute("PRAGMA integrity_check").fetchone()[0]
    return {
        "sync": sync,
        "cycles": len(events),
        "kills": args.kills,
        "terms": args.terms,
        "accepted": len(accepted),
        "lost": len(lost),
        "lost_detail": lost[:10],
        "duplicated": duplicated,
        "duplicated_detail": {"key_conflicts": load.conflicts[:5], "extra_jobs": extra_jobs[:5],
                              "finished_twice": finished_twice[:5]},
        "retried": load.retried,
        "retried_existing": load.retried_existing,
        "rerun_jobs": sum(1 for a in attempts if a > 1),
        "max_attempts": max(attempts, default=0),
        "validated_glb": validated,
        "integrity": integrity,
        "recovery_s": recoveries[1:],
    }


def runs_after_finish(logs):
    """Jobs with a second "job finished" (succeeded) line, or a "job started" after one."""
    finished = set()
    twice = []
    for path in logs:
        with open(path) as log:
            for line in log:
                if '"job ' not in line:
                    continue
                try:
                    entry = json.loads(line)
                except ValueError:
                    continue  # the last line of a killed process may be cut short
                job = entry.get("job")
                if entry.get("msg") == "job started" and job in finished:
                    twice.append(job)
                elif entry.get("msg") == "job finished" and entry.get("status") == "succeeded":
                    if job in finished:
                        twice.append(job)
                    finished.add(job)
    return twice


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--brisance", required=True)
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--terms", type=int, default=5)
    parser.add_argument("--sync", nargs="+", default=["normal", "full"])
    parser.add_argument("--rate", type=float, default=8.0, help="submissions per second")
    parser.add_argument("--min-uptime", type=float, default=0.3)
    parser.add_argument("--max-uptime", type=float, default=2.5)
    parser.add_argument("--drain-timeout", type=float, default=300)
    parser.add_argument("--validator", help="tests/gltf/validate.mjs (node), for a sample")
    parser.add_argument("--validate-sample", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--max-attempts", type=int, default=25,
                        help="the server's --max-attempts (its default, 3, fails a job that "
                             "dies with its process three times, by design)")
    parser.add_argument("--keep", action="store_true", help="keep the data folders and logs")
    args = parser.parse_args()

    rng = random.Random(args.seed)
    work = tempfile.mkdtemp(prefix="brisance-soak-")
    failed = False
    try:
        for sync in args.sync:
            started = time.monotonic()
            figures = run_mode(args, sync, rng, work)
            recovery = figures.pop("recovery_s")
            ok = figures["lost"] == 0 and figures["duplicated"] == 0 and \
                figures["integrity"] == "ok"
            failed |= not ok
            print("sync=%s cycles=%d (kill -9: %d, SIGTERM: %d) accepted=%d lost=%d "
                  "duplicated=%d retried_posts=%d (found the job: %d) rerun=%d max_attempts=%d glb_validated=%d integrity=%s "
                  "wall=%.0fs %s" %
                  (sync, figures["cycles"], figures["kills"], figures["terms"],
                   figures["accepted"], figures["lost"], figures["duplicated"],
                   figures["retried"], figures["retried_existing"],
                   figures["rerun_jobs"], figures["max_attempts"], figures["validated_glb"],
                   figures["integrity"], time.monotonic() - started, "OK" if ok else "FAILED"))
            print("  recovery s per restart (spawn to /readyz 200): min %.3f median %.3f max %.3f"
                  % (min(recovery), statistics.median(recovery), max(recovery)))
            print("  " + " ".join("%.3f" % r for r in recovery))
            if not ok:
                print("  detail: " + json.dumps({"lost": figures["lost_detail"],
                                                 "duplicated": figures["duplicated_detail"]}))
            sys.stdout.flush()
    finally:
        if args.keep or failed:
            print("data and logs kept in " + work)
        else:
            shutil.rmtree(work, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
