#!/usr/bin/env bash
# Short smoke run of the engine benchmarks, for CI: builds nothing, runs an already built
# bench_engine on the small sizes (no 10^5 coverage, no 10^6) with a tiny min time, and writes
# bench/results/engine_smoke.json. Fails when the binary is missing, when the run fails, or when
# a benchmark reports an error other than an absent data set.
#   BENCH_ENGINE=path/to/bench_engine bench/run_smoke.sh   (default: newest of build/{bench,release,dev})
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
binary="${BENCH_ENGINE:-}"
if [[ -z "$binary" ]]; then
  # The most recently built of the presets' binaries (CI builds `release`; a stale one loses).
  for candidate in "$root"/build/{bench,release,dev}/bench/bench_engine; do
    if [[ -x "$candidate" && ( -z "$binary" || "$candidate" -nt "$binary" ) ]]; then
      binary="$candidate"
    fi
  done
fi
if [[ -z "$binary" || ! -x "$binary" ]]; then
  echo "run_smoke: bench_engine not found; build it first (cmake --preset bench && cmake --build --preset bench), or set BENCH_ENGINE" >&2
  exit 1
fi

out="$root/bench/results/engine_smoke.json"
mkdir -p "$(dirname "$out")"
# TRISNAP_BENCH_LARGE unset: the 10^6 coverage is not even registered. The JSON goes to the
# file (for comparisons); the log gets the readable table.
env -u TRISNAP_BENCH_LARGE timeout 300 "$binary" \
  --benchmark_filter='(Coverage|Only)/(1000|10000)/|NearDegenerate/(100|1000)/|Andorra' \
  --benchmark_min_time=0.01 \
  --benchmark_format=console --benchmark_out="$out" --benchmark_out_format=json \
  || { echo "run_smoke: bench_engine failed (exit $?)" >&2; exit 1; }

# A benchmark that skipped with an error still lets the binary exit 0: look for errors here.
# Only an absent data set is tolerated (machines without ../shared/data).
python3 - "$out" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
bad = [r for r in runs if r.get("error_occurred")
       and not r.get("error_message", "").startswith("data set absent")]
for r in bad:
    print(f"run_smoke: {r['name']}: {r.get('error_message', '')}", file=sys.stderr)
for r in runs:
    if r.get("error_occurred") and r not in bad:
        print(f"run_smoke: skipped {r['name']}: {r.get('error_message', '')}", file=sys.stderr)
if not runs:
    print("run_smoke: no benchmark ran", file=sys.stderr)
sys.exit(1 if bad or not runs else 0)
PY
echo "run_smoke: ok, $(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["benchmarks"]))' "$out") results in $out"
