"""A mesh validated once for many calls (``uvf_mesh_new``): :class:`Mesh`.

Positions may be ``float32`` or ``float64`` and any numpy view whose rows are evenly spaced (a
field of a structured vertex array is passed with its stride, not copied); faces are triangles
``(m, 3)`` or polygons (flat corner indices plus ``face_sizes``), ``uint16`` or ``uint32``
(other integer types are converted). Polygons are triangulated inside the library (the fan, or
ear clipping where the fan would fold), and :meth:`Mesh.face_corner_uv` maps per-triangle-corner
UVs back to the polygons' corners.
"""

from __future__ import annotations

import ctypes
from ctypes import POINTER, byref, c_double, c_uint32
from typing import Optional

import numpy as np

from . import _library as L
from ._errors import InvalidArgument


def _check(status: int) -> None:
    from ._common import _check as check  # the one error translation of the binding

    check(status)


class Mesh:
    """A validated triangle mesh with its connectivity, built once; pass it instead of
    ``positions, triangles`` to :func:`natural_conformal_map`, :func:`fixed_boundary_map`,
    :func:`abf`, :func:`nonlinear_map`, :func:`unwrap` and :func:`metrics`.

    Args:
        positions: ``(n, 3)`` float32 or float64 coordinates (a strided view is read in place).
        faces: ``(m, 3)`` triangles, or a flat array of polygon corners with ``face_sizes``.
        face_sizes: corners per polygon (each ≥ 3), or ``None`` for triangles.

    Raises:
        InvalidArgument (bad shapes or types, a face of fewer than 3 corners, an index past the
        vertices: the message names the face), InvalidMesh (as the flat calls; a polygon's
        problem names the face).
    """

    def __init__(self, positions: np.ndarray, faces: np.ndarray, face_sizes: Optional[np.ndarray] = None) -> None:
        self._handle = POINTER(L.UvfMesh)()
        p = np.asarray(positions)
        if p.dtype not in (np.float32, np.float64):
            p = p.astype(np.float64)
        if p.ndim != 2 or p.shape[1] != 3:
            raise InvalidArgument(f"positions must have shape (n, 3), not {p.shape}")
        if p.strides[1] != p.itemsize or p.strides[0] <= 0:
            p = np.ascontiguousarray(p)
        f = np.asarray(faces)
        if face_sizes is None:
            if f.ndim != 2 or f.shape[1] != 3:
                raise InvalidArgument(f"triangles must have shape (m, 3), not {f.shape}")
            sizes = None
        else:
            sizes = np.ascontiguousarray(face_sizes, dtype=np.uint32).ravel()
        if f.dtype not in (np.uint16, np.uint32):
            if f.size and (f.min() < 0 or f.max() > 0xFFFFFFFF):
                raise InvalidArgument("face indices must be in [0, 2**32)")
            f = f.astype(np.uint32)
        f = np.ascontiguousarray(f).ravel()
        if sizes is not None and int(sizes.sum(dtype=np.uint64)) != f.size:
            raise InvalidArgument(f"face_sizes add up to {int(sizes.sum())} corners but faces has {f.size} indices")
        desc = L.UvfMeshDesc()
        L.library().uvf_mesh_desc_default(byref(desc))
        desc.positions = p.ctypes.data if len(p) else None
        desc.position_type = L.UVF_SCALAR_FLOAT if p.dtype == np.float32 else L.UVF_SCALAR_DOUBLE
        desc.position_stride = p.strides[0]
        desc.vertex_count = len(p)
        desc.indices = f.ctypes.data if f.size else None
        desc.index_type = L.UVF_INDEX_UINT16 if f.dtype == np.uint16 else L.UVF_INDEX_UINT32
        if sizes is None:
            desc.face_count = f.size // 3
        else:
            desc.face_sizes = sizes.ctypes.data_as(POINTER(c_uint32))
            desc.face_count = len(sizes)
        _check(L.library().uvf_mesh_new(byref(desc), byref(self._handle)))
        self.corner_count = int(f.size)
        info = L.UvfMeshInfo()
        _check(L.library().uvf_mesh_handle_info(self._handle, byref(info)))
        self.vertex_count = int(info.vertices)
        self.triangle_count = int(info.triangles)

    @property
    def handle(self) -> "ctypes._Pointer[L.UvfMesh]":
        """The ``UvfMesh *`` (raises once the mesh is closed)."""
        if not self._handle:
            raise InvalidArgument("the mesh was closed")
        return self._handle

    @property
    def triangles(self) -> np.ndarray:
        """``(triangle_count, 3)`` uint32: the triangulation the methods work on."""
        out = np.empty((self.triangle_count, 3), dtype=np.uint32)
        _check(L.library().uvf_mesh_copy_triangles(self.handle, out.ctypes.data_as(POINTER(c_uint32)), out.size))
        return out

    @property
    def triangle_faces(self) -> np.ndarray:
        """``(triangle_count,)`` uint32: the input face of each triangle."""
        out = np.empty(self.triangle_count, dtype=np.uint32)
        _check(L.library().uvf_mesh_copy_triangle_faces(self.handle, out.ctypes.data_as(POINTER(c_uint32)), out.size))
        return out

    def face_corner_uv(self, corner_uv: np.ndarray) -> np.ndarray:
        """Per-triangle-corner UVs (``(triangle_count, 3, 2)``, as :func:`unwrap` gives them)
        as per-face-corner UVs: ``(corner_count, 2)``, in the order of the input's face
        indices (``uvf_mesh_face_corner_uv``)."""
        c = np.ascontiguousarray(corner_uv, dtype=np.float64)
        out = np.empty((self.corner_count, 2), dtype=np.float64)
        _check(
            L.library().uvf_mesh_face_corner_uv(
                self.handle, c.ctypes.data_as(POINTER(c_double)), c.size, out.ctypes.data_as(POINTER(c_double)), out.size
            )
        )
        return out

    def close(self) -> None:
        """Releases the handle now (``uvf_mesh_free``); later use raises."""
        if self._handle:
            L.library().uvf_mesh_free(self._handle)
            self._handle = POINTER(L.UvfMesh)()

    def __enter__(self) -> "Mesh":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown: the library may be gone
            pass

    def __len__(self) -> int:
        """The vertex count (so a mesh stands where a positions array did)."""
        return self.vertex_count
