#!/usr/bin/env bash
# Runs one fuzz target for a fixed time and keeps the evidence: a log with the target, the
# revision, the date, the command, the exit status, the wall time, libFuzzer's run count and
# rate, the corpus size before and after, the coverage, the findings, and the end of
# libFuzzer's own output.
#
#   fuzz/run.sh TARGET [SECONDS] [LOG_DIR]
#
# TARGET: graph_file, layer_file, scene_file or track_file. SECONDS: 600 unless given.
# LOG_DIR: results/fuzz unless given (relative to the repository root). The log is
# LOG_DIR/TARGET-<UTC date>.log; libFuzzer's whole output goes beside it as
# TARGET-<UTC date>.libfuzzer.txt (not kept in git). The corpus grows in fuzz/corpus/TARGET
# (seeded from fuzz/seeds/TARGET), crashes land in fuzz/artifacts/TARGET. Needs the nightly
# toolchain and cargo-fuzz (`cargo install cargo-fuzz`). Exits with libFuzzer's status.
set -euo pipefail

target=${1:?usage: fuzz/run.sh TARGET [SECONDS] [LOG_DIR]}
seconds=${2:-600}
root=$(cd "$(dirname "$0")/.." && pwd)
log_dir=${3:-$root/results/fuzz}
case $log_dir in /*) ;; *) log_dir=$root/$log_dir ;; esac
[ -f "$root/fuzz/fuzz_targets/$target.rs" ] || { echo "no fuzz target $target (fuzz/fuzz_targets/)" >&2; exit 2; }

stamp=$(date -u +%Y-%m-%dT%H-%M-%SZ)
log=$log_dir/$target-$stamp.log
raw=$log_dir/$target-$stamp.libfuzzer.txt
corpus=$root/fuzz/corpus/$target
artifacts=$root/fuzz/artifacts/$target
mkdir -p "$log_dir" "$corpus" "$artifacts"
count() { find "$1" -maxdepth 1 -type f | wc -l | tr -d ' '; }
corpus_before=$(count "$corpus")
crashes_before=$(count "$artifacts")
command=(cargo +nightly fuzz run -O "$target" "$corpus" "$root/fuzz/seeds/$target" -- "-max_total_time=$seconds" -rss_limit_mb=4096 -timeout=20 -print_final_stats=1)

start=$(date +%s)
set +e
(cd "$root/fuzz" && "${command[@]}") >"$raw" 2>&1
status=$?
set -e
wall=$(( $(date +%s) - start ))

stat() { grep -o "stat::$1: *[0-9]*" "$raw" | tail -1 | grep -o '[0-9]*$' || true; }
runs=$(stat number_of_executed_units)
rate=$(stat average_exec_per_sec)
coverage=$(grep -o 'cov: [0-9]*' "$raw" | tail -1 | grep -o '[0-9]*$' || true)
fuzz_seconds=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$raw" | tail -1 | grep -o 'in [0-9]*' | grep -o '[0-9]*' || true)
{
  echo "target: $target"
  echo "revision: $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)"
  echo "date: $stamp"
  echo "host: $(uname -srm), $(nproc) cores"
  echo "command: (cd fuzz && ${command[*]})"
  echo "exit status: $status"
  echo "wall seconds (build included): $wall"
  echo "fuzzing seconds (libFuzzer): ${fuzz_seconds:-unknown}"
  echo "runs: ${runs:-unknown}"
  echo "runs per second: ${rate:-unknown}"
  echo "corpus files: $corpus_before before, $(count "$corpus") after"
  echo "coverage (edges): ${coverage:-unknown}"
  echo "findings (new files in fuzz/artifacts/$target): $(( $(count "$artifacts") - crashes_before ))"
  echo "libFuzzer output (last 30 lines; all of it in $(basename "$raw")):"
  tail -n 30 "$raw" | sed 's/^/    /'
} >"$log"
cat "$log"
exit $status
