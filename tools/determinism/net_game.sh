#!/usr/bin/env bash
# One networked game of the demo between two rattle-demo programs, possibly of different builds (make
# test-determinism: the reference x86-64 build hosts, each build joins, the aarch64 one under qemu-user).
# Exits 0 and prints the final line both sides agreed on when both exit 0 with the same final hash;
# otherwise 1 (each side's status and the end of its output on stderr), 2 on a usage error.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: tools/determinism/net_game.sh --host CMD --join CMD [--map FILE] [--ticks N] [--units N] [--seed N]
                                     [--timeout S] [--log DIR]

Plays one lockstep game over ENet on 127.0.0.1: CMD --host 0 (the system picks a free port) and
CMD --join 127.0.0.1:PORT, headless (--no-render), with the same game options on both sides. Each CMD is
a rattle-demo program, word-split, so it may start with a runner: "qemu-aarch64 -L /usr/aarch64-linux-gnu
build-aarch64/bin/rattle-demo". Succeeds when both exit 0 and print the same final state hash, and prints
that line ("Network game over after N ticks: final state hash H") on stdout.

  --host CMD     the hosting rattle-demo (plays blue)
  --join CMD     the joining rattle-demo (plays red)
  --map FILE     the map (default: the programs' own default, assets/maps/arena.json)
  --ticks N      ticks to play (default 600: the teams meet and fight from about tick 400)
  --units N      units a team (default 100)
  --seed N       the scripted opponents' seed (default 1)
  --timeout S    seconds either side may take before it is ended as failed (default 600)
  --log DIR      where the two sides' output goes, as host.log and join.log (default: a temporary
                 directory, removed at the end)
  --help         this text

Exit status: 0 the game completed with equal final hashes, 1 it did not (a side failed, timed out,
desynced (rattle-demo's status 4) or the two final lines differ), 2 bad options.
EOF
}

host="" join="" map="" ticks=600 units=100 seed=1 timeout_s=600 log=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --help|-h) usage; exit 0 ;;
    --host) host="${2:?--host needs a command}"; shift 2 ;;
    --join) join="${2:?--join needs a command}"; shift 2 ;;
    --map) map="${2:?--map needs a file}"; shift 2 ;;
    --ticks) ticks="${2:?--ticks needs a number}"; shift 2 ;;
    --units) units="${2:?--units needs a number}"; shift 2 ;;
    --seed) seed="${2:?--seed needs a number}"; shift 2 ;;
    --timeout) timeout_s="${2:?--timeout needs seconds}"; shift 2 ;;
    --log) log="${2:?--log needs a directory}"; shift 2 ;;
    *) echo "net_game.sh: $1: unknown option (see --help)" >&2; exit 2 ;;
  esac
done
[[ -n "$host" && -n "$join" ]] || { echo "net_game.sh: both --host and --join are needed (see --help)" >&2; exit 2; }
for v in ticks units seed timeout_s; do
  [[ "${!v}" =~ ^[0-9]+$ ]] || { echo "net_game.sh: --${v%_s} ${!v}: expected a whole number" >&2; exit 2; }
done
if [[ -n "$log" ]]; then
  mkdir -p "$log"
else
  log="$(mktemp -d)"
  trap 'rm -rf "$log"' EXIT
fi
read -r -a host_cmd <<< "$host"
read -r -a join_cmd <<< "$join"
game=(--no-render --quiet --ticks "$ticks" --units "$units" --seed "$seed")
[[ -n "$map" ]] && game+=(--map "$map")

# The host first; the port it was given is in its first lines.
timeout "$timeout_s" "${host_cmd[@]}" --host 0 "${game[@]}" > "$log/host.log" 2>&1 &
host_pid=$!
port=""
for _ in $(seq 1 "$((timeout_s * 10))"); do
  port="$(sed -n 's/.*hosting on UDP port \([0-9][0-9]*\).*/\1/p' "$log/host.log" | head -n 1)"
  [[ -n "$port" ]] && break
  kill -0 "$host_pid" 2> /dev/null || break
  sleep 0.1
done
if [[ -z "$port" ]]; then
  kill "$host_pid" 2> /dev/null || true
  wait "$host_pid" 2> /dev/null || true
  echo "net_game.sh: the host never said which port it listens on; the end of its output:" >&2
  tail -n 20 "$log/host.log" >&2
  exit 1
fi
join_status=0
timeout "$timeout_s" "${join_cmd[@]}" --join "127.0.0.1:$port" "${game[@]}" > "$log/join.log" 2>&1 || join_status=$?
# A joiner that failed before it connected leaves the host waiting for a player: give it the time a
# connected peer's loss takes to notice (rattle-demo's --peer-timeout, 10 s), then end it.
if [[ $join_status -ne 0 ]]; then
  for _ in $(seq 1 150); do kill -0 "$host_pid" 2> /dev/null || break; sleep 0.1; done
  kill "$host_pid" 2> /dev/null || true
fi
host_status=0
wait "$host_pid" || host_status=$?

final_line() { grep -o 'Network game over after .*' "$1" | head -n 1 || true; }
host_line="$(final_line "$log/host.log")"
join_line="$(final_line "$log/join.log")"
problem=""
if [[ $host_status -ne 0 || $join_status -ne 0 ]]; then
  problem="host exited with status $host_status, joiner with $join_status (4: desync; 124: timed out after $timeout_s s; 143: ended after the joiner failed)"
elif [[ -z "$host_line" || "$host_line" != "$join_line" ]]; then
  problem="the final lines differ: host '${host_line:-(none)}', joiner '${join_line:-(none)}'"
elif [[ "$host_line" != "Network game over after $ticks ticks: final state hash "* ]]; then
  problem="unexpected final line: '$host_line'"
fi
if [[ -n "$problem" ]]; then
  echo "net_game.sh: $problem" >&2
  for side in host join; do
    echo "net_game.sh: the end of the $side's output:" >&2
    tail -n 15 "$log/$side.log" >&2
  done
  exit 1
fi
echo "$host_line"
