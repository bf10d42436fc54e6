/* Built against an installed uvflat (pkg-config or CMake) by crates/uvflat-capi/tests/it/install.rs. */
#include <uvflat.h>
#include <stdio.h>

int main(void) {
    /* a unit square folded along its diagonal */
    const double positions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0.3, 0, 1, 0};
    const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    double uv[8];
    if (uvf_abi_version() != UVF_ABI_VERSION) return 3;
    if (uvf_natural_conformal_map(positions, 4, triangles, 2, NULL, uv) != UVF_OK) {
        fprintf(stderr, "uvflat: %s\n", uvf_last_error_message());
        return 1;
    }
    if (uv[0] != uv[0]) return 4; /* NaN */
    printf("uvflat %s ok\n", uvf_version());
    return 0;
}
