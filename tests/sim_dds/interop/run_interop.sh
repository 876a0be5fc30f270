#!/usr/bin/env bash
# Runs the Fast DDS reader against Cyclone writers of real beacons on a
# domain of this test's own. Usage: run_interop.sh READER WRITER ROBOTS MODE
#   one        one writer process with ROBOTS radios; passes when the reader
#              saw every sender and only valid beacons
#   processes  ROBOTS writer processes of one radio each, on a shared round
#              grid; passes likewise (also prints the writers' own counters)
#   garbage    one writer process that adds invalid samples; passes only when
#              the reader reports them invalid (its checks can fail)
set -euo pipefail
reader=$1
writer=$2
robots=$3
mode=$4
# A domain of its own (1 .. 231) from this shell's pid, so parallel runs of
# the suite do not meet.
domain=$(( 1 + $$ % 231 ))
dir=$(mktemp -d)
writer_pids=()
cleanup() {
  for pid in "${writer_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${writer_pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$dir"
}
trap cleanup EXIT

"$reader" --domain "$domain" --swarm "$robots" --min-per-sender 20 --seconds 40 >"$dir/reader" 2>&1 &
reader_pid=$!
case "$mode" in
  one|garbage)
    garbage=0
    [ "$mode" = garbage ] && garbage=1
    "$writer" --domain "$domain" --robots "$robots" --seconds 60 --garbage "$garbage" >"$dir/writer0" 2>&1 &
    writer_pids+=($!)
    ;;
  processes)
    # Round 0 a second from now on CLOCK_REALTIME, for every process.
    origin=$(( $(date +%s%3N) + 1000 ))
    for ((i = 0; i < robots; ++i)); do
      "$writer" --domain "$domain" --robots "$robots" --only "$i" --seconds 60 --origin-ms "$origin" \
        >"$dir/writer$i" 2>&1 &
      writer_pids+=($!)
    done
    ;;
  *)
    echo "run_interop.sh: unknown mode $mode" >&2
    exit 2
    ;;
esac
status=0
wait "$reader_pid" || status=$?
cat "$dir/reader"
if [ "$mode" = garbage ]; then
  grep -q "INVALID beacons" "$dir/reader" && grep -q "first problem: wrong version" "$dir/reader"
  exit $?
fi
exit "$status"
