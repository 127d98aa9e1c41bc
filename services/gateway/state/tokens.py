"""`TokenStore`: the docs/robot-api.md §2 access tokens (32 hex characters, issued for
username/password)."""

from __future__ import annotations

import hmac
import threading
import uuid
from collections import OrderedDict

from .config import GatewayConfig

__all__ = ["TokenStore"]


class TokenStore:
    """Issues tokens for the configured user and checks them.

    At most ``capacity`` tokens are valid at once; the oldest is forgotten first. With
    ``no_token_check`` every request passes, with or without a token.
    """

    def __init__(self, config: GatewayConfig, capacity: int = 1024) -> None:
        self.config = config
        self._capacity = capacity
        self._tokens: OrderedDict[str, None] = OrderedDict()
        self._lock = threading.Lock()

    @property
    def checking(self) -> bool:
        return not self.config.no_token_check

    def issue(self, username: str, password: str) -> str | None:
        """A new token for the right credentials, else None."""
        ok = hmac.compare_digest(username.encode(), self.config.username.encode())
        ok &= hmac.compare_digest(password.encode(), self.config.password.encode())
        if not ok:
            return None
        token = uuid.uuid4().hex
        with self._lock:
            self._tokens[token] = None
            while len(self._tokens) > self._capacity:
                self._tokens.popitem(last=False)
        return token

    def problem(self, token: str | None) -> str | None:
        """None when ``token`` may pass; otherwise why not."""
        if not self.checking:
            return None
        if not token:
            return "missing token: get one from /api/v1/token and pass ?token=..."
        if token not in self._tokens:
            return "invalid token"
        return None
