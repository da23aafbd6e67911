#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets (tests/fuzz/corpus/<target>/<name>).

Seeds are named after what they exercise. Crash reproducers found by fuzzing are added to the
same folders by hand (named crash-<what>), not by this script. Run from anywhere:
    python3 tests/fuzz/make_seeds.py
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


# ---- WKB (little endian, ISO type codes: +1000 Z, +2000 M, +3000 ZM) -------------------------

def wkb_points(points, dims):
    out = struct.pack("<I", len(points))
    for p in points:
        out += struct.pack("<" + "d" * dims, *p)
    return out


def wkb(type_code, body):
    return struct.pack("<BI", 1, type_code) + body


def polygon(rings, dims=2, base=3):
    return wkb(base + {2: 0, 3: 1000, 4: 3000}[dims], struct.pack("<I", len(rings)) + b"".join(wkb_points(r, dims) for r in rings))


def linestring(points, dims=2, base=2):
    return wkb(base + {2: 0, 3: 1000, 4: 3000}[dims], wkb_points(points, dims))


def collection(type_code, parts):
    return wkb(type_code, struct.pack("<I", len(parts)) + b"".join(parts))


SQUARE = [(0, 0), (10, 0), (10, 10), (0, 10), (0, 0)]
HOLE = [(2, 2), (2, 4), (4, 4), (4, 2), (2, 2)]


def wkb_seeds():
    write("ogr_wkb", "triangle", polygon([[(0, 0), (1, 0), (0, 1), (0, 0)]]))
    write("ogr_wkb", "square_with_hole", polygon([SQUARE, HOLE]))
    write("ogr_wkb", "polygon_z", polygon([[(0, 0, 1), (10, 0, 2), (10, 10, 3), (0, 0, 1)]], dims=3))
    write("ogr_wkb", "polygon_zm", polygon([[(0, 0, 1, 7), (10, 0, 2, 7), (10, 10, 3, 7), (0, 0, 1, 7)]], dims=4))
    write("ogr_wkb", "multipolygon", collection(6, [polygon([SQUARE]), polygon([[(20, 0), (30, 0), (30, 10), (20, 0)]])]))
    write("ogr_wkb", "multipolygon_with_empty_part", collection(6, [polygon([SQUARE]), polygon([])]))
    write("ogr_wkb", "polygon_with_empty_ring", polygon([SQUARE, []]))
    write("ogr_wkb", "unclosed_ring", polygon([[(0, 0), (10, 0), (10, 10)]]))
    write("ogr_wkb", "linestring", linestring([(0, 0), (5, 5), (10, 0)]))
    write("ogr_wkb", "linestring_z", linestring([(0, 0, 1), (5, 5, 2)], dims=3))
    write("ogr_wkb", "multilinestring", collection(5, [linestring([(0, 0), (1, 1)]), linestring([])]))
    write("ogr_wkb", "nan_coordinate", polygon([[(0, 0), (math.nan, 0), (10, 10), (0, 0)]]))
    write("ogr_wkb", "infinite_coordinate", linestring([(0, 0), (math.inf, 1)]))
    write("ogr_wkb", "huge_coordinates", polygon([[(0, 0), (1e308, 0), (1e308, 1.7e308), (0, 0)]]))
    write("ogr_wkb", "point", wkb(1, struct.pack("<dd", 1, 2)))
    write("ogr_wkb", "empty_point", wkb(1, struct.pack("<dd", math.nan, math.nan)))
    write("ogr_wkb", "multipoint", collection(4, [wkb(1, struct.pack("<dd", 1, 2))]))
    write("ogr_wkb", "geometry_collection", collection(7, [polygon([SQUARE]), linestring([(0, 0), (1, 1)])]))
    write("ogr_wkb", "empty_polygon", polygon([]))
    arc = wkb(8, wkb_points([(0, 0), (5, 5), (10, 0), (5, -5), (0, 0)], 2))
    write("ogr_wkb", "circularstring", arc)
    write("ogr_wkb", "curvepolygon", collection(10, [arc]))
    compound = collection(9, [wkb(8, wkb_points([(0, 0), (5, 5), (10, 0)], 2)), linestring([(10, 0), (0, 0)])])
    write("ogr_wkb", "compoundcurve", compound)
    write("ogr_wkb", "curvepolygon_compound", collection(10, [compound]))
    write("ogr_wkb", "multisurface", collection(12, [collection(10, [arc]), polygon([SQUARE])]))
    write("ogr_wkb", "multicurve", collection(11, [arc, linestring([(0, 0), (1, 1)])]))
    triangle = polygon([[(0, 0), (1, 0), (0, 1), (0, 0)]], base=17)
    write("ogr_wkb", "tin", collection(16, [triangle, triangle]))
    write("ogr_wkb", "polyhedralsurface", collection(15, [polygon([SQUARE])]))
    write("ogr_wkb", "big_endian_triangle", struct.pack(">BII", 0, 3, 1) + struct.pack(">I", 4)
          + b"".join(struct.pack(">dd", *p) for p in [(0, 0), (1, 0), (0, 1), (0, 0)]))


# ---- engine problems, in fuzz_snap_decode.cpp's format ------------------------------------------

def pick(predicate):
    """The first byte value for which predicate(b) holds."""
    for b in range(256):
        if predicate(b):
            return b
    raise ValueError("no byte")


def snap_seed(tolerance, features, coords="grid", unit_exp=0, origin=None, edge=0, sliver=0, grid=0):
    """tolerance: a float (raw double). features: (kind, parts) with kind in polygon,
    multipolygon, line, multiline; parts: list of rings/lines (lists of points, in units of the
    grid step, or raw doubles). Rings are closed by the decoder unless given as ('open', pts)."""
    mode = 1 | (edge << 1) | (sliver << 3) | (grid << 5)
    out = bytes([mode]) + struct.pack("<d", tolerance) + bytes([0, 0])
    cmode = 3 if coords == "raw" else 0
    cmode |= (unit_exp + 6) << 2
    if origin is not None:
        cmode |= 0x20
    out += bytes([cmode])
    if origin is not None:
        out += struct.pack("<dd", *origin)
    out += bytes([pick(lambda b: 1 + b % 6 == len(features))])
    kinds = {"polygon": 0, "multipolygon": 1, "line": 2, "multiline": 3}
    for kind, parts in features:
        k = kinds[kind]
        polygonal = k < 2
        if polygonal:
            # parts: list of polygons, each a list of rings
            polys = parts if k == 1 else [parts]
            n_parts, n_rings = len(polys), len(polys[0])
            assert all(len(p) == n_rings for p in polys)
            head = pick(lambda b: b & 3 == k and (k == 0 or 1 + (b >> 2) % 3 == n_parts) and 1 + (b >> 4) % 3 == n_rings)
            out += bytes([head])
            for poly in polys:
                for ring in poly:
                    out += path_bytes(ring, coords, True)
        else:
            lines = parts if k == 3 else [parts]
            head = pick(lambda b: b & 3 == k and (k == 2 or 1 + (b >> 2) % 3 == len(lines)))
            out += bytes([head])
            for line in lines:
                out += path_bytes(line, coords, False)
    return out


def path_bytes(path, coords, ring):
    open_ring = isinstance(path, tuple)
    points = path[1] if open_ring else path
    n = len(points)
    head = pick(lambda b: b % 13 == n and bool(b & 0x80) == open_ring)
    out = bytes([head])
    for x, y in points:
        out += struct.pack("<dd", x, y) if coords == "raw" else struct.pack("<hh", x, y)
    return out


def snap_seeds():
    tri = [[(0, 0), (1, 0), (0, 1)]]
    # The tolerances: refused by validate(), never snapped.
    for name, t in [("tolerance_1e308", 1e308), ("tolerance_5e307", 5e307), ("tolerance_1.7e308", 1.7e308),
                    ("tolerance_1e145", 1e145), ("tolerance_nan", math.nan), ("tolerance_negative", -1.0)]:
        write("snap", name, snap_seed(t, [("polygon", tri)], coords="raw"))
    # A 1e-200 square at t = 1e-202 (refused: t*t underflows) and at t = 1e-140 (collapses, 201).
    square = [[(0, 0), (1e-200, 0), (1e-200, 1e-200), (0, 1e-200)]]
    write("snap", "square_1e-200_t_1e-202", snap_seed(1e-202, [("polygon", square)], coords="raw"))
    write("snap", "square_1e-200_t_1e-140", snap_seed(1e-140, [("polygon", square)], coords="raw"))
    # Coordinates beyond 2^500 at the largest tolerance: huge (109), not overflowing squares.
    huge = [[(0, 0), (1e155, 0), (1e155, 1e155), (0, 1e155)]]
    write("snap", "coordinates_1e155_t_1e144", snap_seed(1e144, [("polygon", huge)], coords="raw"))
    write("snap", "nan_coordinate", snap_seed(1.0, [("polygon", [[(0, 0), (math.nan, 0), (10, 10)]]),
                                                    ("polygon", [[(20, 0), (30, 0), (30, 10)]])], coords="raw"))
    # Grid coordinates in steps of t (unit_exp 6 = t * 2^0).
    g = dict(unit_exp=6 - 6)
    write("snap", "collinear_vertices", snap_seed(1.0, [("polygon", [[(0, 0), (5, 0), (10, 0), (10, 10), (0, 10)]]),
                                                        ("line", [(0, 0), (3, 0), (7, 0), (10, 0)])], **g))
    write("snap", "ring_of_collinear_points", snap_seed(1.0, [("polygon", [[(0, 0), (5, 0), (10, 0)]])], **g))
    write("snap", "bowtie", snap_seed(1.0, [("polygon", [[(0, 0), (10, 10), (10, 0), (0, 10)]])], **g))
    write("snap", "two_squares_sharing_an_edge", snap_seed(1.0, [("polygon", [[(0, 0), (10, 0), (10, 10), (0, 10)]]),
                                                                 ("polygon", [[(10, 0), (20, 0), (20, 10), (10, 10)]])], **g))
    write("snap", "unclosed_ring", snap_seed(1.0, [("polygon", [("open", [(0, 0), (10, 0), (10, 10), (0, 10)])])], **g))
    write("snap", "repeated_points", snap_seed(1.0, [("polygon", [[(0, 0), (0, 0), (10, 0), (10, 10), (10, 10), (0, 10)]])], **g))
    write("snap", "square_with_hole", snap_seed(1.0, [("polygon", [[(0, 0), (20, 0), (20, 20), (0, 20)],
                                                                   [(5, 5), (5, 15), (15, 15), (15, 5)]])], **g))
    write("snap", "multipolygon_and_multiline", snap_seed(1.0, [
        ("multipolygon", [[[(0, 0), (10, 0), (10, 10), (0, 10)]], [[(12, 0), (20, 0), (20, 10), (12, 10)]]]),
        ("multiline", [[(-5, 5), (25, 5)], [(5, -5), (5, 15)]])], **g))
    write("snap", "line_crossing_a_polygon", snap_seed(1.0, [("polygon", [[(0, 0), (10, 0), (10, 10), (0, 10)]]),
                                                             ("line", [(-5, 5), (15, 5)])], **g))
    # Steps of t/16 (unit_exp 2): vertices and edges closer than t, every snapping case.
    f = dict(unit_exp=2 - 6)
    write("snap", "vertex_cluster", snap_seed(1.0, [("polygon", [[(0, 0), (160, 0), (80, 160)]]),
                                                    ("polygon", [[(5, 3), (-160, 20), (-80, 160)]]),
                                                    ("polygon", [[(-4, -5), (-100, -160), (60, -160)]])], **f))
    write("snap", "sliver_between_neighbours", snap_seed(1.0, [("polygon", [[(0, 0), (160, 0), (160, 160), (0, 160)]]),
                                                               ("polygon", [[(164, 0), (320, 0), (320, 160), (166, 160)]])], **f))
    write("snap", "polygon_thinner_than_t", snap_seed(1.0, [("polygon", [[(0, 0), (160, 0), (160, 8), (0, 8)]])], **f))
    write("snap", "spike", snap_seed(1.0, [("polygon", [[(0, 0), (160, 0), (160, 160), (85, 160), (80, 320), (78, 160), (0, 160)]])], **f))
    write("snap", "t_junction", snap_seed(1.0, [("polygon", [[(0, 0), (160, 0), (160, 160), (0, 160)]]),
                                                ("polygon", [[(165, 80), (320, 0), (320, 160)]])], grid=2, **f))
    write("snap", "short_line", snap_seed(1.0, [("line", [(0, 0), (9, 0)])], **f))
    write("snap", "edge_separation_1_sliver_0", snap_seed(1.0, [("polygon", [[(0, 0), (160, 0), (160, 160), (0, 160)]]),
                                                                ("line", [(170, -10), (168, 170)])], edge=1, sliver=1, **f))
    # Geographic-looking coordinates (origin 4.35, 52.0) at 1e-6.
    write("snap", "geographic_origin", snap_seed(1e-6, [("polygon", [[(0, 0), (100, 0), (100, 100), (0, 100)]]),
                                                        ("polygon", [[(101, 0), (200, 0), (200, 100), (102, 100)]])],
                                                 origin=(4.35, 52.0), unit_exp=-2))


# ---- TOML configs --------------------------------------------------------------------------------

def config_seeds():
    configs = os.path.join(HERE, "..", "..", "configs")
    for name in sorted(os.listdir(configs)):
        if name.endswith(".toml"):
            with open(os.path.join(configs, name), "rb") as f:
                write("config", "preset_" + name[:-5], f.read())
    seeds = {
        "all_keys": "[snap]\ntolerance = 0.5\nedge_separation = 1.0\nsliver_factor = 0.25\ngrid = 0.1\n"
                    "max_drift_factor = 3\nmax_operations = 1000\n[tiling]\nsize = 20.0\nvertex_budget = 5000\n"
                    "halo = 8\nmax_growth = 2\nno_tiles = false\n[run]\nthreads = 2\n",
        "threads_wraps": "[run]\nthreads = 4294967297\n",
        "max_operations_beyond_64_bits": "[snap]\nmax_operations = 99999999999999999999\n",
        "vertex_budget_huge": "[tiling]\nvertex_budget = 9223372036854775807\n",
        "tolerance_1e308": "[snap]\ntolerance = 1e308\n",
        "tolerance_nan": "[snap]\ntolerance = nan\n",
        "tolerance_inf": "[snap]\ntolerance = -inf\n",
        "both_tolerances": "[snap]\ntolerance = 1\ntolerance_m = 1\n",
        "unknown_key": "[snap]\ntolerence = 1\n",
        "unknown_section": "[tiles]\nsize = 1\n",
        "wrong_type": "[run]\nthreads = \"many\"\n",
        "inline_table": "snap = { tolerance = 0.5, grid = 0.1 }\nrun = { threads = 1 }\n",
        "dotted_keys": "snap.tolerance = 0.5\ntiling.halo = 4\n",
        "section_not_a_table": "snap = 3\n",
        "array_of_tables": "[[snap]]\ntolerance = 1\n",
        "duplicate_section": "[snap]\ntolerance = 1\n[snap]\ngrid = 0\n",
        "nested_arrays": "[snap]\ntolerance = " + "[" * 300 + "]" * 300 + "\n",
        "empty": "",
        "nul_byte": "[snap]\0tolerance = 1\n",
        "utf8_key": "[snap]\n\"tol\u00e9rance\" = 1\n",
    }
    for name, text in seeds.items():
        write("config", name, text)


if __name__ == "__main__":
    wkb_seeds()
    snap_seeds()
    config_seeds()
