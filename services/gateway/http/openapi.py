"""`openapi_document`: the OpenAPI 3.1 document of an `Api`, built from its own routes.

Parameters and bodies come from the msgspec structs that validate them, summaries from the
handlers' docstrings, so the document cannot drift from what the server does. Its section
numbers (§1.2, §2) are those of docs/robot-api.md.
"""

from __future__ import annotations

from typing import Any

import msgspec

from .api import PREFIX, Api, Endpoint
from .fleet import ROBOTS

__all__ = ["openapi_document"]

_ERROR = {"type": "object", "properties": {
    "status": {"const": "error"}, "result": {"const": False}, "description": {"type": "string"}},
    "required": ["description"]}
_TOKEN = {"name": "token", "in": "query", "required": False,
          "description": "access token from /token (§2)", "schema": {"type": "string"}}
_ROBOT = {"name": "robot", "in": "path", "required": True,
          "description": "a robot this gateway serves (GET /api/v1/robots lists them)",
          "schema": {"type": "string"}}
_POSE = {"type": ["object", "null"], "properties": {
    "x": {"type": "number"}, "y": {"type": "number"}, "theta": {"type": "number"}}}
# GET /api/v1/robots (`FleetApi`, `robot_summary`)
_ROBOT_LIST = {"type": "object", "required": ["default", "robots"], "properties": {
    "default": {"type": "string", "description": "the robot of the single-robot paths"},
    "robots": {"type": "array", "items": {"type": "object", "properties": {
        "name": {"type": "string"}, "online": {"type": "boolean"},
        "state": {"type": "string"}, "estop": {"type": "boolean"},
        "battery": {"type": "number"}, "charging": {"type": "boolean"}, "pose": _POSE,
        "target_status": {"type": "integer"}}}}}}


def _operation(ep: Endpoint, components: dict[str, Any]) -> dict[str, Any]:
    op: dict[str, Any] = {
        "operationId": f"{ep.method.lower()}_{ep.path.strip('/').replace('/', '_') or 'index'}",
        "summary": ep.summary,
        "tags": [ep.path.strip("/").split("/")[0] or "api"],
    }
    if ep.description:
        op["description"] = ep.description
    params: list[dict[str, Any]] = []
    if not ep.public:
        params.append(_TOKEN)
    for name in (ep.path.split("{")[1:] if "{" in ep.path else []):
        params.append({"name": name.split("}")[0], "in": "path", "required": True,
                       "schema": {"type": "string"}})
    if ep.query is not None:
        (schema,), defs = msgspec.json.schema_components([ep.query])
        defs_q = defs.get(ep.query.__name__, schema)
        required = set(defs_q.get("required", []))
        for name, prop in defs_q.get("properties", {}).items():
            params.append({"name": name, "in": "query", "required": name in required,
                           "schema": prop})
    if params:
        op["parameters"] = params
    if ep.body is not None:
        (schema,), defs = msgspec.json.schema_components(
            [ep.body], ref_template="#/components/schemas/{name}")
        components.update(defs)
        op["requestBody"] = {"required": True,
                             "content": {"application/json": {"schema": schema}}}
    if ep.raw_body:   # a multipart upload; the handler's docstring names the fields
        op["requestBody"] = {"required": True, "content": {"multipart/form-data": {
            "schema": {"type": "object", "additionalProperties": True}}}}
    err = {"description": "error (§1.2 body)",
           "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
    if not ep.implemented:
        op["responses"] = {"501": {"description": "not implemented", 
            "content": err["content"]}}
        return op
    ok_content: dict[str, Any] = ({ep.media_type: {}} if ep.media_type != "application/json"
                  else {"application/json": {"schema": {}}})
    responses: dict[str, Any] = {"200": {"description": "success", "content": ok_content},
                                 "400": err}
    if not ep.public:
        responses["401"] = err
    if ep.body is not None or ep.raw_body:
        responses["413"] = err
    responses["default"] = {**err, "description": "any other refusal (404, 409, 503, ...), "
                                                 "with the §1.2 body"}
    op["responses"] = responses
    return op


def _robots_operation() -> dict[str, Any]:
    err = {"description": "error (§1.2 body)",
           "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
    return {"operationId": "get_robots", "tags": ["robots"],
            "summary": "The robots this gateway serves, each with its state, battery, pose "
                       "and e-stop (a fleet gateway; docs/fleet.md)",
            "parameters": [_TOKEN],
            "responses": {"200": {"description": "success", "content": {"application/json": {
                "schema": _ROBOT_LIST}}}, "400": err, "401": err}}


def _robot_operation(op: dict[str, Any]) -> dict[str, Any]:
    """``op`` as robot ``{robot}``'s, under /api/v1/robots/{robot}."""
    out = {**op, "operationId": f"robot_{op['operationId']}",
           "parameters": [_ROBOT, *op.get("parameters", [])]}
    if "200" in op["responses"]:  # an implemented operation: a robot not served is a 404
        out["responses"] = {**op["responses"], "404": {
            **op["responses"]["400"], "description": "no such robot on this gateway"}}
    return out


def openapi_document(api: Api, title: str, version: str,
                     fleet: bool = False) -> dict[str, Any]:
    """The document of ``api``'s operations under /api/v1; with ``fleet`` (a fleet
    gateway's default robot), also GET /api/v1/robots and every operation again under
    /api/v1/robots/{robot} for each robot."""
    components: dict[str, Any] = {"Error": _ERROR}
    paths: dict[str, Any] = {}
    robot_paths: dict[str, Any] = {}
    for ep in sorted(api.endpoints(), key=lambda e: (e.path, e.method)):
        op = _operation(ep, components)
        paths.setdefault(PREFIX + ep.path, {})[ep.method.lower()] = op
        if fleet:
            robot_paths.setdefault(ROBOTS + "/{robot}" + ep.path, {})[ep.method.lower()] = (
                _robot_operation(op))
    if fleet:
        paths[ROBOTS] = {"get": _robots_operation()}
        paths.update(robot_paths)
    return {"openapi": "3.1.0", "info": {"title": title, "version": version},
            "paths": paths, "components": {"schemas": components}}
