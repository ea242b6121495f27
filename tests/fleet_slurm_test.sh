#!/usr/bin/env bash
# docs/fleet/slurm-array.sbatch run for real: a Slurm cluster of one node (munged, slurmctld and
# slurmd of Debian's slurm-wlm and munge packages) is started on localhost in a temporary folder,
# for this test only; the documented array job is submitted with `sbatch --wait` as 3 tasks of a
# small config on the device present (lavapipe on CI); the parts are merged (`hybridbench merge`)
# and compared with one unsharded sweep of the config by tools/same_outputs.py: every count,
# accuracy figure and image the same. A part altered on purpose must then compare different, so
# that the comparison is seen to be able to fail. Every daemon the test started, and every job
# process, is stopped on exit, also when it fails.
#
# The daemons need root (slurmd starts each job as its user); without root the test is skipped
# (exit 77). The cluster is the temporary folder's alone: its own munge key and socket, its own
# slurm.conf (SLURM_CONF), state and spool, on free ports, so a Slurm or munge already on the
# machine is neither used nor disturbed.
#
# usage: bash tests/fleet_slurm_test.sh HYBRIDBENCH SOURCE_DIR   (ctest: Fleet.SlurmArrayJobOnALocalClusterMergesIntoWhatOneSweepGives)
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: bash tests/fleet_slurm_test.sh HYBRIDBENCH SOURCE_DIR" >&2
  exit 2
fi
hb=$(realpath "$1")
src=$(realpath "$2")
config="$src/tests/fixtures/sweep-shard.json"  # 5 variants at 64x36 (one at 96x54), 1 frame
parts=3

for tool in munged mungekey slurmctld slurmd sbatch scontrol squeue scancel python3; do
  if ! command -v "$tool" >/dev/null; then
    echo "fleet_slurm_test: $tool is missing; run scripts/setup.sh (Debian packages slurm-wlm, munge)" >&2
    exit 1
  fi
done
if [ "$(id -u)" != 0 ]; then
  echo "fleet_slurm_test: skipped: slurmd must run as root to start jobs; run the test as root (CI does)"
  exit 77
fi

# munged requires every folder above its socket to be searchable by all (so /tmp, not a TMPDIR that
# may lie in a private home), and the key's folder to be private.
tmp=$(mktemp -d /tmp/hybridbench_slurm_XXXXXX)
chmod 711 "$tmp"
mkdir -m 700 "$tmp/key" "$tmp/state" "$tmp/spool"
mkdir -m 755 "$tmp/run" "$tmp/log"
export SLURM_CONF="$tmp/slurm.conf"
daemons=()
slurm_up=0

# Jobs first (their processes belong to slurmstepd, which outlives slurmd), then the daemons by
# the ids they were started with; then any process left whose environment names this test's
# slurm.conf: a job step that scancel did not end.
cleanup() {
  local rc=$? pid left
  set +e
  if [ $slurm_up = 1 ] && [ -n "$(squeue -h -o %A 2>/dev/null)" ]; then
    scancel --full --user=root >/dev/null 2>&1
    for _ in $(seq 20); do [ -z "$(squeue -h -o %A 2>/dev/null)" ] && break; sleep 0.5; done
  fi
  for pid in "${daemons[@]}"; do kill "$pid" 2>/dev/null; done
  for pid in "${daemons[@]}"; do wait "$pid" 2>/dev/null; done
  mapfile -t left < <(grep -lzsxF "SLURM_CONF=$SLURM_CONF" /proc/[0-9]*/environ | cut -d/ -f3)
  for pid in "${left[@]}"; do [ "$pid" != $$ ] && kill -9 "$pid" 2>/dev/null; done
  if [ $rc != 0 ] && [ $rc != 77 ]; then
    echo "--- the daemons' logs ($tmp/log), last lines:"
    tail -n 15 "$tmp"/log/munged.out "$tmp"/log/{munged,slurmctld,slurmd}.log 2>/dev/null
  fi
  rm -rf "$tmp"
  exit $rc
}
trap cleanup EXIT
trap 'exit 1' INT TERM

failures=0
ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; failures=$((failures + 1)); }
# waitFor WHAT SECONDS COMMAND...: runs COMMAND every half second until it succeeds.
waitFor() {
  local what=$1 tries=$(($2 * 2))
  shift 2
  for _ in $(seq "$tries"); do "$@" >/dev/null 2>&1 && return 0; sleep 0.5; done
  echo "FAIL $what: not within $((tries / 2)) s" >&2
  exit 1
}

# munge: a key of its own, a socket of its own.
mungekey --create --keyfile="$tmp/key/munge.key"
munged --foreground --socket="$tmp/run/munge.socket" --key-file="$tmp/key/munge.key" \
  --pid-file="$tmp/run/munged.pid" --log-file="$tmp/log/munged.log" --seed-file="$tmp/key/munged.seed" \
  >"$tmp/log/munged.out" 2>&1 &
daemons+=($!)
waitFor "munged answers" 10 munge --socket="$tmp/run/munge.socket" --no-input

# Slurm: one node, this machine, with its real CPUs and memory; no cgroups, accounting or job
# completion log (none of which a fresh container has); two free ports.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
host=$(uname -n)
host=${host%%.*}
memory=$(awk '/^MemTotal:/ {print int($2 / 1024)}' /proc/meminfo)
cat >"$SLURM_CONF" <<EOF
ClusterName=hybridbench-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$tmp/run/munge.socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
# sbatch --wait polls at growing intervals (2, 8, 32 s) while they stay under a third of MinJobAge
# (a finished job's record must outlive a poll): at 6 s it polls every 2 s, not 32 s late.
MinJobAge=6
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D >"$tmp/log/slurmctld.out" 2>&1 &
daemons+=($!)
slurm_up=1
slurmd -D -N "$host" >"$tmp/log/slurmd.out" 2>&1 &
daemons+=($!)
nodeIdle() { [ "$(sinfo -h -n "$host" -o %T)" = idle ]; }
waitFor "the node $host is idle" 30 nodeIdle
ok "munged, slurmctld and slurmd up on $host (ports $ctld_port, $slurmd_port)"

# The unsharded sweep, beside the array job.
"$hb" sweep "$config" --device 0 --out "$tmp/whole" >"$tmp/log/whole.out" 2>&1 &
whole=$!

# The documented job, as written, but for what a 2-core machine without a GPU has: 3 tasks
# (PARTS=3, --array=0-2) of one CPU and no GPU request. The tasks get the environment sbatch
# sees (HYBRIDBENCH_VALIDATION, LP_NUM_THREADS and the script's variables); OUT is the script's
# own, out/fleet/JOBID under the folder sbatch ran in.
# In the background and waited for, so that a signal to the test runs its trap at once (bash
# runs a trap only once a foreground command has ended).
cd "$tmp"
PARTS=$parts CONFIG="$config" HYBRIDBENCH="$hb" \
  timeout 300 sbatch --wait --parsable --array=0-$((parts - 1)) --cpus-per-task=1 --gres=none \
  --output="$tmp/log/task-%a.log" "$src/docs/fleet/slurm-array.sbatch" >"$tmp/log/sbatch.out" 2>&1 &
if wait $!; then
  ok "sbatch --wait: every array task exited 0"
else
  bad "sbatch --wait exited non-zero:"
  tail -n 5 "$tmp/log/sbatch.out" "$tmp"/log/task-*.log
fi
jid=$(head -n1 "$tmp/log/sbatch.out")
if wait "$whole"; then ok "the unsharded sweep"; else bad "the unsharded sweep exited non-zero:"; tail "$tmp/log/whole.out"; fi
if grep -l "validation:" "$tmp"/log/task-*.log "$tmp/log/whole.out"; then bad "Vulkan validation messages (files above)"; fi
[ $failures = 0 ] || exit 1

# Each task ran its own part, as context.shard records.
for k in $(seq 0 $((parts - 1))); do
  shard=$(python3 -c 'import json, sys; s = json.load(open(sys.argv[1]))["context"]["shard"]; print(s["index"], s["count"], sep="/")' \
    "out/fleet/$jid/part-$k/results.json" 2>&1) || true
  if [ "$shard" = "$k/$parts" ]; then ok "part-$k holds shard $k/$parts"; else bad "part-$k: shard '$shard', expected $k/$parts"; fi
done

# The documented merge; merged, the parts are the unsharded sweep: every untimed field of every
# run, every image.
merge() { "$hb" merge "out/fleet/$jid/"part-* --out "$1" >"$tmp/log/merge.out" 2>&1; }
if merge "out/fleet/$jid/merged"; then ok "hybridbench merge"; else bad "hybridbench merge:"; cat "$tmp/log/merge.out"; fi
if python3 "$src/tools/same_outputs.py" "$tmp/whole" "out/fleet/$jid/merged" >"$tmp/log/same.md"; then
  ok "the merged parts equal the unsharded sweep ($(grep -m1 '^Images:' "$tmp/log/same.md"))"
else
  bad "the merged parts differ from the unsharded sweep:"
  cat "$tmp/log/same.md"
fi

# The comparison can fail: one count of part 1 changed and one image of part 2 replaced by
# another, merged again, must compare different, naming both.
python3 - "out/fleet/$jid/part-1/results.json" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
r["runs"][0]["rays"]["traced"] += 1
json.dump(r, open(sys.argv[1], "w"))
EOF
mapfile -t pngs < <(find "out/fleet/$jid/part-2" -mindepth 2 -name "*.png" | sort)
rm "${pngs[0]}"  # merge hard-links the images: a new file, not the merged copy's
cp "${pngs[1]}" "${pngs[0]}"
if merge "$tmp/merged-altered"; then
  python3 "$src/tools/same_outputs.py" "$tmp/whole" "$tmp/merged-altered" >"$tmp/log/altered.md" && same=0 || same=$?
  image=${pngs[0]#"out/fleet/$jid/part-2/"}
  if [ "$same" = 1 ] && grep -q "/rays/traced: " "$tmp/log/altered.md" && grep -qF -- "- differs: $image" "$tmp/log/altered.md"; then
    ok "parts with one count and one image changed compare different, naming both"
  else
    bad "parts with one count and one image ($image) changed: same_outputs.py exited $same:"
    cat "$tmp/log/altered.md"
  fi
else
  bad "merge of the altered parts:"
  cat "$tmp/log/merge.out"
fi

echo "$failures failure(s)"
[ $failures = 0 ]
