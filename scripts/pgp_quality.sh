#!/usr/bin/env bash
# PGP quality and timing table (README, "Periodic Global Parameterization"): runs
# `uvflat pgp --json` with and without --curl-correction on every closed test mesh
# (or the meshes given as arguments) under /usr/bin/time, and prints a Markdown table of singular
# triangles, singular points, Σ indices, stretch, shear, alignment, Newton iterations (* where
# ‖∇F**‖ < 1e-6 was reached) and CPU seconds (user +
# system). Set UVFLAT to use another CLI binary (default target/release/uvflat, built here) and
# UVFLAT_PGP_ARGS to pass more options to every run (e.g. "--newton-iterations 100").
# Example: scripts/pgp_quality.sh "$(python3 tests/data/meshes.py)/disk_face_libigl_loop1.obj"  (206,848 faces)
set -euo pipefail
cd "$(dirname "$0")/.."

cli=${UVFLAT:-target/release/uvflat}
if [ -z "${UVFLAT:-}" ]; then
    cargo build --release --quiet -p uvflat-cli
fi
if [ "$#" -gt 0 ]; then
    meshes=("$@")
else
    meshes=("$(python3 tests/data/meshes.py)"/closed_*.obj)
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
for mesh in "${meshes[@]}"; do
    name=$(basename "$mesh" .obj)
    for mode in pgp cc; do
        flag=()
        [ "$mode" = cc ] && flag=(--curl-correction)
        /usr/bin/time -f "%U %S %e" -o "$out/$name.$mode.time" \
            "$cli" pgp "$mesh" -o "$out/$name.$mode.obj" "${flag[@]}" ${UVFLAT_PGP_ARGS:-} --json >"$out/$name.$mode.json"
        rm -f "$out/$name.$mode.obj"
    done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >&2

python3 - "$out" "${meshes[@]}" <<'EOF'
import json, os, sys
out, meshes = sys.argv[1], sys.argv[2:]
def run(name, mode):
    j = json.load(open(f"{out}/{name}.{mode}.json"))
    user, system, wall = map(float, open(f"{out}/{name}.{mode}.time").read().split()[-3:])
    return j, user + system, wall
print("| mesh | triangles | genus | Σ indices | singular triangles PGP / ccPGP | singular points PGP / ccPGP "
      "| stretch PGP / ccPGP | shear PGP / ccPGP | alignment PGP / ccPGP | Newton iterations PGP / ccPGP "
      "| CPU s PGP / ccPGP | wall s PGP / ccPGP |")
print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
for mesh in meshes:
    name = os.path.basename(mesh)[:-4]
    (a, ca, wa), (b, cb, wb) = run(name, "pgp"), run(name, "cc")
    pct = lambda j: f"{100 * j['singular_triangle_fraction']:.2f}%"
    # Iterations, with * where ‖∇F**‖ < 10⁻⁶ was reached.
    newton = lambda j: f"{j['newton_iterations']}{'*' if j['converged'] else ''}"
    print(f"| {name.replace('closed_', '')} | {a['triangles']} | {a['genus']} | {round(a['index_sum']) + 0} "
          f"| {pct(a)} / {pct(b)} | {a['singular_points']} / {b['singular_points']} "
          f"| {a['stretch']:.3f} / {b['stretch']:.3f} | {a['shear']:.3f} / {b['shear']:.3f} "
          f"| {a['alignment_degrees']:.1f}° / {b['alignment_degrees']:.1f}° | {newton(a)} / {newton(b)} "
          f"| {ca:.2f} / {cb:.2f} | {wa:.2f} / {wb:.2f} |")
# Dislocation annihilation (dislocations.rs): dislocations found, pairs annihilated, moved into a
# singular triangle of the field.
print()
print("| mesh | dislocations PGP / ccPGP | pairs annihilated PGP / ccPGP | moved into a field singularity PGP / ccPGP |")
print("|---|--:|--:|--:|")
for mesh in meshes:
    name = os.path.basename(mesh)[:-4]
    a, b = run(name, "pgp")[0]["dislocations"], run(name, "cc")[0]["dislocations"]
    print(f"| {name.replace('closed_', '')} | {a['before']} / {b['before']} "
          f"| {a['annihilated_pairs']} / {b['annihilated_pairs']} | {a['absorbed']} / {b['absorbed']} |")
EOF
