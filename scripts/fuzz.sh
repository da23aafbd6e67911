#!/usr/bin/env bash
# Runs one libFuzzer target: scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]
#   TARGET   ogr_wkb | snap | config   (tests/fuzz/fuzz_TARGET.cpp)
#   SECONDS  how long to fuzz (60 in CI; an hour or more for a real hunt)
# Builds the `fuzz` preset (clang, libFuzzer + ASan + UBSan) for that target only, then fuzzes
# at low priority (nice 10) starting from the seed corpus tests/fuzz/corpus/TARGET. New inputs go
# to build/fuzz/corpus/TARGET (not into the repository); a crash is written to
# build/fuzz/crashes/TARGET/ and the script exits non-zero. To keep a crash as a regression
# test, fix it and copy the file into tests/fuzz/corpus/TARGET/ (the release build replays that
# folder as the test fuzz_corpus_TARGET).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  echo "usage: scripts/fuzz.sh ogr_wkb|snap|config SECONDS [libFuzzer options...]" >&2
  exit 2
fi
target=$1
seconds=$2
shift 2
case "$target" in
  ogr_wkb|snap|config) ;;
  *) echo "fuzz.sh: unknown target '$target' (ogr_wkb, snap or config)" >&2; exit 2 ;;
esac
cmake --preset fuzz > /dev/null
cmake --build --preset fuzz --target "fuzz_$target"
work=build/fuzz/corpus/$target
crashes=build/fuzz/crashes/$target
mkdir -p "$work" "$crashes"
# UBSan stops at the first report so libFuzzer keeps the input; ASan's leak check stays on.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
nice -n 10 "build/fuzz/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 \
  -max_len=4096 -print_final_stats=1 -artifact_prefix="$crashes/" "$@" "$work" "tests/fuzz/corpus/$target"
