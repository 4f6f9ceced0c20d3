#!/usr/bin/env bash
# The main job: install what is missing, build the sglab command (only what it
# needs: no tests, benchmarks or Python package), and run `sglab run` into out/
# (see out/index.md). Extra arguments go to `sglab run` (e.g. --full, --quick).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh --target sglab
build/sglab table --kappa 4
build/sglab run --out out "$@"
