#!/usr/bin/env bash
# Installs uvflat for C and C++ builds:
#   PREFIX/lib/libuvflat.so, libuvflat.a
#   PREFIX/include/uvflat.h, uvflat.hpp
#   PREFIX/lib/pkgconfig/uvflat.pc                    (pkg-config --cflags --libs uvflat)
#   PREFIX/lib/cmake/uvflat/uvflatConfig.cmake (+ ConfigVersion)   (find_package(uvflat), uvflat::uvflat)
#
# usage: scripts/install.sh PREFIX [--lib-dir DIR]
#   --lib-dir DIR  take libuvflat.so/.a from DIR instead of running `cargo build --release`
set -euo pipefail
cd "$(dirname "$0")/.."

if [ $# -lt 1 ]; then
    echo "usage: $0 PREFIX [--lib-dir DIR]" >&2
    exit 2
fi
prefix=$(realpath -m "$1")
shift
lib_dir=""
while [ $# -gt 0 ]; do
    case "$1" in
        --lib-dir) lib_dir="$2"; shift 2 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done
if [ -z "$lib_dir" ]; then
    cargo build --release --lib
    lib_dir=target/release
fi
version=$(sed -n 's/^version *= *"\(.*\)"/\1/p' Cargo.toml | head -1)

install -d "$prefix/lib/pkgconfig" "$prefix/lib/cmake/uvflat" "$prefix/include"
major=${version%%.*}
install -m 755 "$lib_dir/libuvflat.so" "$prefix/lib/libuvflat.so.$version"
ln -sf "libuvflat.so.$version" "$prefix/lib/libuvflat.so.$major"   # the SONAME (build.rs)
ln -sf "libuvflat.so.$major" "$prefix/lib/libuvflat.so"
install -m 644 "$lib_dir/libuvflat.a" "$prefix/lib/libuvflat.a"
install -m 644 include/uvflat.h bindings/cpp/uvflat.hpp "$prefix/include/"

cat > "$prefix/lib/pkgconfig/uvflat.pc" <<PC
prefix=$prefix
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: uvflat
Description: Mesh parameterization (UV maps) with a C ABI
Version: $version
Libs: -L\${libdir} -luvflat
Libs.private: -lpthread -ldl -lm
Cflags: -I\${includedir}
PC

cat > "$prefix/lib/cmake/uvflat/uvflatConfig.cmake" <<'CMAKE'
# find_package(uvflat) gives the imported target uvflat::uvflat (shared library) and
# uvflat::uvflat_static (static library; links the threads, dl and math libraries it needs).
get_filename_component(_uvflat_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET uvflat::uvflat)
  add_library(uvflat::uvflat SHARED IMPORTED)
  set_target_properties(uvflat::uvflat PROPERTIES
    IMPORTED_LOCATION "${_uvflat_prefix}/lib/libuvflat.so"
    INTERFACE_INCLUDE_DIRECTORIES "${_uvflat_prefix}/include")
  add_library(uvflat::uvflat_static STATIC IMPORTED)
  set_target_properties(uvflat::uvflat_static PROPERTIES
    IMPORTED_LOCATION "${_uvflat_prefix}/lib/libuvflat.a"
    INTERFACE_INCLUDE_DIRECTORIES "${_uvflat_prefix}/include"
    INTERFACE_LINK_LIBRARIES "pthread;dl;m")
endif()
set(uvflat_FOUND TRUE)
CMAKE

cat > "$prefix/lib/cmake/uvflat/uvflatConfigVersion.cmake" <<CMAKE
set(PACKAGE_VERSION "$version")
if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  # 0.x releases: compatible within the same minor version.
  string(REGEX MATCH "^[0-9]+\\\\.[0-9]+" _have "\${PACKAGE_VERSION}")
  string(REGEX MATCH "^[0-9]+\\\\.[0-9]+" _want "\${PACKAGE_FIND_VERSION}")
  if(_have STREQUAL _want OR NOT PACKAGE_FIND_VERSION)
    set(PACKAGE_VERSION_COMPATIBLE TRUE)
  else()
    set(PACKAGE_VERSION_COMPATIBLE FALSE)
  endif()
  if(PACKAGE_FIND_VERSION STREQUAL PACKAGE_VERSION)
    set(PACKAGE_VERSION_EXACT TRUE)
  endif()
endif()
CMAKE

echo "installed uvflat $version into $prefix"
