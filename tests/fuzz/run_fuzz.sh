#!/usr/bin/env bash
# Runs one libFuzzer target for SECONDS (default 60) from its committed seed corpus, writing new
# inputs to SCRATCH (the committed corpus is only read) and any crash reproducer to
# SCRATCH/crashes. Exits non-zero when the target crashed, leaked or timed out on an input.
#   run_fuzz.sh TARGET_BINARY SCRATCH SEED_CORPUS [SECONDS]
set -euo pipefail
binary=$1 scratch=$2 seeds=$3 seconds=${4:-60}
[[ -n "$seconds" ]] || seconds=60
mkdir -p "$scratch/corpus" "$scratch/crashes"
dict="$(dirname "$0")/$(basename "$binary").dict"
dict_flag=()
[[ -f "$dict" ]] && dict_flag=(-dict="$dict")
exec "$binary" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2560 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$scratch/crashes/" "${dict_flag[@]}" \
  "$scratch/corpus" "$seeds"
