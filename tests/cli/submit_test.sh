#!/usr/bin/env bash
# scripts/slurm/submit without a Slurm: a stand-in `sbatch` first on PATH records its arguments
# and answers job ids. Checks the array it submits (0..N-1, or --only's shards, with %M and the
# shard count passed on), the stitch job's dependency on it, and that --only is checked against N
# (the plan's number, or --shards) before anything is submitted: a shard outside 0..N-1 or a
# backwards range is refused with one line and exit 2. Usage: submit_test.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
submit="$here/../../scripts/slurm/submit"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

mkdir -p "$tmp/bin" "$tmp/run"
cat >"$tmp/bin/sbatch" <<'SBATCH'
#!/usr/bin/env bash
echo "$*" >>"$FAKE_SBATCH_LOG"
echo "$((1000 + $(wc -l <"$FAKE_SBATCH_LOG")))"
SBATCH
chmod +x "$tmp/bin/sbatch"
printf '{\n  "tiles": 40,\n  "shards": 4,\n  "suggested_shards": 2\n}\n' >"$tmp/run/cluster.json"
export FAKE_SBATCH_LOG="$tmp/sbatch.log"
export PATH="$tmp/bin:$PATH"

# submit ARGS...: runs the script; sets code, out, err.
run_submit() {
  : >"$FAKE_SBATCH_LOG"
  set +e
  "$submit" "$tmp/run" "$tmp/out.gpkg" --trisnap /bin/true --logs "$tmp/logs" "$@" >"$tmp/out" 2>"$tmp/err"
  code=$?
  set -e
  out="$(cat "$tmp/out")" err="$(cat "$tmp/err")"
}

# refused OPTIONS... TEXT: exit 2, one line on stderr holding TEXT, nothing submitted.
refused() {
  local text="${*: -1}"
  run_submit "${@:1:$#-1}"
  [ "$code" -eq 2 ] || fail "submit ${*:1:$#-1}: exit $code, expected 2 ($err)"
  [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "submit ${*:1:$#-1}: expected one line on stderr, got: $err"
  [[ "$err" == "submit: error: "*"$text"* ]] || fail "submit ${*:1:$#-1}: expected '$text' in: $err"
  [ ! -s "$FAKE_SBATCH_LOG" ] || fail "submit ${*:1:$#-1} submitted: $(cat "$FAKE_SBATCH_LOG")"
}

refused --only 4 "--only 4: shard 4 is outside 0..3 (the run has 4 shards; --shards to change it)"
refused --only 0,2-7 "--only 0,2-7: shard 7 is outside 0..3"
refused --only 3-1 "--only 3-1: the range 3-1 runs backwards"
refused --only 1,x "--only must be shard numbers like 3,5 or 2-4, got '1,x'"
refused --only 5 --shards 5 "--only 5: shard 5 is outside 0..4 (the run has 5 shards"

# The whole array: 0..N-1 with the cap, N passed on; the stitch job after it.
run_submit --max-running 2
[ "$code" -eq 0 ] || fail "submit: exit $code: $err"
array="$(sed -n 1p "$FAKE_SBATCH_LOG")" stitch="$(sed -n 2p "$FAKE_SBATCH_LOG")"
[[ "$array" == *"--array=0-3%2 --requeue"* && "$array" == *"TRISNAP_NUM_SHARDS=4"* ]] || fail "array job: $array"
[[ "$array" != *TRISNAP_SHARD_IS_TASK_ID* ]] || fail "the whole array must take its shard less SLURM_ARRAY_TASK_MIN: $array"
[[ "$stitch" == *"--dependency=afterok:1001 --kill-on-invalid-dep=yes"* ]] || fail "stitch job: $stitch"
[[ "$out" == *"array job 1001: snap-tiles tasks 0-3 of 4 shards"* ]] || fail "stdout: $out"

# Shards run again: the array index is the shard; the last shard and a range within N are fine.
run_submit --only 1,2-3
[ "$code" -eq 0 ] || fail "submit --only 1,2-3: exit $code: $err"
array="$(sed -n 1p "$FAKE_SBATCH_LOG")"
[[ "$array" == *"--array=1,2-3%8"* && "$array" == *"TRISNAP_SHARD_IS_TASK_ID=1"* ]] || fail "array job: $array"
run_submit --only 7 --shards 8
[ "$code" -eq 0 ] || fail "submit --only 7 --shards 8: exit $code: $err"
[[ "$(sed -n 1p "$FAKE_SBATCH_LOG")" == *"TRISNAP_NUM_SHARDS=8"* ]] || fail "--shards 8 not passed on"
echo "submit_test: passed"
