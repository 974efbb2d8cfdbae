"""Command line: ``python3 -m brisance_client COMMAND ...``.

    submit SCENE.json [--wait] [-o OUT.glb|OUT.json] [--priority N] [--progress]
    status ID | cancel ID | delete ID | queue | explosives
    blast --charge-kg M --distance-m R [--explosive NAME] [--burst air|surface] [--angle-deg A]
    response --element E.json (--charge-kg M --distance-m R [--explosive NAME] [--burst B]
             [--angle-deg A] | --pulse-peak-kpa P --pulse-duration-ms T [--pulse-shape S])
    pi --element E.json [--ductility MU | --rotation-deg T] [--points N]

Every command takes ``--url URL`` (default ``$BRISANCE_URL``, else http://127.0.0.1:8080) and
``--api-key KEY`` (default ``$BRISANCE_API_KEY``). Exit codes: 0 success; 2 invalid input (a bad
option, an unreadable scene file, a rejected job -- each problem printed as a ``pointer: detail``
line on stderr); 1 any other failure (a job that failed or was cancelled, the server unreachable,
a missing key, an unknown job...).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any, Dict, List, Optional, TextIO, Tuple

from . import __version__
from .client import DEFAULT_URL, Client, Job
from .errors import (BrisanceError, JobFailedError, ProblemError, TransportError,
                     WaitTimeoutError)

EXIT_OK = 0
EXIT_FAILURE = 1
EXIT_INVALID = 2

# Problems that mean "your input is wrong" rather than "something failed".
_INPUT_PROBLEMS = {"malformed-json", "invalid-parameter", "invalid-scene", "invalid-input",
                   "idempotency-key-reused", "payload-too-large", "unsupported-media-type"}


class UsageError(Exception):
    """Invalid input found before talking to the server (exit 2)."""


class ProgressBar:
    """The job's progress: a one-line bar redrawn in place (``\\r``) on a terminal, a plain line
    at every change of state and every tenth otherwise (logs, CI). Both show the time left,
    estimated from the rate since the job started running (its progress is in work done)."""

    def __init__(self, stream: TextIO, enabled: bool, width: int = 30) -> None:
        self.stream = stream
        self.enabled = enabled
        self.width = width
        self.drawn = False
        self.started = time.monotonic()
        self.terminal = bool(getattr(stream, "isatty", lambda: False)())
        self.last: Optional[Tuple[str, int]] = None
        self.first: Optional[Tuple[float, float]] = None  # (clock, fraction) once running

    def _left(self, fraction: float, now: float) -> str:
        if fraction >= 1.0:
            return "done"
        if self.first is None or fraction <= self.first[1] or now <= self.first[0]:
            return ""
        rate = (fraction - self.first[1]) / (now - self.first[0])
        return "about %.0fs left" % max(1.0, (1.0 - fraction) / rate)

    def __call__(self, job: Job) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        fraction = 1.0 if job.succeeded else max(0.0, min(1.0, job.progress))
        if job.status == "running" and self.first is None:
            self.first = (now, fraction)
        elapsed = now - self.started
        left = self._left(fraction, now)
        if not self.terminal:
            key = (str(job.status), int(10 * fraction))
            if key == self.last:
                return
            self.last = key
            self.stream.write("%-9s %5.1f%%  %5.1fs  %s%s\n" % (
                job.status, 100.0 * fraction, elapsed, job.id, "  " + left if left else ""))
            self.stream.flush()
            return
        filled = int(round(fraction * self.width))
        bar = "#" * filled + "-" * (self.width - filled)
        self.stream.write("\r%-9s [%s] %5.1f%%  %5.1fs  %s  %-18s" % (
            job.status, bar, 100.0 * fraction, elapsed, job.id, left))
        self.stream.flush()
        self.drawn = True

    def close(self) -> None:
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = False


def _add_common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--url", default=None,
                        help="server URL (default $BRISANCE_URL, else %s)" % DEFAULT_URL)
    parser.add_argument("--api-key", default=None,
                        help="API key sent as 'Authorization: Bearer KEY' "
                             "(default $BRISANCE_API_KEY)")
    parser.add_argument("--timeout", type=float, default=30.0,
                        help="socket timeout of one request, s (default 30)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python3 -m brisance_client",
        description="Client of the Brisance blast-simulation job service.",
        epilog="Exit codes: 0 ok, 2 invalid input, 1 other failures.")
    parser.add_argument("--version", action="version", version="%(prog)s " + __version__)
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    submit = commands.add_parser(
        "submit", help="submit a scene (or a whole job body) and optionally wait for it",
        description="Submit SCENE.json (a scene, or a job body {\"scene\": ..., \"priority\": "
                    "...}; '-' reads stdin). Prints the job id on stdout.")
    submit.add_argument("scene", metavar="SCENE.json")
    submit.add_argument("--wait", action="store_true", help="wait until the job has finished")
    submit.add_argument("-o", "--output", metavar="OUT.glb|OUT.json",
                        help="save the result: the animated glTF (.glb) or the result summary "
                             "(.json); implies --wait")
    submit.add_argument("--priority", type=int, default=None,
                        help="-100..100, higher runs first (default: the file's, else 0)")
    submit.add_argument("--name", default=None, help="name the job (lists and the dashboard)")
    submit.add_argument("--label", action="append", default=[], metavar="KEY=VALUE",
                        help="label the job; repeat for several")
    submit.add_argument("--idempotency-key", default=None,
                        help="name this submission (default: a fresh uuid4)")
    submit.add_argument("--wait-timeout", type=float, default=None,
                        help="give up waiting after this many seconds (exit 1)")
    submit.add_argument("--progress", action="store_true",
                        help="draw the progress bar on stderr even when it is not a terminal")
    _add_common(submit)

    for name, text in (("status", "print a job as JSON"),
                       ("cancel", "cancel a queued or running job"),
                       ("delete", "delete a job and its results")):
        sub = commands.add_parser(name, help=text, description=text)
        sub.add_argument("id", metavar="ID")
        _add_common(sub)

    blast = commands.add_parser("blast", help="blast-wave numbers at a distance from a charge")
    blast.add_argument("--charge-kg", type=float, required=True, metavar="M")
    blast.add_argument("--distance-m", type=float, required=True, metavar="R")
    blast.add_argument("--explosive", default=None, help="name from `explosives` (default TNT)")
    blast.add_argument("--burst", choices=("air", "surface"), default=None)
    blast.add_argument("--angle-deg", type=float, default=None)
    _add_common(blast)

    response = commands.add_parser(
        "response", help="an element's SDOF response to a charge or a pulse (docs/response.md)")
    response.add_argument("--element", required=True, metavar="E.json")
    response.add_argument("--charge-kg", type=float, default=None, metavar="M")
    response.add_argument("--distance-m", type=float, default=None, metavar="R")
    response.add_argument("--explosive", default=None)
    response.add_argument("--burst", choices=("air", "surface"), default=None)
    response.add_argument("--angle-deg", type=float, default=None)
    response.add_argument("--pulse-peak-kpa", type=float, default=None, metavar="P")
    response.add_argument("--pulse-duration-ms", type=float, default=None, metavar="T")
    response.add_argument("--pulse-shape", choices=("triangular", "friedlander"), default=None)
    _add_common(response)

    pi = commands.add_parser("pi", help="an element's pressure-impulse curve")
    pi.add_argument("--element", required=True, metavar="E.json")
    pi.add_argument("--ductility", type=float, default=None, metavar="MU")
    pi.add_argument("--rotation-deg", type=float, default=None, metavar="T")
    pi.add_argument("--points", type=int, default=None, metavar="N")
    _add_common(pi)

    for name, text in (("queue", "jobs by state and workers"),
                       ("explosives", "the explosives the server knows")):
        _add_common(commands.add_parser(name, help=text, description=text))
    return parser


def _load_element(path: str) -> Dict[str, Any]:
    try:
        with open(path, encoding="utf-8") as handle:
            return json.load(handle)
    except (OSError, ValueError) as error:
        raise UsageError("cannot read the element %s: %s" % (path, error)) from error


def _cmd_response(client: Client, args: argparse.Namespace, out: TextIO) -> None:
    charge = {key: value for key, value in (
        ("charge_kg", args.charge_kg), ("distance_m", args.distance_m),
        ("explosive", args.explosive), ("burst", args.burst), ("angle_deg", args.angle_deg))
        if value is not None}
    pulse = {key: value for key, value in (
        ("peak_kpa", args.pulse_peak_kpa), ("duration_ms", args.pulse_duration_ms),
        ("shape", args.pulse_shape)) if value is not None}
    if bool(charge) == bool(pulse):
        raise UsageError("give a charge (--charge-kg, --distance-m) or a pulse (--pulse-peak-kpa, "
                         "--pulse-duration-ms), one of them")
    _print_json(client.response(_load_element(args.element), charge=charge or None,
                                pulse=pulse or None, history=False), out)


def _load_job_body(path: str, priority: Optional[int]) -> Dict[str, Any]:
    try:
        if path == "-":
            text = sys.stdin.read()
        else:
            with open(path, "r", encoding="utf-8") as handle:
                text = handle.read()
    except OSError as error:
        raise UsageError("cannot read %s: %s" % (path, error.strerror or error))
    try:
        document = json.loads(text)
    except ValueError as error:
        raise UsageError("%s is not JSON: %s" % (path, error))
    if not isinstance(document, dict):
        raise UsageError("%s must hold a JSON object (a scene or a job body)" % path)
    if "scene" in document and "charges" not in document:
        body = dict(document)  # a whole job body
    else:
        body = {"scene": document, "priority": 0}
    if priority is not None:
        body["priority"] = priority
    return body


def _print_json(value: Any, out: TextIO) -> None:
    out.write(json.dumps(value, indent=2, sort_keys=False) + "\n")


def _cmd_submit(client: Client, args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    output = args.output
    if output is not None:
        extension = os.path.splitext(output)[1].lower()
        if extension not in (".glb", ".json"):
            raise UsageError("-o must name a .glb or a .json file, got %r" % output)
    body = _load_job_body(args.scene, args.priority)
    if args.name is not None:
        body["name"] = args.name
    for label in args.label:
        key, equals, value = label.partition("=")
        if not equals or not key:
            raise UsageError("--label takes KEY=VALUE, got %r" % label)
        body.setdefault("labels", {})[key] = value
    job = client.submit_job(body, idempotency_key=args.idempotency_key)
    out.write(job.id + "\n")
    out.flush()
    if not (args.wait or output):
        err.write("submitted %s (%s)\n" % (job.id, job.status))
        return EXIT_OK
    bar = ProgressBar(err, enabled=args.progress or err.isatty())
    try:
        job = client.wait(job, args.wait_timeout, progress=bar)
    finally:
        bar.close()
    wall = (job.stats or {}).get("wall_time_s")
    err.write("job %s succeeded%s\n" % (job.id, " in %.2f s" % wall if wall is not None else ""))
    if output:
        if output.lower().endswith(".glb"):
            client.download_glb(job, output)
        else:
            summary = client.result(job)
            temporary = output + ".part"
            with open(temporary, "w", encoding="utf-8") as handle:
                json.dump(summary, handle, indent=2)
                handle.write("\n")
            os.replace(temporary, output)
        err.write("wrote %s (%d bytes)\n" % (output, os.path.getsize(output)))
    return EXIT_OK


def _cmd_cancel(client: Client, args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    job = client.cancel(args.id)
    _print_json(job.data, out)
    if job.status == "cancelled":
        err.write("job %s cancelled\n" % job.id)
    else:
        err.write("job %s is %s; asked to stop\n" % (job.id, job.status))
    return EXIT_OK


def run(argv: Optional[List[str]] = None, out: TextIO = sys.stdout,
        err: TextIO = sys.stderr) -> int:
    """Run the command line; returns the exit code."""
    args = build_parser().parse_args(argv)
    try:
        client = Client(args.url, args.api_key, timeout=args.timeout)
    except ValueError as error:  # a bad --url
        err.write("error: %s\n" % error)
        return EXIT_INVALID
    try:
        if args.command == "submit":
            return _cmd_submit(client, args, out, err)
        if args.command == "status":
            _print_json(client.job(args.id).data, out)
        elif args.command == "cancel":
            return _cmd_cancel(client, args, out, err)
        elif args.command == "delete":
            client.delete(args.id)
            err.write("job %s deleted\n" % args.id)
        elif args.command == "blast":
            _print_json(client.blast(args.charge_kg, args.distance_m, explosive=args.explosive,
                                     burst=args.burst, angle_deg=args.angle_deg), out)
        elif args.command == "response":
            _cmd_response(client, args, out)
        elif args.command == "pi":
            _print_json(client.pi(_load_element(args.element), ductility=args.ductility,
                                  rotation_deg=args.rotation_deg, points=args.points), out)
        elif args.command == "queue":
            _print_json(client.queue(), out)
        elif args.command == "explosives":
            _print_json(client.explosives(), out)
        return EXIT_OK
    except UsageError as error:
        err.write("error: %s\n" % error)
        return EXIT_INVALID
    except ProblemError as problem:
        err.write("error: %d %s: %s\n" % (problem.status, problem.title, problem.detail))
        for pointer, detail in problem.errors:
            err.write("%s: %s\n" % (pointer, detail))
        for parameter, detail in problem.parameters:
            err.write("%s: %s\n" % (parameter, detail))
        return EXIT_INVALID if problem.kind in _INPUT_PROBLEMS else EXIT_FAILURE
    except JobFailedError as failure:
        err.write("error: %s\n" % failure)
        return EXIT_FAILURE
    except WaitTimeoutError as timeout:
        err.write("error: %s (it keeps running; see `status %s`)\n" % (timeout, timeout.job.id))
        return EXIT_FAILURE
    except TransportError as error:
        err.write("error: cannot reach the server: %s\n" % error)
        return EXIT_FAILURE
    except BrisanceError as error:
        err.write("error: %s\n" % error)
        return EXIT_FAILURE
    except OSError as error:  # writing the output file
        err.write("error: %s\n" % error)
        return EXIT_FAILURE
    except KeyboardInterrupt:
        err.write("\ninterrupted\n")
        return 130


def main() -> None:
    sys.exit(run())


if __name__ == "__main__":
    main()
