#!/usr/bin/env bash
# scripts/results_tables.sh WORK: fills the generated blocks of README.md, docs/*.md and
# data/results/*.md from data/results (costs.json, callgrind.csv,
# heldout_sweep.json, vulkan_sweep.json, kappa_range.csv), from the fit reports that
# scripts/results.sh leaves in WORK, and from the registry cards (`sglab methods`; $SGLAB, by
# default build/sglab). Called by scripts/results.sh; on its own
# it redraws the tables from the committed sources without rerunning anything.
# A block is the text between `<!-- generated: NAME (scripts/results.sh) -->`
# and `<!-- end: NAME -->`; a file without the block is an error (exit 2).
set -euo pipefail
cd "$(dirname "$0")/.."
(($# == 1)) || { echo "usage: scripts/results_tables.sh WORK" >&2; exit 2; }
work=$1
results=data/results
costs=$results/costs.json
heldout=$results/heldout_sweep.json
standard=$results/vulkan_sweep.json
callgrind=$results/callgrind.csv
sglab=${SGLAB:-build/sglab}

# fill FILE NAME: replaces the block NAME of FILE with standard input.
fill() {
  local file=$1 name=$2 body
  body=$(mktemp)
  cat >"$body"
  grep -qF -- "<!-- generated: $name (scripts/results.sh) -->" "$file" && grep -qF -- "<!-- end: $name -->" "$file" ||
    { echo "results_tables: $file has no block '$name'" >&2; rm -f "$body"; exit 2; }
  local partial
  partial=$(mktemp "$file.XXXXXX")
  awk -v begin="<!-- generated: $name (scripts/results.sh) -->" -v end="<!-- end: $name -->" -v body="$body" '
    $0 == begin { print; while ((getline line < body) > 0) print line; skip = 1; next }
    $0 == end { skip = 0 }
    !skip { print }' "$file" >"$partial"
  mv "$partial" "$file"
  rm -f "$body"
}

# Number formats of the documents: three significant digits, a Unicode minus
# in exponents (1.93e−4); `plain` for CSV-like cells (1.93e-04 → 0.000193).
fmt_awk='function sig(x,   s, m, e) {
  if (x == "" || x == "null") return "";
  if (x >= 0.01 || x == 0) { s = sprintf("%.3g", x); return s }
  s = sprintf("%.2e", x); split(s, m, "e"); e = m[2] + 0;
  sub(/0+$/, "", m[1]); sub(/\.$/, "", m[1]);
  return m[1] "e\xe2\x88\x92" (-e)
}
function ratio(a, b) { return sprintf("%.2f", a / b) }'

# Float max peak_rel of METHOD in a sweep summary (irradiance rows).
peak() { jq -r --arg m "$2" --arg p "${3:-float}" \
  '[.results[] | select(.method == $m and .quantity == "irradiance" and .precision == $p)][0].max_peak_rel // ""' "$1"; }
worst_kappa() { jq -r --arg m "$2" \
  '[.results[] | select(.method == $m and .quantity == "irradiance" and .precision == "float")][0].worst_kappa // ""' "$1"; }
# ACO inverse throughput of one call of METHOD's GLSL float export (glslang's SPIR-V, harness
# single) on FAMILY (split: true|false).
cycles() { jq -r --arg m "$1" --arg f "$2" --argjson s "${3:-false}" \
  '[.gpu.rows[] | select(.method == $m and .family == $f and .lang == "glsl" and .compile == "none" and .precision == "float" and .harness == "single" and .split == $s)][0].inverse_throughput // ""' "$costs"; }
# GPU cycles per light per pixel of METHOD on FAMILY (--cost gpu:FAMILY): the 8-light loop of its
# GLSL float export, the split form where it has one.
per_light() { jq -r --arg m "$1" --arg f "$2" \
  '[.gpu.rows[] | select(.method == $m and .family == $f and .lang == "glsl" and .compile == "none" and .precision == "float" and .harness == "loop" and .lights == 8)] | ([.[] | select(.split)] + [.[] | select(.split | not)])[0] | if . == null then "" else .inverse_throughput / .lights end' "$costs"; }
batch_ns() { jq -r --arg m "$1" \
  '[.costs[] | select(.method == $m and .kind == "irradiance" and .precision == "float" and .mode == "batch")][0].ns_per_eval // ""' "$costs"; }
instructions() { awk -F, -v m="$1" -v mode="$2" '$1 == m && $2 == mode { print $3 }' "$callgrind"; }

# The registry cards (include/sglab/registry.hpp) as `sglab methods` prints them: every table
# below takes a method's name, origin and form from its card.
cards=$(mktemp)
trap 'rm -f "$cards"' EXIT
"$sglab" methods --json >"$cards"

# README.md: sglab's own models (origin sglab on their cards) beside the published methods they
# are measured against, the most accurate held-out error in bold; "—" where a source has no
# row for the method yet.
models_table() {
  echo "| method | form | held-out max peak_rel | standard grid | GPU cycles per light per pixel | GPU cycles, one call | batch ns |"
  echo "|---|---|---:|---:|---:|---:|---:|"
  jq -r '.irradiance[] | select(.origin == "sglab" or .id == "vsgl2015" or .id == "tokuyoshi2024") |
    [.id, .origin, .form] | @tsv' "$cards" |
    while IFS=$'\t' read -r method origin form; do
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$method" "$origin" "$form" "$(peak "$heldout" "$method")" \
        "$(peak "$standard" "$method")" "$(per_light "$method" navi21)" "$(cycles "$method" navi21)" "$(batch_ns "$method")"
    done | awk -F'\t' "$fmt_awk"'
    function cell(x) { return x == "" ? "—" : sprintf("%.3g", x) }
    function num(x) { return x == "" ? "—" : sig(x) }
    { row[NR] = $0; if ($4 != "" && (best == "" || $4 + 0 < best)) { best = $4 + 0; at = NR } }
    END {
      for (i = 1; i <= NR; ++i) {
        split(row[i], f, "\t")
        name = f[2] == "sglab" ? "`" f[1] "`" : f[1] " (" f[2] ")"
        h = num(f[4]); s = num(f[5]); if (i == at) { h = "**" h "**"; s = "**" s "**" }
        printf "| %s | %s | %s | %s | %s | %s | %s |\n", name, f[3], h, s, cell(f[6]), num(f[7]) == "—" ? "—" : f[7], cell(f[8])
      }
    }'
}
models_table | fill README.md sglab-models

# The registry cards against `sglab range` (data/results/kappa_range.csv): each METHOD's bound
# and valid κ range, its worst error on that range and where, the measured range where the bound
# holds, and its worst error over every κ a float holds. No METHOD: every method.
kappa_range=$results/kappa_range.csv
range_table() {
  echo "| method | bound (card) | valid κ (card) | worst on it | at κ, c | holds | bound holds on (measured) | worst anywhere | at κ |"
  echo "|---|---:|---|---:|---|---|---|---:|---:|"
  awk -F, -v want="$*" "$fmt_awk"'
    function k(x) { return x + 0 >= 3.4e38 ? "FLT_MAX" : (x + 0 == 0 ? "0" : sprintf("%.2g", x)) }
    BEGIN { n = split(want, w, " "); for (i = 1; i <= n; ++i) pick[w[i]] = 1 }
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    n == 0 || ($col["method"] in pick) {
      any = $col["max_peak_rel_anywhere"]; any = any == "inf" ? "inf" : sig(any)
      printf "| %s | %s | [%s, %s] | %s | %.3g, %.3g | %s | [%s, %s] | %s | %.3g |\n", $col["method"], sig($col["bound"]),
        k($col["kappa_lo"]), k($col["kappa_hi"]), sig($col["max_peak_rel"]), $col["at_kappa"], $col["at_cosine"],
        $col["holds"], k($col["holds_from"]), k($col["holds_to"]), any, $col["anywhere_at_kappa"] }' \
    "$kappa_range"
}
range_table | fill docs/cli.md kappa-range

# data/results/sglab_acc.md: the fit report, the held-out errors, the costs.
fence() { echo '```'; cat; echo '```'; }
fence <"$work/fit-sglab-acc.txt" | fill "$results/sglab_acc.md" fit
{
  echo "| method | float | double | worst κ (float) |"
  echo "|---|---:|---:|---:|"
  for m in tokuyoshi2024 sglab_acc1 sglab_acc2 sglab_acc3 sglab_acc4; do
    printf '%s\t%s\t%s\t%s\n' "$m" "$(peak "$heldout" "$m")" "$(peak "$heldout" "$m" double)" "$(worst_kappa "$heldout" "$m")"
  done | awk -F'\t' "$fmt_awk"'{ printf "| %s | %s | %s | %.4g |\n", $1, sig($2), sig($3), $4 }'
} | fill "$results/sglab_acc.md" heldout
cost_table() {  # METHOD...: callgrind and GPU cost, ratios to the first
  echo "| method | scalar Ir | ratio | batch Ir | ratio | setup Ir | eval Ir | navi21 | ratio | gfx1100 | ratio | navi21 split | navi21 per light | ratio |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  for m in "$@"; do
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$m" "$(instructions "$m" scalar)" "$(instructions "$m" batch)" \
      "$(instructions "$m" setup)" "$(instructions "$m" eval)" \
      "$(cycles "$m" navi21)" "$(cycles "$m" gfx1100)" "$(cycles "$m" navi21 true)" "$(per_light "$m" navi21)"
  done | awk -F'\t' "$fmt_awk"'
    NR == 1 { s = $2; b = $3; n = $6; g = $7; l = $9 }
    { printf "| %s | %.0f | %s | %.0f | %s | %.0f | %.0f | %s | %s | %s | %s | %s | %.3g | %s |\n", $1, $2, ratio($2, s), $3, ratio($3, b),
        $4, $5, $6, ratio($6, n), $7, ratio($7, g), $8, $9, ratio($9, l) }'
}
cost_table tokuyoshi2024 sglab_acc1 sglab_acc2 sglab_acc3 sglab_acc4 | fill "$results/sglab_acc.md" cost
range_table sglab_acc1 sglab_acc2 sglab_acc3 sglab_acc4 tokuyoshi2024 | fill "$results/sglab_acc.md" kappa-range

# accuracy_table METHOD...: each METHOD's max peak_rel in float and double on the standard and
# held-out grids, and the κ of its held-out float worst.
accuracy_table() {
  echo "| method | standard float | standard double | held-out float | held-out double | worst κ held-out (float) |"
  echo "|---|---:|---:|---:|---:|---:|"
  for m in "$@"; do
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$m" "$(peak "$standard" "$m")" "$(peak "$standard" "$m" double)" \
      "$(peak "$heldout" "$m")" "$(peak "$heldout" "$m" double)" "$(worst_kappa "$heldout" "$m")"
  done | awk -F'\t' "$fmt_awk"'{ printf "| %s | %s | %s | %s | %s | %.4g |\n", $1, sig($2), sig($3), sig($4), sig($5), $6 }'
}
# model_cost_table "FAMILY..." METHOD...: each METHOD's callgrind instructions (scalar, batch,
# per-light setup, per-point eval), GPU cycles of one call on navi21 and gfx1100, of the split
# form on each FAMILY, and per light per pixel on navi21.
model_cost_table() {
  local families=($1) head rule
  shift
  head="| method | scalar Ir | batch Ir | per-light setup Ir | per-point eval Ir | navi21 | gfx1100 |"
  rule="|---|---:|---:|---:|---:|---:|---:|"
  for f in "${families[@]}"; do
    head+=" $f split |"
    rule+="---:|"
  done
  echo "$head navi21 per light |"
  echo "$rule---:|"
  for m in "$@"; do
    local row=("$m" "$(instructions "$m" scalar)" "$(instructions "$m" batch)" "$(instructions "$m" setup)"
      "$(instructions "$m" eval)" "$(cycles "$m" navi21)" "$(cycles "$m" gfx1100)")
    for f in "${families[@]}"; do row+=("$(cycles "$m" "$f" true)"); done
    row+=("$(per_light "$m" navi21)")
    (IFS=$'\t'; echo "${row[*]}")
  done | awk -F'\t' '{ for (i = 2; i <= 5; ++i) if ($i == "") $i = "–"; else $i = sprintf("%.0f", $i);
                        line = "|"; for (i = 1; i < NF; ++i) line = line " " $i " |"
                        printf "%s %.3g |\n", line, $NF }'
}

# data/results/sglab_fast.md: the fit report, errors on both grids, the costs.
fence <"$work/fit-sglab-fast.txt" | fill "$results/sglab_fast.md" fit
accuracy_table sglab_fast tokuyoshi2024 vsgl2015 | fill "$results/sglab_fast.md" accuracy
model_cost_table navi21 sglab_fast vsgl2015 tokuyoshi2024 | fill "$results/sglab_fast.md" cost
range_table sglab_fast tokuyoshi2024 vsgl2015 | fill "$results/sglab_fast.md" kappa-range
for scene in studio sun_and_sky soft_room; do
  echo '```sh'
  echo "build/sglab recommend --scene data/scenes/$scene.json --budget 5e-3 --costs data/results/costs.json"
  echo '```'
  echo
  fence <"$work/recommend-$scene.txt"
  echo
done | sed '$d' | fill "$results/sglab_fast.md" scenes

# data/results/sglab_mid.md: the fit report, errors on both grids, the costs.
fence <"$work/fit-sglab-mid.txt" | fill "$results/sglab_mid.md" fit
accuracy_table sglab_mid tokuyoshi2024 sglab_fast | fill "$results/sglab_mid.md" accuracy
model_cost_table "navi21 gfx1100" sglab_mid tokuyoshi2024 sglab_fast | fill "$results/sglab_mid.md" cost
range_table sglab_mid tokuyoshi2024 sglab_fast | fill "$results/sglab_mid.md" kappa-range

# data/results/vulkan_sweep.md: one row per method, one column per backend.
{
  echo "| method | double (model) | C++ float | Vulkan GLSL | Vulkan HLSL | GLSL split | GLSL half | HLSL half | max \\|GLSL − C++ float\\|/E(1, κ) | max \\|split GLSL − C++ float\\|/E(1, κ) |"
  echo "|:---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  jq -r '
    .results as $r | (.device_vs_float // []) as $d |
    def err($m; $p): ([$r[] | select(.method == $m and .quantity == "irradiance" and .precision == $p)][0].max_peak_rel) // "";
    def diff($m; $p): ([$d[] | select(.method == $m and .quantity == "irradiance" and .precision == $p)][0].max_diff_peak_rel) // "";
    (reduce ($r[] | select(.quantity == "irradiance") | .method) as $m ([]; if index([$m]) then . else . + [$m] end))[] as $m |
    [$m, err($m; "double"), err($m; "float"), err($m; "vulkan"), err($m; "vulkan_hlsl"), err($m; "vulkan_split"),
     err($m; "vulkan_half"), err($m; "vulkan_hlsl_half"), diff($m; "vulkan"), diff($m; "vulkan_split")] | @tsv' "$standard" |
    awk -F'\t' '{ printf "| %s |", $1; for (i = 2; i <= NF; ++i) printf " %s |", ($i == "" ? "" : sprintf("%.3g", $i)); printf "\n" }'
} | fill "$results/vulkan_sweep.md" vulkan-table

# docs/envmaps.md: the environment-map baselines (data/results/envmaps.csv, `sglab envmap baselines`):
# per lobe count the range over the maps of each fit's max error, and the worst map's (a)/(c).
envmaps=$results/envmaps.csv
awk -F, 'NR > 1 { v[$1 "," $2 "," $3] = $4; maps[$1] = 1 }
  END {
    print "| lobes | (a) BakingLab baseline | (b) sglab radiance fit | (c) sglab irradiance fit | (a)/(c), worst map |"
    print "|---:|---|---|---|---:|"
    split("4 8 12 24", ns, " ")
    split("baseline radiance irradiance", fits, " ")
    for (i = 1; i <= 4; ++i) {
      n = ns[i]; line = "| " n " |"
      for (f = 1; f <= 3; ++f) {
        lo = ""; hi = ""
        for (m in maps) { x = v[m "," n "," fits[f]] + 0; if (lo == "" || x < lo) lo = x; if (hi == "" || x > hi) hi = x }
        line = line sprintf(" %.2g – %.2g |", lo, hi)
      }
      worst = ""; wm = ""
      for (m in maps) { q = v[m "," n ",baseline"] / v[m "," n ",irradiance"]; if (worst == "" || q < worst) { worst = q; wm = m } }
      print line sprintf(" %.3g (%s) |", worst, wm)
    }
  }' "$envmaps" | fill docs/envmaps.md envmap-table
awk -F, 'NR > 1 { v[$1 "," $2 "," $3] = $4; maps[$1] = 1; if (!($2 in seen)) { seen[$2] = 1; lobes[++nl] = $2 + 0 } }
  END {
    split("4 8 12 24", ns, " "); lo = ""; hi = ""; cases = 0; ok = 0
    for (m in maps) for (i = 1; i <= 4; ++i) {
      q = v[m "," ns[i] ",baseline"] / v[m "," ns[i] ",irradiance"]; ++cases; if (q >= 2) ++ok
      if (lo == "" || q < lo) lo = q; if (hi == "" || q > hi) hi = q
    }
    # The fewest lobes at which each map'"'"'s irradiance fit is within 1 %, maps grouped by it (sorted names).
    for (m in maps) { need[m] = 0; for (k = 1; k <= nl; ++k) if (v[m "," lobes[k] ",irradiance"] <= 0.01) { need[m] = lobes[k]; break } }
    nm = 0; for (m in maps) names[++nm] = m
    for (i = 2; i <= nm; ++i) for (j = i; j > 1 && names[j - 1] > names[j]; --j) { t = names[j]; names[j] = names[j - 1]; names[j - 1] = t }
    groups = ""; ng = 0
    for (k = 1; k <= nl; ++k) {
      list = ""
      for (i = 1; i <= nm; ++i) if (need[names[i]] == lobes[k]) list = list (list == "" ? "" : ", ") names[i]
      if (list == "") continue
      ++ng
      part[ng] = lobes[k] (ng == 1 ? " lobes" : "") " (" list ")"
    }
    for (g = 1; g <= ng; ++g) groups = groups (g == 1 ? "" : (g == ng ? " or " : ", ")) part[g]
    # Maps that no lobe count of the results brings within 1 %.
    list = ""
    for (i = 1; i <= nm; ++i) if (need[names[i]] == 0) list = list (list == "" ? "" : ", ") names[i]
    if (list != "") groups = groups ", and more than " lobes[nl] " (" list ")"
    printf "(c) has %.2g× to %.3g× lower max error than (a) on every map at every N (%d of %d cases; the target\n", lo, hi, ok, cases
    printf "was 2×). For a 1 %% budget on the lobe fit alone, (c) needs %s;\n", groups
    print "neither (a) nor (b) reaches 1 % within 24 lobes."
  }' "$envmaps" | fill docs/envmaps.md envmap-summary

# docs/references.md: the methods by source, every registry card as `sglab methods --format md`.
"$sglab" methods --format md | fill docs/references.md methods
