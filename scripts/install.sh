#!/usr/bin/env bash
# Installs uvflat for C and C++ builds:
#   PREFIX/lib/libuvflat.so.X.Y.Z (+ the SONAME link libuvflat.so.X and libuvflat.so), libuvflat.a
#   PREFIX/include/uvflat.h, uvflat.hpp
#   PREFIX/bin/uvflat                                   (the command-line tool)
#   PREFIX/lib/pkgconfig/uvflat.pc, uvflat-static.pc    (pkg-config --cflags --libs uvflat[-static])
#   PREFIX/lib/cmake/uvflat/uvflatConfig.cmake (+ ConfigVersion)
#                                                       (find_package(uvflat): uvflat::uvflat, uvflat::uvflat_static)
#   PREFIX/share/uvflat/install_manifest.txt            (what was installed, for --uninstall)
# The pkg-config and CMake files find the prefix from where they are, so the tree can be moved
# (the SDK tarball of scripts/dist.sh is this tree).
#
# usage: scripts/install.sh PREFIX [--lib-dir DIR] [--strip]
#        scripts/install.sh --uninstall PREFIX
#   --lib-dir DIR  take libuvflat.so/.a (and the uvflat CLI, if there) from DIR; without it, the
#                  release build in target/release is used, built first unless it is newer than
#                  every source file
#   --strip        strip debug information from the installed libraries and CLI
#   DESTDIR=/stage scripts/install.sh /usr/local   stages the files under /stage/usr/local
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { echo "usage: $0 PREFIX [--lib-dir DIR] [--strip] | $0 --uninstall PREFIX" >&2; exit 2; }
[ $# -ge 1 ] || usage

uninstall() {
    local root="${DESTDIR:-}$(realpath -m "$1")"
    local manifest="$root/share/uvflat/install_manifest.txt"
    [ -f "$manifest" ] || { echo "error: $manifest not found: nothing installed there" >&2; exit 1; }
    while IFS= read -r file; do
        rm -f "$root/$file"
    done < "$manifest"
    rm -f "$manifest"
    for dir in lib/cmake/uvflat share/uvflat lib/pkgconfig lib/cmake include bin lib share; do
        rmdir "$root/$dir" 2>/dev/null || true
    done
    echo "removed uvflat from $root"
}

if [ "$1" = --uninstall ]; then
    [ $# -eq 2 ] || usage
    uninstall "$2"
    exit 0
fi

prefix=$(realpath -m "$1")
shift
lib_dir=""
strip_debug=false
while [ $# -gt 0 ]; do
    case "$1" in
        --lib-dir) [ $# -ge 2 ] || usage; lib_dir="$2"; shift 2 ;;
        --strip) strip_debug=true; shift ;;
        *) echo "unknown option $1" >&2; usage ;;
    esac
done
if [ -z "$lib_dir" ]; then
    lib_dir=target/release
    built="$lib_dir/libuvflat.so"
    if [ ! -f "$built" ] || [ ! -f "$lib_dir/libuvflat.a" ] || [ ! -f "$lib_dir/uvflat" ] \
        || [ -n "$(find crates Cargo.toml Cargo.lock -name target -prune -o -newer "$built" -print -quit)" ]; then
        cargo build --release --locked -p uvflat-capi -p uvflat-cli
    else
        echo "using the up-to-date build in $lib_dir"
    fi
fi
version=$(sed -n 's/^version *= *"\(.*\)"/\1/p' Cargo.toml | head -1)
major=${version%%.*}
root="${DESTDIR:-}$prefix"

installed=()
put() { # put MODE SOURCE DEST-RELATIVE-TO-PREFIX
    install -D -m "$1" "$2" "$root/$3"
    installed+=("$3")
}
link() { # link TARGET NAME-RELATIVE-TO-PREFIX
    ln -sfn "$1" "$root/$2"
    installed+=("$2")
}
write() { # write DEST-RELATIVE-TO-PREFIX < content
    install -d "$(dirname "$root/$1")"
    cat > "$root/$1"
    installed+=("$1")
}

put 755 "$lib_dir/libuvflat.so" "lib/libuvflat.so.$version"
link "libuvflat.so.$version" "lib/libuvflat.so.$major"   # the SONAME (build.rs)
link "libuvflat.so.$major" "lib/libuvflat.so"
# The static library as one relocatable object whose only global symbols are the uvf_*
# functions: rustc's archive also exports the Rust runtime and every dependency
# (rust_eh_personality, __rust_alloc, compiler builtins, faer kernels: thousands of symbols),
# which clash with a second Rust static library linked into the same program. `ld -r` joins
# the archive's objects, the embedded LLVM bitcode (.llvmbc: dead weight, and LLVM's bfd plugin
# cannot read the joined sections) is dropped, the COMDAT groups get private names (a linker
# keeps one group per name: ours, made local, would otherwise replace another library's
# DW.ref.rust_eh_personality), and objcopy makes every other symbol local.
localized_archive() { # localized_archive IN OUT
    local work
    work=$(mktemp -d)
    ld -r --whole-archive "$1" -o "$work/uvflat.o"
    objcopy --remove-section=.llvmbc --remove-section=.llvmcmd "$work/uvflat.o"
    nm -g --defined-only "$work/uvflat.o" | awk '$3 ~ /^uvf_/ { print $3 }' > "$work/exports"
    [ -s "$work/exports" ] || { echo "error: no uvf_ symbols in $1" >&2; rm -rf "$work"; exit 1; }
    readelf -W -g "$work/uvflat.o" | sed -n "s/^COMDAT group section .* \[\(.*\)\] contains .*/\1 uvflat.private.\1/p" \
        | sort -u > "$work/groups"
    objcopy --redefine-syms="$work/groups" --keep-global-symbols="$work/exports" "$work/uvflat.o"
    rm -f "$2"
    ar crs "$2" "$work/uvflat.o"
    rm -rf "$work"
}
install -d "$root/lib"
localized_archive "$lib_dir/libuvflat.a" "$root/lib/libuvflat.a"
chmod 644 "$root/lib/libuvflat.a"
installed+=(lib/libuvflat.a)
put 644 include/uvflat.h include/uvflat.h
put 644 bindings/cpp/uvflat.hpp include/uvflat.hpp
if [ -f "$lib_dir/uvflat" ]; then put 755 "$lib_dir/uvflat" bin/uvflat; fi
if $strip_debug; then
    strip --strip-unneeded "$root/lib/libuvflat.so.$version"
    strip --strip-debug "$root/lib/libuvflat.a"
    if [ -f "$root/bin/uvflat" ]; then strip "$root/bin/uvflat"; fi
fi

# ${pcfiledir} is where pkg-config found the file: the prefix is two levels up.
write lib/pkgconfig/uvflat.pc <<PC
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: uvflat
Description: Mesh parameterization (UV maps) with a C ABI (shared library)
Version: $version
Libs: -L\${libdir} -Wl,-rpath,\${libdir} -luvflat
Libs.private: -lpthread -ldl -lm
Cflags: -I\${includedir}
PC
write lib/pkgconfig/uvflat-static.pc <<PC
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: uvflat-static
Description: Mesh parameterization (UV maps) with a C ABI (static library)
Version: $version
Libs: \${libdir}/libuvflat.a -lpthread -ldl -lm
Cflags: -I\${includedir}
PC

write lib/cmake/uvflat/uvflatConfig.cmake <<'CMAKE'
# find_package(uvflat) gives the imported target uvflat::uvflat (shared library) and
# uvflat::uvflat_static (static library; links the threads, dl and math libraries it needs).
get_filename_component(_uvflat_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET uvflat::uvflat)
  add_library(uvflat::uvflat SHARED IMPORTED)
  set_target_properties(uvflat::uvflat PROPERTIES
    IMPORTED_LOCATION "${_uvflat_prefix}/lib/libuvflat.so"
    IMPORTED_SONAME "libuvflat.so.@MAJOR@"
    INTERFACE_INCLUDE_DIRECTORIES "${_uvflat_prefix}/include")
  add_library(uvflat::uvflat_static STATIC IMPORTED)
  set_target_properties(uvflat::uvflat_static PROPERTIES
    IMPORTED_LOCATION "${_uvflat_prefix}/lib/libuvflat.a"
    INTERFACE_INCLUDE_DIRECTORIES "${_uvflat_prefix}/include"
    INTERFACE_LINK_LIBRARIES "pthread;dl;m")
endif()
set(uvflat_FOUND TRUE)
CMAKE
sed -i "s/@MAJOR@/$major/" "$root/lib/cmake/uvflat/uvflatConfig.cmake"

write lib/cmake/uvflat/uvflatConfigVersion.cmake <<CMAKE
# One rule for every version number (docs/c-api.md): the ABI is the major version, so a
# request is met by the same major version at or above the requested one.
set(PACKAGE_VERSION "$version")
string(REGEX MATCH "^[0-9]+" _have_major "\${PACKAGE_VERSION}")
string(REGEX MATCH "^[0-9]+" _want_major "\${PACKAGE_FIND_VERSION}")
if(NOT PACKAGE_FIND_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
elseif(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION OR NOT _have_major STREQUAL _want_major)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
endif()
if(PACKAGE_FIND_VERSION STREQUAL PACKAGE_VERSION)
  set(PACKAGE_VERSION_EXACT TRUE)
endif()
CMAKE

installed+=(share/uvflat/install_manifest.txt)
install -d "$root/share/uvflat"
printf '%s\n' "${installed[@]}" > "$root/share/uvflat/install_manifest.txt"
echo "installed uvflat $version into $root (remove with: $0 --uninstall $prefix)"
