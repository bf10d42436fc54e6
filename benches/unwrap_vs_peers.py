#!/usr/bin/env python3
"""The default unwrap against xatlas and Blender, one run, same meshes, same machine; and
bijective SLIM against plain SLIM.

Table 1, for every manifold mesh given (default: every disk_*, holes_* and closed_* mesh of the
mesh folder except the subdivided *_loop* ones):
  - uvflat: `uvflat.unwrap(V, F)` (the library's default: islands under L2 1.5, repaired or
    split where the conformal map folds, packed, verified);
  - uvflat ≤S: the same with `max_stretch=S` (`--tight S`, default 1.01; 0 leaves it out);
  - xatlas: `xatlas.Atlas().add_mesh(V, F); generate()` with its default options (PyPI
    `xatlas`, its own chart growing and packer);
  - Blender: `bpy.ops.uv.unwrap(method='ANGLE_BASED', margin=0.005)` then
    `bpy.ops.uv.pack_islands(rotate=True, margin=0.005)` on the whole mesh, everything selected,
    no seams marked (Blender 4.5 as the PyPI module `bpy`).
Every figure is measured here from the output UVs by this script's numpy code, the same way
for the three tools, except `overlaps`, which is the library's exact checker
(`uvflat.check_layout`: crossing or touching boundary-edge pairs plus nested islands; it reads
only the UVs and is blind to which tool made them):
  - islands: connected components of UV triangles sharing a UV vertex (Blender's per-corner
    UVs are welded per vertex where equal);
  - flips: triangles whose orientation is opposite to their own island's (a mirrored island
    is not a flip), plus zero-area ones;
  - L2: Sander et al. 2001 L2 stretch of the whole layout after one global scale; max island
    L2: the largest L2 of one island measured alone;
  - angle°: mean |UV corner angle − 3D corner angle| in degrees;
  - s: wall seconds of the call (median of --repeats runs), the mesh already in memory.

Table 2, on the disk_* meshes, for each method of --bijective-methods (default slim):
`uvflat.nonlinear_map(V, F, method)` against the same with `bijective=True`: boundary
crossings (the exact checker), L2, final energy, seconds (median).

Usage: python benches/unwrap_vs_peers.py [--repeats N] [--skip-blender] [--skip-bijective] [--skip-peers]
       [--tight S] [--bijective-methods m1,m2] [name-filter ...]
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "data"))
os.environ.setdefault("UVFLAT_LIBRARY", os.path.join(ROOT, "target", "release", "libuvflat.so"))
import uvflat  # noqa: E402
import xatlas  # noqa: E402
import meshes  # noqa: E402  (tests/data/meshes.py)


def read_obj(path):
    verts, tris = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) - 1 for tok in line.split()[1:]]
                for k in range(1, len(idx) - 1):
                    tris.append([idx[0], idx[k], idx[k + 1]])
    return np.asarray(verts, dtype=np.float64), np.asarray(tris, dtype=np.int64)


def islands_of(n_uv, ft):
    """Island of every triangle: components of the graph joining a triangle's UV vertices."""
    parent = np.arange(n_uv)

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b, c in ft:
        ra = find(a)
        parent[find(b)] = ra
        parent[find(c)] = ra
    roots = np.array([find(x) for x in ft[:, 0]])
    _, island = np.unique(roots, return_inverse=True)
    return island, int(island.max()) + 1 if len(island) else 0


def corner_angles(p0, p1, p2):
    def angle(a, b, c):
        u, v = b - a, c - a
        cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) if u.shape[1] == 2 else np.linalg.norm(np.cross(u, v), axis=1)
        return np.arctan2(cross, np.einsum("ij,ij->i", u, v))

    return np.stack([angle(p0, p1, p2), angle(p1, p2, p0), angle(p2, p0, p1)], axis=1)


def stretch_l2(P, Q, island=None, count=1):
    """Sander L2 stretch of triangles P (3 × (m, 3)) mapped from UV triangles Q (3 × (m, 2)),
    each island scaled alone to its 3D area; one value per island (islands: `island` ids)."""
    island = np.zeros(len(P[0]), dtype=np.int64) if island is None else island
    e1, e2 = Q[1] - Q[0], Q[2] - Q[0]
    area2 = np.abs(0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]))
    area3 = 0.5 * np.linalg.norm(np.cross(P[1] - P[0], P[2] - P[0]), axis=1)
    ok = area2 > 0
    s1, s2 = P[1] - P[0], P[2] - P[0]
    # Stretch of the map UV → surface before scaling: |f_u|² + |f_v|², f_u = (s1 d2v − s2 d1v)/2A.
    a2 = np.where(ok, area2, 1.0)[:, None]
    fu = (s1 * e2[:, 1:2] - s2 * e1[:, 1:2]) / (2 * a2)
    fv = (s2 * e1[:, 0:1] - s1 * e2[:, 0:1]) / (2 * a2)
    sq = np.where(ok, (np.einsum("ij,ij->i", fu, fu) + np.einsum("ij,ij->i", fv, fv)) / 2, 0.0)
    a3_ok = np.where(ok, area3, 0.0)
    per = lambda w: np.bincount(island, weights=w, minlength=count)  # noqa: E731
    # Scaling an island's UVs by k divides σ² by k², k² = A3 / A2 of the island.
    scale = per(area3) / np.maximum(per(area2), 1e-300)
    return np.sqrt(per(a3_ok * sq) / np.maximum(per(a3_ok), 1e-300) / scale)


def measure(V, F, uv, ft):
    P = [V[F[:, k]] for k in range(3)]
    Q = [uv[ft[:, k]] for k in range(3)]
    e1, e2 = Q[1] - Q[0], Q[2] - Q[0]
    signed = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    island, count = islands_of(len(uv), ft)
    sign = np.sign(np.bincount(island, weights=signed, minlength=count))
    flips = int(np.sum(np.sign(signed) != sign[island]))
    # The exact checker wants counter-clockwise islands: mirror the clockwise ones in place
    # (about their own centre, so they do not move onto other islands).
    island_of_uv = np.zeros(len(uv), dtype=np.int64)
    island_of_uv[ft.reshape(-1)] = np.repeat(island, 3)
    oriented = uv.copy()
    for i in np.flatnonzero(sign < 0):
        members = island_of_uv == i
        lo, hi = uv[members, 0].min(), uv[members, 0].max()
        oriented[members, 0] = lo + hi - uv[members, 0]
    check = uvflat.check_layout(oriented, ft)
    worst = float(stretch_l2(P, Q, island, count).max())
    angle = float(np.degrees(np.mean(np.abs(corner_angles(*Q) - corner_angles(*P)))))
    return {"islands": count, "flips": flips, "overlaps": check.overlaps, "l2": float(stretch_l2(P, Q)[0]), "max_l2": worst,
            "angle": angle}


def run_uvflat(V, F, max_stretch=1.5):
    r = uvflat.unwrap(V, F, max_stretch=max_stretch)
    return r.uv, r.triangles.astype(np.int64)


def run_xatlas(V, F):
    atlas = xatlas.Atlas()
    atlas.add_mesh(V.astype(np.float32), F.astype(np.uint32))
    atlas.generate()
    vmapping, indices, uvs = atlas[0]
    # Per-corner UV vertices of the input triangles (xatlas keeps the triangle order).
    return uvs.astype(np.float64), indices.astype(np.int64), vmapping


def run_blender(V, F):
    import bpy

    sys.path.insert(0, HERE)
    from blender_abf import blender_object  # a fresh mesh object, in Edit Mode, all selected

    me = blender_object(V, F).data
    start = time.perf_counter()
    assert bpy.ops.uv.unwrap(method="ANGLE_BASED", margin=0.005) == {"FINISHED"}
    assert bpy.ops.uv.pack_islands(rotate=True, margin=0.005) == {"FINISHED"}
    seconds = time.perf_counter() - start
    bpy.ops.object.mode_set(mode="OBJECT")
    loop_uv = np.zeros(2 * len(me.loops), dtype=np.float32)
    me.uv_layers.active.uv.foreach_get("vector", loop_uv)
    corner = loop_uv.reshape(-1, 2).astype(np.float64).reshape(-1, 3, 2)
    # Weld equal UVs of one vertex into one UV vertex (Blender stores UVs per corner).
    key = np.concatenate([F.reshape(-1, 1).astype(np.float64), corner.reshape(-1, 2)], axis=1)
    _, index = np.unique(key, axis=0, return_inverse=True)
    index = index.reshape(-1)
    uv = np.zeros((index.max() + 1, 2))
    uv[index] = corner.reshape(-1, 2)
    return seconds, uv, index.reshape(-1, 3)


def timed(run, repeats):
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - start)
    return statistics.median(times), out


def peers_table(mesh_dir, names, repeats, blender, tight):
    print("| mesh | faces | tool | islands | flips | overlaps | L2 | max island L2 | angle° | s |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    tight_label = f"uvflat ≤{tight:g}"
    verdicts = {"uvflat": [], tight_label: []}
    for name in names:
        V, F = read_obj(os.path.join(mesh_dir, name))
        rows = []
        seconds, (uv, ft) = timed(lambda: run_uvflat(V, F), repeats)
        rows.append(("uvflat", measure(V, F, uv, ft), seconds))
        if tight:
            seconds, (uv, ft) = timed(lambda: run_uvflat(V, F, tight), repeats)
            rows.append((tight_label, measure(V, F, uv, ft), seconds))
        seconds, (uv, ft, vmap) = timed(lambda: run_xatlas(V, F), repeats)
        rows.append(("xatlas", measure(V, vmap[ft], uv, ft), seconds))
        if blender:
            times = []
            for _ in range(repeats):
                s, uv, ft = run_blender(V, F)
                times.append(s)
            rows.append(("Blender", measure(V, F, uv, ft), statistics.median(times)))
        for label, m, s in rows:
            print(f"| {name[:-4]} | {len(F)} | {label} | {m['islands']} | {m['flips']} | {m['overlaps']} | "
                  f"{m['l2']:.3f} | {m['max_l2']:.3f} | {m['angle']:.3f} | {s:.3f} |", flush=True)
        xa = dict((label, m) for label, m, _ in rows)["xatlas"]
        for label, m, _ in rows:
            if label in verdicts:
                verdicts[label].append((name[:-4], m["islands"] < xa["islands"], m["l2"] < xa["l2"]))
    print()
    for label, rows in verdicts.items():
        both = [n for n, fewer, lower in rows if fewer and lower]
        print(f"{label}: fewer islands and lower L2 than xatlas on {len(both)} of {len(rows)}; not on: "
              + ", ".join(f"{n} (fewer {fewer}, lower {lower})" for n, fewer, lower in rows if not (fewer and lower)))


def bijective_table(mesh_dir, names, repeats, method="slim"):
    print(f"{method}:\n")
    print("| mesh | faces | plain crossings | bijective crossings | plain L2 | bijective L2 | plain energy | "
          "bijective energy | plain s | bijective s | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    ratios = []
    for name in names:
        V, F = read_obj(os.path.join(mesh_dir, name))
        row = []
        for bijective in (False, True):
            s, (uv, report) = timed(lambda: uvflat.nonlinear_map(V, F, method, bijective=bijective), repeats)
            check = uvflat.check_layout(uv, F)
            l2 = float(stretch_l2([V[F[:, k]] for k in range(3)], [uv[F[:, k]] for k in range(3)])[0])
            row.append((check.overlaps, l2, report.final_energy, s))
        ratios.append(row[1][3] / row[0][3])
        print(f"| {name[:-4]} | {len(F)} | {row[0][0]} | {row[1][0]} | {row[0][1]:.4f} | {row[1][1]:.4f} | "
              f"{row[0][2]:.5g} | {row[1][2]:.5g} | {row[0][3]:.2f} | {row[1][3]:.2f} | {ratios[-1]:.2f} |", flush=True)
    print(f"\nmedian time ratio bijective / plain: {statistics.median(ratios):.2f}\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("filters", nargs="*")
    parser.add_argument("--meshes", default=os.environ.get("UVFLAT_MESHES"),
                        help="a folder of plain OBJ meshes (default: the test meshes, unpacked)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--skip-blender", action="store_true")
    parser.add_argument("--skip-bijective", action="store_true")
    parser.add_argument("--skip-peers", action="store_true", help="only the bijective tables")
    parser.add_argument("--bijective-methods", default="slim",
                        help="comma-separated non-linear methods of the bijective tables (default: slim)")
    parser.add_argument("--tight", type=float, default=1.01,
                        help="also run uvflat.unwrap with this stretch bound (0: do not)")
    args = parser.parse_args()
    args.meshes = args.meshes or str(meshes.unpacked_dir())
    names = sorted(n for n in os.listdir(args.meshes) if n.endswith(".obj") and n.startswith(("disk_", "holes_", "closed_"))
                   and "_loop" not in n)
    if args.filters:
        names = [n for n in names if any(f in n for f in args.filters)]
    print(f"uvflat {uvflat.version()}, xatlas (PyPI), load {os.getloadavg()}")
    print()
    if not args.skip_peers:
        peers_table(args.meshes, names, args.repeats, not args.skip_blender, args.tight)
    if not args.skip_bijective:
        print()
        for method in args.bijective_methods.split(","):
            bijective_table(args.meshes, [n for n in names if n.startswith("disk_")], args.repeats, method)


if __name__ == "__main__":
    main()
