#!/usr/bin/env bash
# Runs the Fast DDS reader against Cyclone writers of real beacons on a
# domain of this test's own. Usage: run_interop.sh READER WRITER ROBOTS MODE
#   one        one writer process with ROBOTS radios; passes when the reader
#              saw every sender and only valid beacons
#   processes  ROBOTS writer processes of one radio each, on a shared round
#              grid; passes likewise (also prints the writers' own counters)
#   garbage    one writer process that adds invalid samples; passes only when
#              the reader reports them invalid (its checks can fail)
#   shared     as "one", beside a writer of another run with twice the robots
#              on the same domain (what a test running beside this one does
#              when it lands on this domain); passes when the reader heard
#              the other run, left it alone and judged its own run as in "one"
set -euo pipefail
reader=$1
writer=$2
robots=$3
mode=$4
# A domain of its own (1 .. 231) from this shell's pid, so parallel runs of
# the suite do not meet, and a run id of its own: a DDS test running beside
# it may still land on this domain (docs/dds.md, "Domain ids"), and the
# reader judges only this run's beacons, as a robot does.
domain=$(( 1 + $$ % 231 ))
run_id=$(( 1000 + $$ ))
dir=$(mktemp -d)
writer_pids=()
cleanup() {
  for pid in "${writer_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${writer_pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$dir"
}
trap cleanup EXIT

reader_extra=()
[ "$mode" = shared ] && reader_extra=(--min-foreign 1)

"$reader" --domain "$domain" --swarm "$robots" --min-per-sender 20 --seconds 40 --run-id "$run_id" \
  "${reader_extra[@]}" >"$dir/reader" 2>&1 &
reader_pid=$!
case "$mode" in
  one|garbage|shared)
    garbage=0
    [ "$mode" = garbage ] && garbage=1
    "$writer" --domain "$domain" --robots "$robots" --seconds 60 --garbage "$garbage" --run-id "$run_id" \
      >"$dir/writer0" 2>&1 &
    writer_pids+=($!)
    if [ "$mode" = shared ]; then
      # Robot ids past this run's swarm: judged as this run's beacons they
      # would be invalid ("robot id out of range").
      "$writer" --domain "$domain" --robots $(( 2 * robots )) --seconds 60 --run-id $(( run_id + 1 )) \
        >"$dir/other-run" 2>&1 &
      writer_pids+=($!)
    fi
    ;;
  processes)
    # Round 0 a second from now on CLOCK_REALTIME, for every process.
    origin=$(( $(date +%s%3N) + 1000 ))
    for ((i = 0; i < robots; ++i)); do
      "$writer" --domain "$domain" --robots "$robots" --only "$i" --seconds 60 --origin-ms "$origin" --run-id "$run_id" \
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
