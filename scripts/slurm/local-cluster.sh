#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for trying scripts/slurm/submit.sh
# without a real cluster and for the test campaign_slurm_cluster.
# Usage: scripts/slurm/local-cluster.sh start|stop|status [--dir DIR]
#   start   writes a fresh munge key and slurm.conf into DIR, starts munged,
#           slurmctld and slurmd, waits until the node is idle and prints on
#           stdout the line to give the shell:  export SLURM_CONF=DIR/slurm.conf
#           (so `eval "$(scripts/slurm/local-cluster.sh start)"` sets it).
#           If this cluster is already running it prints the same line and
#           exits 0; if only some of its daemons run it refuses (run stop).
#   stop    stops the daemons started from DIR (by their pid files, each
#           checked to be that daemon), and only those; removes
#           DIR/slurm.conf and keeps DIR's logs.
#   status  says running, stopped or partial, and shows sinfo when running.
#           Exit status: 0 running, 3 stopped, 1 partial.
#   --dir DIR  the state directory (configuration, key, pid files, logs);
#           default $FSS_SLURM_DIR, else /tmp/fssim-slurm (the same for root
#           and for the users who submit).
# Needs Debian's slurmctld slurmd slurm-client munge (scripts/install-deps.sh)
# and root for start and stop: the daemons run as root (SlurmUser=root) so
# that jobs run as the user who submits them; any user may submit. The node is this machine (all its CPUs), one
# partition `main`; the ports are chosen at each start. docs/campaign.md
# ("On a Slurm cluster") walks through a campaign on it.
set -euo pipefail
usage="usage: local-cluster.sh start|stop|status [--dir DIR]"
command=${1:-}
[ $# -gt 0 ] && shift
dir=${FSS_SLURM_DIR:-/tmp/fssim-slurm}
while [ $# -gt 0 ]; do
  case "$1" in
    --dir) dir=${2:?local-cluster.sh: --dir needs a directory}; shift 2 ;;
    --dir=*) dir=${1#--dir=}; shift ;;
    *) echo "local-cluster.sh: unknown argument '$1' ($usage)" >&2; exit 2 ;;
  esac
done
case "$command" in start|stop|status) ;; *) echo "$usage" >&2; exit 2 ;; esac
[ -n "$dir" ] || { echo "local-cluster.sh: --dir needs a directory" >&2; exit 2; }
dir=$(realpath -m -- "$dir")
daemons=(munged slurmctld slurmd)

# The pid in DIR/NAME.pid if that process is alive and is NAME started with
# this directory's files (a stale pid reused by another process is not ours).
daemon_pid() {
  local name=$1 pid cmdline
  [ -s "$dir/$name.pid" ] || return 1
  pid=$(tr -dc 0-9 < "$dir/$name.pid")
  [ -n "$pid" ] && [ -r "/proc/$pid/cmdline" ] || return 1
  cmdline=$(tr '\0' ' ' < "/proc/$pid/cmdline")
  case "$cmdline" in *"$name"*"$dir/"*) echo "$pid" ;; *) return 1 ;; esac
}

# running, stopped or partial, from the three daemons' pid files.
cluster_state() {
  local alive=0 name
  for name in "${daemons[@]}"; do
    daemon_pid "$name" >/dev/null && alive=$((alive + 1))
  done
  if [ "$alive" -eq "${#daemons[@]}" ]; then echo running
  elif [ "$alive" -eq 0 ]; then echo stopped
  else echo partial; fi
}

# SIGTERM to every daemon of this cluster, then up to 5 s each before SIGKILL.
stop_cluster() {
  local pids=() pid name
  for name in slurmd slurmctld munged; do
    if pid=$(daemon_pid "$name"); then
      pids+=("$pid")
      kill "$pid" 2>/dev/null || true
    fi
    rm -f "$dir/$name.pid" 2>/dev/null || true
  done
  rm -f "$dir/slurm.conf" 2>/dev/null || true  # a SLURM_CONF left set now fails at once
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  echo "local-cluster.sh: stopped ${#pids[@]} daemon(s) of $dir" >&2
}

# Exit trap of a start: stops what a failed start left running.
stop_on_failure() {
  local status=$?
  [ "$status" -eq 0 ] || stop_cluster
  exit "$status"
}

# A TCP port in [20000, 40000) on which nothing answers on 127.0.0.1, with
# the next one free too (slurmctld takes PORT, slurmd PORT + 1).
free_port() {
  local port
  for _ in $(seq 50); do
    port=$((20000 + RANDOM % 20000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null &&
       ! (exec 3<>"/dev/tcp/127.0.0.1/$((port + 1))") 2>/dev/null; then
      echo "$port"; return 0
    fi
  done
  echo "local-cluster.sh: no free TCP port pair found in 20000-40000" >&2
  return 1
}

# A minimal slurm.conf: this machine as the one node with all its CPUs, one
# default partition, no accounting.
write_config() {
  local host=$1 port=$2
  cat > "$dir/slurm.conf" <<CONF
ClusterName=fssimlocal
SlurmctldHost=${host}(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=${port}
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${dir}/munge/munge.sock
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
StateSaveLocation=${dir}/state
SlurmdSpoolDir=${dir}/spool
SlurmctldPidFile=${dir}/slurmctld.pid
SlurmdPidFile=${dir}/slurmd.pid
SlurmctldLogFile=${dir}/slurmctld.log
SlurmdLogFile=${dir}/slurmd.log
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=${host} NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=main Nodes=${host} Default=YES MaxTime=INFINITE State=UP
CONF
}

# Starts munged (a fresh key, a private socket), then slurmctld and slurmd,
# and waits up to 20 s for the node to be idle.
start_cluster() {
  local tool socket="$dir/munge/munge.sock"
  for tool in munged mungekey slurmctld slurmd sbatch sinfo; do
    command -v "$tool" >/dev/null || PATH=$PATH:/usr/sbin command -v "$tool" >/dev/null || {
      echo "local-cluster.sh: $tool is missing (apt-get install slurmctld slurmd slurm-client munge, or scripts/install-deps.sh)" >&2
      exit 1
    }
  done
  export PATH=$PATH:/usr/sbin
  [ "$(id -u)" -eq 0 ] || {
    echo "local-cluster.sh: start needs root (the daemons run as SlurmUser=root); run it with sudo" >&2
    exit 1
  }
  [ ${#socket} -lt 100 ] || {
    echo "local-cluster.sh: the state directory's path is too long for munge's socket ($socket); use a shorter --dir" >&2
    exit 2
  }
  mkdir -p "$dir"
  [ -O "$dir" ] || { echo "local-cluster.sh: $dir belongs to another user; use another --dir" >&2; exit 1; }
  trap stop_on_failure EXIT
  rm -rf "$dir/munge" "$dir/state" "$dir/spool"
  rm -f "$dir"/*.log "$dir/slurm.conf"
  mkdir -p "$dir/munge" "$dir/state" "$dir/spool"
  chmod 755 "$dir"
  chmod 755 "$dir/munge"  # its socket serves every user; the key stays root's (0400)
  mungekey --create --keyfile="$dir/munge/munge.key" --force >/dev/null
  chmod 400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$socket" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munge/seed"
  write_config "$(hostname -s)" "$(free_port)"
  export SLURM_CONF="$dir/slurm.conf"
  slurmctld -f "$SLURM_CONF"
  slurmd -f "$SLURM_CONF"
  for _ in $(seq 100); do
    if sinfo -h -o %T 2>/dev/null | grep -Eq '^(idle|mixed)'; then trap - EXIT; return 0; fi
    sleep 0.2
  done
  echo "local-cluster.sh: the node never became idle; logs in $dir/*.log" >&2
  sinfo >&2 || true
  exit 1
}

case "$command" in
  start)
    case "$(cluster_state)" in
      running) echo "local-cluster.sh: already running from $dir" >&2 ;;
      partial)
        echo "local-cluster.sh: only some daemons of $dir run; run 'local-cluster.sh stop --dir $dir' first" >&2
        exit 1 ;;
      stopped)
        start_cluster
        echo "local-cluster.sh: running from $dir (node $(hostname -s), $(nproc) CPUs, partition main)" >&2 ;;
    esac
    echo "export SLURM_CONF=$dir/slurm.conf" ;;
  stop)
    if [ "$(cluster_state)" != stopped ] && [ "$(id -u)" -ne 0 ]; then
      echo "local-cluster.sh: stop needs root (the daemons run as root); run it with sudo" >&2
      exit 1
    fi
    stop_cluster ;;
  status)
    state=$(cluster_state)
    echo "local-cluster.sh: $state ($dir)"
    case "$state" in
      running)
        echo "export SLURM_CONF=$dir/slurm.conf"
        SLURM_CONF="$dir/slurm.conf" PATH=$PATH:/usr/sbin sinfo ;;
      stopped) exit 3 ;;
      partial)
        for name in "${daemons[@]}"; do
          daemon_pid "$name" >/dev/null && echo "  $name running" || echo "  $name stopped"
        done
        exit 1 ;;
    esac ;;
esac
