#!/usr/bin/env bash
# scripts/callgrind_costs.sh OUT_CSV METHOD...: the CPU cost of registry
# methods in instructions per float evaluation, counted by valgrind's callgrind
# on build/bench/method_cost (bench/method_cost.cpp: 4096 inputs, κ
# log-uniform over [1e−3, 1e4], c uniform). Per method and mode
# (scalar: f32 per element; batch: batch32; eval and setup: the per-light
# split, where the method has one), cost = (Ir(PASSES) − Ir(0)) / (PASSES × 4096):
# the difference removes start-up and input generation. Instruction counts do
# not depend on the machine's load. Writes OUT_CSV (method,mode,instructions).
set -euo pipefail
cd "$(dirname "$0")/.."
(($# >= 2)) || { echo "usage: scripts/callgrind_costs.sh OUT_CSV METHOD..." >&2; exit 2; }
out=$1
shift
passes=4
inputs=4096
tool=build/bench/method_cost
[ -x "$tool" ] || { echo "callgrind_costs: $tool is not built (cmake --build build --target method_cost)" >&2; exit 2; }
scratch=$(mktemp -d)
# The table is written beside OUT_CSV and renamed over it when complete.
partial=$(mktemp "$out.XXXXXX")
trap 'rm -rf "$scratch" "$partial"' EXIT

# Total instructions (callgrind's "summary:" line) of one run.
instructions() {
  local file=$scratch/callgrind.out
  valgrind --tool=callgrind --callgrind-out-file="$file" "$tool" "$@" >/dev/null 2>&1
  awk '/^(summary|totals):/ { print $2; exit }' "$file"
}

modes_of() {
  # The split modes only where the method has one (method_cost exits 2 otherwise).
  if "$tool" "$1" 0 eval >/dev/null 2>&1; then echo "scalar batch eval setup"; else echo "scalar batch"; fi
}

{
  echo "method,mode,instructions"
  for method in "$@"; do
    for mode in $(modes_of "$method"); do
      with=$(instructions "$method" "$passes" "$mode")
      without=$(instructions "$method" 0 "$mode")
      awk -v m="$method" -v mode="$mode" -v a="$with" -v b="$without" -v p="$passes" -v n="$inputs" \
        'BEGIN { printf "%s,%s,%.1f\n", m, mode, (a - b) / (p * n) }'
      [ -t 2 ] && printf '\rcallgrind: %-24s %-6s' "$method" "$mode" >&2
    done
  done
  [ -t 2 ] && printf '\r%60s\r' '' >&2
} >"$partial"
mv "$partial" "$out"
