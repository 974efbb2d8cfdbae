"""Checks of deploy/ that need no container runtime and no systemd as PID 1 (CTest: deploy.*).

  SystemdUnit      systemd-analyze verify and security on deploy/systemd/brisance.service (a copy
                   whose ExecStart names the built binary), and its stop timeout against --grace-s.
  SystemdSandbox   the unit's ExecStart traced (strace) through a whole life: its system calls,
                   sockets, memory mappings, writes and /proc reads against the unit's sandbox.
  Dockerfile       the image's stages and files; its scripts through shellcheck; its runtime
                   packages against the shared libraries of the built binary (ldd, dpkg -S); the
                   build stage's sources against a CMake configure of just those.
  RunForms         each form's command line and settings run for real against a temporary data
                   folder: the unit's ExecStart with its environment, the image's entry point and
                   healthcheck with its ENV, the compose nodes' and the Kubernetes ConfigMap's
                   settings. Each serves /healthz and /readyz, runs a job, and on SIGTERM exits 0
                   within the stop timeout of its form. And docs/deploy.md's SQLite online
                   backup, taken while serving.

Run: BRISANCE_BINARY=build/.../brisance python3 tests/deploy/deploy_test.py -v [CLASS ...]
Standard library only, plus the Debian tools named in each test (make deploy-test-deps).
"""
from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
import urllib.error
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DEPLOY = ROOT / "deploy"
BINARY = os.path.abspath(os.environ["BRISANCE_BINARY"]) if os.environ.get("BRISANCE_BINARY") else ""
# `brisance serve` finishes requests in flight for up to 10 s before running jobs get --grace-s
# (cli/serve_command.cpp).
REQUEST_DRAIN_S = 10
THREE_BLOCKS = json.loads((ROOT / "scenes" / "three_blocks.json").read_text())
# A job that runs for minutes (as in clients/python/tests): boxes falling forever, 10 us steps.
SLOW_SCENE = {
    "charges": [{"position": [0, 0, -50], "mass": 0.001}],
    "environment": {"ground": None, "air_density": 0},
    "objects": [{"name": f"box{i}", "shape": {"type": "box", "size": [1, 1, 1]},
                 "position": [3.0 * i, 10, 0], "mass": 1} for i in range(4)],
    "simulation": {"duration": 600, "time_step": 1e-5},
}


def require_binary(test: unittest.TestCase) -> None:
    if not BINARY or not os.access(BINARY, os.X_OK):
        test.fail("set BRISANCE_BINARY to the built brisance binary")


# --- reading the files --------------------------------------------------------------------------


def read_unit(path: Path) -> dict[str, list[tuple[str, str]]]:
    """A systemd unit as {section: [(key, value), ...]}; keys may repeat, lines may continue."""
    sections: dict[str, list[tuple[str, str]]] = {}
    current = None
    pending = ""
    for raw in path.read_text().splitlines():
        line = pending + raw.strip()
        pending = ""
        if line.endswith("\\"):
            pending = line[:-1] + " "
            continue
        if not line or line.startswith(("#", ";")):
            continue
        if line.startswith("[") and line.endswith("]"):
            current = line[1:-1]
            sections.setdefault(current, [])
        elif current is not None and "=" in line:
            key, value = line.split("=", 1)
            sections[current].append((key.strip(), value.strip()))
    return sections


def unit_value(unit: dict, section: str, key: str) -> str | None:
    values = [v for k, v in unit.get(section, []) if k == key]
    return values[-1] if values else None


def read_env_file(path: Path) -> dict[str, str]:
    env = {}
    for line in path.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        key, value = line.split("=", 1)
        env[key.strip()] = value.strip().strip('"')
    return env


def systemd_seconds(text: str) -> float:
    """'40', '40s', '1min 30s' -> seconds."""
    units = {"": 1, "s": 1, "sec": 1, "m": 60, "min": 60, "h": 3600}
    total = 0.0
    for number, unit in re.findall(r"(\d+(?:\.\d+)?)\s*([a-z]*)", text):
        total += float(number) * units[unit]
    return total


def flag_value(args: list[str], flag: str) -> str | None:
    for i, arg in enumerate(args):
        if arg == flag and i + 1 < len(args):
            return args[i + 1]
        if arg.startswith(flag + "="):
            return arg.split("=", 1)[1]
    return None


def dockerfile_stages(path: Path) -> list[dict]:
    """The Dockerfile's stages: base image, name and instructions (continuations joined)."""
    text = re.sub(r"\\\n", " ", path.read_text())
    stages: list[dict] = []
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        instruction, _, rest = line.partition(" ")
        instruction = instruction.upper()
        if instruction == "FROM":
            parts = rest.split()
            stages.append({"base": parts[0], "name": parts[2] if len(parts) > 2 else None,
                           "lines": []})
        elif stages:
            stages[-1]["lines"].append((instruction, rest.strip()))
    return stages


def dockerfile_env(stage: dict) -> dict[str, str]:
    env = {}
    for instruction, rest in stage["lines"]:
        if instruction == "ENV":
            for key, value in re.findall(r"(\w+)=(\S+)", rest):
                env[key] = value
    return env


def simple_yaml_map(path: Path, key: str) -> dict[str, str]:
    """The flat `key:` map of string values in a small YAML file (a ConfigMap's data): enough for
    the files in deploy/, whose schemas tests/deploy/manifests.mjs checks with a real parser."""
    values: dict[str, str] = {}
    inside = False
    for line in path.read_text().splitlines():
        if re.match(rf"^{key}:\s*$", line):
            inside = True
            continue
        if inside:
            if line and not line.startswith(" "):
                break
            match = re.match(r"^\s+([A-Z_0-9]+):\s*(.*)$", line)
            if match:
                values[match.group(1)] = match.group(2).strip().strip('"')
    return values


def variables_read() -> set[str]:
    names: set[str] = set()
    for folder in ("cli", "server"):
        for source in (ROOT / folder).rglob("*.[ch]pp"):
            names.update(re.findall(r'"(BRISANCE_[A-Z0-9_]+)"', source.read_text()))
    return names


# --- running a server ---------------------------------------------------------------------------


class Server:
    """A `brisance serve` process started from some command line, its log read on a thread."""

    def __init__(self, args: list[str], env: dict[str, str], cwd: Path):
        self.log: list[str] = []
        self.listening = threading.Event()
        self.port = 0
        self.process = subprocess.Popen(args, env=env, cwd=cwd, stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                        text=True)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.process.stderr is not None
        for line in self.process.stderr:
            self.log.append(line.rstrip("\n"))
            try:
                event = json.loads(line)
            except ValueError:
                continue
            if event.get("msg") == "listening" and not self.port:
                self.port = int(event["port"])
                self.listening.set()

    def wait_listening(self, test: unittest.TestCase, timeout_s: float = 30) -> None:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline and self.process.poll() is None:
            if self.listening.wait(0.1):
                return
        self.stop_now()
        test.fail("no 'listening' line; log:\n" + "\n".join(self.log))

    def event(self, message: str) -> dict | None:
        for line in self.log:
            try:
                event = json.loads(line)
            except ValueError:
                continue
            if event.get("msg") == message:
                return event
        return None

    def request(self, method: str, path: str, body: dict | None = None,
                headers: dict | None = None) -> tuple[int, dict, bytes]:
        data = json.dumps(body).encode() if body is not None else None
        request = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", data=data,
                                         method=method, headers=headers or {})
        if data is not None:
            request.add_header("Content-Type", "application/json")
        try:
            with urllib.request.urlopen(request, timeout=30) as response:
                return response.status, dict(response.headers), response.read()
        except urllib.error.HTTPError as error:
            return error.code, dict(error.headers), error.read()

    def terminate(self, limit_s: float, pid: int | None = None) -> tuple[int | None, float]:
        """SIGTERM to the server (or to pid: the server under strace); the exit code (None if it
        outlived limit_s and was killed) and the time."""
        start = time.monotonic()
        if pid is None:
            self.process.send_signal(signal.SIGTERM)
        else:
            os.kill(pid, signal.SIGTERM)
        try:
            code = self.process.wait(timeout=limit_s)
        except subprocess.TimeoutExpired:
            self.stop_now()
            return None, time.monotonic() - start
        self.reader.join(timeout=5)
        return code, time.monotonic() - start

    def stop_now(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.reader.join(timeout=5)
        if self.process.stderr is not None:
            self.process.stderr.close()


# --- systemd ------------------------------------------------------------------------------------


class SystemdUnit(unittest.TestCase):
    """deploy/systemd/brisance.service with Debian's systemd-analyze (no running systemd needed)."""

    unit_path = DEPLOY / "systemd" / "brisance.service"
    env_path = DEPLOY / "systemd" / "brisance.env"

    def setUp(self) -> None:
        require_binary(self)
        if shutil.which("systemd-analyze") is None:
            self.fail("systemd-analyze not found: install the Debian package systemd "
                      "(make test does)")
        self.folder = Path(tempfile.mkdtemp(prefix="brisance-unit-"))
        self.addCleanup(shutil.rmtree, self.folder, ignore_errors=True)

    def copy_with_binary(self, text: str) -> Path:
        """The unit with ExecStart's program replaced by the built binary: verify checks that
        the program exists and is executable."""
        copy = self.folder / "brisance.service"
        copy.write_text(text.replace("ExecStart=/usr/local/bin/brisance ", f"ExecStart={BINARY} "))
        return copy

    def verify(self, unit: Path) -> str:
        """systemd-analyze verify's complaints (it exits 0 on unknown keys: any output counts)."""
        run = subprocess.run(["systemd-analyze", "verify", "--man=no", str(unit)],
                             capture_output=True, text=True, timeout=60)
        status = "" if run.returncode == 0 else f" (exit {run.returncode})"
        return (run.stdout + run.stderr).strip() + status

    def test_verify_is_clean(self) -> None:
        text = self.unit_path.read_text()
        self.assertIn("ExecStart=/usr/local/bin/brisance serve", text)
        self.assertEqual(self.verify(self.copy_with_binary(text)), "")

    def test_verify_catches_mistakes(self) -> None:
        text = self.unit_path.read_text()
        self.assertIn("Unknown key", self.verify(self.copy_with_binary(
            text.replace("TimeoutStopSec=", "TimeoutStopSc="))))
        self.assertIn("not executable", self.verify(self.copy_with_binary(
            text.replace("ExecStart=/usr/local/bin/brisance ", "ExecStart=/no/such/brisance "))))

    def exposure(self, unit: Path) -> float:
        run = subprocess.run(["systemd-analyze", "security", "--offline=true", "--no-pager",
                              str(unit)], capture_output=True, text=True, timeout=60)
        match = re.search(r"Overall exposure level for \S+: (\d+(?:\.\d+)?)", run.stdout)
        self.assertIsNotNone(match, run.stdout + run.stderr)
        return float(match.group(1))

    def test_hardening(self) -> None:
        # systemd's own score, 0 (locked down) to 10 (exposed); 2.0 and below it calls "OK".
        text = self.unit_path.read_text()
        hardened = self.exposure(self.copy_with_binary(text))
        self.assertLessEqual(hardened, 2.0)
        unhardened = "\n".join(line for line in text.splitlines()
                               if not line.startswith(("Protect", "Private", "Restrict",
                                                       "SystemCall", "Capability")))
        self.assertGreater(self.exposure(self.copy_with_binary(unhardened)), 2.0)
        unit = read_unit(self.unit_path)
        service = dict(unit["Service"])
        self.assertEqual(service.get("ProtectSystem"), "strict")
        self.assertEqual(service.get("NoNewPrivileges"), "yes")
        self.assertTrue(service.get("DynamicUser") == "yes" or service.get("User"))

    def test_data_folder_is_the_state_directory(self) -> None:
        unit = read_unit(self.unit_path)
        args = shlex.split(unit_value(unit, "Service", "ExecStart"))
        self.assertEqual(flag_value(args, "--data"),
                         "/var/lib/" + unit_value(unit, "Service", "StateDirectory"))

    def test_stop_timeout_covers_the_grace_period(self) -> None:
        unit = read_unit(self.unit_path)
        args = shlex.split(unit_value(unit, "Service", "ExecStart"))
        grace = flag_value(args, "--grace-s")
        self.assertIsNotNone(grace, "ExecStart must fix --grace-s beside TimeoutStopSec")
        timeout = systemd_seconds(unit_value(unit, "Service", "TimeoutStopSec") or "90")
        self.assertGreater(timeout, REQUEST_DRAIN_S + float(grace))
        self.assertEqual(unit_value(unit, "Service", "KillSignal"), "SIGTERM")

    def test_settings_are_variables_the_service_reads(self) -> None:
        read = variables_read()
        unit = read_unit(self.unit_path)
        names = [v.split("=", 1)[0] for k, v in unit["Service"] if k == "Environment"]
        names += list(read_env_file(self.env_path))
        commented = re.findall(r"^#(BRISANCE_[A-Z0-9_]+)=", self.env_path.read_text(), re.M)
        for name in names + commented:
            self.assertIn(name, read, f"{name} is not a variable brisance serve reads")
        self.assertIn("-" + "/etc/brisance/brisance.env",
                      [v for k, v in unit["Service"] if k == "EnvironmentFile"])


# --- Dockerfile ---------------------------------------------------------------------------------

# Runtime packages that are data the binary reads, not libraries it links.
RUNTIME_DATA_PACKAGES = {"ca-certificates"}

# Shared libraries the runtime stage gets from debian:bookworm-slim itself (essential packages)
# and the sanitizer runtimes of `make test`'s build, which a release image does not link.
BASE_IMAGE_PACKAGES = {"libc6", "libgcc-s1", "libstdc++6"}
SANITIZER_LIBRARIES = re.compile(r"^lib(asan|ubsan|lsan|tsan)\.so")


def apt_packages(run_line: str) -> list[str]:
    match = re.search(r"apt-get install ([^&|;]*)", run_line)
    if not match:
        return []
    return [word for word in match.group(1).split() if not word.startswith("-")]


def package_known(name: str) -> bool:
    """In Debian: installed here, or known to apt-cache (whose lists may be empty on a fresh
    machine where everything needed was installed)."""
    installed = subprocess.run(["dpkg-query", "-W", "-f=${Status}", name], capture_output=True,
                               text=True)
    if "install ok installed" in installed.stdout:
        return True
    shown = subprocess.run(["apt-cache", "show", name], capture_output=True, text=True)
    return shown.returncode == 0 and f"Package: {name}" in shown.stdout


class Dockerfile(unittest.TestCase):
    """deploy/container/Dockerfile, checked without building it."""

    path = DEPLOY / "container" / "Dockerfile"

    def setUp(self) -> None:
        self.stages = dockerfile_stages(self.path)
        self.by_name = {s["name"]: s for s in self.stages}
        self.runtime = self.stages[-1]

    def test_stages(self) -> None:
        self.assertGreaterEqual(len(self.stages), 2, "multi-stage")
        for stage in self.stages:
            self.assertRegex(stage["base"], r"bookworm", f"{stage['base']}: Debian 12")
        self.assertTrue(self.runtime["base"].startswith("debian:bookworm-slim"))
        # The build stage installs the Makefile's build packages with `make deps`.
        build_runs = [rest for i, rest in self.by_name["build"]["lines"] if i == "RUN"]
        self.assertTrue(any(re.search(r"\bmake deps\b", r) for r in build_runs))
        self.assertRegex((ROOT / "Makefile").read_text(), r"(?m)^deps:")

    def test_runtime_stage(self) -> None:
        lines = self.runtime["lines"]
        users = [rest for i, rest in lines if i == "USER"]
        self.assertTrue(users and re.fullmatch(r"[1-9]\d*(:[1-9]\d*)?", users[-1]),
                        "the runtime stage ends as a numeric non-root user")
        env = dockerfile_env(self.runtime)
        self.assertIn(f'["{env["BRISANCE_DATA"]}"]', [r for i, r in lines if i == "VOLUME"])
        health = [r for i, r in lines if i == "HEALTHCHECK"]
        self.assertTrue(health and "brisance-healthcheck" in health[-1])
        copies = {r.split()[-1]: r for i, r in lines if i == "COPY"}
        self.assertIn(env["BRISANCE_WEB_DIR"], copies)
        self.assertIn("--from=web", copies[env["BRISANCE_WEB_DIR"]])
        entry = json.loads([r for i, r in lines if i == "ENTRYPOINT"][-1])
        self.assertIn(entry[0], copies)
        for name in env:
            self.assertIn(name, variables_read())

    def test_copied_sources_exist_and_scripts_run(self) -> None:
        for stage in self.stages:
            for instruction, rest in stage["lines"]:
                if instruction != "COPY" or rest.startswith("--from"):
                    continue
                for source in rest.split()[:-1]:
                    self.assertTrue((ROOT / source).exists(), f"COPY {source}: no such file")
        for script in ("entrypoint.sh", "healthcheck.sh"):
            self.assertTrue(os.access(DEPLOY / "container" / script, os.X_OK), script)
        ignored = (ROOT / ".dockerignore").read_text().split()
        for heavy in ("build", "**/node_modules", ".git"):
            self.assertIn(heavy, ignored)

    def test_scripts_pass_shellcheck(self) -> None:
        if shutil.which("shellcheck") is None:
            self.fail("shellcheck not found: install the Debian package shellcheck "
                      "(make test does)")
        scripts = [str(DEPLOY / "container" / n) for n in ("entrypoint.sh", "healthcheck.sh")]
        run = subprocess.run(["shellcheck", *scripts], capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        with tempfile.NamedTemporaryFile("w", suffix=".sh") as careless:
            careless.write("#!/bin/sh\nrm -rf $1/data\n")
            careless.flush()
            run = subprocess.run(["shellcheck", careless.name], capture_output=True, text=True)
            self.assertIn("SC2086", run.stdout)

    def test_runtime_packages_cover_the_binary(self) -> None:
        require_binary(self)
        runtime_packages: set[str] = set()
        for instruction, rest in self.runtime["lines"]:
            if instruction == "RUN":
                runtime_packages.update(apt_packages(rest))
        self.assertTrue(runtime_packages)
        for package in runtime_packages:
            self.assertTrue(package_known(package), f"{package}: not a Debian package")
        ldd = subprocess.run(["ldd", BINARY], capture_output=True, text=True, check=True).stdout
        needed: dict[str, str] = {}
        for name, target in re.findall(r"^\s*(\S+) => (\S+)", ldd, re.M):
            if SANITIZER_LIBRARIES.match(name):
                continue
            owner = subprocess.run(["dpkg", "-S", os.path.realpath(target)], capture_output=True,
                                   text=True)
            if owner.returncode != 0:
                owner = subprocess.run(["dpkg", "-S", target], capture_output=True, text=True)
            self.assertEqual(owner.returncode, 0, f"{target}: no Debian package owns it")
            needed[name] = owner.stdout.split(":")[0]
        # The libraries the binary names itself (NEEDED): apt brings their own dependencies (libpq5
        # pulls in Kerberos, LDAP and the like), so only these must be listed.
        dynamic = subprocess.run(["readelf", "-d", BINARY], capture_output=True, text=True,
                                 check=True).stdout
        direct = set(re.findall(r"\(NEEDED\)\s+Shared library: \[(\S+)\]", dynamic))
        needed = {name: package for name, package in needed.items() if name in direct}
        self.assertIn("libsqlite3.so.0", needed)
        self.assertIn("libpq.so.5", needed)
        for library, package in needed.items():
            self.assertIn(package, runtime_packages | BASE_IMAGE_PACKAGES,
                          f"the binary links {library} from {package}: add it to the runtime stage")
        # Only runtime libraries: each package installed there provides one the binary links,
        # but for the data the binary reads (the CA store https callbacks verify against).
        for package in runtime_packages - RUNTIME_DATA_PACKAGES:
            self.assertIn(package, set(needed.values()),
                          f"the runtime stage installs {package}, which the binary does not link")

    def test_build_stage_sources_configure(self) -> None:
        """The build stage COPYs only some folders: CMake must configure from just those."""
        if shutil.which("cmake") is None:
            self.fail("cmake not found")
        with tempfile.TemporaryDirectory(prefix="brisance-image-src-") as folder:
            source = Path(folder) / "src"
            source.mkdir()
            for instruction, rest in self.by_name["build"]["lines"]:
                if instruction == "COPY" and not rest.startswith("--from"):
                    *sources, destination = rest.split()
                    for item in sources:
                        target = source / (item if destination in ("./", ".") else destination)
                        if (ROOT / item).is_dir():
                            shutil.copytree(ROOT / item, target,
                                            ignore=shutil.ignore_patterns("node_modules"))
                        else:
                            shutil.copy2(ROOT / item, target)
            cmake_line = next(r for i, r in self.by_name["build"]["lines"]
                              if i == "RUN" and r.startswith("cmake "))
            configure = shlex.split(cmake_line.split("&&")[0])
            configure = [a for a in configure if a != "-G" and a != "Ninja"]
            run = subprocess.run(configure + ["-DCMAKE_CXX_COMPILER_LAUNCHER="], cwd=source,
                                 capture_output=True, text=True, timeout=300)
            self.assertEqual(run.returncode, 0, run.stdout[-3000:] + run.stderr[-3000:])

    def test_web_stage_sources(self) -> None:
        """The dashboard reaches outside web/ (../clients, ../scenes): those folders are copied."""
        copied = {rest.split()[0].split("/")[0] for i, rest in self.by_name["web"]["lines"]
                  if i == "COPY"}
        outside = set()
        for file in list((ROOT / "web" / "src").rglob("*.ts")) + [ROOT / "web" / "vite.config.ts",
                                                                  ROOT / "web" / "tsconfig.json"]:
            for match in re.findall(r"\.\./(?:\.\./)*([A-Za-z_][\w-]*)", file.read_text()):
                if (ROOT / match).is_dir() and match != "web":
                    outside.add(match)
        self.assertTrue(outside, "expected the dashboard to use ../clients")
        self.assertLessEqual(outside, copied)


# --- the forms, run ---------------------------------------------------------------------------


class FormRunner(unittest.TestCase):
    """Runs a form's command line against the built binary and a temporary folder."""

    def setUp(self) -> None:
        require_binary(self)
        self.folder = Path(tempfile.mkdtemp(prefix="brisance-forms-"))
        self.addCleanup(shutil.rmtree, self.folder, ignore_errors=True)
        self.data = self.folder / "data"
        self.data.mkdir()
        self.bin = self.folder / "bin"
        self.bin.mkdir()
        (self.bin / "brisance").symlink_to(os.path.abspath(BINARY))
        self.web = ROOT / "web" / "dist"

    def base_env(self) -> dict[str, str]:
        env = {k: v for k, v in os.environ.items() if not k.startswith("BRISANCE_")}
        env["PATH"] = f"{self.bin}:{env.get('PATH', '/usr/bin:/bin')}"
        return env

    def map_path(self, value: str) -> str:
        """Paths of a deployed machine to this test's folders."""
        for deployed, here in (("/usr/local/bin/brisance", str(self.bin / "brisance")),
                               ("/var/lib/brisance", str(self.data)),
                               ("/usr/local/share/brisance/web", str(self.web))):
            if value == deployed or value.startswith(deployed + "/"):
                return here + value[len(deployed):]
        return value

    def exercise(self, server: Server, stop_limit_s: float, grace_s: float,
                 signal_pid: int | None = None, stop_while_running: bool = False) -> str | None:
        """Probes, one job to success, then SIGTERM: exit 0 within the form's stop limit. With
        stop_while_running, a job that outlasts the grace period runs when SIGTERM comes: its
        location is returned."""
        server.wait_listening(self)
        listening = server.event("listening")
        self.assertEqual(Path(listening["database"]).parent.resolve(), self.data.resolve())
        self.assertEqual(server.request("GET", "/healthz")[0], 200)
        deadline = time.monotonic() + 20
        while server.request("GET", "/readyz")[0] != 200:
            self.assertLess(time.monotonic(), deadline, "/readyz never became 200")
            time.sleep(0.2)
        status, headers, body = server.request("POST", "/v1/jobs",
                                               {"scene": THREE_BLOCKS, "priority": 0})
        self.assertEqual(status, 202, body)
        location = headers["Location"]
        deadline = time.monotonic() + 120
        job = {}
        while time.monotonic() < deadline:
            status, _, body = server.request("GET", location + "?wait=5")
            self.assertEqual(status, 200, body)
            job = json.loads(body)
            if job["status"] in ("succeeded", "failed", "cancelled"):
                break
        self.assertEqual(job.get("status"), "succeeded", job)
        self.assertEqual(server.request("GET", location + "/result")[0], 200)
        running = None
        if stop_while_running:
            status, headers, body = server.request("POST", "/v1/jobs", {"scene": SLOW_SCENE})
            self.assertEqual(status, 202, body)
            running = headers["Location"]
            deadline = time.monotonic() + 60
            while json.loads(server.request("GET", running + "?wait=2")[2])["status"] != "running":
                self.assertLess(time.monotonic(), deadline, "the slow job never started")
        code, took_s = server.terminate(stop_limit_s, signal_pid)
        self.assertEqual(code, 0, f"exit after SIGTERM (limit {stop_limit_s} s); log:\n" +
                         "\n".join(server.log[-20:]))
        shutting = server.event("shutting down")
        self.assertIsNotNone(shutting)
        self.assertEqual(shutting["signal"], "SIGTERM")
        self.assertEqual(float(shutting["grace_s"]), grace_s)
        self.assertIsNotNone(server.event("stopped"))
        return running

    def unit_command(self) -> tuple[dict, list[str], dict[str, str]]:
        """The unit, its ExecStart and the environment systemd would give it (Environment=, then
        the env file), with this test's paths and a free port instead of 8080."""
        unit = read_unit(DEPLOY / "systemd" / "brisance.service")
        args = [self.map_path(a) for a in shlex.split(unit_value(unit, "Service", "ExecStart"))]
        env = self.base_env()
        for key, value in unit["Service"]:
            if key == "Environment":
                name, _, setting = value.partition("=")
                env[name] = self.map_path(setting)
        for name, setting in read_env_file(DEPLOY / "systemd" / "brisance.env").items():
            env[name] = self.map_path(setting)
        env["BRISANCE_PORT"] = "0"
        self.assertIsNone(flag_value(args, "--port"))
        return unit, args, env


class RunForms(FormRunner):
    """Each form's command line and settings against the built binary and a temporary folder.
    The PostgreSQL URL and blob folder of the multi-node forms are left out: these runs use the
    SQLite store (issue 14's postgres tests run the multi-node case)."""

    def test_systemd_exec_start(self) -> None:
        """The unit's command line, stopped while a job runs that outlasts --grace-s: it must
        exit 0 before TimeoutStopSec (systemd would SIGKILL it then) and find the job queued
        again at the next start."""
        unit, args, env = self.unit_command()
        server = Server(args, env, self.folder)
        self.addCleanup(server.stop_now)
        stop_limit = systemd_seconds(unit_value(unit, "Service", "TimeoutStopSec"))
        slow = self.exercise(server, stop_limit, float(flag_value(args, "--grace-s")),
                             stop_while_running=True)
        again = Server(args, env, self.folder)
        self.addCleanup(again.stop_now)
        again.wait_listening(self)
        job = json.loads(again.request("GET", slow)[2])
        self.assertIn(job["status"], ("queued", "running"), job)
        self.assertEqual(again.request("POST", slow + "/cancel")[0] // 100, 2)
        self.assertEqual(again.terminate(stop_limit)[0], 0)

    def test_online_backup(self) -> None:
        """docs/deploy.md "Backups": SQLite's online backup of a serving node's database, served
        again from a fresh folder, still has the finished job and its result."""
        env = self.base_env()
        env["BRISANCE_PORT"] = "0"
        env["BRISANCE_WORKERS"] = "1"
        server = Server([BINARY, "serve", "--data", str(self.data)], env, self.folder)
        self.addCleanup(server.stop_now)
        server.wait_listening(self)
        status, headers, body = server.request("POST", "/v1/jobs", {"scene": THREE_BLOCKS})
        self.assertEqual(status, 202, body)
        location = headers["Location"]
        deadline = time.monotonic() + 120
        while json.loads(server.request("GET", location + "?wait=5")[2])["status"] != "succeeded":
            self.assertLess(time.monotonic(), deadline)
        result = server.request("GET", location + "/result")
        restored = self.folder / "restored"
        restored.mkdir()
        backup = restored / "brisance.sqlite3"
        # The documented one-liner, while the server runs (and holds the database open).
        subprocess.run([sys.executable, "-c",
                        "import sqlite3,sys; "
                        "sqlite3.connect(sys.argv[1]).backup(sqlite3.connect(sys.argv[2]))",
                        str(self.data / "brisance.sqlite3"), str(backup)], check=True, timeout=60)
        self.assertEqual(server.terminate(30)[0], 0)
        again = Server([BINARY, "serve", "--data", str(restored)], env, self.folder)
        self.addCleanup(again.stop_now)
        again.wait_listening(self)
        status, _, body = again.request("GET", location)
        self.assertEqual(status, 200, body)
        self.assertEqual(json.loads(body)["status"], "succeeded")
        self.assertEqual(again.request("GET", location + "/result")[2], result[2])
        self.assertEqual(again.terminate(30)[0], 0)

    def image_env(self) -> dict[str, str]:
        env = self.base_env()
        runtime = dockerfile_stages(DEPLOY / "container" / "Dockerfile")[-1]
        for name, value in dockerfile_env(runtime).items():
            env[name] = self.map_path(value)
        # Loopback only on a test machine, and a free port (the healthcheck reads BRISANCE_PORT).
        env["BRISANCE_BIND"] = "127.0.0.1"
        env["BRISANCE_PORT"] = "0"
        return env

    def healthcheck(self, env: dict[str, str], port: int, *args: str) -> int:
        run_env = dict(env, BRISANCE_PORT=str(port))
        return subprocess.run([str(DEPLOY / "container" / "healthcheck.sh"), *args], env=run_env,
                              capture_output=True, timeout=10).returncode

    def test_container_entry_point(self) -> None:
        env = self.image_env()
        # The image's default command: the entry point with CMD ["serve"].
        server = Server([str(DEPLOY / "container" / "entrypoint.sh"), "serve"], env, self.folder)
        self.addCleanup(server.stop_now)
        server.wait_listening(self)
        self.assertEqual(self.healthcheck(env, server.port), 0)
        self.assertEqual(self.healthcheck(env, server.port, "/readyz"), 0)
        self.assertNotEqual(self.healthcheck(env, server.port, "/no-such-route"), 0)
        self.assertEqual(server.event("listening")["dashboard"],
                         self.web.joinpath("index.html").exists())
        # docker stop's default is 10 s; docs/deploy.md says to give it 10 + grace (+ margin).
        self.exercise(server, REQUEST_DRAIN_S + 10 + 5, 10.0)
        self.assertNotEqual(self.healthcheck(env, server.port), 0)

    def test_container_entry_point_commands(self) -> None:
        env = self.image_env()
        script = str(DEPLOY / "container" / "entrypoint.sh")
        version = subprocess.run([script, "version"], env=env, capture_output=True, text=True,
                                 timeout=30)
        self.assertEqual(version.returncode, 0, version.stderr)
        self.assertRegex(version.stdout, r"\d+\.\d+")
        # Flags alone mean `serve`: a bad one is serve's usage error.
        flags = subprocess.run([script, "--workers", "0"], env=env, capture_output=True,
                               text=True, timeout=30)
        self.assertNotEqual(flags.returncode, 0)
        self.assertIn("brisance serve", flags.stderr)
        # A data folder that cannot be one is named before brisance starts.
        blocked = self.folder / "not-a-folder"
        blocked.write_text("")
        refused = subprocess.run([script], env=dict(env, BRISANCE_DATA=str(blocked)),
                                 capture_output=True, text=True, timeout=30)
        self.assertEqual(refused.returncode, 1)
        self.assertIn("brisance-entrypoint: the data folder", refused.stderr)
        other = subprocess.run([script, "sh", "-c", "echo $BRISANCE_DATA"], env=env,
                               capture_output=True, text=True, timeout=30)
        self.assertEqual(other.stdout.strip(), str(self.data))

    def test_compose_node_settings(self) -> None:
        text = (DEPLOY / "compose.yaml").read_text()
        block = re.search(r"(?ms)^  environment: &brisance-environment\n(.*?)^  \S", text)
        self.assertIsNotNone(block)
        settings = dict(re.findall(r"^    (BRISANCE_[A-Z_0-9]+): \"?([^\"\n]*)\"?$",
                                   block.group(1), re.M))
        self.assertIn("BRISANCE_STORE", settings)
        env = self.image_env()
        for name, value in settings.items():
            if name not in ("BRISANCE_STORE", "BRISANCE_BLOBS"):
                # Compose's ${NAME:-default}, with NAME unset: the default.
                env[name] = re.sub(r"\$\{[A-Z_0-9]+:-([^}]*)\}", r"\1", value)
        grace = float(settings["BRISANCE_GRACE_S"])
        stop = re.search(r"stop_grace_period: (\d+)s", text)
        server = Server([str(DEPLOY / "container" / "entrypoint.sh"), "serve"], env, self.folder)
        self.addCleanup(server.stop_now)
        server.wait_listening(self)
        self.assertEqual(self.healthcheck(env, server.port, "/readyz"), 0)
        self.exercise(server, float(stop.group(1)), grace)

    def test_kubernetes_settings(self) -> None:
        config = simple_yaml_map(DEPLOY / "kubernetes" / "configmap.yaml", "data")
        self.assertIn("BRISANCE_API_KEYS", config)
        # The keys Secret's placeholder file, where the Deployment mounts it.
        secret = (DEPLOY / "kubernetes" / "secret.yaml").read_text()
        keys_block = re.search(r"(?ms)^  keys: \|\n((?:    .*\n)+)", secret)
        self.assertIsNotNone(keys_block)
        keys = self.folder / "keys"
        keys.write_text("".join(line[4:] + "\n" for line in keys_block.group(1).splitlines()))
        env = self.image_env()
        for name, value in config.items():
            env[name] = self.map_path(value)
        env["BRISANCE_API_KEYS"] = str(keys)
        env["BRISANCE_BIND"] = "127.0.0.1"
        env["BRISANCE_PORT"] = "0"
        server = Server([str(DEPLOY / "container" / "entrypoint.sh"), "serve"], env, self.folder)
        self.addCleanup(server.stop_now)
        server.wait_listening(self)
        self.assertEqual(server.event("listening")["api_keys"], 1)
        self.assertEqual(server.event("listening")["workers"], int(config["BRISANCE_WORKERS"]))
        self.assertEqual(server.request("GET", "/readyz")[0], 200)
        # The placeholder key is nobody's: the API is closed until it is replaced.
        self.assertEqual(server.request("GET", "/v1/jobs")[0], 401)
        grace = float(config["BRISANCE_GRACE_S"])
        code, _ = server.terminate(REQUEST_DRAIN_S + grace + 5)
        self.assertEqual(code, 0, "\n".join(server.log[-20:]))


# --- the unit's sandbox, traced -------------------------------------------------------------------


def syscall_groups() -> dict[str, list[str]]:
    """systemd's system call groups (`systemd-analyze syscall-filter`): name -> members, which
    may be groups themselves."""
    run = subprocess.run(["systemd-analyze", "syscall-filter", "--no-pager"], capture_output=True,
                         text=True, check=True)
    groups: dict[str, list[str]] = {}
    current = None
    for line in run.stdout.splitlines():
        if line.startswith("@"):
            current = line.strip()
            groups[current] = []
        elif current and line.startswith("    ") and not line.strip().startswith("#"):
            groups[current].append(line.strip())
    return groups


def expand(names: list[str], groups: dict[str, list[str]]) -> set[str]:
    out: set[str] = set()
    for name in names:
        if name.startswith("@"):
            out |= expand(groups[name], groups)
        else:
            out.add(name)
    return out


def allowed_syscalls(unit: dict) -> set[str]:
    """What the unit's SystemCallFilter= lines allow: the first line without ~ starts an allow
    list, later ones add to it, lines with ~ take away (systemd.exec(5))."""
    groups = syscall_groups()
    allowed: set[str] = set()
    for key, value in unit["Service"]:
        if key != "SystemCallFilter":
            continue
        if value.startswith("~"):
            allowed -= expand(value[1:].split(), groups)
        else:
            allowed |= expand(value.split(), groups)
    return allowed


NOBODY = 65534
TRACE_LINE = re.compile(r"^(\d+)\s+(?:<\.\.\. )?([a-z_0-9]+)[\( ](.*)$")
WRITE_FLAGS = re.compile(r"O_WRONLY|O_RDWR|O_CREAT|O_TRUNC")


class SystemdSandbox(FormRunner):
    """The unit's sandbox cannot run here (no systemd as PID 1), so the unit's ExecStart runs
    under strace through a whole life (probes, a job, SIGTERM) and what it did is checked
    against what the sandbox allows: every system call passes SystemCallFilter, every socket is
    of RestrictAddressFamilies, no memory is writable and executable (MemoryDenyWriteExecute),
    nothing is written outside the state directory (ProtectSystem=strict), and /proc is read
    only for its own process (ProcSubset=pid)."""

    def test_a_traced_run_stays_inside_the_sandbox(self) -> None:
        if shutil.which("strace") is None:
            self.fail("strace not found: install the Debian package strace (make test does)")
        unit, args, env = self.unit_command()
        trace = self.folder / "trace.txt"
        # As the unit's dynamic user is, not root: SQLite, for one, chowns its files only as root.
        user = []
        if os.geteuid() == 0:
            user = ["setpriv", "--reuid", str(NOBODY), "--regid", str(NOBODY), "--clear-groups"]
            os.chmod(self.folder, 0o755)
            os.chown(self.data, NOBODY, NOBODY)
            # A copy the user can run wherever the build tree is (a root-only home, say).
            args[0] = str(self.folder / "brisance")
            shutil.copy2(BINARY, args[0])
            os.chmod(args[0], 0o755)
        # LeakSanitizer (make test's build) cannot run under ptrace; leaks are other tests' job.
        env["ASAN_OPTIONS"] = ":".join(filter(None, [env.get("ASAN_OPTIONS"), "detect_leaks=0"]))
        server = Server(["strace", "-f", "-qq", "-s", "256", "-o", str(trace), "--", *user, *args],
                        env, self.folder)
        self.addCleanup(server.stop_now)
        server.wait_listening(self)
        traced = self.traced_child(server.process.pid)
        stop_limit = systemd_seconds(unit_value(unit, "Service", "TimeoutStopSec"))
        self.exercise(server, stop_limit, float(flag_value(args, "--grace-s")), signal_pid=traced)
        calls = [m.groups() for m in map(TRACE_LINE.match, trace.read_text().splitlines()) if m]
        # From the server's own start on (not strace's or setpriv's).
        starts = [i for i, (_, name, rest) in enumerate(calls)
                  if name == "execve" and rest.startswith(f'"{args[0]}"')]
        self.assertTrue(starts, "the trace shows the server's execve")
        calls = calls[starts[-1] + 1:]
        self.assertGreater(len(calls), 100, "strace recorded the run")
        service = dict(unit["Service"])

        used = {name for _, name, _ in calls if name not in ("exited", "killed", "resumed")}
        outside = used - allowed_syscalls(unit)
        self.assertEqual(outside, set(), "system calls SystemCallFilter= would refuse")

        families = set(service["RestrictAddressFamilies"].split())
        for _, name, rest in calls:
            # Under load strace splits a call in two ("socket(AF_INET, ... <unfinished ...>" and
            # "<... socket resumed>) = 9"); the first half names the family.
            if name == "socket" and not rest.startswith("resumed>"):
                self.assertIn(rest.split(",")[0], families, rest)
            if name in ("mmap", "mprotect", "pkey_mprotect"):
                self.assertFalse("PROT_WRITE" in rest and "PROT_EXEC" in rest, rest)

        data = str(self.data.resolve())
        for _, name, rest in calls:
            path = re.search(r'"([^"]*)"', rest)
            if not path:
                continue
            target = os.path.normpath(os.path.join(str(self.folder), path.group(1)))
            writes = (name in ("open", "openat", "creat") and WRITE_FLAGS.search(rest)) or name in (
                "unlink", "unlinkat", "rename", "renameat", "renameat2", "mkdir", "mkdirat",
                "rmdir", "truncate", "chmod", "fchmodat", "chown", "fchownat", "link", "symlink")
            if writes and not target.startswith("/dev/"):
                self.assertTrue(target == data or target.startswith(data + "/"),
                                f"writes {target} outside the state directory: {name}({rest[:120]}")
            # glibc's malloc reads overcommit_memory when it shrinks a thread's heap; where
            # ProcSubset=pid hides the file it keeps the heap, so the read is harmless.
            if target.startswith("/proc/") and target != "/proc/sys/vm/overcommit_memory":
                self.assertRegex(target, r"^/proc/(self|thread-self|\d+)(/|$)",
                                 "ProcSubset=pid hides it")

    def traced_child(self, strace_pid: int) -> int:
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            for task in Path(f"/proc/{strace_pid}/task").iterdir():
                children = (task / "children").read_text().split()
                if children:
                    return int(children[0])
            time.sleep(0.05)
        self.fail("no traced child under strace")


if __name__ == "__main__":
    unittest.main()
