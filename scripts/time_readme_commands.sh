#!/usr/bin/env bash
# scripts/time_readme_commands.sh: times README's two commands as a newcomer
# runs them, and writes data/results/job_times.md, which README's stated times
# quote (tests/test_readme_numbers.cpp checks them against it). A fresh clone
# of this checkout's HEAD (commit first) into a temporary folder, then, there:
# scripts/test.sh (packages, configure, build, every test), then
# scripts/run.sh (the build of the sglab command, here already done, the κ = 4
# table and the main job `sglab run`, whose own step times are recorded).
# Without ccache (CCACHE_DISABLE=1), so that the build is a cold one. The load
# average before and after each command says what else ran; measure on an
# otherwise idle machine. Packages already installed make scripts/deps.sh's
# part a fraction of a second (its time is recorded); on a fresh machine its
# apt-get comes on top.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out="$root/data/results/job_times.md"
work=$(mktemp -d "${TMPDIR:-/tmp}/sglab-time.XXXXXX")
trap 'rm -rf "$work"' EXIT
git clone -q "$root" "$work/sglab"
commit=$(git -C "$work/sglab" rev-parse --short HEAD)
export CCACHE_DISABLE=1

load() { cut -d' ' -f1 /proc/loadavg; }
# timed NAME COMMAND...: runs COMMAND in the clone (output into NAME.log),
# recording wall and CPU seconds and the load before and after.
timed() {
  local name=$1
  shift
  local before
  before=$(load)
  (cd "$work/sglab" && /usr/bin/time -f '%e %U %S' -o "$work/$name.time" "$@") >"$work/$name.log" 2>&1 ||
    { echo "time_readme_commands: $* failed (see $work/$name.log)" >&2; tail -20 "$work/$name.log" >&2; trap - EXIT; exit 1; }
  read -r wall user sys <"$work/$name.time"
  printf -v "${name}_wall" '%s' "$wall"
  printf -v "${name}_cpu" '%s' "$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')"
  printf -v "${name}_before" '%s' "$before"
  printf -v "${name}_after" '%s' "$(load)"
}
# minutes SECONDS: "7 min 12 s" (rounded to the second).
minutes() { awk -v t="$1" 'BEGIN { s = int(t + 0.5); printf "%d min %d s", int(s / 60), s % 60 }'; }

timed deps scripts/deps.sh
timed test scripts/test.sh
timed run scripts/run.sh
main_total=$(sed -n 's/^total \([0-9.]*\) s; wrote .*/\1/p' "$work/run.log")
[ -n "$main_total" ] || { echo "time_readme_commands: no total in the output of sglab run" >&2; exit 1; }
tests=$(sed -n 's/.*tests passed, [0-9]* tests failed out of \([0-9]*\)/\1/p' "$work/test.log")

{
  echo "# Time of README's two commands"
  echo
  echo "Measured by \`scripts/time_readme_commands.sh\` on $(date -u '+%Y-%m-%d %H:%M') UTC, commit $commit,"
  echo "from a fresh clone, without ccache, on $(nproc) cores ($(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)),"
  echo "$(free -g | awk '/^Mem:/ {print $2}') GiB of memory. Load: the 1-minute load average before and after each command"
  echo "(the command itself adds up to $(nproc)). The packages were already installed: on a fresh machine"
  echo "scripts/deps.sh's apt-get comes on top of scripts/test.sh's time."
  echo
  echo "| command | wall | wall s | CPU s (user + sys) | load before | load after |"
  echo "|---|---|---|---|---|---|"
  echo "| scripts/test.sh ($tests tests) | $(minutes "$test_wall") | $test_wall | $test_cpu | $test_before | $test_after |"
  echo "| scripts/deps.sh alone (packages present) | $(minutes "$deps_wall") | $deps_wall | $deps_cpu | $deps_before | $deps_after |"
  echo "| scripts/run.sh (after scripts/test.sh) | $(minutes "$run_wall") | $run_wall | $run_cpu | $run_before | $run_after |"
  echo "| main job \`sglab run\` (in scripts/run.sh) | $(minutes "$main_total") | $main_total | | | |"
  echo
  echo "The main job's steps (\`sglab run\`'s own timing, each in the form out/index.md names):"
  echo
  echo "| step | s |"
  echo "|---|---|"
  sed -n 's/^\([a-z-]*\) *\([0-9.]*\) s  ok$/| \1 | \2 |/p' "$work/run.log"
} >"$out.tmp"
mv "$out.tmp" "$out"

# README's block job-times: the three wall times, quoted from the file above.
begin="<!-- generated: job-times (scripts/time_readme_commands.sh) -->" end="<!-- end: job-times -->"
grep -qF -- "$begin" README.md && grep -qF -- "$end" README.md ||
  { echo "time_readme_commands: README.md has no block job-times" >&2; exit 1; }
line="Measured on $(nproc) cores ([data/results/job_times.md](data/results/job_times.md), load $test_before before)"
line+=": \`scripts/test.sh\` $(minutes "$test_wall") from a fresh clone with the packages installed,"
line+=" \`scripts/run.sh\` after it $(minutes "$run_wall"), of which the main job \`sglab run\` $(minutes "$main_total")."
awk -v begin="$begin" -v end="$end" -v body="$line" '
  $0 == begin { print; print body; skip = 1; next }
  $0 == end { skip = 0 }
  !skip { print }' README.md >README.md.tmp
mv README.md.tmp README.md
echo "time_readme_commands: wrote $out and README.md's block job-times"
