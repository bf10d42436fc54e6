#!/usr/bin/env bash
# Tests of the Python binding (bindings/python, tests/python): creates (or reuses) a venv in
# target/python-venv, installs numpy, pytest, bpy 4.5 and the binding into it, builds the library with
# cargo, and runs pytest with UVFLAT_LIBRARY pointing at the freshly built libuvflat.so.
# Extra arguments go to pytest. Set PYTHON to choose the interpreter (default python3) and
# UVFLAT_CARGO_PROFILE the cargo profile of the library under test (default release; the test
# command uses `ci`).
set -euo pipefail
cd "$(dirname "$0")/.."

python=${PYTHON:-python3}
target=${CARGO_TARGET_DIR:-target}
venv=target/python-venv

if ! command -v "$python" >/dev/null; then
    echo "error: $python not found; install Python 3 (Debian: apt-get install python3 python3-venv)" >&2
    exit 1
fi

# Debian splits venv/ensurepip into python3-venv; install it when `python3 -m venv` cannot work.
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import sys" 2>/dev/null; then
    rm -rf "$venv"
    if ! "$python" -m venv "$venv" >/dev/null 2>&1; then
        rm -rf "$venv"
        if command -v apt-get >/dev/null; then
            sudo=""
            [ "$(id -u)" -eq 0 ] || sudo="sudo"
            minor=$("$python" -c 'import sys; print(f"{sys.version_info[0]}.{sys.version_info[1]}")')
            echo "python_tests: installing python3-venv (python$minor-venv)"
            $sudo apt-get update -qq
            $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-venv \
                || $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "python$minor-venv"
        fi
        "$python" -m venv "$venv"
    fi
fi
py="$venv/bin/python"

"$py" -m pip install -q --disable-pip-version-check numpy pytest "setuptools>=70.1" wheel
# bpy (Blender 4.5 as a Python module) for the add-on tests (tests/python/test_blender_addon.py);
# its wheels exist for CPython 3.11 only. pip returns at once when it is already installed.
if "$py" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
    "$py" -m pip install -q --disable-pip-version-check "bpy==4.5.*"
else
    echo "python_tests: bpy 4.5 needs Python 3.11 (set PYTHON=python3.11); the Blender add-on tests will be skipped (and fail under CI=true)" >&2
fi
# The binding is reinstalled every run so the tests see the working tree's version.
"$py" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps --force-reinstall ./bindings/python

profile=${UVFLAT_CARGO_PROFILE:-release}
profile_dir=$profile
[ "$profile" = dev ] && profile_dir=debug
# --tests: with the test targets, the dev-dependencies take part in feature resolution as they
# do in the test command's `cargo test`, so the library built there is reused instead of rebuilt
# (cbindgen, a dev-dependency, turns on bitflags' `std` through tempfile, and bitflags sits under
# faer through raw-cpuid and gemm: without --tests the whole numeric stack is compiled twice).
cargo build --profile "$profile" --locked -p uvflat-capi -p uvflat-cli --lib --bins --tests
export UVFLAT_LIBRARY="$PWD/$target/$profile_dir/libuvflat.so"
[[ "$target" = /* ]] && UVFLAT_LIBRARY="$target/$profile_dir/libuvflat.so"
export UVFLAT_CLI="${UVFLAT_LIBRARY%/*}/uvflat"

# bindings/python is not on sys.path here, so the tests import the installed package.
exec "$py" -m pytest tests/python -p no:cacheprovider "$@"
