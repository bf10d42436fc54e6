/* Compiled as C99 with -Wall -Wextra -pedantic -Werror by crates/uvflat-capi/tests/it/c_abi.rs: the generated header
 * must be valid, warning-free C, and the public structs must keep their documented layout. */
#include "uvflat.h"

#define UVF_STATIC_ASSERT(cond, name) typedef char uvf_static_assert_##name[(cond) ? 1 : -1]

UVF_STATIC_ASSERT(sizeof(UvfStatus) == sizeof(int), status_is_int);
UVF_STATIC_ASSERT(sizeof(UvfMeshInfo) == 8 * sizeof(size_t) + 2 * sizeof(int64_t), mesh_info_size);
UVF_STATIC_ASSERT(sizeof(UvfMetrics) == 5 * sizeof(size_t) + 8 * sizeof(double), metrics_size);
UVF_STATIC_ASSERT(offsetof(UvfFixedBoundaryOptions, struct_size) == 0, fixed_size_first);
UVF_STATIC_ASSERT(offsetof(UvfNaturalConformalOptions, struct_size) == 0, conformal_size_first);
UVF_STATIC_ASSERT(offsetof(UvfCutOptions, struct_size) == 0, cut_size_first);
UVF_STATIC_ASSERT(offsetof(UvfSphereOptions, struct_size) == 0, sphere_size_first);
UVF_STATIC_ASSERT(sizeof(UvfCutInfo) == 4 * sizeof(size_t) + 2 * sizeof(double), cut_info_size);
UVF_STATIC_ASSERT(offsetof(UvfCurvatureOptions, struct_size) == 0, curvature_size_first);
UVF_STATIC_ASSERT(offsetof(UvfPgpOptions, struct_size) == 0, pgp_size_first);
/* The size, 3 + 3 uint32_t (each group padded to 8 bytes) and 5 doubles. */
UVF_STATIC_ASSERT(sizeof(UvfQuadCoverReport) == sizeof(size_t) + 10 * sizeof(uint32_t) + 5 * sizeof(double), quadcover_report_size);
UVF_STATIC_ASSERT(sizeof(UvfPgpInfo) == 5 * sizeof(size_t) + 6 * sizeof(double) + 2 * sizeof(uint32_t), pgp_info_size);
UVF_STATIC_ASSERT(UVF_OK == 0, ok_is_zero);

int uvf_header_check_c(void);
int uvf_header_check_c(void) { return UVF_ABI_VERSION; }
