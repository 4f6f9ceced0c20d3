#!/usr/bin/env bash
# The main job: install what is missing, build, and run `sglab run`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
build/sglab table --kappa 4
