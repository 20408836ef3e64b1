#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan/UBSan) and runs each for SECONDS (default 60)
# on a seed corpus from configs/, data/ and fuzz/corpus/. Exits non-zero on any crash, sanitizer report,
# timeout or leak; the failing input is left in build/fuzz/findings/.
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target fuzz_experiment_loader fuzz_csv_table

work=build/fuzz
rm -rf "$work/corpus-loader" "$work/corpus-csv"
mkdir -p "$work/corpus-loader" "$work/corpus-csv" "$work/findings"
cp configs/*.yaml fuzz/corpus/loader/* "$work/corpus-loader/"
cp fuzz/corpus/csv/* "$work/corpus-csv/"
# The recordings' first rows (whole files would make every run slow).
for f in data/*/*.csv; do
  head -n 40 "$f" > "$work/corpus-csv/$(basename "$(dirname "$f")")-$(basename "$f")"
done

for target in fuzz_experiment_loader fuzz_csv_table; do
  corpus="$work/corpus-loader"
  [ "$target" = fuzz_csv_table ] && corpus="$work/corpus-csv"
  echo "fuzz: $target for ${seconds} s"
  log="$work/findings/$target.log"
  if ! "$work/fuzz/$target" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 \
      -max_len=8192 -print_final_stats=1 -artifact_prefix="$work/findings/$target-" >"$log" 2>&1; then
    tail -n 40 "$log"
    echo "fuzz: $target found a problem; input and log in $work/findings/" >&2
    exit 1
  fi
  grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|#[0-9]+ *DONE)" "$log" || tail -n 3 "$log"
done
echo "fuzz: no crash, hang or sanitizer report"
