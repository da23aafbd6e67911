#!/usr/bin/env bash
# Short smoke run of the benchmarks, for CI: builds nothing, runs an already built
#  - bench_engine on the small sizes (no 10^5 coverage, no 10^6) with a tiny min time, writing
#    bench/results/engine_smoke.json (< 10 s);
#  - bench_pipeline once per data set and output format (one iteration each), writing
#    bench/results/pipeline_smoke.json (< 30 s here);
#  - bench/compare on the bundled data/delft_partition_sample.gpkg at 1 cm, every tool (trisnap,
#    CGAL ISR and SR, GEOS, each judged by `trisnap assess`), writing
#    bench/results/compare_smoke.json (< 60 s); fails when a tool fails or the table lacks a key;
#  - bench_handoff once on the same sample (bench/results/handoff_smoke.json, < 1 s);
#  - bench/threads --quick: one and two threads end to end on the same sample (< 2 s);
#  - bench_write on Andorra, GeoPackage rows and GDAL's path, the rows with the index sorted on
#    disk, one iteration each, and the spatial index's packing of 20,000 boxes (< 5 s);
# Fails when a binary is missing, when a run fails, or when a benchmark reports an error other
# than an absent data set.
#   BENCH_ENGINE=path BENCH_PIPELINE=path BENCH_COMPARE_TOOLS=path bench/run_smoke.sh   (default: newest of build/{bench,release,dev})
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

# find_binary NAME OVERRIDE: OVERRIDE when given, else the most recently built of the presets'
# binaries (CI builds `release`; a stale one loses).
find_binary() {
  local name="$1" binary="$2" candidate
  if [[ -z "$binary" ]]; then
    for candidate in "$root"/build/{bench,release,dev}/bench/"$name"; do
      if [[ -x "$candidate" && ( -z "$binary" || "$candidate" -nt "$binary" ) ]]; then
        binary="$candidate"
      fi
    done
  fi
  if [[ -z "$binary" || ! -x "$binary" ]]; then
    echo "run_smoke: $name not found; build it first (cmake --preset bench && cmake --build --preset bench), or set ${name^^}" >&2
    return 1
  fi
  echo "$binary"
}

# check_results FILE: a benchmark that skipped with an error still lets the binary exit 0, so
# look for errors here. Only an absent data set is tolerated (machines without ../shared/data).
check_results() {
  python3 - "$1" <<'PY'
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
    print(f"run_smoke: no benchmark ran ({sys.argv[1]})", file=sys.stderr)
sys.exit(1 if bad or not runs else 0)
PY
  echo "run_smoke: ok, $(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["benchmarks"]))' "$1") results in $1"
}

engine="$(find_binary bench_engine "${BENCH_ENGINE:-}")"
pipeline="$(find_binary bench_pipeline "${BENCH_PIPELINE:-}")"
mkdir -p "$root/bench/results"

# TRISNAP_BENCH_LARGE unset: the 10^6 coverage is not even registered. The JSON goes to the
# file (for comparisons); the log gets the readable table.
out="$root/bench/results/engine_smoke.json"
env -u TRISNAP_BENCH_LARGE timeout 300 "$engine" \
  --benchmark_filter='(Coverage|Coverage_Progress|Only)/(1000|10000)/|NearDegenerate/(100|1000)/|Andorra' \
  --benchmark_min_time=0.01 \
  --benchmark_format=console --benchmark_out="$out" --benchmark_out_format=json \
  || { echo "run_smoke: bench_engine failed (exit $?)" >&2; exit 1; }
check_results "$out"

# Every data set and format, one iteration each (each call takes well over the min time).
out="$root/bench/results/pipeline_smoke.json"
timeout 300 "$pipeline" --benchmark_min_time=0.01 \
  --benchmark_format=console --benchmark_out="$out" --benchmark_out_format=json \
  || { echo "run_smoke: bench_pipeline failed (exit $?)" >&2; exit 1; }
check_results "$out"

# bench/compare: all tools on a small layer that ships with the repository (no ../shared/data).
compare_tools="$(find_binary bench_compare_tools "${BENCH_COMPARE_TOOLS:-}")"
out="$root/bench/results/compare_smoke.json"
timeout 120 python3 "$root/bench/compare" "$root/data/delft_partition_sample.gpkg" --tolerance 0.01 \
  --dataset smoke --timeout 60 --runner "$compare_tools" --out-dir "$root/bench/results/compare_smoke" \
  --json "$out" || { echo "run_smoke: bench/compare failed (exit $?)" >&2; exit 1; }
python3 - "$out" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
keys = ("tool", "status", "wall_s", "peak_rss_mb", "n_out", "n_invalid", "n_crossings", "min_vv_T",
        "min_ve_T", "max_hausdorff_T", "lost")
rows = {row["tool"]: row for row in report["table"]}
bad = [f"{t}: missing" for t in ("trisnap", "isr", "sr", "geos", "input") if t not in rows]
bad += [f"{t}: status {r['status']}" for t, r in rows.items() if r["status"] != "ok"]
bad += [f"{t}: no {k}" for t, r in rows.items() for k in keys
        if r.get(k) is None and not (t == "input" and k in ("wall_s", "peak_rss_mb"))]
for b in bad:
    print(f"run_smoke: compare: {b}", file=sys.stderr)
sys.exit(1 if bad else 0)
PY
echo "run_smoke: ok, bench/compare table in $out"
rm -rf "$root/bench/results/compare_smoke"

# One thread against two, end to end (issue 11), once each on the bundled sample; with two CPUs
# also pinned to each (the ceiling and efficiency table).
pinned=()
if [[ "$(nproc)" -ge 2 ]]; then pinned=(--pinned); fi
python3 "$root/bench/threads" --quick "${pinned[@]}" --json "$root/bench/results/threads_smoke.json" \
  || { echo "run_smoke: bench/threads failed" >&2; exit 1; }

# Tiling (issue 5): untiled vs tiles on 1 and 2 threads on Andorra, one repetition.
python3 "$root/bench/tiling" --quick --out "$root/bench/results/tiling_smoke.json" \
  || { echo "run_smoke: bench/tiling failed" >&2; exit 1; }

# Out of core (issue 10): 20k replicated Jakarta polygons in memory, under --memory-limit and
# --no-tiles; fails when the peak RSS exceeds the limit or the three outputs differ.
jakarta="$root/../shared/data/osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg"
if [[ -f "$jakarta" ]]; then
  large="$(mktemp -d)"
  "$root/bench/make-large-layer" 20k --out "$large" >/dev/null
  python3 "$root/bench/out-of-core" --sizes 20k --limits 20k=192MiB --large-dir "$large" --no-make \
    --json "$root/bench/results/out_of_core_smoke.json" \
    || { rm -rf "$large"; echo "run_smoke: bench/out-of-core failed" >&2; exit 1; }
  rm -rf "$large"
else
  echo "run_smoke: out-of-core skipped: data set absent: $jakarta"
fi

# Cluster (issue 12): plan, 4 shards as separate processes, stitch, against one snap on Andorra;
# fails when a step fails or the bytes differ.
andorra="$root/../shared/data/snapoly_andorra/andorra.gpkg"
if [[ -f "$andorra" ]]; then
  python3 "$root/bench/cluster" "$andorra" --tolerance 1e-6 --option=--tile-size=0.01 --shards 4 \
    --json "$root/bench/results/cluster_smoke.json" || { echo "run_smoke: bench/cluster failed" >&2; exit 1; }
else
  echo "run_smoke: cluster skipped: data set absent: $andorra"
fi

# Adversarial inputs: each at a small and a large tolerance, the tenth sizes plus Andorra and
# JTS's failure case 4 (skipped when ../shared/data is absent); prints the large/small ratios.
adversarial="$(find_binary bench_adversarial "${BENCH_ADVERSARIAL:-}")"
timeout 300 python3 "$root/bench/adversarial" --bench "$adversarial" \
  --json "$root/bench/results/adversarial_smoke.json" \
  || { echo "run_smoke: bench/adversarial failed" >&2; exit 1; }
check_results "$root/bench/results/adversarial_smoke.json"

# Handing features between threads (GDAL alone), once on the bundled sample: every setup ran.
handoff="$(find_binary bench_handoff "${BENCH_HANDOFF:-}")"
timeout 120 "$handoff" "$root/data/delft_partition_sample.gpkg" --runs 1 \
  --json "$root/bench/results/handoff_smoke.json" || { echo "run_smoke: bench_handoff failed" >&2; exit 1; }
python3 - "$root/bench/results/handoff_smoke.json" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
setups = doc["setups"]
want = {"read", "write", "read_beside_write", "write_made_elsewhere", "serial", "pipeline", "pipeline_back"}
bad = sorted(want - {s["name"] for s in setups}) + [s["name"] for s in setups if not s["wall_s"] > 0]
trips = doc.get("round_trip_ns", {})  # null with one CPU to run on
bad += [f"round trip {k}" for k in ("before", "after") if k not in trips or not (trips[k] is None or trips[k] > 0)]
if bad:
    print(f"run_smoke: bench_handoff: missing or not timed: {bad}", file=sys.stderr)
    sys.exit(1)
print(f"run_smoke: ok, {len(setups)} setups in {sys.argv[1]}")
PY

# OUT's writer alone: GeoPackage rows against GDAL's per-feature path, one iteration each (fails
# when a feature is refused, the count differs or the rows path was not taken).
write_bench="$(find_binary bench_write "${BENCH_WRITE:-}")"
out="$root/bench/results/write_smoke.json"
timeout 120 "$write_bench" --benchmark_filter='Write/(rows|gdal|rows-index-on-disk)/andorra|PackRtree/20000' --benchmark_min_time=0.01 \
  --benchmark_format=console --benchmark_out="$out" --benchmark_out_format=json \
  || { echo "run_smoke: bench_write failed (exit $?)" >&2; exit 1; }
check_results "$out"

# trisnap against GEOS per feature and the read + CDT + write floor, one run on Andorra.
if [[ -f "$andorra" ]]; then
  timeout 300 python3 "$root/bench/vs-geos" --runs 1 --layers andorra \
    --tools "$compare_tools" || { echo "run_smoke: bench/vs-geos failed" >&2; exit 1; }
else
  echo "run_smoke: vs-geos skipped: data set absent: $andorra"
fi
