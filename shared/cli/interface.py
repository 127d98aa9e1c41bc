"""`zenros interface list|packages|package|show|generate`: the message, service and action
types zenros holds, as `ros2 interface` shows them, and Python modules made from a package's
.msg/.srv/.action files (docs/cli.md, docs/interfaces.md)."""

from __future__ import annotations

import argparse
import re
import typing
from pathlib import Path
from typing import Any

import msgspec

from ..errors import UnknownTypeError
from ..registry import (
    load_all_packages,
    lookup_action,
    lookup_service,
    lookup_type,
    registered_actions,
    registered_services,
    registered_types,
)
from ..ros2.idl import EMPTY_FIELD, FieldType, InterfaceError, MsgDef
from ..ros2.registry import definition, ros_name_of
from .common import CliError

__all__ = ["interface_names", "show_lines"]

KINDS = ("msg", "srv", "action")
_DOTTED = re.compile(r"[A-Za-z_][\w.]*\.(\w+)")  # typing.Any, pkg.mod.Task: the last part
MAX_DEPTH = 10


def register(sub: Any) -> None:
    p = sub.add_parser("interface", help="message, service and action types: list, "
                                         "packages, package, show, generate",
                       description="The types zenros holds (ros2 interface).")
    verbs = p.add_subparsers(dest="verb", required=True)
    ls = verbs.add_parser("list", help="every type, by kind")
    for flag, kind in (("-m", "messages"), ("-s", "services"), ("-a", "actions")):
        ls.add_argument(flag, f"--only-{kind[:-1] if kind != 'messages' else 'msgs'}",
                        dest=kind, action="store_true", help=f"{kind} only")
    verbs.add_parser("packages", help="the packages with types")
    pk = verbs.add_parser("package", help="the types of one package")
    pk.add_argument("package")
    sh = verbs.add_parser("show", help="a type's fields, nested types expanded")
    sh.add_argument("type", help="pkg/msg/Name, pkg/srv/Name, pkg/action/Name (or pkg/Name)")
    sh.add_argument("--no-expand", action="store_true", help="the type's own fields only")
    gen = verbs.add_parser("generate", help="write a Python module of zenros types for each "
                                            "interface package (.msg/.srv/.action files)")
    gen.add_argument("packages", nargs="+", metavar="PKG_DIR",
                     help="a package folder (msg/, srv/, action/), or a folder of them")
    gen.add_argument("-o", "--out", default=".", help="where the modules go (default: here)")
    p.set_defaults(func=run)


def interface_names() -> dict[str, list[str]]:
    """Every type zenros ships or registered, as ``pkg/msg|srv|action/Name``, by kind."""
    load_all_packages()
    return {
        "msg": sorted(n for n in {ros_name_of(c) for c in registered_types().values()}
                      - _parts() if n.split("/")[1] == "msg"),  # not a service's _Event
        "srv": sorted(f"{pkg}/srv/{n}" for pkg, _, n in
                      (s.partition("/") for s in registered_services())),
        "action": sorted(f"{pkg}/action/{n}" for pkg, _, n in
                         (a.partition("/") for a in registered_actions())),
    }


def _parts() -> set[str]:
    """Request, response, goal, result and feedback messages (listed with their service or
    action, not as messages)."""
    out = set()
    for srv in registered_services().values():
        out |= {ros_name_of(srv.Request), ros_name_of(srv.Response)}
    for act in registered_actions().values():
        out |= {ros_name_of(act.Goal), ros_name_of(act.Result), ros_name_of(act.Feedback)}
    return out


def _sections(name: str) -> list[tuple[str, type[Any]]]:
    """The structures a type's text shows, ``---`` between them: (ROS 2 name, class)."""
    pkg, kind, short = _split(name)
    full = f"{pkg}/{kind}/{short}"
    if kind == "msg":
        return [(full, lookup_type(full))]
    if kind == "srv":
        srv = lookup_service(full)
        return [(f"{full}_Request", srv.Request), (f"{full}_Response", srv.Response)]
    act = lookup_action(full)
    return [(f"{full}_Goal", act.Goal), (f"{full}_Result", act.Result),
            (f"{full}_Feedback", act.Feedback)]


def _zenros_only(ros_name: str, cls: type[Any]) -> list[str]:
    """A structure with no ROS 2 form (a field holds JSON-like data, an enum, Any): its
    fields as zenros declares them, said so."""
    lines = [(f"# {ros_name}: zenros only, no ROS 2 form (its fields as zenros declares "
              "them; it travels as JSON or msgpack, not CDR)")]
    hints = typing.get_type_hints(cls)
    for f in msgspec.structs.fields(cls):
        tp = hints.get(f.name, f.type)
        text = tp.__name__ if isinstance(tp, type) else _DOTTED.sub(r"\1", str(tp))
        lines.append(f"{text} {f.name}")
    return lines


def _split(name: str) -> tuple[str, str, str]:
    parts = name.strip("/").split("/")
    if len(parts) == 3 and parts[1] in KINDS:
        return parts[0], parts[1], parts[2]
    if len(parts) == 2:  # pkg/Name: the kind it is registered as
        for kind, lookup in (("msg", lookup_type), ("srv", lookup_service),
                             ("action", lookup_action)):
            try:
                lookup(f"{parts[0]}/{kind}/{parts[1]}")
            except UnknownTypeError:
                continue
            return parts[0], kind, parts[1]
    raise UnknownTypeError(f"unknown interface {name!r} (pkg/msg|srv|action/Name; "
                           "`zenros interface list` names them)")


def _type_text(t: FieldType, package: str) -> str:
    base = t.base
    if t.is_nested:
        pkg, _, short = base.split("/")
        base = short if pkg == package else f"{pkg}/{short}"
    return str(FieldType(base, t.kind, t.size, t.string_bound))


def show_lines(name: str, expand: bool = True) -> list[str]:
    """The lines `zenros interface show` prints: one ``type name`` per field, a nested
    type's fields under it indented by a tab (as ros2 interface show), ``---`` between a
    service's or an action's parts. Constants and defaults are not shown: zenros keeps a
    type's wire layout (the fields, their order and bounds), not its comments."""
    out: list[str] = []

    def fields(d: MsgDef, depth: int) -> None:
        for f in d.fields:
            if f == EMPTY_FIELD:
                continue
            out.append("\t" * depth + f"{_type_text(f.type, d.package)} {f.name}")
            if expand and f.type.is_nested and depth < MAX_DEPTH:
                fields(definition(f.type.base), depth + 1)

    for i, (part, cls) in enumerate(_sections(name)):
        if i:
            out.append("---")
        try:
            d = definition(part)
        except (InterfaceError, UnknownTypeError):
            out.extend(_zenros_only(part, cls))
            continue
        fields(d, 0)
    return out


def generate(folders: list[str], out: str) -> list[Path]:
    """Write ``<out>/<package>.py`` for every package of ``folders``; the files written."""
    from ..interfaces import find_packages, generate_module, read_package

    packages: dict[str, Path] = {}
    for folder in folders:
        if not Path(folder).is_dir():
            raise CliError(f"{folder}: no such folder")
        found = find_packages(folder)
        if not found:
            raise CliError(f"{folder}: no interface package (a folder with msg/, srv/ or "
                           "action/) in it")
        packages.update(found)
    target = Path(out)
    target.mkdir(parents=True, exist_ok=True)
    written = []
    for name, where in sorted(packages.items()):
        try:
            source = generate_module(read_package(where))
        except InterfaceError as exc:
            raise CliError(str(exc)) from None
        path = target / f"{name}.py"
        path.write_text(source, encoding="utf-8")
        written.append(path)
    return written


def run(args: argparse.Namespace) -> int:
    if args.verb == "generate":
        for path in generate(args.packages, args.out):
            print(path)
        return 0
    try:
        if args.verb == "show":
            print("\n".join(show_lines(args.type, not args.no_expand)))
            return 0
        names = interface_names()
    except UnknownTypeError as exc:
        raise CliError(str(exc)) from None
    if args.verb == "packages":
        print("\n".join(sorted({n.split("/")[0] for ns in names.values() for n in ns})))
        return 0
    if args.verb == "package":
        found = [n for kind in KINDS for n in names[kind] if n.split("/")[0] == args.package]
        if not found:
            raise CliError(f"no package {args.package!r} (`zenros interface packages` names "
                           "them)")
        print("\n".join(found))
        return 0
    chosen = [k for k, flag in zip(KINDS, (args.messages, args.services, args.actions),
                                    strict=True) if flag] or list(KINDS)
    for kind in chosen:
        print({"msg": "Messages:", "srv": "Services:", "action": "Actions:"}[kind])
        for n in names[kind]:
            print(f"    {n}")
    return 0
