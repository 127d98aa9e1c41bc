"""The zenros exception hierarchy: every error the library raises, and nothing else."""

from __future__ import annotations


class ZenrosError(Exception):
    """Root of every error raised by zenros."""


class ConfigError(ZenrosError, ValueError):
    """A node's configuration is invalid: a parameter value, a file it names, a port it should
    listen on. Raised at startup, it ends the process with exit code 3 ("configuration: stop
    the launch"; `zenros.exits.EXIT_STARTUP`), where a bug in the code exits 1."""


class InvalidNameError(ConfigError):
    """A node, topic, service or namespace name breaks the ROS naming rules."""


class CodecError(ZenrosError, ValueError):
    """A message could not be encoded or decoded."""


class EncodeError(CodecError):
    """A message could not be encoded."""


class DecodeError(CodecError):
    """A payload could not be decoded into the expected type."""


class TypeMismatchError(DecodeError):
    """A payload carries another message type than the one expected."""


class UnknownTypeError(ZenrosError, LookupError):
    """A message type name is not registered."""


class ServiceError(ZenrosError, RuntimeError):
    """A service handler failed; carries the service name, the remote reason and, when the
    handler refused with a `RefusedError`, its result ``code`` (else None)."""

    def __init__(self, service: str, reason: str, code: int | None = None) -> None:
        super().__init__(f"service {service} failed: {reason}")
        self.service = service
        self.reason = reason
        self.code = code


class RefusedError(ZenrosError):
    """A service handler's refusal with a result code for the caller to branch on (the
    code's meaning is the service's message package's, e.g. ``zenros_msgs.ResultCode``).

    The caller's `ServiceError` carries ``code``; its ``reason`` is for people only.
    """

    def __init__(self, code: int, reason: str, kind: str = "RefusedError") -> None:
        super().__init__(reason)
        self.code = int(code)
        self.kind = kind  # the error kind the caller sees (the refused exception's class)


class ServiceUnavailableError(ZenrosError, ConnectionError):
    """No server answered for a service."""


class ZenrosTimeout(ZenrosError, TimeoutError):
    """An operation did not complete within its timeout."""


class ParameterError(ZenrosError, ValueError):
    """A parameter operation failed."""


class ParameterNotDeclaredError(ParameterError, LookupError):
    """A parameter was read or set before it was declared."""


class ParameterAlreadyDeclaredError(ParameterError):
    """A parameter was declared twice."""


class ParameterImmutableError(ParameterError):
    """A read-only parameter was to be changed or undeclared (rclpy's
    ``ParameterImmutableException``)."""


class InvalidParameterValueError(ParameterError, ConfigError, TypeError):
    """A parameter value has the wrong type or is out of range."""


class ParameterSourceError(ParameterError, ConfigError):
    """A source of parameter values cannot be read: a params file, a ``-p name:=value``, a
    parameter database."""


class GoalRejectedError(ZenrosError, RuntimeError):
    """An action server rejected a goal."""


class NodeClosedError(ZenrosError, RuntimeError):
    """A node (or one of its parts) was used after it was closed."""


class StartupError(ZenrosError, RuntimeError):
    """A node could not start (no Zenoh session, a missing extra); exit code 3 as for
    `ConfigError`."""


class LaunchError(ConfigError):
    """A launch file is invalid (bad YAML, unknown key, unresolved substitution, bad include)."""


# ------------------------------------------------------------------ TF (tf2's names)


class TransformException(ZenrosError, RuntimeError):
    """Base of the tf2 errors (tf2.TransformException)."""


class LookupException(TransformException, LookupError):
    """A frame is not known to the buffer."""


class ConnectivityException(TransformException):
    """Two frames are known but not connected in one tree."""


class ExtrapolationException(TransformException):
    """A lookup asked for a time outside the buffered data (past, future, or a single sample)."""


class InvalidArgumentException(TransformException, ValueError):
    """A transform or request is malformed (NaN, unnormalized quaternion, empty or equal ids)."""


class TimeoutException(TransformException, TimeoutError):
    """A transform did not become available before the timeout."""


# ------------------------------------------------------------------ state machines (smach)


class SmachError(ZenrosError, RuntimeError):
    """Base of the state machine errors."""


class InvalidStateError(SmachError, ValueError):
    """A state or container is wired wrongly (unknown state, bad outcome, duplicate label)."""


class InvalidTransitionError(SmachError, ValueError):
    """A transition names a target that does not exist, or an outcome is unconnected."""


class InvalidUserCodeError(SmachError):
    """A state's execute() raised, or returned an undeclared outcome."""


class UserDataError(SmachError, KeyError):
    """A state read an undeclared key, wrote an input-only key, or a key is missing."""

    def __str__(self) -> str:  # KeyError quotes its message; keep it readable
        return str(self.args[0]) if self.args else ""


# ------------------------------------------------------------------ parameter server


class ParameterNotFoundError(ParameterError, LookupError):
    """A parameter (or namespace) is not set on the parameter server."""


# ------------------------------------------------------------------ TF: ROS 2's extrapolation kinds


class BackwardExtrapolationException(ExtrapolationException):
    """A lookup asked for a time older than the oldest buffered sample of a link."""


class ForwardExtrapolationException(ExtrapolationException):
    """A lookup asked for a time newer than the newest buffered sample of a link."""


class NoDataForExtrapolationException(ExtrapolationException):
    """A link holds no sample, or a single sample at another time than the one asked for."""


# ------------------------------------------------------------------ actions


class ActionError(ZenrosError, RuntimeError):
    """An action request failed: a bad goal, a server error, or a client-side failure."""


class UnknownGoalError(ActionError, LookupError):
    """A goal id is not known to the action server (never accepted there, or its result expired)."""


class GoalStateError(ActionError):
    """A goal handle was moved through a transition its state does not allow."""


class ActionServerUnavailableError(ActionError, ConnectionError):
    """No action server answered for an action name."""


# ------------------------------------------------------------------ maps


class MapError(ConfigError):
    """A map file (map_server YAML, its image or a side file) is missing or malformed."""


class MapItemNotFoundError(MapError, LookupError):
    """A map, path, nav point or point connection a request names is not stored."""
