#!/usr/bin/env bash
# `syrof new` -> build -> `syrof run`, for the C and the C++ starter, from
# the build tree, in a fresh folder outside the source tree, the way a
# student runs them. Checks that each run reached its end with metrics.json,
# a replay and a log per robot, without faults or collisions, and that the
# source tree's `git status` is the same afterwards. Prints how long each
# took (a figure for the record, never a check).
#   new_project_test.sh SOURCE_DIR BIN_DIR
set -euo pipefail
source_dir=$1
bin_dir=$2
export PATH="$bin_dir:$PATH"

git_status() { git -C "$source_dir" status --porcelain --untracked-files=all 2>/dev/null || echo "(not a git tree)"; }
before=$(git_status)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for lang in c cpp; do
  name="starter_$lang"
  started=$(date +%s%N)
  (
    cd "$work"
    syrof new "$name" --lang "$lang" > /dev/null
    cd "$name"
    cmake -S . -B build > build.log 2>&1 && cmake --build build >> build.log 2>&1 || { cat build.log >&2; exit 1; }
    syrof run scenario.yaml --quiet
  )
  elapsed_ms=$(( ($(date +%s%N) - started) / 1000000 ))
  out="$work/$name/out/$name"
  metrics="$out/metrics.json"
  check() { grep -q -- "$2" "$metrics" || { echo "$lang: metrics.json lacks $1 ($2)" >&2; exit 1; }; }
  check "the whole 30 s" '"sim_seconds": 30'
  check "no faults" '"faults": \[\],'
  check "sandbox notes" '"sandbox": \['
  grep -A 1 '"collisions": {' "$metrics" | grep -q '"count": 0,' || { echo "$lang: collisions" >&2; exit 1; }
  for id in 0 7; do [ -s "$out/robots/$id.log" ] || { echo "no log for robot $id" >&2; exit 1; }; done
  [ -s "$out/replay" ] || { echo "no replay" >&2; exit 1; }
  echo "new_project_test: $lang: syrof new -> build -> run in ${elapsed_ms} ms"
done

after=$(git_status)
if [ "$before" != "$after" ]; then
  echo "the source tree changed:" >&2
  diff <(echo "$before") <(echo "$after") >&2 || true
  exit 1
fi
echo "new_project_test: the source tree is unchanged"
