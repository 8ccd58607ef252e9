#!/usr/bin/env bash
# make test-determinism: builds the code the checks need with several compilers and optimisation levels,
# each in its own build directory, runs the same checks in every build and shows that they agree bit for
# bit; one build is for aarch64 (Debian's cross compiler), its programs run here under qemu-user. Exits 1
# when a build disagrees (naming the first differing scene and tick) or a check fails, 2 on a usage
# error. See tools/determinism/README.md.
set -euo pipefail

# The builds: name, C++ compiler, CMake build type, compiler flags. "None" makes CMake add no flags of its
# own, so the flags here are the whole optimisation story. The sanitizer build is the one make
# test-sanitize uses (its directory is reused, and only the targets below are built in it).
builds=(
  "gcc-O2    g++      None            -O2 -DNDEBUG"
  "gcc-O0    g++      None            -O0"
  "gcc-O3    g++      None            -O3 -DNDEBUG"
  "gcc-asan  g++      RelWithDebInfo  sanitize"
  "clang-O2  clang++  None            -O2 -DNDEBUG"
  "aarch64   aarch64-linux-gnu-g++  None  -O2 -DNDEBUG"
)
# Builds for another processor: the CMake toolchain file (it names the compiler; the column above is for
# the summary), and the command that runs their programs on this machine ({run} in the checks; nothing
# for the others).
declare -A toolchains=([aarch64]="cmake/aarch64-linux-gnu.cmake")
declare -A runners=([aarch64]="qemu-aarch64 -L /usr/aarch64-linux-gnu")
# What each build compiles: only what the checks run.
targets=(rattle-trace rattle-replay rattle-demo)
# What runs in every build. "same NAME COMMAND": COMMAND's stdout must be byte-identical in every build
# (the first build is the reference); "pass NAME COMMAND": COMMAND must exit 0 in every build.
# {bin} is the build's bin/ directory, {ref} the reference build's, {run} the build's runner (qemu-user for
# aarch64, else nothing), {src} the source tree. The network check plays the reference build's
# rattle-demo (host) against this build's (joiner) in lockstep: both must end with the same final hash,
# and it must be the reference build's own.
checks=(
  "same trace {run} {bin}/rattle-trace"
  "pass replays for r in {src}/assets/replays/*.replay; do {run} {bin}/rattle-replay verify --quiet \"\$r\" || exit 1; done"
  "same net {src}/tools/determinism/net_game.sh --timeout 600 --map {src}/assets/maps/arena.json --host {ref}/rattle-demo --join '{run} {bin}/rattle-demo'"
)

usage() {
  cat <<'EOF'
usage: tools/determinism/run_builds.sh [--out DIR] [--sanitize-dir DIR] [--only NAME] [--jobs N]

Builds the determinism checks (rattle-trace, rattle-replay, rattle-demo) with g++ -O2, -O0, -O3, g++ with
ASan+UBSan, clang++ -O2 and aarch64-linux-gnu-g++ -O2 (run under qemu-aarch64), runs them in each build,
and compares the outputs: every build must print the same bytes as the first. The checks: the trace
(rattle-trace), every replay in assets/replays/ verifies (rattle-replay verify), and a networked game
between the first build's rattle-demo (host) and this build's (joiner) ends without a desync
(tools/determinism/net_game.sh). On a difference it names the first differing line, "<scene>/<mode>
<tick> <hash>" for the trace. Every compile command of every build must carry -ffp-contract=off.
The aarch64 build needs scripts/packages-aarch64.txt (make test-determinism installs it).

  --out DIR           where the builds go, one directory each (default: build-determinism)
  --sanitize-dir DIR  the ASan+UBSan build directory to reuse (default: build-sanitize, as make test-sanitize)
  --only NAME         build and check only NAME (with the reference build, gcc-O2)
  --jobs N            parallel compile jobs (default: 2)
  --help              this text

Writes DIR/<build>/ (a CMake build tree) and DIR/<build>/<check>.out (what each check printed), and a
log of each configure and build in DIR/<build>.log. Extra CMake arguments: $CMAKE_FLAGS.
EOF
}

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="build-determinism"
sanitize_dir="build-sanitize"
only=""
jobs=2
while [[ $# -gt 0 ]]; do
  case "$1" in
    --help|-h) usage; exit 0 ;;
    --out) out="${2:?--out needs a directory}"; shift 2 ;;
    --sanitize-dir) sanitize_dir="${2:?--sanitize-dir needs a directory}"; shift 2 ;;
    --only) only="${2:?--only needs a build name}"; shift 2 ;;
    --jobs) jobs="${2:?--jobs needs a number}"; shift 2 ;;
    *) echo "run_builds.sh: $1: unknown option (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "run_builds.sh: --jobs $jobs: expected a whole number from 1" >&2; exit 2; }
if [[ -n "$only" ]]; then
  kept=("${builds[0]}")
  for b in "${builds[@]:1}"; do [[ "${b%% *}" == "$only" ]] && kept+=("$b"); done
  if [[ ${#kept[@]} -eq 1 && "$only" != "${builds[0]%% *}" ]]; then
    echo "run_builds.sh: --only $only: no such build (have:$(for b in "${builds[@]}"; do printf ' %s' "${b%% *}"; done))" >&2
    exit 2
  fi
  builds=("${kept[@]}")
fi
mkdir -p "$out"
read -r -a extra <<< "${CMAKE_FLAGS:-}"

# Configures and builds one build; prints its directory. (Called as `if ! dir=$(...)`, where set -e does
# not apply, hence the explicit returns.)
build_one() {
  local name="$1" cxx="$2" type="$3" flags="$4" dir log
  log="$out/$name.log"
  if [[ "$flags" == sanitize ]]; then
    dir="$sanitize_dir"
    cmake -S "$root" -B "$dir" -DCMAKE_BUILD_TYPE="$type" -DRATTLE_SANITIZE=ON "${extra[@]}" > "$log" 2>&1 || return 1
  else
    dir="$out/$name"
    local compiler=(-DCMAKE_CXX_COMPILER="$cxx")
    [[ -n "${toolchains[$name]:-}" ]] && compiler=(-DCMAKE_TOOLCHAIN_FILE="$root/${toolchains[$name]}")
    cmake -S "$root" -B "$dir" "${compiler[@]}" -DCMAKE_BUILD_TYPE="$type" -DCMAKE_CXX_FLAGS="$flags" \
      -DRATTLE_BUILD_TESTS=OFF -DRATTLE_BUILD_EXAMPLES=OFF "${extra[@]}" > "$log" 2>&1 || return 1
  fi
  cmake --build "$dir" --target "${targets[@]}" -j "$jobs" >> "$log" 2>&1 || return 1
  # The project's -ffp-contract=off must reach every compile (a cross compiler, a toolchain file or
  # CMAKE_FLAGS could lose it; aarch64 g++ fuses a*b+c into an fma without it).
  local unflagged
  [[ -r "$dir/compile_commands.json" ]] || { echo "no $dir/compile_commands.json to check the flags in" >> "$log"; return 1; }
  unflagged="$(grep '"command"' "$dir/compile_commands.json" | grep -v -c -e '-ffp-contract=off' || true)"
  if ! grep -q '"command"' "$dir/compile_commands.json"; then
    echo "$dir/compile_commands.json lists no compile command to check the flags of" >> "$log"
    return 1
  elif [[ "$unflagged" != 0 ]]; then
    echo "$unflagged compile command(s) in $dir/compile_commands.json lack -ffp-contract=off" >> "$log"
    return 1
  fi
  echo "$dir"
}

# Prints the first line where two outputs differ, as "line N: <a> | <b>".
first_difference() {
  awk 'NR == FNR { a[FNR] = $0; n = FNR; next }
       { if (!(FNR in a) || a[FNR] != $0) { print "line " FNR ": " (FNR in a ? a[FNR] : "(nothing)") " | " $0; found = 1; exit } }
       END { if (!found && FNR < n) print "line " FNR + 1 ": " a[FNR + 1] " | (nothing: the output ends)" }' "$1" "$2"
}

reference=""
failures=0
summary=()
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
for b in "${builds[@]}"; do
  read -r name cxx type flags <<< "$b"
  start=$SECONDS
  echo "determinism: $name: building ${targets[*]} ($cxx, ${flags})" >&2
  if ! dir="$(build_one "$name" "$cxx" "$type" "$flags")"; then
    echo "determinism: $name: the build failed; the end of $out/$name.log:" >&2
    tail -n 30 "$out/$name.log" >&2
    summary+=("$(printf '%-9s build failed' "$name")")
    failures=$((failures + 1))
    continue
  fi
  built=$((SECONDS - start))
  start=$SECONDS
  result="agrees"
  [[ -z "$reference" ]] && reference_bin="$dir/bin"
  for c in "${checks[@]}"; do
    read -r kind check command <<< "$c"
    command="${command//\{run\}/${runners[$name]:-}}"
    command="${command//\{ref\}/$reference_bin}"
    command="${command//\{bin\}/$dir/bin}"
    command="${command//\{src\}/$root}"
    output="$out/$name/$check.out"
    mkdir -p "$(dirname "$output")"
    echo "determinism: $name: $check" >&2
    status=0
    # A shell command line (globs, loops), in a subshell so that an `exit` in it ends only the check.
    (eval "$command") > "$output" 2> "$output.err" || status=$?
    if [[ $status -ne 0 ]]; then
      echo "determinism: $name: $check exited with status $status; the end of $output.err:" >&2
      tail -n 20 "$output.err" >&2
      result="$check failed"
      failures=$((failures + 1))
      continue
    fi
    if [[ "$kind" == same && -n "$reference" ]]; then
      ref_output="$out/$reference/$check.out"
      if ! cmp -s "$ref_output" "$output"; then
        echo "determinism: $name differs from $reference in $check, first at $(first_difference "$ref_output" "$output")" >&2
        result="DIFFERS from $reference ($check)"
        failures=$((failures + 1))
      fi
    fi
  done
  [[ -z "$reference" ]] && reference="$name" && result="reference"
  summary+=("$(printf '%-9s %-21s built in %3d s, checks in %3d s: %s' "$name" "$cxx" "$built" $((SECONDS - start)) "$result")")
done

echo "determinism: summary" >&2
printf '  %s\n' "${summary[@]}" >&2
[[ $failures -eq 0 ]] || { echo "determinism: $failures problem(s)" >&2; exit 1; }
