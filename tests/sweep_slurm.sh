#!/usr/bin/env bash
# A sweep through a real Slurm on this machine: starts munged, slurmctld and slurmd (Debian's
# munge and slurm-wlm) on private ports with their state in a temporary folder, runs a small sweep
# locally and as a job array through sbatch, waits for the array, merges it with --collect and
# checks that its sweep.csv equals the local run's byte for byte. Stops what it started by pid,
# munged last. Exit 77 (ctest: skipped, with the reason on stderr) when Slurm cannot start here.
#   tests/sweep_slurm.sh BLENDBENCH_BINARY TINY_SCENARIO WORK_DIR [SWEEP_FILE [ARRAY_SIZE]]
# With SWEEP_FILE, that sweep runs instead of the small one on the tiny scenario (by hand: the
# shipped example through a job array of ARRAY_SIZE tasks, default 2).
set -uo pipefail
binary=$1
scenario=$2
work=$3
sweep=${4:-}
tasks=${5:-2}

skip() { echo "SKIPPED: $*" >&2; exit 77; }
fail() { echo "FAILED: $*" >&2; exit 1; }
now() { date +%s.%N; }

for program in munged munge unmunge slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v "$program" >/dev/null 2>&1 || skip "'$program' is not installed (apt-get install slurm-wlm munge)"
done
[ "$(id -u)" -eq 0 ] || skip "slurmd must run as root (it starts jobs as their users); run the suite as root"

# daemons' files in a private folder with a short path (a Unix socket path is at most 107 bytes)
rt=$(mktemp -d /tmp/blendbench-slurm.XXXXXX) || skip "cannot make a temporary folder"
chmod 700 "$rt"
mkdir -p "$rt/state" "$rt/spool" "$rt/log"

# stop by pid file, the daemons that depend on munge first; wait for each to go
stop() {
  local pidfile=$1 pid
  [ -s "$pidfile" ] || return 0
  pid=$(cat "$pidfile")
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.2; done
  kill -9 "$pid" 2>/dev/null || true
}
cleanup() {
  stop "$rt/slurmd.pid"
  stop "$rt/slurmctld.pid"
  stop "$rt/munged.pid"
  rm -rf "$rt"
}
trap cleanup EXIT

# a free TCP port pair: nothing answers on either
free_port() {
  local port
  for _ in $(seq 50); do
    port=$((20000 + RANDOM % 20000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && ! (exec 3<>"/dev/tcp/127.0.0.1/$((port + 1))") 2>/dev/null; then
      echo "$port"
      return 0
    fi
  done
  return 1
}
port=$(free_port) || skip "no free TCP port pair found"

# munge with its own key and socket, so a munged of the system is neither needed nor touched
dd if=/dev/urandom of="$rt/munge.key" bs=1024 count=1 status=none
chmod 400 "$rt/munge.key"
munged --force --socket="$rt/munge.sock" --key-file="$rt/munge.key" --pid-file="$rt/munged.pid" \
  --log-file="$rt/munged.log" --seed-file="$rt/munged.seed" 2>"$rt/munged.err" ||
  skip "munged does not start: $(cat "$rt/munged.err" "$rt/munged.log" 2>/dev/null | tail -3)"
munge -S "$rt/munge.sock" -n | unmunge -S "$rt/munge.sock" >/dev/null 2>&1 || skip "munge does not answer on its socket"

cpus=$(nproc)
cat >"$rt/slurm.conf" <<EOF
ClusterName=blendbench
SlurmctldHost=localhost
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$rt/munge.sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
StateSaveLocation=$rt/state
SlurmdSpoolDir=$rt/spool
SlurmctldPidFile=$rt/slurmctld.pid
SlurmdPidFile=$rt/slurmd.pid
SlurmctldLogFile=$rt/log/slurmctld.log
SlurmdLogFile=$rt/log/slurmd.log
NodeName=localhost CPUs=$cpus State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$rt/slurm.conf
slurmctld -f "$SLURM_CONF" 2>"$rt/log/slurmctld.err" || skip "slurmctld does not start: $(tail -3 "$rt/log/slurmctld.err" "$rt/log/slurmctld.log" 2>/dev/null)"
slurmd -f "$SLURM_CONF" -N localhost 2>"$rt/log/slurmd.err" || skip "slurmd does not start: $(tail -3 "$rt/log/slurmd.err" "$rt/log/slurmd.log" 2>/dev/null)"
up=
for _ in $(seq 60); do
  if sinfo -h -o %T 2>/dev/null | grep -q idle; then up=1; break; fi
  sleep 0.5
done
[ -n "$up" ] || skip "the Slurm node did not come up within 30 s: $(tail -3 "$rt/log/slurmctld.log" "$rt/log/slurmd.log" 2>/dev/null)"
echo "slurm: slurmctld and slurmd up on ports $port and $((port + 1)) ($(sinfo -h -o '%P %T %c CPUs'))"

# the sweep: 2 x 2 points of both variants of the tiny scenario
rm -rf "$work"
mkdir -p "$work"
if [ -z "$sweep" ]; then
  sweep=$work/sweep.yaml
  cat >"$sweep" <<EOF
scenario: $scenario
axes:
  variants[1].transition.parameter: [2, 5]
  defaults.velocity: [150, 200]
constraints: ["metrics.contour_error_programmed_max_mm <= 1.0"]
EOF
fi
"$binary" sweep "$sweep" --out "$work/local" --jobs 2 --no-plots >"$work/local.log" 2>&1 ||
  fail "the local sweep failed: $(tail -5 "$work/local.log")"

# through sbatch: the array of 2 shards, waited for, then merged
start=$(now)
"$binary" sweep "$sweep" --out "$work/slurm" --slurm --array-size "$tasks" >"$work/submit.log" 2>&1 ||
  fail "--slurm failed: $(cat "$work/submit.log")"
[ -s "$work/slurm/slurm/job_id" ] || fail "no job was submitted: $(cat "$work/submit.log")"
job=$(cat "$work/slurm/slurm/job_id")
done_=
for _ in $(seq 360); do
  if [ -z "$(squeue -h -j "$job" 2>/dev/null)" ]; then done_=1; break; fi
  sleep 0.5
done
[ -n "$done_" ] || fail "job array $job did not end within 180 s: $(squeue -j "$job" 2>&1)"
ran=$(now)
states=$(scontrol show job "$job" 2>/dev/null | grep -o 'JobState=[A-Z]*' | sort | uniq -c | tr -s ' ')
for shard in $(seq 0 $((tasks - 1))); do
  [ -s "$work/slurm/shards/$shard-of-$tasks.json" ] ||
    fail "array task $shard left no shard record (states:$states): $(cat "$work/slurm/slurm/"*_"$shard".out 2>/dev/null | tail -5)"
done
"$binary" sweep --collect "$work/slurm" --no-plots >"$work/collect.log" 2>&1 || fail "--collect failed: $(cat "$work/collect.log")"
end=$(now)
cmp "$work/local/sweep.csv" "$work/slurm/sweep.csv" || fail "the merged sweep.csv differs from the local run's"
cmp "$work/local/best.csv" "$work/slurm/best.csv" || fail "the merged best.csv differs from the local run's"
rows=$(($(wc -l <"$work/slurm/sweep.csv") - 1))
printf 'slurm: job array %s (tasks:%s) ran %s rows in %.1f s from sbatch to the end; %.1f s from submission to the merged sweep.csv, equal to the local run'"'"'s\n' \
  "$job" "$states" "$rows" "$(awk "BEGIN {print $ran - $start}")" "$(awk "BEGIN {print $end - $start}")"
