"""Python client of the Brisance blast-simulation job service (standard library only).

    from brisance_client import Client
    client = Client("http://127.0.0.1:8080")            # or $BRISANCE_URL, $BRISANCE_API_KEY
    job = client.wait(client.submit(scene), progress=lambda j: print(j.status, j.progress))
    client.download_glb(job, "out.glb")
"""

__version__ = "0.1.0"

from .errors import (BrisanceError, FrameFormatError, JobFailedError, ProblemError,  # noqa: E402
                     TransportError, WaitTimeoutError)
from .client import (DEFAULT_URL, FINAL_STATES, Client, Job, Response, parse_brf1,  # noqa: E402
                     parse_retry_after)

__all__ = [
    "__version__",
    "Client",
    "Job",
    "Response",
    "BrisanceError",
    "ProblemError",
    "JobFailedError",
    "TransportError",
    "WaitTimeoutError",
    "FrameFormatError",
    "parse_brf1",
    "parse_retry_after",
    "DEFAULT_URL",
    "FINAL_STATES",
]
