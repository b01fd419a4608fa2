#!/usr/bin/env bash
# Submits an fssim campaign to Slurm as an N-task array job (one shard per
# task) and a merge job that runs once every task succeeded.
# Usage: scripts/slurm/submit.sh [OPTION]... N OUTDIR CAMPAIGN-ARGS...
#   --wait              block until the merge is done (sbatch --wait); exit 1
#                       if a job failed, naming its log
#   --figures           the merge also draws the figures (OUTDIR/merged/figures);
#                       a --figures among CAMPAIGN-ARGS is moved to the merge
#                       too (a shard draws none)
#   --merge-option OPT  pass OPT to `fssim campaign merge` (repeatable), e.g.
#                       --merge-option --skip-unrunnable
#   -h, --help          this text
# The options come before N; everything after OUTDIR goes to every shard's
# `fssim campaign` (with --shard I/N -o OUTDIR/part-I added).
# Example:
#   FSSIM=$PWD/build/fssim scripts/slurm/submit.sh --figures 16 /shared/run1 \
#     -i images/ -c raskar mip sinc --velocity 0.25:1:x2 --snr 25:400:x2 --trials 20
# The merged results are in OUTDIR/merged; the parts in OUTDIR/part-I; the
# jobs' logs in OUTDIR/slurm-*.out. FSSIM must be a path every node can run
# (default: fssim on PATH), OUTDIR a directory every node can write.
# Without a cluster, scripts/slurm/local-cluster.sh starts one on this
# machine; docs/campaign.md ("On a Slurm cluster") walks through both.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
usage="usage: submit.sh [--wait] [--figures] [--merge-option OPT]... N OUTDIR CAMPAIGN-ARGS..."
wait=()
merge_options=()
while [ $# -gt 0 ]; do
  case "$1" in
    --wait) wait=(--wait); shift ;;
    --figures) merge_options+=(--figures); shift ;;
    --merge-option)
      [ $# -ge 2 ] || { echo "submit.sh: --merge-option needs an option of 'fssim campaign merge'" >&2; exit 2; }
      merge_options+=("$2"); shift 2 ;;
    --merge-option=*) merge_options+=("${1#--merge-option=}"); shift ;;
    -h|--help) sed -n '2,/^set -euo/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
    --) shift; break ;;
    -*) echo "submit.sh: unknown option '$1' ($usage)" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
count=$1
outdir=$2
shift 2
case "$count" in ''|*[!0-9]*|0) echo "submit.sh: N must be a positive integer, got '$count'" >&2; exit 2;; esac
[ $# -gt 0 ] || { echo "submit.sh: no CAMPAIGN-ARGS ($usage)" >&2; exit 2; }
# A shard leaves --figures out: the merge draws them.
campaign_args=()
for argument in "$@"; do
  if [ "$argument" = --figures ]; then
    case " ${merge_options[*]-} " in *" --figures "*) ;; *) merge_options+=(--figures) ;; esac
    echo "submit.sh: --figures goes to the merge job (figures in $outdir/merged/figures)" >&2
  else
    campaign_args+=("$argument")
  fi
done
command -v sbatch >/dev/null || {
  echo "submit.sh: sbatch not found: run this on a Slurm login node, or start a local cluster with scripts/slurm/local-cluster.sh (see docs/campaign.md, 'On a Slurm cluster')" >&2
  exit 1
}
if [ -n "${SLURM_CONF:-}" ] && [ ! -f "$SLURM_CONF" ]; then
  echo "submit.sh: SLURM_CONF names $SLURM_CONF, which does not exist (a stopped local cluster? eval \"\$(scripts/slurm/local-cluster.sh start)\" sets it anew)" >&2
  exit 1
fi
mkdir -p "$outdir"
export FSSIM=${FSSIM:-fssim}

# sbatch ARGS...: prints the job id (also of a job that --wait saw fail);
# fails as sbatch does, and says in one line what to do
# when Slurm has no configuration, else shows sbatch's own message.
submit() {
  local errors status=0 id
  errors=$(mktemp)
  id=$(sbatch --parsable "$@" 2>"$errors") || status=$?
  if [ "$status" -ne 0 ]; then
    if grep -q 'Could not establish a configuration source' "$errors"; then
      echo "submit.sh: sbatch finds no Slurm configuration: run this on the cluster's login node, or set SLURM_CONF (for a cluster on this machine: eval \"\$(scripts/slurm/local-cluster.sh start)\"; see docs/campaign.md, 'On a Slurm cluster')" >&2
    else
      cat "$errors" >&2
    fi
  fi
  rm -f "$errors"
  [ -z "$id" ] || echo "${id%%;*}"
  return "$status"
}

# With --wait the array is waited for first: a failed task then stops here
# instead of leaving a merge job whose dependency can never be satisfied.
# The jobs run in this directory, so relative paths in CAMPAIGN-ARGS (which
# name the images in the results) mean what they mean here.
if ! array=$(submit "${wait[@]}" --output="$outdir/slurm-%A_%a.out" --array="1-${count}" \
    "$here/campaign.sbatch" "$outdir" "${campaign_args[@]}"); then
  [ -z "${array:-}" ] || echo "submit.sh: array job $array failed; see $outdir/slurm-${array}_*.out" >&2
  exit 1
fi
echo "submit.sh: array job $array ($count tasks)" >&2
if ! merge=$(submit "${wait[@]}" --output="$outdir/slurm-merge-%j.out" --dependency="afterok:${array}" \
    "$here/merge.sbatch" "$outdir" "$count" "${merge_options[@]}"); then
  [ -z "${merge:-}" ] || echo "submit.sh: merge job $merge failed; see $outdir/slurm-merge-${merge}.out" >&2
  exit 1
fi
echo "submit.sh: merge job $merge, results in $outdir/merged" >&2
