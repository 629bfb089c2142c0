#!/usr/bin/env bash
# Builds every fuzz target once and runs each for SECONDS_PER_TARGET (default 20) on a
# copy of its seed corpus (docs/fuzzing.md). Exit status 1 when any target found a
# crash, a timeout or memory past the limit; its input is saved in fuzz/artifacts/.
#
#   fuzz/run.sh [SECONDS_PER_TARGET] [TARGET...]
#
# Stable Rust: libFuzzer comes from the libfuzzer-sys crate (its build script compiles
# it with the C++ compiler), coverage from rustc's SanitizerCoverage pass, switched on
# by the flags below (what cargo-fuzz passes on nightly, minus the sanitizers). Debug
# assertions and overflow checks come from Cargo.toml's release profile, which keeps
# npyz's arithmetic wrapping as in the shipped build.
set -euo pipefail
cd "$(dirname "$0")"
seconds=${1:-20}
shift || true
all=(ply obj mtl npy npz gltf scn aff mitsuba adf image)
targets=("${@:-${all[@]}}")
[[ $seconds =~ ^[0-9]+$ ]] || { echo "fuzz/run.sh: SECONDS_PER_TARGET must be a whole number, not '$seconds'" >&2; exit 2; }

# Longest input each target tries, a little above its largest seed: longer inputs only
# slow a run down (every reader is linear in its input), and the seeds' structure is
# what the fuzzer mutates.
declare -A max_len=(
  [ply]=16384 [obj]=8192 [mtl]=8192 [npy]=4096 [npz]=8192 [gltf]=32768
  [scn]=16384 [aff]=16384 [mitsuba]=16384 [adf]=65536 [image]=16384
)
for t in "${targets[@]}"; do
  [[ -n ${max_len[$t]:-} ]] || { echo "fuzz/run.sh: no target '$t' (targets: ${all[*]})" >&2; exit 2; }
done

host=$(rustc -vV | sed -n 's/^host: //p')
export RUSTFLAGS="--cfg fuzzing -Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares"
# --target keeps RUSTFLAGS off build scripts and proc macros, which would otherwise be
# instrumented too and fail to link without libFuzzer.
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$PWD/target}
start=$SECONDS
bins=()
for t in "${targets[@]}"; do bins+=(--bin "$t"); done
cargo build --release --locked --target "$host" "${bins[@]}"
echo "fuzz/run.sh: built ${#targets[@]} targets in $((SECONDS - start)) s" >&2
bindir=$CARGO_TARGET_DIR/$host/release

# Each input's files are written under TMPDIR (fuzz/src/lib.rs): memory, where there is
# some, so the targets do not wait on a disk.
if [[ -d /dev/shm && -w /dev/shm ]]; then work=$(mktemp -d -p /dev/shm dynray-fuzz.XXXXXX); else work=$(mktemp -d); fi
trap 'rm -rf "$work"' EXIT
mkdir -p artifacts

# One target per core at a time, each for the full SECONDS_PER_TARGET on its own core:
# the run takes SECONDS × targets / cores. The loaders' rayon pools get one thread, so
# two targets do not fight over the cores.
jobs=${FUZZ_JOBS:-$(nproc)}
fuzz_one() {
  local t=$1
  # The repository's corpus stays as it is: libFuzzer adds what it finds to a copy.
  mkdir -p "$work/$t/corpus" "$work/$t/tmp"
  cp -r "corpus/$t/." "$work/$t/corpus/"
  local rc=0
  TMPDIR=$work/$t/tmp RAYON_NUM_THREADS=1 "$bindir/$t" "$work/$t/corpus" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len="${max_len[$t]}" \
    -artifact_prefix="$PWD/artifacts/$t-" -print_final_stats=1 >"$work/$t/log" 2>&1 || rc=$?
  echo "$rc" >"$work/$t/rc"
}
running=0
for t in "${targets[@]}"; do
  if ((running >= jobs)); then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
wait

failed=()
summary=()
for t in "${targets[@]}"; do
  log=$work/$t/log
  rc=$(cat "$work/$t/rc" 2>/dev/null || echo "?")
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
  if [[ $rc != 0 ]]; then
    failed+=("$t")
    summary+=("$(printf '%-8s FAILED (exit %s) after %s executions' "$t" "$rc" "${runs:-?}")")
    echo "fuzz/run.sh: $t failed; the end of its log:" >&2
    tail -n 40 "$log" >&2
  else
    summary+=("$(printf '%-8s %9s executions in %s s, coverage %s' "$t" "${runs:-?}" "$seconds" "${cov:-?}")")
  fi
done
printf 'fuzz/run.sh: %s\n' "${summary[@]}"
echo "fuzz/run.sh: done in $((SECONDS - start)) s (build included)" >&2
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz/run.sh: findings in: ${failed[*]} (inputs in fuzz/artifacts/; docs/fuzzing.md says how to reproduce)" >&2
  exit 1
fi
