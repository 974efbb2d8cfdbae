"""brisance_client against live `brisance serve` processes that these tests start themselves.

The server binary comes from $BRISANCE_BINARY (CTest's clients.python sets it); without it every
test is skipped. Each test class starts its own server (--port 0, a temporary --data folder) and
stops it with SIGTERM, which must exit 0.
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import os
import random
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from pathlib import Path
from typing import List, Optional

HERE = Path(__file__).resolve().parent
CLIENT_ROOT = HERE.parent                      # clients/python
REPO = CLIENT_ROOT.parent.parent               # the repository
sys.path.insert(0, str(CLIENT_ROOT))

from brisance_client import (Client, Job, JobFailedError, ProblemError,  # noqa: E402
                             TransportError, WaitTimeoutError, parse_brf1, parse_retry_after)
from brisance_client import __main__ as cli  # noqa: E402
from brisance_client import client as client_module  # noqa: E402

BINARY = os.environ.get("BRISANCE_BINARY", "")
START_TIMEOUT_S = 20.0


def load_scene(name: str) -> dict:
    with open(REPO / "scenes" / name, encoding="utf-8") as handle:
        return json.load(handle)


THREE_BLOCKS = load_scene("three_blocks.json")


def slow_scene(bodies: int = 4) -> dict:
    """A job that runs for minutes: boxes falling forever (no ground, no air) with a 10 us step."""
    return {
        "charges": [{"position": [0, 0, -50], "mass": 0.001}],
        "environment": {"ground": None, "air_density": 0},
        "objects": [{"name": "box%d" % i, "shape": {"type": "box", "size": [1, 1, 1]},
                     "position": [3.0 * i, 10, 0], "mass": 1} for i in range(bodies)],
        "simulation": {"duration": 600, "time_step": 1e-5},
    }


def invalid_scene() -> dict:
    scene = copy.deepcopy(THREE_BLOCKS)
    scene["objects"][0]["mass"] = -1
    return scene


class Server:
    """One `brisance serve --port 0` in a temporary data folder; its log goes to a file."""

    def __init__(self, *flags: str) -> None:
        self.dir = tempfile.TemporaryDirectory(prefix="brisance-pytest-")
        self.log_path = Path(self.dir.name) / "serve.log"
        self._log = open(self.log_path, "wb")
        command = [BINARY, "serve", "--port", "0", "--data", str(Path(self.dir.name) / "data"),
                   "--workers", "1", *flags]
        self.process = subprocess.Popen(command, stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=self._log)
        self.port = self._wait_listening()
        self.url = "http://127.0.0.1:%d" % self.port

    def _wait_listening(self) -> int:
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline:
            for line in self.log_path.read_text(errors="replace").splitlines():
                try:
                    event = json.loads(line)
                except ValueError:
                    continue
                if event.get("msg") == "listening":
                    return int(event["port"])
            if self.process.poll() is not None:
                break
            time.sleep(0.02)
        self.process.kill()
        self.process.wait()
        raise RuntimeError("brisance serve did not start (exit %s); log:\n%s"
                           % (self.process.returncode, self.log()))

    def log(self) -> str:
        return self.log_path.read_text(errors="replace")

    def stop(self) -> int:
        """SIGTERM and wait; returns the exit code."""
        try:
            self.process.send_signal(signal.SIGTERM)
            try:
                return self.process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
                return -9
        finally:
            self._log.close()
            self.dir.cleanup()


class ServerTestCase(unittest.TestCase):
    """Starts one server for the class; stopping it with SIGTERM must exit 0."""

    flags: tuple = ()
    server: Server
    client: Client

    @classmethod
    def setUpClass(cls) -> None:
        if not BINARY:
            raise unittest.SkipTest("set BRISANCE_BINARY to the brisance binary")
        if not os.access(BINARY, os.X_OK):
            raise RuntimeError("BRISANCE_BINARY=%s is not an executable" % BINARY)
        cls.server = Server(*cls.flags)
        cls.client = Client(cls.server.url, api_key="", timeout=15, max_retry_wait=10)

    @classmethod
    def tearDownClass(cls) -> None:
        server = getattr(cls, "server", None)
        if server is None:
            return
        log = server.log()
        code = server.stop()
        if code != 0:
            raise AssertionError("brisance serve exited %d on SIGTERM; log:\n%s" % (code, log))

    def tearDown(self) -> None:
        if self.server.process.poll() is not None:
            self.fail("brisance serve died (exit %s); log:\n%s"
                      % (self.server.process.returncode, self.server.log()[-4000:]))

    def run_cli(self, *args: str, env: Optional[dict] = None,
                timeout: float = 60) -> subprocess.CompletedProcess:
        environment = dict(os.environ)
        environment["PYTHONPATH"] = str(CLIENT_ROOT)
        environment.pop("BRISANCE_API_KEY", None)
        environment["BRISANCE_URL"] = self.server.url
        if env:
            environment.update(env)
        return subprocess.run([sys.executable, "-m", "brisance_client", *args], env=environment,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              timeout=timeout, cwd=str(CLIENT_ROOT))


class RecordingSleep:
    """A stand-in for time.sleep: records the delays, optionally runs an action on each call."""

    def __init__(self, action=None) -> None:
        self.delays: List[float] = []
        self.action = action

    def __call__(self, delay: float) -> None:
        self.delays.append(delay)
        if self.action:
            self.action(len(self.delays))


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


# ---------------------------------------------------------------------------------------------


class UnitTest(unittest.TestCase):
    """Parts that need no server."""

    def test_parse_brf1(self) -> None:
        import struct
        data = (b"BRF1" + struct.pack("<III", 7, 2, 2) + struct.pack("<II", 3, 5)
                + struct.pack("<d14f", 0.5, *range(14)) + struct.pack("<d14f", 1.0, *range(14)))
        first, bodies, frames = parse_brf1(data)
        self.assertEqual((first, bodies), (7, [3, 5]))
        self.assertEqual(frames[1][0], 1.0)
        self.assertEqual(frames[0][1][1], ((7.0, 8.0, 9.0), (10.0, 11.0, 12.0, 13.0)))
        with self.assertRaises(Exception):
            parse_brf1(data[:-1])
        with self.assertRaises(Exception):
            parse_brf1(b"XXXX" + data[4:])

    def test_parse_retry_after(self) -> None:
        self.assertEqual(parse_retry_after("5"), 5.0)
        self.assertIsNone(parse_retry_after(None))
        self.assertIsNone(parse_retry_after("soon"))
        self.assertGreaterEqual(parse_retry_after("Wed, 21 Oct 2015 07:28:00 GMT"), 0.0)

    def test_unreachable_server_raises_transport_error_after_backoff(self) -> None:
        sleep = RecordingSleep()
        client = Client("http://127.0.0.1:%d" % free_port(), api_key="", timeout=2,
                        max_retries=3, backoff_base=0.1, sleep=sleep)
        with self.assertRaises(TransportError):
            client.queue()
        self.assertEqual(len(sleep.delays), 3)
        # Capped exponential backoff with jitter in [0.5, 1] of 0.1 * 2**n.
        for n, delay in enumerate(sleep.delays):
            self.assertGreaterEqual(delay, 0.05 * 2 ** n - 1e-9)
            self.assertLessEqual(delay, 0.1 * 2 ** n + 1e-9)

    def test_cli_usage_errors_exit_2(self) -> None:
        err = io.StringIO()
        self.assertEqual(cli.run(["submit", str(HERE / "no-such-scene.json"),
                                  "--url", "http://127.0.0.1:1"], io.StringIO(), err), 2)
        self.assertIn("cannot read", err.getvalue())
        err = io.StringIO()
        self.assertEqual(cli.run(["submit", str(REPO / "scenes" / "three_blocks.json"),
                                  "-o", "out.txt", "--url", "http://127.0.0.1:1"],
                                 io.StringIO(), err), 2)
        with self.assertRaises(SystemExit) as exit_, contextlib.redirect_stderr(io.StringIO()):
            cli.run(["blast", "--charge-kg", "1"], io.StringIO(), io.StringIO())
        self.assertEqual(exit_.exception.code, 2)


# ---------------------------------------------------------------------------------------------


class JobsTest(ServerTestCase):
    """A plain server: submit, wait, results, frames, errors, the CLI."""

    def submit_and_wait(self) -> Job:
        return self.client.wait(self.client.submit(THREE_BLOCKS), timeout=30)

    def test_submit_wait_and_glb(self) -> None:
        job = self.client.submit(THREE_BLOCKS, priority=5)
        self.assertIn(job.status, ("queued", "running", "succeeded"))
        self.assertEqual(job.priority, 5)
        self.assertTrue(job.etag)
        seen: List[Job] = []
        done = self.client.wait(job, timeout=30, progress=seen.append)
        self.assertEqual(done.status, "succeeded")
        self.assertEqual(done.progress, 1.0)
        self.assertIs(seen[-1], done)
        self.assertIsNotNone(done.stats)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "out.glb")
            self.assertEqual(self.client.download_glb(done, path), path)
            with open(path, "rb") as handle:
                data = handle.read()
            self.assertTrue(data.startswith(b"glTF"))
            self.assertEqual(os.listdir(folder), ["out.glb"])  # no temporary file left
            mask = os.umask(0o027)
            os.umask(mask)
            self.assertEqual(stat.S_IMODE(os.stat(path).st_mode), 0o666 & ~mask)
            os.chmod(path, 0o640)  # a file that is replaced keeps its mode
            self.client.download_glb(done, path)
            self.assertEqual(stat.S_IMODE(os.stat(path).st_mode), 0o640)
        self.assertEqual(self.client.glb(done.id), data)
        summary = self.client.result(done)
        self.assertEqual(summary["frame_count"], 61)
        self.assertEqual(summary["job"]["id"], job.id)
        self.assertEqual(self.client.scene(job.id), THREE_BLOCKS)
        self.assertEqual(len(self.client.meshes(job)["bodies"]), 3)

    def test_upload_asset_and_blow_up_the_crate(self) -> None:
        assets = REPO / "tests" / "assets"
        asset = self.client.upload_asset(assets / "crate.glb")
        self.assertEqual(asset["format"], "glb")
        self.assertEqual(asset["nodes"], ["Crate", "Pallet"])
        self.assertEqual(len(asset["id"]), 64)
        self.assertEqual(self.client.upload_asset((assets / "crate.glb").read_bytes(), "glb"),
                         asset)
        self.assertEqual(self.client.asset(asset["id"]), asset)
        with self.assertRaises(ProblemError) as caught:
            self.client.upload_asset(assets / "open_crate.obj")
        self.assertEqual(caught.exception.status, 422)
        self.assertIn("4 edges open", str(caught.exception))
        scene = copy.deepcopy(THREE_BLOCKS)
        scene["objects"] = [{"name": "crate", "position": [0, 0.3, 6], "density": 500,
                             "shape": {"type": "asset", "asset": asset["id"], "node": "Crate"}}]
        done = self.client.wait(self.client.submit(scene), timeout=30)
        self.assertEqual(done.status, "succeeded")
        self.assertAlmostEqual(self.client.result(done)["bodies"][0]["mass"], 240.0, places=3)

    def test_frames_binary_and_json_agree(self) -> None:
        job = self.submit_and_wait()
        binary = list(self.client.frames(job))
        as_json = list(self.client.frames(job, binary=False))
        self.assertEqual(len(binary), 61)
        self.assertEqual(binary, as_json)
        self.assertEqual([f[0] for f in binary], list(range(61)))
        index, time_s, poses = binary[30]
        self.assertAlmostEqual(time_s, 1.0)
        self.assertEqual(sorted(poses), self.client.result(job)["animated"])
        for position, orientation in poses.values():
            self.assertEqual((len(position), len(orientation)), (3, 4))
        # Sub-ranges in small chunks, explicit bodies (in the order asked), none at all.
        part_b = list(self.client.frames(job, 10, 25, bodies=[2, 0], chunk=4))
        part_j = list(self.client.frames(job, 10, 25, bodies=[2, 0], binary=False, chunk=6))
        self.assertEqual(part_b, part_j)
        self.assertEqual([f[0] for f in part_b], list(range(10, 25)))
        self.assertEqual(list(part_b[0][2]), [2, 0])
        self.assertEqual(part_b[5][2][0], binary[15][2][0])
        empty = list(self.client.frames(job, 0, 3, bodies=[]))
        self.assertEqual([f[2] for f in empty], [{}, {}, {}])
        self.assertEqual(list(self.client.frames(job, 5, 5)), [])

    def test_brisance_run_writes_the_frames_the_server_serves(self) -> None:
        """One frame shape: `brisance run -o OUT.brf` holds the served BRF1 bytes, and the
        frames of `-o OUT.json` are the served JSON frames before float32 rounding."""
        import struct
        job = self.submit_and_wait()
        served_brf = self.client.request("GET", "/v1/jobs/%s/frames" % job.id,
                                         accept="application/octet-stream").body
        served = self.client.request("GET", "/v1/jobs/%s/frames" % job.id).json()["frames"]
        with tempfile.TemporaryDirectory() as folder:
            scene = os.path.join(folder, "scene.json")
            with open(scene, "w", encoding="utf-8") as handle:
                json.dump(THREE_BLOCKS, handle)
            outputs = {}
            for extension in ("brf", "json"):
                outputs[extension] = os.path.join(folder, "out." + extension)
                subprocess.run([BINARY, "run", scene, "-o", outputs[extension]], check=True,
                               stdout=subprocess.DEVNULL, timeout=60)
            with open(outputs["brf"], "rb") as handle:
                self.assertEqual(handle.read(), served_brf)
            with open(outputs["json"], encoding="utf-8") as handle:
                local = json.load(handle)["frames"]

        def float32(x: float) -> float:
            return struct.unpack("<f", struct.pack("<f", x))[0]

        self.assertEqual(len(local), 61)
        self.assertEqual(len(local), len(served))
        for mine, theirs in zip(local, served):
            self.assertEqual(sorted(mine), ["index", "poses", "time"])
            self.assertEqual((mine["index"], mine["time"]), (theirs["index"], theirs["time"]))
            self.assertEqual([p["body"] for p in mine["poses"]],
                             [p["body"] for p in theirs["poses"]])
            for p, q in zip(mine["poses"], theirs["poses"]):
                self.assertEqual(sorted(p), ["body", "orientation", "position"])
                for key in ("position", "orientation"):
                    self.assertEqual([float32(x) for x in p[key]], q[key])

    def test_frames_out_of_range_is_invalid_parameter(self) -> None:
        job = self.submit_and_wait()
        with self.assertRaises(ProblemError) as caught:
            list(self.client.frames(job, 0, 62))
        self.assertEqual(caught.exception.status, 400)
        self.assertEqual(caught.exception.kind, "invalid-parameter")
        self.assertEqual([p for p, _ in caught.exception.parameters], ["to"])

    def test_validation_error_carries_pointers(self) -> None:
        with self.assertRaises(ProblemError) as caught:
            self.client.submit(invalid_scene())
        problem = caught.exception
        self.assertEqual(problem.status, 422)
        self.assertEqual(problem.type, "urn:brisance:problem:invalid-scene")
        self.assertEqual(problem.kind, "invalid-scene")
        self.assertTrue(problem.title)
        self.assertTrue(problem.detail)
        self.assertEqual([p for p, _ in problem.errors], ["/scene/objects/0/mass"])
        self.assertIn("mass", problem.errors[0][1])
        self.assertIn("/scene/objects/0/mass", str(problem))
        # Several problems at once, every one with its pointer.
        scene = copy.deepcopy(THREE_BLOCKS)
        scene["charges"][0]["mass"] = -1
        scene["objects"][1]["shape"]["size"][1] = 0
        with self.assertRaises(ProblemError) as caught:
            self.client.submit(scene, priority=500)
        pointers = {p for p, _ in caught.exception.errors}
        self.assertEqual(pointers, {"/scene/charges/0/mass", "/scene/objects/1/shape/size/1",
                                    "/priority"})

    def test_idempotency_key(self) -> None:
        key = "test-idempotency-key"
        first = self.client.submit(THREE_BLOCKS, idempotency_key=key)
        again = self.client.submit(THREE_BLOCKS, idempotency_key=key)
        self.assertEqual(again.id, first.id)
        other = copy.deepcopy(THREE_BLOCKS)
        other["simulation"]["duration"] = 1
        with self.assertRaises(ProblemError) as caught:
            self.client.submit(other, idempotency_key=key)
        self.assertEqual((caught.exception.status, caught.exception.kind),
                         (422, "idempotency-key-reused"))

    def test_submit_retried_after_lost_response_makes_one_job(self) -> None:
        """The first attempt reaches the server but its answer is lost: the retry, with the same
        Idempotency-Key, gets that job back instead of making a second one."""
        sleep = RecordingSleep()
        client = Client(self.server.url, api_key="", timeout=15, backoff_base=0.01, sleep=sleep)
        real = client._exchange
        calls: List[int] = []

        def lossy(request, timeout, ok, sink):
            response = real(request, timeout, ok, sink)
            calls.append(response.status)
            if len(calls) == 1:
                raise client_module._Transport(ConnectionResetError("answer lost"))
            return response

        client._exchange = lossy  # type: ignore[assignment]
        before = sum(1 for _ in self.client.jobs(limit=500))
        job = client.submit(THREE_BLOCKS)
        self.assertEqual(calls, [202, 200])
        self.assertEqual(len(sleep.delays), 1)
        self.assertEqual(sum(1 for _ in self.client.jobs(limit=500)), before + 1)
        self.assertEqual(self.client.job(job).id, job.id)

    def test_etag_and_long_poll_of_a_finished_job(self) -> None:
        job = self.submit_and_wait()
        again = self.client.job(job.id)
        self.assertEqual(again.etag, job.etag)
        started = time.monotonic()
        self.assertIs(self.client.poll(job, wait=10), job)  # 304: unchanged, and never parked
        self.assertLess(time.monotonic() - started, 5)
        stale = Job(job.data, '"%s.0"' % job.id)
        self.assertEqual(self.client.poll(stale, wait=10).etag, job.etag)  # 200 at once
        self.assertIs(self.client.wait(job), job)

    def test_missing_job_is_not_found(self) -> None:
        with self.assertRaises(ProblemError) as caught:
            self.client.job("j000000000000000000000000")
        self.assertEqual((caught.exception.status, caught.exception.kind), (404, "not-found"))
        self.assertTrue(caught.exception.request_id)

    def test_cancel_finished_job_conflicts_and_delete(self) -> None:
        job = self.submit_and_wait()
        with self.assertRaises(ProblemError) as caught:
            self.client.cancel(job)
        self.assertEqual((caught.exception.status, caught.exception.kind), (409, "job-finished"))
        self.client.delete(job)
        with self.assertRaises(ProblemError) as caught:
            self.client.job(job)
        self.assertEqual(caught.exception.status, 404)

    def test_names_and_labels(self) -> None:
        tag = "t%d" % random.randrange(10**9)  # the server is shared by the tests
        first = self.client.submit(THREE_BLOCKS, name="Facade shot 12",
                                   labels={"run": tag, "shot": "sq010"})
        second = self.client.submit(THREE_BLOCKS, name="Crate", labels={"run": tag})
        self.assertEqual(first.name, "Facade shot 12")
        self.assertEqual(first.labels, {"run": tag, "shot": "sq010"})
        self.assertEqual([job.id for job in self.client.jobs(labels={"run": tag})],
                         [second.id, first.id])
        self.assertEqual([job.id for job in self.client.jobs(labels={"run": tag, "shot": None})],
                         [first.id])
        self.assertEqual([job.id for job in self.client.jobs(labels={"run": tag},
                                                             name="facade")], [first.id])
        with self.assertRaises(ProblemError) as caught:
            self.client.submit(THREE_BLOCKS, labels={"bad key": "x"})
        self.assertEqual(caught.exception.status, 422)
        self.assertIn("/labels/bad key", [pointer for pointer, _ in caught.exception.errors])

    def test_list_jobs_pages(self) -> None:
        for _ in range(3):
            self.client.submit(THREE_BLOCKS)
        ids = [job.id for job in self.client.jobs(limit=2)]
        self.assertGreaterEqual(len(ids), 3)
        self.assertEqual(len(ids), len(set(ids)))
        for job in self.client.jobs(status="succeeded", limit=1):
            self.assertEqual(job.status, "succeeded")

    def test_service_views(self) -> None:
        blast = self.client.blast(100, 15)
        self.assertEqual(blast["tnt_equivalent_kg"], 100)
        self.assertTrue(blast["in_validity_range"])
        c4 = self.client.blast(100, 15, explosive="C4", burst="surface", angle_deg=30)
        self.assertGreater(c4["tnt_equivalent_kg"], 100)
        with self.assertRaises(ProblemError) as caught:
            self.client.blast(-1, 15)
        self.assertEqual(caught.exception.parameters[0][0], "charge_kg")
        self.assertIn("TNT", [e["name"] for e in self.client.explosives()])
        self.assertEqual(blast["inputs"]["explosive"], "TNT")

    def test_response_and_pi(self) -> None:
        # m = 100 kg, k = 1e6 N/m (omega = 100 rad/s); a 0.05 ms triangle of 1000 kPa carries
        # I = 25 Pa*s: the impulsive response I A / (m omega) = 2.5 mm.
        element = {"mass_kg": 100, "loaded_area_m2": 1,
                   "resistance": {"type": "elastic_plastic", "stiffness_n_per_m": 1e6,
                                  "yield_resistance_n": 1e4}}
        r = self.client.response(element, pulse={"peak_kpa": 1000, "duration_ms": 0.05})
        self.assertAlmostEqual(r["peak_displacement_m"], 2.5e-3, delta=2.5e-6)
        self.assertIsNone(r["damage"])
        self.assertEqual(len(r["history"]["time_ms"]), len(r["history"]["displacement_m"]))
        charged = self.client.response(element, charge={"charge_kg": 100, "distance_m": 15},
                                       history=False)
        self.assertNotIn("history", charged)
        self.assertAlmostEqual(charged["load"]["peak_pressure_kpa"],
                               self.client.blast(100, 15)["reflected_overpressure_kpa"])
        # mu = 2, y = 20 mm: impulsive asymptote sqrt(2 m R_y (y - y_el / 2)) / A
        # = sqrt(2 * 100 * 1e4 * 0.015) = 173.2 Pa*s; quasi-static R_y (1 - 1 / (2 mu)) = 7.5 kPa.
        curve = self.client.pi(element, ductility=2, points=6)
        self.assertAlmostEqual(curve["impulsive_asymptote_kpa_ms"], (2 * 100 * 1e4 * 0.015) ** 0.5)
        self.assertAlmostEqual(curve["quasi_static_asymptote_kpa"], 7.5)
        self.assertEqual(len(curve["points"]), 6)
        # The W-R diagram of the same limit: the charge grows with the stand-off.
        wr = self.client.wr(element, ductility=2, points=3, distances_m=[5, 20])
        self.assertEqual(wr["diagram"], "wr")
        charges = [p["charge_kg"] for p in wr["points"]]
        self.assertEqual([p["distance_m"] for p in wr["points"]][1], 10.0)
        self.assertLess(charges[0], charges[1])
        self.assertLess(charges[1], charges[2])
        with self.assertRaises(ProblemError) as caught:
            self.client.wr(element, ductility=2, burst="ground", distances_m=[5, 1])
        self.assertEqual([p for p, _ in caught.exception.errors], ["/distances_m", "/burst"])
        with self.assertRaises(ProblemError) as caught:
            self.client.response(dict(element, mass_kg=-1), pulse={"peak_kpa": 1})
        self.assertEqual((caught.exception.status, caught.exception.kind), (422, "invalid-input"))
        self.assertEqual([p for p, _ in caught.exception.errors],
                         ["/element/mass_kg", "/pulse/duration_ms"])
        queue = self.client.queue()
        self.assertEqual(set(queue["counts"]),
                         {"queued", "running", "succeeded", "failed", "cancelled"})
        self.assertEqual(queue["workers"]["total"], 1)
        self.assertEqual(self.client.health(), {"status": "ok"})
        self.assertTrue(self.client.ready())
        self.assertTrue(self.client.metrics().startswith("# HELP brisance_"))
        self.assertTrue(self.client.openapi().startswith("openapi: 3.1."))

    # --------------------------------------------------------------------------- the CLI

    def test_cli_submit_wait_glb(self) -> None:
        with tempfile.TemporaryDirectory() as folder:
            out = os.path.join(folder, "out.glb")
            done = self.run_cli("submit", str(REPO / "scenes" / "three_blocks.json"), "--wait",
                                "-o", out, "--url", self.server.url, "--progress")
            self.assertEqual(done.returncode, 0, done.stderr)
            job_id = done.stdout.strip()
            self.assertRegex(job_id, r"^j[0-9a-f]{24}$")
            self.assertIn("100.0%", done.stderr)  # --progress reports on a pipe too,
            self.assertNotIn("\r", done.stderr)  # as plain lines
            self.assertRegex(done.stderr, r"(?m)^succeeded +100\.0%.*done$")
            with open(out, "rb") as handle:
                self.assertEqual(handle.read(4), b"glTF")
            self.assertEqual(self.client.job(job_id).status, "succeeded")

            summary = os.path.join(folder, "out.json")
            done = self.run_cli("submit", str(REPO / "scenes" / "three_blocks.json"), "-o",
                                summary, "--priority", "3")
            self.assertEqual(done.returncode, 0, done.stderr)
            self.assertNotIn("[", done.stderr)  # no bar when stderr is not a terminal
            with open(summary, encoding="utf-8") as handle:
                result = json.load(handle)
            self.assertEqual(result["frame_count"], 61)
            self.assertEqual(result["job"]["priority"], 3)

    def test_cli_response_and_pi(self) -> None:
        wall = str(REPO / "scenes" / "elements" / "rc_wall.json")
        done = self.run_cli("response", "--element", wall, "--charge-kg", "100", "--distance-m", "15")
        self.assertEqual(done.returncode, 0, done.stderr)
        answer = json.loads(done.stdout)
        self.assertEqual(answer["limits"], "rc_flexure")
        self.assertAlmostEqual(answer["load"]["peak_pressure_kpa"],
                               self.client.blast(100, 15)["reflected_overpressure_kpa"])
        done = self.run_cli("pi", "--element", wall, "--ductility", "3", "--points", "5")
        self.assertEqual(done.returncode, 0, done.stderr)
        # rc_wall.json: K_M m = 720 kg, K_L = 0.64, R_y = 111.7 kN, y_el = R_y / k; at mu = 3 the
        # impulsive asymptote is sqrt(2 K_M m R_y (3 - 1/2) y_el / K_L) / A (docs/response.md).
        y_el = 111700 / 2.844e7
        expected = (2 * 720 * 111700 * 2.5 * y_el / 0.64) ** 0.5 / 3
        self.assertAlmostEqual(json.loads(done.stdout)["impulsive_asymptote_kpa_ms"], expected,
                               delta=1e-9 * expected)
        done = self.run_cli("response", "--element", wall, "--pulse-peak-kpa", "-1",
                            "--pulse-duration-ms", "5")
        self.assertEqual(done.returncode, 2, done.stderr)
        self.assertRegex(done.stderr, r"(?m)^/pulse/peak_kpa: ")
        done = self.run_cli("response", "--element", wall)
        self.assertEqual(done.returncode, 2, done.stderr)

    def test_cli_invalid_scene_exits_2_with_pointers(self) -> None:
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "bad.json")
            with open(path, "w", encoding="utf-8") as handle:
                json.dump(invalid_scene(), handle)
            done = self.run_cli("submit", path, "--wait", "-o", os.path.join(folder, "o.glb"))
            self.assertEqual(done.returncode, 2, done.stderr)
            self.assertEqual(done.stdout, "")
            self.assertRegex(done.stderr, r"(?m)^/scene/objects/0/mass: .*mass")
            self.assertFalse(os.path.exists(os.path.join(folder, "o.glb")))
            with open(path, "w", encoding="utf-8") as handle:
                handle.write("{not json")
            done = self.run_cli("submit", path)
            self.assertEqual(done.returncode, 2, done.stderr)

    def test_cli_status_blast_and_failures(self) -> None:
        job = self.submit_and_wait()
        done = self.run_cli("status", job.id)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(json.loads(done.stdout)["status"], "succeeded")
        done = self.run_cli("blast", "--charge-kg", "100", "--distance-m", "15")
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(json.loads(done.stdout)["tnt_equivalent_kg"], 100)
        done = self.run_cli("status", "j000000000000000000000000")
        self.assertEqual(done.returncode, 1)
        self.assertIn("404", done.stderr)
        done = self.run_cli("cancel", job.id)
        self.assertEqual(done.returncode, 1)
        self.assertIn("409", done.stderr)
        done = self.run_cli("blast", "--charge-kg", "-1", "--distance-m", "15")
        self.assertEqual(done.returncode, 2)
        self.assertRegex(done.stderr, r"(?m)^charge_kg: ")


# ---------------------------------------------------------------------------------------------


class BackpressureTest(ServerTestCase):
    """--max-queue 1 and one worker busy with a job of minutes: submissions get 429."""

    flags = ("--max-queue", "1", "--grace-s", "0")

    def setUp(self) -> None:
        """Every test starts with one slow job running and one queued (the queue is full)."""
        no_retry = Client(self.server.url, api_key="", timeout=15, max_retries=0)
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            counts = self.client.queue()["counts"]
            if counts["running"] >= 1 and counts["queued"] >= 1:
                running = list(self.client.jobs(status="running"))
                queued = list(self.client.jobs(status="queued"))
                if running and queued:
                    self.running, self.queued = running[0], queued[0]
                    return
            if counts["queued"] == 0:
                try:
                    no_retry.submit(slow_scene())
                except ProblemError as problem:  # the server's queued count lags by <= 100 ms
                    self.assertEqual(problem.status, 429)
            time.sleep(0.05)
        self.fail("could not fill the queue: %r" % self.client.queue())

    def full_queue_client(self, **options) -> Client:
        options.setdefault("api_key", "")
        options.setdefault("timeout", 15)
        return Client(self.server.url, **options)

    def test_429_gives_up_at_once_when_retry_after_exceeds_budget(self) -> None:
        sleep = RecordingSleep()
        client = self.full_queue_client(max_retry_wait=1, sleep=sleep)
        with self.assertRaises(ProblemError) as caught:
            client.submit(slow_scene())
        problem = caught.exception
        self.assertEqual((problem.status, problem.kind), (429, "queue-full"))
        self.assertEqual(problem.retry_after, 5)
        self.assertEqual(sleep.delays, [])  # never waits less than Retry-After

    def test_429_retries_honour_retry_after_then_raise(self) -> None:
        sleep = RecordingSleep()
        client = self.full_queue_client(max_retries=2, max_retry_wait=60, sleep=sleep)
        with self.assertRaises(ProblemError) as caught:
            client.submit(slow_scene())
        self.assertEqual(caught.exception.status, 429)
        self.assertEqual(len(sleep.delays), 2)
        for delay in sleep.delays:
            self.assertGreaterEqual(delay, 5)
            self.assertLessEqual(delay, 30)
        self.assertEqual(self.client.queue()["counts"]["queued"], 1)  # nothing was added

    def test_429_retry_succeeds_once_room_is_made(self) -> None:
        def make_room(n: int) -> None:
            if n == 1:
                self.client.cancel(self.queued)
                time.sleep(0.2)  # the server's queued count may be up to 100 ms old

        sleep = RecordingSleep(action=make_room)
        client = self.full_queue_client(max_retries=3, sleep=sleep)
        job = client.submit(slow_scene())
        self.assertEqual(job.status, "queued")
        self.assertEqual(len(sleep.delays), 1)
        self.assertGreaterEqual(sleep.delays[0], 5)

    def test_429_real_wait_is_not_shorter_than_retry_after(self) -> None:
        """With the real clock: room is made after 0.5 s, yet the retry comes after 5 s."""
        timer = threading.Timer(0.5, lambda: self.client.cancel(self.queued))
        timer.start()
        try:
            client = self.full_queue_client(max_retries=1, max_retry_wait=10)
            started = time.monotonic()
            job = client.submit(slow_scene())
            elapsed = time.monotonic() - started
        finally:
            timer.join()
        self.assertEqual(job.status, "queued")
        self.assertGreaterEqual(elapsed, 5.0)
        self.assertLess(elapsed, 9.0)

    def test_idempotent_retry_of_accepted_job_while_full(self) -> None:
        scene = slow_scene(bodies=3)
        self.client.cancel(self.queued)
        time.sleep(0.2)  # the server's queued count may be up to 100 ms old
        first = self.client.submit(scene, idempotency_key="full-queue-key")
        self.assertEqual(self.client.queue()["counts"]["queued"], 1)
        again = self.full_queue_client(max_retries=0).submit(scene,
                                                            idempotency_key="full-queue-key")
        self.assertEqual(again.id, first.id)

    def test_cancel_queued_job(self) -> None:
        job = self.client.cancel(self.queued)
        self.assertEqual(job.status, "cancelled")
        with self.assertRaises(JobFailedError) as caught:
            self.client.wait(job.id, timeout=10)
        self.assertEqual(caught.exception.job.status, "cancelled")
        final = self.client.wait(job.id, timeout=10, raise_on_failure=False)
        self.assertEqual(final.status, "cancelled")

    def test_cancel_running_job(self) -> None:
        job = self.client.cancel(self.running)
        self.assertTrue(job.cancel_requested)
        self.assertIn(job.status, ("running", "cancelled"))
        with self.assertRaises(JobFailedError) as caught:
            self.client.wait(job, timeout=20)
        self.assertEqual(caught.exception.job.status, "cancelled")
        self.assertIn("cancelled", str(caught.exception))

    def test_delete_queued_job(self) -> None:
        self.client.delete(self.queued)
        with self.assertRaises(ProblemError) as caught:
            self.client.job(self.queued)
        self.assertEqual(caught.exception.status, 404)

    def test_running_job_result_not_ready_and_wait_timeout(self) -> None:
        with self.assertRaises(ProblemError) as caught:
            self.client.result(self.running)
        self.assertEqual((caught.exception.status, caught.exception.kind),
                         (409, "result-not-ready"))
        self.assertEqual(caught.exception.retry_after, 1)
        started = time.monotonic()
        seen: List[Job] = []
        with self.assertRaises(WaitTimeoutError) as timeout:
            self.client.wait(self.running, timeout=1.5, progress=seen.append)
        self.assertLess(time.monotonic() - started, 5)
        self.assertEqual(timeout.exception.job.status, "running")
        self.assertTrue(seen)
        self.assertEqual({job.status for job in seen}, {"running"})
        progress = [job.progress for job in seen]
        self.assertEqual(progress, sorted(progress))  # each change reported, in order

    def test_cli_cancel_and_cancelled_wait_exits_1(self) -> None:
        done = self.run_cli("cancel", self.queued.id)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(json.loads(done.stdout)["status"], "cancelled")
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "slow.json")
            with open(path, "w", encoding="utf-8") as handle:
                json.dump(slow_scene(), handle)
            environment = dict(os.environ, PYTHONPATH=str(CLIENT_ROOT),
                               BRISANCE_URL=self.server.url)
            process = subprocess.Popen(
                [sys.executable, "-m", "brisance_client", "submit", path, "--wait"],
                env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            try:
                job_id = process.stdout.readline().strip()
                self.assertRegex(job_id, r"^j[0-9a-f]{24}$")
                self.client.cancel(job_id)
                _, stderr = process.communicate(timeout=30)
            finally:
                if process.poll() is None:
                    process.kill()
                    process.wait()
            self.assertEqual(process.returncode, 1, stderr)
            self.assertIn("cancelled", stderr)


# ---------------------------------------------------------------------------------------------


class ApiKeyTest(ServerTestCase):
    """--api-keys: no key or an unknown one is 401, a read key may not write (403)."""

    @classmethod
    def setUpClass(cls) -> None:
        if not BINARY:
            raise unittest.SkipTest("set BRISANCE_BINARY to the brisance binary")
        cls.keys_dir = tempfile.TemporaryDirectory(prefix="brisance-keys-")
        lines = []
        cls.keys = {}
        for scope in ("read", "write"):
            made = subprocess.run([BINARY, "api-key", "--name", "t" + scope, "--scope", scope],
                                  stdout=subprocess.PIPE, text=True, check=True, timeout=30)
            fields = dict(line.split(":", 1) for line in made.stdout.splitlines() if ":" in line)
            cls.keys[scope] = fields["key"].strip()
            lines.append(fields["line"].strip())
        path = os.path.join(cls.keys_dir.name, "keys")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write("# NAME SCOPE HASH\n" + "\n".join(lines) + "\n")
        cls.flags = ("--api-keys", path)
        super().setUpClass()

    @classmethod
    def tearDownClass(cls) -> None:
        try:
            super().tearDownClass()
        finally:
            cls.keys_dir.cleanup()

    def keyed(self, key: str) -> Client:
        return Client(self.server.url, api_key=key, timeout=15, max_retry_wait=5)

    def test_no_or_unknown_key_is_unauthorized(self) -> None:
        for key in ("", "bk_" + "0" * 40):
            with self.assertRaises(ProblemError) as caught:
                self.keyed(key).queue()
            self.assertEqual((caught.exception.status, caught.exception.kind),
                             (401, "unauthorized"))
        self.assertEqual(self.keyed("").health(), {"status": "ok"})  # probes need no key
        self.assertTrue(self.keyed("").ready())

    def test_read_key_reads_but_may_not_write(self) -> None:
        reader = self.keyed(self.keys["read"])
        self.assertIn("counts", reader.queue())
        with self.assertRaises(ProblemError) as caught:
            reader.submit(THREE_BLOCKS)
        self.assertEqual((caught.exception.status, caught.exception.kind), (403, "forbidden"))

    def test_write_key_runs_a_job(self) -> None:
        writer = self.keyed(self.keys["write"])
        job = writer.run(THREE_BLOCKS, timeout=30)
        self.assertEqual(job.status, "succeeded")
        self.assertTrue(writer.glb(job).startswith(b"glTF"))
        # The job is the write key's own: another key does not see it (docs/service.md).
        with self.assertRaises(ProblemError) as caught:
            self.keyed(self.keys["read"]).job(job)
        self.assertEqual((caught.exception.status, caught.exception.kind), (404, "not-found"))

    def test_cli_keys(self) -> None:
        scene = str(REPO / "scenes" / "three_blocks.json")
        done = self.run_cli("submit", scene)
        self.assertEqual(done.returncode, 1)
        self.assertIn("401", done.stderr)
        done = self.run_cli("submit", scene, "--api-key", self.keys["read"])
        self.assertEqual(done.returncode, 1)
        self.assertIn("403", done.stderr)
        done = self.run_cli("submit", scene, "--wait",
                            env={"BRISANCE_API_KEY": self.keys["write"]})
        self.assertEqual(done.returncode, 0, done.stderr)


if __name__ == "__main__":
    unittest.main()
