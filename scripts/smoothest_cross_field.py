#!/usr/bin/env python3
"""Singular points of the globally smoothest cross field of a closed triangle mesh.

A yardstick for PGP's singular-triangle rate (README, "Periodic Global Parameterization"),
independent of uvflat's code: how many singularities does the smoothest possible cross field
of the surface itself have, before any curvature fitting?

Method (Knöppel, Crane, Pinkall, Schröder 2013, "Globally Optimal Direction Fields", §4–5):
one unknown u_f in C per triangle, a cross field being u = exp(4 i alpha) in the triangle's
frame; across every interior edge the discrete Levi-Civita connection (unfolding the two
triangles about the edge) gives u_g ~ r_fg u_f with r_fg = exp(4 i (a_g - a_f)), a_f and a_g
the angles of the shared edge in the two frames. The smoothest field minimizes
sum_edges |u_g - r_fg u_f|^2 subject to sum_f A_f |u_f|^2 = 1: the eigenvector of the smallest
eigenvalue of that Hermitian form against the area matrix (scipy's shift-invert Lanczos).

The index of every vertex v (Ray, Vallet, Li, Levy 2008) is (K_v + sum of the changes of the
field's angle across the edges around v, each reduced into (-pi/4, pi/4]) / 2 pi, with K_v
the angle defect; it is a multiple of 1/4 and the indices sum to 2 - 2g (checked, printed).

    python3 -m venv /tmp/v && /tmp/v/bin/pip install numpy scipy
    /tmp/v/bin/python scripts/smoothest_cross_field.py "$(python3 tests/data/meshes.py)"/closed_*.obj

Prints per mesh: triangles, sum of quarter indices, singular vertices (+ / -) and their
number as a percentage of the triangles.
"""
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

SYMMETRY = 4


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s:
                continue
            if s[0] == "v":
                vertices.append([float(x) for x in s[1:4]])
            elif s[0] == "f":
                idx = [int(x.split("/")[0]) - 1 for x in s[1:]]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.array(vertices), np.array(faces)


def triangle_frames(V, F):
    """Per-triangle orthonormal frame (x along the first edge) and area."""
    e1 = V[F[:, 1]] - V[F[:, 0]]
    n = np.cross(e1, V[F[:, 2]] - V[F[:, 0]])
    area = np.linalg.norm(n, axis=1) / 2
    n /= 2 * area[:, None]
    x = e1 / np.linalg.norm(e1, axis=1)[:, None]
    return x, np.cross(n, x), area


def angle_defects(V, F):
    K = np.full(len(V), 2 * np.pi)
    for c in range(3):
        a = V[F[:, (c + 1) % 3]] - V[F[:, c]]
        b = V[F[:, (c + 2) % 3]] - V[F[:, c]]
        np.subtract.at(K, F[:, c], np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(1)))
    return K


def smoothest_field(V, F):
    """Angle of the smoothest cross field per triangle, and the half-edge -> triangle map."""
    x, y, area = triangle_frames(V, F)

    def edge_angle(f, d):
        return np.arctan2(d @ y[f], d @ x[f])

    face_of = {}
    for f, tri in enumerate(F):
        for c in range(3):
            face_of[(tri[c], tri[(c + 1) % 3])] = f
    rows, cols, vals = [], [], []
    for (a, b), f in face_of.items():
        if a < b and (b, a) in face_of:
            g = face_of[(b, a)]
            d = V[b] - V[a]
            r = np.exp(1j * SYMMETRY * (edge_angle(g, d) - edge_angle(f, d)))
            rows += [f, g, f, g]
            cols += [f, g, g, f]
            vals += [1, 1, -np.conj(r), -r]
    n = len(F)
    form = sp.csc_matrix((vals, (rows, cols)), shape=(n, n))
    _, vectors = sla.eigsh(form, k=1, M=sp.diags(area).tocsc(), sigma=-1e-8, which="LM")
    return np.angle(vectors[:, 0]) / SYMMETRY, face_of, edge_angle


def quarter_indices(V, F, alpha, face_of, edge_angle):
    """Index x 4 of every vertex whose star is closed (all of them on a closed mesh)."""
    defect = angle_defects(V, F)
    star = {}
    for f, tri in enumerate(F):
        for c in range(3):
            star.setdefault(tri[c], []).append((f, tri[(c + 2) % 3]))
    out = []
    for v, fans in star.items():
        total = defect[v]
        for f, w in fans:
            # Triangle f has the edge w -> v; the next triangle around v has v -> w.
            g = face_of.get((v, w))
            if g is None:
                total = None
                break
            d = V[w] - V[v]
            change = (alpha[g] - edge_angle(g, d)) - (alpha[f] - edge_angle(f, d))
            total += (change + np.pi / SYMMETRY) % (2 * np.pi / SYMMETRY) - np.pi / SYMMETRY
        if total is not None:
            out.append(int(round(total * SYMMETRY / (2 * np.pi))))
    return np.array(out)


def main(paths):
    for path in paths:
        V, F = read_obj(path)
        alpha, face_of, edge_angle = smoothest_field(V, F)
        q = quarter_indices(V, F, alpha, face_of, edge_angle)
        pos, neg = int((q > 0).sum()), int((q < 0).sum())
        print(
            f"{path.rsplit('/', 1)[-1]:<34} triangles {len(F):>7}  sum of quarter indices {int(q.sum()):>5}"
            f"  singular vertices +{pos} -{neg} = {pos + neg} ({100.0 * (pos + neg) / len(F):.2f}% of the triangles)"
        )


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
