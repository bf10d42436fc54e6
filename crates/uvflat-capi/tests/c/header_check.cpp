// Compiled as C++17 with -Wall -Wextra -pedantic -Werror by crates/uvflat-capi/tests/it/c_abi.rs, together with the
// header-only C++ wrapper (which includes uvflat.h itself).
#include "uvflat.h"
#include "uvflat.hpp" /* bindings/cpp, on the include path */

#include <cstddef>
#include <type_traits>

static_assert(UVF_OK == 0, "UVF_OK must be 0");
static_assert(sizeof(UvfMetrics) == 5 * sizeof(size_t) + 8 * sizeof(double), "UvfMetrics layout");
static_assert(sizeof(UvfMeshInfo) == 8 * sizeof(size_t) + 2 * sizeof(int64_t), "UvfMeshInfo layout");
static_assert(offsetof(UvfFixedBoundaryOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfNaturalConformalOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfPgpOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfCurvatureOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfAtlasOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfQuadCoverOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfIntrinsicToolOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfIntrinsicOptimalOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfBoundaryOptimizationOptions, struct_size) == 0, "struct_size comes first");

// The wrapper's owners of library handles are move-only and move without throwing.
template <class T> constexpr bool move_only_owner() {
    return !std::is_copy_constructible<T>::value && !std::is_copy_assignable<T>::value &&
           std::is_nothrow_move_constructible<T>::value && std::is_nothrow_move_assignable<T>::value;
}
static_assert(move_only_owner<uvflat::Pgp>(), "uvflat::Pgp");
static_assert(move_only_owner<uvflat::QuadMesh>(), "uvflat::QuadMesh");
static_assert(move_only_owner<uvflat::ChartLayout>(), "uvflat::ChartLayout");
static_assert(move_only_owner<uvflat::PgpCharts>(), "uvflat::PgpCharts");
static_assert(move_only_owner<uvflat::Atlas>(), "uvflat::Atlas");
static_assert(move_only_owner<uvflat::Cut>(), "uvflat::Cut");
static_assert(move_only_owner<uvflat::BoundaryEditor>(), "uvflat::BoundaryEditor");

static_assert(std::is_same<decltype(&uvf_natural_conformal_map),
                           UvfStatus (*)(const double *, size_t, const uint32_t *, size_t,
                                         const UvfNaturalConformalOptions *, double *)>::value,
              "uvf_natural_conformal_map signature");

int uvf_header_check_cpp() { return UVF_ABI_VERSION; }
