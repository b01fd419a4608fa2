#!/usr/bin/env bash
# Runs a campaign on a real single-node Slurm cluster and checks that the
# merged shards are byte-identical to a single-machine run.
# Usage: tests/campaign/slurm_cluster_test.sh FSSIM SOURCE_DIR
#
# Starts the cluster with scripts/slurm/local-cluster.sh under a temporary
# directory (and checks its start, status and stop), checks submit.sh's
# one-line advice when sbatch has no configuration, submits
# scripts/slurm/submit.sh --wait --merge-option --figures 4 ... (a 4-task
# array job, then the merge job), compares results and figures, and stops
# the daemons on any exit. Needs root (or passwordless sudo); without root,
# the packages, or daemons that start here it skips (exit 77), unless CI is
# set, where it fails.
set -euo pipefail
fssim=$(realpath "${1:?usage: slurm_cluster_test.sh FSSIM SOURCE_DIR}")
source_dir=$(realpath "${2:?usage: slurm_cluster_test.sh FSSIM SOURCE_DIR}")
cluster_sh="$source_dir/scripts/slurm/local-cluster.sh"
start_time=$(date +%s.%N)

skip() {
  if [ -n "${CI:-}" ]; then
    echo "slurm_cluster_test: FAIL: $1 (CI is set: the Slurm test must run; see scripts/install-deps.sh)" >&2
    exit 1
  fi
  echo "slurm_cluster_test: SKIP: $1" >&2
  exit 77
}
fail() {
  echo "slurm_cluster_test: FAIL: $1" >&2
  exit 1
}
if [ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
  exec sudo -n --preserve-env=CI "$0" "$fssim" "$source_dir"  # passwordless sudo, as on CI
fi
[ "$(id -u)" -eq 0 ] || skip "needs root (the test cluster runs its daemons as SlurmUser=root)"
export PATH=$PATH:/usr/sbin
for tool in munged mungekey slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$tool" >/dev/null || skip "$tool is missing (apt-get install slurmctld slurmd slurm-client munge)"
done

work=$(mktemp -d /tmp/fssim-slurm.XXXXXX)
chmod 755 "$work"
cluster="$work/cluster"
show_logs() {
  for log in "$cluster"/*.log "$work"/out/slurm-*.out; do
    [ -f "$log" ] && { echo "--- $log" >&2; tail -n 20 "$log" >&2; }
  done
  return 0
}
cleanup() {
  local status=$?
  "$cluster_sh" stop --dir "$cluster" 2>/dev/null || true
  [ "$status" -eq 0 ] || [ "$status" -eq 77 ] || show_logs
  rm -rf "$work"
  awk -v t0="$start_time" -v t1="$(date +%s.%N)" 'BEGIN { printf "slurm_cluster_test: %.1f s in all\n", t1 - t0 }'
  exit "$status"
}
trap cleanup EXIT

# The cluster: stopped, started (twice: the second start only prints the
# environment again), running.
status=0; "$cluster_sh" status --dir "$cluster" >/dev/null || status=$?
[ "$status" -eq 3 ] || fail "status before start exited $status, expected 3 (stopped)"
if ! env_line=$("$cluster_sh" start --dir "$cluster"); then
  show_logs
  skip "the Slurm daemons did not start here (scripts/slurm/local-cluster.sh start)"
fi
[ "$env_line" = "export SLURM_CONF=$cluster/slurm.conf" ] || fail "start printed '$env_line'"
[ "$("$cluster_sh" start --dir "$cluster" 2>/dev/null)" = "$env_line" ] || fail "a second start did not print the same environment"
"$cluster_sh" status --dir "$cluster" | grep -q ' idle ' || fail "status of a running cluster shows no idle node"
ready_time=$(date +%s.%N)

cd "$work"
printf '1 0 1 1 0 0 1 1\n' > short.txt
args=(-i "$source_dir/data/camera.png" -c short.txt snapshot --velocity "0.5,1" --snr 50:200:x2
      --trials 2 --seed 11 --threads 1)

# No configuration (unless this machine has one of its own): one line that
# points to local-cluster.sh, and nothing submitted.
if [ ! -e /etc/slurm/slurm.conf ]; then
  status=0
  message=$(env -u SLURM_CONF FSSIM="$fssim" "$source_dir/scripts/slurm/submit.sh" 4 "$work/none" "${args[@]}" 2>&1) || status=$?
  if [ "$status" -ne 1 ] || [ "$(printf '%s\n' "$message" | wc -l)" -ne 1 ] ||
     [[ "$message" != *local-cluster.sh*docs/campaign.md* ]]; then
    fail "submit.sh without a configuration exited $status and said: $message"
  fi
fi

# The campaign: 4 shards, the merge draws the figures; a single run to compare.
eval "$env_line"
FSSIM="$fssim" "$source_dir/scripts/slurm/submit.sh" --wait --merge-option --figures 4 "$work/out" "${args[@]}"
"$fssim" campaign --no-progress "${args[@]}" --figures -o "$work/single" >/dev/null
for f in results.csv results.jsonl campaign.json journal.jsonl; do
  cmp "$work/out/merged/$f" "$work/single/$f"
done
figures=$(cd "$work/single/figures" && ls)
[ -n "$figures" ] || fail "the single run drew no figures"
[ "$(cd "$work/out/merged/figures" && ls)" = "$figures" ] || fail "the merge job drew other figures than a single run"
end_time=$(date +%s.%N)

# stop: the daemons are gone, status says stopped.
pids=$(cat "$cluster"/*.pid)
"$cluster_sh" stop --dir "$cluster" 2>/dev/null
for pid in $pids; do
  ! kill -0 "$pid" 2>/dev/null || fail "daemon $pid still runs after stop"
done
status=0; "$cluster_sh" status --dir "$cluster" >/dev/null || status=$?
[ "$status" -eq 3 ] || fail "status after stop exited $status, expected 3 (stopped)"

rows=$(($(wc -l < "$work/single/results.csv") - 1))
awk -v rows="$rows" -v t0="$start_time" -v t1="$ready_time" -v t2="$end_time" 'BEGIN {
  printf "slurm_cluster_test: PASS: 4 shards on Slurm merged to the bytes of one run (%d settings); cluster start %.1f s, jobs and checks %.1f s\n", rows, t1 - t0, t2 - t1 }'
