#!/usr/bin/env bash
# Runs the Fast DDS reader against the Cyclone writer of real beacons on a
# domain of this test's own and passes when the reader saw every sender and
# only valid beacons. Usage: run_interop.sh READER WRITER ROBOTS [garbage]
# With "garbage" the writer adds invalid samples and the test passes only
# when the reader reports them as invalid (its checks can fail).
set -euo pipefail
reader=$1
writer=$2
robots=$3
mode=${4:-valid}
# A domain of its own (1 .. 231) from this shell's pid, so parallel runs of
# the suite do not meet.
domain=$(( 1 + $$ % 231 ))
out=$(mktemp)
trap 'rm -f "$out"' EXIT

"$reader" --domain "$domain" --swarm "$robots" --min-per-sender 20 --seconds 30 >"$out" 2>&1 &
reader_pid=$!
garbage=0
[ "$mode" = garbage ] && garbage=1
"$writer" --domain "$domain" --robots "$robots" --seconds 40 --garbage "$garbage" >/dev/null 2>&1 &
writer_pid=$!
status=0
wait "$reader_pid" || status=$?
kill "$writer_pid" 2>/dev/null || true
wait "$writer_pid" 2>/dev/null || true
cat "$out"
if [ "$mode" = garbage ]; then
  grep -q "INVALID beacons" "$out" && grep -q "first problem: wrong version" "$out"
  exit $?
fi
exit "$status"
