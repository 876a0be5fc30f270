#!/usr/bin/env bash
# Every assignment's Gradescope bundle graded under Gradescope's default
# limits (half a CPU, 768 MB; docs/grading.md, "Gradescope's limits"): for
# each assignment, `syrof gradescope` writes the bundle, its scripts are laid
# out as /autograder in a temporary folder, and run_autograder grades the
# assignment's reference inside a control group with a CPU quota of half a
# core and a memory limit of 768 MB (cgroup v1 cpu and memory controllers
# where they are writable, else cgroup v2's cpu.max and memory.max). It
# prints a table of the wall time, the peak memory and the score, and fails
# (exit 1) when an assignment takes more than the budget (default 300 s,
# half Gradescope's default timeout of 10 minutes), is killed for memory,
# or its reference does not get full marks.
#
# Usage (as root): scripts/gradescope-limits.sh [--budget SECONDS] [BUILD_DIR] [ASSIGNMENT...]
# Needs BUILD_DIR/gradescope-prefix (make gradescope-prefix).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
budget_s=300
if [ "${1:-}" = --budget ]; then budget_s=$2; shift 2; fi
build=$(cd "${1:-$repo/build}" && pwd)
shift $(( $# > 0 ? 1 : 0 ))
assignments=("$@")
if [ ${#assignments[@]} -eq 0 ]; then
  for folder in "$repo"/assignments/*/; do assignments+=("$(basename "$folder")"); done
fi
[ "$(id -u)" -eq 0 ] || { echo "gradescope-limits: run as root (it makes control groups)" >&2; exit 2; }

readonly cpu_quota_us=50000 cpu_period_us=100000 memory_bytes=$((768 * 1024 * 1024))
name=syrof-gradescope-limits-$$
v1_cpu=/sys/fs/cgroup/cpu/$name
v1_memory=/sys/fs/cgroup/memory/$name
v2=/sys/fs/cgroup/$name
if [ -w /sys/fs/cgroup/cpu ] && [ -w /sys/fs/cgroup/memory ]; then
  mode=v1
  mkdir "$v1_cpu" "$v1_memory"
  echo $cpu_period_us > "$v1_cpu/cpu.cfs_period_us"
  echo $cpu_quota_us > "$v1_cpu/cpu.cfs_quota_us"
  echo $memory_bytes > "$v1_memory/memory.limit_in_bytes"
elif [ -f /sys/fs/cgroup/cgroup.controllers ] && grep -qw memory /sys/fs/cgroup/cgroup.controllers; then
  mode=v2
  mkdir "$v2"
  echo "$cpu_quota_us $cpu_period_us" > "$v2/cpu.max"
  echo $memory_bytes > "$v2/memory.max"
else
  echo "gradescope-limits: no writable cgroup v1 cpu and memory controllers, nor cgroup v2 with memory" >&2
  exit 2
fi
work=$(mktemp -d /tmp/syrof-gradescope-limits.XXXXXX)
cleanup() {
  rm -rf "$work"
  if [ $mode = v1 ]; then rmdir "$v1_cpu" "$v1_memory" 2>/dev/null || true; else rmdir "$v2" 2>/dev/null || true; fi
}
trap cleanup EXIT

# Runs the command inside the control group (a child shell moves itself in, then execs it).
limited() {
  if [ $mode = v1 ]; then
    bash -c 'echo $$ > "$1/cgroup.procs" && echo $$ > "$2/cgroup.procs" && shift 2 && exec "$@"' _ "$v1_cpu" "$v1_memory" "$@"
  else
    bash -c 'echo $$ > "$1/cgroup.procs" && shift && exec "$@"' _ "$v2" "$@"
  fi
}
reset_peak() { if [ $mode = v1 ]; then echo 0 > "$v1_memory/memory.max_usage_in_bytes"; fi; }
peak_bytes() {
  if [ $mode = v1 ]; then cat "$v1_memory/memory.max_usage_in_bytes"
  elif [ -f "$v2/memory.peak" ]; then cat "$v2/memory.peak"
  else echo 0; fi
}
oom_kills() {
  if [ $mode = v1 ]; then sed -n 's/^oom_kill //p' "$v1_memory/memory.oom_control"
  else sed -n 's/^oom_kill //p' "$v2/memory.events"; fi
}

echo "gradescope-limits: cgroup $mode, CPU quota ${cpu_quota_us}/${cpu_period_us} us (half a core), memory $((memory_bytes / 1048576)) MB, budget ${budget_s} s"
printf '%-16s %10s %12s %8s  %s\n' assignment "wall (s)" "peak (MB)" score verdict
status=0
for assignment in "${assignments[@]}"; do
  root="$work/$assignment"
  mkdir -p "$root/source" "$root/submission" "$root/results"
  "$build/bin/syrof" gradescope "$repo/assignments/$assignment" -o "$work/$assignment.zip" > /dev/null
  (cd "$root/source" && unzip -q "$work/$assignment.zip")
  cp -r "$repo/assignments/$assignment/reference/." "$root/submission/"
  rm -rf "$root/submission/build" "$root/submission/expected.yaml"
  AUTOGRADER_ROOT=$root SYROF_SKIP_INSTALL=1 "$root/source/setup.sh" > "$root/setup.log" 2>&1 ||
    { cat "$root/setup.log" >&2; exit 1; }
  reset_peak
  kills_before=$(oom_kills)
  started=$(date +%s.%N)
  AUTOGRADER_ROOT=$root limited "$root/source/run_autograder" > "$root/run.log" 2>&1 || true
  wall=$(awk -v a="$started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  peak_mb=$(( $(peak_bytes) / 1048576 ))
  score=$(sed -n 's/^ *"score": \([0-9.]*\),*$/\1/p' "$root/results/results.json" | head -n 1)
  verdict=ok
  if [ "$(oom_kills)" != "$kills_before" ]; then verdict="killed for memory"; status=1
  elif awk -v w="$wall" -v b="$budget_s" 'BEGIN { exit !(w > b) }'; then verdict="over the ${budget_s} s budget"; status=1
  elif [ "$(printf '%.2f' "${score:-0}")" != 100.00 ]; then verdict="the reference got ${score:-no score}"; status=1
  fi
  printf '%-16s %10.1f %12d %8s  %s\n' "$assignment" "$wall" "$peak_mb" "${score:-none}" "$verdict"
  [ "$verdict" = ok ] || tail -n 20 "$root/run.log" >&2
  rm -rf "$root"
done
exit $status
