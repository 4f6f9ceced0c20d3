#!/usr/bin/env bash
# scripts/results.sh: regenerates every committed result, data/results/ and
# the measured tables of README.md and docs/*.md, from the commands that produce them. One
# command, so that no number in them is ever typed: `sglab run --full` (every
# step in its full form: the exhaustive erf check, the long benchmark
# repetitions; sweep, erf,
# stability, claims, bench, GPU cost, Pareto, figures, environment maps) into
# out/results/run, the curated files copied from it, then the runs `sglab run`
# does not make (GPU cost of the half exports, per light over 1 to 64 lights
# and by compile path, the Vulkan sweep with split and half rows, the held-out
# sweep, half stability, the κ range of every method's registry card,
# callgrind instruction counts),
# and the generated blocks of the Markdown files filled from them: each lies
# between `<!-- generated: NAME (scripts/results.sh) -->` and
# `<!-- end: NAME -->` and is replaced whole; the prose around it is not
# touched. tests/test_readme_numbers.cpp checks their numbers against
# the same sources. The bench timings depend
# on the machine's load, the instruction counts and GPU statistics do not.
# Extra arguments go to `sglab run`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh jq valgrind blender-data
scripts/build.sh
cmake --build build --target method_cost -j"$(nproc)"

results=data/results
work=out/results
# `sglab run` replaces its folder as a whole (only ever its own earlier output),
# so the other runs below write beside it, never into it.
run="$work/run"
sglab=build/sglab

# 1. The main job in its full form, then the files of it that are committed.
"$sglab" run --full --out "$run" "$@"
cp "$run"/bench/{bench.csv,bench.md,bench_summary.csv,bench_summary.md,costs.json,gpu_costs.md} "$results"/
cp "$run"/claims/claims.md "$run"/erf/erf_summary.md "$results"/
cp "$run"/stability/{stability.md,findings.md} "$results"/
cp "$run"/pareto/{pareto.csv,pareto.md} "$results"/
cp "$run"/figures/[a-g]_*.{png,svg} "$results"/
cp "$run"/envmap/{probes.md,probes.csv,probes.png} "$results"/  # the probe table, full maps

# 2. What `sglab run` does not make.
"$sglab" envmap baselines --out "$results"  # envmaps.md: lobe fits against the BakingLab baseline
"$sglab" gpucost --lang both --precision both --out "$results"  # the gpu section of costs.json, gpu_costs.md
{ # cycles per light over 1, 8 and 64 lights (the 8-light loop is the default figure)
  echo "# GPU cost per light against the number of lights"
  echo
  "$sglab" gpucost --families navi21,gfx1100 --harness loop --lights 1,8,64
} >"$results/gpu_loop_lights.md"
{ # what spirv-opt does to each language's exports
  echo "# GPU cost by compile path: glslang's SPIR-V, legalized (HLSL), optimized"
  echo
  "$sglab" gpucost --families navi21,gfx1100 --lang both --compile none,legalized,optimized --harness single,loop
} >"$results/gpu_compile_paths.md"
"$sglab" sweep --backend cpu,vulkan --precision float,half --lang both --out "$work/vulkan"
cp "$work/vulkan/summary.json" "$results/vulkan_sweep.json"
cp "$work/vulkan/summary.md" "$results/sweep_summary.md"
"$sglab" sweep --kappa 1.1e-3:9.7e3:217 --cosines 401 --out "$work/heldout"
cp "$work/heldout/summary.json" "$results/heldout_sweep.json"
# Python against the C++ float batch (a wall-clock benchmark: it states its load).
PYTHONPATH=build/python /usr/bin/python3 bench/python_irradiance.py --out "$results/python_speed.md"
"$sglab" stability --half --out "$work/stability-half"
cp "$work/stability-half/stability_half.md" "$results"/
"$sglab" range --out "$work/range"  # every method's card from κ = 0 to FLT_MAX
cp "$work"/range/kappa_range.{csv,md} "$results"/
# sglab's own models (origin sglab on their registry cards) and the published methods their
# documents compare them with.
mapfile -t models < <("$sglab" methods --json |
  jq -r '.irradiance[] | select(.origin == "sglab" or .id == "vsgl2015" or .id == "tokuyoshi2024") | .id')
scripts/callgrind_costs.sh "$results/callgrind.csv" "${models[@]}"
"$sglab" fit sglab-acc --dry-run --costs "$results/costs.json" >"$work/fit-sglab-acc.txt"
"$sglab" fit sglab-fast --dry-run >"$work/fit-sglab-fast.txt"
"$sglab" fit sglab-mid --dry-run >"$work/fit-sglab-mid.txt"
for scene in studio sun_and_sky soft_room; do
  "$sglab" recommend --scene "data/scenes/$scene.json" --budget 5e-3 --costs "$results/costs.json" >"$work/recommend-$scene.txt"
done

# 3. The generated blocks.
scripts/results_tables.sh "$work"
echo "results.sh: data/results, README.md and docs/ regenerated (git diff shows what moved)"
