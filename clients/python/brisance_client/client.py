"""A standard-library client of the Brisance job service (``brisance serve``, api/openapi.yaml).

Retry policy (every call):

* ``429`` (queue full) and ``503`` (storage unavailable) are retried, never sooner than the
  server's ``Retry-After`` and never sooner than a capped exponential backoff
  (``backoff_base * 2**attempt``, at most ``backoff_cap`` s, with jitter): the wait is the larger
  of the two.
* Connection errors (refused, reset, timed out, the server closing mid-answer) are retried with
  the same backoff for reads, ``DELETE`` and job submissions -- every submission carries an
  ``Idempotency-Key`` (a fresh uuid4 unless you give one), so a retried submission whose first
  attempt was in fact accepted returns that job (``200``) instead of making a second one. A
  ``cancel`` is retried only when the connection was refused (the request never left).
* A call gives up after ``max_retries`` retries, or as soon as the next wait would take its total
  waiting over ``max_retry_wait`` seconds: it then raises the last answer as a
  :class:`ProblemError` (``status`` 429 or 503, ``retry_after`` set) or a
  :class:`TransportError`. It never waits less than ``Retry-After`` to squeeze into the budget.
"""

from __future__ import annotations

import email.utils
import http.client
import ipaddress
import json
import os
import random
import shutil
import struct
import stat
import tempfile
import time
import urllib.error
import urllib.parse
import urllib.request
import uuid
from typing import (Any, BinaryIO, Callable, Dict, Iterator, List, Mapping, Optional, Sequence,
                    Tuple, Union)

from . import __version__
from .errors import (BrisanceError, FrameFormatError, JobFailedError, ProblemError,
                     TransportError, WaitTimeoutError)

DEFAULT_URL = "http://127.0.0.1:8080"
FINAL_STATES = frozenset({"succeeded", "failed", "cancelled"})
MAX_LONG_POLL_S = 30  # the server's limit for ?wait=

Vec3 = Tuple[float, float, float]
Quat = Tuple[float, float, float, float]
Pose = Tuple[Vec3, Quat]
Frame = Tuple[int, float, Dict[int, Pose]]


class Job:
    """A job as the server last described it (the ``Job`` schema) and its ``ETag``.

    ``job.data`` is the decoded JSON; the common fields are attributes. Client methods take a
    ``Job`` or a job id string.
    """

    __slots__ = ("data", "etag")

    def __init__(self, data: Mapping[str, Any], etag: Optional[str] = None) -> None:
        self.data: Dict[str, Any] = dict(data)
        self.etag = etag

    id = property(lambda self: self.data["id"])
    status = property(lambda self: self.data.get("status"))
    progress = property(lambda self: float(self.data.get("progress") or 0.0))
    priority = property(lambda self: self.data.get("priority"))
    name = property(lambda self: self.data.get("name") or "")
    labels = property(lambda self: dict(self.data.get("labels") or {}))
    attempts = property(lambda self: self.data.get("attempts"))
    cancel_requested = property(lambda self: bool(self.data.get("cancel_requested")))
    error = property(lambda self: self.data.get("error"))
    stats = property(lambda self: self.data.get("stats"))
    links = property(lambda self: self.data.get("links") or {})
    created_at = property(lambda self: self.data.get("created_at"))
    started_at = property(lambda self: self.data.get("started_at"))
    finished_at = property(lambda self: self.data.get("finished_at"))

    @property
    def finished(self) -> bool:
        """True once the job is ``succeeded``, ``failed`` or ``cancelled``."""
        return self.status in FINAL_STATES

    @property
    def succeeded(self) -> bool:
        return self.status == "succeeded"

    def __repr__(self) -> str:
        return "Job(id=%r, status=%r, progress=%.3f)" % (self.id, self.status, self.progress)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Job) and other.data == self.data

    __hash__ = None  # type: ignore[assignment]


JobRef = Union[Job, str]


def _file_mode(path: str) -> int:
    """The permissions ``open(path, "w")`` would leave: those of the file it replaces, else
    0666 less the process umask."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode)
    except OSError:
        pass
    mask = os.umask(0o022)  # reading the umask means setting it; put it straight back
    os.umask(mask)
    return 0o666 & ~mask


def _job_id(job: JobRef) -> str:
    job_id = job.id if isinstance(job, Job) else str(job)
    if not job_id or "/" in job_id or "?" in job_id or "#" in job_id:
        raise ValueError("not a job id: %r" % (job_id,))
    return job_id


class Response:
    """One HTTP answer: ``status``, ``headers`` (an ``email.message.Message``) and ``body``."""

    __slots__ = ("status", "headers", "body")

    def __init__(self, status: int, headers: Any, body: bytes) -> None:
        self.status = status
        self.headers = headers
        self.body = body

    def header(self, name: str) -> Optional[str]:
        return self.headers.get(name) if self.headers is not None else None

    def json(self) -> Any:
        return json.loads(self.body.decode("utf-8"))


def parse_retry_after(value: Optional[str]) -> Optional[float]:
    """``Retry-After`` as seconds: delta-seconds or an HTTP date; ``None`` when absent or bad."""
    if value is None:
        return None
    value = value.strip()
    if value.isdigit():
        return float(value)
    try:
        when = email.utils.parsedate_to_datetime(value)
    except (TypeError, ValueError, IndexError):
        return None
    if when is None:
        return None
    return max(0.0, when.timestamp() - time.time())


# --------------------------------------------------------------------------- BRF1 frames

_BRF1_HEADER = struct.Struct("<4sIII")


def parse_brf1(data: bytes) -> Tuple[int, List[int], List[Tuple[float, List[Pose]]]]:
    """Decode a binary frames body (``BRF1``, little-endian, see api/openapi.yaml).

    Returns ``(first_frame_index, body_indices, frames)`` where each frame is
    ``(time_s, [((x, y, z), (qx, qy, qz, qw)), ...])`` in the order of ``body_indices``.
    """
    view = memoryview(data)
    if len(view) < _BRF1_HEADER.size:
        raise FrameFormatError("BRF1 body of %d bytes is shorter than its header" % len(view))
    magic, first, frame_count, body_count = _BRF1_HEADER.unpack_from(view, 0)
    if magic != b"BRF1":
        raise FrameFormatError("not a BRF1 body (magic %r)" % (bytes(magic),))
    offset = _BRF1_HEADER.size
    record = struct.Struct("<d%df" % (7 * body_count))
    expected = offset + 4 * body_count + frame_count * record.size
    if len(view) != expected:
        raise FrameFormatError("BRF1 body of %d frames x %d bodies should be %d bytes, got %d"
                               % (frame_count, body_count, expected, len(view)))
    bodies = list(struct.unpack_from("<%dI" % body_count, view, offset))
    offset += 4 * body_count
    frames: List[Tuple[float, List[Pose]]] = []
    for values in record.iter_unpack(view[offset:]):
        poses = [(values[1 + 7 * k:4 + 7 * k], values[4 + 7 * k:8 + 7 * k])
                 for k in range(body_count)]
        frames.append((values[0], poses))  # type: ignore[arg-type]
    return first, bodies, frames


# --------------------------------------------------------------------------- the client


def _is_loopback(host: Optional[str]) -> bool:
    if not host:
        return False
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _limit_body(element: Mapping[str, Any], ductility: Optional[float],
                rotation_deg: Optional[float], points: Optional[int]) -> Dict[str, Any]:
    """The body of ``POST /v1/pi``: the element, its damage limit and the number of points."""
    body: Dict[str, Any] = {"element": element}
    if ductility is not None:
        body["ductility"] = float(ductility)
    if rotation_deg is not None:
        body["rotation_deg"] = float(rotation_deg)
    if points is not None:
        body["points"] = int(points)
    return body


class Client:
    """The Brisance HTTP API.

    Args:
        url: the server, ``$BRISANCE_URL`` or ``http://127.0.0.1:8080`` by default.
        api_key: sent as ``Authorization: Bearer KEY``; ``$BRISANCE_API_KEY`` by default,
            ``""`` for none.
        timeout: socket timeout of one request in seconds (a long-poll adds its wait to it).
        max_retries: retries of one call on 429, 503 and connection errors (see the module doc).
        max_retry_wait: the most one call may spend waiting between retries, in seconds.
        backoff_base, backoff_cap: the exponential backoff, ``base * 2**attempt`` capped.
        sleep: the function used to wait (tests replace it).
    """

    def __init__(
        self,
        url: Optional[str] = None,
        api_key: Optional[str] = None,
        *,
        timeout: float = 30.0,
        max_retries: int = 5,
        max_retry_wait: float = 120.0,
        backoff_base: float = 0.5,
        backoff_cap: float = 30.0,
        user_agent: Optional[str] = None,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        url = url or os.environ.get("BRISANCE_URL") or DEFAULT_URL
        parsed = urllib.parse.urlsplit(url)
        if parsed.scheme not in ("http", "https") or not parsed.netloc:
            raise ValueError("the server URL must be http(s)://HOST[:PORT], got %r" % (url,))
        self.url = url.rstrip("/")
        self.api_key = os.environ.get("BRISANCE_API_KEY", "") if api_key is None else api_key
        self.timeout = float(timeout)
        self.max_retries = int(max_retries)
        self.max_retry_wait = float(max_retry_wait)
        self.backoff_base = float(backoff_base)
        self.backoff_cap = float(backoff_cap)
        self.user_agent = user_agent or "brisance-client-python/%s" % __version__
        self._sleep = sleep
        handlers: List[urllib.request.BaseHandler] = []
        if _is_loopback(parsed.hostname):
            handlers.append(urllib.request.ProxyHandler({}))  # never send loopback via a proxy
        self._opener = urllib.request.build_opener(*handlers)

    def __repr__(self) -> str:
        return "Client(%r)" % self.url

    # ----------------------------------------------------------------- transport

    def _backoff(self, attempt: int) -> float:
        delay = min(self.backoff_cap, self.backoff_base * (2 ** attempt))
        return delay * random.uniform(0.5, 1.0)

    def request(
        self,
        method: str,
        path: str,
        *,
        query: Optional[Mapping[str, Any]] = None,
        body: Optional[bytes] = None,
        headers: Optional[Mapping[str, str]] = None,
        accept: str = "application/json",
        ok: Sequence[int] = (200,),
        timeout: Optional[float] = None,
        retry_transport: str = "always",
        sink: Optional[BinaryIO] = None,
    ) -> Response:
        """Send one request with the retry policy; raise :class:`ProblemError` unless its
        status is in ``ok``. ``retry_transport`` is ``always``, ``refused`` or ``never``. With
        ``sink``, a successful body is copied into that file instead of being kept."""
        url = self.url + path
        if query:
            url += "?" + urllib.parse.urlencode(
                [(k, v) for k, v in query.items() if v is not None])
        all_headers = {"User-Agent": self.user_agent, "Accept": accept}
        if self.api_key:
            all_headers["Authorization"] = "Bearer " + self.api_key
        if headers:
            all_headers.update(headers)
        waited = 0.0
        attempt = 0
        while True:
            request = urllib.request.Request(url, data=body, headers=all_headers, method=method)
            try:
                response = self._exchange(request, timeout or self.timeout, ok, sink)
            except _Transport as failure:
                cause = failure.cause
                retryable = retry_transport == "always" or (
                    retry_transport == "refused" and isinstance(cause, ConnectionRefusedError))
                delay = self._backoff(attempt)
                if (not retryable or attempt >= self.max_retries
                        or waited + delay > self.max_retry_wait):
                    raise TransportError("%s %s: %s" % (method, url, cause), cause) from cause
                self._sleep(delay)
                waited += delay
                attempt += 1
                continue
            if response.status in (429, 503) and response.status not in ok:
                retry_after = parse_retry_after(response.header("Retry-After"))
                delay = max(retry_after or 0.0, self._backoff(attempt))
                if attempt < self.max_retries and waited + delay <= self.max_retry_wait:
                    self._sleep(delay)
                    waited += delay
                    attempt += 1
                    continue
            if response.status not in ok:
                raise self._problem(response)
            return response

    def _exchange(self, request: urllib.request.Request, timeout: float, ok: Sequence[int],
                  sink: Optional[BinaryIO]) -> Response:
        try:
            try:
                answer = self._opener.open(request, timeout=timeout)
            except urllib.error.HTTPError as error:  # every status urllib thinks is an error
                answer = error
            with answer:
                status = answer.status if answer.status is not None else answer.getcode()
                if sink is not None and status in ok:
                    sink.seek(0)
                    sink.truncate()
                    shutil.copyfileobj(answer, sink, 1 << 16)
                    data = b""
                else:
                    data = answer.read()
                return Response(status, answer.headers, data)
        except urllib.error.URLError as error:
            reason = error.reason
            raise _Transport(reason if isinstance(reason, BaseException) else error) from error
        except (OSError, http.client.HTTPException) as error:  # reset, timeout, closed early
            raise _Transport(error) from error

    @staticmethod
    def _problem(response: Response) -> ProblemError:
        problem: Dict[str, Any] = {}
        text = ""
        try:
            decoded = response.json()
            if isinstance(decoded, dict):
                problem = decoded
        except (ValueError, UnicodeDecodeError):
            text = response.body[:500].decode("utf-8", "replace").strip()
        return ProblemError(response.status, problem,
                            retry_after=parse_retry_after(response.header("Retry-After")),
                            request_id=response.header("X-Request-Id"),
                            fallback_detail=text)

    def _json(self, method: str, path: str, **kwargs: Any) -> Any:
        return self.request(method, path, **kwargs).json()

    # ----------------------------------------------------------------- jobs

    def submit(
        self,
        scene: Mapping[str, Any],
        priority: int = 0,
        *,
        name: Optional[str] = None,
        labels: Optional[Mapping[str, str]] = None,
        callback: Optional[str] = None,
        idempotency_key: Optional[str] = None,
    ) -> Job:
        """Queue a job ``{"scene": scene, "priority": priority}`` and return it (``queued``).

        ``name`` (at most 200 characters) and ``labels`` (up to 32 ``key: value`` strings) are
        kept with the job for lists and the dashboard; :meth:`jobs` filters by them.
        ``callback`` is an ``http://`` URL the server POSTs the finished job to (signed; see
        docs/service.md "Callbacks").

        Retries are safe: they carry the same ``Idempotency-Key`` (a fresh uuid4 unless given)
        and the same bytes. Raises :class:`ProblemError` -- ``422 invalid-scene`` with every
        problem in ``.errors`` as ``(pointer, detail)``; ``429 queue-full`` once the retry
        budget is spent.
        """
        if not isinstance(scene, Mapping):
            raise TypeError("scene must be a mapping (the decoded scene JSON)")
        body: Dict[str, Any] = {"scene": scene, "priority": priority}
        if name is not None:
            body["name"] = name
        if labels is not None:
            body["labels"] = dict(labels)
        if callback is not None:
            body["callback"] = callback
        return self.submit_job(body, idempotency_key=idempotency_key)

    def submit_job(self, job: Mapping[str, Any], *, idempotency_key: Optional[str] = None) -> Job:
        """Queue a whole job body (``{"scene": ..., "priority": ...}``) as given."""
        key = idempotency_key or str(uuid.uuid4())
        payload = json.dumps(job, separators=(",", ":"), allow_nan=False).encode("utf-8")
        response = self.request(
            "POST", "/v1/jobs", body=payload, ok=(200, 202),
            headers={"Content-Type": "application/json", "Idempotency-Key": key})
        return Job(response.json(), response.header("ETag"))

    def job(self, job: JobRef) -> Job:
        """The job's current state (``GET /v1/jobs/{id}``)."""
        response = self.request("GET", "/v1/jobs/" + _job_id(job))
        return Job(response.json(), response.header("ETag"))

    status = job  # ``client.status(id)`` reads as well as ``client.job(id)``

    def poll(self, job: Job, wait: int = MAX_LONG_POLL_S) -> Job:
        """One long-poll: the job once it differs from ``job`` (by ``ETag``), or ``job`` itself
        when ``wait`` seconds pass unchanged (``304``)."""
        wait = max(0, min(MAX_LONG_POLL_S, int(wait)))
        headers = {"If-None-Match": job.etag} if job.etag else None
        response = self.request("GET", "/v1/jobs/" + _job_id(job), query={"wait": wait},
                                headers=headers, ok=(200, 304), timeout=self.timeout + wait)
        if response.status == 304:
            return job
        return Job(response.json(), response.header("ETag"))

    def wait(
        self,
        job: JobRef,
        timeout: Optional[float] = None,
        *,
        progress: Optional[Callable[[Job], None]] = None,
        raise_on_failure: bool = True,
    ) -> Job:
        """Wait until the job is finished and return it, long-polling (``?wait=`` with
        ``If-None-Match``) so that every change arrives at once without busy polling.

        ``progress(job)`` is called with the first state and every change. A job that ends
        ``failed`` or ``cancelled`` raises :class:`JobFailedError` unless ``raise_on_failure``
        is false; running out of ``timeout`` seconds raises :class:`WaitTimeoutError`.
        """
        deadline = None if timeout is None else time.monotonic() + timeout
        current = job if isinstance(job, Job) and job.etag else self.job(job)
        if progress:
            progress(current)
        while not current.finished:
            wait = MAX_LONG_POLL_S
            if deadline is not None:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise WaitTimeoutError(current, timeout or 0.0)
                wait = max(1, min(MAX_LONG_POLL_S, int(remaining + 0.999)))
            changed = self.poll(current, wait)
            if changed is not current:
                current = changed
                if progress:
                    progress(current)
        if raise_on_failure and not current.succeeded:
            raise JobFailedError(current)
        return current

    def run(self, scene: Mapping[str, Any], priority: int = 0, *,
            timeout: Optional[float] = None,
            progress: Optional[Callable[[Job], None]] = None) -> Job:
        """Submit and wait: the succeeded job (or :class:`JobFailedError`)."""
        return self.wait(self.submit(scene, priority), timeout, progress=progress)

    def jobs(self, status: Optional[str] = None, limit: int = 50, *,
             labels: Optional[Mapping[str, Optional[str]]] = None,
             name: Optional[str] = None) -> Iterator[Job]:
        """Every job, newest first, following ``next_cursor`` page by page.

        Only jobs with every label in ``labels`` (a value of ``None`` asks only that the key is
        there) and, with ``name``, whose name contains that text.
        """
        label = None
        if labels:
            label = ",".join(key if value is None else "%s=%s" % (key, value)
                             for key, value in labels.items())
        cursor: Optional[str] = None
        while True:
            page = self._json("GET", "/v1/jobs",
                              query={"status": status, "limit": limit, "cursor": cursor,
                                     "label": label, "name": name})
            for item in page["jobs"]:
                yield Job(item)
            cursor = page.get("next_cursor")
            if not cursor:
                return

    def cancel(self, job: JobRef) -> Job:
        """Cancel: a queued job is ``cancelled`` at once, a running one gets
        ``cancel_requested`` and stops within a step (``wait()`` to see it end). A finished job
        raises ``ProblemError`` ``409 job-finished``."""
        response = self.request("POST", "/v1/jobs/%s/cancel" % _job_id(job), ok=(200, 202),
                                retry_transport="refused")
        return Job(response.json())

    def delete(self, job: JobRef) -> None:
        """Delete the job and its results (stopping it first if it runs)."""
        self.request("DELETE", "/v1/jobs/" + _job_id(job), ok=(204,))

    # ----------------------------------------------------------------- results

    def scene(self, job: JobRef) -> Dict[str, Any]:
        """The scene as submitted."""
        return self._json("GET", "/v1/jobs/%s/scene" % _job_id(job))

    def result(self, job: JobRef) -> Dict[str, Any]:
        """The result summary (bodies, frame times, final state, stats, warnings, job).
        ``409 result-not-ready`` unless the job succeeded."""
        return self._json("GET", "/v1/jobs/%s/result" % _job_id(job))

    def meshes(self, job: JobRef) -> Dict[str, Any]:
        """Every body's triangle mesh in its own frame."""
        return self._json("GET", "/v1/jobs/%s/meshes" % _job_id(job))

    def frames(
        self,
        job: JobRef,
        from_: int = 0,
        to: Optional[int] = None,
        bodies: Optional[Sequence[int]] = None,
        binary: bool = True,
        *,
        chunk: int = 1000,
    ) -> Iterator[Frame]:
        """Iterate frames ``[from_, to)`` as ``(index, time_s, {body: (position, orientation)})``,
        ``chunk`` frames per request; ``to`` defaults to the frame count. ``bodies`` selects body
        indices (default: the bodies that move). ``binary`` fetches the compact ``BRF1`` form;
        otherwise JSON -- both give the same float32 poses."""
        job_id = _job_id(job)
        if to is None:
            to = int(self.result(job_id)["frame_count"])
        if from_ < 0 or to < from_:
            raise ValueError("need 0 <= from_ <= to, got %d and %d" % (from_, to))
        chunk = max(1, int(chunk))
        selection = None if bodies is None else ",".join(str(int(b)) for b in bodies)
        start = from_
        while start < to:
            end = min(to, start + chunk)
            query = {"from": start, "to": end, "bodies": selection}
            path = "/v1/jobs/%s/frames" % job_id
            if binary:
                data = self.request("GET", path, query=query,
                                    accept="application/octet-stream").body
                first, indices, frames = parse_brf1(data)
                if first != start or len(frames) != end - start:
                    raise FrameFormatError("asked for frames [%d, %d), got %d from %d"
                                           % (start, end, len(frames), first))
                for offset, (t, poses) in enumerate(frames):
                    yield first + offset, t, dict(zip(indices, poses))
            else:
                page = self._json("GET", path, query=query)
                for frame in page["frames"]:
                    yield frame["index"], frame["time"], {
                        pose["body"]: (tuple(pose["position"]), tuple(pose["orientation"]))
                        for pose in frame["poses"]}
            start = end

    def glb(self, job: JobRef) -> bytes:
        """The animated glTF binary, in memory."""
        return self.request("GET", "/v1/jobs/%s/result.glb" % _job_id(job),
                            accept="model/gltf-binary").body

    def download_glb(self, job: JobRef, path: Union[str, "os.PathLike[str]"]) -> str:
        """Save the animated glTF binary to ``path`` (written to a temporary file in the same
        folder, then renamed, so ``path`` is never left half-written). Returns the path."""
        target = os.fspath(path)
        folder = os.path.dirname(os.path.abspath(target))
        handle, temporary = tempfile.mkstemp(prefix=".brisance-", suffix=".glb", dir=folder)
        try:
            # mkstemp makes the file 0600; the saved file gets the mode open() would give it.
            os.fchmod(handle, _file_mode(target))
            with os.fdopen(handle, "w+b") as sink:
                self.request("GET", "/v1/jobs/%s/result.glb" % _job_id(job),
                             accept="model/gltf-binary", sink=sink)
                sink.seek(0)
                if sink.read(4) != b"glTF":
                    raise BrisanceError("the server's result.glb does not start with 'glTF'")
            os.replace(temporary, target)
        except BaseException:
            try:
                os.unlink(temporary)
            except OSError:
                pass
            raise
        return target

    # ----------------------------------------------------------------- service

    # ----------------------------------------------------------------- assets

    ASSET_MEDIA_TYPES = {"glb": "model/gltf-binary", "gltf": "model/gltf+json",
                         "obj": "model/obj"}

    def upload_asset(self, data: Union[bytes, str, "os.PathLike[str]"],
                     format: Optional[str] = None) -> Dict[str, Any]:
        """Upload a mesh file (``POST /v1/assets``): GLB, glTF with embedded buffers, or OBJ,
        in metres. ``data`` is the file's bytes or its path; ``format`` (``glb``, ``gltf``,
        ``obj``) defaults to the path's extension. Returns the asset (``id``, ``format``,
        ``size_bytes``, ``nodes``); a scene names it as ``{"type": "asset", "asset": id,
        "node": name}``. Uploading the same file again returns the same asset. Raises
        :class:`ProblemError` -- ``422 invalid-asset`` with the reason for a mesh that is not
        closed or not manifold, ``413`` for a file over the limit."""
        if not isinstance(data, bytes):
            path = os.fspath(data)
            if format is None:
                format = os.path.splitext(path)[1].lstrip(".").lower()
            with open(path, "rb") as handle:
                data = handle.read()
        if format not in self.ASSET_MEDIA_TYPES:
            raise ValueError("format must be one of glb, gltf, obj; got %r" % (format,))
        return self.request("POST", "/v1/assets", body=data, ok=(200, 201),
                            headers={"Content-Type": self.ASSET_MEDIA_TYPES[format]}).json()

    def asset(self, asset_id: str) -> Dict[str, Any]:
        """An uploaded asset (``GET /v1/assets/{id}``)."""
        return self._json("GET", "/v1/assets/" + urllib.parse.quote(asset_id, safe=""))

    def blast(self, charge_kg: float, distance_m: float, *, explosive: Optional[str] = None,
              burst: Optional[str] = None, angle_deg: Optional[float] = None) -> Dict[str, Any]:
        """Blast-wave numbers at ``distance_m`` from ``charge_kg`` (Kingery-Bulmash)."""
        return self._json("GET", "/v1/blast", query={
            "charge_kg": repr(float(charge_kg)), "distance_m": repr(float(distance_m)),
            "explosive": explosive, "burst": burst,
            "angle_deg": None if angle_deg is None else repr(float(angle_deg))})

    def response(self, element: Mapping[str, Any], *,
                 charge: Optional[Mapping[str, Any]] = None,
                 pulse: Optional[Mapping[str, Any]] = None,
                 history: bool = True) -> Dict[str, Any]:
        """The SDOF response of ``element`` (``POST /v1/response``, docs/response.md) to a
        ``charge`` (``{"charge_kg", "distance_m", ...}`` as :meth:`blast`) or a ``pulse``
        (``{"peak_kpa", "duration_ms", "shape"}``), exactly one. Raises :class:`ProblemError`
        ``422 invalid-input`` with every bad field in ``.errors`` as ``(pointer, detail)``."""
        body: Dict[str, Any] = {"element": element, "history": history}
        if charge is not None:
            body["charge"] = charge
        if pulse is not None:
            body["pulse"] = pulse
        return self._post_json("/v1/response", body)

    def pi(self, element: Mapping[str, Any], *, ductility: Optional[float] = None,
           rotation_deg: Optional[float] = None, points: Optional[int] = None) -> Dict[str, Any]:
        """The pressure-impulse curve of ``element`` for a ductility ratio or a support rotation
        (``POST /v1/pi``), with its two asymptotes."""
        return self._post_json("/v1/pi", _limit_body(element, ductility, rotation_deg, points))

    def wr(self, element: Mapping[str, Any], *, ductility: Optional[float] = None,
           rotation_deg: Optional[float] = None, points: Optional[int] = None,
           distances_m: Optional[Sequence[float]] = None, burst: Optional[str] = None,
           angle_deg: Optional[float] = None) -> Dict[str, Any]:
        """The charge weight-stand-off (W-R) diagram of ``element`` for a ductility ratio or a
        support rotation (``POST /v1/pi`` with ``"diagram": "wr"``): for each stand-off in
        ``distances_m`` = [min, max] (log-spaced), the TNT charge that just reaches the limit."""
        body = _limit_body(element, ductility, rotation_deg, points)
        body["diagram"] = "wr"
        if distances_m is not None:
            body["distances_m"] = [float(d) for d in distances_m]
        if burst is not None:
            body["burst"] = burst
        if angle_deg is not None:
            body["angle_deg"] = float(angle_deg)
        return self._post_json("/v1/pi", body)

    def _post_json(self, path: str, body: Mapping[str, Any]) -> Dict[str, Any]:
        payload = json.dumps(body, separators=(",", ":"), allow_nan=False).encode("utf-8")
        return self.request("POST", path, body=payload,
                            headers={"Content-Type": "application/json"}).json()

    def explosives(self) -> List[Dict[str, Any]]:
        """The explosives a charge may name, with their TNT factors."""
        return self._json("GET", "/v1/explosives")["explosives"]

    def queue(self) -> Dict[str, Any]:
        """Jobs by state, workers, the oldest queued job, throughput."""
        return self._json("GET", "/v1/queue")

    def health(self) -> Dict[str, Any]:
        return self._json("GET", "/healthz")

    def ready(self) -> bool:
        """True when the store answers and workers run (``/readyz`` 200)."""
        return self.request("GET", "/readyz", ok=(200, 503)).status == 200

    def metrics(self) -> str:
        """Prometheus text."""
        return self.request("GET", "/metrics", accept="text/plain").body.decode("utf-8")

    def openapi(self) -> str:
        """The server's contract, api/openapi.yaml."""
        return self.request("GET", "/openapi.yaml", accept="application/yaml").body.decode(
            "utf-8")


class _Transport(Exception):
    """Internal: a request failed below HTTP."""

    def __init__(self, cause: BaseException) -> None:
        super().__init__(str(cause))
        self.cause = cause


__all__ = ["Client", "Job", "Response", "parse_brf1", "parse_retry_after", "DEFAULT_URL",
           "FINAL_STATES", "JobFailedError", "ProblemError", "TransportError",
           "WaitTimeoutError"]
