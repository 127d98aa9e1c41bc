"""Parameter descriptions: each node answers what it declared (type, description, read-only).

A node serves one queryable, ``<prefix>/paramdesc/<node fqn>``, that replies a JSON object
``{"rate": {"type": "float", "description": "...", "read_only": false}, ...}`` built from its
declared parameters at query time (a parameter declared with limits, see
`zenros.param_config`, adds ``"constraints": {"gt": 0.0}``) (ROS 2's ``describe_parameters``, without a graph entry).
The CLI reads it to refuse ``zenros param set /talker/rate fast`` before storing a value the
node would reject.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

import zenoh

if TYPE_CHECKING:
    from .context import Context
    from .params import Parameters

__all__ = ["ParameterDescriptions", "describe", "fetch_descriptions"]

_TYPE_NAMES = {bool: "bool", int: "int", float: "float", str: "str", bytes: "bytes",
               list: "list", dict: "dict", type(None): "not set"}


def describe(params: Parameters) -> dict[str, dict[str, Any]]:
    """The declared parameters as plain data."""
    out: dict[str, dict[str, Any]] = {}
    for p in params.describe():
        entry: dict[str, Any] = {"type": _TYPE_NAMES.get(p.type, p.type.__name__),
                                 "description": p.description, "read_only": p.read_only}
        if p.constraints:
            entry["constraints"] = dict(p.constraints)
        if p.dynamic_typing:
            entry["dynamic_typing"] = True
        out[p.name] = entry
    return out


class ParameterDescriptions:
    """The queryable that answers a node's parameter descriptions (closed with the node)."""

    def __init__(self, ctx: Context, node_fqn: str, params: Parameters) -> None:
        self._params = params
        self._queryable = ctx.session.declare_queryable(
            ctx.keys.param_describe(node_fqn), self._on_query)

    def _on_query(self, query: zenoh.Query) -> None:
        try:
            body = json.dumps(describe(self._params))
            query.reply(query.key_expr, body.encode(), encoding=zenoh.Encoding.APPLICATION_JSON)
        except Exception:  # noqa: BLE001, S110 -- a failed reply must never end the serving thread
            pass

    def close(self) -> None:
        try:
            self._queryable.undeclare()  # type: ignore[no-untyped-call]  # zenoh stub: unannotated
        except zenoh.ZError:
            pass


def fetch_descriptions(ctx: Context, node_fqn: str,
                       timeout: float = 2.0) -> dict[str, dict[str, Any]] | None:
    """What ``node_fqn`` declared, or None when it does not answer."""
    for reply in ctx.session.get(ctx.keys.param_describe(node_fqn), timeout=timeout):
        if reply.ok is None:
            continue
        try:
            data = json.loads(reply.ok.payload.to_bytes())
        except ValueError:
            continue
        if isinstance(data, dict):
            return data
    return None
