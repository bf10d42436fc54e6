"""Wheel tag of the binding: a wheel that carries libuvflat (a native library, loaded with
ctypes, so not tied to one Python version or ABI) is tagged for its platform, ``py3-none-<platform>``;
without a library in the package it stays pure (``py3-none-any``) and finds one at run time
(``UVFLAT_LIBRARY`` or the system's search path). Everything else is in pyproject.toml."""

from pathlib import Path

from setuptools import setup
try:
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:  # setuptools < 70.1 keeps it in the `wheel` package
    from wheel.bdist_wheel import bdist_wheel
from setuptools.dist import Distribution

LIBRARIES = ("libuvflat.so", "libuvflat.dylib", "uvflat.dll")
CARRIES_LIBRARY = any((Path(__file__).parent / "uvflat" / name).exists() for name in LIBRARIES)


class NativeDistribution(Distribution):
    """Installs into platlib (not purelib) when the package carries the native library."""

    def has_ext_modules(self):
        return CARRIES_LIBRARY


class PlatformWheel(bdist_wheel):
    def get_tag(self):
        python, abi, platform = super().get_tag()
        return ("py3", "none", platform) if CARRIES_LIBRARY else (python, abi, platform)


setup(distclass=NativeDistribution, cmdclass={"bdist_wheel": PlatformWheel})
