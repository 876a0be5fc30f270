#!/usr/bin/env bash
# The Gradescope bundle on a machine that has none of SyROF's libraries
# (docs/grading.md, "Publishing to Gradescope"): a Debian 12 minbase root
# (debootstrap) with a compiler, CMake and make and nothing else of what
# SyROF's build installs, laid out as Gradescope lays out /autograder. For
# each assignment named (default: gather strongest leader_follow), the
# bundle `syrof gradescope` writes is unzipped into /autograder/source,
# setup.sh runs, then run_autograder grades the reference (it must get full
# marks) and a broken variant (it must get its expected.yaml's points), each
# as the root's own processes: the root is entered with pivot_root in fresh
# mount and PID namespaces (not chroot, under which the grader's sandbox
# could not make its user namespace), with /proc, /dev and a /tmp of its own.
#
# Usage (as root): scripts/test-gradescope-bundle.sh [--root DIR] [BUILD_DIR] [ASSIGNMENT...]
#   --root DIR  a minbase root made before (debootstrap --variant=minbase
#               --include=gcc,g++,cmake,make,libc6-dev bookworm DIR); else
#               one is made in a temporary folder (about 3 minutes, from the
#               Debian mirror) and removed at the end.
# Needs BUILD_DIR/gradescope-prefix (make gradescope-prefix).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
jail=""
if [ "${1:-}" = --root ]; then jail=$(cd "$2" && pwd); shift 2; fi
build=$(cd "${1:-$repo/build}" && pwd)
shift $(( $# > 0 ? 1 : 0 ))
assignments=("$@")
[ ${#assignments[@]} -gt 0 ] || assignments=(gather strongest leader_follow)
[ "$(id -u)" -eq 0 ] || { echo "test-gradescope-bundle: run as root" >&2; exit 2; }
[ -f "$build/gradescope-prefix/gradescope-prefix.txt" ] ||
  { echo "test-gradescope-bundle: no $build/gradescope-prefix: make gradescope-prefix" >&2; exit 2; }

work=$(mktemp -d /tmp/syrof-gradescope.XXXXXX)
cleanup() { rm -rf "$work"; }
trap cleanup EXIT
if [ -z "$jail" ]; then
  jail="$work/root"
  echo "test-gradescope-bundle: debootstrap of a Debian 12 minbase root with gcc, g++, cmake, make"
  debootstrap --variant=minbase --include=gcc,g++,cmake,make,libc6-dev bookworm "$jail" http://deb.debian.org/debian \
    > "$work/debootstrap.log" 2>&1 || { tail -20 "$work/debootstrap.log" >&2; exit 1; }
fi
# (libseccomp2 is in every Debian and Ubuntu base: apt links it.)
for library in libyaml-cpp0.7 libfmt9 libzip4 cyclonedds libddsc0debian libcpp-httplib0.11; do
  if chroot "$jail" dpkg-query -W -f='${Status}' "$library" 2>/dev/null | grep -q 'install ok installed'; then
    echo "test-gradescope-bundle: $jail has $library installed: not a machine without SyROF's libraries" >&2
    exit 1
  fi
done

# Runs a bash command as the root's own process (see the top).
in_root() {
  unshare --mount --pid --fork bash -c '
    set -e
    jail=$1; shift
    mount --make-rprivate /
    mount --bind "$jail" "$jail"
    mount -t proc proc "$jail/proc"
    mount --rbind /dev "$jail/dev"
    mount -t tmpfs tmpfs "$jail/tmp"
    cd "$jail"
    mkdir -p .old
    pivot_root . .old
    umount -l /.old
    rmdir /.old
    exec env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 bash -c "$1"
  ' _ "$jail" "$1"
}

# Grades SUBMISSION_DIR with NAME's bundle in the root; prints the score.
grade_in_root() {
  local name=$1 submission=$2
  rm -rf "$jail/autograder"
  mkdir -p "$jail/autograder/source" "$jail/autograder/submission" "$jail/autograder/results"
  (cd "$jail/autograder/source" && unzip -q "$work/$name.zip")
  cp -r "$submission/." "$jail/autograder/submission/"
  rm -rf "$jail/autograder/submission/build" "$jail/autograder/submission/expected.yaml"
  in_root "cd /autograder && SYROF_SKIP_INSTALL=1 source/setup.sh && source/run_autograder" > "$work/$name.log" 2>&1 ||
    { cat "$work/$name.log" >&2; echo "test-gradescope-bundle: $name: setup.sh or run_autograder failed" >&2; return 1; }
  sed -n 's/^ *"score": \([0-9.]*\),*$/\1/p' "$jail/autograder/results/results.json" | head -n 1
}

# The points an expected.yaml gives (its `points:` line).
expected_points() { sed -n 's/^points: *\([0-9.]*\).*/\1/p' "$1"; }

status=0
for name in "${assignments[@]}"; do
  "$build/bin/syrof" gradescope "$repo/assignments/$name" -o "$work/$name.zip" > /dev/null
  started=$(date +%s)
  score=$(grade_in_root "$name" "$repo/assignments/$name/reference") || { status=1; continue; }
  reference_seconds=$(( $(date +%s) - started ))
  if [ "$(printf '%.2f' "$score")" != 100.00 ]; then
    echo "test-gradescope-bundle: $name: the reference got $score, not 100"; status=1
  else
    echo "test-gradescope-bundle: $name: the reference got 100 (${reference_seconds} s)"
  fi
  variant=$(ls "$repo/assignments/$name/broken" | head -n 1)
  bash "$repo/scripts/broken-variant.sh" "$name" "$variant" "$work/$name-$variant" > /dev/null
  want=$(expected_points "$repo/assignments/$name/broken/$variant/expected.yaml")
  score=$(grade_in_root "$name" "$work/$name-$variant") || { status=1; continue; }
  if [ "$(printf '%.2f' "$score")" != "$(printf '%.2f' "$want")" ]; then
    echo "test-gradescope-bundle: $name: broken/$variant got $score, not its expected $want"; status=1
  else
    echo "test-gradescope-bundle: $name: broken/$variant got its expected $score"
  fi
done
[ $status -eq 0 ] && echo "test-gradescope-bundle: passed (${assignments[*]})"
exit $status
