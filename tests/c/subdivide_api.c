/*
 * Subdivision through the C ABI (C99): katachi_subdivide and its result handle, options,
 * vertex and face-varying data, stencils, face origins, faces with holes, and bad input.
 */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "shapes.h"

static KatachiMesh *make_cube(void)
{
    KatachiMesh *m = NULL;
    katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6,
                        CUBE_CORNERS, 24, &m);
    return m;
}

static void test_cube(void)
{
    KatachiMesh *cube = make_cube();
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *s = NULL;
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    KatachiMesh *out = NULL;
    KatachiMeshCounts counts = katachi_mesh_counts_default();
    double pos[26 * 3];
    uint32_t origin[24];
    size_t i;
    int origin_ok = 1;

    CHECK("defaults: 1 level, method [a], edge-only, uniform",
          o.levels == 1 && o.holes == KATACHI_HOLE_METHOD_SMOOTH &&
              o.boundary == KATACHI_BOUNDARY_EDGE_ONLY &&
              o.crease_method == KATACHI_CREASE_METHOD_UNIFORM);
    CHECK_OK("subdivide the cube", katachi_subdivide(cube, &o, &s));
    CHECK_OK("info", katachi_subdivision_info(s, &info));
    CHECK("26 vertices, 24 faces, 96 corners",
          info.vertex_count == 26 && info.face_count == 24 && info.corner_count == 96);
    CHECK("input counts", info.input_vertex_count == 8 && info.input_corner_count == 24);
    CHECK("no fallback", info.fallback_face_count == 0);
    CHECK_OK("result mesh", katachi_subdivision_mesh(s, &out));
    CHECK_OK("counts", katachi_mesh_counts(out, &counts));
    CHECK("result counts", counts.vertex_count == 26 && counts.face_count == 24);
    CHECK_OK("positions", katachi_mesh_copy_positions(out, pos, 26 * 3));
    /* Corner 7 = (0.5, 0.5, 0.5) goes to 5/9 of itself (seed 001 eq. (2)). */
    CHECK("corner vertex point is 5/9 (1/2, 1/2, 1/2)", fabs(pos[7 * 3] - 5.0 / 18.0) < 1e-15);
    CHECK_OK("face origin", katachi_subdivision_copy_face_origin(s, origin, 24));
    for (i = 0; i < 24; i++) {
        origin_ok = origin_ok && origin[i] == i / 4;
    }
    CHECK("each input face gives 4 result faces, in order", origin_ok);

    {
        /* Vertex data: the positions themselves, refined as data, equal the result. */
        double data[26 * 3];
        int same = 1;
        CHECK_OK("refine vertex data", katachi_subdivision_refine_vertex_data(
                                           s, CUBE_POSITIONS, 24, 3, data, 26 * 3));
        for (i = 0; i < 26 * 3; i++) {
            same = same && fabs(data[i] - pos[i]) < 1e-15;
        }
        CHECK("vertex data follow the positions", same);
        CHECK_ERR("wrong value count",
                  katachi_subdivision_refine_vertex_data(s, CUBE_POSITIONS, 23, 3, data, 78),
                  KATACHI_STATUS_INVALID_ARGUMENT, "8 vertices");
        CHECK_ERR("zero components",
                  katachi_subdivision_refine_vertex_data(s, CUBE_POSITIONS, 24, 0, data, 78),
                  KATACHI_STATUS_INVALID_ARGUMENT, "components");
        CHECK_ERR("short output",
                  katachi_subdivision_refine_vertex_data(s, CUBE_POSITIONS, 24, 3, data, 10),
                  KATACHI_STATUS_BUFFER_TOO_SMALL, "78");
        CHECK_ERR("NULL values",
                  katachi_subdivision_refine_vertex_data(s, NULL, 24, 3, data, 78),
                  KATACHI_STATUS_NULL_POINTER, "values");
    }
    {
        /* Face-varying: one UV per corner; bilinear keeps the corners' values at vertex
         * children and averages elsewhere. */
        double uv[24 * 2];
        uint32_t idx[24];
        double out_uv[96 * 2];
        for (i = 0; i < 24; i++) {
            uv[2 * i] = (double)(i % 4 == 1 || i % 4 == 2);
            uv[2 * i + 1] = (double)(i % 4 >= 2);
            idx[i] = (uint32_t)i;
        }
        CHECK_OK("refine UVs, linear all",
                 katachi_subdivision_refine_face_varying(s, uv, 48, 2, idx, 24,
                                                         KATACHI_FACE_VARYING_LINEAR_ALL,
                                                         out_uv, 96 * 2));
        /* Child 0 of face 0 starts at its parent corner 0: (0,0); its face point is (0.5,0.5). */
        CHECK("bilinear corner value kept", out_uv[0] == 0.0 && out_uv[1] == 0.0);
        CHECK("bilinear face centre", out_uv[4] == 0.5 && out_uv[5] == 0.5);
        CHECK_OK("refine UVs, smooth",
                 katachi_subdivision_refine_face_varying(s, uv, 48, 2, idx, 24,
                                                         KATACHI_FACE_VARYING_SMOOTH, out_uv,
                                                         96 * 2));
        CHECK_ERR("bad mode",
                  katachi_subdivision_refine_face_varying(s, uv, 48, 2, idx, 24, 9, out_uv, 192),
                  KATACHI_STATUS_INVALID_ARGUMENT, "mode");
        idx[5] = 99;
        CHECK_ERR("index out of range",
                  katachi_subdivision_refine_face_varying(s, uv, 48, 2, idx, 24,
                                                          KATACHI_FACE_VARYING_LINEAR_ALL,
                                                          out_uv, 192),
                  KATACHI_STATUS_INVALID_ARGUMENT, "corner 5");
        CHECK_ERR("index count",
                  katachi_subdivision_refine_face_varying(s, uv, 48, 2, idx, 23,
                                                          KATACHI_FACE_VARYING_LINEAR_ALL,
                                                          out_uv, 192),
                  KATACHI_STATUS_BAD_INPUT, "face corner");
    }
    {
        /* Stencils: applying them to the input positions gives the result positions. */
        uint32_t *offsets = malloc(27 * sizeof *offsets);
        uint32_t *sources = malloc(info.stencil_entry_count * sizeof *sources);
        double *weights = malloc(info.stencil_entry_count * sizeof *weights);
        int same = 1;
        CHECK("stencils have entries", info.stencil_entry_count >= 26);
        CHECK_OK("copy stencils",
                 katachi_subdivision_copy_stencils(s, offsets, 27, sources,
                                                   info.stencil_entry_count, weights,
                                                   info.stencil_entry_count));
        for (i = 0; i < 26; i++) {
            double x = 0;
            uint32_t k;
            for (k = offsets[i]; k < offsets[i + 1]; k++) {
                x += weights[k] * CUBE_POSITIONS[3 * sources[k]];
            }
            same = same && fabs(x - pos[3 * i]) < 1e-15;
        }
        CHECK("stencils reproduce the positions", same);
        CHECK_ERR("short stencil buffer",
                  katachi_subdivision_copy_stencils(s, offsets, 3, sources,
                                                    info.stencil_entry_count, weights,
                                                    info.stencil_entry_count),
                  KATACHI_STATUS_BUFFER_TOO_SMALL, "offsets");
        free(offsets);
        free(sources);
        free(weights);
    }
    {
        uint32_t none[1];
        CHECK_OK("no fallback faces", katachi_subdivision_copy_fallback_faces(s, none, 0));
    }
    katachi_mesh_free(out);
    katachi_subdivision_free(s);
    katachi_mesh_free(cube);
}

static void test_plate_with_holes(void)
{
    KatachiMesh *plate = NULL;
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *s = NULL;
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    CHECK_OK("create the plate", katachi_mesh_create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12,
                                                     PLATE_FACE_LOOP_COUNTS, 10, PLATE_CORNERS,
                                                     48, &plate));
    o.holes = KATACHI_HOLE_METHOD_SHARP;
    o.levels = 2;
    CHECK_OK("subdivide with method [b]", katachi_subdivide(plate, &o, &s));
    CHECK_OK("info", katachi_subdivision_info(s, &info));
    /* Two kept faces plus 8 quads × 16. */
    CHECK("faces with holes stay whole", info.face_count == 2 + 8 * 16);
    katachi_subdivision_free(s);
    katachi_mesh_free(plate);
}

static void test_bad_input(void)
{
    KatachiMesh *cube = make_cube();
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *s = (KatachiSubdivision *)&o; /* not NULL: must be reset */
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    KatachiMesh *empty = NULL;
    KatachiMesh *m = NULL;
    uint32_t f[1];

    CHECK_ERR("NULL mesh", katachi_subdivide(NULL, &o, &s), KATACHI_STATUS_NULL_POINTER, "mesh");
    CHECK("out reset to NULL", s == NULL);
    CHECK_ERR("NULL options", katachi_subdivide(cube, NULL, &s), KATACHI_STATUS_NULL_POINTER,
              "options");
    CHECK_ERR("NULL out", katachi_subdivide(cube, &o, NULL), KATACHI_STATUS_NULL_POINTER, "out");
    o.levels = 0;
    CHECK_ERR("0 levels", katachi_subdivide(cube, &o, &s), KATACHI_STATUS_INVALID_ARGUMENT,
              "levels");
    o.levels = 9;
    CHECK_ERR("9 levels", katachi_subdivide(cube, &o, &s), KATACHI_STATUS_INVALID_ARGUMENT,
              "levels");
    o = katachi_subdivide_options_default();
    o.holes = 7;
    CHECK_ERR("bad hole method", katachi_subdivide(cube, &o, &s), KATACHI_STATUS_INVALID_ARGUMENT,
              "holes");
    o = katachi_subdivide_options_default();
    o.boundary = 5;
    CHECK_ERR("bad boundary", katachi_subdivide(cube, &o, &s), KATACHI_STATUS_INVALID_ARGUMENT,
              "boundary");
    o = katachi_subdivide_options_default();
    o.crease_method = 2;
    CHECK_ERR("bad crease method", katachi_subdivide(cube, &o, &s),
              KATACHI_STATUS_INVALID_ARGUMENT, "crease_method");
    o = katachi_subdivide_options_default();
    o.struct_size = 4;
    CHECK_ERR("struct_size too small", katachi_subdivide(cube, &o, &s),
              KATACHI_STATUS_INVALID_ARGUMENT, "struct_size");
    o = katachi_subdivide_options_default();
    CHECK_OK("empty mesh created", katachi_mesh_create(NULL, 0, NULL, 0, NULL, 0, NULL, 0, &empty));
    CHECK_ERR("empty mesh", katachi_subdivide(empty, &o, &s), KATACHI_STATUS_BAD_INPUT, "empty");
    CHECK("out NULL after failures", s == NULL);
    CHECK_ERR("info of NULL", katachi_subdivision_info(NULL, &info), KATACHI_STATUS_NULL_POINTER,
              "subdivision");
    CHECK_ERR("mesh of NULL", katachi_subdivision_mesh(NULL, &m), KATACHI_STATUS_NULL_POINTER,
              "subdivision");
    CHECK_ERR("origin of NULL", katachi_subdivision_copy_face_origin(NULL, f, 1),
              KATACHI_STATUS_NULL_POINTER, "subdivision");
    katachi_subdivision_free(NULL);
    katachi_mesh_free(empty);
    katachi_mesh_free(cube);
}

/* The plate's two faces with holes triangulated, as a boolean outputs them. */
static KatachiMesh *make_boolean_plate(void)
{
    KatachiMesh *plate = NULL, *split = NULL;
    KatachiMeshCounts c = katachi_mesh_counts_default();
    uint32_t origin[64];
    katachi_mesh_create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12, PLATE_FACE_LOOP_COUNTS, 10,
                        PLATE_CORNERS, 48, &plate);
    CHECK_OK("split faces with holes",
             katachi_mesh_split_faces_with_holes(plate, &split, origin, 64));
    CHECK_OK("split counts", katachi_mesh_counts(split, &c));
    CHECK("16 simple faces", c.face_count == 16 && c.loop_count == 16);
    CHECK("first faces come from face 0", origin[0] == 0);
    katachi_mesh_free(split);
    CHECK_ERR("split: short origin buffer",
              katachi_mesh_split_faces_with_holes(plate, &split, origin, 3),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "face_origin");
    CHECK("split: out NULL after failure", split == NULL);
    CHECK_OK("split without origins", katachi_mesh_split_faces_with_holes(plate, &split, NULL, 0));
    katachi_mesh_free(plate);
    return split;
}

static void test_recovery_and_features(void)
{
    KatachiMesh *split = make_boolean_plate();
    KatachiMesh *merged = NULL, *tagged = NULL, *cube = make_cube();
    KatachiMeshCounts c = katachi_mesh_counts_default();
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *s = NULL;
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    char reason[8];

    CHECK_OK("merge coplanar regions", katachi_merge_coplanar_regions(split, 1e-3, &merged));
    CHECK_OK("merged counts", katachi_mesh_counts(merged, &c));
    CHECK("faces with holes recovered", c.face_count == 10 && c.loop_count == 12);
    CHECK_ERR("merge: bad tolerance", katachi_merge_coplanar_regions(split, 2.0, &tagged),
              KATACHI_STATUS_INVALID_ARGUMENT, "angle");
    CHECK_OK("tag feature edges", katachi_tag_feature_edges(cube, 30.0, &tagged));
    CHECK_OK("tagged counts", katachi_mesh_counts(tagged, &c));
    CHECK("all 12 cube edges are sharp at 30 degrees", c.sharp_edge_count == 12);
    katachi_mesh_free(tagged);
    tagged = NULL;
    CHECK_ERR("tag: angle 0", katachi_tag_feature_edges(cube, 0.0, &tagged),
              KATACHI_STATUS_INVALID_ARGUMENT, "angle");
    CHECK("tag: out NULL", tagged == NULL);

    o.recover_faces_with_holes = 1;
    o.levels = 2;
    CHECK_OK("subdivide a boolean's plate with recovery", katachi_subdivide(split, &o, &s));
    CHECK_OK("info", katachi_subdivision_info(s, &info));
    CHECK("method [a]: all quads, no fallback", info.face_count == 16 * 16 && info.fallback_face_count == 0);
    CHECK("input counts refer to the caller's mesh", info.input_vertex_count == 16 && info.input_corner_count == 64);
    CHECK_ERR("fallback reason: no such fallback",
              katachi_subdivision_fallback_reason(s, 0, reason, sizeof reason),
              KATACHI_STATUS_INVALID_ARGUMENT, "out of range");
    katachi_subdivision_free(s);
    o.recover_faces_with_holes = 3;
    CHECK_ERR("bad recover flag", katachi_subdivide(split, &o, &s), KATACHI_STATUS_INVALID_ARGUMENT,
              "recover_faces_with_holes");
    o = katachi_subdivide_options_default();
    o.feature_angle_degrees = 30.0;
    CHECK_OK("subdivide with feature angle", katachi_subdivide(cube, &o, &s));
    katachi_subdivision_free(s);
    katachi_mesh_free(merged);
    katachi_mesh_free(split);
    katachi_mesh_free(cube);
}

/* What the progress callback saw. */
typedef struct {
    uint32_t calls, last_done, total, in_order;
} Progress;

static void on_progress(uint32_t done, uint32_t total, void *user)
{
    Progress *p = (Progress *)user;
    p->calls++;
    if (done != p->last_done + 1) {
        p->in_order = 0;
    }
    p->last_done = done;
    p->total = total;
}

static void test_progress(void)
{
    KatachiMesh *cube = make_cube();
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *a = NULL, *b = NULL, *c = NULL;
    KatachiMesh *ma = NULL, *mb = NULL;
    Progress p = {0, 0, 0, 1};
    double pa[386 * 3], pb[386 * 3];
    size_t i;
    int same = 1;

    o.levels = 3;
    CHECK_OK("subdivide with progress",
             katachi_subdivide_with_progress(cube, &o, on_progress, &p, &a));
    CHECK("progress called once per level, in order, with the total",
          p.calls == 3 && p.last_done == 3 && p.total == 3 && p.in_order);
    CHECK_OK("NULL progress is allowed", katachi_subdivide_with_progress(cube, &o, NULL, NULL, &c));
    CHECK_OK("same call without progress", katachi_subdivide(cube, &o, &b));
    CHECK_OK("mesh a", katachi_subdivision_mesh(a, &ma));
    CHECK_OK("mesh b", katachi_subdivision_mesh(b, &mb));
    CHECK_OK("positions a", katachi_mesh_copy_positions(ma, pa, 386 * 3));
    CHECK_OK("positions b", katachi_mesh_copy_positions(mb, pb, 386 * 3));
    for (i = 0; i < 386 * 3; ++i) {
        if (pa[i] != pb[i]) {
            same = 0;
        }
    }
    CHECK("the same result bit for bit", same);
    katachi_subdivision_free(c);
    c = NULL;
    p.calls = 0;
    o.levels = 0;
    CHECK("bad options fail before any progress",
          katachi_subdivide_with_progress(cube, &o, on_progress, &p, &c) ==
                  KATACHI_STATUS_INVALID_ARGUMENT &&
              c == NULL && p.calls == 0);
    katachi_mesh_free(ma);
    katachi_mesh_free(mb);
    katachi_subdivision_free(a);
    katachi_subdivision_free(b);
    katachi_mesh_free(cube);
}

int main(void)
{
    printf("katachi %s, subdivision from C99\n", katachi_version_string());
    test_cube();
    test_plate_with_holes();
    test_bad_input();
    test_recovery_and_features();
    test_progress();
    return check_finish();
}
