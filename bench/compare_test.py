#!/usr/bin/env python3
"""CTest for bench/compare (label cli): runs it on a tiny hand-made layer and checks that the JSON
table has every tool and that the measurements can fail:
 - CGAL ISR at pixel T keeps what Halperin & Packer promise (vertices >= T apart, vertex-edge >= T/2);
 - plain SR on the same layer leaves a vertex closer than T/2 to an edge (about 0.2 T): the same
   measurement, reporting a violation, so the ISR check is not vacuous;
 - trisnap keeps its contract, 0 crossings, 0 invalid;
 - bench/report --render-only writes REPORT.md from that table and keeps the hand-written sections
   below its KEEP_MARK line as they were.
The layer: three overlapping triangles (GeoJSON, T = 1) whose edges pass near the others' vertices;
found by searching random triangles for an SR violation, then frozen here.

  compare_test.py TRISNAP RUNNER WORKDIR     exit 0 pass, 1 fail, 77 skipped (no `trisnap assess`)
"""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TRIANGLES = [
    [[2.17, 4.76], [2.12, 6.64], [0.85, 6.26], [2.17, 4.76]],
    [[1.22, 5.71], [6.26, 7.55], [7.22, 0.2], [1.22, 5.71]],
    [[5.29, 7.28], [6.16, 3.63], [6.0, 2.27], [5.29, 7.28]],
]
TOOLS = ("trisnap", "isr", "sr", "geos", "input")
EPS = 1e-9


def main(trisnap, runner, workdir):
    os.makedirs(workdir, exist_ok=True)
    probe = subprocess.run([trisnap, "assess", "--help"], capture_output=True, text=True)
    if probe.returncode != 0 or "trisnap assess" not in probe.stdout:  # older CLI11 prints the main help
        print("SKIPPED: this trisnap has no `assess` command yet", file=sys.stderr)
        return 77
    layer = os.path.join(workdir, "triangles.geojson")
    with open(layer, "w") as f:
        json.dump({"type": "FeatureCollection", "features": [
            {"type": "Feature", "id": i + 1, "properties": {"id": i + 1},
             "geometry": {"type": "Polygon", "coordinates": [ring]}} for i, ring in enumerate(TRIANGLES)]}, f)
    out_json = os.path.join(workdir, "compare.json")
    p = subprocess.run([sys.executable, os.path.join(HERE, "compare"), layer, "--tolerance", "1",
                        "--tools", ",".join(TOOLS), "--timeout", "60", "--out-dir", workdir, "--json", out_json,
                        "--trisnap", trisnap, "--runner", runner], capture_output=True, text=True)
    print(p.stdout)
    print(p.stderr, file=sys.stderr)
    failures = []
    check = lambda ok, what: ok or failures.append(what)
    check(p.returncode == 0, f"bench/compare exit {p.returncode}")
    with open(out_json) as f:
        report = json.load(f)
    rows = {row["tool"]: row for row in report["table"]}
    for tool in TOOLS:
        check(tool in rows and rows[tool]["status"] == "ok", f"{tool}: missing or not ok in the table")
        check(tool == "input" or (rows.get(tool, {}).get("wall_s") or 0) > 0, f"{tool}: no wall time")
        check(tool == "input" or (rows.get(tool, {}).get("peak_rss_mb") or 0) > 0, f"{tool}: no peak RSS")
        check(report["tools"].get(tool, {}).get("assess") is not None, f"{tool}: not assessed")
    isr, sr, ts = rows.get("isr", {}), rows.get("sr", {}), rows.get("trisnap", {})
    check((isr.get("min_vv_T") or 0) >= 1 - EPS, f"ISR vertex-vertex {isr.get('min_vv_T')} T < T")
    check((isr.get("min_ve_T") or 0) >= 0.5 - EPS, f"ISR vertex-edge {isr.get('min_ve_T')} T < T/2")
    check(isr.get("n_crossings") == 0, f"ISR crossings {isr.get('n_crossings')}")
    check(sr.get("min_ve_T") is not None and sr["min_ve_T"] < 0.5,
          f"SR vertex-edge {sr.get('min_ve_T')} T: expected a violation (< T/2) on this layer")
    check((ts.get("min_vv_T") or 0) >= 1 - EPS and (ts.get("min_ve_T") or 0) >= 0.5 - EPS,
          f"trisnap separations {ts.get('min_vv_T')} T, {ts.get('min_ve_T')} T below its contract")
    check(ts.get("n_crossings") == 0 and ts.get("n_invalid") == 0, "trisnap crossings/invalid not 0")
    check(abs(report["pixel"] - 1.0) < EPS, f"pixel {report['pixel']} != T")
    check("trisnap/isr" in report["ratios"] and "trisnap/geos" in report["ratios"], "ratios missing")
    check(bool(report.get("commit")), "the run's commit is not recorded")
    check_render(out_json, workdir, check)
    for f in failures:
        print(f"FAIL: {f}", file=sys.stderr)
    return 1 if failures else 0


def check_render(out_json, workdir, check):
    """bench/report --render-only on this table (as Andorra's at 10 cm): the generated part is new, the
    hand-written part below the mark stays byte for byte, and a report without the mark gets none."""
    mark = [l for l in open(os.path.join(HERE, "report")) if l.startswith("KEEP_MARK = ")][0].split("=", 1)[1].strip().strip('"')
    results = os.path.join(workdir, "results")
    os.makedirs(results, exist_ok=True)
    with open(out_json) as f, open(os.path.join(results, "compare_andorra_10cm.json"), "w") as g:
        g.write(f.read())
    tail = "## Hand-written\n\nA table that no run makes.\n\n| a | b |\n|---|---|\n| 1 | 2 |\n"
    with open(os.path.join(results, "REPORT.md"), "w") as f:
        f.write("# an old generated part\n\nstale\n\n" + mark + "\n" + tail)
    cmd = [sys.executable, os.path.join(HERE, "report"), "--render-only", "--datasets", "andorra",
           "--tolerances", "0.1", "--results", results]
    p = subprocess.run(cmd, capture_output=True, text=True)
    check(p.returncode == 0, f"bench/report --render-only exit {p.returncode}: {p.stderr.strip()}")
    text = open(os.path.join(results, "REPORT.md")).read()
    check("stale" not in text and "## Headline" in text, "report: the generated part was not rewritten")
    check(f"commit {json.load(open(out_json))['commit']}," in text, "report: the runs' commit is not in the header")
    check(text.endswith("\n" + mark + "\n" + tail), "report: the hand-written part was not kept as it was")
    os.remove(os.path.join(results, "REPORT.md"))
    p = subprocess.run(cmd, capture_output=True, text=True)
    text = open(os.path.join(results, "REPORT.md")).read() if p.returncode == 0 else ""
    check(p.returncode == 0 and "## Headline" in text and mark not in text, "report: a fresh report is wrong")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: compare_test.py TRISNAP RUNNER WORKDIR")
    sys.exit(main(*sys.argv[1:]))
