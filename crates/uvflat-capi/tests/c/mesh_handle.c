/* The mesh handle as a DCC tool feeds it: float positions inside a 32-byte vertex struct (as
 * Blender and game engines hold them), quads and one convex 8-gon, uint16 and uint32 indices.
 * The handle's UVs must equal those of the flat-array call on the same mesh given as packed
 * doubles and triangles this program makes itself (fans; every face here is convex), to 1e-9;
 * the handle's triangulation must be that fan, the per-face-corner UVs must be the
 * per-triangle-corner UVs of the same corners, and bad descriptions must be refused.
 * Built and run by crates/uvflat-capi/tests/it/c_abi.rs. */
#include "uvflat.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define GX 9 /* vertices per row of the quad grid */
#define GY 7
#define RIM 6 /* vertices of the n-gon besides its edge on the grid */
#define NV (GX * GY + RIM)
#define MAX_CORNERS (4 * (GX - 1) * (GY - 1) + 2 + RIM)
#define MAX_TRIANGLES (2 * (GX - 1) * (GY - 1) + RIM)

typedef struct {
    float co[3];
    float normal[3];
    uint32_t flags;
    uint32_t pad;
} Vertex;

static int failures = 0;

static void check(int ok, const char *what) {
    if (!ok) {
        char message[512];
        uvf_last_error(message, sizeof message);
        fprintf(stderr, "FAILED: %s (last error: %s)\n", what, message);
        failures++;
    }
}

static Vertex vertices[NV];
static uint32_t corners32[MAX_CORNERS];
static uint16_t corners16[2 * MAX_CORNERS]; /* every other slot: a stride of 4 bytes */
static uint32_t face_sizes[(GX - 1) * (GY - 1) + 1];
static size_t face_count, corner_count;

/* A bent grid of quads, and a half-disk 8-gon above its last top edge. */
static void build(void) {
    int i, j, k;
    for (j = 0; j < GY; j++)
        for (i = 0; i < GX; i++) {
            Vertex *v = &vertices[j * GX + i];
            float x = (float)i / (GX - 1), y = (float)j / (GY - 1);
            v->co[0] = x;
            v->co[1] = y;
            v->co[2] = 0.25f * sinf(3.0f * x) * cosf(2.0f * y);
            v->flags = 0xdeadbeef;
        }
    { /* a half-disk above the grid's last top edge: the arc from its right end back to the left */
        const Vertex *a = &vertices[GY * GX - 2], *b = &vertices[GY * GX - 1];
        double cx = 0.5 * (a->co[0] + b->co[0]), r = 0.5 * (b->co[0] - a->co[0]);
        for (k = 0; k < RIM; k++) {
            double angle = 3.14159265358979 * (k + 1) / (RIM + 1), s = 0.5 + 0.5 * cos(angle);
            Vertex *v = &vertices[GX * GY + k];
            v->co[0] = (float)(cx + r * cos(angle));
            v->co[1] = (float)(1.0 + r * sin(angle));
            v->co[2] = (float)(a->co[2] + s * (b->co[2] - a->co[2]));
            v->flags = 0xdeadbeef;
        }
    }
    face_count = corner_count = 0;
    for (j = 0; j + 1 < GY; j++)
        for (i = 0; i + 1 < GX; i++) {
            uint32_t a = (uint32_t)(j * GX + i);
            uint32_t quad[4] = {a, a + 1, a + 1 + GX, a + GX};
            for (k = 0; k < 4; k++) corners32[corner_count++] = quad[k];
            face_sizes[face_count++] = 4;
        }
    /* The n-gon: the edge left to right, then the arc right to left (counter-clockwise). */
    corners32[corner_count++] = (uint32_t)(GY * GX - 2);
    corners32[corner_count++] = (uint32_t)(GY * GX - 1);
    for (k = 0; k < RIM; k++) corners32[corner_count++] = (uint32_t)(GX * GY + k);
    face_sizes[face_count++] = 2 + RIM;
    for (k = 0; k < (int)corner_count; k++) {
        corners16[2 * k] = (uint16_t)corners32[k];
        corners16[2 * k + 1] = 0xffff; /* never read: the stride skips it */
    }
}

/* uvf_polygon_islands on the quads and the n-gon: a seam down the grid's middle column of edges
 * makes two islands; with the left half unselected only the right one is left; every corner of
 * one island and one mesh vertex shares one island vertex, and bad input is refused. */
static void check_polygon_islands(void) {
    static uint8_t seams[MAX_CORNERS], selected[MAX_TRIANGLES];
    static uint32_t face_island[MAX_TRIANGLES], corner_vertex[MAX_CORNERS];
    static size_t face_of[MAX_CORNERS];
    UvfPolygonIslandsInfo info;
    size_t c, d, f, start = 0, mid = GX / 2;
    int consistent = 1;
    memset(seams, 0, sizeof seams);
    for (f = 0; f + 1 < face_count; f++) /* the quads' left edge (corner 3 → 0) on column mid */
        if (corners32[4 * f] % GX == mid) seams[4 * f + 3] = 1;
    info.struct_size = sizeof info;
    check(uvf_polygon_islands(corners32, corner_count, NV, face_sizes, face_count, NULL, seams, face_island,
                              corner_vertex, &info) == UVF_OK,
          "polygon islands");
    check(info.islands == 2 && info.non_manifold_edges == 0 && info.misoriented_edges == 0, "a seam column: two islands");
    /* The middle column's vertices are doubled, the rest are one each. */
    check(info.island_vertices == NV + GY, "the seam doubles its column's vertices");
    for (f = 0; f < face_count; f++) {
        for (c = start; c < start + face_sizes[f]; c++) face_of[c] = f;
        start += face_sizes[f];
    }
    for (c = 0; c < corner_count; c++)
        for (d = 0; d < corner_count; d++) {
            int same_vertex = corners32[c] == corners32[d];
            int same_island = face_island[face_of[c]] == face_island[face_of[d]];
            int shared = corner_vertex[c] == corner_vertex[d];
            if (shared && !(same_vertex && same_island)) consistent = 0;
            if (same_vertex && same_island && corners32[c] % GX != mid && !shared) consistent = 0;
        }
    check(consistent, "corners share an island vertex exactly when they share a mesh vertex and an island (off the seam)");
    for (f = 0; f < face_count; f++) selected[f] = f + 1 == face_count || corners32[4 * f] % GX >= mid;
    check(uvf_polygon_islands(corners32, corner_count, NV, face_sizes, face_count, selected, NULL, face_island,
                              corner_vertex, &info) == UVF_OK &&
              info.islands == 1 && face_island[0] == UVF_NOT_IN_AN_ISLAND && corner_vertex[0] == UVF_NOT_IN_AN_ISLAND,
          "the selection border cuts; unselected faces are in no island");
    face_island[0] = 7;
    check(uvf_polygon_islands(corners32, corner_count, NV - 1, face_sizes, face_count, NULL, NULL, face_island,
                              corner_vertex, &info) == UVF_INVALID_ARGUMENT &&
              strstr(uvf_last_error_message(), "vertices") != NULL && face_island[0] == 7,
          "a vertex index past vertex_count is refused, outputs untouched");
    check(uvf_polygon_islands(corners32, corner_count, NV, NULL, face_count, NULL, NULL, face_island, corner_vertex,
                              &info) == UVF_INVALID_ARGUMENT,
          "NULL face sizes means triangles: the counts must agree");
    check(uvf_polygon_islands(corners32, corner_count, NV, face_sizes, face_count, NULL, NULL, NULL, corner_vertex,
                              &info) == UVF_INVALID_ARGUMENT,
          "NULL output");
    info.struct_size = 0;
    check(uvf_polygon_islands(corners32, corner_count, NV, face_sizes, face_count, NULL, NULL, face_island,
                              corner_vertex, &info) == UVF_INVALID_ARGUMENT,
          "unset struct_size");
}

int main(void) {
    static double packed[3 * NV], uv_flat[2 * NV], uv_handle[2 * NV], uv16[2 * NV];
    static uint32_t fan[3 * MAX_TRIANGLES], handle_triangles[3 * MAX_TRIANGLES], faces[MAX_TRIANGLES];
    static double corner_uv[6 * MAX_TRIANGLES], face_corner_uv[2 * MAX_CORNERS];
    size_t nt = 0, start = 0, f, k, v;
    double worst = 0.0;
    UvfMeshDesc desc;
    UvfMesh *mesh = NULL, *mesh16 = NULL, *bad = NULL;
    UvfMeshInfo info;
    UvfUnwrap *unwrap = NULL;
    const UvfAtlas *layout = NULL;
    int same = 1;

    build();
    check_polygon_islands();
    /* The caller's own triangulation: fans, and packed doubles. */
    for (f = 0; f < face_count; f++) {
        for (k = 1; k + 1 < face_sizes[f]; k++) {
            fan[3 * nt] = corners32[start];
            fan[3 * nt + 1] = corners32[start + k];
            fan[3 * nt + 2] = corners32[start + k + 1];
            faces[nt++] = (uint32_t)f;
        }
        start += face_sizes[f];
    }
    for (v = 0; v < NV; v++)
        for (k = 0; k < 3; k++) packed[3 * v + k] = (double)vertices[v].co[k];

    uvf_mesh_desc_default(&desc);
    check(desc.struct_size == sizeof desc && desc.position_type == UVF_SCALAR_DOUBLE &&
              desc.index_type == UVF_INDEX_UINT32 && desc.face_sizes == NULL,
          "description defaults");
    desc.positions = vertices[0].co;
    desc.position_type = UVF_SCALAR_FLOAT;
    desc.position_stride = sizeof(Vertex);
    desc.vertex_count = NV;
    desc.indices = corners32;
    desc.face_sizes = face_sizes;
    desc.face_count = face_count;
    check(uvf_mesh_new(&desc, &mesh) == UVF_OK && mesh != NULL, "a float, strided, polygon mesh is accepted");
    if (mesh == NULL) return 1;

    info.struct_size = sizeof info;
    check(uvf_mesh_handle_info(mesh, &info) == UVF_OK && info.triangles == nt && info.vertices == NV &&
              info.boundary_loops == 1 && info.genus == 0,
          "handle info: the triangulation's counts, a disk");
    check(uvf_mesh_copy_triangles(mesh, handle_triangles, 3 * nt) == UVF_OK &&
              memcmp(handle_triangles, fan, 3 * nt * sizeof *fan) == 0,
          "convex faces are triangulated as fans");
    check(uvf_mesh_copy_triangles(mesh, handle_triangles, 3 * nt - 1) == UVF_INVALID_ARGUMENT, "small capacity");
    check(uvf_mesh_copy_triangle_faces(mesh, handle_triangles, nt) == UVF_OK &&
              memcmp(handle_triangles, faces, nt * sizeof *faces) == 0,
          "the face of every triangle");

    /* Natural conformal map: the handle against the flat call. */
    check(uvf_natural_conformal_map(packed, NV, fan, nt, NULL, uv_flat) == UVF_OK, "flat natural conformal map");
    check(uvf_mesh_natural_conformal_map(mesh, NULL, uv_handle) == UVF_OK, "handle natural conformal map");
    for (k = 0; k < 2 * NV; k++) worst = fmax(worst, fabs(uv_flat[k] - uv_handle[k]));
    check(worst <= 1e-9, "the handle's UVs equal the flat call's");
    printf("natural conformal: largest difference %.3g\n", worst);

    /* The same with uint16 indices at a stride of 4 bytes. */
    desc.indices = corners16;
    desc.index_type = UVF_INDEX_UINT16;
    desc.index_stride = 2 * sizeof(uint16_t);
    check(uvf_mesh_new(&desc, &mesh16) == UVF_OK, "uint16 indices with a stride");
    check(uvf_mesh_natural_conformal_map(mesh16, NULL, uv16) == UVF_OK, "uint16 natural conformal map");
    check(memcmp(uv16, uv_handle, sizeof uv16) == 0, "uint16 and uint32 indices give the same UVs");
    uvf_mesh_free(mesh16);

    /* The other methods that take a handle agree with their flat calls too. */
    check(uvf_fixed_boundary_map(packed, NV, fan, nt, NULL, uv_flat) == UVF_OK &&
              uvf_mesh_fixed_boundary_map(mesh, NULL, uv_handle) == UVF_OK && memcmp(uv_flat, uv_handle, sizeof uv_flat) == 0,
          "fixed boundary map: handle = flat");
    check(uvf_abf(packed, NV, fan, nt, NULL, uv_flat, NULL) == UVF_OK && uvf_mesh_abf(mesh, NULL, uv_handle, NULL) == UVF_OK &&
              memcmp(uv_flat, uv_handle, sizeof uv_flat) == 0,
          "ABF++: handle = flat");
    check(uvf_nonlinear_map(packed, NV, fan, nt, NULL, uv_flat, NULL) == UVF_OK &&
              uvf_mesh_nonlinear_map(mesh, NULL, uv_handle, NULL) == UVF_OK && memcmp(uv_flat, uv_handle, sizeof uv_flat) == 0,
          "SLIM: handle = flat");

    {
        UvfMetrics flat_metrics, handle_metrics;
        static uint32_t flat_loop[NV], handle_loop[NV], flat_offsets[2], handle_offsets[2];
        flat_metrics.struct_size = handle_metrics.struct_size = sizeof flat_metrics;
        check(uvf_spectral_conformal_map(packed, NV, fan, nt, NULL, uv_flat, NULL) == UVF_OK &&
                  uvf_mesh_spectral_conformal_map(mesh, NULL, uv_handle, NULL) == UVF_OK &&
                  memcmp(uv_flat, uv_handle, sizeof uv_flat) == 0,
              "spectral conformal map: handle = flat");
        check(uvf_circle_pattern_map(packed, NV, fan, nt, NULL, uv_flat, NULL) == UVF_OK &&
                  uvf_mesh_circle_pattern_map(mesh, NULL, uv_handle, NULL) == UVF_OK &&
                  memcmp(uv_flat, uv_handle, sizeof uv_flat) == 0,
              "circle patterns: handle = flat");
        check(uvf_metrics(packed, NV, fan, nt, uv_flat, NV, NULL, &flat_metrics) == UVF_OK &&
                  uvf_mesh_metrics(mesh, uv_flat, NV, NULL, &handle_metrics) == UVF_OK &&
                  flat_metrics.stretch_l2 == handle_metrics.stretch_l2 &&
                  flat_metrics.angle_mean == handle_metrics.angle_mean && handle_metrics.flipped == 0,
              "metrics: handle = flat");
        check(uvf_boundary_loops(packed, NV, fan, nt, flat_loop, NV, flat_offsets, 2) == UVF_OK &&
                  uvf_mesh_boundary_loops(mesh, handle_loop, NV, handle_offsets, 2) == UVF_OK &&
                  flat_offsets[1] == handle_offsets[1] &&
                  memcmp(flat_loop, handle_loop, flat_offsets[1] * sizeof *flat_loop) == 0,
              "boundary loops: handle = flat");
    }

    /* The default unwrap, its per-triangle-corner layout mapped back to the faces' corners. */
    check(uvf_mesh_unwrap(mesh, NULL, &unwrap) == UVF_OK && uvf_unwrap_atlas(unwrap, &layout) == UVF_OK,
          "handle unwrap");
    check(uvf_atlas_copy_corner_uv(layout, corner_uv, 6 * nt) == UVF_OK, "its corner UVs");
    check(uvf_mesh_face_corner_uv(mesh, corner_uv, 6 * nt - 1, face_corner_uv, 2 * corner_count) == UVF_INVALID_ARGUMENT,
          "a corner UV count that does not match the triangles is refused");
    check(uvf_mesh_face_corner_uv(mesh, corner_uv, 6 * nt, face_corner_uv, 2 * corner_count) == UVF_OK,
          "per-face-corner UVs");
    for (start = 0, nt = 0, f = 0; f < face_count; f++) { /* corner k of a fan triangle is a face corner */
        for (k = 1; k + 1 < face_sizes[f]; k++, nt++) {
            size_t tri_corner[3] = {start, start + k, start + k + 1}, c;
            for (c = 0; c < 3; c++)
                same &= face_corner_uv[2 * tri_corner[c]] == corner_uv[6 * nt + 2 * c] &&
                        face_corner_uv[2 * tri_corner[c] + 1] == corner_uv[6 * nt + 2 * c + 1];
        }
        start += face_sizes[f];
    }
    check(same, "every face corner has the UV of its triangles' corners (one island, no seam inside a face)");
    uvf_unwrap_free(unwrap);

    /* Bad descriptions. */
    desc.indices = corners32;
    desc.index_type = UVF_INDEX_UINT32;
    desc.index_stride = 0;
    face_sizes[3] = 2;
    check(uvf_mesh_new(&desc, &bad) == UVF_INVALID_ARGUMENT && bad == NULL, "a face of 2 corners is refused");
    face_sizes[3] = 4;
    desc.position_stride = 8;
    check(uvf_mesh_new(&desc, &bad) == UVF_INVALID_ARGUMENT, "a stride shorter than a vertex is refused");
    desc.position_stride = sizeof(Vertex);
    desc.position_type = 7;
    check(uvf_mesh_new(&desc, &bad) == UVF_INVALID_ARGUMENT, "an unknown position type is refused");
    desc.position_type = UVF_SCALAR_FLOAT;
    corners32[5] = NV + 3;
    check(uvf_mesh_new(&desc, &bad) == UVF_INVALID_ARGUMENT && strstr(uvf_last_error_message(), "face 1") != NULL,
          "an index past the vertices names its face");
    corners32[5] = corners32[4];
    check(uvf_mesh_new(&desc, &bad) == UVF_INVALID_MESH && strstr(uvf_last_error_message(), "face 1") != NULL,
          "a repeated vertex names its face");
    check(uvf_mesh_new(NULL, &bad) == UVF_INVALID_ARGUMENT && bad == NULL, "NULL description");
    check(uvf_mesh_natural_conformal_map(NULL, NULL, uv_handle) == UVF_INVALID_ARGUMENT, "NULL handle");
    uvf_mesh_free(mesh);
    uvf_mesh_free(NULL);

    if (failures) return 1;
    printf("all mesh handle checks passed\n");
    return 0;
}
