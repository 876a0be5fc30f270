#!/usr/bin/env bash
# The promise that the lab and the robot's real firmware give the same
# answers, checked: runs SCENARIO in the lab (`syrof run`) and on the
# emulated firmware swarm (`syrof-firmware-swarm --realtime`, one qemu per
# robot), then `syrof compare`s them: the same epochs, started in the same
# rounds and modes, with the same members (docs/firmware.md, "One start for
# every robot"). `make test-firmware-swarm` runs it on
# lab/scenarios/four_runtimes.yaml (loss, a join, a pause, a crash) and on
# its SSYNC and ASYNC variants in tests/sim_dds/scenarios. Under those the
# firmware run's own checks include that each robot looked exactly at the
# epoch starts its schedule says (the epochs alone would agree with an
# image that ignored its schedule).
#
#   firmware-agrees-with-lab.sh BUILD_DIR IMAGE SCENARIO OUT
#
# LAB_APP=LIB runs the lab with `--app LIB` (a student's library; the image
# must be built with the same C file, SYROF_FIRMWARE_APP), and
# POSE_TOLERANCE_M=M also compares every robot's true position round by
# round (`syrof compare --pose-tolerance-m M`): the epochs alone agree
# whatever the app does. PAYLOADS=1 also compares the apps' payloads in
# every map a robot started an epoch with (`syrof compare --payloads`): the
# state the apps share, epoch by epoch. FIRMWARE_SECONDS=S runs the firmware swarm S
# seconds (--seconds; without it, the swarm's default 20 s): the scenario's
# duration, for a scenario shorter than that.
#
# The emulated robots run in real time on a shared machine: a guest held
# back tens of milliseconds sends or hears a beacon a round late, and one
# such beacon can change an epoch's mode (docs/firmware.md, "What made
# them disagree, and the fixes"). So a run that disagrees gets another
# try, after printing what it showed, and so does a run whose own checks
# failed; five such runs fail (exit 1). Exit 2 for a usage error, or when
# the lab run could not be made.
set -euo pipefail

if [[ $# -ne 4 ]]; then
  echo "usage: $0 BUILD_DIR IMAGE SCENARIO OUT" >&2
  exit 2
fi
build=$1 image=$2 scenario=$3 out=$4
for program in "$build/bin/syrof" "$build/bin/syrof-firmware-swarm"; do
  [[ -x $program ]] || { echo "$0: $program is not built" >&2; exit 2; }
done
[[ -r $image ]] || { echo "$0: cannot read the robot image $image" >&2; exit 2; }
mkdir -p "$out"

lab_app=()
[[ -n ${LAB_APP:-} ]] && lab_app=(--app "$LAB_APP")
compare_poses=()
[[ -n ${POSE_TOLERANCE_M:-} ]] && compare_poses=(--pose-tolerance-m "$POSE_TOLERANCE_M")
[[ ${PAYLOADS:-0} == 1 ]] && compare_poses+=(--payloads)
firmware_seconds=()
[[ -n ${FIRMWARE_SECONDS:-} ]] && firmware_seconds=(--seconds "$FIRMWARE_SECONDS")
if ! "$build/bin/syrof" run "$scenario" "${lab_app[@]}" --out "$out/lab" >"$out/lab.txt" 2>&1; then
  cat "$out/lab.txt" >&2
  echo "$0: the lab run of $scenario failed" >&2
  exit 2
fi
tries=5
for try in $(seq 1 $tries); do
  rm -rf "$out/firmware"
  status=0
  "$build/bin/syrof-firmware-swarm" --image "$image" --scenario "$scenario" --out "$out/firmware" \
      "${firmware_seconds[@]}" --realtime >"$out/firmware-$try.txt" 2>&1 || status=$?
  if [[ $status -eq 2 ]]; then  # a usage error: no try can do better
    cat "$out/firmware-$try.txt" >&2
    echo "$0: the firmware swarm refused its arguments" >&2
    exit 2
  fi
  grep -E "^  beacons offered" "$out/firmware-$try.txt" || true
  if [[ $status -ne 0 ]]; then
    # One of the run's own checks failed (a console line cut, an instance
    # that did not run to its end): a run the comparison cannot trust, so
    # it is a failed try.
    grep -E "console, column|FAILED|never|deadline" "$out/firmware-$try.txt" >&2 || true
    echo "$0: the firmware run's own checks failed (above)" >&2
  elif "$build/bin/syrof" compare "$out/lab" "$out/firmware" "${compare_poses[@]}"; then
    echo "$0: agreed on try $try of $tries"
    exit 0
  fi
  if [[ $try -lt $tries ]]; then
    echo "$0: the firmware run disagreed with the lab (above); another try" >&2
  fi
done
echo "$0: $tries firmware runs of $scenario disagreed with the lab or failed their own checks" >&2
exit 1
