#!/usr/bin/env bash
# Runs every libFuzzer target of a fuzz build (make fuzz builds build-fuzz/ and calls this) for a set
# time each, from the seeds in fuzz/corpus/<name>/ and the kept findings in fuzz/regressions/<name>/.
# Exits 1 when any target finds something (a crash, a sanitizer report, a failed check, a timeout, too
# much memory), 2 on a usage error. See fuzz/README.md.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: fuzz/run.sh [--build DIR] [--seconds N] [--only NAME]

Runs each fuzz target listed in DIR/fuzzers.txt for N seconds, one after the other, and prints one line
per target: executions, corpus size, and whether it found anything.

  --build DIR    the fuzz build directory (default: build-fuzz, or $FUZZ_BUILD_DIR)
  --seconds N    seconds per target (default: 60, or $FUZZ_SECONDS)
  --only NAME    run only the target NAME (e.g. map_reader)
  FUZZ_SKIP=A,B  (environment) leave out these targets
  RATTLE_WORLD_API_REPORT=budget  (environment) world_api reports these invariant classes (one line
                 each, with the input in base64) instead of failing on them; CI sets it (fuzz/README.md)
  --help         this text

Written under DIR: corpus/<name>/ (the working corpus: seeds plus what the fuzzer found interesting;
kept between runs), findings/<name>/ (inputs that failed), logs/<name>.log (libFuzzer's output).
A finding is reproduced with:  DIR/bin/fuzz_<name> FILE
and kept as a regression test by copying it into fuzz/regressions/<name>/ (make test checks every file
there).
EOF
}

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${FUZZ_BUILD_DIR:-build-fuzz}"
seconds="${FUZZ_SECONDS:-60}"
only=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --help|-h) usage; exit 0 ;;
    --build) build="${2:?--build needs a directory}"; shift 2 ;;
    --seconds) seconds="${2:?--seconds needs a number}"; shift 2 ;;
    --only) only="${2:?--only needs a target name}"; shift 2 ;;
    *) echo "fuzz/run.sh: $1: unknown option (see --help)" >&2; exit 2 ;;
  esac
done
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [[ "$seconds" -lt 1 ]]; then
  echo "fuzz/run.sh: seconds = '$seconds': expected a whole number of seconds, at least 1" >&2; exit 2
fi
list="$build/fuzzers.txt"
if [[ ! -r "$list" ]]; then
  echo "fuzz/run.sh: $list: not found; build the fuzzers first (make fuzz)" >&2; exit 2
fi
mapfile -t names < <(grep -v '^\s*$' "$list")
if [[ -n "$only" ]]; then
  found=0
  for n in "${names[@]}"; do [[ "$n" == "$only" ]] && found=1; done
  [[ $found -eq 1 ]] || { echo "fuzz/run.sh: --only $only: no such target (have: ${names[*]})" >&2; exit 2; }
  names=("$only")
fi
if [[ -n "${FUZZ_SKIP:-}" ]]; then
  kept=()
  for n in "${names[@]}"; do [[ ",$FUZZ_SKIP," == *",$n,"* ]] || kept+=("$n"); done
  names=("${kept[@]}")
fi

# Inputs longer than this are not generated; it also keeps the kept regressions that are large on purpose
# (100,000 nested brackets) out of the corpus, where they would slow every mutation. make test runs them.
max_len=65536

# Copies a target's seeds into its working corpus: the files named in seeds.txt, the other files of
# fuzz/corpus/<name>/, and the kept regressions up to max_len. Files already there (earlier runs) stay.
seed_corpus() {
  local name="$1" work="$2" seeds="$root/fuzz/corpus/$1" line file
  mkdir -p "$work"
  if [[ -r "$seeds/seeds.txt" ]]; then
    while IFS= read -r line; do
      [[ "$line" =~ ^[[:space:]]*(#|$) ]] && continue
      file="$root/$line"
      [[ -r "$file" ]] || { echo "fuzz/run.sh: $seeds/seeds.txt: '$line' not found" >&2; exit 2; }
      cp "$file" "$work/seed-$(basename "$line")"
    done < "$seeds/seeds.txt"
  fi
  for file in "$seeds"/* "$root/fuzz/regressions/$name"/*; do
    [[ -f "$file" && "$(basename "$file")" != seeds.txt && "$(basename "$file")" != README.md ]] || continue
    [[ $(stat -c %s "$file") -le $max_len ]] || continue
    cp "$file" "$work/seed-$(basename "$file")"
  done
}

failed=()
summary=()
for name in "${names[@]}"; do
  bin="$build/bin/fuzz_$name"
  [[ -x "$bin" ]] || { echo "fuzz/run.sh: $bin: not built" >&2; exit 2; }
  work="$build/corpus/$name"
  findings="$build/findings/$name"
  log="$build/logs/$name.log"
  mkdir -p "$findings" "$(dirname "$log")"
  seed_corpus "$name" "$work"
  marker="$build/logs/$name.started"
  touch "$marker"
  # libFuzzer also writes slow-unit-* there (an input that took longer than -report_slow_units): on a
  # busy machine that is the machine, not a finding; -timeout catches the inputs that hang.
  before=$(find "$findings" -type f ! -name 'slow-unit-*' | wc -l)
  # A timeout stands for a hang. world_api's inputs are bounded by events and by their work (kWorkBudget
  # in fuzz/world_api.cpp), but one step of a pile stepped a whole second still costs up to 0.4 s in the
  # release build and 2.5 s in this one (ASan, UBSan, coverage) on a busy machine, and rarer ones may
  # cost more: world_api gets 30 s, a margin over the worst seen (a CI run at 7899866 stopped at 10 s on
  # an input it did not print; every one a local run found past 3 s had such steps; bench/README.md,
  # "Piles").
  timeout=10
  [[ $name == world_api ]] && timeout=30
  args=(-max_total_time="$seconds" -timeout=$timeout -rss_limit_mb=2048 -malloc_limit_mb=512 -max_len=$max_len
        -artifact_prefix="$findings/" -print_final_stats=1)
  [[ -r "$root/fuzz/$name.dict" ]] && args+=(-dict="$root/fuzz/$name.dict")
  echo "fuzz: $name for ${seconds} s (log $log)" >&2
  # libFuzzer's own output is long: it goes to the log, and a progress line is drawn from it.
  ASAN_OPTIONS="abort_on_error=1:detect_leaks=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    "$bin" "${args[@]}" "$work" > "$log" 2>&1 &
  pid=$!
  start=$SECONDS
  while sleep 5 && kill -0 "$pid" 2>/dev/null; do
    execs=$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#' || true)
    printf '\rfuzz: %s %d/%d s, %s executions ' "$name" $((SECONDS - start)) "$seconds" "${execs:-0}" >&2
  done
  status=0
  wait "$pid" || status=$?
  printf '\r%60s\r' '' >&2
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  corpus=$(find "$work" -type f | wc -l)
  after=$(find "$findings" -type f ! -name 'slow-unit-*' | wc -l)
  # Violations a target was asked to report rather than fail on (RATTLE_WORLD_API_REPORT): each input
  # that showed one is printed with its bytes, and counted in the summary.
  reports=$(grep -c '^rattle fuzz report:' "$log" || true)
  if [[ $reports -gt 0 ]]; then
    echo "fuzz: $name reported $reports input(s) (not failures; fuzz/README.md says how to keep one):" >&2
    # awk reads the whole log: `grep | head` lost grep to SIGPIPE once head had its lines, and under
    # pipefail that 141 ended this script (a 420 s world_api run with 16 reports).
    awk '/^rattle fuzz report:/ && shown < 5 { print "  " $0; ++shown }' "$log" >&2
  fi
  note=""
  [[ $reports -gt 0 ]] && note=", $reports reported"
  if [[ $status -ne 0 || $after -gt $before ]]; then
    failed+=("$name")
    summary+=("$(printf '%-14s FOUND SOMETHING  %s executions, exit status %d' "$name" "${execs:-?}" "$status")")
    echo "fuzz: $name found something (exit status $status). The end of $log:" >&2
    tail -n 40 "$log" >&2
    for f in $(find "$findings" -type f ! -name 'slow-unit-*' -newer "$marker"); do
      echo "fuzz: finding $f ($(stat -c %s "$f") bytes)" >&2
      echo "  reproduce:  $bin $f" >&2
      echo "  keep it:    cp $f $root/fuzz/regressions/$name/  (once fixed; make test checks it; fuzz/README.md)" >&2
      # CI machines are thrown away: small findings are printed whole, to be rebuilt with base64 -d.
      if [[ $(stat -c %s "$f") -le 65536 ]]; then
        echo "  base64:" >&2
        base64 -w 100 "$f" | sed 's/^/    /' >&2
      fi
    done
  else
    summary+=("$(printf '%-14s ok  %s executions in %d s, corpus %d inputs%s' "$name" "${execs:-?}" "$seconds" "$corpus" "$note")")
  fi
done

echo "fuzz: summary" >&2
printf '  %s\n' "${summary[@]}" >&2
[[ ${#failed[@]} -eq 0 ]] || { echo "fuzz: findings in: ${failed[*]}" >&2; exit 1; }
