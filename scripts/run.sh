#!/usr/bin/env bash
# The main job: install what is missing, build, and run `sglab run` into out/
# (see out/index.md). Extra arguments go to `sglab run` (e.g. --quick).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
build/sglab table --kappa 4
build/sglab run --out out "$@"
