"""Gateway benchmark: REST, WebSocket fan-out and Modbus, each beside a bare reference.

- ``rest_ratio``: ``GET /api/v1/system/status`` requests/s on the gateway ÷ a bare Starlette
  JSON endpoint on uvicorn (same uvicorn settings), 8 keep-alive connections.
- ``ws_p99_age_ms``: GalileoStatus (30 Hz) fanned out to 50 WebSocket clients: p99 of the
  age of each frame on arrival (now - header.stamp), and the slowest client's rate.
- ``modbus_ratio``: input-register reads/s (doc 1-27) on the gateway ÷ a bare pymodbus 3.16
  server with the same tables and no hook, 4 clients.

Servers run in child processes, the load in this one; gateway and reference are measured
back to back in each repeat and the ratio is the median of the per-repeat ratios.
Prints one JSON line.
"""

from __future__ import annotations

import asyncio
import json
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import msgspec
from _harness import Child, bench_parser, emit, free_port, median, percentile


class _Stamp(msgspec.Struct):
    secs: int
    nsecs: int


class _Header(msgspec.Struct):
    stamp: _Stamp


class _Frame(msgspec.Struct):
    """Only what a frame's age needs, so the 50 clients stay light."""

    header: _Header


REST_CONNS = 8
MODBUS_CONNS = 4
WS_CLIENTS = 50


# ------------------------------------------------------------------ children


def child_gateway(args: Any) -> None:
    from zenros.context import Context
    from zenros.services.gateway.node import GatewayNode
    from zenros.testing import loopback_options

    home = Path(tempfile.mkdtemp())
    ctx = Context(loopback_options(), prefix=args.prefix)
    node = GatewayNode(context=ctx, parameter_overrides={
        "rest_port": args.rest_port, "ws_port": args.ws_port, "modbus_port": args.modbus_port,
        "discovery_port": -1, "config_file": str(home / "config.json"),
        "data_dir": str(home / "data")})
    node.core.state.voltage = 37.05
    print("ready", flush=True)
    try:
        sys.stdin.readline()
    finally:
        node.close()
        ctx.close()


def child_bare_rest(args: Any) -> None:
    import uvicorn
    from starlette.applications import Starlette
    from starlette.responses import JSONResponse
    from starlette.routing import Route

    async def status(request: Any) -> JSONResponse:
        return JSONResponse({"status": "Free"})

    app = Starlette(routes=[Route("/api/v1/system/status", status)])
    config = uvicorn.Config(app, host="127.0.0.1", port=args.rest_port, lifespan="off",
                            log_level="warning", access_log=False)
    server = uvicorn.Server(config)

    async def main() -> None:
        task = asyncio.create_task(server.serve())
        while not server.started:
            await asyncio.sleep(0.01)
        print("ready", flush=True)
        await asyncio.to_thread(sys.stdin.readline)
        server.should_exit = True
        await task

    asyncio.run(main())


def child_bare_modbus(args: Any) -> None:
    from pymodbus.server import ModbusTcpServer
    from pymodbus.simulator import DataType, SimData, SimDevice

    device = SimDevice(id=0, simdata=(
        [SimData(0, count=16, values=False, datatype=DataType.BITS)],
        [SimData(0, count=30, values=False, datatype=DataType.BITS)],
        [SimData(0, count=14, values=0, datatype=DataType.REGISTERS)],
        [SimData(0, count=27, values=0, datatype=DataType.REGISTERS)]))

    async def main() -> None:
        server = ModbusTcpServer(device, address=("127.0.0.1", args.modbus_port))
        await server.serve_forever(background=True)
        print("ready", flush=True)
        await asyncio.to_thread(sys.stdin.readline)
        await server.shutdown()

    asyncio.run(main())


# ------------------------------------------------------------------ load


async def rest_load(port: int, path: str, seconds: float) -> float:
    """Requests/s over ``REST_CONNS`` keep-alive HTTP/1.1 connections (a minimal client)."""
    request = f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n".encode()
    deadline = time.perf_counter() + seconds
    counts = [0] * REST_CONNS

    async def conn(i: int) -> None:
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        try:
            while time.perf_counter() < deadline:
                writer.write(request)
                head = await reader.readuntil(b"\r\n\r\n")
                length = 0
                for line in head.split(b"\r\n"):
                    if line.lower().startswith(b"content-length:"):
                        length = int(line.split(b":")[1])
                if not head.startswith(b"HTTP/1.1 200"):
                    raise RuntimeError(head.decode(errors="replace"))
                await reader.readexactly(length)
                counts[i] += 1
        finally:
            writer.close()

    t0 = time.perf_counter()
    await asyncio.gather(*(conn(i) for i in range(REST_CONNS)))
    return sum(counts) / (time.perf_counter() - t0)


async def modbus_load(port: int, seconds: float) -> float:
    from pymodbus.client import AsyncModbusTcpClient

    deadline = time.perf_counter() + seconds
    counts = [0] * MODBUS_CONNS

    async def conn(i: int) -> None:
        c = AsyncModbusTcpClient("127.0.0.1", port=port, timeout=5)
        await c.connect()
        try:
            while time.perf_counter() < deadline:
                rr = await c.read_input_registers(0, count=27, device_id=1)
                if rr.isError():
                    raise RuntimeError(str(rr))
                counts[i] += 1
        finally:
            c.close()

    t0 = time.perf_counter()
    await asyncio.gather(*(conn(i) for i in range(MODBUS_CONNS)))
    return sum(counts) / (time.perf_counter() - t0)


async def ws_fanout(port: int, token: str, seconds: float) -> tuple[float, float, float]:
    """(p50 age ms, p99 age ms, slowest client's frames/s) for ``WS_CLIENTS`` clients."""
    from websockets.asyncio.client import connect

    decode = msgspec.json.Decoder(_Frame).decode
    ages: list[float] = []
    rates: list[float] = []

    async def client() -> None:
        async with connect(f"ws://127.0.0.1:{port}/galileo/status?token={token}", max_size=None) as ws:
            await ws.recv()
            n, t0 = 0, time.perf_counter()
            while time.perf_counter() - t0 < seconds:
                stamp = decode(await ws.recv()).header.stamp
                ages.append(time.time() - (stamp.secs + stamp.nsecs * 1e-9))
                n += 1
            rates.append(n / (time.perf_counter() - t0))

    await asyncio.gather(*(client() for _ in range(WS_CLIENTS)))
    return percentile(ages, 50) * 1e3, percentile(ages, 99) * 1e3, min(rates)


def main() -> None:
    ap = bench_parser(__doc__.split("\n")[0], ["gateway", "bare-rest", "bare-modbus"], 3)
    ap.add_argument("--rest-port", type=int, default=0)
    ap.add_argument("--ws-port", type=int, default=0)
    ap.add_argument("--modbus-port", type=int, default=0)
    ap.add_argument("--seconds", type=float, default=3.0)
    args = ap.parse_args()
    if args.role == "gateway":
        return child_gateway(args)
    if args.role == "bare-rest":
        return child_bare_rest(args)
    if args.role == "bare-modbus":
        return child_bare_modbus(args)

    script = os.path.abspath(__file__)
    ports = {k: free_port() for k in ("rest", "ws", "modbus", "bare_rest", "bare_modbus")}
    gw = Child(script, "--role", "gateway", "--prefix", f"bench{os.getpid()}",
               "--rest-port", str(ports["rest"]), "--ws-port", str(ports["ws"]),
               "--modbus-port", str(ports["modbus"]))
    bare_rest = Child(script, "--role", "bare-rest", "--rest-port", str(ports["bare_rest"]))
    bare_mb = Child(script, "--role", "bare-modbus", "--modbus-port", str(ports["bare_modbus"]))
    try:
        tok = asyncio.run(_token(ports["rest"]))
        gw_path = f"/api/v1/system/status?token={tok}"
        rest: dict[str, list[float]] = {"gateway": [], "bare": []}
        mb: dict[str, list[float]] = {"gateway": [], "bare": []}
        asyncio.run(rest_load(ports["rest"], gw_path, 0.5))  # warm-up
        asyncio.run(rest_load(ports["bare_rest"], "/api/v1/system/status", 0.5))
        for _ in range(args.repeats):
            rest["gateway"].append(asyncio.run(rest_load(ports["rest"], gw_path, args.seconds)))
            rest["bare"].append(asyncio.run(
                rest_load(ports["bare_rest"], "/api/v1/system/status", args.seconds)))
            mb["gateway"].append(asyncio.run(modbus_load(ports["modbus"], args.seconds)))
            mb["bare"].append(asyncio.run(modbus_load(ports["bare_modbus"], args.seconds)))
        p50, p99, slowest = asyncio.run(ws_fanout(ports["ws"], tok, max(args.seconds, 3.0)))
    finally:
        for c in (gw, bare_rest, bare_mb):
            c.stop()
    emit("gateway", {
        "rest_ratio": round(median([g / b for g, b in zip(rest["gateway"], rest["bare"])]), 3),
        "rest_rps_gateway": round(median(rest["gateway"])),
        "rest_rps_bare": round(median(rest["bare"])),
        "ws_p99_age_ms": round(p99, 2), "ws_p50_age_ms": round(p50, 2),
        "ws_clients": WS_CLIENTS, "ws_slowest_client_hz": round(slowest, 1),
        "modbus_ratio": round(median([g / b for g, b in zip(mb["gateway"], mb["bare"])]), 3),
        "modbus_rps_gateway": round(median(mb["gateway"])),
        "modbus_rps_bare": round(median(mb["bare"])),
    }, repeats=args.repeats, seconds=args.seconds,
        load_average=round(os.getloadavg()[0], 1))


async def _token(port: int) -> str:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    writer.write(b"GET /api/v1/token?username=admin&password=admin HTTP/1.1\r\n"
                 b"Host: 127.0.0.1\r\nConnection: close\r\n\r\n")
    data = await reader.read()
    writer.close()
    return str(json.loads(data.split(b"\r\n\r\n", 1)[1])["token"])


if __name__ == "__main__":
    main()
