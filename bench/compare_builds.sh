#!/bin/bash
# bench/compare_builds.sh: the simulated lab's speed, this tree against
# another commit, side by side, so that a regression shows as a ratio.
#
#   bench/compare_builds.sh COMMIT [--rounds R] [--case ROBOTSxSECONDS]...
#                                  [--scenario FILE] [--this BIN]
#
# Builds COMMIT's `syrof` (Release, only that target, warnings not errors)
# in a git worktree under build-against/, then runs one scenario with the
# two binaries in turn, R times each (default 3), alternating, so that the
# machine's other load falls on both alike. Each run is `syrof run SCENARIO --app
# builtin:idle --robots N --duration S --seed 1` timed in CPU seconds (user +
# system of the run, from bash's `times`); its figure is robot-seconds per
# CPU-second, N x S / CPU. Prints every run, the best of each side and the
# ratio this / COMMIT (above 1: this tree is faster).
#
# Defaults: bench_lab_throughput's standard scenario, written for each case
# (robots on a 1 m grid, the arena one spacing wider and at most 32 m, its
# anchors at the corners, 50 ms rounds, 5% i.i.d. loss: 11 m for 100
# robots), and two cases: 100 robots for 60 s (the platform's own cost
# per robot) and 1000 robots for 3 s (where the per-beacon work dominates). --scenario FILE runs that file instead, with --robots as the
# case says. --this: the binary to compare (default build/bin/syrof; build
# it Release first). Both binaries read the same scenario file; a commit
# whose parser refuses it needs another --scenario. Deterministic runs: the
# same bytes each time, so the figures differ only by timing.
set -euo pipefail

usage() {
  sed -n '5,6p' "$0" | sed 's/^# \{0,3\}//' >&2
  exit 2
}

[ $# -ge 1 ] || usage
commit=$1
shift
rounds=3
cases=()
root=$(git rev-parse --show-toplevel)
scenario=
this="$root/build/bin/syrof"
while [ $# -gt 0 ]; do
  case $1 in
    --rounds | --case | --scenario | --this)
      [ $# -ge 2 ] || { echo "compare_builds.sh: $1 needs a value" >&2; usage; } ;;&
    --rounds) rounds=$2; shift 2 ;;
    --case) cases+=("$2"); shift 2 ;;
    --scenario) scenario=$(realpath "$2"); shift 2 ;;
    --this) this=$(realpath "$2"); shift 2 ;;
    *) echo "compare_builds.sh: unknown option '$1'" >&2; usage ;;
  esac
done
[ ${#cases[@]} -gt 0 ] || cases=(100x60 1000x3)
for c in "${cases[@]}"; do
  [[ $c =~ ^[0-9]+x[0-9.]+$ ]] || { echo "compare_builds.sh: --case '$c': expected ROBOTSxSECONDS, e.g. 100x60" >&2; exit 2; }
done
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "compare_builds.sh: --rounds '$rounds': expected a positive count" >&2; exit 2; }
[ -x "$this" ] || { echo "compare_builds.sh: $this: no such binary (build this tree first: cmake --build build --target syrof)" >&2; exit 2; }
[ -z "$scenario" ] || [ -f "$scenario" ] || { echo "compare_builds.sh: $scenario: no such scenario file" >&2; exit 2; }
sha=$(git -C "$root" rev-parse --verify --quiet "$commit^{commit}") ||
  { echo "compare_builds.sh: '$commit' names no commit of $root" >&2; exit 2; }
short=${sha:0:9}

# The other build: a worktree per commit, kept for the next comparison.
tree="$root/build-against/$short"
if [ ! -d "$tree" ]; then
  mkdir -p "$root/build-against"
  git -C "$root" worktree add --quiet --detach "$tree" "$sha"
fi
other="$tree/build/bin/syrof"
if [ ! -x "$other" ]; then
  echo "building $short's syrof in $tree/build (Release, this target only)..." >&2
  launcher=()
  if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
  generator=()
  if command -v ninja >/dev/null; then generator=(-G Ninja); fi
  # Warnings are not errors there: an older tree may trip a newer compiler's
  # false positive (5d653b8 and GCC 12's -Wrestrict).
  cmake -S "$tree" -B "$tree/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSYROF_WERROR=OFF "${launcher[@]}" \
    >"$tree/configure.log" 2>&1 ||
    { echo "compare_builds.sh: configuring $short failed; see $tree/configure.log" >&2; exit 1; }
  cmake --build "$tree/build" --target syrof -j "$(nproc)" >"$tree/build.log" 2>&1 ||
    { echo "compare_builds.sh: building $short failed; see $tree/build.log" >&2; exit 1; }
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# bench_lab_throughput's standard scenario for `robots` robots.
write_standard() {
  local robots=$1 file=$2
  awk -v n="$robots" 'BEGIN {
    side = int(sqrt(n)); if (side * side < n) side++
    arena = side + 1; if (arena > 32) arena = 32
    spacing = arena / (side + 1)
    printf "name: standard_%d\nseed: 1\narena:\n  width_m: %g\n  height_m: %g\n", n, arena, arena
    printf "  anchors:\n    - {x_m: 0, y_m: 0, z_m: 0}\n    - {x_m: %g, y_m: %g, z_m: 0}\n", arena, arena
    printf "    - {x_m: 0, y_m: %g, z_m: 2}\n    - {x_m: %g, y_m: 0, z_m: 2}\n", arena, arena
    printf "robots:\n  count: %d\n  placement: grid\n  spacing_m: %.9g\n", n, spacing
    printf "timing: { radio_round_s: 0.05, app_round_s: 1.0, duration_s: 1 }\n"
    printf "channel: { model: iid, loss: 0.05 }\napp: builtin:idle\n"
  }' >"$file"
}

# One run: prints its CPU seconds (user + system of the child).
cpu_of_run() {
  local binary=$1 robots=$2 seconds=$3 file=$4
  local before after
  # `times` straight into a file: in a pipe it would run in a subshell that
  # has no children.
  times >"$out/times"
  before=$(tail -1 "$out/times")
  if ! "$binary" run "$file" --app builtin:idle --robots "$robots" --duration "$seconds" --seed 1 \
      --out "$out/run" --no-replay --quiet >"$out/stdout" 2>"$out/stderr"; then
    echo "compare_builds.sh: $binary refused the run:" >&2
    cat "$out/stderr" >&2
    exit 1
  fi
  times >"$out/times"
  after=$(tail -1 "$out/times")
  # `times` prints the children's user and system time, as 0m1.234s each.
  awk -v b="$before" -v a="$after" 'function s(t,  m) { split(t, m, /[ms]/); return m[1] * 60 + m[2] }
    BEGIN { split(b, x, " "); split(a, y, " "); printf "%.3f\n", s(y[1]) + s(y[2]) - s(x[1]) - s(x[2]) }'
}

echo "lab throughput, robot-seconds per CPU-second: this tree ($this) against $short"
described=${scenario:-"the standard scenario of bench_lab_throughput, written per case"}
echo "scenario $described, builtin:idle, seed 1, $rounds rounds alternating"
printf '\n%-14s %-8s %10s %14s\n' "case" "build" "CPU s" "robot-s/CPU-s"
for c in "${cases[@]}"; do
  robots=${c%x*}
  seconds=${c#*x}
  file=$scenario
  if [ -z "$file" ]; then
    file="$out/standard_$robots.yaml"
    write_standard "$robots" "$file"
  fi
  best_this=0
  best_other=0
  for ((round = 1; round <= rounds; ++round)); do
    for side in this other; do
      if [ $side = this ]; then binary=$this; else binary=$other; fi
      cpu=$(cpu_of_run "$binary" "$robots" "$seconds" "$file")
      rate=$(awk -v n="$robots" -v s="$seconds" -v c="$cpu" 'BEGIN { printf "%.0f", (c > 0) ? n * s / c : 0 }')
      label=$side
      [ $side = other ] && label=$short
      printf '%-14s %-8s %10s %14s\n' "$c" "${label:0:8}" "$cpu" "$rate"
      if [ $side = this ]; then
        [ "$rate" -gt "$best_this" ] && best_this=$rate
      else
        [ "$rate" -gt "$best_other" ] && best_other=$rate
      fi
    done
  done
  ratio=$(awk -v a="$best_this" -v b="$best_other" 'BEGIN { printf "%.2f", (b > 0) ? a / b : 0 }')
  printf '%-14s best: this %s, %s %s: ratio %sx\n\n' "$c" "$best_this" "$short" "$best_other" "$ratio"
done
