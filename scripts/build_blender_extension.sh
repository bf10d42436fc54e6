#!/usr/bin/env bash
# Builds the Blender extension zip: blender_addon/ + the Python binding (bindings/python/uvflat,
# vendored as blender_addon's subpackage `vendor/uvflat`) + the release libuvflat.so inside it.
# Output: target/blender/uvflat-<version>-linux-x64.zip (or the path given as $1).
# UVFLAT_CARGO_PROFILE chooses the cargo profile of the library (default release; the test suite
# passes its own, `ci`, to reuse the library it already built); UVFLAT_LIBRARY_FILE names a
# library already built (scripts/dist.sh gives its stripped one), and then cargo is not run.
# Install it in Blender: Edit > Preferences > Get Extensions > (menu) Install from Disk..., or
#   blender --command extension install-file -r user_default target/blender/uvflat-*.zip
set -euo pipefail
cd "$(dirname "$0")/.."

target=${CARGO_TARGET_DIR:-target}
[[ "$target" = /* ]] || target="$PWD/$target"
version=$(sed -n 's/^version = "\(.*\)"/\1/p' blender_addon/blender_manifest.toml | head -1)
out=${1:-$target/blender/uvflat-$version-linux-x64.zip}

if [ -n "${UVFLAT_LIBRARY_FILE:-}" ]; then
    library=$UVFLAT_LIBRARY_FILE
else
    profile=${UVFLAT_CARGO_PROFILE:-release}
    profile_dir=$profile
    [ "$profile" = dev ] && profile_dir=debug
    cargo build --profile "$profile" --locked -p uvflat-capi
    library="$target/$profile_dir/libuvflat.so"
fi
[ -f "$library" ] || { echo "error: $library was not built" >&2; exit 1; }

stage="$target/blender/stage"
rm -rf "$stage"
mkdir -p "$stage/vendor/uvflat" "$(dirname "$out")"
# The add-on's own files (no caches, no vendor/ left over from a development copy).
for f in blender_addon/*.py blender_addon/blender_manifest.toml; do cp "$f" "$stage/"; done
# The binding, unchanged, with the library next to it (its lookup finds it there).
cp bindings/python/uvflat/*.py bindings/python/uvflat/py.typed "$stage/vendor/uvflat/"
cp "$library" "$stage/vendor/uvflat/libuvflat.so"
strip --strip-debug "$stage/vendor/uvflat/libuvflat.so" 2>/dev/null || true
printf '"""Third-party code bundled with the extension: the uvflat binding and library."""\n' > "$stage/vendor/__init__.py"

rm -f "$out"
(cd "$stage" && python3 - "$out" <<'PY'
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED) as z:
    for root, dirs, files in os.walk("."):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for f in sorted(files):
            path = os.path.join(root, f)
            z.write(path, os.path.relpath(path, "."))
PY
)
echo "$out"
