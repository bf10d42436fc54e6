#!/usr/bin/env bash
# QuadCover quad-mesh table (README, "QuadCover"): runs `uvflat quadcover --quad-mesh --json`
# with the default options and with --cones-on-grid on the meshes of the table in docs/methods/quadcover.md (or the
# meshes given as arguments) and prints a Markdown row per mesh: folded triangles, faces of the
# quad mesh and their share of quads, for both modes. Set UVFLAT to use another CLI binary
# (default target/release/uvflat, built here) and UVFLAT_QUADCOVER_ARGS to pass more options
# to every run (e.g. "--quad-density 2").
set -euo pipefail
cd "$(dirname "$0")/.."

cli=${UVFLAT:-target/release/uvflat}
if [ -z "${UVFLAT:-}" ]; then
    cargo build --release --quiet -p uvflat-cli
fi
if [ "$#" -gt 0 ]; then
    meshes=("$@")
else
    meshes=()
    dir=$(python3 tests/data/meshes.py)
    for name in closed_g0_bunny closed_g0_cow closed_g0_decimated_knight closed_g0_man closed_g0_spot closed_g1_bob \
        closed_g1_knot closed_g1_torus closed_g2_eight closed_g3_triple_torus closed_g4_fertility holes_pig \
        holes_annulus disk_lilium disk_spothead closed_g1_kitten closed_g0_armadillo; do
        meshes+=("$dir/$name.obj")
    done
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "| mesh | folded | faces | quads | folded, cones on grid | faces | quads |"
echo "|---|--:|--:|--:|--:|--:|--:|"
for mesh in "${meshes[@]}"; do
    row="| $(basename "$mesh" .obj)"
    for flag in "" --cones-on-grid; do
        # shellcheck disable=SC2086
        "$cli" quadcover "$mesh" -o "$out/uv.obj" --quad-mesh "$out/quads.obj" $flag ${UVFLAT_QUADCOVER_ARGS:-} --json \
            >"$out/report.json"
        row="$row | $(python3 -c '
import json, sys
r = json.load(open(sys.argv[1]))
q = r["quad_mesh"]
share = "%.1f%%" % (100.0 * q["quads"] / q["faces"]) if q["faces"] else "–"
print("%d | %d | %s" % (r["flipped"], q["faces"], share))' "$out/report.json")"
    done
    echo "$row |"
done
