#!/usr/bin/env bash
# The project's test command (README "Testing", docs/testing.md): installs on Debian what the tests need
# (CGAL + Eigen for the reference cross-check, OpenMesh for the C++ tests, a C/C++ compiler),
# then runs every test. Set CI=true to make missing references fail instead of skip.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ pkg-config cmake binutils libcgal-dev libeigen3-dev libopenmesh-dev)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Debian splits venv/ensurepip (needed for the venvs of scripts/dist.sh and the Python tests).
python3 -c "import ensurepip" 2>/dev/null || missing+=(python3-venv)
if ((${#missing[@]})); then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "installing: ${missing[*]}"
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The `ci` profile (Cargo.toml) is the release profile without link-time optimisation and debug
# info: the same optimised code for the tests' timings, a fraction of the build time (7 against
# 31 minutes from a clean clone on the 2-core CI machine, each test binary being a thin-LTO link).
# UVFLAT_CARGO_PROFILE=release tests the shipped profile instead.
export UVFLAT_CARGO_PROFILE=${UVFLAT_CARGO_PROFILE:-ci}

# The artifacts users install (scripts/dist.sh: C SDK, wheel, Blender extension, from the release
# profile), which crates/uvflat-capi/tests/it/install.rs and tests/python/test_dist.py install and use.
export UVFLAT_DIST=${UVFLAT_DIST:-$PWD/dist}
scripts/dist.sh

cargo test --profile "$UVFLAT_CARGO_PROFILE" --locked --no-fail-fast "$@"

# Python binding (ctypes + numpy, in a venv under target/) and its pytest suite, on the library and
# CLI of the same profile.
scripts/python_tests.sh
