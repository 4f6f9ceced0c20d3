#!/usr/bin/env bash
# Configures and builds sglab into build/ (Release). `--target NAME`
# (repeatable) builds only NAME and what it needs instead of the default
# targets (everything but the benchmarks); other arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
configure=() targets=()
while [ $# -gt 0 ]; do
  if [ "$1" = --target ] && [ $# -gt 1 ]; then
    targets+=(--target "$2")
    shift 2
  else
    configure+=("$1")
    shift
  fi
done
scripts/deps.sh
# Ninja (scripts/deps.sh installs it) schedules every target's files on both
# cores at once; a build/ configured before keeps its generator.
generator=()
[ -f build/CMakeCache.txt ] || generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${configure[@]}" >/dev/null
cmake --build build -j"$(nproc)" "${targets[@]}"
