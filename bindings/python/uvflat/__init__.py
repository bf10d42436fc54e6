"""uvflat: mesh parameterization (UV unwrapping) from Python.

A pure-Python ``ctypes`` binding of the uvflat C library (``libuvflat.so``) with numpy arrays
in and out::

    import numpy as np
    import uvflat

    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]], dtype=float)
    triangles = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
    uv = uvflat.natural_conformal_map(positions, triangles)     # (4, 2) float64
    print(uvflat.metrics(positions, triangles, uv).angle_mean)

The library is found on first use (see :func:`load_library`): an explicit path, then
``$UVFLAT_LIBRARY``, then a ``libuvflat.so`` copied into this package, then the system
search path. Failures raise a subclass of :class:`Error` carrying ``.status`` and the
library's ``.message``.

Threads: ``ctypes`` releases the GIL while a uvflat function runs, so calls from several
Python threads run in parallel; the library is reentrant and keeps its error message per
thread. Progress callbacks run with the GIL held, in the calling thread.
"""

from ._api import (
    AbfReport,
    Cut,
    MeshInfo,
    NonlinearReport,
    abf,
    cut_to_disk,
    nonlinear_map,
    pinned_natural_conformal_map,
    spherical_map,
    Metrics,
    abi_version,
    authalic,
    boundary_loops,
    conformal,
    fixed_boundary_map,
    floater,
    intrinsic,
    lscm,
    mean_value,
    mesh_info,
    metrics,
    natural_conformal_map,
    triangle_components,
    tutte,
    version,
)
from ._errors import (
    Cancelled,
    Error,
    InternalError,
    InvalidArgument,
    InvalidMesh,
    IoError,
    LibraryError,
    NotImplemented,
    NumericalFailure,
    Status,
    UnsupportedTopology,
)
from ._library import (
    UVF_ABF_VARIANT_ABF,
    UVF_ABF_VARIANT_ABF_PLUS_PLUS,
    UVF_NONLINEAR_SLIM,
    UVF_NONLINEAR_ARAP,
    UVF_NONLINEAR_MIPS,
    UVF_NONLINEAR_STRETCH,
    UVF_NONLINEAR_GREEN_LAGRANGE,
    UVF_NONLINEAR_DEGENER,
    UVF_CUT_COST_CURVATURE,
    UVF_CUT_COST_LENGTH,
    UVF_CUT_COST_GIVEN,
    UVF_SPHERE_TUTTE_GNOMONIC,
    UVF_SPHERE_GAUSS_SEIDEL,
    UVF_SPHERE_STEREOGRAPHIC,
    ABI_VERSION,
    LIBRARY_ENV,
    UVF_BOUNDARY_CIRCLE,
    UVF_BOUNDARY_GIVEN,
    UVF_BOUNDARY_SQUARE,
    UVF_DISTRIBUTION_CENTRIPETAL,
    UVF_DISTRIBUTION_CHORD,
    UVF_DISTRIBUTION_UNIFORM,
    UVF_WEIGHTS_AUTHALIC,
    UVF_WEIGHTS_CONFORMAL,
    UVF_WEIGHTS_FLOATER,
    UVF_WEIGHTS_INTRINSIC,
    UVF_WEIGHTS_MEAN_VALUE,
    UVF_WEIGHTS_UNIFORM,
    library_path,
    load_library,
)

#: Version of this Python package (the library's is :func:`version`).
__version__ = "0.1.0"

__all__ = [
    "ABI_VERSION",
    "LIBRARY_ENV",
    "Cancelled",
    "Error",
    "InternalError",
    "InvalidArgument",
    "InvalidMesh",
    "IoError",
    "LibraryError",
    "AbfReport",
    "Cut",
    "MeshInfo",
    "NonlinearReport",
    "abf",
    "cut_to_disk",
    "nonlinear_map",
    "pinned_natural_conformal_map",
    "spherical_map",
    "Metrics",
    "NotImplemented",
    "NumericalFailure",
    "Status",
    "UnsupportedTopology",
    "UVF_ABF_VARIANT_ABF",
    "UVF_ABF_VARIANT_ABF_PLUS_PLUS",
    "UVF_NONLINEAR_SLIM",
    "UVF_NONLINEAR_ARAP",
    "UVF_NONLINEAR_MIPS",
    "UVF_NONLINEAR_STRETCH",
    "UVF_NONLINEAR_GREEN_LAGRANGE",
    "UVF_NONLINEAR_DEGENER",
    "UVF_CUT_COST_CURVATURE",
    "UVF_CUT_COST_LENGTH",
    "UVF_CUT_COST_GIVEN",
    "UVF_SPHERE_TUTTE_GNOMONIC",
    "UVF_SPHERE_GAUSS_SEIDEL",
    "UVF_SPHERE_STEREOGRAPHIC",
    "UVF_BOUNDARY_CIRCLE",
    "UVF_BOUNDARY_GIVEN",
    "UVF_BOUNDARY_SQUARE",
    "UVF_DISTRIBUTION_CENTRIPETAL",
    "UVF_DISTRIBUTION_CHORD",
    "UVF_DISTRIBUTION_UNIFORM",
    "UVF_WEIGHTS_AUTHALIC",
    "UVF_WEIGHTS_CONFORMAL",
    "UVF_WEIGHTS_FLOATER",
    "UVF_WEIGHTS_INTRINSIC",
    "UVF_WEIGHTS_MEAN_VALUE",
    "UVF_WEIGHTS_UNIFORM",
    "abi_version",
    "authalic",
    "boundary_loops",
    "conformal",
    "fixed_boundary_map",
    "floater",
    "intrinsic",
    "library_path",
    "load_library",
    "lscm",
    "mean_value",
    "mesh_info",
    "metrics",
    "natural_conformal_map",
    "triangle_components",
    "tutte",
    "version",
]
