"""uvflat: mesh parameterization (UV unwrapping) from Python.

A pure-Python ``ctypes`` binding of the uvflat C library (``libuvflat.so``) with numpy arrays
in and out::

    import numpy as np
    import uvflat

    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]], dtype=float)
    triangles = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
    result = uvflat.unwrap(positions, triangles)   # verified: no flip, no overlap
    corner_uv = result.corner_uv                     # (2, 3, 2) float64, in [0, 1]²
    uv = uvflat.natural_conformal_map(positions, triangles)     # one method: (4, 2) float64
    print(uvflat.metrics(positions, triangles, uv).angle_mean)

The library is found on first use (see :func:`load_library`): an explicit path, then
``$UVFLAT_LIBRARY``, then a ``libuvflat.so`` copied into this package, then the system
search path. Failures raise a subclass of :class:`Error` carrying ``.status`` and the
library's ``.message``.

Threads: ``ctypes`` releases the GIL while a uvflat function runs, so calls from several
Python threads run in parallel; the library is reentrant and keeps its error message per
thread. Progress callbacks run with the GIL held, in the calling thread.
"""

from ._mesh import Mesh
from ._common import (
    abi_version,
    set_thread_count,
    thread_count,
    version,
)
from ._queries import (
    LayoutCheck,
    check_layout,
    MeshInfo,
    Metrics,
    boundary_loops,
    mesh_info,
    metrics,
    triangle_components,
)
from ._barycentric import (
    authalic,
    conformal,
    fixed_boundary_map,
    floater,
    intrinsic,
    mean_value,
    tutte,
)
from ._conformal import (
    pinned_natural_conformal_map,
    lscm,
    natural_conformal_map,
)
from ._nonlinear import (
    AbfReport,
    NonlinearReport,
    abf,
    nonlinear_map,
)
from ._intrinsic_tools import (
    BoundaryEditor,
    BoundaryOptimizationReport,
    IntrinsicOptimalReport,
    SpectralReport,
    boundary_optimized_map,
    intrinsic_optimal_map,
    spectral_conformal_map,
)
from ._circle_patterns import (
    circle_pattern_map,
    circle_pattern_cone_map,
    ConePlacement,
    place_cones,
    polygon_boundary_curvature,
    CirclePatternReport,
)
from ._quadcover import (
    QuadCoverReport,
    quadcover,
    quadcover_quad_mesh,
)
from ._closed import (
    Cut,
    cut_to_disk,
    spherical_map,
)
from ._pgp import (
    Curvatures,
    PgpCharts,
    PgpResult,
    curvature,
    pgp,
)
from ._atlas import (
    Atlas,
    atlas,
)
from ._unwrap import (
    Unwrapped,
    UnwrapReport,
    unwrap,
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
    UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT,
    UVF_ABF_WEIGHTS_INVERSE,
    UVF_ABF_WEIGHTS_INVERSE_SQUARE,
    UVF_NONLINEAR_SLIM,
    UVF_PGP_CHART_ASSEMBLED,
    UVF_PGP_CHART_ATLAS,
    UVF_PGP_CHART_MEAN_VALUE,
    UVF_PGP_CHART_SPLIT_QUAD,
    UVF_PGP_CHART_UNRESOLVED,
    UVF_NONLINEAR_ARAP,
    UVF_NONLINEAR_MIPS,
    UVF_NONLINEAR_STRETCH,
    UVF_NONLINEAR_GREEN_LAGRANGE,
    UVF_NONLINEAR_DEGENER,
    UVF_CUT_COST_CURVATURE,
    UVF_CUT_COST_LENGTH,
    UVF_CUT_COST_GIVEN,
    UVF_ATLAS_CHART_NATURAL_CONFORMAL,
    UVF_ATLAS_CHART_MEAN_VALUE,
    UVF_ATLAS_CHART_SLIM,
    UVF_ATLAS_CHART_STRETCH,
    UVF_SPHERE_TUTTE_GNOMONIC,
    UVF_SPHERE_GAUSS_SEIDEL,
    UVF_SPHERE_STEREOGRAPHIC,
    UVF_SPHERE_CIRCLE_PATTERNS,
    UVF_ENERGY_EDGE_LENGTH,
    UVF_ENERGY_AREA,
    UVF_CURVATURE_RINGS,
    UVF_CURVATURE_RADIUS,
    UVF_INDEX_UINT16,
    UVF_INDEX_UINT32,
    UVF_SCALAR_DOUBLE,
    UVF_SCALAR_FLOAT,
    UVF_SMOOTH_NONE,
    UVF_SMOOTH_2PI,
    UVF_SMOOTH_PI,
    UVF_SMOOTH_HALF_PI,
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
__version__ = "1.0.0"

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
    "Curvatures",
    "Atlas",
    "BoundaryOptimizationReport",
    "IntrinsicOptimalReport",
    "SpectralReport",
    "boundary_optimized_map",
    "intrinsic_optimal_map",
    "spectral_conformal_map",
    "circle_pattern_map",
    "circle_pattern_cone_map",
    "ConePlacement",
    "place_cones",
    "polygon_boundary_curvature",
    "CirclePatternReport",
    "QuadCoverReport",
    "quadcover",
    "quadcover_quad_mesh",
    "UVF_ENERGY_EDGE_LENGTH",
    "UVF_ENERGY_AREA",
    "Cut",
    "PgpCharts",
    "PgpResult",
    "curvature",
    "pgp",
    "MeshInfo",
    "NonlinearReport",
    "abf",
    "BoundaryEditor",
    "atlas",
    "unwrap",
    "check_layout",
    "LayoutCheck",
    "Unwrapped",
    "UnwrapReport",
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
    "UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT",
    "UVF_ABF_WEIGHTS_INVERSE",
    "UVF_ABF_WEIGHTS_INVERSE_SQUARE",
    "UVF_PGP_CHART_ASSEMBLED",
    "UVF_PGP_CHART_ATLAS",
    "UVF_PGP_CHART_MEAN_VALUE",
    "UVF_PGP_CHART_SPLIT_QUAD",
    "UVF_PGP_CHART_UNRESOLVED",
    "UVF_NONLINEAR_SLIM",
    "UVF_NONLINEAR_ARAP",
    "UVF_NONLINEAR_MIPS",
    "UVF_NONLINEAR_STRETCH",
    "UVF_NONLINEAR_GREEN_LAGRANGE",
    "UVF_NONLINEAR_DEGENER",
    "UVF_CUT_COST_CURVATURE",
    "UVF_CUT_COST_LENGTH",
    "UVF_CUT_COST_GIVEN",
    "UVF_ATLAS_CHART_NATURAL_CONFORMAL",
    "UVF_ATLAS_CHART_MEAN_VALUE",
    "UVF_ATLAS_CHART_SLIM",
    "UVF_ATLAS_CHART_STRETCH",
    "UVF_SPHERE_TUTTE_GNOMONIC",
    "UVF_SPHERE_GAUSS_SEIDEL",
    "UVF_SPHERE_STEREOGRAPHIC",
    "UVF_SPHERE_CIRCLE_PATTERNS",
    "UVF_CURVATURE_RINGS",
    "UVF_CURVATURE_RADIUS",
    "UVF_INDEX_UINT16",
    "UVF_INDEX_UINT32",
    "UVF_SCALAR_DOUBLE",
    "UVF_SCALAR_FLOAT",
    "UVF_SMOOTH_NONE",
    "UVF_SMOOTH_2PI",
    "UVF_SMOOTH_PI",
    "UVF_SMOOTH_HALF_PI",
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
    "Mesh",
    "set_thread_count",
    "thread_count",
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
