"""Shared by the method modules: array conversion and checks, the status check, progress
callbacks, option codes, the library version and thread count."""

from __future__ import annotations

import ctypes
import dataclasses
import threading
from ctypes import POINTER, byref, c_double, c_uint32
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _library as L
from ._mesh import Mesh
from ._errors import Error, InternalError, InvalidArgument, InvalidMesh, Status, error_for_status


ArrayLike = Any


#: A progress callback: receives the fraction done in [0, 1]; returning ``False`` cancels.
ProgressCallback = Callable[[float], Optional[bool]]


#: Two pins: ``((vertex0, (u0, v0)), (vertex1, (u1, v1)))``.
Pins = Tuple[Tuple[int, Tuple[float, float]], Tuple[int, Tuple[float, float]]]


_U32_MAX = np.iinfo(np.uint32).max


def _from_struct(cls: type, struct: ctypes.Structure) -> Any:
    return cls(**{f.name: getattr(struct, f.name) for f in dataclasses.fields(cls)})


def _check(status: int) -> None:
    """Raises the exception for a failed call, with this thread's library message."""
    if status != 0:
        message = L.library().uvf_last_error_message()
        raise error_for_status(status, message.decode("utf-8", "replace") if message else "")


def version() -> str:
    """Version of the loaded library, e.g. ``"1.0.0"`` (``uvf_version()``)."""
    return L.library().uvf_version().decode("ascii")


def abi_version() -> int:
    """ABI version of the loaded library (``uvf_abi_version()``); equals :data:`ABI_VERSION`."""
    return int(L.library().uvf_abi_version())


def set_thread_count(count: int) -> None:
    """Number of worker threads the library computes on (0: one per core, or the
    ``RAYON_NUM_THREADS`` environment variable). Call it before any other uvflat function: once
    the workers exist their number is fixed and this raises :class:`InvalidArgument`
    (``uvf_set_thread_count``)."""
    if not 0 <= int(count) <= 0xFFFFFFFF:
        raise ValueError(f"count must be in [0, 2**32), not {count}")
    _check(L.library().uvf_set_thread_count(int(count)))


def thread_count() -> int:
    """Number of worker threads the library computes on (``uvf_thread_count``); creates them
    with their default number if no call has needed them yet."""
    return int(L.library().uvf_thread_count())


def _f64p(a: np.ndarray) -> "ctypes._Pointer[c_double]":
    return a.ctypes.data_as(POINTER(c_double))


def _u32p(a: np.ndarray) -> "ctypes._Pointer[c_uint32]":
    return a.ctypes.data_as(POINTER(c_uint32))


def _as_points(a: ArrayLike, columns: int, what: str) -> np.ndarray:
    """A C-contiguous, aligned float64 ``(k, columns)`` array; copies only when needed."""
    array = np.asarray(a)
    if array.size == 0:
        array = array.reshape(0, columns)
    if array.ndim != 2 or array.shape[1] != columns:
        raise InvalidArgument(f"{what} must have shape (k, {columns}), not {array.shape}")
    if array.dtype.kind not in "fiu":
        raise InvalidArgument(f"{what} must hold real numbers, not {array.dtype}")
    return np.require(array, dtype=np.float64, requirements=["C", "A"])


def _as_indices(
    a: ArrayLike,
    what: str,
    error: type,
    columns: Optional[int] = 3,
    describe: str = "triangle {row} references vertex {value}, which {reason}",
) -> np.ndarray:
    """A C-contiguous, aligned uint32 array of shape ``(k, columns)`` (or ``(k,)`` when
    ``columns`` is None); copies only when needed. An index that is negative or does not fit in
    32 bits raises ``error`` with ``describe`` filled in for the first one."""
    array = np.asarray(a)
    if array.size == 0:
        # (An empty list becomes a float64 array: no index in it, so nothing to refuse.)
        array = array.reshape((0, columns) if columns else (0,)).astype(np.uint32)
    if array.ndim != (2 if columns else 1) or (columns and array.shape[1] != columns):
        shape = f"(k, {columns})" if columns else "(k,)"
        raise InvalidArgument(f"{what} must have shape {shape}, not {array.shape}")
    if array.dtype.kind not in "iu":
        raise InvalidArgument(f"{what} must hold integers, not {array.dtype}")
    if array.dtype != np.uint32 and array.size:
        bad = (array < 0) | (array > _U32_MAX)
        if bad.any():
            where = tuple(np.argwhere(bad)[0])
            value = int(array[where])
            reason = "is negative" if value < 0 else "does not fit in 32 bits"
            raise error(describe.format(row=where[0], value=value, reason=reason))
    return np.require(array, dtype=np.uint32, requirements=["C", "A"])


def _mesh_arrays(positions: ArrayLike, triangles: ArrayLike) -> Tuple[np.ndarray, np.ndarray]:
    return _as_points(positions, 3, "positions"), _as_indices(triangles, "triangles", InvalidMesh)


def _mesh_source(positions: Any, triangles: Optional[ArrayLike]) -> Tuple[Any, Optional[np.ndarray]]:
    """A :class:`Mesh` handle as given (``triangles`` then None), or the checked arrays."""
    if isinstance(positions, Mesh):
        if triangles is not None:
            raise InvalidArgument("triangles must be None when a Mesh is given: the mesh has its own")
        return positions, None
    if triangles is None:
        raise InvalidArgument("triangles is missing (it may only be left out when positions is a Mesh)")
    return _mesh_arrays(positions, triangles)


def _on_mesh(lib: Any, name: str, p: Any, t: Optional[np.ndarray], *rest: Any) -> int:
    """``uvf_<name>(positions, n, triangles, m, *rest)``, or ``uvf_mesh_<name>(mesh, *rest)``
    for a :class:`Mesh`."""
    if isinstance(p, Mesh):
        return getattr(lib, "uvf_mesh_" + name)(p.handle, *rest)
    return getattr(lib, "uvf_" + name)(_f64p(p), len(p), _u32p(t), len(t), *rest)


class _ProgressBridge:
    """Wraps a Python callable as a ``UvfProgressFn`` kept alive for one call.

    The callable receives the fraction done in [0, 1]. Returning ``False`` (or another falsy
    value other than ``None``) cancels; ``True`` or ``None`` continues. An exception raised by
    the callable also cancels, and :meth:`reraise` raises it again after the C call returned.
    """

    def __init__(self, callback: Optional[ProgressCallback]) -> None:
        if callback is not None and not callable(callback):
            raise InvalidArgument(f"progress must be callable or None, not {type(callback).__name__}")
        self.callback = callback
        self.exception: Optional[BaseException] = None
        self.declined = False  # the callable asked to stop
        # A NULL function pointer when there is no callback.
        self.c_function = L.UvfProgressFn(self._call) if callback is not None else L.UvfProgressFn()

    def _call(self, _user: Optional[int], fraction: float) -> int:
        if self.exception is not None:
            return 1
        try:
            keep_going = self.callback(fraction)  # type: ignore[misc]
        except BaseException as e:  # noqa: B902 - re-raised after the call, KeyboardInterrupt too
            self.exception = e
            return 1
        if keep_going is None or keep_going:
            return 0
        self.declined = True
        return 1

    def run(self, call: Callable[[], int]) -> None:
        """Runs the C call, then re-raises the callback's exception or checks the status."""
        status = call()
        if self.exception is not None:
            raise self.exception
        if status == Status.CANCELLED and self.callback is not None and not self.declined:
            # Cancelled, but neither by the callable's answer nor by an exception it raised:
            # Ctrl-C arrived as the callback was entered, before its `try` (ctypes reports
            # such an exception as "ignored" and the call stops). Not a cancellation.
            raise KeyboardInterrupt("interrupted during a uvflat call")
        _check(status)


_WEIGHTS: Dict[str, int] = {
    "uniform": L.UVF_WEIGHTS_UNIFORM,
    "tutte": L.UVF_WEIGHTS_UNIFORM,
    "floater": L.UVF_WEIGHTS_FLOATER,
    "authalic": L.UVF_WEIGHTS_AUTHALIC,
    "wachspress": L.UVF_WEIGHTS_AUTHALIC,
    "conformal": L.UVF_WEIGHTS_CONFORMAL,
    "harmonic": L.UVF_WEIGHTS_CONFORMAL,
    "mean_value": L.UVF_WEIGHTS_MEAN_VALUE,
    "intrinsic": L.UVF_WEIGHTS_INTRINSIC,
}


_SHAPES: Dict[str, int] = {"circle": L.UVF_BOUNDARY_CIRCLE, "square": L.UVF_BOUNDARY_SQUARE}


_DISTRIBUTIONS: Dict[str, int] = {
    "uniform": L.UVF_DISTRIBUTION_UNIFORM,
    "chord": L.UVF_DISTRIBUTION_CHORD,
    "centripetal": L.UVF_DISTRIBUTION_CENTRIPETAL,
}


Weights = Union[str, int]


Boundary = Union[str, int, Mapping[int, Sequence[float]], Tuple[ArrayLike, ArrayLike]]


def _code(value: Union[str, int], table: Dict[str, int], what: str) -> int:
    """A ``UVF_*`` code from a name (``"mean_value"``, ``"mean-value"``) or the code itself.
    Unknown integers are passed on for the library to reject."""
    if isinstance(value, str):
        key = value.strip().lower().replace("-", "_").replace(" ", "_")
        if key not in table:
            names = ", ".join(sorted(set(table)))
            raise InvalidArgument(f"unknown {what} {value!r}; use one of {names}")
        return table[key]
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool) and 0 <= int(value) <= _U32_MAX:
        return int(value)
    raise InvalidArgument(f"{what} must be a name or a UVF_* code, not {value!r}")


def _given_boundary(boundary: Any) -> Tuple[np.ndarray, np.ndarray]:
    """(vertices uint32 (k,), uv float64 (k, 2)) from a mapping or a (vertices, uv) pair."""
    if isinstance(boundary, Mapping):
        vertices: Any = list(boundary.keys())
        uv: Any = [boundary[v] for v in vertices]
    elif isinstance(boundary, tuple) and len(boundary) == 2:
        vertices, uv = boundary
    else:
        raise InvalidArgument(
            "boundary must be 'circle', 'square', a mapping {vertex: (u, v)} or a pair "
            f"(vertices, uv), not {type(boundary).__name__}"
        )
    v = _as_indices(
        vertices, "boundary vertices", InvalidArgument, None, "boundary vertex {value} (entry {row}) {reason}"
    )
    q = _as_points(uv, 2, "boundary uv")
    if len(v) != len(q):
        raise InvalidArgument(f"boundary has {len(v)} vertices but {len(q)} uv pairs")
    return v, q


def _set_two_pins(options: Any, pins: Pins) -> None:
    """Writes ``((v0, (u0, v0_)), (v1, (u1, v1_)))`` into an options struct's ``pin_count``,
    ``pin_vertices`` and ``pin_uv`` fields (natural conformal and ABF options share them)."""
    try:
        (v0, uv0), (v1, uv1) = pins
        if any(isinstance(v, bool) or not isinstance(v, (int, np.integer)) for v in (v0, v1)):
            raise TypeError  # a float vertex would be truncated to another vertex
        vertices = [int(v0), int(v1)]
        uvs = [float(uv0[0]), float(uv0[1]), float(uv1[0]), float(uv1[1])]
        if len(uv0) != 2 or len(uv1) != 2:
            raise ValueError
    except (TypeError, ValueError, IndexError):
        raise InvalidArgument(f"pins must be ((vertex, (u, v)), (vertex, (u, v))), not {pins!r}") from None
    for v in vertices:
        if not 0 <= v <= _U32_MAX:
            raise InvalidArgument(f"pinned vertex {v} is not a vertex index")
    options.pin_count = 2
    options.pin_vertices[:] = vertices
    options.pin_uv[:] = uvs


_ENERGIES: Dict[str, int] = {
    "edge": L.UVF_ENERGY_EDGE_LENGTH,
    "edge_length": L.UVF_ENERGY_EDGE_LENGTH,
    "area": L.UVF_ENERGY_AREA,
}


def _set_boundary(options: ctypes.Structure, boundary: Boundary) -> Tuple[Any, Any]:
    """Fills ``boundary``/``given_*`` of an options struct; returns the arrays it points into
    (keep them alive until the call returns)."""
    if isinstance(boundary, (str, int, np.integer)) and not isinstance(boundary, bool):
        options.boundary = _code(boundary, _SHAPES, "boundary")
        if options.boundary == L.UVF_BOUNDARY_GIVEN:
            raise InvalidArgument("give the boundary positions themselves (a mapping or (vertices, uv))")
        return None, None
    given_vertices, given_uv = _given_boundary(boundary)
    options.boundary = L.UVF_BOUNDARY_GIVEN
    options.given_count = len(given_vertices)
    options.given_vertices = _u32p(given_vertices)
    options.given_uv = _f64p(given_uv)
    return given_vertices, given_uv


def _non_negative_int(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0 or value > 2**32 - 1:
        raise InvalidArgument(f"{what} must be a non-negative integer, not {value!r}")
    return int(value)


def _split(flat: np.ndarray, sizes: np.ndarray) -> List[np.ndarray]:
    return np.split(flat, np.cumsum(sizes)[:-1]) if len(sizes) else []


def _take_quad_mesh(lib, quad) -> Tuple[np.ndarray, List[np.ndarray]]:
    """Copies a ``UvfQuadMesh`` handle out and frees it."""
    try:
        info = L.UvfQuadMeshInfo()
        _check(lib.uvf_quad_mesh_info(quad, byref(info)))
        positions = np.empty((info.vertex_count, 3), dtype=np.float64)
        sizes = np.empty(info.face_count, dtype=np.uint32)
        indices = np.empty(info.index_count, dtype=np.uint32)
        _check(
            lib.uvf_quad_mesh_copy(
                quad, _f64p(positions), positions.size, _u32p(sizes), sizes.size, _u32p(indices), indices.size
            )
        )
    finally:
        lib.uvf_quad_mesh_free(quad)
    return positions, _split(indices, sizes)
