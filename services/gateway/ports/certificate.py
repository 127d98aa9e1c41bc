"""The gateway's TLS certificate (docs/robot-api.md §3.5 ``check_cert``): loaded with its key
at start, read again from its file on every check, so a renewed certificate shows at once.

The fields come from the standard `ssl` module's own reader of a PEM certificate (the one
its test suite uses, ``ssl._ssl._test_decode_cert``): no extra dependency."""

from __future__ import annotations

import ssl
import time
from pathlib import Path
from typing import Any

from ..errors import Failed, Unavailable

__all__ = ["check_certificate", "load_tls"]


def load_tls(cert: str, key: str) -> None:
    """Whether ``cert`` and ``key`` make a server's TLS identity; ValueError saying why."""
    try:
        ssl.create_default_context(ssl.Purpose.CLIENT_AUTH).load_cert_chain(cert, key)
    except (OSError, ssl.SSLError) as exc:
        raise ValueError(f"tls_cert {cert!r} with tls_key {key!r}: {exc}") from None


def _name(parts: Any) -> str:
    return ", ".join(f"{k}={v}" for rdn in parts for k, v in rdn)


def check_certificate(cert: str, now: float | None = None) -> dict[str, Any]:
    """The certificate's subject, issuer, validity and days left; ``status`` ``ok``, or
    ``expired`` / ``not yet valid``.

    Raises:
        Unavailable: the gateway serves no certificate.
        Failed: its file cannot be read as a certificate.
    """
    if not cert:
        raise Unavailable("the gateway serves no TLS certificate: give its tls_cert and "
                          "tls_key parameters (docs/gateway.md, \"HTTPS\")")
    if not Path(cert).is_file():
        raise Failed(f"the gateway's certificate {cert} is gone")
    try:
        info = ssl._ssl._test_decode_cert(cert)  # type: ignore[attr-defined]
    except (OSError, ssl.SSLError, ValueError) as exc:
        raise Failed(f"the gateway's certificate {cert} cannot be read: {exc}") from None
    start = ssl.cert_time_to_seconds(info["notBefore"])
    end = ssl.cert_time_to_seconds(info["notAfter"])
    now = time.time() if now is None else now
    status = "ok" if start <= now <= end else ("expired" if now > end else "not yet valid")
    return {"status": status, "subject": _name(info.get("subject", ())),
            "issuer": _name(info.get("issuer", ())),
            "not_before": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(start)),
            "not_after": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(end)),
            "days_left": int((end - now) // 86400)}
