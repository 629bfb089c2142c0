#!/usr/bin/env bash
# The figures of docs/animate.md, "Measured": one process against the same frames as a
# Slurm array job, for a BART animation and for a physics scene (simulate once, then
# blocks). Needs a cluster (SLURM_CONF; deploy/slurm/local-cluster.sh start DIR) and a
# release binary in DYNRAY. Wall times from submission until squeue shows no task left
# (sbatch --wait polls with growing sleeps, which would add up to half a minute).
#
#   DYNRAY=target/release/dynray SLURM_CONF=… deploy/slurm/measure.sh [WORKDIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
: "${DYNRAY:?set DYNRAY to a release binary}"
: "${SLURM_CONF:?start a cluster first: deploy/slurm/local-cluster.sh start DIR}"
work=${1:-$(mktemp -d)}
mkdir -p "$work"
cd "$work"
robot="$root/../shared/scenes/bart/robot/aff/Robot.aff"
drop="$root/examples/physics/bunny_drop.scn"

now() { date +%s.%N; }
secs() { echo "$2 - $1" | bc; }
# Waits until no task of job $1 is pending or running.
wait_job() { while [ -n "$(squeue -h -j "$1" -t PD,R,CG 2>/dev/null)" ]; do sleep 0.1; done; }
# Prints the wall time of an array job: submit "$@" and wait.
array() { local s j; s=$(now); j=$(sbatch --parsable "$@"); wait_job "${j%%;*}"; secs "$s" "$(now)"; }
same() { for f in "$1"/frame_*.png; do cmp -s "$f" "$2/$(basename "$f")" || { echo "DIFFERENT: $f" >&2; exit 1; }; done; }

# Sum of a timings column over files: physics and posing time spent by all tasks, s.
pose_s() { awk -F, 'FNR > 1 { s += $3 } END { printf "%.2f", s / 1000 }' "$@"; }

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
# One task a machine is the cluster's case: one process on one core against two tasks of
# one core each (the two cores standing in for two machines), and one process on both.
opts=(--frames 0..95 --width 320 --height 240 --spp 1)
s=$(now); "$DYNRAY" --threads 1 animate "$robot" --out one "${opts[@]}" 2>/dev/null; t1=$(secs "$s" "$(now)")
s=$(now); "$DYNRAY" animate "$robot" --out two "${opts[@]}" 2>/dev/null; t2=$(secs "$s" "$(now)")
s=$(now); "$DYNRAY" --threads 1 animate "$robot" --out task --frames 0..0 --width 320 --height 240 --spp 1 2>/dev/null
t0=$(secs "$s" "$(now)")
ta=$(array --array=0-1 --cpus-per-task=1 "$here/animate.sbatch" "$robot" array "${opts[@]}")
same one array
same one two
echo "BART robots, 96 frames 320x240 1 spp: one process, 1 thread ${t1} s; 2 threads ${t2} s; Slurm, 2 tasks x 1 CPU ${ta} s; a task's start, load, build and first frame ${t0} s"

popts=(--width 320 --height 240 --spp 4)
s=$(now); "$DYNRAY" --threads 1 animate "$drop" --out pone "${popts[@]}" --checkpoint-every 0 2>/dev/null; p1=$(secs "$s" "$(now)")
s=$(now); "$DYNRAY" animate "$drop" --out ptwo "${popts[@]}" --checkpoint-every 0 2>/dev/null; p0=$(secs "$s" "$(now)")
p2=$(DYNRAY_SHARDS= array --array=0-1 --cpus-per-task=1 "$here/animate.sbatch" "$drop" pshards "${popts[@]}" --checkpoint-every 0)
s=$(now); "$DYNRAY" --threads 1 animate "$drop" --out pblocks --checkpoints-only 2>/dev/null; p3=$(secs "$s" "$(now)")
p4=$(DYNRAY_SHARDS=blocks array --array=0-1 --cpus-per-task=1 "$here/animate.sbatch" "$drop" pblocks "${popts[@]}")
same pone pshards
same pone pblocks
same pone ptwo
# The pipelined chain: the simulation as a job of its own beside two blocks that wait for
# its checkpoints (what submit.sh --physics submits).
rm -rf ppipe
s=$(now)
sim=$(sbatch --parsable --cpus-per-task=1 "$here/simulate.sbatch" "$drop" ppipe)
j=$(DYNRAY_SHARDS=blocks sbatch --parsable --array=0-1 --cpus-per-task=1 "$here/animate.sbatch" "$drop" ppipe "${popts[@]}" --await-checkpoints 600)
wait_job "$sim"
wait_job "$j"
p5=$(secs "$s" "$(now)")
same pone ppipe
echo "bunny drop, 36 frames 320x240 4 spp: one process, 1 thread ${p1} s (posing and physics $(pose_s pone/timings.csv) s); 2 threads ${p0} s"
echo "  Slurm, 2 interleaved shards x 1 CPU, no checkpoints: ${p2} s (posing and physics $(pose_s pshards/timings_shard_*.csv) s over both tasks)"
echo "  --checkpoints-only, 1 thread: ${p3} s, then 2 blocks x 1 CPU: ${p4} s (posing and physics $(pose_s pblocks/timings_shard_*.csv) s over both tasks)"
echo "  the simulation job beside 2 blocks x 1 CPU waiting for its checkpoints: ${p5} s (posing and physics $(pose_s ppipe/timings_shard_*.csv) s over both blocks)"
