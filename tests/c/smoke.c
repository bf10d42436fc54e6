/* A C99 caller of libuvflat: unwraps a bent grid with two methods, measures the result, and
 * checks that bad input gives the documented status, a message, and untouched outputs.
 * Built and run by tests/c_abi.rs; exits non-zero on the first failed check. */
#include "uvflat.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define N 12 /* grid of N x N vertices */

static int failures = 0;

static void check(int ok, const char *what) {
    if (!ok) {
        fprintf(stderr, "FAILED: %s (last error: %s)\n", what, uvf_last_error_message());
        failures++;
    }
}

static void bent_grid(double *positions, uint32_t *triangles) {
    int i, j, t = 0;
    for (j = 0; j < N; j++)
        for (i = 0; i < N; i++) {
            double x = (double)i / (N - 1), y = (double)j / (N - 1);
            double *p = positions + 3 * (j * N + i);
            p[0] = x;
            p[1] = y;
            p[2] = 0.3 * sin(3.0 * x) * cos(2.0 * y);
        }
    for (j = 0; j + 1 < N; j++)
        for (i = 0; i + 1 < N; i++) {
            uint32_t a = (uint32_t)(j * N + i), b = a + 1, c = a + N, d = c + 1;
            uint32_t *tri = triangles + 6 * t++;
            tri[0] = a; tri[1] = b; tri[2] = d;
            tri[3] = a; tri[4] = d; tri[5] = c;
        }
}

static int cancel_at_half(void *user, double fraction) {
    int *calls = (int *)user;
    (*calls)++;
    return fraction >= 0.5;
}

int main(void) {
    static double positions[3 * N * N];
    static uint32_t triangles[6 * (N - 1) * (N - 1)];
    static double uv[2 * N * N];
    const size_t nv = N * N, nt = 2 * (N - 1) * (N - 1);
    UvfMeshInfo info;
    UvfMetrics metrics;
    UvfFixedBoundaryOptions fixed;
    UvfNaturalConformalOptions conformal;
    UvfStatus status;
    int calls = 0;
    uint32_t saved;

    bent_grid(positions, triangles);
    check(uvf_abi_version() == UVF_ABI_VERSION, "ABI version matches the header");
    check(strlen(uvf_version()) > 0, "version string");

    status = uvf_mesh_info(positions, nv, triangles, nt, &info);
    check(status == UVF_OK && info.boundary_loops == 1 && info.euler_characteristic == 1 && info.genus == 0,
          "mesh info of a grid: one boundary loop, disk");

    status = uvf_natural_conformal_map(positions, nv, triangles, nt, NULL, uv);
    check(status == UVF_OK, "natural conformal map succeeds");
    status = uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics);
    check(status == UVF_OK && metrics.flipped == 0 && metrics.triangles == nt, "no flipped triangles");
    check(metrics.conformal_mean < 1.05, "natural conformal map is nearly conformal");

    uvf_fixed_boundary_options_default(&fixed);
    fixed.weights = UVF_WEIGHTS_MEAN_VALUE;
    fixed.boundary = UVF_BOUNDARY_SQUARE;
    status = uvf_fixed_boundary_map(positions, nv, triangles, nt, &fixed, uv);
    check(status == UVF_OK, "mean value map onto a square succeeds");
    status = uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics);
    check(status == UVF_OK && metrics.flipped == 0, "mean value map onto a square never flips");

    /* Bad input: out-of-range index; the output must stay untouched. */
    uv[0] = 42.0;
    saved = triangles[4];
    triangles[4] = 99999;
    status = uvf_natural_conformal_map(positions, nv, triangles, nt, NULL, uv);
    check(status == UVF_INVALID_MESH, "out-of-range index gives UVF_INVALID_MESH");
    check(strstr(uvf_last_error_message(), "99999") != NULL, "message names the bad index");
    check(uv[0] == 42.0, "output untouched on failure");
    triangles[4] = saved;

    status = uvf_natural_conformal_map(NULL, nv, triangles, nt, NULL, uv);
    check(status == UVF_INVALID_ARGUMENT, "NULL positions give UVF_INVALID_ARGUMENT");

    positions[5] = NAN;
    status = uvf_fixed_boundary_map(positions, nv, triangles, nt, NULL, uv);
    check(status == UVF_INVALID_MESH && strstr(uvf_last_error_message(), "vertex 1") != NULL,
          "NaN coordinate is named");
    positions[5] = 0.0;

    fixed.weights = 77;
    status = uvf_fixed_boundary_map(positions, nv, triangles, nt, &fixed, uv);
    check(status == UVF_INVALID_ARGUMENT, "unknown weights give UVF_INVALID_ARGUMENT");

    uvf_natural_conformal_options_default(&conformal);
    conformal.progress = cancel_at_half;
    conformal.progress_user = &calls;
    status = uvf_natural_conformal_map(positions, nv, triangles, nt, &conformal, uv);
    check(status == UVF_CANCELLED && calls > 0, "progress callback cancels");

    status = uvf_natural_conformal_map(positions, nv, triangles, nt, NULL, uv);
    check(status == UVF_OK && uvf_last_error_message()[0] == '\0', "success clears the message");

    if (failures == 0) printf("all C checks passed\n");
    return failures == 0 ? 0 : 1;
}
