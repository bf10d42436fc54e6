/* A C99 caller of libuvflat: unwraps a bent grid with two methods, measures the result, and
 * checks that bad input gives the documented status, a message, and untouched outputs.
 * Built and run by crates/uvflat-capi/tests/it/c_abi.rs; exits non-zero on the first failed check. */
#include "uvflat.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
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

/* A report or info struct as a program built against an older header lays it out: without its
 * last field (`struct_size` = the offset of that field), followed by guard bytes. */
static union {
    double align_double;
    size_t align_size;
    unsigned char bytes[512];
} old_struct;

static void *old_layout(size_t old_size) {
    memset(old_struct.bytes, 0xA5, sizeof old_struct.bytes);
    memcpy(old_struct.bytes, &old_size, sizeof old_size);
    return old_struct.bytes;
}

static int old_layout_intact(size_t old_size) {
    size_t k;
    size_t written;
    int intact = 1;
    memcpy(&written, old_struct.bytes, sizeof written);
    for (k = old_size; k < sizeof old_struct.bytes; k++) intact &= old_struct.bytes[k] == 0xA5;
    return intact && written == old_size;
}

/* CALL (which writes through `report_`) into a current struct and into an older, shorter
 * layout: the library writes the older layout's fields and not one byte past its struct_size. */
#define CHECK_OLD_LAYOUT(T, first, last, CALL)                                                   \
    do {                                                                                         \
        T full_;                                                                                 \
        T *old_ = (T *)old_layout(offsetof(T, last));                                            \
        full_.struct_size = sizeof full_;                                                        \
        {                                                                                        \
            T *report_ = &full_;                                                                 \
            check((CALL) == UVF_OK, #T ": current layout");                                      \
        }                                                                                        \
        {                                                                                        \
            T *report_ = old_;                                                                   \
            check((CALL) == UVF_OK, #T ": older layout accepted");                               \
        }                                                                                        \
        check(old_layout_intact(offsetof(T, last)), #T ": nothing written past struct_size");    \
        check(old_->first == full_.first, #T ": the older layout's fields are written");         \
    } while (0)


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

/* uvf_boundary_loops and uvf_triangle_components, including undersized outputs. */
static void check_topology_queries(const double *positions, size_t nv, const uint32_t *triangles, size_t nt) {
    static uint32_t loop_vertices[4 * N], offsets[2], components[2 * (N - 1) * (N - 1)];
    size_t i;
    UvfStatus status = uvf_boundary_loops(positions, nv, triangles, nt, loop_vertices, 4 * (N - 1) - 1, offsets, 2);
    check(status == UVF_INVALID_ARGUMENT, "boundary loops: too small vertex capacity is rejected");
    offsets[1] = 12345;
    status = uvf_boundary_loops(positions, nv, triangles, nt, loop_vertices, 4 * (N - 1), offsets, 1);
    check(status == UVF_INVALID_ARGUMENT && offsets[1] == 12345, "boundary loops: too small offsets capacity");
    status = uvf_boundary_loops(positions, nv, triangles, nt, loop_vertices, 4 * (N - 1), offsets, 2);
    check(status == UVF_OK && offsets[0] == 0 && offsets[1] == 4 * (N - 1), "grid has one loop of 4(N-1) vertices");
    for (i = 0; i < 4 * (N - 1); i++) {
        uint32_t v = loop_vertices[i], x = v % N, y = v / N;
        check(x == 0 || y == 0 || x == N - 1 || y == N - 1, "loop vertices lie on the grid border");
    }
    status = uvf_triangle_components(positions, nv, triangles, nt, components);
    check(status == UVF_OK, "triangle components");
    for (i = 0; i < nt; i++) check(components[i] == 0, "grid is one component");
    status = uvf_triangle_components(positions, nv, triangles, nt, NULL);
    check(status == UVF_INVALID_ARGUMENT, "NULL component output is rejected");
}

/* Versioned options and zero/overflowing counts. */
static void check_options_and_counts(const double *positions, size_t nv, const uint32_t *triangles, size_t nt,
                                     double *uv) {
    UvfFixedBoundaryOptions fixed;
    UvfNaturalConformalOptions conformal;
    UvfMeshInfo info;
    info.struct_size = sizeof info;
    UvfStatus status;
    uvf_fixed_boundary_options_default(&fixed);
    check(fixed.struct_size == sizeof fixed && fixed.weights == UVF_WEIGHTS_MEAN_VALUE, "fixed defaults");
    fixed.struct_size = 4;
    status = uvf_fixed_boundary_map(positions, nv, triangles, nt, &fixed, uv);
    check(status == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "struct_size") != NULL,
          "undersized options struct is rejected");
    uvf_natural_conformal_options_default(&conformal);
    check(conformal.struct_size == sizeof conformal && conformal.pin_count == 0, "conformal defaults");
    conformal.pin_count = 2;
    conformal.pin_vertices[0] = 0;
    conformal.pin_vertices[1] = 0;
    status = uvf_natural_conformal_map(positions, nv, triangles, nt, &conformal, uv);
    check(status == UVF_INVALID_ARGUMENT, "the same vertex pinned twice is rejected");
    status = uvf_mesh_info(positions, nv, triangles, 0, &info);
    check(status == UVF_INVALID_MESH, "zero triangles: empty mesh");
    status = uvf_mesh_info(positions, (size_t)-1 / 2, triangles, nt, &info);
    check(status == UVF_INVALID_ARGUMENT, "vertex count whose byte size overflows");
    status = uvf_mesh_info(positions, nv, triangles, nt, NULL);
    check(status == UVF_INVALID_ARGUMENT, "NULL info output");
}

/* uvf_metrics with per-corner UVs: every corner its own UV, same layout. */
static void check_corner_metrics(const double *positions, size_t nv, const uint32_t *triangles, size_t nt,
                                 const double *uv) {
    static double corner_uv[2 * 6 * (N - 1) * (N - 1)];
    static uint32_t corner_index[6 * (N - 1) * (N - 1)];
    UvfMetrics per_vertex, per_corner;
    per_vertex.struct_size = sizeof per_vertex;
    per_corner.struct_size = sizeof per_corner;
    size_t c;
    for (c = 0; c < 3 * nt; c++) {
        corner_uv[2 * c] = uv[2 * triangles[c]];
        corner_uv[2 * c + 1] = uv[2 * triangles[c] + 1];
        corner_index[c] = (uint32_t)c;
    }
    check(uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &per_vertex) == UVF_OK, "per-vertex metrics");
    CHECK_OLD_LAYOUT(UvfLayoutCheck, flipped, islands, uvf_check_layout(uv, nv, triangles, nt, report_));
    CHECK_OLD_LAYOUT(UvfMetrics, triangles, area_max, uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, report_));
    check(uvf_metrics(positions, nv, triangles, nt, corner_uv, 3 * nt, corner_index, &per_corner) == UVF_OK,
          "per-corner metrics");
    check(per_vertex.stretch_l2 == per_corner.stretch_l2 && per_vertex.flipped == per_corner.flipped,
          "per-corner and per-vertex metrics agree");
    /* Every corner split: every edge is a UV boundary edge, neighbours' edges overlap but
     * do not cross properly. */
    check(uvf_metrics(positions, nv, triangles, nt, uv, nv - 1, NULL, &per_vertex) == UVF_INVALID_ARGUMENT,
          "per-vertex UV count must match the vertex count");
}

static int cancel_at_third_call(void *user, double fraction) {
    int *calls = (int *)user;
    (void)fraction;
    (*calls)++;
    return *calls >= 3;
}

/* uvf_nonlinear_map: every method keeps every triangle positively oriented, lowers its energy,
 * reports its run; cancellation, bad options. */
static void check_nonlinear(const double *positions, size_t nv, const uint32_t *triangles, size_t nt, double *uv) {
    static const uint32_t methods[6] = {UVF_NONLINEAR_SLIM, UVF_NONLINEAR_ARAP, UVF_NONLINEAR_MIPS,
                                        UVF_NONLINEAR_STRETCH, UVF_NONLINEAR_GREEN_LAGRANGE, UVF_NONLINEAR_DEGENER};
    UvfNonlinearOptions options;
    UvfNonlinearReport report;
    report.struct_size = sizeof report;
    UvfStatus status;
    size_t m, t;
    int calls = 0;
    for (m = 0; m < 6; m++) {
        int positive = 1;
        uvf_nonlinear_options_default(&options);
        check(options.struct_size == sizeof options && options.iterations > 0 && options.theta == 3.0,
              "nonlinear defaults");
        options.method = methods[m];
        options.iterations = 20;
        status = uvf_nonlinear_map(positions, nv, triangles, nt, &options, uv, &report);
        CHECK_OLD_LAYOUT(UvfNonlinearReport, iterations, final_energy, uvf_nonlinear_map(positions, nv, triangles, nt, &options, uv, report_));
        check(status == UVF_OK, "uvf_nonlinear_map succeeds");
        for (t = 0; t < nt; t++) {
            const double *a = uv + 2 * triangles[3 * t], *b = uv + 2 * triangles[3 * t + 1], *c = uv + 2 * triangles[3 * t + 2];
            if (!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0)) positive = 0;
        }
        check(positive, "uvf_nonlinear_map flips no triangle");
        check(report.iterations > 0 && report.final_energy < report.initial_energy, "uvf_nonlinear_map lowers its energy");
    }
    check(uvf_nonlinear_map(positions, nv, triangles, nt, NULL, uv, NULL) == UVF_OK, "NULL options and report");

    uvf_nonlinear_options_default(&options);
    options.progress = cancel_at_third_call;
    options.progress_user = &calls;
    status = uvf_nonlinear_map(positions, nv, triangles, nt, &options, uv, NULL);
    check(status == UVF_CANCELLED && calls == 3, "nonlinear progress callback cancels at once");

    uvf_nonlinear_options_default(&options);
    options.method = 99;
    check(uvf_nonlinear_map(positions, nv, triangles, nt, &options, uv, NULL) == UVF_INVALID_ARGUMENT, "unknown nonlinear method");
    uvf_nonlinear_options_default(&options);
    options.method = UVF_NONLINEAR_DEGENER;
    options.theta = -1.0;
    check(uvf_nonlinear_map(positions, nv, triangles, nt, &options, uv, NULL) == UVF_INVALID_ARGUMENT, "theta <= 0 rejected");
}

/* Desbrun et al. 2002 §4.1-4.2: point constraints, more than two pins, the boundary editor. */
static void check_intrinsic_tools(const double *positions, size_t nv, const uint32_t *triangles, size_t nt,
                                  double *uv) {
    static double uv2[2 * N * N];
    static double basis[4 * (N - 1) * N * N];
    static uint32_t boundary[4 * (N - 1)];
    static double boundary_uv[8 * (N - 1)];
    UvfFixedBoundaryOptions fixed;
    UvfIntrinsicToolOptions tool;
    UvfPointConstraint c[2];
    UvfBoundaryEditor *editor = NULL;
    uint32_t pins[3];
    double pin_uv[6];
    const uint32_t t = (uint32_t)(nt / 2);
    double px, py, sum, worst = 0.0;
    size_t b = 0, i, v;
    int k;

    uvf_fixed_boundary_options_default(&fixed);
    fixed.weights = UVF_WEIGHTS_CONFORMAL;
    c[0].triangle = t;
    c[0].barycentric[0] = 0.2; c[0].barycentric[1] = 0.3; c[0].barycentric[2] = 0.5;
    c[0].uv[0] = 0.45; c[0].uv[1] = 0.55;
    check(uvf_constrained_fixed_boundary_map(positions, nv, triangles, nt, &fixed, c, 1, uv) == UVF_OK,
          "constrained fixed-boundary map succeeds");
    px = py = 0.0;
    for (k = 0; k < 3; k++) {
        px += c[0].barycentric[k] * uv[2 * triangles[3 * t + k]];
        py += c[0].barycentric[k] * uv[2 * triangles[3 * t + k] + 1];
    }
    check(fabs(px - 0.45) < 1e-9 && fabs(py - 0.55) < 1e-9, "constrained point lands on its target");
    c[1] = c[0];
    c[1].uv[0] = 0.1;
    check(uvf_constrained_fixed_boundary_map(positions, nv, triangles, nt, &fixed, c, 2, uv) == UVF_INVALID_ARGUMENT
              && strstr(uvf_last_error_message(), "conflicts") != NULL,
          "conflicting constraints give UVF_INVALID_ARGUMENT");

    uvf_intrinsic_tool_options_default(&tool);
    pins[0] = 0; pins[1] = N - 1; pins[2] = (N / 2) * N + N / 2;
    pin_uv[0] = 0.0; pin_uv[1] = 0.0; pin_uv[2] = 1.0; pin_uv[3] = 0.0; pin_uv[4] = 0.5; pin_uv[5] = 0.6;
    check(uvf_pinned_natural_conformal_map(positions, nv, triangles, nt, pins, pin_uv, 3, &tool, uv) == UVF_OK,
          "natural conformal map with three pins");
    check(fabs(uv[2 * pins[2]] - 0.5) < 1e-9 && fabs(uv[2 * pins[2] + 1] - 0.6) < 1e-9, "third pin honoured");
    check(uvf_pinned_natural_conformal_map(positions, nv, triangles, nt, pins, pin_uv, 1, &tool, uv) == UVF_INVALID_ARGUMENT,
          "one pin is not enough");
    check(uvf_constrained_natural_conformal_map(positions, nv, triangles, nt, c, 1, NULL, uv) == UVF_INVALID_ARGUMENT,
          "one constraint is not enough");

    check(uvf_boundary_editor_new(positions, nv, triangles, nt, 0.5, 0.5, NULL, &editor) == UVF_OK && editor != NULL,
          "boundary editor created");
    check(uvf_boundary_editor_boundary(editor, &b, NULL) == UVF_OK && b == 4 * (N - 1), "boundary count");
    check(uvf_boundary_editor_boundary(editor, &b, boundary) == UVF_OK, "boundary vertices");
    for (i = 0; i < b; i++) {
        double a = 6.283185307179586 * (double)i / (double)b;
        boundary_uv[2 * i] = cos(a) * (1.0 + 0.1 * cos(3 * a));
        boundary_uv[2 * i + 1] = sin(a);
    }
    check(uvf_boundary_editor_solve(editor, boundary_uv, b, uv) == UVF_OK, "editor solve");
    check(uvf_boundary_editor_solve(editor, boundary_uv, b - 1, uv) == UVF_INVALID_ARGUMENT, "editor needs every boundary vertex");
    check(uvf_boundary_editor_basis(editor, 8 * nv * b - 1, basis) == UVF_INVALID_ARGUMENT, "basis above the memory cap refused");
    check(uvf_boundary_editor_basis(editor, 8 * nv * b, basis) == UVF_OK, "basis within the cap");
    for (v = 0; v < nv; v++) {
        for (k = 0; k < 2; k++) {
            sum = 0.0;
            for (i = 0; i < b; i++) sum += basis[i * nv + v] * boundary_uv[2 * i + k];
            if (fabs(sum - uv[2 * v + k]) > worst) worst = fabs(sum - uv[2 * v + k]);
        }
    }
    check(worst < 1e-9, "Green basis sum equals the editor solve");
    uvf_fixed_boundary_options_default(&fixed);
    fixed.weights = UVF_WEIGHTS_INTRINSIC;
    fixed.lambda = 0.5;
    fixed.mu = 0.5;
    fixed.boundary = UVF_BOUNDARY_GIVEN;
    fixed.given_count = b;
    fixed.given_vertices = boundary;
    fixed.given_uv = boundary_uv;
    check(uvf_fixed_boundary_map(positions, nv, triangles, nt, &fixed, uv2) == UVF_OK, "fresh fixed-boundary solve");
    worst = 0.0;
    for (v = 0; v < 2 * nv; v++)
        if (fabs(uv2[v] - uv[v]) > worst) worst = fabs(uv2[v] - uv[v]);
    check(worst < 1e-9, "editor solve equals a fresh fixed-boundary solve");
    uvf_boundary_editor_free(editor);
    uvf_boundary_editor_free(NULL);
    check(uvf_boundary_editor_new(positions, nv, triangles, nt, 0.0, 0.0, NULL, &editor) == UVF_INVALID_ARGUMENT
              && editor == NULL, "λ = μ = 0 refused");
}

/* uvf_abf: ABF++ and ABF converge on the bent grid without flips, report their iterations, and
 * a progress callback that returns non-zero at the first iteration cancels. */
static int cancel_first(void *user, double fraction) {
    (void)fraction;
    (*(int *)user)++;
    return 1;
}

static void check_abf(const double *positions, size_t nv, const uint32_t *triangles, size_t nt, double *uv) {
    UvfAbfOptions options;
    UvfAbfReport report;
    report.struct_size = sizeof report;
    UvfMetrics metrics;
    metrics.struct_size = sizeof metrics;
    UvfStatus status;
    int calls = 0;
    uvf_abf_options_default(&options);
    check(options.struct_size == sizeof(UvfAbfOptions) && options.variant == UVF_ABF_VARIANT_ABF_PLUS_PLUS,
          "ABF defaults: ABF++");
    status = uvf_abf(positions, nv, triangles, nt, &options, uv, &report);
    CHECK_OLD_LAYOUT(UvfAbfReport, iterations, invalid_angles, uvf_abf(positions, nv, triangles, nt, &options, uv, report_));
    check(status == UVF_OK && report.converged == 1 && report.gradient_norm <= 1e-6 && report.iterations <= 10,
          "ABF++ converges on the bent grid");
    status = uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics);
    check(status == UVF_OK && metrics.flipped == 0, "ABF++ flips no triangle");
    options.variant = UVF_ABF_VARIANT_ABF;
    status = uvf_abf(positions, nv, triangles, nt, &options, uv, NULL);
    check(status == UVF_OK, "original ABF succeeds");
    options.variant = 9;
    check(uvf_abf(positions, nv, triangles, nt, &options, uv, NULL) == UVF_INVALID_ARGUMENT, "unknown ABF variant");
    uvf_abf_options_default(&options);
    check(options.weights == UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT && options.barrier == 1.0, "ABF objective defaults");
    options.weights = UVF_ABF_WEIGHTS_INVERSE_SQUARE;
    options.barrier = 0.0;
    status = uvf_abf(positions, nv, triangles, nt, &options, uv, &report);
    check(status == UVF_OK && report.converged == 1, "ABF++ with the papers' objective converges on the bent grid");
    options.weights = 7;
    check(uvf_abf(positions, nv, triangles, nt, &options, uv, NULL) == UVF_INVALID_ARGUMENT, "unknown ABF weights");
    options.weights = UVF_ABF_WEIGHTS_INVERSE;
    options.barrier = -1.0;
    check(uvf_abf(positions, nv, triangles, nt, &options, uv, NULL) == UVF_INVALID_ARGUMENT, "negative ABF barrier");
    /* A caller built against the first version of the struct (without weights and barrier). */
    uvf_abf_options_default(&options);
    options.struct_size = offsetof(UvfAbfOptions, weights);
    options.weights = 7;
    check(uvf_abf(positions, nv, triangles, nt, &options, uv, NULL) == UVF_OK, "version-1 ABF options get the defaults");
    uvf_abf_options_default(&options);
    options.progress = cancel_first;
    options.progress_user = &calls;
    uv[0] = 42.0;
    status = uvf_abf(positions, nv, triangles, nt, &options, uv, &report);
    check(status == UVF_CANCELLED && calls == 1 && uv[0] == 42.0, "ABF++ cancels within one iteration");
}

/* Closed surfaces: cut a torus into a disk through the result handle, flatten the cut mesh,
 * and map an octahedron onto the sphere without flips. */
#define TN 10
#define TM 6
/* Spectral conformal map, near-optimal λ and boundary optimization (Desbrun et al. 2002 §5,
 * Mullen et al. 2008) on the bent grid: converged eigenpair, λ no worse than DCP and DAP, a
 * decreasing energy history without flips, cancellation and bad options. */
static void check_intrinsic_optimization(const double *positions, size_t nv, const uint32_t *triangles, size_t nt,
                                         double *uv) {
    UvfSpectralOptions spectral;
    UvfSpectralReport spectral_report;
    spectral_report.struct_size = sizeof spectral_report;
    UvfIntrinsicOptimalOptions optimal;
    UvfIntrinsicOptimalReport optimal_report;
    optimal_report.struct_size = sizeof optimal_report;
    UvfBoundaryOptimizationOptions bopt;
    UvfBoundaryOptimizationReport breport;
    breport.struct_size = sizeof breport;
    UvfMetrics metrics;
    metrics.struct_size = sizeof metrics;
    double history[101];
    size_t i;
    int calls = 0, monotone = 1;

    uvf_spectral_options_default(&spectral);
    check(spectral.struct_size == sizeof spectral && spectral.iterations > 0, "spectral defaults");
    check(uvf_spectral_conformal_map(positions, nv, triangles, nt, &spectral, uv, &spectral_report) == UVF_OK,
          "spectral conformal map succeeds");
    CHECK_OLD_LAYOUT(UvfSpectralReport, iterations, residual, uvf_spectral_conformal_map(positions, nv, triangles, nt, &spectral, uv, report_));
    check(spectral_report.converged == 1 && spectral_report.residual <= spectral.tolerance &&
              spectral_report.eigenvalue >= 0.0,
          "spectral eigenpair converged");
    check(uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics) == UVF_OK && metrics.flipped == 0 &&
              metrics.conformal_mean < 1.05,
          "spectral map is nearly conformal without flips");
    check(uvf_spectral_conformal_map(positions, nv, triangles, nt, NULL, uv, NULL) == UVF_OK,
          "spectral map with NULL options and report");
    spectral.iterations = 0;
    uv[0] = 42.0;
    check(uvf_spectral_conformal_map(positions, nv, triangles, nt, &spectral, uv, NULL) == UVF_INVALID_ARGUMENT &&
              uv[0] == 42.0,
          "zero spectral iterations refused, output untouched");
    uvf_spectral_options_default(&spectral);
    spectral.progress = cancel_first;
    spectral.progress_user = &calls;
    check(uvf_spectral_conformal_map(positions, nv, triangles, nt, &spectral, uv, NULL) == UVF_CANCELLED &&
              calls == 1 && uv[0] == 42.0,
          "spectral map cancelled by its callback");

    {
        UvfCirclePatternOptions circles;
        UvfCirclePatternReport circles_report;
        circles_report.struct_size = sizeof circles_report;
        uvf_circle_pattern_options_default(&circles);
        check(circles.struct_size == sizeof circles && circles.max_iterations > 0 && circles.pin_count == 0 &&
                  circles.intrinsic_delaunay == 1 && circles.convex_boundary == 0,
              "circle pattern defaults");
        {
            UvfConePlacementOptions placing;
            uint32_t cone_vertices[64];
            double cone_curvatures[64], largest = -1.0;
            size_t cone_count = 99;
            uvf_cone_placement_options_default(&placing);
            check(placing.struct_size == sizeof placing && placing.max_cones == 64 && placing.max_log_scale > 0.0,
                  "cone placement defaults");
            check(uvf_place_cones(positions, nv, triangles, nt, &placing, cone_vertices, cone_curvatures, &cone_count,
                                  &largest) == UVF_OK &&
                      cone_count <= 64 && (largest <= placing.max_log_scale || cone_count == 64),
                  "cone placement succeeds within its limits");
            check(uvf_place_cones(positions, nv, triangles, nt, &placing, cone_vertices, cone_curvatures, NULL, NULL) ==
                      UVF_INVALID_ARGUMENT,
                  "cone placement without count_out refused");
            placing.max_log_scale = NAN;
            cone_count = 99;
            check(uvf_place_cones(positions, nv, triangles, nt, &placing, cone_vertices, cone_curvatures, &cone_count,
                                  NULL) == UVF_INVALID_ARGUMENT &&
                      cone_count == 99 && strstr(uvf_last_error_message(), "max_log_scale") != NULL,
                  "cone placement with a NaN max_log_scale refused, output untouched");
            uvf_cone_placement_options_default(&placing);
            placing.struct_size = 4;
            check(uvf_place_cones(positions, nv, triangles, nt, &placing, cone_vertices, cone_curvatures, &cone_count,
                                  NULL) == UVF_INVALID_ARGUMENT,
                  "cone placement options of a wrong size refused");
        }
        circles.convex_boundary = 1;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, &circles_report) == UVF_OK &&
                  circles_report.closure_error < 1e-9 && circles_report.radius_span >= 0.0 &&
                  circles_report.radius_span < 12.0,
              "circle pattern map with a convex boundary");
        CHECK_OLD_LAYOUT(UvfCirclePatternReport, angle_iterations, radius_span, uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, report_));
        check(uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics) == UVF_OK &&
                  metrics.boundary_intersections == 0,
              "circle pattern map with a convex boundary does not cross its boundary");
        circles.convex_boundary = 2;
        uv[0] = 42.0;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, NULL) == UVF_INVALID_ARGUMENT &&
                  uv[0] == 42.0,
              "convex_boundary other than 0 or 1 refused, output untouched");
        circles.convex_boundary = 0;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, &circles_report) == UVF_OK &&
                  circles_report.closure_error < 1e-9,
              "circle pattern map succeeds with every circle closed");
        check(uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics) == UVF_OK &&
                  metrics.flipped == circles_report.flipped_triangles && metrics.degenerate_uv == 0,
              "circle pattern map reports its flipped triangles, none degenerate");
        circles.intrinsic_delaunay = 0;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, &circles_report) == UVF_OK &&
                  circles_report.intrinsic_flips == 0 && circles_report.flipped_triangles == 0,
              "circle pattern map without intrinsic flips");
        check(uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics) == UVF_OK && metrics.flipped == 0 &&
                  metrics.degenerate_uv == 0,
              "circle pattern map without intrinsic flips has no flipped or degenerate triangle");
        circles.intrinsic_delaunay = 2;
        uv[0] = 42.0;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, NULL) == UVF_INVALID_ARGUMENT &&
                  uv[0] == 42.0,
              "intrinsic_delaunay other than 0 or 1 refused, output untouched");
        circles.intrinsic_delaunay = 1;
        {
            /* The grid's four corners as the corners of a rectangle: straight sides. */
            static double curvature[N * N];
            uint32_t corners[4] = {0, N - 1, N * N - 1, N * (N - 1)};
            double cross;
            check(uvf_circle_pattern_polygon_curvature(positions, nv, triangles, nt, corners, 4, curvature) == UVF_OK &&
                      fabs(curvature[0] - 3.14159265358979 / 2) < 1e-12 && curvature[1] == 0.0 &&
                      isnan(curvature[N + 1]),
                  "polygon curvature: pi/2 at the corners, 0 along the boundary, NaN inside");
            circles.boundary_curvature = curvature;
            check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, &circles_report) == UVF_OK &&
                      circles_report.closure_error < 1e-9,
                  "circle pattern map onto a rectangle");
            cross = (uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[3] - uv[1]) * (uv[4] - uv[0]);
            check(fabs(cross) < 1e-9 * ((uv[4] - uv[0]) * (uv[4] - uv[0]) + (uv[5] - uv[1]) * (uv[5] - uv[1])),
                  "rectangle side through vertices 0, 1, 2 is straight");
            curvature[1] = 0.5; /* the boundary no longer turns by 2 pi in all */
            uv[0] = 42.0;
            check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, NULL) == UVF_INVALID_ARGUMENT &&
                      uv[0] == 42.0,
                  "boundary curvature against Gauss-Bonnet refused, output untouched");
            corners[3] = N + 1; /* interior vertex */
            check(uvf_circle_pattern_polygon_curvature(positions, nv, triangles, nt, corners, 4, curvature) ==
                      UVF_INVALID_ARGUMENT,
                  "polygon corner off the boundary refused");
            circles.boundary_curvature = NULL;
        }
        {
            /* One cone of curvature pi/2 in the middle of the grid: cut to the boundary. */
            static double corner_uv[6 * 2 * (N - 1) * (N - 1)];
            uint32_t cone = (N / 2) * N + N / 2, boundary_vertex = 0;
            double kappa = 3.14159265358979 / 2;
            size_t k;
            int finite = 1;
            check(uvf_circle_pattern_cone_map(positions, nv, triangles, nt, &cone, &kappa, 1, &circles, corner_uv,
                                              &circles_report) == UVF_OK &&
                      circles_report.closure_error < 1e-9 && circles_report.flipped_triangles == 0,
                  "circle pattern cone map");
            for (k = 0; k < 6 * nt; k++)
                finite &= isfinite(corner_uv[k]);
            check(finite, "cone map corner uv finite");
            corner_uv[0] = 42.0;
            check(uvf_circle_pattern_cone_map(positions, nv, triangles, nt, &boundary_vertex, &kappa, 1, &circles,
                                              corner_uv, NULL) == UVF_INVALID_ARGUMENT &&
                      corner_uv[0] == 42.0,
                  "cone on the boundary refused, output untouched");
            check(uvf_circle_pattern_cone_map(positions, nv, triangles, nt, NULL, NULL, 1, &circles, corner_uv, NULL) ==
                      UVF_INVALID_ARGUMENT,
                  "NULL cone arrays with a count refused");
        }
        circles.pin_count = 1;
        uv[0] = 42.0;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, NULL) == UVF_INVALID_ARGUMENT &&
                  uv[0] == 42.0,
              "one pin refused, output untouched");
        uvf_circle_pattern_options_default(&circles);
        calls = 0;
        circles.progress = cancel_first;
        circles.progress_user = &calls;
        check(uvf_circle_pattern_map(positions, nv, triangles, nt, &circles, uv, NULL) == UVF_CANCELLED &&
                  calls == 1 && uv[0] == 42.0,
              "circle pattern map cancelled by its callback");
        calls = 0;
    }

    {
        UvfQuadCoverOptions qc;
        UvfQuadCoverReport qc_report;
        qc_report.struct_size = sizeof qc_report;
        static double corner_uv[6 * 2 * (N - 1) * (N - 1)], field[3 * 2 * (N - 1) * (N - 1)];
        static int32_t cone_index[N * N];
        size_t k;
        uvf_quadcover_options_default(&qc);
        check(qc.struct_size == sizeof qc && qc.grid_spacing == 0.0 && qc.round == 1 && qc.pair_cells == 2.0 &&
                  qc.untangle == 1,
              "quadcover defaults");
        qc.grid_spacing = 0.1;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, cone_index, &qc_report) == UVF_OK &&
                  qc_report.lattice_error < 1e-9 && qc_report.grid_spacing == 0.1 && isfinite(qc_report.energy) &&
                  qc_report.cone_count <= qc_report.cones_before_cancellation &&
                  qc_report.flipped_count <= qc_report.flipped_before_untangling &&
                  qc_report.forced_flat_count <= qc_report.flipped_count,
              "quadcover with the curvature field, integer gaps");
        CHECK_OLD_LAYOUT(UvfQuadCoverReport, cone_count, forced_flat_count, uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, cone_index, report_));
        qc.untangle = 2;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, NULL, NULL) == UVF_INVALID_ARGUMENT &&
                  strstr(uvf_last_error_message(), "untangle") != NULL,
              "quadcover: untangle must be 0 or 1");
        qc.untangle = 1;
        qc.pair_cells = -1.0;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, NULL, NULL) == UVF_INVALID_ARGUMENT &&
                  strstr(uvf_last_error_message(), "pair_cells") != NULL,
              "quadcover: negative pair_cells refused");
        /* A caller built against the first layout (no pair_cells) gets the default. */
        qc.struct_size = offsetof(UvfQuadCoverOptions, pair_cells);
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, NULL, NULL) == UVF_OK,
              "quadcover: the first options layout is still accepted");
        /* ... and the second (no untangle) too. */
        qc.struct_size = offsetof(UvfQuadCoverOptions, untangle);
        qc.pair_cells = 2.0;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, NULL, NULL) == UVF_OK,
              "quadcover: the second options layout is still accepted");
        qc.struct_size = sizeof qc;
        qc.pair_cells = 2.0;
        for (k = 0; k < 6 * nt; k++)
            check(isfinite(corner_uv[k]), "quadcover corner uv finite");
        for (k = 0; k < nt; k++) {
            field[3 * k] = 1.0;
            field[3 * k + 1] = 0.0;
            field[3 * k + 2] = 0.0;
        }
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, field, corner_uv, NULL, &qc_report) == UVF_OK &&
                  qc_report.cone_count == 0 && qc_report.flipped_count == 0,
              "quadcover with a constant field: no cone, no fold");
        {
            UvfQuadMesh *grid_quads = NULL;
            UvfQuadMeshInfo gi;
            gi.struct_size = sizeof gi;
            check(uvf_quadcover_quad_mesh(positions, nv, triangles, nt, &qc, field, 1.0, &grid_quads, &qc_report) ==
                          UVF_OK &&
                      grid_quads != NULL && qc_report.cone_count == 0,
                  "quadcover quad mesh of the flat grid");
            if (grid_quads != NULL) {
                /* The faces tile the (u, v) image of the surface (area = cells covered, from the
                   corner (u, v) of the same map above): whole cells inside, cells cut by the
                   boundary around it. */
                double cells = 0.0;
                for (k = 0; k < nt; k++) {
                    const double *q = corner_uv + 6 * k;
                    cells += 0.5 * ((q[2] - q[0]) * (q[5] - q[1]) - (q[4] - q[0]) * (q[3] - q[1]));
                }
                check(uvf_quad_mesh_info(grid_quads, &gi) == UVF_OK, "quadcover quad mesh info");
                CHECK_OLD_LAYOUT(UvfQuadMeshInfo, vertex_count, quad_count, uvf_quad_mesh_info(grid_quads, report_));
                check((double)gi.face_count >= cells && 5 * gi.quad_count >= 4 * gi.face_count,
                      "quadcover quad mesh: the cells of the grid");
                uvf_quad_mesh_free(grid_quads);
            }
            grid_quads = NULL;
            check(uvf_quadcover_quad_mesh(positions, nv, triangles, nt, &qc, field, 2.5, &grid_quads, NULL) ==
                          UVF_INVALID_ARGUMENT &&
                      grid_quads == NULL && strstr(uvf_last_error_message(), "density") != NULL,
                  "quadcover quad mesh: a fractional density is refused");
            check(uvf_quadcover_quad_mesh(positions, nv, triangles, nt, &qc, field, 1.0, NULL, NULL) ==
                      UVF_INVALID_ARGUMENT,
                  "quadcover quad mesh: NULL output refused");
        }
        field[5] = NAN;
        corner_uv[0] = 42.0;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, field, corner_uv, NULL, NULL) == UVF_INVALID_ARGUMENT &&
                  corner_uv[0] == 42.0 && strstr(uvf_last_error_message(), "triangle 1") != NULL,
              "quadcover: a NaN field vector is refused, naming its triangle, output untouched");
        qc.grid_spacing = -1.0;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, NULL, NULL) == UVF_INVALID_ARGUMENT &&
                  corner_uv[0] == 42.0,
              "quadcover: negative grid spacing refused");
        uvf_quadcover_options_default(&qc);
        calls = 0;
        qc.progress = cancel_first;
        qc.progress_user = &calls;
        check(uvf_quadcover(positions, nv, triangles, nt, &qc, NULL, corner_uv, NULL, NULL) == UVF_CANCELLED &&
                  calls == 1 && corner_uv[0] == 42.0,
              "quadcover cancelled by its callback");
        calls = 0;
    }

    uvf_intrinsic_optimal_options_default(&optimal);
    check(optimal.energy == UVF_ENERGY_EDGE_LENGTH && isinf(optimal.lambda_min) && optimal.lambda_min < 0,
          "near-optimal defaults: edge energy, unbounded lambda");
    check(uvf_intrinsic_optimal_map(positions, nv, triangles, nt, &optimal, uv, &optimal_report) == UVF_OK,
          "near-optimal lambda (edge lengths)");
    CHECK_OLD_LAYOUT(UvfIntrinsicOptimalReport, lambda, flipped, uvf_intrinsic_optimal_map(positions, nv, triangles, nt, &optimal, uv, report_));
    check(optimal_report.energy <= optimal_report.energy_conformal &&
              optimal_report.energy <= optimal_report.energy_authalic && isfinite(optimal_report.lambda),
          "near-optimal energy no worse than DCP and DAP");
    optimal.energy = UVF_ENERGY_AREA;
    optimal.lambda_min = 0.0;
    optimal.lambda_max = 1.0;
    check(uvf_intrinsic_optimal_map(positions, nv, triangles, nt, &optimal, uv, &optimal_report) == UVF_OK &&
              optimal_report.lambda >= 0.0 && optimal_report.lambda <= 1.0,
          "near-optimal lambda (areas) within [0, 1]");
    optimal.lambda_min = 2.0;
    uv[0] = 42.0;
    check(uvf_intrinsic_optimal_map(positions, nv, triangles, nt, &optimal, uv, NULL) == UVF_INVALID_ARGUMENT &&
              uv[0] == 42.0,
          "empty lambda range refused, output untouched");
    optimal.lambda_min = 0.0;
    optimal.energy = 9;
    check(uvf_intrinsic_optimal_map(positions, nv, triangles, nt, &optimal, uv, NULL) == UVF_INVALID_ARGUMENT,
          "unknown energy refused");

    uvf_boundary_optimization_options_default(&bopt);
    check(bopt.iterations == 100 && bopt.lambda == 1.0 && bopt.mu == 0.0, "boundary optimization defaults");
    check(uvf_boundary_optimized_map(positions, nv, triangles, nt, &bopt, uv, history, 101, &breport) == UVF_OK,
          "boundary optimization succeeds");
    CHECK_OLD_LAYOUT(UvfBoundaryOptimizationReport, iterations, flipped, uvf_boundary_optimized_map(positions, nv, triangles, nt, &bopt, uv, history, 101, report_));
    check(breport.history_length == (size_t)breport.iterations + 1 && breport.history_length <= 101 &&
              history[0] == breport.initial_energy && history[breport.history_length - 1] == breport.final_energy &&
              breport.final_energy < breport.initial_energy && breport.flipped == 0,
          "boundary optimization lowers the energy, history reported");
    for (i = 1; i < breport.history_length; i++)
        if (history[i] > history[i - 1]) monotone = 0;
    check(monotone, "energy history never increases");
    check(uvf_metrics(positions, nv, triangles, nt, uv, nv, NULL, &metrics) == UVF_OK && metrics.flipped == 0 &&
              metrics.degenerate_uv == 0,
          "boundary-optimized map has no flipped or degenerate triangle");
    history[1] = -1.0;
    bopt.energy = UVF_ENERGY_AREA;
    check(uvf_boundary_optimized_map(positions, nv, triangles, nt, &bopt, uv, history, 1, &breport) == UVF_OK &&
              breport.history_length > 1 && history[1] == -1.0,
          "history truncated to its capacity, full length reported");
    calls = 0;
    bopt.progress = cancel_first;
    bopt.progress_user = &calls;
    uv[0] = 42.0;
    check(uvf_boundary_optimized_map(positions, nv, triangles, nt, &bopt, uv, history, 101, NULL) == UVF_CANCELLED &&
              calls == 1 && uv[0] == 42.0,
          "boundary optimization cancelled before its first iteration");
    bopt.progress = NULL;
    bopt.tolerance = -1.0;
    check(uvf_boundary_optimized_map(positions, nv, triangles, nt, &bopt, uv, NULL, 0, NULL) == UVF_INVALID_ARGUMENT,
          "negative tolerance refused");
}

static void check_closed_surfaces(void) {
    static double pos[3 * TN * TM], cut_pos[3 * 4 * TN * TM], cut_uv[2 * 4 * TN * TM];
    static uint32_t tris[6 * TN * TM], cut_tris[6 * TN * TM], original[4 * TN * TM], edges[4 * TN * TM];
    static const double oct[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    static const uint32_t oct_tris[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    double sphere[18];
    size_t flipped = 99, k;
    int i, j, t = 0, calls = 0;
    UvfCut *cut = NULL;
    UvfCutInfo info;
    info.struct_size = sizeof info;
    UvfCutOptions options;
    UvfSphereOptions sphere_options;
    UvfMetrics metrics;
    metrics.struct_size = sizeof metrics;
    UvfStatus status;
    for (i = 0; i < TN; i++)
        for (j = 0; j < TM; j++) {
            double u = 6.283185307179586 * i / TN, v = 6.283185307179586 * j / TM, r = 2.0 + cos(v);
            pos[3 * (i * TM + j)] = r * cos(u);
            pos[3 * (i * TM + j) + 1] = r * sin(u);
            pos[3 * (i * TM + j) + 2] = sin(v);
        }
    for (i = 0; i < TN; i++)
        for (j = 0; j < TM; j++) {
            uint32_t a = (uint32_t)(i * TM + j), b = (uint32_t)(((i + 1) % TN) * TM + j);
            uint32_t c = (uint32_t)(((i + 1) % TN) * TM + (j + 1) % TM), d = (uint32_t)(i * TM + (j + 1) % TM);
            uint32_t *q = tris + 6 * t++;
            q[0] = a; q[1] = b; q[2] = c; q[3] = a; q[4] = c; q[5] = d;
        }
    status = uvf_natural_conformal_map(pos, TN * TM, tris, 2 * TN * TM, NULL, cut_uv);
    check(status == UVF_UNSUPPORTED_TOPOLOGY, "a torus is not a disk for the disk methods");

    uvf_cut_options_default(&options);
    check(options.struct_size == sizeof options && options.cost == UVF_CUT_COST_CURVATURE, "cut defaults");
    status = uvf_cut_to_disk(pos, TN * TM, tris, 2 * TN * TM, &options, &cut);
    check(status == UVF_OK && cut != NULL, "torus is cut into a disk");
    if (cut == NULL) return;
    status = uvf_cut_info(cut, &info);
    CHECK_OLD_LAYOUT(UvfCutInfo, vertex_count, total_edge_length, uvf_cut_info(cut, report_));
    check(status == UVF_OK && info.triangle_count == 2 * TN * TM && info.edge_count > 0, "cut info");
    check(info.seam_length > 0.0 && info.seam_length < info.total_edge_length, "seam is part of the edges");
    /* A two-loop cut graph of E edges adds E + 1 vertex copies. */
    check(info.vertex_count == TN * TM + info.edge_count + 1, "torus cut duplicates E + 1 vertices");
    status = uvf_cut_copy_triangles(cut, cut_tris, 3 * info.triangle_count - 1);
    check(status == UVF_INVALID_ARGUMENT, "too small triangle capacity is rejected");
    check(uvf_cut_copy_triangles(cut, cut_tris, 3 * info.triangle_count) == UVF_OK, "copy triangles");
    check(uvf_cut_copy_original_vertices(cut, original, info.vertex_count) == UVF_OK, "copy original vertices");
    check(uvf_cut_copy_positions(cut, cut_pos, 3 * info.vertex_count) == UVF_OK, "copy positions");
    check(uvf_cut_copy_edges(cut, edges, 2 * info.edge_count) == UVF_OK, "copy edges");
    for (k = 0; k < 3 * info.triangle_count; k++)
        check(original[cut_tris[k]] == tris[k], "every corner maps back to its input vertex");
    for (k = 0; k < info.edge_count; k++) check(edges[2 * k] < edges[2 * k + 1], "edges are ordered pairs");
    status = uvf_fixed_boundary_map(cut_pos, info.vertex_count, cut_tris, info.triangle_count, NULL, cut_uv);
    check(status == UVF_OK, "the cut mesh flattens with a disk method");
    status = uvf_metrics(pos, TN * TM, tris, info.triangle_count, cut_uv, info.vertex_count, cut_tris, &metrics);
    check(status == UVF_OK && metrics.flipped == 0, "per-corner UVs of the cut torus do not flip");
    check(uvf_cut_info(NULL, &info) == UVF_INVALID_ARGUMENT, "NULL handle is rejected");
    uvf_cut_free(cut);
    uvf_cut_free(NULL);
    options.cost = 42;
    cut = NULL;
    status = uvf_cut_to_disk(pos, TN * TM, tris, 2 * TN * TM, &options, &cut);
    check(status == UVF_INVALID_ARGUMENT && cut == NULL, "unknown cost is rejected");

    uvf_sphere_options_default(&sphere_options);
    check(sphere_options.method == UVF_SPHERE_TUTTE_GNOMONIC, "sphere defaults");
    status = uvf_spherical_map(oct, 6, oct_tris, 8, &sphere_options, sphere, &flipped);
    check(status == UVF_OK && flipped == 0, "octahedron maps to the sphere without flips");
    for (k = 0; k < 6; k++)
        check(fabs(sphere[3 * k] * sphere[3 * k] + sphere[3 * k + 1] * sphere[3 * k + 1] +
                   sphere[3 * k + 2] * sphere[3 * k + 2] - 1.0) < 1e-12, "positions on the unit sphere");
    sphere_options.method = UVF_SPHERE_CIRCLE_PATTERNS;
    status = uvf_spherical_map(oct, 6, oct_tris, 8, &sphere_options, sphere, &flipped);
    check(status == UVF_OK && flipped == 0, "octahedron by circle patterns");
    /* The octahedron is mapped onto a regular octahedron: opposite vertices antipodal. */
    for (k = 0; k < 6; k += 2)
        check(fabs(sphere[3 * k] * sphere[3 * k + 3] + sphere[3 * k + 1] * sphere[3 * k + 4] +
                   sphere[3 * k + 2] * sphere[3 * k + 5] + 1.0) < 1e-9,
              "circle-pattern octahedron: opposite vertices antipodal");
    calls = 0;
    sphere_options.progress = cancel_first;
    sphere_options.progress_user = &calls;
    sphere[0] = 42.0;
    check(uvf_spherical_map(oct, 6, oct_tris, 8, &sphere_options, sphere, &flipped) == UVF_CANCELLED &&
              calls == 1 && sphere[0] == 42.0,
          "sphere map cancelled by its callback, output untouched");
    sphere_options.progress = NULL;
    /* A caller built against the first layout (no progress callback) is still accepted. */
    sphere_options.struct_size = offsetof(UvfSphereOptions, progress);
    check(uvf_spherical_map(oct, 6, oct_tris, 8, &sphere_options, sphere, &flipped) == UVF_OK,
          "sphere map: the first options layout is still accepted");
    sphere_options.struct_size = sizeof sphere_options;
    sphere_options.method = 42;
    check(uvf_spherical_map(oct, 6, oct_tris, 8, &sphere_options, sphere, &flipped) == UVF_INVALID_ARGUMENT,
          "unknown sphere method refused");
    sphere_options.method = UVF_SPHERE_TUTTE_GNOMONIC;
    status = uvf_spherical_map(pos, TN * TM, tris, 2 * TN * TM, NULL, sphere, &flipped);
    check(status == UVF_UNSUPPORTED_TOPOLOGY, "a torus has no spherical map");
}

/* Periodic Global Parameterization on a torus: curvatures, per-corner (θ, φ), the result
 * handle's singularity lists (a torus has χ = 0), cancellation, bad fields, and the entry
 * points that are not implemented yet. */
#define PN 60
#define PM 12
static int cancel_pgp(void *user, double fraction) {
    (void)user;
    return fraction > 0.2;
}

static void check_pgp(void) {
    static double pos[3 * PN * PM], kmin_dir[3 * PN * PM], kmax_dir[3 * PN * PM], kmin[PN * PM], kmax[PN * PM];
    static double corners[6 * 2 * PN * PM], field[3 * PN * PM], copied_field[3 * PN * PM], indices[PN * PM];
    static uint32_t tris[6 * PN * PM], list[6 * PN * PM];
    const size_t nv = PN * PM, nt = 2 * PN * PM;
    UvfCurvatureOptions copts;
    UvfPgpOptions options;
    UvfPgpInfo info;
    info.struct_size = sizeof info;
    UvfPgp *pgp = NULL;
    UvfQuadMesh *quads = NULL;
    UvfChartLayout *layout = NULL;
    UvfStatus status;
    size_t k;
    int i, j, t = 0, ok = 1;
    for (i = 0; i < PN; i++)
        for (j = 0; j < PM; j++) {
            double u = 6.283185307179586 * i / PN, v = 6.283185307179586 * j / PM, r = 5.0 + cos(v);
            pos[3 * (i * PM + j)] = r * cos(u);
            pos[3 * (i * PM + j) + 1] = r * sin(u);
            pos[3 * (i * PM + j) + 2] = sin(v);
        }
    for (i = 0; i < PN; i++)
        for (j = 0; j < PM; j++) {
            uint32_t a = (uint32_t)(i * PM + j), b = (uint32_t)(((i + 1) % PN) * PM + j);
            uint32_t c = (uint32_t)(((i + 1) % PN) * PM + (j + 1) % PM), d = (uint32_t)(i * PM + (j + 1) % PM);
            uint32_t *q = tris + 6 * t++;
            q[0] = a; q[1] = b; q[2] = c; q[3] = a; q[4] = c; q[5] = d;
        }

    uvf_curvature_options_default(&copts);
    check(copts.struct_size == sizeof copts && copts.neighbourhood == UVF_CURVATURE_RINGS && copts.rings == 2,
          "curvature defaults");
    status = uvf_curvature(pos, nv, tris, nt, &copts, kmin_dir, kmax_dir, kmin, kmax);
    check(status == UVF_OK, "curvature of a torus");
    for (k = 0; k < nv; k++) ok &= fabs(kmax[k] - 1.0) < 0.15 && kmin[k] <= kmax[k];
    check(ok, "torus kmax is 1/r around the tube");
    check(uvf_curvature(pos, nv, tris, nt, NULL, NULL, NULL, NULL, kmax) == UVF_OK, "curvature outputs may be NULL");
    copts.rings = 0;
    kmax[0] = 42.0;
    status = uvf_curvature(pos, nv, tris, nt, &copts, NULL, NULL, NULL, kmax);
    check(status == UVF_INVALID_ARGUMENT && kmax[0] == 42.0, "zero rings are rejected, output untouched");

    uvf_pgp_options_default(&options);
    check(options.struct_size == sizeof options && options.smoothing == UVF_SMOOTH_HALF_PI && options.omega == 0.0 &&
              options.epsilon == 0.1 && options.max_newton_iterations == 100 && options.rho == 0.8 &&
              options.untangle == 1 && options.feature_periods == 3.0 && options.pair_periods == 0.5 &&
              options.dislocation_periods == 1.5 && options.relax == 1,
          "pgp defaults");
    status = uvf_pgp(pos, nv, tris, nt, &options, corners, &pgp);
    check(status == UVF_OK && pgp != NULL, "pgp of a torus");
    if (pgp == NULL) return;
    ok = 1;
    for (k = 0; k < 6 * nt; k++) ok &= isfinite(corners[k]);
    check(ok, "per-corner coordinates are finite");
    status = uvf_pgp_info(pgp, &info);
    CHECK_OLD_LAYOUT(UvfPgpInfo, omega, alignment_degrees, uvf_pgp_info(pgp, report_));
    check(status == UVF_OK && info.omega > 0.0 && fabs(info.index_sum) < 1e-9, "pgp info: index sum 0 on a torus");
    check(info.singular_triangle_count < nt / 20, "few singular triangles");
    check(uvf_pgp_copy_singular_vertices(pgp, list, info.singular_vertex_count) == UVF_OK, "copy singular vertices");
    check(uvf_pgp_copy_singular_edges(pgp, list, 2 * info.singular_edge_count) == UVF_OK, "copy singular edges");
    check(uvf_pgp_copy_singular_triangles(pgp, list, info.singular_triangle_count) == UVF_OK,
          "copy singular triangles");
    for (k = 0; k < info.singular_triangle_count; k++) check(list[k] < nt, "singular triangles are triangles");
    check(uvf_pgp_copy_singular_points(pgp, list, indices, info.singular_point_count) == UVF_OK, "copy points");
    check(uvf_pgp_copy_field(pgp, copied_field, 3 * nv) == UVF_OK, "copy field");
    check(uvf_pgp_copy_field(pgp, copied_field, 3 * nv - 1) == UVF_INVALID_ARGUMENT, "too small field capacity");
    status = uvf_pgp_quad_mesh(pgp, 4.0, &quads);
    check(status == UVF_OK && quads != NULL, "quad-dominant remesh of a torus");
    if (quads != NULL) {
        UvfQuadMeshInfo qi;
        qi.struct_size = sizeof qi;
        check(uvf_quad_mesh_info(quads, &qi) == UVF_OK && qi.face_count > 0 && qi.quad_count * 10 >= qi.face_count * 9,
              "remesh info: at least 90% quads");
        double *qpos = malloc(sizeof(double) * 3 * qi.vertex_count);
        uint32_t *qsizes = malloc(sizeof(uint32_t) * qi.face_count);
        uint32_t *qidx = malloc(sizeof(uint32_t) * qi.index_count);
        check(uvf_quad_mesh_copy(quads, qpos, 3 * qi.vertex_count, qsizes, qi.face_count, qidx, qi.index_count - 1) ==
                  UVF_INVALID_ARGUMENT,
              "remesh copy rejects a short index array");
        check(uvf_quad_mesh_copy(quads, qpos, 3 * qi.vertex_count, qsizes, qi.face_count, qidx, qi.index_count) ==
                  UVF_OK,
              "remesh copy");
        uint32_t *qsizes_only = malloc(sizeof(uint32_t) * qi.face_count);
        check(uvf_quad_mesh_copy(quads, NULL, 0, qsizes_only, qi.face_count, NULL, 0) == UVF_OK &&
                  memcmp(qsizes_only, qsizes, sizeof(uint32_t) * qi.face_count) == 0,
              "remesh copy skips NULL outputs");
        free(qsizes_only);
        size_t sum = 0;
        ok = 1;
        for (k = 0; k < qi.face_count; k++) sum += qsizes[k];
        for (k = 0; k < qi.index_count; k++) ok &= qidx[k] < qi.vertex_count;
        check(sum == qi.index_count && ok, "remesh face sizes and indices are consistent");
        free(qpos);
        free(qsizes);
        free(qidx);
        uvf_quad_mesh_free(quads);
    }
    uvf_quad_mesh_free(NULL);
    quads = NULL;
    status = uvf_pgp_quad_mesh(pgp, 1.5, &quads);
    check(status == UVF_INVALID_ARGUMENT && quads == NULL && strstr(uvf_last_error_message(), "density") != NULL,
          "a fractional remesh density is rejected");
    status = uvf_pgp_chart_layout(pgp, &layout);
    check(status == UVF_OK && layout != NULL, "chart layout of a torus");
    if (layout != NULL) {
        UvfChartLayoutInfo li;
        li.struct_size = sizeof li;
        check(uvf_chart_layout_info(layout, &li) == UVF_OK && li.chart_count > 0 && li.polyline_count > 0,
              "chart layout info");
        CHECK_OLD_LAYOUT(UvfChartLayoutInfo, polyline_count, four_corner_chart_count, uvf_chart_layout_info(layout, report_));
        uint32_t *lsizes = malloc(sizeof(uint32_t) * li.polyline_count);
        double *lpoints = malloc(sizeof(double) * 3 * li.point_count);
        uint32_t *lcorners = malloc(sizeof(uint32_t) * li.chart_count);
        check(uvf_chart_layout_copy(layout, lsizes, li.polyline_count, lpoints, 3 * li.point_count, lcorners,
                                    li.chart_count) == UVF_OK,
              "chart layout copy");
        uint32_t *lcorners_only = malloc(sizeof(uint32_t) * li.chart_count);
        check(uvf_chart_layout_copy(layout, NULL, 0, NULL, 0, lcorners_only, li.chart_count) == UVF_OK &&
                  memcmp(lcorners_only, lcorners, sizeof(uint32_t) * li.chart_count) == 0,
              "chart layout copy skips NULL outputs");
        free(lcorners_only);
        size_t sum = 0;
        for (k = 0; k < li.polyline_count; k++) sum += lsizes[k];
        check(sum == li.point_count && li.four_corner_chart_count > 0 && li.four_corner_chart_count <= li.chart_count,
              "polyline sizes add up; the torus has four-cornered charts");
        free(lsizes);
        free(lpoints);
        free(lcorners);
        uvf_chart_layout_free(layout);
    }
    uvf_chart_layout_free(NULL);
    UvfPgpCharts *charts = NULL;
    status = uvf_pgp_charts(pgp, 1.0, &charts);
    check(status == UVF_OK && charts != NULL, "per-chart parameterization of a torus");
    if (charts != NULL) {
        UvfPgpChartsInfo ci;
        ci.struct_size = sizeof ci;
        check(uvf_pgp_charts_info(charts, &ci) == UVF_OK && ci.chart_count > 0 && ci.triangle_count > 0,
              "charts info");
        CHECK_OLD_LAYOUT(UvfPgpChartsInfo, vertex_count, kind_counts, uvf_pgp_charts_info(charts, report_));
        check(ci.kind_counts[UVF_PGP_CHART_ASSEMBLED] == ci.chart_count, "a torus without singularity is assembled");
        double *cpos = malloc(sizeof(double) * 3 * ci.vertex_count);
        uint32_t *ctri = malloc(sizeof(uint32_t) * 3 * ci.triangle_count);
        double *cuv = malloc(sizeof(double) * 6 * ci.triangle_count);
        uint32_t *cchart = malloc(sizeof(uint32_t) * ci.triangle_count);
        uint32_t *kinds = malloc(sizeof(uint32_t) * ci.chart_count);
        double *sizes = malloc(sizeof(double) * 2 * ci.chart_count);
        check(uvf_pgp_charts_copy(charts, cpos, 3 * ci.vertex_count, ctri, 3 * ci.triangle_count, cuv,
                                  6 * ci.triangle_count, cchart, ci.triangle_count, NULL, 0) == UVF_OK,
              "charts copy (origin skipped)");
        check(uvf_pgp_charts_copy(charts, NULL, 0, NULL, 0, cuv, 1, NULL, 0, NULL, 0) == UVF_INVALID_ARGUMENT,
              "a short uv output is rejected");
        check(uvf_pgp_charts_copy_charts(charts, kinds, ci.chart_count, NULL, 0, NULL, 0, sizes,
                                         2 * ci.chart_count) == UVF_OK,
              "charts copy per chart");
        int inside = 1;
        for (k = 0; k < 6 * ci.triangle_count; k++) {
            double w = sizes[2 * cchart[k / 6] + (k % 2)];
            if (cuv[k] < -1e-6 || cuv[k] > w + 1e-6 || ctri[k / 2] >= ci.vertex_count) inside = 0;
        }
        check(inside, "every (u, v) lies in its chart's extent");
        free(cpos);
        free(ctri);
        free(cuv);
        free(cchart);
        free(kinds);
        free(sizes);
        uvf_pgp_charts_free(charts);
    }
    uvf_pgp_charts_free(NULL);
    charts = NULL;
    check(uvf_pgp_charts(pgp, 0.5, &charts) == UVF_INVALID_ARGUMENT && charts == NULL, "a chart density below 1 is rejected");
    check(uvf_pgp_charts_info(NULL, NULL) == UVF_INVALID_ARGUMENT, "a NULL charts handle is rejected");
    check(uvf_pgp_info(NULL, &info) == UVF_INVALID_ARGUMENT, "NULL pgp handle is rejected");
    uvf_pgp_free(pgp);
    uvf_pgp_free(NULL);

    /* The caller's field: kmax directions with one NaN vector, named in the message. */
    for (k = 0; k < 3 * nv; k++) field[k] = kmax_dir[k];
    status = uvf_curvature(pos, nv, tris, nt, NULL, NULL, field, NULL, NULL);
    field[3 * 7] = NAN;
    options.field = field;
    corners[0] = 42.0;
    status = uvf_pgp(pos, nv, tris, nt, &options, corners, NULL);
    check(status == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "vertex 7") != NULL && corners[0] == 42.0,
          "a NaN field vector is named, output untouched");
    options.field = NULL;
    options.progress = cancel_pgp;
    status = uvf_pgp(pos, nv, tris, nt, &options, corners, NULL);
    check(status == UVF_CANCELLED && corners[0] == 42.0, "pgp cancels from the progress callback");
    options.progress = NULL;
    options.smoothing = 3;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_INVALID_ARGUMENT, "unknown smoothing");
    options.smoothing = UVF_SMOOTH_HALF_PI;
    options.untangle = 0;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "pgp without untangling");
    options.feature_periods = -1.0;
    status = uvf_pgp(pos, nv, tris, nt, &options, corners, NULL);
    check(status == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "feature_periods") != NULL,
          "a negative feature_periods is refused, naming it");
    options.feature_periods = 0.0;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "pgp with the paper's single omega");
    options.pair_periods = NAN;
    status = uvf_pgp(pos, nv, tris, nt, &options, corners, NULL);
    check(status == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "pair_periods") != NULL,
          "a NaN pair_periods is refused, naming it");
    options.pair_periods = 0.0;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "pgp without pair cancellation");
    options.dislocation_periods = -0.5;
    status = uvf_pgp(pos, nv, tris, nt, &options, corners, NULL);
    check(status == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "dislocation_periods") != NULL,
          "a negative dislocation_periods is refused, naming it");
    options.dislocation_periods = 0.0;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "pgp without dislocation annihilation");
    options.relax = 0;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "pgp without phase relaxation");
    /* Callers built before `relax` existed (fifth version) get its default. */
    options.struct_size = offsetof(UvfPgpOptions, relax);
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "fifth-version pgp options are accepted");
    /* Callers built before `dislocation_periods` existed (fourth version) get its default. */
    options.dislocation_periods = -1.0;
    options.struct_size = offsetof(UvfPgpOptions, dislocation_periods);
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "fourth-version pgp options are accepted");
    /* Callers built before `pair_periods` existed (third version) get its default. */
    options.pair_periods = -1.0;
    options.struct_size = offsetof(UvfPgpOptions, pair_periods);
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "third-version pgp options are accepted");
    /* Callers built before `feature_periods` existed (second version) get its default. */
    options.feature_periods = -1.0;
    options.struct_size = offsetof(UvfPgpOptions, feature_periods);
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "second-version pgp options are accepted");
    /* Callers built before `untangle` existed pass the first version's size and get the default. */
    options.struct_size = offsetof(UvfPgpOptions, untangle);
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_OK, "first-version pgp options are accepted");
    options.struct_size = offsetof(UvfPgpOptions, untangle) - 1;
    check(uvf_pgp(pos, nv, tris, nt, &options, corners, NULL) == UVF_INVALID_ARGUMENT, "too small options");
}

/* uvf_atlas: a torus becomes charts without flips, packed into the unit square; the handle's
 * accessors agree with each other; bad options and a cancelling callback are refused. */
/* A 16 x 8 torus: 128 vertices, 256 triangles. */
enum { AN = 16, AM = 8 };
static void torus(double *pos, uint32_t *tris) {
    int i, j, t = 0;
    for (i = 0; i < AN; i++)
        for (j = 0; j < AM; j++) {
            double u = 6.283185307179586 * i / AN, v = 6.283185307179586 * j / AM, r = 2.0 + cos(v);
            pos[3 * (i * AM + j)] = r * cos(u);
            pos[3 * (i * AM + j) + 1] = r * sin(u);
            pos[3 * (i * AM + j) + 2] = sin(v);
        }
    for (i = 0; i < AN; i++)
        for (j = 0; j < AM; j++) {
            uint32_t a = (uint32_t)(i * AM + j), b = (uint32_t)(((i + 1) % AN) * AM + j);
            uint32_t c = (uint32_t)(((i + 1) % AN) * AM + (j + 1) % AM), d = (uint32_t)(i * AM + (j + 1) % AM);
            uint32_t *q = tris + 6 * t++;
            q[0] = a; q[1] = b; q[2] = c; q[3] = a; q[4] = c; q[5] = d;
        }
}

static void check_atlas(void) {
    static double pos[3 * AN * AM], uv[2 * 8 * AN * AM], corner_uv[12 * AN * AM];
    static uint32_t tris[6 * AN * AM], uv_tris[6 * AN * AM], charts[2 * AN * AM], original[8 * AN * AM];
    UvfAtlasOptions options;
    UvfAtlasInfo info;
    info.struct_size = sizeof info;
    UvfAtlas *atlas = NULL;
    UvfMetrics metrics;
    metrics.struct_size = sizeof metrics;
    UvfStatus status;
    int calls = 0;
    size_t k;
    torus(pos, tris);
    uvf_atlas_options_default(&options);
    check(options.struct_size == sizeof options && options.max_stretch >= 1.0 && options.rotate == 1, "atlas defaults");
    options.max_stretch = 1.05;
    status = uvf_atlas(pos, AN * AM, tris, 2 * AN * AM, &options, &atlas);
    check(status == UVF_OK && atlas != NULL, "a torus becomes an atlas");
    if (atlas == NULL) return;
    check(uvf_atlas_info(atlas, &info) == UVF_OK && info.triangle_count == 2 * AN * AM, "atlas info");
    CHECK_OLD_LAYOUT(UvfAtlasInfo, vertex_count, max_chart_stretch, uvf_atlas_info(atlas, report_));
    check(info.chart_count >= 1 && info.max_chart_stretch <= 1.05 && info.stretch_l2 <= 1.05, "charts under the bound");
    check(info.utilization > 0.0 && info.utilization < 1.0, "utilization is a fraction");
    check(info.vertex_count <= 8 * AN * AM, "atlas vertices fit the test buffers");
    check(uvf_atlas_copy_uv(atlas, uv, 2 * info.vertex_count - 1) == UVF_INVALID_ARGUMENT, "small uv capacity");
    check(uvf_atlas_copy_uv(atlas, uv, 2 * info.vertex_count) == UVF_OK, "copy uv");
    check(uvf_atlas_copy_triangles(atlas, uv_tris, 3 * info.triangle_count) == UVF_OK, "copy uv triangles");
    check(uvf_atlas_copy_corner_uv(atlas, corner_uv, 6 * info.triangle_count) == UVF_OK, "copy corner uv");
    check(uvf_atlas_copy_charts(atlas, charts, info.triangle_count) == UVF_OK, "copy charts");
    check(uvf_atlas_copy_original_vertices(atlas, original, info.vertex_count) == UVF_OK, "copy original vertices");
    for (k = 0; k < 3 * info.triangle_count; k++) {
        check(original[uv_tris[k]] == tris[k], "every atlas corner maps back to its input vertex");
        check(corner_uv[2 * k] == uv[2 * uv_tris[k]] && corner_uv[2 * k + 1] == uv[2 * uv_tris[k] + 1], "corner uv");
    }
    for (k = 0; k < 2 * info.vertex_count; k++) check(uv[k] >= 0.0 && uv[k] <= 1.0, "uv in the unit square");
    for (k = 0; k < info.triangle_count; k++) check(charts[k] < info.chart_count, "chart ids in range");
    status = uvf_metrics(pos, AN * AM, tris, info.triangle_count, uv, info.vertex_count, uv_tris, &metrics);
    check(status == UVF_OK && metrics.flipped == 0 && metrics.boundary_intersections == 0, "atlas flips nothing");
    uvf_atlas_free(atlas);
    uvf_atlas_free(NULL);
    check(uvf_atlas_info(NULL, &info) == UVF_INVALID_ARGUMENT, "NULL atlas handle is rejected");
    atlas = NULL;
    options.max_stretch = 0.5;
    status = uvf_atlas(pos, AN * AM, tris, 2 * AN * AM, &options, &atlas);
    check(status == UVF_INVALID_ARGUMENT && atlas == NULL, "max_stretch < 1 is rejected");
    check(strlen(uvf_last_error_message()) > 0, "and says why");
    uvf_atlas_options_default(&options);
    options.progress = cancel_first;
    options.progress_user = &calls;
    status = uvf_atlas(pos, AN * AM, tris, 2 * AN * AM, &options, &atlas);
    check(status == UVF_CANCELLED && atlas == NULL && calls == 1, "atlas progress callback cancels");
}

/* The default unwrap: verified layout, seams, report written only up to its struct_size. */
static void check_unwrap(void) {
    static double pos[3 * AN * AM], uv[2 * 8 * AN * AM];
    static uint32_t tris[6 * AN * AM], uv_tris[6 * AN * AM], seams[6 * AN * AM];
    static unsigned char old_report[sizeof(UvfUnwrapReport) + 16];
    const size_t cut = offsetof(UvfUnwrapReport, seam_edges);
    UvfUnwrapOptions options;
    UvfUnwrapReport report;
    UvfUnwrapReport *old = (UvfUnwrapReport *)(void *)old_report;
    UvfUnwrap *result = NULL;
    const UvfAtlas *layout = NULL;
    UvfAtlasInfo info;
    info.struct_size = sizeof info;
    UvfMetrics metrics;
    metrics.struct_size = sizeof metrics;
    UvfStatus status;
    size_t k;
    int calls = 0, untouched = 1;
    torus(pos, tris);
    uvf_unwrap_options_default(&options);
    check(options.struct_size == sizeof options && options.max_stretch == 1.5 && options.rotate == 1, "unwrap defaults");
    status = uvf_unwrap(pos, AN * AM, tris, 2 * AN * AM, &options, &result);
    check(status == UVF_OK && result != NULL, "a torus unwraps");
    if (result == NULL) return;
    report.struct_size = sizeof report;
    check(uvf_unwrap_report(result, &report) == UVF_OK, "unwrap report");
    CHECK_OLD_LAYOUT(UvfUnwrapReport, islands, utilization, uvf_unwrap_report(result, report_));
    check(report.flipped == 0 && report.overlaps == 0 && report.islands >= 1, "verified: no flip, no overlap");
    check(report.max_island_stretch <= 1.5 && report.seam_edges > 0, "islands under the bound, the torus is cut");
    check(uvf_unwrap_atlas(result, &layout) == UVF_OK && layout != NULL, "the layout as an atlas handle");
    check(uvf_atlas_info(layout, &info) == UVF_OK && info.chart_count == report.islands, "atlas info agrees");
    check(info.vertex_count == report.uv_vertex_count && info.vertex_count <= 8 * AN * AM, "uv vertex count");
    check(uvf_atlas_copy_uv(layout, uv, 2 * info.vertex_count) == UVF_OK, "copy the layout's uv");
    check(uvf_atlas_copy_triangles(layout, uv_tris, 3 * info.triangle_count) == UVF_OK, "copy its corners");
    status = uvf_metrics(pos, AN * AM, tris, info.triangle_count, uv, info.vertex_count, uv_tris, &metrics);
    check(status == UVF_OK && metrics.flipped == 0 && metrics.boundary_intersections == 0, "metrics agree: no flip");
    check(uvf_unwrap_copy_seams(result, seams, 2 * report.seam_edges - 1) == UVF_INVALID_ARGUMENT, "small seams capacity");
    check(uvf_unwrap_copy_seams(result, seams, 2 * report.seam_edges) == UVF_OK, "copy seams");
    for (k = 0; k < report.seam_edges; k++)
        check(seams[2 * k] < seams[2 * k + 1] && seams[2 * k + 1] < AN * AM, "seams are vertex pairs a < b");
    /* A caller built against a shorter report: nothing past its struct_size is written. */
    memset(old_report, 0xAB, sizeof old_report);
    old->struct_size = cut;
    check(uvf_unwrap_report(result, old) == UVF_OK && old->islands == report.islands, "an older, shorter report");
    for (k = cut; k < sizeof old_report; k++) untouched &= old_report[k] == 0xAB;
    check(untouched, "no byte past the caller's struct_size is touched");
    old->struct_size = 4;
    check(uvf_unwrap_report(result, old) == UVF_INVALID_ARGUMENT, "a struct_size below the first fields is refused");
    uvf_unwrap_free(result);
    uvf_unwrap_free(NULL);
    check(uvf_unwrap_report(NULL, &report) == UVF_INVALID_ARGUMENT, "NULL unwrap handle is rejected");
    /* Without a stretch bound the torus is one island. */
    result = NULL;
    options.max_stretch = INFINITY;
    check(uvf_unwrap(pos, AN * AM, tris, 2 * AN * AM, &options, &result) == UVF_OK, "unwrap without a bound");
    check(result != NULL && uvf_unwrap_report(result, &report) == UVF_OK && report.islands == 1, "one island");
    uvf_unwrap_free(result);
    result = NULL;
    options.max_stretch = 0.5;
    check(uvf_unwrap(pos, AN * AM, tris, 2 * AN * AM, &options, &result) == UVF_INVALID_ARGUMENT && result == NULL,
          "max_stretch < 1 is rejected");
    uvf_unwrap_options_default(&options);
    options.progress = cancel_first;
    options.progress_user = &calls;
    status = uvf_unwrap(pos, AN * AM, tris, 2 * AN * AM, &options, &result);
    check(status == UVF_CANCELLED && result == NULL && calls == 1, "unwrap progress callback cancels");
}

/* uvf_status_string, uvf_last_error and the message's lifetime across successful calls. */
static void check_status_strings_and_error_copies(const double *positions, size_t nv, const uint32_t *triangles) {
    static const uint32_t bad_triangle[3] = {0, 1, 100000};
    char buffer[256], tiny[8];
    const char *message;
    size_t length;
    UvfMeshInfo info;
    info.struct_size = sizeof info;
    check(strcmp(uvf_status_string(UVF_OK), "success") == 0, "status string of UVF_OK");
    check(strcmp(uvf_status_string(UVF_INVALID_MESH), "invalid mesh") == 0, "status string of UVF_INVALID_MESH");
    check(strcmp(uvf_status_string(12345), "unknown uvflat status") == 0, "status string of an unknown code");
    check(strcmp(uvf_status_string(-1), "unknown uvflat status") == 0, "status string of a negative code");
    check(uvf_mesh_info(positions, nv, bad_triangle, 1, &info) == UVF_INVALID_MESH, "a bad index is refused");
    message = uvf_last_error_message();
    length = uvf_last_error(buffer, sizeof buffer);
    check(length == strlen(buffer) && length > 0 && strstr(buffer, "100000") != NULL, "the error copied in full");
    check(uvf_last_error(tiny, sizeof tiny) == length && strlen(tiny) == sizeof tiny - 1 &&
              strncmp(tiny, buffer, sizeof tiny - 1) == 0,
          "a short buffer gets a NUL-terminated prefix and the full length");
    check(uvf_last_error(NULL, 0) == length, "the length alone");
    check(uvf_mesh_info(positions, nv, triangles, 1, &info) == UVF_OK, "a valid call");
    check(strcmp(uvf_last_error_message(), "") == 0 && uvf_last_error(buffer, sizeof buffer) == 0 && buffer[0] == 0,
          "no message after a success");
    check(strstr(message, "100000") != NULL, "the failed call's message pointer survives a successful call");
}

int main(void) {
    static double positions[3 * N * N];
    static uint32_t triangles[6 * (N - 1) * (N - 1)];
    static double uv[2 * N * N];
    const size_t nv = N * N, nt = 2 * (N - 1) * (N - 1);
    UvfMeshInfo info;
    info.struct_size = sizeof info;
    UvfMetrics metrics;
    metrics.struct_size = sizeof metrics;
    UvfFixedBoundaryOptions fixed;
    UvfNaturalConformalOptions conformal;
    UvfStatus status;
    int calls = 0;
    uint32_t saved;

    bent_grid(positions, triangles);
    check(uvf_abi_version() == UVF_ABI_VERSION, "ABI version matches the header");
    check(strlen(uvf_version()) > 0, "version string");
    check(strcmp(uvf_version(), UVF_VERSION_STRING) == 0 && uvf_version_number() == UVF_VERSION_NUMBER,
          "the library's version is the header's");
    check_status_strings_and_error_copies(positions, nv, triangles);
    check(uvf_thread_count() >= 1, "at least one worker thread");
    check(uvf_set_thread_count(2) == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "already") != NULL,
          "the thread count cannot change once the workers exist");

    status = uvf_mesh_info(positions, nv, triangles, nt, &info);
    CHECK_OLD_LAYOUT(UvfMeshInfo, vertices, genus, uvf_mesh_info(positions, nv, triangles, nt, report_));
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

    check_topology_queries(positions, nv, triangles, nt);
    check_options_and_counts(positions, nv, triangles, nt, uv);
    check_corner_metrics(positions, nv, triangles, nt, uv);
    check_nonlinear(positions, nv, triangles, nt, uv);
    check_intrinsic_tools(positions, nv, triangles, nt, uv);
    check_abf(positions, nv, triangles, nt, uv);
    check_intrinsic_optimization(positions, nv, triangles, nt, uv);
    check_closed_surfaces();
    check_pgp();
    check_atlas();
    check_unwrap();

    if (failures == 0) printf("all C checks passed\n");
    return failures == 0 ? 0 : 1;
}
