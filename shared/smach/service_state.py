"""`ServiceState`: call a service with a request built from userdata; store the response."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from ..errors import (
    InvalidStateError,
    ServiceError,
    ServiceUnavailableError,
    ZenrosTimeout,
)
from ..message import Message, ServiceType
from .ros_state import RosState, build_message, check_slots, read_slots, slot_keys
from .userdata import UserDataAccess

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["ServiceState"]

RequestCb = Callable[[UserDataAccess, Any], Any]
ResponseCb = Callable[[UserDataAccess, Any], str | None]


class ServiceState(RosState):
    """Call service ``name`` once, as smach_ros's ServiceState.

    The request starts from ``request`` (default: an empty ``srv_type.Request``), or from
    ``userdata[request_key]``; each field in ``request_slots`` is then set from the
    userdata key of the same name; last, ``request_cb(userdata, request)`` may return a
    new request (or None to keep it). The state waits up to ``server_wait_timeout``
    seconds for a server, then calls it.

    Outcomes: ``"succeeded"`` when the call returns; ``"aborted"`` when no server appears
    in time or the call fails (a handler error, no answer within ``call_timeout``);
    ``"preempted"`` on a preempt, also one that arrives during the wait or the call (the
    reply, if it comes, is dropped). On success the response is stored under
    ``response_key``, its ``response_slots`` fields under their own names, and
    ``response_cb(userdata, response)`` may return another outcome (declare it in
    ``outcomes`` or with `cb_interface`).

    A request that cannot be built (a missing key, a bad slot, a callback that raises)
    is a bug, not a failed call: ``execute`` raises `InvalidUserCodeError`.

    Example:
        >>> ServiceState(node, AddTwoInts, "add_two_ints", request_slots=["a", "b"],
        ...              response_slots=["sum"])

    Args:
        node: The node that owns the client.
        srv_type: The service type.
        name: The service name (resolved against the node).
        request: The request template (copied, never changed).
        request_cb: Builds or adjusts the request.
        request_key: Userdata key holding the whole request.
        request_slots: Request fields read from same-named userdata keys.
        response_cb: Looks at the response; may return an outcome.
        response_key: Userdata key that receives the whole response.
        response_slots: Response fields written to same-named userdata keys.
        input_keys: More keys the callbacks read.
        output_keys: More keys the callbacks write.
        outcomes: More outcomes ``response_cb`` may return.
        server_wait_timeout: Seconds to wait for a server on each run.
        call_timeout: Seconds to wait for the answer.
    """

    def __init__(
        self,
        node: Node,
        srv_type: ServiceType,
        name: str,
        request: Message | None = None,
        *,
        request_cb: RequestCb | None = None,
        request_key: str | None = None,
        request_slots: Sequence[str] = (),
        response_cb: ResponseCb | None = None,
        response_key: str | None = None,
        response_slots: Sequence[str] = (),
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        outcomes: Sequence[str] = (),
        server_wait_timeout: float = 5.0,
        call_timeout: float = 10.0,
    ) -> None:
        if request is not None and type(request) is not srv_type.Request:
            raise InvalidStateError(
                f"ServiceState for {name}: request must be {srv_type.Request.__name__},"
                f" got {type(request).__name__}")
        check_slots("ServiceState", srv_type.Request, request_slots, "request_slots")
        check_slots("ServiceState", srv_type.Response, response_slots, "response_slots")
        super().__init__(
            node, ("succeeded", "aborted", "preempted", *outcomes),
            slot_keys(request_slots, request_key, input_keys),
            slot_keys(response_slots, response_key, output_keys),
            callbacks=(request_cb, response_cb),
        )
        self.srv_type = srv_type
        self.client = node.create_client(srv_type, name)
        self._request = request
        self._request_cb = request_cb
        self._request_key = request_key
        self._request_slots = tuple(request_slots)
        self._response_cb = response_cb
        self._response_key = response_key
        self._response_slots = tuple(response_slots)
        self._server_wait = server_wait_timeout
        self._call_timeout = call_timeout

    @property
    def name(self) -> str:
        """The resolved service name."""
        return self.client.name

    def execute(self, userdata: UserDataAccess) -> str:
        """Build the request, wait for a server, call it; see the class docstring."""
        if self.take_preempt():
            return "preempted"
        request = self._build(userdata)
        missing = self.await_server(self.client.service_is_ready, f"service {self.name}",
                                    self._server_wait)
        if missing is not None:
            return missing
        future = self.node.context.executor.submit(
            self.client.call_async(request, self._call_timeout))
        future.add_done_callback(lambda _f: self.notify())
        if not self.wait_until(future.done):
            future.cancel()
            self.service_preempt()
            return "preempted"
        try:
            response = future.result()
        except (ServiceError, ServiceUnavailableError, ZenrosTimeout) as exc:
            self.node.logger.warning("%s: call to %s failed: %s", self.describe(), self.name, exc)
            return "aborted"
        read_slots(response, userdata, self._response_slots, self._response_key)
        if self._response_cb is not None:
            outcome = self._response_cb(userdata, response)
            if outcome is not None:
                return outcome
        return "succeeded"

    def _build(self, userdata: UserDataAccess) -> Message:
        request: Message = build_message(
            self, self._request, self.srv_type.Request, userdata, self._request_slots,
            self._request_key, self._request_cb, "request", f"service {self.name}")
        return request
