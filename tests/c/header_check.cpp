// Compiled as C++17 with -Wall -Wextra -pedantic -Werror by tests/c_abi.rs.
#include "uvflat.h"

#include <cstddef>
#include <type_traits>

static_assert(UVF_OK == 0, "UVF_OK must be 0");
static_assert(sizeof(UvfMetrics) == 4 * sizeof(size_t) + 8 * sizeof(double), "UvfMetrics layout");
static_assert(sizeof(UvfMeshInfo) == 7 * sizeof(size_t) + 2 * sizeof(int64_t), "UvfMeshInfo layout");
static_assert(offsetof(UvfFixedBoundaryOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfNaturalConformalOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfPgpOptions, struct_size) == 0, "struct_size comes first");
static_assert(offsetof(UvfCurvatureOptions, struct_size) == 0, "struct_size comes first");
static_assert(std::is_same<decltype(&uvf_natural_conformal_map),
                           UvfStatus (*)(const double *, size_t, const uint32_t *, size_t,
                                         const UvfNaturalConformalOptions *, double *)>::value,
              "uvf_natural_conformal_map signature");

int uvf_header_check_cpp() { return UVF_ABI_VERSION; }
