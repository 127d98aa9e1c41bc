"""An rmw_zenoh service (an ``SS`` token of another session) served to zenros clients.

The bridge declares a zenros queryable and ``srv`` token under the service's ROS name and an
``SC`` token in the rmw_zenoh graph; each zenros request is re-encoded as CDR and sent as
rmw_zenoh's client sends it (`rmw_io.Requester`: target ALL_COMPLETE, the attachment); the
reply must echo the request's sequence number and GID, else the zenros caller gets an error
(``RemoteError``) naming both.
"""

from __future__ import annotations

from typing import Any

import zenoh
from zenros.codec import Codec, codec_for
from zenros.errors import CodecError
from zenros.message import ServiceType
from zenros.ros2.cdr import CdrCodec, cdr_codec
from zenros.ros2.rmw_zenoh import EntityKind, Qos, data_key
from zenros.rpc import error_payload

from .host import BridgeHost
from .rmw_io import Requester

__all__ = ["ServiceIn"]


class ServiceIn:
    def __init__(self, bridge: BridgeHost, name: str, srv: ServiceType) -> None:
        self.bridge = bridge
        self.name = name
        pkg, _, short = srv.name.partition("/")
        ros_type = f"{pkg}/srv/{short}"
        self.req_native: Codec[Any] = codec_for(srv.Request)
        self.res_native: Codec[Any] = codec_for(srv.Response)
        self.req_cdr: CdrCodec[Any] = cdr_codec(srv.Request)
        self.res_cdr: CdrCodec[Any] = cdr_codec(srv.Response)
        self.res_enc = zenoh.Encoding(self.res_native.mime).with_schema(self.res_native.type_name)
        s = bridge.session
        ctx = bridge.context
        ent = bridge.entity(EntityKind.CLIENT, name, ros_type, Qos(depth=10))
        self.requester = Requester(s, data_key(bridge.domain, name, ros_type), ent.gid)
        self.rmw_token = s.liveliness().declare_token(ent.token())
        self.queryable = s.declare_queryable(ctx.keys.service(name), self._on_query,
                                             complete=True)
        self.token = s.liveliness().declare_token(ctx.keys.entity_token(
            "srv", bridge.fqn, name, srv.name, "", ctx.zid, ctx.next_eid()))

    def _on_query(self, query: zenoh.Query) -> None:
        try:
            payload = query.payload.to_bytes() if query.payload is not None else b"{}"
            data = self.req_cdr.encode(self.req_native.decode(payload))
        except CodecError as exc:
            query.reply_err(error_payload("BadRequest", f"service {self.name}: {exc}"))
            query.drop()  # type: ignore[no-untyped-call]
            return

        def done(reply: bytes | None, why: str) -> None:
            self.bridge.pool.submit(self._answer, query, reply, why)

        self.requester.call(data, self.bridge.call_timeout, done)

    def _answer(self, query: zenoh.Query, reply: bytes | None, why: str) -> None:
        try:
            if reply is None:
                kind = "ServiceUnavailable" if why == "no reply" else "RemoteError"
                query.reply_err(error_payload(kind, f"ROS 2 service {self.name}: {why}"))
                return
            try:
                data = self.res_native.encode(self.res_cdr.decode(reply))
            except CodecError as exc:
                self.bridge.problems(f"bad reply {self.name}", "ROS 2 service %s: bad reply: %s",
                                     self.name, exc)
                query.reply_err(error_payload("BadResponse", str(exc)))
                return
            query.reply(query.key_expr, data, encoding=self.res_enc)
        finally:
            query.drop()  # type: ignore[no-untyped-call]

    def close(self) -> None:
        self.token.undeclare()  # type: ignore[no-untyped-call]
        self.queryable.undeclare()  # type: ignore[no-untyped-call]
        self.rmw_token.undeclare()  # type: ignore[no-untyped-call]
