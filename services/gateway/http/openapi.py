"""`openapi_document`: the OpenAPI 3.1 document of an `Api`, built from its own routes.

Parameters and bodies come from the msgspec structs that validate them, summaries from the
handlers' docstrings, so the document cannot drift from what the server does. Its section
numbers (§1.2, §2) are those of docs/robot-api.md.
"""

from __future__ import annotations

from typing import Any

import msgspec

from .api import PREFIX, Api, Endpoint

__all__ = ["openapi_document"]

_ERROR = {"type": "object", "properties": {
    "status": {"const": "error"}, "result": {"const": False}, "description": {"type": "string"}},
    "required": ["description"]}



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
        params.append({"name": "token", "in": "query", "required": False,
                       "description": "access token from /token (§2)",
                       "schema": {"type": "string"}})
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


def openapi_document(api: Api, title: str, version: str) -> dict[str, Any]:
    components: dict[str, Any] = {"Error": _ERROR}
    paths: dict[str, Any] = {}
    for ep in sorted(api.endpoints(), key=lambda e: (e.path, e.method)):
        paths.setdefault(PREFIX + ep.path, {})[ep.method.lower()] = _operation(ep, components)
    return {"openapi": "3.1.0", "info": {"title": title, "version": version},
            "paths": paths, "components": {"schemas": components}}
