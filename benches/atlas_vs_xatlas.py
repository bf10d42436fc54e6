#!/usr/bin/env python3
"""uvflat `--atlas` and `--cut auto` against xatlas (PyPI `xatlas`) on every closed_* and holes_*
test mesh (tests/data/meshes), in one run; prints a Markdown table.

Run through benches/atlas_vs_xatlas.sh (creates target/xatlas-venv with xatlas and numpy, builds
the release CLI). For every mesh and tool the same measurements are taken from the output UVs
by this script's own numpy code:
- charts: connected components of the UV triangles (sharing a UV vertex index);
- seam: 3D length of the input edges whose two sides have different UV vertices, over the
  total edge length;
- L2: Sander et al. 2001 L2 stretch after one global scale (UV area = 3D area);
- flips: triangles whose orientation is opposite to the majority of their own chart (xatlas may
  mirror a whole chart, which is not a flip);
- util: UV area over the area of the square around the UVs' bounding box;
- s: wall seconds, cpu: CPU seconds (all threads). uvflat runs as the CLI (`uvflat unwrap
  ... --json`, OBJ reading and writing included); xatlas as `Atlas.add_mesh` + `generate()`
  with default options (OBJ read by this script, not timed).
"""

import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np
import xatlas

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "data"))
import meshes  # noqa: E402  (tests/data/meshes.py)

MESHES = str(meshes.unpacked_dir())
CLI = os.path.join(ROOT, "target", "release", "uvflat")


def load_obj(path):
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) for tok in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(v) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    f.append([idx[0], idx[k], idx[k + 1]])
    return np.array(v, dtype=np.float64), np.array(f, dtype=np.int64)


def load_uv_obj(path):
    uv, ft = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("vt "):
                uv.append([float(x) for x in line.split()[1:3]])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[1]) - 1 for tok in line.split()[1:]]
                for k in range(1, len(idx) - 1):
                    ft.append([idx[0], idx[k], idx[k + 1]])
    return np.array(uv, dtype=np.float64), np.array(ft, dtype=np.int64)


def components(n_uv, ft):
    parent = np.arange(n_uv)

    def find(x):
        root = x
        while parent[root] != root:
            root = parent[root]
        while parent[x] != root:
            parent[x], x = root, parent[x]
        return root

    for a, b, c in ft:
        ra, rb, rc = find(a), find(b), find(c)
        parent[rb] = ra
        parent[find(rc)] = ra
    roots = np.array([find(x) for x in range(n_uv)])
    _, chart_of_uv = np.unique(roots, return_inverse=True)
    return chart_of_uv[ft[:, 0]], chart_of_uv.max() + 1 if n_uv else 0


def measure(p, f, uv, ft):
    q = uv[ft]
    P = p[f]
    a3 = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    d1, d2 = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
    auv = 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    chart, charts = components(len(uv), ft)
    sign = np.sign(np.bincount(chart, weights=auv, minlength=charts))
    flips = int((np.sign(auv) != sign[chart]).sum() + (auv == 0).sum())
    s, t = q[:, :, 0], q[:, :, 1]
    two_a = 2 * auv[:, None]
    ss = (P[:, 0] * (t[:, 1] - t[:, 2])[:, None] + P[:, 1] * (t[:, 2] - t[:, 0])[:, None]
          + P[:, 2] * (t[:, 0] - t[:, 1])[:, None]) / two_a
    st = (P[:, 0] * (s[:, 2] - s[:, 1])[:, None] + P[:, 1] * (s[:, 0] - s[:, 2])[:, None]
          + P[:, 2] * (s[:, 1] - s[:, 0])[:, None]) / two_a
    ok = auv != 0
    stretch2 = ((ss * ss).sum(1) + (st * st).sum(1)) / 2
    scale = np.abs(auv).sum() / a3.sum()
    l2 = float(np.sqrt((a3[ok] * stretch2[ok]).sum() / a3[ok].sum() * scale))
    # Seams: input edges (a, b) whose two sides carry different UV vertices.
    half = {}
    for t_, (tri, tri_uv) in enumerate(zip(f, ft)):
        for k in range(3):
            half[(tri[k], tri[(k + 1) % 3])] = (tri_uv[k], tri_uv[(k + 1) % 3])
    seam = total = 0.0
    for (a, b), (ua, ub) in half.items():
        if a > b and (b, a) in half:
            continue
        length = float(np.linalg.norm(p[a] - p[b]))
        total += length
        other = half.get((b, a))
        if other is not None and (other[1], other[0]) != (ua, ub):
            seam += length
    lo, hi = uv.min(0), uv.max(0)
    side = float((hi - lo).max())
    util = float(np.abs(auv).sum() / side**2) if side > 0 else 0.0
    return {"charts": int(charts), "seam": seam / total, "l2": l2, "flips": flips, "util": util}


def run_uvflat(path, mode_args):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.obj")
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        result = subprocess.run([CLI, "unwrap", path, "-o", out, "--json"] + mode_args,
                                capture_output=True, text=True, check=True)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        report = json.loads(result.stdout)
        uv, ft = load_uv_obj(out)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return uv, ft, wall, cpu, report


def run_xatlas(p, f):
    before = resource.getrusage(resource.RUSAGE_SELF)
    start = time.perf_counter()
    atlas = xatlas.Atlas()
    atlas.add_mesh(p.astype(np.float32), f.astype(np.uint32))
    atlas.generate()
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF)
    vmapping, indices, uvs = atlas[0]
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return vmapping, indices.astype(np.int64), uvs.astype(np.float64), wall, cpu


def main():
    names = sorted(n for n in os.listdir(MESHES) if n.endswith(".obj") and n.startswith(("closed_", "holes_")))
    if len(sys.argv) > 1:
        names = [n for n in names if any(a in n for a in sys.argv[1:])]
    print(f"# uptime: {os.popen('uptime').read().strip()}")
    print("| mesh | faces | tool | charts | seam/E | L2 stretch | flips | util | s | cpu s |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for name in names:
        path = os.path.join(MESHES, name)
        p, f = load_obj(path)
        rows = []
        for label, args in [("uvflat --atlas", ["--atlas"]), ("uvflat --cut auto", ["--cut", "auto"])]:
            uv, ft, wall, cpu, _ = run_uvflat(path, args)
            rows.append((label, measure(p, f, uv, ft), wall, cpu))
        vmapping, indices, uvs, wall, cpu = run_xatlas(p, f)
        # xatlas renumbers vertices; map its triangles back to the input vertices for the seams.
        rows.append(("xatlas", measure(p, vmapping[indices], uvs, indices), wall, cpu))
        for label, m, wall, cpu in rows:
            print(f"| {name[:-4]} | {len(f)} | {label} | {m['charts']} | {m['seam']:.4f} | {m['l2']:.4f} | "
                  f"{m['flips']} | {m['util']:.3f} | {wall:.2f} | {cpu:.2f} |", flush=True)
    print(f"# uptime: {os.popen('uptime').read().strip()}")


if __name__ == "__main__":
    main()
