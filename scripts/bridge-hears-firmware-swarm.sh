#!/usr/bin/env bash
# The base station against the emulated firmware swarm: runs
# syrof-firmware-swarm (ROBOTS qemu robots, SECONDS seconds) with
# --base-station, connects syrof-bridge to it with --socket, and checks what
# the bridge recorded, read back from its replay (DIR/bridge.json, "replay"):
# every robot heard, its epoch advancing, COOPERATIVE epochs in the run;
# each robot's epoch starts, and its COOPERATIVE ones, as the robot itself
# reported them on its console (the swarm's metrics.json,
# starts_by_robot and cooperative_starts_by_robot; one fewer allowed, for
# an epoch started just before the robot stopped and never beaconed);
# nothing rejected; and exactly the beacons the swarm sent it accepted
# (docs/bridge.md, "Tested with the emulated swarm"). Then a second swarm
# for the live page: the bridge serves it (--live on a free port), headless
# Chromium opens it while the swarm runs and takes LIVE_ROUNDS rounds
# (default 100: 5 s), and its report must show every robot RUNNING in the
# newest round. (A separate run: Chromium on 2 cores delays the qemu robots'
# beacons enough to cost them COOPERATIVE epochs.) A loaded machine can
# leave a robot without a COOPERATIVE start in a short run (its beacons
# late): the swarm says so too, and the bridge must agree, so that is not a
# failure. `make test-firmware-swarm` runs it.
#
#   bridge-hears-firmware-swarm.sh BUILD_DIR IMAGE OUT [ROBOTS] [SECONDS]
#
# Exit 0 when every check holds, 1 when one does not (it says which), 2 for a
# usage error or a missing program or image.
set -euo pipefail

if [[ $# -lt 3 || $# -gt 5 ]]; then
  echo "usage: $0 BUILD_DIR IMAGE OUT [ROBOTS] [SECONDS]" >&2
  exit 2
fi
build=$1 image=$2 out=$3 robots=${4:-4} seconds=${5:-8}
for program in "$build/bin/syrof-bridge" "$build/bin/syrof-firmware-swarm"; do
  [[ -x $program ]] || { echo "$0: $program is not built" >&2; exit 2; }
done
[[ -r $image ]] || { echo "$0: cannot read the robot image $image" >&2; exit 2; }
command -v jq >/dev/null || { echo "$0: needs jq" >&2; exit 2; }
chromium=$(command -v chromium || command -v chromium-browser || true)
[[ -n $chromium ]] || { echo "$0: needs chromium (the live page's check)" >&2; exit 2; }
live_rounds=${LIVE_ROUNDS:-100}
rm -rf "$out"
mkdir -p "$out"
socket="$out/base-station.sock"

"$build/bin/syrof-firmware-swarm" --image "$image" --robots "$robots" --seconds "$seconds" --out "$out/swarm" \
    --base-station "$socket" >"$out/swarm.txt" 2>&1 &
swarm=$!
bridge_status=0
"$build/bin/syrof-bridge" --socket "$socket" --robots "$robots" --no-dds --out "$out/bridge" \
    >"$out/bridge.txt" 2>&1 || bridge_status=$?
swarm_status=0
wait "$swarm" || swarm_status=$?
cat "$out/bridge.txt"
if [[ $swarm_status -ne 0 || $bridge_status -ne 0 ]]; then
  tail -n 20 "$out/swarm.txt" >&2
  echo "$0: syrof-firmware-swarm exited $swarm_status, syrof-bridge $bridge_status" >&2
  exit 1
fi

summary="$out/bridge/bridge.json"
sent=$(sed -nE 's/^syrof-firmware-swarm: base station: ([0-9]+) beacons sent.*/\1/p' "$out/swarm.txt")
failed=0
check() {  # check DESCRIPTION JQ-EXPRESSION: the expression must be true
  if [[ $(jq -r "$2" "$summary") != true ]]; then
    echo "$0: FAILED: $1" >&2
    failed=1
  fi
}
check "the replay reads back whole" '.replay.read_back'
check "the replay holds $robots robots" ".replay.robots | length == $robots"
check "every robot is heard in the replay" '[.replay.robots[] | .seen] | all'
check "every robot's epoch advances" '[.replay.robots[] | .last_epoch > .first_epoch] | all'
check "the replay has COOPERATIVE epochs" '[.replay.robots[] | .cooperative_starts] | add >= 1'
metrics="$out/swarm/metrics.json"
for robot in $(seq 0 $((robots - 1))); do
  own=$(jq -r ".common_knowledge.starts_by_robot[$robot]" "$metrics")
  own_cooperative=$(jq -r ".common_knowledge.cooperative_starts_by_robot[$robot]" "$metrics")
  check "robot $robot's epoch starts agree with its own report ($own, $own_cooperative COOPERATIVE)" \
      ".replay.robots[$robot] | ($own - .epoch_starts) as \$d | ($own_cooperative - .cooperative_starts) as \$c
       | \$d >= 0 and \$d <= 1 and \$c >= 0 and \$c <= 1"
done
check "nothing is rejected" '.rejected.total == 0 and .rejected.bytes_discarded == 0'
check "the bridge accepted every beacon the swarm sent it ($sent)" ".beacons_accepted == ${sent:-0} and ${sent:-0} > 0"
if [[ $failed -ne 0 ]]; then
  echo "$0: see $summary and $out/swarm.txt" >&2
  exit 1
fi
echo "$0: the bridge heard $sent beacons of $robots robots; every robot's epochs advance, and its epoch starts agree with the robots' own"

# The live page, in a browser, while a second swarm runs.
live="$out/live"
mkdir -p "$live"
"$build/bin/syrof-firmware-swarm" --image "$image" --robots "$robots" --seconds "$seconds" --out "$live/swarm" \
    --base-station "$live/base-station.sock" >"$live/swarm.txt" 2>&1 &
swarm=$!
"$build/bin/syrof-bridge" --socket "$live/base-station.sock" --robots "$robots" --no-dds --out "$live/bridge" \
    --live=127.0.0.1:0 --live-linger 0 >"$live/bridge.txt" 2>&1 &
bridge=$!
url=
for _ in $(seq 1 100); do
  url=$(sed -nE 's/^  live page: (http[^ ]+)$/\1/p' "$live/bridge.txt")
  [[ -n $url ]] && break
  sleep 0.1
done
chromium_status=0
if [[ -n $url ]]; then
  timeout 60 "$chromium" --headless --no-sandbox --disable-gpu --no-first-run --disable-extensions \
      --disable-dev-shm-usage --user-data-dir="$live/chromium-profile" --window-size=1280,1000 \
      --virtual-time-budget=30000 --dump-dom "${url}#live-until=rounds:$live_rounds" \
      >"$live/page.html" 2>/dev/null || chromium_status=$?
fi
bridge_status=0
wait "$bridge" || bridge_status=$?
swarm_status=0
wait "$swarm" || swarm_status=$?
if [[ -z $url || $swarm_status -ne 0 || $bridge_status -ne 0 || $chromium_status -ne 0 ]]; then
  tail -n 20 "$live/bridge.txt" "$live/swarm.txt" >&2
  echo "$0: live page run: live page ${url:-never announced}; syrof-firmware-swarm exited $swarm_status," \
       "syrof-bridge $bridge_status, chromium $chromium_status" >&2
  exit 1
fi
# The page's own report (viewer.js's <pre id="report">, HTML-escaped in the
# DOM dump): the rounds it took and, in the newest, each robot's position
# and presence (1: RUNNING).
sed -nE 's/.*<pre id="report"[^>]*>([^<]*)<\/pre>.*/\1/p' "$live/page.html" |
  sed -e 's/&quot;/"/g' -e 's/&lt;/</g' -e 's/&gt;/>/g' -e 's/&amp;/\&/g' >"$live/report.json"
summary="$live/report.json"
jq -e . "$summary" >/dev/null 2>&1 || { echo "$0: FAILED: the live page gave no report (see $live/page.html)" >&2; exit 1; }
check "the live page took $live_rounds rounds" ".live.rounds >= $live_rounds"
check "the live page shows all $robots robots RUNNING in its newest round" \
    ".live.positions | length == $robots and all(.[]; . != null and .[2] == 1)"
if [[ $failed -ne 0 ]]; then
  echo "$0: see $summary" >&2
  exit 1
fi
echo "$0: the live page, served by the bridge, showed all $robots robots running after $live_rounds rounds"
