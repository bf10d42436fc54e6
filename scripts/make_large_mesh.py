"""Makes the optional 1.43M-triangle benchmark mesh that the repository does not hold:
``disk_bimba_cut_loop2.obj.gz``, the test mesh ``disk_bimba_cut`` Loop-subdivided twice
(libigl's ``igl.loop``, PyPI ``libigl``). Point ``UVFLAT_LARGE_MESHES`` at the output folder.

usage: python scripts/make_large_mesh.py OUT_DIR      (needs numpy and libigl: pip install libigl)
"""

import gzip
import os
import sys

import igl
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_obj_gz(path):
    positions, triangles = [], []
    with gzip.open(path, "rt") as f:
        for line in f:
            if line.startswith("v "):
                positions.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                triangles.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    return np.array(positions), np.array(triangles, dtype=np.int64)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    v, f = read_obj_gz(os.path.join(REPO, "tests", "data", "meshes", "disk_bimba_cut.obj.gz"))
    v2, f2 = igl.loop(v, f, 2)
    out = os.path.join(out_dir, "disk_bimba_cut_loop2.obj.gz")
    partial = out + ".partial"
    with gzip.open(partial, "wt") as g:
        g.write("# disk_bimba_cut.obj (tests/data/meshes) Loop-subdivided twice by libigl's igl.loop\n")
        g.write("# license: as disk_bimba_cut.obj (tests/data/meshes/MANIFEST.tsv)\n")
        np.savetxt(g, v2, fmt="v %.17g %.17g %.17g")
        np.savetxt(g, f2 + 1, fmt="f %d %d %d")
    os.replace(partial, out)
    print(f"{out}: {len(v2)} vertices, {len(f2)} triangles")


if __name__ == "__main__":
    main()
