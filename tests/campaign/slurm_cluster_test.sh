#!/usr/bin/env bash
# Runs a campaign on a real single-node Slurm cluster and checks that the
# merged shards are byte-identical to a single-machine run.
# Usage: tests/campaign/slurm_cluster_test.sh FSSIM SOURCE_DIR
#
# Starts munged and the Slurm daemons (Debian: slurmctld slurmd
# slurm-client munge) with a configuration under a temporary directory,
# submits scripts/slurm/submit.sh --wait 4 ... (a 4-task array job, then the
# merge job), compares, and stops the daemons by their pid files on any
# exit. Needs root (or passwordless sudo); without root or the packages it
# skips (exit 77), unless CI is set, where it fails.
set -euo pipefail
fssim=$(realpath "${1:?usage: slurm_cluster_test.sh FSSIM SOURCE_DIR}")
source_dir=$(realpath "${2:?usage: slurm_cluster_test.sh FSSIM SOURCE_DIR}")
start_time=$(date +%s.%N)

skip() {
  if [ -n "${CI:-}" ]; then
    echo "slurm_cluster_test: FAIL: $1 (CI is set: the Slurm test must run; see scripts/install-deps.sh)" >&2
    exit 1
  fi
  echo "slurm_cluster_test: SKIP: $1" >&2
  exit 77
}
if [ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
  exec sudo -n --preserve-env=CI "$0" "$fssim" "$source_dir"  # passwordless sudo, as on CI
fi
[ "$(id -u)" -eq 0 ] || skip "needs root (the test cluster runs its daemons as SlurmUser=root)"
for tool in munged mungekey slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$tool" >/dev/null || skip "$tool is missing (apt-get install slurmctld slurmd slurm-client munge)"
done

work=$(mktemp -d /tmp/fssim-slurm.XXXXXX)
chmod 755 "$work"
stop_daemons() {
  local status=$?
  # SIGTERM to all three at once, then up to 5 s each before SIGKILL.
  local pids=()
  for name in slurmd slurmctld munged; do
    if [ -s "$work/$name.pid" ]; then
      pids+=("$(cat "$work/$name.pid")")
      kill "${pids[-1]}" 2>/dev/null || true
    fi
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ "$status" -ne 0 ]; then
    for log in slurmctld.log slurmd.log munged.log; do
      [ -f "$work/$log" ] && { echo "--- $log" >&2; tail -n 20 "$work/$log" >&2; }
    done
    for out in "$work"/out/slurm-*.out; do
      [ -f "$out" ] && { echo "--- $out" >&2; cat "$out" >&2; }
    done
  fi
  rm -rf "$work"
  awk -v t0="$start_time" -v t1="$(date +%s.%N)" 'BEGIN { printf "slurm_cluster_test: %.1f s in all\n", t1 - t0 }'
  exit "$status"
}
trap stop_daemons EXIT

# munge: a fresh key, a private socket.
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/out"
chmod 700 "$work/munge"
mungekey --create --keyfile="$work/munge/munge.key" --force >/dev/null
chmod 400 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.sock" \
  --pid-file="$work/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge/seed"

# A minimal slurm.conf: this machine as the one node, all its CPUs, one
# default partition; ports chosen per run so that a leftover cluster never
# answers.
host=$(hostname -s)
cpus=$(nproc)
port=$((20000 + RANDOM % 20000))
cat > "$work/slurm.conf" <<CONF
ClusterName=fssimtest
SlurmctldHost=${host}(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=${port}
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${work}/munge/munge.sock
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
StateSaveLocation=${work}/state
SlurmdSpoolDir=${work}/spool
SlurmctldPidFile=${work}/slurmctld.pid
SlurmdPidFile=${work}/slurmd.pid
SlurmctldLogFile=${work}/slurmctld.log
SlurmdLogFile=${work}/slurmd.log
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=${host} NodeAddr=127.0.0.1 CPUs=${cpus} State=UNKNOWN
PartitionName=main Nodes=${host} Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 100); do
  sinfo -h -o %T 2>/dev/null | grep -E '^(idle|mixed)' >/dev/null && break
  sleep 0.2
done
sinfo -h -o %T | grep -E '^(idle|mixed)' >/dev/null || { echo "slurm_cluster_test: the node never became idle" >&2; sinfo >&2; exit 1; }
ready_time=$(date +%s.%N)

# The campaign: tiny images, a short code, noise-free and a few noisy trials.
cd "$work"
printf '1 0 1 1 0 0 1 1\n' > short.txt
args=(-i "$source_dir/data/camera.png" -c short.txt snapshot --velocity 0.5,1 --snr 50:200:x2
      --trials 2 --seed 11 --threads 1)
FSSIM="$fssim" "$source_dir/scripts/slurm/submit.sh" --wait 4 "$work/out" "${args[@]}"
"$fssim" campaign --no-progress "${args[@]}" -o "$work/single" >/dev/null
for f in results.csv results.jsonl campaign.json journal.jsonl; do
  cmp "$work/out/merged/$f" "$work/single/$f"
done
end_time=$(date +%s.%N)
rows=$(($(wc -l < "$work/single/results.csv") - 1))
awk -v rows="$rows" -v t0="$start_time" -v t1="$ready_time" -v t2="$end_time" 'BEGIN {
  printf "slurm_cluster_test: PASS: 4 shards on Slurm merged to the bytes of one run (%d settings); cluster start %.1f s, jobs and checks %.1f s\n", rows, t1 - t0, t2 - t1 }'
