"""Exceptions raised by the Brisance client."""

from __future__ import annotations

from typing import Any, Dict, List, Mapping, Optional, Tuple

PROBLEM_PREFIX = "urn:brisance:problem:"


class BrisanceError(Exception):
    """Base class of every error this package raises."""


class ProblemError(BrisanceError):
    """The server answered with an error (an RFC 9457 ``application/problem+json`` body).

    Attributes:
        status: the HTTP status code (``422``).
        type: the problem type URN (``urn:brisance:problem:invalid-scene``); ``about:blank``
            when the body was not a problem document (a proxy's error page, say).
        title, detail: the problem's summary and explanation.
        errors: ``[(pointer, detail), ...]`` -- every problem of a rejected job, each located by
            an RFC 6901 JSON pointer into the request body (``/scene/objects/0/mass``).
        parameters: ``[(parameter, detail), ...]`` -- the invalid query parameters of a
            ``400 invalid-parameter`` problem.
        retry_after: the ``Retry-After`` delay in seconds, or ``None``.
        request_id: the response's ``X-Request-Id`` (the server log line has the same id).
        body: the decoded problem document (a dict; empty when there was none).
    """

    def __init__(
        self,
        status: int,
        problem: Optional[Mapping[str, Any]] = None,
        *,
        retry_after: Optional[float] = None,
        request_id: Optional[str] = None,
        fallback_detail: str = "",
    ) -> None:
        body: Dict[str, Any] = dict(problem or {})
        self.status: int = status
        self.type: str = str(body.get("type", "about:blank"))
        self.title: str = str(body.get("title", "HTTP %d" % status))
        self.detail: str = str(body.get("detail", fallback_detail))
        self.errors: List[Tuple[str, str]] = []
        self.parameters: List[Tuple[str, str]] = []
        for item in body.get("errors") or []:
            if not isinstance(item, Mapping):
                continue
            detail = str(item.get("detail", ""))
            if "pointer" in item:
                self.errors.append((str(item["pointer"]), detail))
            elif "parameter" in item:
                self.parameters.append((str(item["parameter"]), detail))
        self.retry_after = retry_after
        self.request_id = request_id
        self.body = body
        super().__init__(self._message())

    @property
    def kind(self) -> str:
        """The short problem name: ``invalid-scene`` for ``urn:brisance:problem:invalid-scene``."""
        if self.type.startswith(PROBLEM_PREFIX):
            return self.type[len(PROBLEM_PREFIX):]
        return self.type

    def _message(self) -> str:
        text = "%d %s" % (self.status, self.title)
        if self.detail:
            text += ": " + self.detail
        for pointer, detail in self.errors:
            text += "\n  %s: %s" % (pointer or "(body)", detail)
        for parameter, detail in self.parameters:
            text += "\n  ?%s: %s" % (parameter, detail)
        return text


class TransportError(BrisanceError):
    """The server could not be reached (connection refused or reset, timeout) after retries."""

    def __init__(self, message: str, cause: Optional[BaseException] = None) -> None:
        super().__init__(message)
        self.cause = cause


class JobFailedError(BrisanceError):
    """A waited-for job ended ``failed`` or ``cancelled`` instead of ``succeeded``.

    ``job`` is the final :class:`~brisance_client.Job`; for a failed job ``error_type``
    (``simulation_error``, ``timeout``, ``worker_lost``, ``invalid_scene``, ``limit_exceeded``,
    ``memory_budget_exceeded``) and ``message`` come from its ``error`` field.
    """

    def __init__(self, job: Any) -> None:
        self.job = job
        error = job.error or {}
        self.error_type: Optional[str] = error.get("type")
        self.message: Optional[str] = error.get("message")
        if job.status == "failed":
            text = "job %s failed" % job.id
            if self.error_type or self.message:
                text += ": %s: %s" % (self.error_type, self.message)
        else:
            text = "job %s was %s" % (job.id, job.status)
        super().__init__(text)


class WaitTimeoutError(BrisanceError, TimeoutError):
    """``wait()`` ran out of time before the job finished; ``job`` is its last known state."""

    def __init__(self, job: Any, timeout: float) -> None:
        self.job = job
        super().__init__("job %s still %s after %.1f s" % (job.id, job.status, timeout))


class FrameFormatError(BrisanceError):
    """A binary frames body (``BRF1``) was malformed."""
