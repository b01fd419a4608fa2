#!/usr/bin/env bash
# Submits an fssim campaign to Slurm as an N-task array job (one shard per
# task) and a merge job that runs once every task succeeded.
# Usage: scripts/slurm/submit.sh [--wait] N OUTDIR CAMPAIGN-ARGS...
#   --wait   block until the merge is done (sbatch --wait); exit 1 if a job failed
# Example:
#   FSSIM=$PWD/build/fssim scripts/slurm/submit.sh 16 /shared/run1 \
#     -i images/ -c raskar mip sinc --velocity 0.25:4:x2 --snr 25:400:x2 --trials 20
# The merged results are in OUTDIR/merged; the parts in OUTDIR/part-I.
# FSSIM must be a path every node can run (default: fssim on PATH), OUTDIR
# a directory every node can write.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
wait=()
if [ "${1:-}" = --wait ]; then wait=(--wait); shift; fi
count=${1:?usage: submit.sh [--wait] N OUTDIR CAMPAIGN-ARGS...}
outdir=${2:?usage: submit.sh [--wait] N OUTDIR CAMPAIGN-ARGS...}
shift 2
case "$count" in ''|*[!0-9]*|0) echo "submit.sh: N must be a positive integer, got '$count'" >&2; exit 2;; esac
mkdir -p "$outdir"
export FSSIM=${FSSIM:-fssim}
# With --wait the array is waited for first: a failed task then stops here
# instead of leaving a merge job whose dependency can never be satisfied.
# The jobs run in this directory, so relative paths in CAMPAIGN-ARGS (which
# name the images in the results) mean what they mean here.
array=$(sbatch --parsable "${wait[@]}" --output="$outdir/slurm-%A_%a.out" --array="1-${count}" \
  "$here/campaign.sbatch" "$outdir" "$@")
array=${array%%;*}
echo "submit.sh: array job $array ($count tasks)" >&2
merge=$(sbatch --parsable "${wait[@]}" --output="$outdir/slurm-merge-%j.out" --dependency="afterok:${array}" \
  "$here/merge.sbatch" "$outdir" "$count")
echo "submit.sh: merge job ${merge%%;*}, results in $outdir/merged" >&2
