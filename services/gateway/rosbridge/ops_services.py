"""`ServiceOps`: rosbridge service calls, to zenros services and rosapi, and services a
client serves (``advertise_service``; its answers come back as ``service_response``): a
`Capability` of one client's session."""

from __future__ import annotations

import asyncio
import concurrent.futures
import itertools
from collections.abc import Callable
from typing import Any, cast

from zenros.action.types import CancelGoalRequest
from zenros.errors import ServiceError, UnknownTypeError, ZenrosError, ZenrosTimeout
from zenros.message import Message, ServiceType
from zenros.registry import lookup_service

from .bridge import BridgeError
from .capability import Capability, Session
from .convert import message_from_json, request_args, to_json
from .frames import (
    AdvertiseService,
    CallService,
    OpError,
    ServiceResponse,
    UnadvertiseService,
    frame_int,
    frame_name,
    frame_text,
    frame_type,
    legacy_id,
)
from .opaque import OpaqueService
from .rosapi import Rosapi, RosapiError
from .tf_republisher import SERVICE as TF_REPUBLISH_SERVICE

__all__ = ["ACTION_CANCEL", "CLIENT_SERVICE_TIMEOUT", "DEFAULT_SERVICE_TIMEOUT", "ServiceOps"]

DEFAULT_SERVICE_TIMEOUT = 10.0  # seconds, when call_service carries no timeout
CLIENT_SERVICE_TIMEOUT = 10.0  # seconds a browser has to answer a forwarded call
ACTION_CANCEL = "/_action/cancel_goal"
"""A ROS 2 action's hidden cancel service (roslibjs's ``Action.cancelAllGoals`` calls it)."""


class ServiceOps(Capability):
    """One client's calls out, and the services it serves (the owner of those of a type
    zenros does not know, `opaque.OpaqueService`)."""

    ops = {CallService: "op_call_service", ServiceResponse: "op_service_response",
           AdvertiseService: "op_advertise_service",
           UnadvertiseService: "op_unadvertise_service"}

    def __init__(self, session: Session) -> None:
        super().__init__(session)
        self.services: dict[str, Any] = {}
        self.pending: dict[str, tuple[concurrent.futures.Future[Any], str]] = {}
        self._request_ids = itertools.count(1)
        self._rosapi_turn = asyncio.Lock()  # one rosapi call of this client at a time, in order

    def op_call_service(self, frame: CallService) -> None:
        mid = legacy_id(frame, "service")
        given = frame.service
        try:
            service = frame_name(frame, "service")
        except OpError as exc:
            if given:
                self._service_failed(given, mid, str(exc))
                return
            raise
        self.spawn(self._call_service(service, str(given), mid, frame))

    def _service_failed(self, service: str, mid: Any, reason: str) -> None:
        self.report("error", f"call_service {service}: {reason}", mid)
        reply: dict[str, Any] = {"op": "service_response", "service": service,
                                 "values": reason, "result": False}
        if mid is not None:
            reply["id"] = mid
        self.send(reply)

    async def _call_service(self, service: str, given: str, mid: Any,
                            frame: CallService) -> None:
        args = frame.args or {}
        try:
            opaque = self.bridge.opaque.services.get(service)
            if opaque is not None:  # a client serves it, in a type zenros does not know
                values = await opaque.owner.forward_unchecked(service, args)
            elif service == TF_REPUBLISH_SERVICE:
                values = self.bridge.tf_republisher.republish_tfs(args)
            elif Rosapi.handles(service):
                if not isinstance(args, dict):
                    raise OpError("rosapi services take an object of named args")
                async with self._rosapi_turn:  # answered in the order asked (set, then get)
                    values = await asyncio.to_thread(self.bridge.rosapi.call, service, args)
            elif service.endswith(ACTION_CANCEL) and self.bridge.has_action(
                    service[:-len(ACTION_CANCEL)]):
                request = cast(CancelGoalRequest, message_from_json(
                    request_args(args, CancelGoalRequest), CancelGoalRequest))
                values = to_json(await asyncio.to_thread(
                    self.bridge.cancel_goals, service[:-len(ACTION_CANCEL)], request,
                    _timeout(frame)))
            else:
                values = await self._call_zenros(service, args, frame)
        except (OpError, BridgeError, RosapiError, ZenrosError, ValueError, TypeError) as exc:
            self._service_failed(given, mid, str(exc) if not isinstance(exc, ServiceError)
                                 else exc.reason)
            return
        reply: dict[str, Any] = {"op": "service_response", "service": given, "values": values,
                                 "result": True}
        if mid is not None:
            reply["id"] = mid
        self.send(reply, frame_int(frame, "fragment_size"))

    async def _call_zenros(self, service: str, args: Any, frame: CallService) -> Any:
        type_name = self.bridge.service_type_of(service)
        if type_name is None:
            raise OpError(f"Service {service} does not exist")
        try:
            srv_type = lookup_service(type_name)
        except UnknownTypeError as exc:
            raise OpError(str(exc)) from None
        request = message_from_json(request_args(args, srv_type.Request), srv_type.Request)
        timeout = _timeout(frame)
        try:
            response = await self.bridge.client(srv_type, service).call_async(request, timeout)
        except ZenrosTimeout:
            raise OpError(f"Service {service} timed out after {timeout:g} s") from None
        return to_json(response)


    def op_advertise_service(self, frame: AdvertiseService) -> None:
        service = frame_name(frame, "service")
        type_name = frame_text(frame, "type")
        if not self.bridge.known(type_name, lookup_service):
            other = self.bridge.opaque.services.get(service)
            if other is not None and other.owner is self and other.type_name == type_name:
                return  # a replay after reconnect
            if service in self.services:
                self._stop_service(service)
            if other is not None and other.owner is not self:
                other.owner._stop_service(service)  # advertising again replaces the server
            self.bridge.opaque.services[service] = OpaqueService(type_name, self)
            self.services[service] = None
            return
        srv_type = frame_type(frame, "type", lookup_service)
        if service in self.services:
            old = self.services[service]
            if old is not None and old.srv_type is srv_type:
                return  # a replay after reconnect
            self._stop_service(service)
        self.services[service] = self.bridge.serve(srv_type, service,
                                                   self._forwarder(service, srv_type))

    async def forward_unchecked(self, service: str, args: Any) -> Any:
        """Call this client's ``service`` (of a type zenros does not know) with ``args`` as
        they came, on the loop; its answer's values, unchecked."""
        cid = f"service_request:{service}:{next(self._request_ids)}"
        fut: concurrent.futures.Future[Any] = concurrent.futures.Future()
        self.pending[cid] = (fut, service)
        self.send({"op": "call_service", "id": cid, "service": service, "args": args})
        try:
            return await asyncio.wait_for(asyncio.wrap_future(fut), CLIENT_SERVICE_TIMEOUT)
        except TimeoutError:
            raise ServiceError(service, f"the rosbridge client did not answer within "
                               f"{CLIENT_SERVICE_TIMEOUT:g} s") from None
        finally:
            self.pending.pop(cid, None)

    def _forwarder(self, service: str, srv_type: ServiceType) -> Callable[..., Any]:
        loop = self.bridge.loop

        async def forward(request: Message) -> Message:  # on the node's executor loop
            cid = f"service_request:{service}:{next(self._request_ids)}"
            fut: concurrent.futures.Future[Any] = concurrent.futures.Future()
            self.pending[cid] = (fut, service)
            loop.call_soon_threadsafe(self.send, {"op": "call_service", "id": cid,
                                                  "service": service, "args": to_json(request)})
            try:
                values = await asyncio.wait_for(asyncio.wrap_future(fut), CLIENT_SERVICE_TIMEOUT)
            except TimeoutError:
                raise ServiceError(service, f"the rosbridge client did not answer within "
                                   f"{CLIENT_SERVICE_TIMEOUT:g} s") from None
            finally:
                self.pending.pop(cid, None)
            return message_from_json(values, srv_type.Response)

        return forward

    def op_service_response(self, frame: ServiceResponse) -> None:
        mid = frame.id
        entry = self.pending.get(mid) if isinstance(mid, str) else None
        if entry is None:
            raise OpError(f"no pending service call with id {mid!r}")
        fut, service = entry
        if fut.done():
            return
        values = frame.values
        # As the reference servers (ROS 1 and 2), response values are the response, whatever
        # ``result`` says (roslibpy sends a handler's False return as result: false); a
        # failure without values (roslibjs 2) or with a reason (a string) fails the call
        if frame.result is False and not (isinstance(values, dict) and values):
            fut.set_exception(ServiceError(service, values if isinstance(values, str)
                                           else "the rosbridge client's handler failed"))
        else:
            fut.set_result(values or {})

    def op_unadvertise_service(self, frame: UnadvertiseService) -> None:
        self._stop_service(frame_name(frame, "service"))

    def _stop_service(self, service: str) -> None:
        if service not in self.services:
            return
        srv = self.services.pop(service)
        if srv is None:  # an unchecked service (opaque.py)
            entry = self.bridge.opaque.services.get(service)
            if entry is not None and entry.owner is self:
                del self.bridge.opaque.services[service]
        else:
            self.bridge.release(srv)
        for cid, (fut, name) in list(self.pending.items()):
            if name == service and not fut.done():
                fut.set_exception(ServiceError(service, "the service was unadvertised"))
                self.pending.pop(cid, None)

    def close(self) -> None:
        for service in list(self.services):
            self._stop_service(service)


def _timeout(frame: CallService) -> float:
    """A ``call_service``'s ``timeout`` (seconds), `DEFAULT_SERVICE_TIMEOUT` if it has none."""
    timeout = frame.timeout
    if not isinstance(timeout, (int, float)) or isinstance(timeout, bool) or timeout <= 0:
        return DEFAULT_SERVICE_TIMEOUT
    return float(timeout)
