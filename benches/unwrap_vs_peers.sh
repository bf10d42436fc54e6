#!/usr/bin/env bash
# The default unwrap against xatlas (PyPI) and Blender 4.5 (PyPI bpy), and bijective SLIM
# against SLIM, in one run (benches/unwrap_vs_peers.py). Creates target/peers-venv (numpy,
# xatlas, bpy 4.5: needs Python 3.11), builds the release library, prints Markdown tables.
# Meshes: the folder in $UVFLAT_MESHES (default tests/data); arguments filter them by name.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/peers-venv
python=${PYTHON:-python3.11}
if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
    "$venv/bin/pip" install -q numpy "xatlas==0.0.11" "bpy==4.5.*"
fi
cargo build --release --lib >&2
exec nice "$venv/bin/python" benches/unwrap_vs_peers.py "$@"
