"""Where the uvflat Python binding comes from.

The extension zip built by ``scripts/build_blender_extension.sh`` carries the binding as the
subpackage ``vendor/uvflat`` with ``libuvflat.so`` inside it (the binding looks next to itself
for the library). Run from the source tree (tests, development), the add-on has no ``vendor``
and uses an installed ``uvflat`` package instead (``pip install ./bindings/python``), with the
library from ``$UVFLAT_LIBRARY``.
"""

from __future__ import annotations

from typing import Any


def binding() -> Any:
    """The ``uvflat`` module, its library loaded (raises ``ImportError`` or
    ``uvflat.LibraryError`` with the reason when it cannot be)."""
    try:
        from .vendor import uvflat  # type: ignore[attr-defined]
    except ImportError:
        import uvflat  # type: ignore[no-redef]
    uvflat.library_path()  # loads the library now, so a missing one is reported up front
    return uvflat
