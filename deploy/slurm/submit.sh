#!/usr/bin/env bash
# Submits the whole chain for one animation and prints the job ids:
#
#   deploy/slurm/submit.sh N SCENE OUTDIR [animate options…]            # N interleaved shards
#   deploy/slurm/submit.sh --physics N SCENE OUTDIR [animate options…]  # simulate + N blocks
#
# then the merge once every task has ended. With --physics the simulation job writes a
# checkpoint every frame while the N block tasks run beside it, each waiting for the
# checkpoint of the frame it renders next (`--await-checkpoints`) instead of simulating. Extra sbatch options (a partition, an
# account, --cpus-per-task) go in SBATCH_* environment variables, which sbatch reads.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
physics=0
if [ "${1:-}" = --physics ]; then
  physics=1
  shift
fi
if [ $# -lt 3 ] || ! [[ $1 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: submit.sh [--physics] N SCENE OUTDIR [animate options…]" >&2
  exit 2
fi
n=$1
shift
ended="afterany"
wait=()
if [ $physics = 1 ]; then
  sim=$(sbatch --parsable "$here/simulate.sbatch" "$@")
  echo "simulate: $sim"
  ended="afterany:$sim"
  wait=(--await-checkpoints 3600)
  export DYNRAY_SHARDS=blocks
fi
frames=$(sbatch --parsable --array="0-$((n - 1))" "$here/animate.sbatch" "$@" "${wait[@]}")
echo "frames: $frames"
merge=$(sbatch --parsable --dependency="$ended:$frames" "$here/merge.sbatch" "$@")
echo "merge: $merge"
