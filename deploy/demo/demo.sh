#!/usr/bin/env bash
# zenros multi-host demo on one machine: a station and two robots, each in a network namespace
# of its own (its own "host" with its own address), joined by a bridge. Needs root and iproute2;
# `loss` also needs iptables. docs/demo.md walks through it; docs/fleet.md ("Beyond one box")
# the routed topology (ZR_TOPOLOGY=routed: a router per host, N robots).
#
#   deploy/demo/demo.sh up          create the namespaces and the network
#   deploy/demo/demo.sh start       station.yaml on the station (with the router and a gateway
#                                   per robot), robot.yaml on each robot (chassis, nav, tf,
#                                   tasks, ...); waits until the station sees every node
#   deploy/demo/demo.sh show        what the station sees: nodes, topics, a service call,
#                                   robot1's TF frames, robot2's pose over REST, heartbeats
#   deploy/demo/demo.sh link robot1 down|up      pull a robot's cable out / plug it back
#   deploy/demo/demo.sh flap robot1 [SECONDS]    down, wait (default 5 s), up
#   deploy/demo/demo.sh loss robot1 PROB|off     random loss on the robot's incoming packets
#   deploy/demo/demo.sh run HOST CMD...          run a command on a host with the demo's env
#   deploy/demo/demo.sh api ROBOT METHOD PATH [JSON]   call the robot's REST API through its
#                                   gateway on the station (token fetched for you)
#   deploy/demo/demo.sh report                   the monitor's latest heartbeat counts
#   deploy/demo/demo.sh cpu [SECONDS]            cores used by each process of each host over
#                                   a window (default 10 s), from /proc/<pid>/task/*/schedstat
#   deploy/demo/demo.sh outage ROBOT [SECONDS]   (routed) pull ROBOT's link for SECONDS (default
#                                   10) while the others drive a goal; one JSON line of figures
#   deploy/demo/demo.sh status | stop | down     (down = stop + delete the namespaces)
#
# Hosts: station 10.99.0.1 (router on tcp/10.99.0.1:7447), robot1 10.99.0.2, robot2 10.99.0.3,
# robotK 10.99.0.(K+1).
# ZR_TOPOLOGY: star (the default) runs station.yaml and robot.yaml with every process a peer
# connected to the station's router, two robots. routed runs a Zenoh router on every host (the
# robot hosts' routers connect to the station's), ZR_ROBOTS robots (default 3), each robot one
# process (robot.yaml compose:=true) and a client of its own host's router; the station runs
# master and one gateway for the fleet (fleet.yaml robots:=0), clients of the station's router.
# Give every command of one demo the same ZR_TOPOLOGY and ZR_ROBOTS.
# Environment: ZR_PREFIX (namespace prefix, default zrdemo, at most 10 characters),
# ZR_STATE (pids and logs, default /tmp/zenros-demo-$ZR_PREFIX), PYTHON (default python3),
# ZR_CONFIG (the session config of every process, default deploy/demo/zenoh-host.json5; routed:
# deploy/demo/zenoh-client.json5), ZR_WAIT (seconds `start` waits for the robots, default 120).
set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
P=${ZR_PREFIX:-zrdemo}
STATE=${ZR_STATE:-/tmp/zenros-demo-$P}
PY=${PYTHON:-python3}
TOPOLOGY=${ZR_TOPOLOGY:-star}
NET=10.99.0
ROUTER="tcp/$NET.1:7447"
SW="${P}sw"

die() { echo "demo.sh: $*" >&2; exit 1; }
say() { echo "[demo] $*"; }

case "$TOPOLOGY" in
    star) ROBOTS=${ZR_ROBOTS:-2}
          [ "$ROBOTS" = 2 ] || die "ZR_TOPOLOGY=star runs two robots (station.yaml's gateways);" \
                                   "ZR_TOPOLOGY=routed runs ZR_ROBOTS of them"
          CONFIG=${ZR_CONFIG:-$HERE/zenoh-host.json5} ;;
    routed) ROBOTS=${ZR_ROBOTS:-3}
            [[ "$ROBOTS" =~ ^[1-9][0-9]?$ ]] && [ "$ROBOTS" -le 11 ] \
                || die "ZR_ROBOTS must be 1 to 11 (fleet.yaml's corridor); got '$ROBOTS'"
            CONFIG=${ZR_CONFIG:-$HERE/zenoh-client.json5} ;;
    *) die "ZR_TOPOLOGY must be star or routed; got '$TOPOLOGY'" ;;
esac
HOSTS=(st)
for ((k = 1; k <= ROBOTS; k++)); do HOSTS+=("r$k"); done

# station|robotK (or st|rK) -> st|rK
short() {
    case "$1" in
        station|st) echo st; return ;;
        robot[1-9]|robot[1-9][0-9]|r[1-9]|r[1-9][0-9])
            local k=${1##*[a-z]}
            [ "$k" -le "$ROBOTS" ] && { echo "r$k"; return; } ;;
    esac
    die "unknown host '$1'; hosts: station, robot1 .. robot$ROBOTS"
}
ns() { echo "$P$1"; }
addr() { case "$1" in st) echo "$NET.1" ;; r*) echo "$NET.$((${1#r} + 1))" ;; esac; }
# The router a process on host $1 connects to: the station's (star), its own host's (routed).
host_router() { if [ "$TOPOLOGY" = routed ]; then echo "tcp/$(addr "$1"):7447"; else echo "$ROUTER"; fi; }

need_root() {
    [ "$(id -u)" = 0 ] || die "needs root (network namespaces); run it with sudo"
    command -v ip >/dev/null || die "needs iproute2 (the 'ip' command): apt-get install -y iproute2"
    [[ "$P" =~ ^[a-z][a-z0-9]{0,9}$ ]] \
        || die "ZR_PREFIX must be 1-10 lowercase letters or digits, starting with a letter; got '$P'"
}

# Everything a process on a simulated host needs: the router's address and the session config
# (peer mode, listens on the host's address, SHM off, 1 s lease); logs under $STATE/home-<host>.
#
# ZENOH_RUNTIME: Zenoh 1.10 closes a TCP link with SO_LINGER 10 s, and the close(2) runs on a
# worker of its "rx" runtime, which has 2 threads by default. When a robot's link is cut and
# the lease drops its sessions, every process that had 2 or more links to that robot blocks
# both rx threads in close(2) until the link returns (or 10 s pass): all its traffic, to every
# host, stalls (measured: robot2 stalled 4.1-4.3 s during robot1's 5 s outage, 10 s during a
# 12 s one). More rx threads than processes per host keep the other links flowing: a robot
# runs 8 processes (robot.yaml), and with 8 threads robot2's nav still dropped out of its own
# tasks service's view during robot1's outage (the goal was lost); 16 did until the robot ran
# its 8 services, its launch and 3 examples (robot2 stalled 4.1 s again); 32 leave room.
host_env() {
    HOST_ENV=("ZENROS_CONNECT=$(host_router "$1")" "ZENROS_CONFIG=$CONFIG" "ZENROS_HOME=$STATE/home-$1"
              "PYTHONUNBUFFERED=1" "ZENOH_RUNTIME=${ZENOH_RUNTIME:-(rx: (worker_threads: 32))}")
}

cmd_up() {
    need_root
    ip netns add "$SW" 2>/dev/null \
        || die "cannot create network namespace $SW (ip netns add failed; already up? try 'down')"
    ip -n "$SW" link set lo up
    ip -n "$SW" link add br0 type bridge
    ip -n "$SW" link set br0 up
    for h in "${HOSTS[@]}"; do
        ip netns add "$(ns "$h")"
        ip -n "$(ns "$h")" link set lo up
        ip -n "$SW" link add "$P$h" type veth peer name "$P$h-h"
        ip -n "$SW" link set "$P$h-h" netns "$(ns "$h")"
        ip -n "$(ns "$h")" link set "$P$h-h" name eth0
        ip -n "$SW" link set "$P$h" master br0 up
        ip -n "$(ns "$h")" addr add "$(addr "$h")/24" dev eth0
        ip -n "$(ns "$h")" link set eth0 up
    done
    mkdir -p "$STATE"
    local h hosts="station $(ns st) $NET.1"
    for h in "${HOSTS[@]:1}"; do hosts+=", robot${h#r} $(ns "$h") $(addr "$h")"; done
    say "up: $hosts (bridge in $SW)"
}

# bg NAME HOST CMD...: CMD on HOST in the background, pid in $STATE/NAME.pid, log in NAME.log.
bg() {
    local name=$1 h=$2; shift 2
    [ -e "$STATE/$name.pid" ] && kill -0 "$(cat "$STATE/$name.pid")" 2>/dev/null \
        && die "$name is already running (pid $(cat "$STATE/$name.pid"))"
    # setsid: its own process group, so a terminal's Ctrl-C does not reach it; `ip netns exec`
    # and `env` exec, so the pid is the program's.
    host_env "$h"
    setsid ip netns exec "$(ns "$h")" env "${HOST_ENV[@]}" "$@" \
        >"$STATE/$name.log" 2>&1 </dev/null &
    echo $! >"$STATE/$name.pid"
}

# start_host HOST LAUNCH_FILE ARGS...: `zenros launch` on HOST, in the background.
# --verbose: the host's log keeps the INFO records too (the report reads the monitor's
# heartbeat_report lines from it).
start_host() {
    local h=$1 file=$2; shift 2
    bg "$h" "$h" "$PY" -m zenros.cli launch "$ROOT/deploy/launch/$file" --verbose "$@"
    say "started $file on $h (pid $(cat "$STATE/$h.pid")), log $STATE/$h.log"
}

# start_router HOST: the host's own Zenoh router on tcp/<address>:7447 (routed topology); a
# robot host's router connects to the station's.
start_router() {
    local h=$1 up=()
    [ "$h" = st ] || up=(--cfg "connect/endpoints:[\"$ROUTER\"]")
    bg "$h-router" "$h" "$PY" -m zenros.router -c "$HERE/zenoh-router.json5" \
        -l "$(host_router "$h")" "${up[@]}"
    say "started the router of $h on $(host_router "$h") (pid $(cat "$STATE/$h-router.pid"))"
}

# until_ok SECONDS WHAT CMD...: retry CMD every 0.2 s until it succeeds or time runs out.
until_ok() {
    local limit=$1 what=$2; shift 2
    local deadline=$((SECONDS + limit))
    local f
    until "$@" >/dev/null 2>&1; do
        [ "$SECONDS" -lt "$deadline" ] || die "$what: not ready after ${limit} s (logs in $STATE)"
        for f in "$STATE"/*.pid; do
            [ ! -e "$f" ] || kill -0 "$(cat "$f")" 2>/dev/null \
                || die "$what: $(basename "$f" .pid) exited; see ${f%.pid}.log"
        done
        sleep 0.2
    done
}

# router_up [HOST]: whether the router HOST's processes use (default the station's) answers.
router_up() {
    local h=${1:-st} r; r=$(host_router "${1:-st}"); r=${r#tcp/}
    ip netns exec "$(ns "$h")" bash -c "exec 3<>/dev/tcp/${r%:*}/${r##*:}"
}

# The zenros CLI on the station, bounded: under heavy load its session's close can take 10 s
# or more, and a call that hangs must not hang the demo (docs/demo.md, Troubleshooting).
station_cli_once() { cmd_run station timeout 20 "$PY" -m zenros.cli "$@"; }

# station_cli ARGS...: the same, tried again (3 tries) while it hangs before printing anything;
# what it printed before hanging in close() counts.
station_cli() {
    local out i
    for i in 1 2 3; do
        if out=$(station_cli_once "$@") || [ -n "$out" ]; then
            echo "$out"
            return 0
        fi
    done
    echo "demo.sh: zenros $* gave no answer in 3 tries" >&2
    return 1
}

# Every node of both robots (robot.yaml), and each robot's gateway on the station; routed:
# each robot's composed services, and the fleet gateway's node for the robot.
ROBOT_NODES=(chassis nav tf tasks heartbeat listener add_two_ints_server gateway)
[ "$TOPOLOGY" = routed ] && ROBOT_NODES=(chassis nav tf tasks gateway)

robots_seen() {
    local out h n
    out=$(station_cli_once node list) || [ -n "$out" ] || return 1
    for h in "${HOSTS[@]:1}"; do
        for n in "${ROBOT_NODES[@]}"; do grep -qx "/robot${h#r}/$n" <<<"$out" || return 1; done
    done
}

cmd_start() {
    need_root
    ip netns list | grep -qw "$(ns st)" || die "the namespaces are not up; run '$0 up' first"
    mkdir -p "$STATE"
    local t0=$SECONDS h
    if [ "$TOPOLOGY" = routed ]; then
        start_router st
        until_ok 30 "the station's router on $ROUTER" router_up
        for h in "${HOSTS[@]:1}"; do start_router "$h"; done
        for h in "${HOSTS[@]:1}"; do until_ok 30 "the router of $h" router_up "$h"; done
        # master and one gateway for the fleet (it finds the robots in the graph)
        start_host st fleet.yaml robots:=0 --no-router
        for h in "${HOSTS[@]:1}"; do
            start_host "$h" robot.yaml "robot:=robot${h#r}" compose:=true examples:=false mapping:=false \
                --no-router
        done
    else
        start_host st station.yaml
        until_ok 30 "the station's router on $ROUTER" router_up
        # mapping:=false: the 8 processes a robot ran when ZENOH_RUNTIME's 16 rx threads were
        # measured (above); with slam and explore, 10, and robot2's nav dropped out of its
        # gateway's view during robot1's outage in 2 of 3 suite runs
        start_host r1 robot.yaml robot:=robot1 mapping:=false --no-router
        start_host r2 robot.yaml robot:=robot2 mapping:=false --no-router
    fi
    until_ok "${ZR_WAIT:-120}" "the robots' nodes, seen from the station" robots_seen
    say "the station sees all $ROBOTS robots, $((SECONDS - t0)) s after start; try '$0 show'"
}

cmd_run() {
    [ $# -ge 2 ] || die "usage: run HOST CMD..."
    local h; h=$(short "$1"); shift
    host_env "$h"
    ip netns exec "$(ns "$h")" env "${HOST_ENV[@]}" "$@"
}

# The base URL of a robot's API on the station: its gateway (station.yaml), or its paths on the
# fleet's gateway (routed: fleet.yaml).
api_base() {
    if [ "$TOPOLOGY" = routed ]; then
        # the station: the fleet gateway's own paths (/robots: every robot and its state)
        if [ "$1" = st ]; then echo http://127.0.0.1:3546/api/v1
        else echo "http://127.0.0.1:3546/api/v1/robots/robot${1#r}"; fi
    else case "$1" in r1) echo http://127.0.0.1:3546/api/v1 ;; r2) echo http://127.0.0.1:3556/api/v1 ;;
                      *) die "no gateway for '$1'" ;; esac
    fi
}

# api ROBOT METHOD PATH [JSON]: one call to the robot's gateway on the station, with a token
# from /api/v1/token (user admin, password admin: the gateway's default config). Prints the
# HTTP status and the body; exits 1 unless the status is 2xx.
cmd_api() {
    [ $# -ge 3 ] || die "usage: api ROBOT METHOD PATH [JSON]"
    local h; h=$(short "$1")
    cmd_run station "$PY" - "$(api_base "$h")" "$2" "$3" "${4:-}" <<'PYEOF'
import json, sys, urllib.error, urllib.request
base, method, path, body = sys.argv[1:5]
token_base = base.split("/robots/", 1)[0]
def call(method, url, data=None):
    req = urllib.request.Request(url, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(req, timeout=15) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode()
status, text = call("GET", token_base + "/token?username=admin&password=admin")
if status != 200:
    sys.exit(f"no token from {base}/token: {status} {text}")
token = json.loads(text)["token"]
url = base + path + ("&" if "?" in path else "?") + "token=" + token
status, text = call(method.upper(), url, body.encode() if body else None)
print(status, text)
sys.exit(0 if 200 <= status < 300 else 1)
PYEOF
}

cmd_show() {
    [ "$TOPOLOGY" = routed ] && { show_routed; return; }
    say "zenros node list (on the station)"; station_cli node list
    say "zenros topic list -t"; station_cli topic list -t
    say "zenros service call /robot2/add_two_ints"
    station_cli service call /robot2/add_two_ints example_interfaces/AddTwoInts '{a: 2, b: 3}'
    say "zenros topic echo /robot1/heartbeat --once"
    station_cli topic echo /robot1/heartbeat --once --timeout 5
    say "zenros tf frames --server /robot1/tf (robot1's own TF tree)"
    station_cli tf frames --server /robot1/tf
    say "GET /api/v1/navigation/pose through robot2's gateway on the station"
    cmd_api robot2 GET /navigation/pose
    say "heartbeat counts (station's heartbeat_monitor)"; cmd_report
}

show_routed() {
    say "zenros node list (on the station)"; station_cli node list
    say "zenros topic hz /robot$ROBOTS/odom (on the station, through two routers)"
    station_cli topic hz "/robot$ROBOTS/odom" --window 100 --count 3 || true
    say "GET /api/v1/robots through the fleet gateway on the station"
    cmd_api station GET /robots
    say "GET robot$ROBOTS's /navigation/pose through the fleet gateway"
    cmd_api "robot$ROBOTS" GET /navigation/pose
}

cmd_report() {
    [ -f "$STATE/st.log" ] || die "no station log in $STATE; run '$0 start' first"
    # The last heartbeat_report line of each topic, as a table.
    grep -o 'heartbeat_report {.*}' "$STATE/st.log" | "$PY" -c '
import json, sys
last = {}
for line in sys.stdin:
    try:
        report = json.loads(line.split(" ", 1)[1])
    except ValueError:
        continue
    last[report["topic"]] = report
print("%-26s %8s %8s %5s %8s" % ("topic", "received", "last seq", "lost", "max gap"))
for topic, r in sorted(last.items()):
    print("%-26s %8d %8d %5d %7.2fs" % (topic, r["received"], r["last"], r["lost"], r["max_gap"]))
'
}

cmd_link() {
    need_root
    local h; h=$(short "${1:?usage: link HOST up|down}")
    case "${2:-}" in up|down) ;; *) die "usage: link HOST up|down" ;; esac
    ip -n "$SW" link set "$P$h" "$2"
    say "$1 link $2"
}

cmd_flap() {
    local secs=${2:-5}
    cmd_link "$1" down
    sleep "$secs"
    cmd_link "$1" up
}

# Random loss on a host's incoming packets, and on the station's packets from that host:
# INPUT rules only (an OUTPUT DROP makes sendto() fail, which Zenoh treats as a dead link).
cmd_loss() {
    need_root
    command -v iptables >/dev/null || die "needs iptables: apt-get install -y iptables"
    local h; h=$(short "${1:?usage: loss HOST PROBABILITY|off}")
    local p=${2:?usage: loss HOST PROBABILITY|off} tag="zenros-demo-loss-$h" n
    for n in "$h" st; do
        ip netns exec "$(ns "$n")" iptables -S INPUT | { grep -- "$tag" || true; } | sed 's/^-A /-D /' \
            | while read -r rule; do
                # shellcheck disable=SC2086
                ip netns exec "$(ns "$n")" iptables $rule
            done
    done
    [ "$p" = off ] && { say "$1: no loss"; return; }
    local rule=(-m statistic --mode random --probability "$p" -m comment --comment "$tag" -j DROP)
    ip netns exec "$(ns "$h")" iptables -A INPUT "${rule[@]}"
    [ "$h" = st ] || ip netns exec "$(ns st)" iptables -A INPUT -s "$(addr "$h")" "${rule[@]}"
    say "$1: dropping incoming packets with probability $p"
}

cmd_status() {
    local h
    for h in "${HOSTS[@]}"; do
        if ! ip netns list | grep -qw "$(ns "$h")"; then echo "$h: no namespace"; continue; fi
        local pids; pids=$(ip netns pids "$(ns "$h")" | tr '\n' ' ')
        echo "$h: namespace $(ns "$h") $(addr "$h"), processes: ${pids:-none}"
    done
}

# The demo's namespaces that exist now (whatever ZR_ROBOTS they were brought up with).
our_ns() { ip netns list | awk '{print $1}' | grep -E "^$P(st|sw|r[0-9]+)\$" || true; }

# stop_pids FILES...: SIGINT each pid (a launch stops its processes in order), wait up to 20 s,
# then SIGKILL; the pid files go.
stop_pids() {
    local f pid deadline
    for f in "$@"; do kill -INT "$(cat "$f")" 2>/dev/null || true; done
    deadline=$((SECONDS + 20))
    for f in "$@"; do
        pid=$(cat "$f")
        while kill -0 "$pid" 2>/dev/null && [ "$SECONDS" -lt "$deadline" ]; do sleep 0.1; done
        kill -KILL "$pid" 2>/dev/null || true
        rm -f "$f"
    done
}

# Stop the launches, then the routers (routed), then kill whatever is left in the namespaces.
cmd_stop() {
    need_root
    local n pid launches=() routers=() f
    for f in "$STATE"/*.pid; do
        [ -e "$f" ] || continue
        case "$f" in *-router.pid) routers+=("$f") ;; *) launches+=("$f") ;; esac
    done
    [ ${#launches[@]} -eq 0 ] || stop_pids "${launches[@]}"
    [ ${#routers[@]} -eq 0 ] || stop_pids "${routers[@]}"
    for n in $(our_ns); do
        for pid in $(ip netns pids "$n"); do kill -KILL "$pid" 2>/dev/null || true; done
    done
    say "stopped"
}

cmd_down() {
    need_root
    cmd_stop
    local n
    for n in $(our_ns); do ip netns del "$n"; done
    say "down (logs kept in $STATE)"
}

# cpu [SECONDS]: cores each process of each host used over a window, every thread counted
# (/proc/<pid>/task/*/schedstat, nanoseconds), and each host's total.
cmd_cpu() {
    need_root
    local secs=${1:-10} h pids=()
    for h in "${HOSTS[@]}"; do
        pids+=("$h:$(ip netns pids "$(ns "$h")" 2>/dev/null | tr '\n' ',')")
    done
    "$PY" - "$secs" "${pids[@]}" <<'PYEOF'
import pathlib, sys, time
secs = float(sys.argv[1])
hosts = {h: [int(p) for p in ps.split(",") if p] for h, _, ps in (a.partition(":") for a in sys.argv[2:])}
def cpu(pid):
    total = 0
    for t in pathlib.Path(f"/proc/{pid}/task").glob("*/schedstat"):
        try:
            total += int(t.read_text().split()[0])
        except (OSError, ValueError, IndexError):
            pass
    return total / 1e9
def label(pid):
    try:
        argv = pathlib.Path(f"/proc/{pid}/cmdline").read_bytes().decode().split("\0")
    except OSError:
        return "?"
    for i, a in enumerate(argv):
        if a == "-m" and i + 1 < len(argv):
            mod = argv[i + 1].removeprefix("zenros.")
            if mod == "cli" and "launch" in argv:
                return "launch " + pathlib.Path(argv[argv.index("launch") + 1]).name
            if mod == "container" and "--ns" in argv and "--name" in argv:
                return "container %s/%s" % (argv[argv.index("--ns") + 1].rstrip("/"),
                                            argv[argv.index("--name") + 1])
            named = [x.split(":=", 1)[1] for x in argv if x.startswith(("__node:=", "__ns:="))]
            return mod + (" " + "/".join(reversed(named)) if named else "")
    return pathlib.Path(argv[0]).name
before = {p: cpu(p) for ps in hosts.values() for p in ps}
t0 = time.monotonic(); time.sleep(secs); dt = time.monotonic() - t0
print("load average %s; cores over %.0f s" % (open("/proc/loadavg").read().split()[0], dt))
for h, ps in hosts.items():
    rows = [(label(p), p, (cpu(p) - before[p]) / dt) for p in ps]
    print("%-4s %.3f" % (h, sum(r[2] for r in rows)))
    for name, p, c in rows:
        print("       %.3f  %-7d %s" % (c, p, name))
PYEOF
}

# outage ROBOT [SECONDS]: (routed) with every robot's odom flowing to the station, pull ROBOT's
# link for SECONDS (default 10) while each other robot drives a 1 m goal through the fleet
# gateway, then restore it; one JSON line of figures (deploy/demo/outage.py).
cmd_outage() {
    need_root
    [ "$TOPOLOGY" = routed ] || die "outage needs ZR_TOPOLOGY=routed (the fleet gateway)"
    local h; h=$(short "${1:?usage: outage ROBOT [SECONDS]}")
    export ZR_PREFIX=$P ZR_STATE=$STATE ZR_TOPOLOGY=$TOPOLOGY ZR_ROBOTS=$ROBOTS
    cmd_run station "$PY" "$HERE/outage.py" --demo "$HERE/demo.sh" --robots "$ROBOTS" \
        --cut "robot${h#r}" --seconds "${2:-10}"
}

main() {
    local cmd=${1:-}; shift || true
    case "$cmd" in
        up|start|show|api|report|link|flap|loss|run|status|stop|down|cpu|outage) "cmd_$cmd" "$@" ;;
        *) awk 'NR > 1 && /^set -euo/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"
           [ -n "$cmd" ] && exit 2; exit 0 ;;
    esac
}

main "$@"
