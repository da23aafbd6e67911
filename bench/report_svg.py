"""Hand-written SVG plots for bench/report (no matplotlib): time and memory versus input vertices
(log-log) per tool, and separation and drift (as multiples of T) per data set and tolerance."""
import math
import os
from xml.sax.saxutils import escape

W, H = 900, 500
LEFT, RIGHT, TOP, BOTTOM = 80, 170, 40, 110
COLORS = {"trisnap": "#1b7837", "isr": "#c51b7d", "sr": "#e08214", "geos": "#2166ac", "input": "#777777"}
LABELS = {"trisnap": "trisnap", "isr": "CGAL ISR", "sr": "CGAL SR", "geos": "GEOS setPrecision", "input": "input"}
MARKERS = ["circle", "square", "triangle", "diamond"]


def marker(kind, x, y, color, hollow=False, r=5):
    fill = "none" if hollow else color
    style = f'fill="{fill}" stroke="{color}" stroke-width="1.5"'
    if kind == "circle":
        return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{r}" {style}/>'
    if kind == "square":
        return f'<rect x="{x - r:.1f}" y="{y - r:.1f}" width="{2 * r}" height="{2 * r}" {style}/>'
    if kind == "triangle":
        return f'<polygon points="{x:.1f},{y - r - 1:.1f} {x - r:.1f},{y + r:.1f} {x + r:.1f},{y + r:.1f}" {style}/>'
    return f'<polygon points="{x:.1f},{y - r - 1:.1f} {x + r + 1:.1f},{y:.1f} {x:.1f},{y + r + 1:.1f} {x - r - 1:.1f},{y:.1f}" {style}/>'


def text(x, y, s, size=12, anchor="middle", rotate=None, weight="normal"):
    t = f' transform="rotate({rotate} {x:.1f} {y:.1f})"' if rotate else ""
    return (f'<text x="{x:.1f}" y="{y:.1f}" font-family="sans-serif" font-size="{size}" '
            f'text-anchor="{anchor}" font-weight="{weight}"{t}>{escape(str(s))}</text>')


class Axis:
    """Maps data to pixels on [lo, hi]; log10 when log."""

    def __init__(self, lo, hi, p0, p1, log):
        self.log = log
        if log:
            lo, hi = 10 ** math.floor(math.log10(lo)), 10 ** math.ceil(math.log10(hi))
        elif hi <= lo:
            hi = lo + 1
        self.lo, self.hi, self.p0, self.p1 = lo, hi, p0, p1

    def __call__(self, v):
        f = (lambda x: math.log10(x)) if self.log else (lambda x: x)
        return self.p0 + (f(v) - f(self.lo)) / (f(self.hi) - f(self.lo)) * (self.p1 - self.p0)

    def ticks(self):
        if self.log:
            return [10 ** e for e in range(round(math.log10(self.lo)), round(math.log10(self.hi)) + 1)]
        step = 10 ** math.floor(math.log10((self.hi - self.lo) / 4))
        for m in (1, 2, 5, 10):
            if (self.hi - self.lo) / (step * m) <= 6:
                step *= m
                break
        first = math.ceil(self.lo / step) * step
        return [first + i * step for i in range(int((self.hi - first) / step + 1e-9) + 1)]


def tick_label(v):
    return f"{v:g}" if 1e-3 <= abs(v) < 1e6 or v == 0 else f"1e{round(math.log10(v))}"


def frame(title, xlabel, ylabel, xaxis, yaxis, xticks=None):
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}">',
           f'<rect width="{W}" height="{H}" fill="white"/>', text(W / 2, 22, title, 14, weight="bold"),
           f'<rect x="{LEFT}" y="{TOP}" width="{W - LEFT - RIGHT}" height="{H - TOP - BOTTOM}" fill="none" stroke="#333"/>']
    for v in yaxis.ticks():
        y = yaxis(v)
        out.append(f'<line x1="{LEFT}" x2="{W - RIGHT}" y1="{y:.1f}" y2="{y:.1f}" stroke="#ddd"/>')
        out.append(text(LEFT - 6, y + 4, tick_label(v), 11, "end"))
    for v, name in (xticks if xticks is not None else [(v, tick_label(v)) for v in xaxis.ticks()]):
        x = xaxis(v)
        out.append(f'<line x1="{x:.1f}" x2="{x:.1f}" y1="{TOP}" y2="{H - BOTTOM}" stroke="#eee"/>')
        out.append(text(x, H - BOTTOM + 16, name, 11))
    out.append(text(LEFT + (W - LEFT - RIGHT) / 2, H - 20, xlabel, 12))
    out.append(text(20, TOP + (H - TOP - BOTTOM) / 2, ylabel, 12, rotate=-90))
    return out


def legend(tools, tol_labels, extra=()):
    out, y = [], TOP + 10
    for tool in tools:
        out.append(f'<line x1="{W - RIGHT + 12}" x2="{W - RIGHT + 32}" y1="{y}" y2="{y}" stroke="{COLORS[tool]}" stroke-width="3"/>')
        out.append(text(W - RIGHT + 38, y + 4, LABELS[tool], 11, "start"))
        y += 18
    y += 6
    for i, lab in enumerate(tol_labels):
        out.append(marker(MARKERS[i % len(MARKERS)], W - RIGHT + 22, y, "#333"))
        out.append(text(W - RIGHT + 38, y + 4, f"T = {lab}", 11, "start"))
        y += 18
    for line in extra:
        out.append(text(W - RIGHT + 12, y + 4, line, 10, "start"))
        y += 14
    return out


def tools_present(results, wanted):
    return [t for t in wanted if any(r["tools"].get(t, {}).get("status") in ("ok", "timeout") for r in results)]


def tol_labels(results):
    seen = []
    for r in sorted(results, key=lambda r: r["tolerance_m"] or 0):
        if r["tolerance_label"] not in seen:
            seen.append(r["tolerance_label"])
    return seen


def size_plot(results, key, title, ylabel, path):
    """Log-log of key (wall_s or peak_rss_mb) against input vertices; hollow = timed out (a lower bound)."""
    tools = tools_present(results, ("trisnap", "isr", "sr", "geos"))
    labels = tol_labels(results)
    points = []  # (tool, tol label, x, y, hollow)
    for r in results:
        n = r["tools"].get("trisnap", {}).get("stats", {}).get("input_vertices")
        for tool in tools:
            t = r["tools"].get(tool, {})
            if n and t.get("status") == "ok" or (n and key == "wall_s" and t.get("status") == "timeout"):
                points.append((tool, r["tolerance_label"], n, t[key], t["status"] == "timeout"))
    if not points:
        return False
    xs, ys = [p[2] for p in points], [p[3] for p in points]
    xa = Axis(min(xs), max(xs), LEFT, W - RIGHT, True)
    ya = Axis(min(ys), max(ys), H - BOTTOM, TOP, True)
    out = frame(title, "input vertices", ylabel, xa, ya)
    for tool in tools:
        for i, lab in enumerate(labels):
            pts = sorted((p for p in points if p[0] == tool and p[1] == lab), key=lambda p: p[2])
            if len(pts) > 1:
                d = " ".join(f"{xa(p[2]):.1f},{ya(p[3]):.1f}" for p in pts)
                out.append(f'<polyline points="{d}" fill="none" stroke="{COLORS[tool]}" stroke-opacity="0.5"/>')
            out += [marker(MARKERS[i % len(MARKERS)], xa(p[2]), ya(p[3]), COLORS[tool], p[4]) for p in pts]
    extra = ["hollow: timed out", "(a lower bound)"] if any(p[4] for p in points) else []
    out += legend(tools, labels, extra) + ["</svg>"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return True


def category_plot(results, field, title, ylabel, refs, path, cap):
    """field of each tool's table row per (data set, tolerance) on a categorical x axis; values above
    cap are drawn at cap with their value written beside."""
    tools = tools_present(results, ("trisnap", "isr", "sr", "geos", "input"))
    labels = tol_labels(results)
    cats = [(r["_name"], r["tolerance_label"]) for r in results]
    values = []
    for i, r in enumerate(results):
        for row in r["table"]:
            if row["tool"] in tools and row.get(field) is not None:
                values.append((i, row["tool"], row[field]))
    if not values:
        return False
    top = min(cap, max(max(v for _, _, v in values), max(refs or [0])) * 1.1 or 1)
    xa = Axis(-0.5, len(cats) - 0.5, LEFT, W - RIGHT, False)
    ya = Axis(0, top, H - BOTTOM, TOP, False)
    out = frame(title, "", ylabel, xa, ya, xticks=[])
    for i, (name, lab) in enumerate(cats):  # slanted: 18 categories do not fit side by side
        out.append(text(xa(i) + 4, H - BOTTOM + 12, f"{name} {lab}", 10, "end", rotate=-35))
    for ref in refs:
        out.append(f'<line x1="{LEFT}" x2="{W - RIGHT}" y1="{ya(ref):.1f}" y2="{ya(ref):.1f}" stroke="#000" stroke-dasharray="5,4"/>')
        out.append(text(W - RIGHT - 4, ya(ref) - 4, f"{ref:g}", 10, "end"))
    offsets = {tool: (k - (len(tools) - 1) / 2) * 0.12 for k, tool in enumerate(tools)}
    for i, tool, v in values:
        x, y = xa(i + offsets[tool]), ya(min(v, top))
        out.append(marker(MARKERS[labels.index(cats[i][1]) % len(MARKERS)], x, y, COLORS[tool], v > top, 4))
        if v > top:
            out.append(text(x, y - 7, f"{v:.3g}", 9))
    out += legend(tools, labels, ["dashed: contract", "hollow: off scale"]) + ["</svg>"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return True


def write_plots(results, out_dir):
    """Writes the SVGs beside REPORT.md; returns [(title, path)] of those written."""
    plots = [
        ("Wall time versus input size", "time_vs_vertices.svg",
         lambda p: size_plot(results, "wall_s", "Wall time (whole process) vs input vertices", "seconds", p)),
        ("Peak memory versus input size", "memory_vs_vertices.svg",
         lambda p: size_plot(results, "peak_rss_mb", "Peak RSS vs input vertices", "MB", p)),
        ("Smallest vertex-edge distance", "separation_vertex_edge.svg",
         lambda p: category_plot(results, "min_ve_T", "Smallest vertex-edge distance / T (contract >= 0.5)",
                                 "min vertex-edge / T", [0.5], p, 3)),
        ("Smallest vertex-vertex distance", "separation_vertex_vertex.svg",
         lambda p: category_plot(results, "min_vv_T", "Smallest vertex-vertex distance / T (contract >= 1)",
                                 "min vertex-vertex / T", [1.0], p, 5)),
        ("Drift (largest Hausdorff distance)", "drift.svg",
         lambda p: category_plot(results, "max_hausdorff_T", "Largest Hausdorff distance per feature / T",
                                 "max Hausdorff / T", [], p, 10)),
    ]
    written = []
    for title, name, make in plots:
        path = os.path.join(out_dir, name)
        if make(path):
            written.append((title, path))
    return written
