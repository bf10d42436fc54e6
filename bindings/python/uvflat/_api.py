"""The Pythonic layer: numpy arrays in and out, keyword options, exceptions.

Conventions (as in ``uvflat.h``): ``positions`` is an ``(n, 3)`` array of vertex positions,
``triangles`` an ``(m, 3)`` array of vertex indices (counter-clockwise), UVs come back as an
``(n, 2)`` float64 array with one row per vertex, NaN for vertices no triangle uses.

Inputs may be anything ``numpy.asarray`` accepts. They are handed to the library without a
copy when they already are C-contiguous, aligned float64 (positions, UVs) or uint32
(triangles); otherwise a converted copy is made. Integer triangle arrays of another type are
range-checked first, so a negative index or one that does not fit in 32 bits is reported, not
wrapped around.
"""

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


# --- results --------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class MeshInfo:
    """Counts and topological invariants of a mesh (``UvfMeshInfo``)."""

    #: Vertices in the input arrays (including unreferenced ones).
    vertices: int
    #: Vertices used by at least one triangle.
    referenced_vertices: int
    #: Triangles.
    triangles: int
    #: Undirected edges.
    edges: int
    #: Connected components.
    components: int
    #: Boundary loops.
    boundary_loops: int
    #: Total number of vertices over all boundary loops.
    boundary_vertices: int
    #: Euler characteristic V − E + F.
    euler_characteristic: int
    #: Total genus.
    genus: int


@dataclasses.dataclass(frozen=True)
class Metrics:
    """Distortion summary of a UV map (``UvfMetrics``); distortion fields are NaN when no
    triangle is measurable. Angles are in radians."""

    #: Number of triangles measured.
    triangles: int
    #: Triangles whose UV orientation is opposite to the layout's majority orientation.
    flipped: int
    #: Triangles with (numerically) zero UV area, left out of every distortion figure.
    degenerate_uv: int
    #: Proper crossings between UV boundary edges.
    boundary_intersections: int
    #: Sander et al. 2001 L2 stretch after a global scale; 1 is optimal.
    stretch_l2: float
    #: Sander et al. 2001 L∞ stretch after the same scale.
    stretch_linf: float
    #: Area-weighted mean of σmax/σmin; 1 is conformal.
    conformal_mean: float
    #: Largest σmax/σmin.
    conformal_max: float
    #: Mean |UV corner angle − surface corner angle|, radians.
    angle_mean: float
    #: Largest corner angle error, radians.
    angle_max: float
    #: Area-weighted mean |ln(s·A_uv / A_3d)| with one global scale s; 0 is authalic.
    area_mean: float
    #: Largest |ln(s·A_uv / A_3d)|.
    area_max: float


def _from_struct(cls: type, struct: ctypes.Structure) -> Any:
    return cls(**{f.name: getattr(struct, f.name) for f in dataclasses.fields(cls)})


# --- calling --------------------------------------------------------------------------------


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


# --- arrays ---------------------------------------------------------------------------------


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


# --- progress -------------------------------------------------------------------------------


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


# --- topology -------------------------------------------------------------------------------


def mesh_info(positions: ArrayLike, triangles: ArrayLike) -> MeshInfo:
    """Validates a mesh and reports its counts and topology (``uvf_mesh_info``).

    Raises :class:`InvalidMesh` (naming the bad triangle, vertex or edge) or
    :class:`InvalidArgument`.
    """
    p, t = _mesh_arrays(positions, triangles)
    info = L.UvfMeshInfo()
    _check(L.library().uvf_mesh_info(_f64p(p), len(p), _u32p(t), len(t), byref(info)))
    return _from_struct(MeshInfo, info)


def boundary_loops(positions: ArrayLike, triangles: ArrayLike) -> List[np.ndarray]:
    """Ordered boundary loops, counter-clockwise with the surface on the left
    (``uvf_boundary_loops``): one uint32 array of vertex indices per loop."""
    p, t = _mesh_arrays(positions, triangles)
    info = mesh_info(p, t)
    vertices = np.empty(info.boundary_vertices, dtype=np.uint32)
    offsets = np.empty(info.boundary_loops + 1, dtype=np.uint32)
    _check(
        L.library().uvf_boundary_loops(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertices), len(vertices), _u32p(offsets), len(offsets)
        )
    )
    return [vertices[offsets[k] : offsets[k + 1]] for k in range(info.boundary_loops)]


def triangle_components(positions: ArrayLike, triangles: ArrayLike) -> np.ndarray:
    """Connected component id (0-based) of every triangle, a uint32 array of length m
    (``uvf_triangle_components``)."""
    p, t = _mesh_arrays(positions, triangles)
    out = np.empty(len(t), dtype=np.uint32)
    _check(L.library().uvf_triangle_components(_f64p(p), len(p), _u32p(t), len(t), _u32p(out)))
    return out


# --- fixed-boundary maps --------------------------------------------------------------------

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


def fixed_boundary_map(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    *,
    weights: Weights = "mean_value",
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    lambda_: Optional[float] = None,
    mu: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Fixed-boundary barycentric map (``uvf_fixed_boundary_map``; course notes ch. 2,
    Desbrun et al. 2002 §3–4.1).

    The longest boundary loop is placed on ``boundary`` and every interior vertex is the
    weighted average of its neighbours; other loops are holes.

    Args:
        positions: ``(n, 3)`` vertex positions, or a :class:`Mesh` (then no ``triangles``).
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        weights: ``"uniform"`` (Tutte; alias ``"tutte"``), ``"floater"``, ``"authalic"``
            (DAP = Wachspress), ``"conformal"`` (DCP = discrete harmonic), ``"mean_value"``
            (default) or ``"intrinsic"`` (λ·DCP + μ·DAP), or a ``UVF_WEIGHTS_*`` code.
        boundary: ``"circle"`` (centre (0.5, 0.5), radius 0.5; default), ``"square"`` (the unit
            square), or given positions: a mapping ``{vertex: (u, v)}`` or a pair
            ``(vertices, uv)`` with ``uv`` of shape ``(k, 2)``; they must cover whole loops.
        distribution: spacing along a circle or square: ``"uniform"``, ``"chord"`` (default)
            or ``"centripetal"``.
        lambda_, mu: λ and μ of ``weights="intrinsic"`` (defaults 1 and 0); an error with
            other weights.
        progress: optional ``callable(fraction) -> bool | None``; see :func:`natural_conformal_map`.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument, InvalidMesh, UnsupportedTopology (not a single genus-0 component
        with a boundary), NumericalFailure, Cancelled, InternalError; or whatever ``progress``
        raised.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfFixedBoundaryOptions()
    L.library().uvf_fixed_boundary_options_default(byref(options))
    options.weights = _code(weights, _WEIGHTS, "weights")
    if options.weights == L.UVF_WEIGHTS_INTRINSIC:
        options.lambda_ = 1.0 if lambda_ is None else float(lambda_)
        options.mu = 0.0 if mu is None else float(mu)
    elif lambda_ is not None or mu is not None:
        raise InvalidArgument(f"lambda_ and mu apply to weights='intrinsic' only, not {weights!r}")
    if isinstance(boundary, (str, int, np.integer)) and not isinstance(boundary, bool):
        options.boundary = _code(boundary, _SHAPES, "boundary")
        if options.boundary == L.UVF_BOUNDARY_GIVEN:
            raise InvalidArgument("give the boundary positions themselves (a mapping or (vertices, uv))")
        given_vertices, given_uv = None, None
    else:
        given_vertices, given_uv = _given_boundary(boundary)
        options.boundary = L.UVF_BOUNDARY_GIVEN
        options.given_count = len(given_vertices)
        options.given_vertices = _u32p(given_vertices)
        options.given_uv = _f64p(given_uv)
    options.distribution = _code(distribution, _DISTRIBUTIONS, "distribution")
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "fixed_boundary_map", p, t, byref(options), _f64p(uv)))
    del given_vertices, given_uv  # kept alive until here: `options` points into them
    return uv


def _named_weights(name: str, doc: str) -> Callable[..., np.ndarray]:
    def method(
        positions: ArrayLike,
        triangles: ArrayLike,
        *,
        boundary: Boundary = "circle",
        distribution: Union[str, int] = "chord",
        progress: Optional[ProgressCallback] = None,
    ) -> np.ndarray:
        return fixed_boundary_map(
            positions, triangles, weights=name, boundary=boundary, distribution=distribution, progress=progress
        )

    method.__name__ = method.__qualname__ = name if name != "uniform" else "tutte"
    method.__doc__ = (
        f"{doc}\n\n``fixed_boundary_map(positions, triangles, weights={name!r}, ...)``; "
        "returns ``(n, 2)`` float64 UVs (NaN for unreferenced vertices)."
    )
    return method


tutte = _named_weights("uniform", "Tutte's embedding: uniform weights (Tutte 1963); never flips with a convex boundary.")
floater = _named_weights("floater", "Floater's shape-preserving weights (1997); never flips with a convex boundary.")
authalic = _named_weights("authalic", "Discrete authalic map = Wachspress weights (Desbrun et al. 2002 eq. 6).")
conformal = _named_weights(
    "conformal", "Fixed-boundary discrete conformal map = discrete harmonic (Desbrun et al. 2002 eq. 4)."
)
mean_value = _named_weights("mean_value", "Floater's mean value weights (2003); never flips with a convex boundary.")


def intrinsic(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    lambda_: float = 1.0,
    mu: float = 0.0,
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Desbrun et al. 2002 §3.4 intrinsic map: weights λ·DCP + μ·DAP with a fixed boundary.

    ``fixed_boundary_map(positions, triangles, weights="intrinsic", lambda_=..., mu=..., ...)``;
    returns ``(n, 2)`` float64 UVs (NaN for unreferenced vertices).
    """
    return fixed_boundary_map(
        positions,
        triangles,
        weights="intrinsic",
        lambda_=lambda_,
        mu=mu,
        boundary=boundary,
        distribution=distribution,
        progress=progress,
    )


# --- natural conformal map ------------------------------------------------------------------


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


def natural_conformal_map(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    *,
    pins: Optional[Pins] = None,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Natural conformal map = LSCM (``uvf_natural_conformal_map``; Desbrun et al. 2002 §4.2
    eq. 7): free boundary, two pinned vertices.

    Args:
        positions: ``(n, 3)`` vertex positions, or a :class:`Mesh` (then no ``triangles``).
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        pins: ``None`` (default) pins the two boundary vertices farthest apart at (0, 0) and
            (d, 0), d their 3D distance; or ``((v0, (u0, v0_)), (v1, (u1, v1_)))``.
        progress: optional callable receiving the fraction done in [0, 1] (called from the
            calling thread, with the GIL held). Return ``True`` or ``None`` to go on,
            ``False`` to cancel (the call then raises :class:`Cancelled`). An exception
            raised by the callback cancels too and is re-raised once the library returns.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument (bad pins), InvalidMesh, UnsupportedTopology, NumericalFailure,
        Cancelled, InternalError; or whatever ``progress`` raised.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfNaturalConformalOptions()
    L.library().uvf_natural_conformal_options_default(byref(options))
    if pins is not None:
        _set_two_pins(options, pins)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "natural_conformal_map", p, t, byref(options), _f64p(uv)))
    return uv


#: Alias: the natural conformal map is LSCM.
lscm = natural_conformal_map


# --- metrics --------------------------------------------------------------------------------


def metrics(
    positions: ArrayLike,
    triangles: ArrayLike,
    uv: ArrayLike,
    uv_triangles: Optional[ArrayLike] = None,
) -> Metrics:
    """Distortion of a UV map (``uvf_metrics``; course notes ch. 4, Sander et al. 2001).

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices.
        uv: ``(k, 2)`` UV coordinates; NaN rows that no triangle uses are fine.
        uv_triangles: ``(m, 3)`` indices into ``uv`` per triangle (per-corner UVs), or
            ``None`` when ``uv`` has one row per vertex (then ``k`` must equal ``n``).

    The mesh need not be manifold. Raises :class:`InvalidArgument` for mis-sized arrays,
    out-of-range indices, non-finite coordinates or no triangles.
    """
    p = _as_points(positions, 3, "positions")
    t = _as_indices(triangles, "triangles", InvalidArgument)
    q = _as_points(uv, 2, "uv")
    if uv_triangles is None:
        ut = None
    else:
        ut = _as_indices(
            uv_triangles, "uv_triangles", InvalidArgument, 3, "uv triangle {row} references uv {value}, which {reason}"
        )
        if len(ut) != len(t):
            raise InvalidArgument(f"uv_triangles has {len(ut)} rows but triangles has {len(t)}")
    out = L.UvfMetrics()
    _check(
        L.library().uvf_metrics(
            _f64p(p), len(p), _u32p(t), len(t), _f64p(q), len(q), None if ut is None else _u32p(ut), byref(out)
        )
    )
    return _from_struct(Metrics, out)


# --- more pins, non-linear methods, ABF, closed surfaces -----------------------------------


def pinned_natural_conformal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    pins: Mapping[int, Sequence[float]],
    *,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Natural conformal map with two or more pinned vertices
    (``uvf_pinned_natural_conformal_map``; Desbrun et al. 2002 §4.1–4.2, pins as Lagrange
    point constraints): every pin lands exactly where given, the rest minimises the conformal
    energy.

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        pins: ``{vertex: (u, v)}`` with at least two entries.
        progress: as for :func:`natural_conformal_map`.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument (fewer than two pins, bad vertices, conflicting pins), InvalidMesh,
        UnsupportedTopology, NumericalFailure, Cancelled.
    """
    p, t = _mesh_arrays(positions, triangles)
    try:
        if any(isinstance(v, bool) or not isinstance(v, (int, np.integer)) for v in dict(pins)):
            raise TypeError  # a float vertex would be truncated to another vertex
        items = sorted((int(v), (float(uv[0]), float(uv[1]))) for v, uv in dict(pins).items())
    except (TypeError, ValueError, IndexError):
        raise InvalidArgument(f"pins must map vertex -> (u, v), not {pins!r}") from None
    vertices = _as_indices(np.array([v for v, _ in items], dtype=np.int64), "pin vertices", InvalidArgument, None,
                           "pin {row} is vertex {value}, which {reason}")
    uvs = np.ascontiguousarray([uv for _, uv in items], dtype=np.float64).reshape(-1, 2)
    options = L.UvfIntrinsicToolOptions()
    L.library().uvf_intrinsic_tool_options_default(byref(options))
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_pinned_natural_conformal_map(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertices), _f64p(uvs), len(vertices), byref(options), _f64p(uv)
        )
    )
    return uv


_NONLINEAR = {
    "slim": L.UVF_NONLINEAR_SLIM,
    "arap": L.UVF_NONLINEAR_ARAP,
    "mips": L.UVF_NONLINEAR_MIPS,
    "stretch": L.UVF_NONLINEAR_STRETCH,
    "green_lagrange": L.UVF_NONLINEAR_GREEN_LAGRANGE,
    "degener": L.UVF_NONLINEAR_DEGENER,
}


@dataclasses.dataclass(frozen=True)
class NonlinearReport:
    """What ``uvf_nonlinear_map`` reports about its run."""

    iterations: int
    converged: int
    initial_energy: float
    final_energy: float


def nonlinear_map(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    method: Union[str, int] = "slim",
    *,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    theta: Optional[float] = None,
    bijective: bool = False,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, NonlinearReport]:
    """Free-boundary distortion minimisation that never flips a triangle
    (``uvf_nonlinear_map``): ``slim`` (symmetric Dirichlet, Rabinovich et al. 2017), ``arap``
    (Liu et al. 2008), ``mips`` (Hormann & Greiner 2000), ``stretch`` (Sander et al. 2001),
    ``green_lagrange`` (Maillot et al. 1993), ``degener`` (Degener et al. 2003, ``theta``).
    ``bijective``: a scaffold around the free boundary keeps it from running into itself, so
    the whole map is one-to-one (Jiang et al. 2017); ``slim`` optimizes map and scaffold
    together, the other methods stop a step where the boundary meets itself (a higher final
    energy where the boundary would have crossed). ``arap`` and
    ``green_lagrange`` keep every triangle at or above 1% of its share of the UV area (their
    energies alone would let a triangle be pressed flat).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and a :class:`NonlinearReport`.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfNonlinearOptions()
    L.library().uvf_nonlinear_options_default(byref(options))
    options.method = _code(method, _NONLINEAR, "method")
    if iterations is not None:
        options.iterations = _non_negative_int(iterations, "iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    if theta is not None:
        options.theta = float(theta)
    options.bijective = 1 if bijective else 0
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfNonlinearReport()
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "nonlinear_map", p, t, byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(NonlinearReport, report)


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


@dataclasses.dataclass(frozen=True)
class SpectralReport:
    """What ``uvf_spectral_conformal_map`` reports: the eigenpair behind the map."""

    iterations: int
    converged: int
    #: λ of ``L_C z = λ B z``.
    eigenvalue: float
    #: Normwise backward error of the eigenpair.
    residual: float


def spectral_conformal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, SpectralReport]:
    """Spectral conformal map (Mullen, Tong, Alliez, Desbrun 2008; ``uvf_spectral_conformal_map``):
    free-boundary conformal map without pins, the smallest non-trivial generalized eigenvector
    of the conformal energy against the boundary mass, by inverse iteration. Scaled to the
    surface area, farthest boundary pair from (0, 0) along +u.

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs (NaN for unreferenced vertices) and a
        :class:`SpectralReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfSpectralOptions()
    L.library().uvf_spectral_options_default(byref(options))
    if iterations is not None:
        options.iterations = _non_negative_int(iterations, "iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfSpectralReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_spectral_conformal_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report))
    )
    return uv, _from_struct(SpectralReport, report)


@dataclasses.dataclass(frozen=True)
class CirclePatternReport:
    """What ``uvf_circle_pattern_map`` reports."""

    #: Iterations of the angle program: primal–dual steps, plus the log-barrier Newton steps
    #: where it fell back.
    angle_iterations: int
    #: Newton steps of the log radii.
    radius_iterations: int
    #: Largest |Σ φ − π| over the circles (radians).
    closure_error: float
    #: Interior edges of the triangulation used (after the intrinsic flips, if any) whose
    #: angles violate the Delaunay condition.
    non_delaunay_edges: int
    #: Largest |α − β| between a planar and a 3D angle (radians).
    max_angle_change: float
    #: Intrinsic edge flips made before the angle program.
    intrinsic_flips: int
    #: Mesh triangles whose uv area is not positive (always 0 without intrinsic flips).
    flipped_triangles: int
    #: log10 of the largest over the smallest circle radius: the orders of magnitude the map's
    #: scale spans (3–4 on typical free maps; beyond about 12 the layout loses the smallest
    #: triangles to double-precision rounding).
    radius_span: float


def _circle_pattern_options(
    p: np.ndarray,
    t: np.ndarray,
    pins: Optional[Pins],
    max_iterations: Optional[int],
    tolerance: Optional[float],
    intrinsic_delaunay: bool,
    boundary_curvature: Optional[ArrayLike],
    corners: Optional[ArrayLike],
    convex_boundary: bool = False,
) -> Tuple[Any, Optional[np.ndarray]]:
    """The C options and the curvature array they point to (keep it alive during the call)."""
    options = L.UvfCirclePatternOptions()
    L.library().uvf_circle_pattern_options_default(byref(options))
    if pins is not None:
        _set_two_pins(options, pins)
    if max_iterations is not None:
        options.max_iterations = _non_negative_int(max_iterations, "max_iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    options.intrinsic_delaunay = 1 if intrinsic_delaunay else 0
    options.convex_boundary = 1 if convex_boundary else 0
    if corners is not None:
        if boundary_curvature is not None:
            raise InvalidArgument("give boundary_curvature or corners, not both")
        boundary_curvature = polygon_boundary_curvature(p, t, corners)
    curvature = None
    if boundary_curvature is not None:
        curvature = np.require(np.asarray(boundary_curvature, dtype=np.float64), requirements=["C", "A"])
        if curvature.shape != (len(p),):
            raise InvalidArgument(f"boundary_curvature must have shape ({len(p)},), not {curvature.shape}")
        options.boundary_curvature = _f64p(curvature)
    return options, curvature


def circle_pattern_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    pins: Optional[Pins] = None,
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    intrinsic_delaunay: bool = True,
    boundary_curvature: Optional[ArrayLike] = None,
    corners: Optional[ArrayLike] = None,
    convex_boundary: bool = False,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, CirclePatternReport]:
    """Conformal map by circle patterns (Kharevych, Springborn & Schröder 2006;
    ``uvf_circle_pattern_map``), free boundary: the edges flipped to the intrinsic Delaunay
    triangulation of the mesh's metric (as in the paper), planar angles from the paper's
    quadratic program, the circumcircles' intersection angles, the log radii minimizing the
    paper's convex energy, and their layout. The mesh's triangles take their vertices' uv, so
    a few may flip after intrinsic flips (``report.flipped_triangles``); with
    ``intrinsic_delaunay=False`` none does, but the angles at non-Delaunay edges are distorted.
    May raise :class:`NumericalFailure` where the barrier or the radii do not converge.

    Args:
        pins: ``None`` (default: the two boundary vertices farthest apart at (0, 0) and (d, 0),
            d their 3D distance)
            or ``((v0, (u0, v0_)), (v1, (u1, v1_)))`` as for :func:`natural_conformal_map`.
        intrinsic_delaunay: flip to the intrinsic Delaunay triangulation first (default).
        boundary_curvature: ``None`` (free boundary, default) or ``(n,)`` floats: the turning
            angle of the uv boundary at each boundary vertex (its uv angle sum is π − κ; 0 keeps
            the boundary straight), NaN where it is free; ignored at interior vertices. A fully
            prescribed boundary must sum to 2π (1 − holes).
        corners: instead of ``boundary_curvature``, the corner vertices of a convex polygon
            with straight sides (see :func:`polygon_boundary_curvature`; 4 give a rectangle).
        convex_boundary: keep the uv boundary convex (the paper's inequality constraints on
            the boundary angles): every boundary vertex whose curvature is not prescribed turns
            by at least 0, so the pattern embeds its triangulation (no overlap). Costs angle
            distortion where the boundary is concave (``report.radius_span`` tells how far the
            scale then spreads).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and a :class:`CirclePatternReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options, _curvature = _circle_pattern_options(
        p, t, pins, max_iterations, tolerance, intrinsic_delaunay, boundary_curvature, corners, convex_boundary
    )
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfCirclePatternReport()
    lib = L.library()
    bridge.run(lambda: lib.uvf_circle_pattern_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(CirclePatternReport, report)


@dataclasses.dataclass(frozen=True)
class ConePlacement:
    """What :func:`place_cones` returns: the cones in the order placed."""

    #: ``(k,)`` uint32 interior vertices.
    vertices: np.ndarray
    #: ``(k,)`` float64 curvatures (2π minus the cone angle, radians); Σ = 2π χ on a closed mesh.
    curvatures: np.ndarray
    #: Largest |log scale| of the conformal flattening with these cones.
    max_log_scale: float

    def cones(self) -> Tuple[np.ndarray, np.ndarray]:
        """``(vertices, curvatures)``, as :func:`circle_pattern_cone_map` takes them."""
        return self.vertices, self.curvatures


def place_cones(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    max_cones: int = 64,
    max_log_scale: float = 0.7,
    progress: Optional[ProgressCallback] = None,
) -> ConePlacement:
    """Cone singularities for a conformal map, placed greedily (Ben-Chen, Gotsman & Bunin 2008;
    ``uvf_place_cones``): each new cone goes where the flattening's log scale |u| is largest,
    until |u| ≤ ``max_log_scale`` everywhere or ``max_cones`` are placed; each cone's curvature
    is the one that flattening gives it. Feed the result to :func:`circle_pattern_cone_map`::

        placement = uvflat.place_cones(p, t)
        corner_uv, report = uvflat.circle_pattern_cone_map(p, t, placement)

    A closed surface of genus g needs at least 2g − 2 cones (raises :class:`InvalidArgument`
    naming the cone that ``max_cones`` leave overloaded; 4 per unit of −χ is ample).
    """
    p, t = _mesh_arrays(positions, triangles)
    if not (isinstance(max_cones, (int, np.integer)) and 0 <= max_cones < 2**32):
        raise InvalidArgument(f"max_cones must be an integer in [0, 2^32), not {max_cones!r}")
    options = L.UvfConePlacementOptions()
    L.library().uvf_cone_placement_options_default(byref(options))
    options.max_cones = int(max_cones)
    options.max_log_scale = float(max_log_scale)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    capacity = max(min(int(max_cones), len(p)), 1)  # a vertex is a cone at most once
    vertices = np.zeros(capacity, dtype=np.uint32)
    curvatures = np.zeros(capacity, dtype=np.float64)
    count, largest = ctypes.c_size_t(0), ctypes.c_double(0.0)
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_place_cones(
            _f64p(p), len(p), _u32p(t), len(t), byref(options), _u32p(vertices), _f64p(curvatures), byref(count), byref(largest)
        )
    )
    k = count.value
    return ConePlacement(vertices[:k].copy(), curvatures[:k].copy(), largest.value)


def circle_pattern_cone_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    cones: Any,
    *,
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    intrinsic_delaunay: bool = True,
    boundary_curvature: Optional[ArrayLike] = None,
    corners: Optional[ArrayLike] = None,
    convex_boundary: bool = False,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, CirclePatternReport]:
    """Conformal map with cone singularities by circle patterns (Kharevych, Springborn &
    Schröder 2006 §5; ``uvf_circle_pattern_cone_map``) of a connected mesh of any genus, closed
    or with boundary. The mesh is cut through the cones (and its handles) and laid out per
    corner: both sides of every seam are congruent, and the uv angles around each cone sum to
    its cone angle.

    Args:
        cones: ``{vertex: curvature}``, ``(vertices, curvatures)`` or a :class:`ConePlacement`
            from :func:`place_cones`: interior vertices and their curvature in radians (2π minus the cone angle; π/2 for a cube corner). On a
            closed mesh the curvatures must sum to 2π χ (4π on a sphere, 0 on a torus: ``{}``).
        boundary_curvature, corners, convex_boundary, intrinsic_delaunay: as for
            :func:`circle_pattern_map`.

    Returns:
        ``(corner_uv, report)``: ``(m, 3, 2)`` uv per triangle corner and a
        :class:`CirclePatternReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    if isinstance(cones, ConePlacement):
        cones = cones.cones()
    if isinstance(cones, Mapping):
        vertices: Any = list(cones.keys())
        curvatures: Any = [cones[v] for v in vertices]
    elif isinstance(cones, tuple) and len(cones) == 2:
        vertices, curvatures = cones
    else:
        raise InvalidArgument(f"cones must be a mapping {{vertex: curvature}} or (vertices, curvatures), not {type(cones).__name__}")
    if np.size(vertices) == 0:
        vertices = np.zeros(0, dtype=np.uint32)
    v = _as_indices(vertices, "cone vertices", InvalidArgument, None, "cone vertex {value} (entry {row}) {reason}")
    k = np.require(np.asarray(curvatures, dtype=np.float64).reshape(-1), requirements=["C", "A"])
    if len(k) != len(v):
        raise InvalidArgument(f"{len(v)} cone vertices but {len(k)} curvatures")
    options, _curvature = _circle_pattern_options(
        p, t, None, max_iterations, tolerance, intrinsic_delaunay, boundary_curvature, corners, convex_boundary
    )
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    corner_uv = np.empty((len(t), 3, 2), dtype=np.float64)
    report = L.UvfCirclePatternReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_circle_pattern_cone_map(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(v), _f64p(k), len(v), byref(options), _f64p(corner_uv), byref(report)
        )
    )
    return corner_uv, _from_struct(CirclePatternReport, report)


def polygon_boundary_curvature(positions: ArrayLike, triangles: ArrayLike, corners: ArrayLike) -> np.ndarray:
    """Boundary curvature (``uvf_circle_pattern_polygon_curvature``) that makes the longest
    boundary loop a convex polygon with the given k ≥ 3 corner vertices: turning 2π / k at each
    corner, 0 (straight) at the loop's other vertices, NaN (free) elsewhere. For the
    ``boundary_curvature`` of :func:`circle_pattern_map`. Raises :class:`InvalidArgument` when a
    corner is not on that loop or is given twice, or when a boundary vertex in a single
    triangle is not a corner (no straight side can pass through it).
    """
    p, t = _mesh_arrays(positions, triangles)
    c = _as_indices(corners, "corners", InvalidArgument, None, "corner {value} (entry {row}) {reason}")
    out = np.empty(len(p), dtype=np.float64)
    _check(L.library().uvf_circle_pattern_polygon_curvature(_f64p(p), len(p), _u32p(t), len(t), _u32p(c), len(c), _f64p(out)))
    return out


@dataclasses.dataclass(frozen=True)
class QuadCoverReport:
    """What ``uvf_quadcover`` reports."""

    #: Cone (singular) vertices of the frame field.
    cone_count: int
    #: Cutting paths, each with one integer gap.
    chain_count: int
    #: Triangles whose (u, v) image has non-positive signed area.
    flipped_count: int
    #: Surface length of one grid cell.
    grid_spacing: float
    #: Largest distance of a free gap or cone coordinate to an integer before rounding.
    rounding_offset: float
    #: Largest distance of any gap or cone coordinate to an integer in the result.
    lattice_error: float
    #: Σ A |∇f − K|² / Σ A |K|² of the continuous solve and of the result.
    energy_continuous: float
    energy: float
    #: Cones of the field before the cone-pair cancellation (``cone_count`` is after it).
    cones_before_cancellation: int
    #: ± pair moves the cancellation kept (re-matching can open cones elsewhere: the net
    #: change is ``cones_before_cancellation - cone_count``).
    cancelled_pairs: int
    #: Cone-to-boundary moves the cancellation kept.
    cones_moved_to_boundary: int
    #: Folded triangles before the untangling (``flipped_count`` is after it).
    flipped_before_untangling: int
    #: Folded triangles no untangling can open (two corners fixed at one grid point by the
    #: integer unknowns); 0 when ``untangle`` is off.
    forced_flat_count: int


def quadcover(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    field: Optional[ArrayLike] = None,
    grid_spacing: Optional[float] = None,
    alignment: Optional[float] = None,
    round: bool = True,
    cones_on_grid: bool = False,
    pair_cells: Optional[float] = None,
    untangle: bool = True,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, np.ndarray, QuadCoverReport]:
    """QuadCover (Kälberer, Nieser & Polthier 2007; course notes ch. 8; ``uvf_quadcover``): a
    global parameterization of a mesh of any genus whose integer iso-lines close up over the
    whole surface. Across every interior edge the two triangles' (u, v) differ by a quarter
    turn and an integer translation (with ``cones_on_grid``, every cone also sits on an integer
    point, as in mixed-integer quadrangulation; otherwise only the gaps are rounded, as in the
    course notes, which folds fewer triangles). The map may fold
    near cones closer than a grid cell or two (``report.flipped_count``).

    Args:
        field: ``(m, 3)`` tangent vectors, one per triangle (projected on its plane); default:
            a smooth cross field aligned with the principal curvature directions.
        grid_spacing: surface length of one grid cell (default: 3 mean edge lengths).
        alignment: curvature alignment of the default field (default 1; > 0).
        round: ``False`` returns the continuous solve (gaps not integer).
        pair_cells: ± cone pairs of the field closer than this many grid cells are cancelled,
            and cones that close to the boundary moved onto it, before the map is computed
            (default 2; 0 keeps the field's cones; not in the paper). Fewer clustered cones fold
            the map less.
        untangle: after rounding, move the regular vertices near folded triangles to open them,
            keeping every gap, seam and cone position (default ``True``; not in the paper).

    Returns:
        ``(corner_uv, cone_index, report)``: ``(m, 3, 2)`` (u, v) per triangle corner in grid
        units, ``(n,)`` int32 array of 4 × the field's index per vertex (0 off the cones), and a
        :class:`QuadCoverReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options, f = _quadcover_options(t, field, grid_spacing, alignment, round, cones_on_grid, pair_cells, untangle)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    corner_uv = np.empty((len(t), 3, 2), dtype=np.float64)
    cones = np.zeros(len(p), dtype=np.int32)
    report = L.UvfQuadCoverReport()
    lib = L.library()
    field_pointer = _f64p(f) if f is not None else None
    bridge.run(
        lambda: lib.uvf_quadcover(
            _f64p(p),
            len(p),
            _u32p(t),
            len(t),
            byref(options),
            field_pointer,
            _f64p(corner_uv),
            cones.ctypes.data_as(POINTER(ctypes.c_int32)),
            byref(report),
        )
    )
    return corner_uv, cones, _from_struct(QuadCoverReport, report)


def quadcover_quad_mesh(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    density: int = 1,
    field: Optional[ArrayLike] = None,
    grid_spacing: Optional[float] = None,
    alignment: Optional[float] = None,
    cones_on_grid: bool = False,
    pair_cells: Optional[float] = None,
    untangle: bool = True,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, List[np.ndarray], QuadCoverReport]:
    """The integer grid lines of a :func:`quadcover` map as a polygon mesh on the surface
    (``uvf_quadcover_quad_mesh``): lines u, v ∈ ℤ / ``density`` (a whole number ≥ 1; 1: one quad
    per grid cell), joined across every seam; faces that are not quads (around cones, next to
    folded triangles, on the boundary) are split into quads and at most one triangle. Where the
    map has no cone and no fold every face is a quad; ``cones_on_grid=True`` makes most faces
    around cones quads as well. The other arguments are :func:`quadcover`'s.

    Returns:
        ``(positions, faces, report)``: ``(k, 3)`` vertex positions on the input surface, a
        list of int arrays (the corners of every face, counter-clockwise seen from outside),
        and the :class:`QuadCoverReport` of the map.
    """
    p, t = _mesh_arrays(positions, triangles)
    options, f = _quadcover_options(t, field, grid_spacing, alignment, True, cones_on_grid, pair_cells, untangle)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    report = L.UvfQuadCoverReport()
    lib = L.library()
    quad = POINTER(L.UvfQuadMesh)()
    field_pointer = _f64p(f) if f is not None else None
    bridge.run(
        lambda: lib.uvf_quadcover_quad_mesh(
            _f64p(p), len(p), _u32p(t), len(t), byref(options), field_pointer, float(density), byref(quad), byref(report)
        )
    )
    quad_positions, faces = _take_quad_mesh(lib, quad)
    return quad_positions, faces, _from_struct(QuadCoverReport, report)


def _quadcover_options(t, field, grid_spacing, alignment, round, cones_on_grid, pair_cells, untangle):
    """``UvfQuadCoverOptions`` and the checked field array (or None)."""
    options = L.UvfQuadCoverOptions()
    L.library().uvf_quadcover_options_default(byref(options))
    if pair_cells is not None:
        options.pair_cells = float(pair_cells)
    if grid_spacing is not None:
        options.grid_spacing = float(grid_spacing)
    if alignment is not None:
        options.alignment = float(alignment)
    options.round = 1 if round else 0
    options.cones_on_grid = 1 if cones_on_grid else 0
    options.untangle = 1 if untangle else 0
    f = None
    if field is not None:
        f = _as_points(field, 3, "field")
        if len(f) != len(t):
            raise InvalidArgument(f"field has {len(f)} vectors but the mesh has {len(t)} triangles")
    return options, f


@dataclasses.dataclass(frozen=True)
class IntrinsicOptimalReport:
    """What ``uvf_intrinsic_optimal_map`` reports."""

    #: The minimizing λ of ``λ·U^A + (1 − λ)·U^χ``.
    lambda_: float
    energy: float
    #: Energy of the DCP map (λ = 1).
    energy_conformal: float
    #: Energy of the DAP map (λ = 0).
    energy_authalic: float
    boundary_scale: float
    #: Clockwise or degenerate UV triangles of the result.
    flipped: int


def intrinsic_optimal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    energy: Union[str, int] = "edge",
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    lambda_min: float = float("-inf"),
    lambda_max: float = float("inf"),
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, IntrinsicOptimalReport]:
    """Near-optimal intrinsic map (Desbrun et al. 2002 §5.1; ``uvf_intrinsic_optimal_map``):
    ``λ·DCP + (1 − λ)·DAP`` (the two maps, same boundary) of least ``energy`` — ``"edge"``
    (edge-length distortion) or ``"area"`` — over λ in [``lambda_min``, ``lambda_max``],
    by exact polynomial minimization. A circle or square boundary is scaled to the surface area.

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and an :class:`IntrinsicOptimalReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfIntrinsicOptimalOptions()
    L.library().uvf_intrinsic_optimal_options_default(byref(options))
    options.energy = _code(energy, _ENERGIES, "energy")
    keep = _set_boundary(options, boundary)
    options.distribution = _code(distribution, _DISTRIBUTIONS, "distribution")
    options.lambda_min = float(lambda_min)
    options.lambda_max = float(lambda_max)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfIntrinsicOptimalReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_intrinsic_optimal_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report))
    )
    del keep
    return uv, _from_struct(IntrinsicOptimalReport, report)


@dataclasses.dataclass(frozen=True)
class BoundaryOptimizationReport:
    """What ``uvf_boundary_optimized_map`` reports."""

    iterations: int
    converged: int
    #: Entries of the energy history (iterations + 1).
    history_length: int
    initial_energy: float
    final_energy: float
    boundary_scale: float
    #: Triangles flipped in the start, kept as they are by every step (0 for a flip-free start).
    flipped: int


def boundary_optimized_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    energy: Union[str, int] = "edge",
    lambda_: float = 1.0,
    mu: float = 0.0,
    iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    boundary: Boundary = "circle",
    distribution: Union[str, int] = "chord",
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, np.ndarray, BoundaryOptimizationReport]:
    """Boundary-optimized intrinsic map (Desbrun et al. 2002 §5.2; ``uvf_boundary_optimized_map``):
    the λ·DCP + μ·DAP map whose outer boundary descends ``energy`` (``"edge"`` or ``"area"``),
    with steps that never flip or degenerate a triangle. ``progress`` is called once per
    iteration; returning ``False`` cancels before the next one.

    Returns:
        ``(uv, history, report)``: ``(n, 2)`` UVs, the energy history (start first,
        non-increasing; its first 2^20 entries) and a :class:`BoundaryOptimizationReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfBoundaryOptimizationOptions()
    L.library().uvf_boundary_optimization_options_default(byref(options))
    options.energy = _code(energy, _ENERGIES, "energy")
    options.lambda_ = float(lambda_)
    options.mu = float(mu)
    if iterations is not None:
        if not 0 <= int(iterations) <= _U32_MAX:
            raise InvalidArgument(f"iterations must be in [0, {_U32_MAX}], not {iterations}")
        options.iterations = int(iterations)
    if tolerance is not None:
        options.tolerance = float(tolerance)
    keep = _set_boundary(options, boundary)
    options.distribution = _code(distribution, _DISTRIBUTIONS, "distribution")
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    # The library writes what fits; 2^20 energies (8 MiB) rather than a buffer sized by a huge
    # iteration limit that the tolerance ends long before.
    history = np.empty(min(options.iterations + 1, 1 << 20), dtype=np.float64)
    report = L.UvfBoundaryOptimizationReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_boundary_optimized_map(
            _f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), _f64p(history), len(history), byref(report)
        )
    )
    del keep
    result = _from_struct(BoundaryOptimizationReport, report)
    return uv, history[: min(result.history_length, len(history))].copy(), result


@dataclasses.dataclass(frozen=True)
class AbfReport:
    """What ``uvf_abf`` reports about its run."""

    iterations: int
    converged: int
    gradient_norm: float
    invalid_angles: int


def abf(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    *,
    variant: str = "abf++",
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    pins: Optional[Pins] = None,
    weights: str = "angle_and_supplement",
    barrier: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, AbfReport]:
    """Angle based flattening (``uvf_abf``): ``"abf++"`` (Sheffer et al. 2005, default) or
    ``"abf"`` (Sheffer & de Sturler 2001), then the LSCM-style reconstruction of UVs.

    Args:
        weights: the objective's weights w in Σ w (α − β)²: ``"angle_and_supplement"``
            (1/(β(π − β)), default), ``"inverse_square"`` (1/β², the papers') or ``"inverse"``.
        barrier: μ ≥ 0 of the angle barrier μ Σ (α/β − ln(α/β) − 1) (default 1); ``0`` with
            ``weights="inverse_square"`` is the papers' objective.
        pins: ``None`` (default) or ``((v0, (u0, v0_)), (v1, (u1, v1_)))``: the two vertices
            the reconstruction pins and their UVs, as for :func:`natural_conformal_map` (by
            default the two boundary vertices farthest apart).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and an :class:`AbfReport`.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfAbfOptions()
    L.library().uvf_abf_options_default(byref(options))
    options.variant = _code(variant, {"abf": L.UVF_ABF_VARIANT_ABF, "abf++": L.UVF_ABF_VARIANT_ABF_PLUS_PLUS}, "variant")
    if pins is not None:
        _set_two_pins(options, pins)
    if max_iterations is not None:
        options.max_iterations = _non_negative_int(max_iterations, "max_iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    options.weights = _code(
        weights,
        {
            "angle_and_supplement": L.UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT,
            "inverse_square": L.UVF_ABF_WEIGHTS_INVERSE_SQUARE,
            "inverse": L.UVF_ABF_WEIGHTS_INVERSE,
        },
        "weights",
    )
    if barrier is not None:
        options.barrier = float(barrier)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfAbfReport()
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "abf", p, t, byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(AbfReport, report)


def spherical_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    method: str = "tutte_gnomonic",
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, int]:
    """Spherical parameterization of a closed genus-0 mesh (``uvf_spherical_map``; course notes
    §6.1): ``tutte_gnomonic`` (flip-free construction, default), ``gauss_seidel``,
    ``stereographic`` (Haker et al. 2000) or ``circle_patterns`` (Kharevych et al. 2006:
    conformal; angles kept best, flips counted).

    Returns:
        ``(sphere, flipped)``: ``(n, 3)`` unit vectors and the count of flipped spherical
        triangles.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfSphereOptions()
    L.library().uvf_sphere_options_default(byref(options))
    options.method = _code(
        method,
        {
            "tutte_gnomonic": L.UVF_SPHERE_TUTTE_GNOMONIC,
            "gauss_seidel": L.UVF_SPHERE_GAUSS_SEIDEL,
            "stereographic": L.UVF_SPHERE_STEREOGRAPHIC,
            "circle_patterns": L.UVF_SPHERE_CIRCLE_PATTERNS,
        },
        "method",
    )
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    out = np.empty((len(p), 3), dtype=np.float64)
    flipped = ctypes.c_size_t(0)
    lib = L.library()
    bridge.run(lambda: lib.uvf_spherical_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(out), byref(flipped)))
    return out, int(flipped.value)


@dataclasses.dataclass(frozen=True)
class Cut:
    """A mesh cut into a topological disk (``uvf_cut_to_disk``)."""

    positions: np.ndarray  #: ``(k, 3)`` positions of the cut mesh's vertices
    triangles: np.ndarray  #: ``(m, 3)`` triangles of the cut mesh (same order as the input)
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each cut-mesh vertex
    edges: np.ndarray  #: ``(e, 2)`` input vertex pairs along the cut
    seam_length: float
    total_edge_length: float


def cut_to_disk(positions: ArrayLike, triangles: ArrayLike, cost: Union[str, ArrayLike] = "curvature") -> Cut:
    """Cuts a manifold mesh of any genus into a topological disk (``uvf_cut_to_disk``:
    tree-cotree cut graph, Erickson & Har-Peled 2002, steered by a ``curvature`` or ``length``
    edge cost, or by a caller-given ``(m, 3)`` array: the cost of half-edge ``k`` of triangle
    ``t`` (corner ``k`` to corner ``k + 1``), finite and ≥ 0, low cost attracting the cut); any
    disk method then runs on ``Cut.positions`` / ``Cut.triangles``."""
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfCutOptions()
    lib = L.library()
    lib.uvf_cut_options_default(byref(options))
    given = None
    if isinstance(cost, str):
        options.cost = _code(cost, {"curvature": L.UVF_CUT_COST_CURVATURE, "length": L.UVF_CUT_COST_LENGTH}, "cost")
    else:
        try:
            given = np.ascontiguousarray(cost, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InvalidArgument(f"cost must be 'curvature', 'length' or an (m, 3) array of numbers: {e}") from None
        if given.shape != (len(t), 3):
            raise InvalidArgument(f"cost array has shape {given.shape}; expected ({len(t)}, 3), one per half-edge")
        options.cost = L.UVF_CUT_COST_GIVEN
        options.edge_cost = _f64p(given)
    handle = POINTER(L.UvfCut)()
    _check(lib.uvf_cut_to_disk(_f64p(p), len(p), _u32p(t), len(t), byref(options), byref(handle)))
    try:
        info = L.UvfCutInfo()
        _check(lib.uvf_cut_info(handle, byref(info)))
        cut_positions = np.empty((info.vertex_count, 3), dtype=np.float64)
        cut_triangles = np.empty((info.triangle_count, 3), dtype=np.uint32)
        original = np.empty(info.vertex_count, dtype=np.uint32)
        edges = np.empty((info.edge_count, 2), dtype=np.uint32)
        _check(lib.uvf_cut_copy_positions(handle, _f64p(cut_positions), cut_positions.size))
        _check(lib.uvf_cut_copy_triangles(handle, _u32p(cut_triangles), cut_triangles.size))
        _check(lib.uvf_cut_copy_original_vertices(handle, _u32p(original), original.size))
        _check(lib.uvf_cut_copy_edges(handle, _u32p(edges), edges.size))
    finally:
        lib.uvf_cut_free(handle)
    return Cut(cut_positions, cut_triangles, original, edges, info.seam_length, info.total_edge_length)


# --- periodic global parameterization (Ray et al. 2006) --------------------------------------


@dataclasses.dataclass(frozen=True)
class Curvatures:
    """Principal curvatures per vertex (``uvf_curvature``)."""

    kmin_direction: np.ndarray  #: ``(n, 3)`` unit tangent directions of the minimum curvature
    kmax_direction: np.ndarray  #: ``(n, 3)`` unit tangent directions of the maximum curvature
    kmin: np.ndarray  #: ``(n,)`` signed minimum curvature
    kmax: np.ndarray  #: ``(n,)`` signed maximum curvature (a sphere of radius r: 1/r)


def curvature(positions: ArrayLike, triangles: ArrayLike, rings: int = 2, radius: Optional[float] = None) -> Curvatures:
    """Principal curvatures by the normal-cycle tensor of Cohen-Steiner & Morvan 2003
    (``uvf_curvature``), averaged over the triangles around the vertices at most ``rings − 1``
    edges away, or, with ``radius``, within that graph distance."""
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfCurvatureOptions()
    lib = L.library()
    lib.uvf_curvature_options_default(byref(options))
    if radius is None:
        options.rings = _non_negative_int(rings, "rings")
    else:
        options.neighbourhood = L.UVF_CURVATURE_RADIUS
        options.radius = float(radius)
    n = len(p)
    kmin_d, kmax_d = np.empty((n, 3), dtype=np.float64), np.empty((n, 3), dtype=np.float64)
    kmin, kmax = np.empty(n, dtype=np.float64), np.empty(n, dtype=np.float64)
    _check(
        lib.uvf_curvature(
            _f64p(p), n, _u32p(t), len(t), byref(options), _f64p(kmin_d), _f64p(kmax_d), _f64p(kmin), _f64p(kmax)
        )
    )
    return Curvatures(kmin_d, kmax_d, kmin, kmax)


def _non_negative_int(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0 or value > 2**32 - 1:
        raise InvalidArgument(f"{what} must be a non-negative integer, not {value!r}")
    return int(value)


@dataclasses.dataclass(frozen=True)
class PgpResult:
    """A periodic global parameterization (``uvf_pgp``)."""

    corner_coords: np.ndarray  #: ``(m, 3, 2)`` (θ, φ) at corner k of triangle t, period 2π
    singular_vertices: np.ndarray  #: ``(a,)`` vertices whose (θ, φ) angles do not sum to 2π
    singular_edges: np.ndarray  #: ``(b, 2)`` edges whose transition functions disagree
    singular_triangles: np.ndarray  #: ``(c,)`` open or flipped (θ, φ) triangles
    singular_points: np.ndarray  #: ``(d,)`` vertices with a non-zero index
    indices: np.ndarray  #: ``(d,)`` their indices (multiples of 1/4; they sum to 2 − 2g)
    field: np.ndarray  #: ``(n, 3)`` the field the solve followed
    omega: float
    newton_iterations: int
    converged: bool
    final_gradient: float
    stretch: float  #: L2 stretch of (θ, φ)/ω over the regular triangles
    shear: float  #: mean |cos| of the angle between the parameter directions
    alignment_degrees: float  #: mean angle between the gradients and the field
    #: the quad-dominant remesh when ``quad_mesh`` was given: ``(positions (k, 3), faces)``,
    #: ``faces`` a list of vertex-index arrays (counter-clockwise seen from outside)
    quad_mesh: Optional[Tuple[np.ndarray, List[np.ndarray]]] = None
    #: the chart layout when ``chart_layout`` was set: ``(polylines, chart_corners)``, the chart
    #: boundaries as ``(j, 3)`` point arrays and the number of corners of every chart
    chart_layout: Optional[Tuple[List[np.ndarray], np.ndarray]] = None
    #: the per-chart parameterization when ``charts`` was given
    charts: Optional["PgpCharts"] = None

    @property
    def uv(self) -> np.ndarray:
        """``(m, 3, 2)`` texture coordinates (θ, φ)/2π: one texture tile per period."""
        return self.corner_coords / (2.0 * np.pi)


@dataclasses.dataclass(frozen=True)
class PgpCharts:
    """The per-chart parameterization of a PGP result (``uvf_pgp_charts``, §3.3–3.4): the
    surface cut along the iso-lines, each chart with its own (u, v) in cells (a regular chart
    is the unit square)."""

    positions: np.ndarray  #: ``(k, 3)`` vertices of the cut triangulation (input vertices first)
    triangles: np.ndarray  #: ``(m, 3)`` its triangles, counter-clockwise
    uv: np.ndarray  #: ``(m, 3, 2)`` (u, v) at every corner, in cells
    chart: np.ndarray  #: ``(m,)`` chart of every triangle
    origin: np.ndarray  #: ``(m,)`` input triangle every triangle lies in
    kinds: np.ndarray  #: ``(c,)`` ``UVF_PGP_CHART_*`` of every chart
    corners: np.ndarray  #: ``(c,)`` corners of every chart (0: not a disk)
    layout: np.ndarray  #: ``(c,)`` layout chart it is (or is a quad of)
    sizes: np.ndarray  #: ``(c, 2)`` (u, v) extent of every chart, in cells


_SMOOTHING = {
    "none": L.UVF_SMOOTH_NONE,
    "2pi": L.UVF_SMOOTH_2PI,
    "pi": L.UVF_SMOOTH_PI,
    "pi/2": L.UVF_SMOOTH_HALF_PI,
}


def pgp(
    positions: ArrayLike,
    triangles: ArrayLike,
    omega: Optional[float] = None,
    field: Optional[ArrayLike] = None,
    smooth: str = "pi/2",
    curl_correction: bool = False,
    rho: float = 0.8,
    epsilon: float = 0.1,
    max_newton_iterations: int = 100,
    progress: Optional[ProgressCallback] = None,
    quad_mesh: Optional[float] = None,
    chart_layout: bool = False,
    charts: Optional[float] = None,
    untangle: bool = True,
    feature_periods: float = 3.0,
    pair_periods: float = 0.5,
    dislocation_periods: float = 1.5,
    relax: bool = True,
) -> PgpResult:
    """Periodic Global Parameterization (Ray, Li, Lévy, Sheffer, Alliez 2006; ``uvf_pgp``) of a
    manifold mesh of any genus, without cutting: principal-curvature field (or ``field``, an
    ``(n, 3)`` array), smoothing modulo ``smooth`` (``"none"``, ``"2pi"``, ``"pi"``,
    ``"pi/2"``), optional curl correction, the periodic solve and the per-corner (θ, φ).
    ``omega`` defaults to 2π / (10 × mean edge length); ``rho`` is the smoothing intensity
    (paper 0.8) and ``epsilon`` the weight of the periodic solve's unit-norm penalty (0.1; the
    paper's 10⁻³ lets every norm collapse on typical meshes, see docs/methods/pgp.md);
    ``max_newton_iterations`` bounds its Newton phase, which stops at the paper's ‖∇F**‖ < 10⁻⁶
    (5–80 iterations on the meshes measured, ``converged`` tells; 10 is about 3× faster with
    nearly the same singularities). ``untangle=False`` keeps Algorithm 1's per-corner (θ, φ) as
    it is; by default the negative triangles next to singular points are made positive by
    moving vertex phases, every transition kept (not in the paper; see docs/methods/pgp.md).
    ``feature_periods`` is the minimum number of periods around a curved feature: where a
    curvature radius r holds fewer (ω r < feature_periods) the frequency is raised there, at
    most 2.5×, so that legs, horns and fingers narrower than a period are not singular standing
    waves (not in the paper; see docs/methods/pgp.md); 0 keeps the paper's single ω everywhere.
    ``pair_periods``: the +¼ and −¼ singularities of the smoothed cross field closer than this
    many periods (2π/ω) are cancelled together and the field re-solved around them (not in the
    paper; see docs/methods/pgp.md); 0 keeps the smoothed field's singularities.
    ``dislocation_periods``: open triangles of opposite winding where the field is regular
    (dislocations of the wave pattern) closer than this many periods are annihilated together by
    turning the phases around them (not in the paper; see docs/methods/pgp.md); 0 keeps the periodic
    solve's phases. ``relax=False`` skips the phase relaxation that by default runs before the
    untangling: every vertex's phases turned by the least-squares fit of the (θ, φ) triangles to
    the field, every transition kept, used only where it leaves no more singular triangles (not
    in the paper; see docs/methods/pgp.md).

    ``quad_mesh`` (a whole number of iso-lines per period, e.g. 8) also returns the quad-dominant
    remesh of §5 (vertices on the surface, non-quads split into quads and triangles; quad sides
    about 2π / (ω · quad_mesh) long); ``chart_layout=True`` returns the chart boundaries along the
    iso-2kπ lines (§3.3); ``charts`` (a whole number of lines per period, 1 for the paper's
    iso-2kπ lines) returns the per-chart parameterization of §3.4 (:class:`PgpCharts`): charts
    without singularity assembled, singular ones re-parameterized by mean-value coordinates
    (N-sided ones split into quads), charts that are not disks flattened by the atlas."""
    p, t = _mesh_arrays(positions, triangles)
    lib = L.library()
    options = L.UvfPgpOptions()
    lib.uvf_pgp_options_default(byref(options))
    if omega is not None:
        options.omega = float(omega)
    options.smoothing = _code(smooth, _SMOOTHING, "smooth")
    options.curl_correction = 1 if curl_correction else 0
    options.untangle = 1 if untangle else 0
    options.feature_periods = float(feature_periods)
    options.pair_periods = float(pair_periods)
    options.dislocation_periods = float(dislocation_periods)
    options.relax = 1 if relax else 0
    options.rho = float(rho)
    options.epsilon = float(epsilon)
    if isinstance(max_newton_iterations, bool) or int(max_newton_iterations) != max_newton_iterations:
        raise InvalidArgument(f"max_newton_iterations must be a whole number (got {max_newton_iterations!r})")
    if not 0 <= max_newton_iterations < 2**32:
        raise InvalidArgument(f"max_newton_iterations must be in [0, 2^32) (got {max_newton_iterations})")
    options.max_newton_iterations = int(max_newton_iterations)
    given = None
    if field is not None:
        given = _as_points(field, 3, "field")
        if len(given) != len(p):
            raise InvalidArgument(f"field has {len(given)} vectors but the mesh has {len(p)} vertices")
        options.field = _f64p(given)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    coords = np.empty((len(t), 3, 2), dtype=np.float64)
    handle = POINTER(L.UvfPgp)()
    bridge.run(lambda: lib.uvf_pgp(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(coords), byref(handle)))
    try:
        remesh = _quad_mesh(lib, handle, quad_mesh) if quad_mesh is not None else None
        layout = _chart_layout(lib, handle) if chart_layout else None
        cut = _charts(lib, handle, charts) if charts is not None else None
        info = L.UvfPgpInfo()
        _check(lib.uvf_pgp_info(handle, byref(info)))
        vertices = np.empty(info.singular_vertex_count, dtype=np.uint32)
        edges = np.empty((info.singular_edge_count, 2), dtype=np.uint32)
        tris = np.empty(info.singular_triangle_count, dtype=np.uint32)
        points = np.empty(info.singular_point_count, dtype=np.uint32)
        indices = np.empty(info.singular_point_count, dtype=np.float64)
        used_field = np.empty((len(p), 3), dtype=np.float64)
        _check(lib.uvf_pgp_copy_singular_vertices(handle, _u32p(vertices), vertices.size))
        _check(lib.uvf_pgp_copy_singular_edges(handle, _u32p(edges), edges.size))
        _check(lib.uvf_pgp_copy_singular_triangles(handle, _u32p(tris), tris.size))
        _check(lib.uvf_pgp_copy_singular_points(handle, _u32p(points), _f64p(indices), points.size))
        _check(lib.uvf_pgp_copy_field(handle, _f64p(used_field), used_field.size))
    finally:
        lib.uvf_pgp_free(handle)
    return PgpResult(
        coords,
        vertices,
        edges,
        tris,
        points,
        indices,
        used_field,
        info.omega,
        info.newton_iterations,
        bool(info.converged),
        info.final_gradient,
        info.stretch,
        info.shear,
        info.alignment_degrees,
        remesh,
        layout,
        cut,
    )


def _split(flat: np.ndarray, sizes: np.ndarray) -> List[np.ndarray]:
    return np.split(flat, np.cumsum(sizes)[:-1]) if len(sizes) else []


def _quad_mesh(lib, handle, density: float) -> Tuple[np.ndarray, List[np.ndarray]]:
    quad = POINTER(L.UvfQuadMesh)()
    _check(lib.uvf_pgp_quad_mesh(handle, float(density), byref(quad)))
    return _take_quad_mesh(lib, quad)


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


def _chart_layout(lib, handle) -> Tuple[List[np.ndarray], np.ndarray]:
    layout = POINTER(L.UvfChartLayout)()
    _check(lib.uvf_pgp_chart_layout(handle, byref(layout)))
    try:
        info = L.UvfChartLayoutInfo()
        _check(lib.uvf_chart_layout_info(layout, byref(info)))
        sizes = np.empty(info.polyline_count, dtype=np.uint32)
        points = np.empty((info.point_count, 3), dtype=np.float64)
        corners = np.empty(info.chart_count, dtype=np.uint32)
        _check(
            lib.uvf_chart_layout_copy(
                layout, _u32p(sizes), sizes.size, _f64p(points), points.size, _u32p(corners), corners.size
            )
        )
    finally:
        lib.uvf_chart_layout_free(layout)
    return _split(points, sizes), corners


def _charts(lib, handle, density: float) -> PgpCharts:
    charts = POINTER(L.UvfPgpCharts)()
    _check(lib.uvf_pgp_charts(handle, float(density), byref(charts)))
    try:
        info = L.UvfPgpChartsInfo()
        _check(lib.uvf_pgp_charts_info(charts, byref(info)))
        m, c = info.triangle_count, info.chart_count
        positions = np.empty((info.vertex_count, 3), dtype=np.float64)
        triangles = np.empty((m, 3), dtype=np.uint32)
        uv = np.empty((m, 3, 2), dtype=np.float64)
        chart = np.empty(m, dtype=np.uint32)
        origin = np.empty(m, dtype=np.uint32)
        _check(
            lib.uvf_pgp_charts_copy(
                charts,
                _f64p(positions),
                positions.size,
                _u32p(triangles),
                triangles.size,
                _f64p(uv),
                uv.size,
                _u32p(chart),
                chart.size,
                _u32p(origin),
                origin.size,
            )
        )
        kinds, corners, layout = (np.empty(c, dtype=np.uint32) for _ in range(3))
        sizes = np.empty((c, 2), dtype=np.float64)
        _check(
            lib.uvf_pgp_charts_copy_charts(
                charts, _u32p(kinds), c, _u32p(corners), c, _u32p(layout), c, _f64p(sizes), sizes.size
            )
        )
    finally:
        lib.uvf_pgp_charts_free(charts)
    return PgpCharts(positions, triangles, uv, chart, origin, kinds, corners, layout, sizes)


@dataclasses.dataclass(frozen=True)
class Atlas:
    """A packed atlas (``uvf_atlas``): charts under a stretch bound in the unit square."""

    uv: np.ndarray  #: ``(k, 2)`` UV of every atlas vertex, in [0, 1]
    triangles: np.ndarray  #: ``(m, 3)`` atlas vertex of each corner of each input triangle
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each atlas vertex
    charts: np.ndarray  #: ``(m,)`` chart id of each input triangle
    chart_count: int
    utilization: float  #: fraction of the unit square covered by charts
    stretch_l2: float  #: L2 stretch of the whole atlas
    max_chart_stretch: float

    @property
    def corner_uv(self) -> np.ndarray:
        """``(m, 3, 2)`` UV of every corner."""
        return self.uv[self.triangles]


def _atlas_arrays(lib: Any, handle: Any) -> Tuple[Any, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Info, UVs, per-corner UV indices, input vertices and chart ids of an atlas handle."""
    info = L.UvfAtlasInfo()
    _check(lib.uvf_atlas_info(handle, byref(info)))
    uv = np.empty((info.vertex_count, 2), dtype=np.float64)
    uv_triangles = np.empty((info.triangle_count, 3), dtype=np.uint32)
    original = np.empty(info.vertex_count, dtype=np.uint32)
    charts = np.empty(info.triangle_count, dtype=np.uint32)
    _check(lib.uvf_atlas_copy_uv(handle, _f64p(uv), uv.size))
    _check(lib.uvf_atlas_copy_triangles(handle, _u32p(uv_triangles), uv_triangles.size))
    _check(lib.uvf_atlas_copy_original_vertices(handle, _u32p(original), original.size))
    _check(lib.uvf_atlas_copy_charts(handle, _u32p(charts), charts.size))
    return info, uv, uv_triangles, original, charts


def _set_layout_options(options: Any, max_stretch: float, margin: float, method: str, iterations: int, rotate: bool) -> None:
    """The fields `UvfAtlasOptions` and `UvfUnwrapOptions` share, checked."""
    options.max_stretch = float(max_stretch)
    options.margin = float(margin)
    options.method = _code(method, _ATLAS_METHODS, "method")
    if not (isinstance(iterations, int) and 0 <= iterations < 2**32):
        raise InvalidArgument(f"iterations must be an integer in [0, 2^32), not {iterations!r}")
    options.iterations = iterations
    options.rotate = 1 if rotate else 0


_ATLAS_METHODS = {
    "natural_conformal": L.UVF_ATLAS_CHART_NATURAL_CONFORMAL,
    "lscm": L.UVF_ATLAS_CHART_NATURAL_CONFORMAL,
    "mean_value": L.UVF_ATLAS_CHART_MEAN_VALUE,
    "slim": L.UVF_ATLAS_CHART_SLIM,
    "stretch": L.UVF_ATLAS_CHART_STRETCH,
}


def atlas(
    positions: ArrayLike,
    triangles: ArrayLike,
    max_stretch: float = 1.004,
    margin: float = 0.005,
    method: str = "natural_conformal",
    iterations: int = 20,
    rotate: bool = True,
    merge: bool = True,
    polish_iterations: int = 10,
    progress: Optional[ProgressCallback] = None,
) -> Atlas:
    """Atlas of any manifold mesh (``uvf_atlas``): charts split top-down until each flattens
    (``method``: ``natural_conformal``, ``mean_value``, ``slim`` or ``stretch``) without flips
    or overlaps with L2 stretch ≤ ``max_stretch``, adjacent charts merged while still valid,
    then packed into the unit square with ``margin`` between charts (``rotate``: let the packer
    turn charts). ``polish_iterations`` L2-stretch minimization steps are spent on every chart
    slightly over the bound before it is judged and on every accepted chart before packing (0:
    none). ``progress`` may cancel (raises :class:`Cancelled`)."""
    p, t = _mesh_arrays(positions, triangles)
    lib = L.library()
    options = L.UvfAtlasOptions()
    lib.uvf_atlas_options_default(byref(options))
    _set_layout_options(options, max_stretch, margin, method, iterations, rotate)
    options.merge = 1 if merge else 0
    if not (isinstance(polish_iterations, int) and 0 <= polish_iterations < 2**32):
        raise InvalidArgument(f"polish_iterations must be an integer in [0, 2^32), not {polish_iterations!r}")
    options.polish_iterations = polish_iterations
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    handle = POINTER(L.UvfAtlas)()
    bridge.run(lambda: lib.uvf_atlas(_f64p(p), len(p), _u32p(t), len(t), byref(options), byref(handle)))
    try:
        info, uv, uv_triangles, original, charts = _atlas_arrays(lib, handle)
        corner = np.empty((info.triangle_count, 3, 2), dtype=np.float64)
        _check(lib.uvf_atlas_copy_corner_uv(handle, _f64p(corner), corner.size))
    finally:
        lib.uvf_atlas_free(handle)
    if not np.array_equal(corner, uv[uv_triangles]):
        raise InternalError("uvf_atlas_copy_corner_uv disagrees with the atlas vertices (please report this bug)")
    return Atlas(
        uv, uv_triangles, original, charts, info.chart_count, info.utilization, info.stretch_l2, info.max_chart_stretch
    )


@dataclasses.dataclass(frozen=True)
class LayoutCheck:
    """What :func:`check_layout` found (``UvfLayoutCheck``)."""

    #: Triangles not strictly counter-clockwise, or with a non-finite corner.
    flipped: int
    #: Crossing, touching or overlapping boundary-edge pairs, plus islands inside another.
    overlaps: int
    #: Islands (triangles connected through shared UV vertices).
    islands: int


def check_layout(uv: ArrayLike, uv_triangles: ArrayLike) -> LayoutCheck:
    """Exact, method-independent check of any UV layout (``uvf_check_layout``): ``uv`` is
    ``(k, 2)``, ``uv_triangles`` ``(m, 3)`` indices into it. A layout with no flipped triangle
    and no overlap covers no point twice."""
    q = np.ascontiguousarray(uv, dtype=np.float64).reshape(-1, 2)
    t = np.ascontiguousarray(uv_triangles, dtype=np.uint32).reshape(-1, 3)
    out = L.UvfLayoutCheck()
    _check(L.library().uvf_check_layout(_f64p(q), len(q), _u32p(t), len(t), byref(out)))
    return LayoutCheck(out.flipped, out.overlaps, out.islands)


@dataclasses.dataclass(frozen=True)
class UnwrapReport:
    """What :func:`unwrap` did, measured on its result (``UvfUnwrapReport``)."""

    #: Islands of the layout.
    islands: int
    #: Islands the method could not lay out validly, laid out by bijective SLIM instead.
    repaired_islands: int
    #: Input edges cut.
    seam_edges: int
    #: UV vertices.
    uv_vertex_count: int
    #: Flipped or degenerate UV triangles, by the library's independent exact checker (0).
    flipped: int
    #: Touching boundary-edge pairs and nested islands, by the same checker (0).
    overlaps: int
    #: L2 stretch of the whole layout.
    stretch_l2: float
    #: Largest L2 stretch of one island.
    max_island_stretch: float
    #: Mean angle distortion over corners, in degrees.
    angle_error_mean_deg: float
    #: Fraction of the unit square covered by islands.
    utilization: float


@dataclasses.dataclass(frozen=True)
class Unwrapped:
    """The result of :func:`unwrap`: a packed, verified layout."""

    uv: np.ndarray  #: ``(k, 2)`` UV of every UV vertex, in [0, 1]
    triangles: np.ndarray  #: ``(m, 3)`` UV vertex of each corner of each input triangle
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each UV vertex
    islands: np.ndarray  #: ``(m,)`` island of each input triangle
    seams: np.ndarray  #: ``(s, 2)`` cut input edges as vertex pairs ``a < b``
    report: UnwrapReport

    @property
    def corner_uv(self) -> np.ndarray:
        """``(m, 3, 2)`` UV of every corner."""
        return self.uv[self.triangles]


def unwrap(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    max_stretch: float = 1.5,
    margin: float = 0.005,
    method: str = "natural_conformal",
    iterations: int = 100,
    rotate: bool = True,
    progress: Optional[ProgressCallback] = None,
) -> Unwrapped:
    """UVs for any manifold mesh in one call (``uvf_unwrap``): every component starts as one
    island (cut into a disk when closed or with handles) flattened by ``method``
    (``natural_conformal``, ``mean_value``, ``slim`` or ``stretch``); an island that flips or
    overlaps is laid out again by bijective SLIM, one over ``max_stretch`` (L2, ≥ 1;
    ``math.inf``: no bound) is split; the islands are packed into the unit square ``margin``
    apart and the layout is verified: no flipped triangle, no overlap. ``progress`` may cancel
    (raises :class:`Cancelled`).

    Example::

        result = uvflat.unwrap(positions, triangles)
        assert result.report.flipped == 0 and result.report.overlaps == 0
        corner_uv = result.corner_uv  # (m, 3, 2)
    """
    p, t = _mesh_source(positions, triangles)
    lib = L.library()
    options = L.UvfUnwrapOptions()
    lib.uvf_unwrap_options_default(byref(options))
    _set_layout_options(options, max_stretch, margin, method, iterations, rotate)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    handle = POINTER(L.UvfUnwrap)()
    bridge.run(lambda: _on_mesh(lib, "unwrap", p, t, byref(options), byref(handle)))
    try:
        report = L.UvfUnwrapReport()
        _check(lib.uvf_unwrap_report(handle, byref(report)))
        layout = POINTER(L.UvfAtlas)()
        _check(lib.uvf_unwrap_atlas(handle, byref(layout)))
        _, uv, uv_triangles, original, islands = _atlas_arrays(lib, layout)
        seams = np.empty((report.seam_edges, 2), dtype=np.uint32)
        _check(lib.uvf_unwrap_copy_seams(handle, _u32p(seams), seams.size))
    finally:
        lib.uvf_unwrap_free(handle)
    fields = {f.name: getattr(report, f.name) for f in dataclasses.fields(UnwrapReport)}
    return Unwrapped(uv, uv_triangles, original, islands, seams, UnwrapReport(**fields))


class BoundaryEditor:
    """Real-time boundary editing (Desbrun et al. 2002 §4.2, ``uvf_boundary_editor_*``): the
    intrinsic map ``lambda_·conformal + mu·authalic`` is factored once; :meth:`solve` then
    returns the whole map for new boundary positions in milliseconds. Solves on one editor may
    run concurrently from several threads.

    Example::

        editor = uvflat.BoundaryEditor(positions, triangles, lambda_=1.0, mu=0.0)
        ring = editor.boundary                      # boundary vertices, solve() order
        angle = np.linspace(0, 2 * np.pi, len(ring), endpoint=False)
        uv = editor.solve(np.c_[np.cos(angle), np.sin(angle)])

    Raises (constructor): InvalidArgument, InvalidMesh, UnsupportedTopology (not a disk),
    NumericalFailure, Cancelled.
    """

    def __init__(
        self,
        positions: ArrayLike,
        triangles: ArrayLike,
        lambda_: float = 1.0,
        mu: float = 0.0,
        progress: Optional[ProgressCallback] = None,
    ) -> None:
        p, t = _mesh_arrays(positions, triangles)
        self._vertex_count = len(p)
        # solve() and basis() run without the GIL; close() must not free the handle under them.
        self._lock = threading.Lock()
        self._lib = L.library()
        options = L.UvfIntrinsicToolOptions()
        self._lib.uvf_intrinsic_tool_options_default(byref(options))
        bridge = _ProgressBridge(progress)
        options.progress = bridge.c_function
        self._handle = POINTER(L.UvfBoundaryEditor)()
        bridge.run(
            lambda: self._lib.uvf_boundary_editor_new(
                _f64p(p), len(p), _u32p(t), len(t), float(lambda_), float(mu), byref(options), byref(self._handle)
            )
        )
        count = ctypes.c_size_t()
        _check(self._lib.uvf_boundary_editor_boundary(self._handle, byref(count), None))
        #: Boundary vertices in the order :meth:`solve` expects their UVs.
        self.boundary = np.empty(count.value, dtype=np.uint32)
        _check(self._lib.uvf_boundary_editor_boundary(self._handle, byref(count), _u32p(self.boundary)))

    def solve(self, boundary_uv: ArrayLike) -> np.ndarray:
        """``(n, 2)`` UVs of every vertex for the ``(b, 2)`` boundary positions (in
        :attr:`boundary` order); NaN for unreferenced vertices."""
        b = np.ascontiguousarray(boundary_uv, dtype=np.float64)
        if b.shape != (len(self.boundary), 2):
            raise InvalidArgument(f"boundary_uv must have shape ({len(self.boundary)}, 2), not {b.shape}")
        uv = np.empty((self._vertex_count, 2), dtype=np.float64)
        with self._lock:
            _check(self._lib.uvf_boundary_editor_solve(self._handle, _f64p(b), len(b), _f64p(uv)))
        return uv

    def basis(self, max_bytes: int = 1 << 30) -> np.ndarray:
        """The Green-function basis as a ``(b, n)`` array: ``uv = basis.T @ boundary_uv``.
        Costs 8·n·b bytes; refused with InvalidArgument above ``max_bytes`` (default 1 GiB)."""
        needed = 8 * len(self.boundary) * self._vertex_count
        if needed > max_bytes:
            raise InvalidArgument(f"the basis needs {needed} bytes, more than max_bytes = {max_bytes}")
        out = np.empty((len(self.boundary), self._vertex_count), dtype=np.float64)
        with self._lock:
            _check(self._lib.uvf_boundary_editor_basis(self._handle, int(max_bytes), _f64p(out)))
        return out

    def close(self) -> None:
        """Frees the factorization now (also done when the editor is garbage-collected); waits
        for a :meth:`solve` running in another thread. Later solves raise InvalidArgument."""
        lock = getattr(self, "_lock", None)
        if lock is None:
            return
        with lock:
            if getattr(self, "_handle", None):
                self._lib.uvf_boundary_editor_free(self._handle)
                self._handle = None

    def __enter__(self) -> "BoundaryEditor":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        self.close()
