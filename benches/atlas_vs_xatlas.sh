#!/usr/bin/env bash
# uvflat --atlas / --cut auto against xatlas (PyPI) on every closed_* and holes_* mesh, one run.
# Creates target/xatlas-venv (xatlas, numpy), builds the release CLI, prints a Markdown table.
# Arguments filter the meshes by name (e.g. `benches/atlas_vs_xatlas.sh kitten bunny`).
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/xatlas-venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q "xatlas==0.0.11" numpy
fi
cargo build --release --bin uvflat >&2
exec nice "$venv/bin/python" benches/atlas_vs_xatlas.py "$@"
