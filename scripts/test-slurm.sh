#!/usr/bin/env bash
# make test-slurm: a class graded as a Slurm job array on this machine, with
# the job script and the submit commands that docs/grading.md shows
# ("Spreading a class over machines", the blocks marked `test-slurm`),
# extracted from the doc, so the doc and this test cannot drift.
#
# It starts munged, slurmctld and slurmd from Debian's packages (munge,
# slurmctld, slurmd, slurm-client) with a private configuration in a
# temporary folder: its own munge key and socket, ports 16817/16818, one
# node (this machine) in one partition. Nothing is written to /etc, and
# every daemon it started is stopped when it ends, whatever happens.
#
# Then, in a course folder (a copy of assignments/gather and five students:
# the reference, the starter, two broken variants and one that does not
# compile):
#   1. the class is graded on one machine (`syrof grade --class`): the bytes
#      to match;
#   2. the doc's job array is submitted with 3 shards; shard 1 is cancelled
#      (`scancel`) once it has graded its first student;
#   3. the cancelled shard is submitted again (it must resume: "resumed 1"),
#      and the doc's merge job runs after it (`--dependency=afterok`);
#   4. the merged class.csv and summary.txt must be the one machine's bytes.
#
# Usage: scripts/test-slurm.sh [BUILD_DIR]   (as root; default build/)
# KEEP=1 keeps the temporary folder and prints where it is.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
[ -x "$build/bin/syrof" ] || { echo "test-slurm: no $build/bin/syrof: build first (make build)" >&2; exit 2; }
[ "$(id -u)" -eq 0 ] || { echo "test-slurm: run as root (it starts munged, slurmctld and slurmd)" >&2; exit 2; }
for program in munged slurmctld slurmd sbatch squeue scancel sinfo; do
  command -v "$program" >/dev/null || [ -x "/usr/sbin/$program" ] ||
    { echo "test-slurm: $program is missing: bash scripts/install-deps.sh slurm" >&2; exit 2; }
done

work=$(mktemp -d /tmp/syrof-slurm.XXXXXX)
chmod 755 "$work"
daemons=()
cleanup() {
  local status=$?
  if [ -n "${SLURM_CONF:-}" ]; then scancel --quiet --user=root >/dev/null 2>&1 || true; fi
  for pid_file in "${daemons[@]}"; do
    [ -f "$pid_file" ] && kill "$(cat "$pid_file")" 2>/dev/null || true
  done
  sleep 1
  for pid_file in "${daemons[@]}"; do
    [ -f "$pid_file" ] && kill -9 "$(cat "$pid_file")" 2>/dev/null || true
  done
  if [ $status -ne 0 ]; then
    echo "test-slurm: FAILED; the daemons' logs:" >&2
    tail -n 20 "$work"/log/*.log >&2 2>/dev/null || true
  fi
  if [ "${KEEP:-0}" = 1 ]; then echo "test-slurm: kept $work"; else rm -rf "$work"; fi
  exit $status
}
trap cleanup EXIT INT TERM
fail() { echo "test-slurm: FAILED: $*" >&2; exit 1; }

# Waits until COMMAND succeeds, at most SECONDS; fails naming WHAT otherwise.
wait_for() {
  local seconds=$1 what=$2; shift 2
  local deadline=$(( $(date +%s) + seconds ))
  until "$@"; do
    [ "$(date +%s)" -lt "$deadline" ] || fail "$what (waited ${seconds}s)"
    sleep 0.2
  done
}

# --- the doc's blocks ---------------------------------------------------------
# The fenced block after the line `<!-- test-slurm: NAME -->` in
# docs/grading.md, with the doc's 8 shards made 3 (the only change).
doc_block() {
  awk -v name="$1" '
    $0 == "<!-- test-slurm: " name " -->" { marked = 1; next }
    marked && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }
  ' "$root/docs/grading.md" | sed -e 's/--array=1-8/--array=1-3/' -e 's/shards=8/shards=3/' -e 's/-of-8/-of-3/g'
}
for block in grade.sh submit resubmit; do
  doc_block "$block" > "$work/$block"
  [ -s "$work/$block" ] || fail "docs/grading.md has no block marked <!-- test-slurm: $block -->"
done
grep -q -- '--array=1-3' "$work/grade.sh" || fail "the doc's grade.sh has no '#SBATCH --array=1-8' line"

# --- munge and Slurm, private to this run ---------------------------------------
mkdir -p "$work/log" "$work/state" "$work/spool"
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
chmod 600 "$work/munge.key"
/usr/sbin/munged --force --socket="$work/munge.sock" --key-file="$work/munge.key" \
  --log-file="$work/log/munged.log" --pid-file="$work/munged.pid" --seed-file="$work/munged.seed"
daemons+=("$work/munged.pid")

node=$(hostname)
cat > "$work/slurm.conf" <<EOF
ClusterName=syrof-test
SlurmctldHost=$node
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge.sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$node CPUs=$(nproc) State=UNKNOWN
PartitionName=grading Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
/usr/sbin/slurmctld -f "$SLURM_CONF"
daemons+=("$work/slurmctld.pid")
/usr/sbin/slurmd -f "$SLURM_CONF"
daemons+=("$work/slurmd.pid")
node_idle() { sinfo --noheader --nodes="$node" --format=%t 2>/dev/null | grep -qx idle; }
wait_for 60 "the Slurm node never became idle" node_idle
echo "test-slurm: munged, slurmctld and slurmd up (node $node, $(nproc) CPUs)"

# --- the course folder ------------------------------------------------------------
course="$work/course"
mkdir -p "$course/assignments" "$course/submissions"
cp -r "$root/assignments/gather" "$course/assignments/gather"
students=(alice bob carol dave erin)
cp -r "$root/assignments/gather/reference" "$course/submissions/alice"
cp -r "$root/assignments/gather/starter" "$course/submissions/bob"
bash "$root/scripts/broken-variant.sh" gather rand "$course/submissions/carol" >/dev/null
cp -r "$root/assignments/gather/starter" "$course/submissions/dave"
printf 'this is not C\n' >> "$course/submissions/dave/gather.c"
bash "$root/scripts/broken-variant.sh" gather fixed_size "$course/submissions/erin" >/dev/null
rm -rf "$course"/submissions/*/build "$course"/submissions/*/{expected.yaml,NOTE.md,mistake.patch}
cp "$work/grade.sh" "$course/grade.sh"
export PATH="$build/bin:$PATH"
cd "$course"

echo "test-slurm: grading the class of ${#students[@]} on one machine"
syrof grade --class submissions --assignment assignments/gather --jobs 2 --out out/one --quiet >/dev/null

# --- the doc's submit block, with shard 3 cancelled mid-way -----------------------
shards=3
cancelled=3
# syrof grade's slices (ShardOf): students [n(i-1)/N, ni/N) of the sorted list.
mapfile -t in_cancelled < <(printf '%s\n' "${students[@]}" | sort | sed -n "$(( ${#students[@]} * (cancelled - 1) / shards + 1 )),$(( ${#students[@]} * cancelled / shards ))p")
[ "${#in_cancelled[@]}" -ge 2 ] || fail "shard $cancelled needs at least two students to be cancelled mid-way"
bash -e "$work/submit"
array_job=$(squeue --noheader --format=%F --name=grade.sh | sort -u | head -n 1)
[ -n "$array_job" ] || fail "the doc's submit block started no job array"
echo "test-slurm: job array $array_job submitted ($shards shards), the merge job waiting for it"
first_graded() { ls out/shard-$cancelled-of-$shards/*/grade.json >/dev/null 2>&1; }
wait_for 600 "shard $cancelled graded no student" first_graded
scancel "${array_job}_$cancelled"
array_done() { [ -z "$(squeue --noheader --jobs="$array_job" 2>/dev/null)" ]; }
wait_for 600 "the job array did not end" array_done
graded=$(ls out/shard-$cancelled-of-$shards/*/grade.json 2>/dev/null | wc -l)
[ "$graded" -lt "${#in_cancelled[@]}" ] ||
  fail "shard $cancelled finished all its ${#in_cancelled[@]} students before scancel: nothing left to resume"
echo "test-slurm: shard $cancelled cancelled after $graded of ${#in_cancelled[@]} students"
merge_waits() { squeue --noheader --name=wrap --format=%r | grep -q DependencyNeverSatisfied; }
wait_for 60 "the merge job is not waiting with DependencyNeverSatisfied" merge_waits
[ ! -e out/class ] || fail "the merge ran although shard $cancelled was cancelled"

# --- the doc's resubmit block: the shard again, then the merge -----------------
bash -e "$work/resubmit"
queue_empty() { [ -z "$(squeue --noheader 2>/dev/null)" ]; }
wait_for 600 "the resubmitted shard and the merge did not end" queue_empty
[ -f out/class/class.csv ] || fail "the merge job wrote no out/class/class.csv: $(cat out/merge-*.txt 2>/dev/null)"
again_output=$(ls -t out/slurm-*_$cancelled.txt | head -n 1)
grep -q "Graded $(( ${#in_cancelled[@]} - graded )), resumed $graded" "$again_output" ||
  fail "the resubmitted shard did not resume: $(cat "$again_output")"

cmp out/one/class.csv out/class/class.csv || fail "the merged class.csv differs from one machine's"
cmp out/one/summary.txt out/class/summary.txt || fail "the merged summary.txt differs from one machine's"
echo "test-slurm: merged class.csv and summary.txt are one machine's bytes ($(( $(wc -l < out/class/class.csv) - 1 )) students)"
echo "test-slurm: passed"
