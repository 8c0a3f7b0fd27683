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
    CHECK("26 vertices, 24 faces, 96 corners, 48 edges",
          info.vertex_count == 26 && info.face_count == 24 && info.corner_count == 96 &&
              info.loop_count == 24 && info.edge_count == 48);
    CHECK("input counts", info.input_vertex_count == 8 && info.input_corner_count == 24 &&
                              info.input_face_count == 6);
    CHECK("no creases left", info.sharp_edge_count == 0 && info.sharp_vertex_count == 0);
    CHECK("no fallback", info.fallback_face_count == 0);
    CHECK_OK("result mesh", katachi_subdivision_mesh(s, &out));
    CHECK_OK("counts", katachi_mesh_counts(out, &counts));
    CHECK("result counts", counts.vertex_count == 26 && counts.face_count == 24);
    CHECK_OK("positions", katachi_mesh_copy_positions(out, pos, 26 * 3));
    /* Corner 7 = (0.5, 0.5, 0.5) goes to 5/9 of itself (seed 001 eq. (2)). */
    CHECK("corner vertex point is 5/9 (1/2, 1/2, 1/2)", fabs(pos[7 * 3] - 5.0 / 18.0) < 1e-15);
    {
        /* The same arrays copied straight from the subdivision, no mesh in between. */
        double direct[26 * 3];
        uint32_t sizes[24], loops[24], corners[96], mesh_sizes[24], mesh_loops[24],
            mesh_corners[96];
        int same = 1;
        CHECK_OK("copy positions from the subdivision",
                 katachi_subdivision_copy_positions(s, direct, 26 * 3));
        CHECK_ERR("copy positions: short buffer",
                  katachi_subdivision_copy_positions(s, direct, 77),
                  KATACHI_STATUS_BUFFER_TOO_SMALL, "78");
        CHECK_OK("copy faces from the subdivision",
                 katachi_subdivision_copy_faces(s, sizes, 24, loops, 24, corners, 96));
        CHECK_OK("copy faces from the mesh",
                 katachi_mesh_copy_faces(out, mesh_sizes, 24, mesh_loops, 24, mesh_corners, 96));
        for (i = 0; i < 26 * 3; i++) {
            same = same && direct[i] == pos[i];
        }
        for (i = 0; i < 24; i++) {
            same = same && sizes[i] == mesh_sizes[i] && loops[i] == mesh_loops[i];
        }
        for (i = 0; i < 96; i++) {
            same = same && corners[i] == mesh_corners[i];
        }
        CHECK("the subdivision's copies are the result mesh's arrays", same);
        CHECK_ERR("copy faces: short corner buffer",
                  katachi_subdivision_copy_faces(s, sizes, 24, loops, 24, corners, 95),
                  KATACHI_STATUS_BUFFER_TOO_SMALL, "corners");
    }
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
        uint32_t entries = 0;
        uint32_t *offsets = malloc(27 * sizeof *offsets);
        uint32_t *sources;
        double *weights;
        int same = 1;
        CHECK_OK("stencil entry count", katachi_subdivision_stencil_entry_count(s, &entries));
        CHECK("stencils have entries", entries >= 26);
        CHECK_ERR("stencil entry count: NULL out",
                  katachi_subdivision_stencil_entry_count(s, NULL), KATACHI_STATUS_NULL_POINTER,
                  "count");
        sources = malloc(entries * sizeof *sources);
        weights = malloc(entries * sizeof *weights);
        CHECK_OK("copy stencils",
                 katachi_subdivision_copy_stencils(s, offsets, 27, sources, entries, weights,
                                                   entries));
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
                  katachi_subdivision_copy_stencils(s, offsets, 3, sources, entries, weights,
                                                    entries),
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

/* The cube as a host stores it (Blender): float positions, faces by their first corner. */
static const float CUBE_F32[8 * 3] = {
    -0.5f, -0.5f, -0.5f, 0.5f, -0.5f, -0.5f, -0.5f, 0.5f, -0.5f, 0.5f, 0.5f, -0.5f,
    -0.5f, -0.5f, 0.5f,  0.5f, -0.5f, 0.5f,  -0.5f, 0.5f, 0.5f,  0.5f, 0.5f, 0.5f,
};

/* A host's read-out: a mesh from a host's arrays (faces stored out of order too), creases
 * from a host's edge list, the result copied as arrays (positions as floats, polygons,
 * edges with their creases, face data carried, UVs per corner welded by katachi). */
static void test_host_arrays(void)
{
    uint32_t starts[6], starts_scattered[6], sizes[6], scattered[24];
    KatachiMesh *m = NULL, *m2 = NULL, *bad = NULL;
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *s = NULL, *s2 = NULL;
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    /* The 12 cube edges (a host's list) plus one loose edge 0-7; one crease 1.0 (0-1), one
     * 0.5 (2-3), the loose one creased too. */
    const uint32_t edges[13 * 2] = {0, 1, 1, 3, 3, 2, 2, 0, 4, 5, 5, 7,
                                    7, 6, 6, 4, 0, 4, 1, 5, 2, 6, 3, 7, 0, 7};
    float creases[13] = {1.0f, 0, 0.5f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.25f};
    uint32_t ignored = 99;
    float uv[24 * 2], uv_scattered[24 * 2], out_uv[96 * 2], out_uv2[96 * 2];
    float pos[26 * 3], crease_out[64];
    uint32_t poly_starts[24], poly_sizes[24], poly_corners[96], edge_verts[96], corner_edges[96];
    uint32_t materials[6] = {0, 1, 2, 3, 4, 5}, mat_out[24];
    uint8_t smooth[6] = {1, 0, 1, 0, 1, 0}, smooth_out[24];
    size_t i;
    int ok;

    for (i = 0; i < 6; i++) {
        starts[i] = (uint32_t)(4 * i);
        sizes[i] = 4;
        /* Faces in reverse: face i's corners stored where face 5 - i's would be. */
        starts_scattered[i] = (uint32_t)(4 * (5 - i));
    }
    for (i = 0; i < 24; i++) {
        /* A UV per corner: the corner's position within its face, so seams everywhere. */
        uv[2 * i] = (float)(i % 4 == 1 || i % 4 == 2);
        uv[2 * i + 1] = (float)(i % 4 >= 2);
    }
    for (i = 0; i < 6; i++) {
        size_t j;
        for (j = 0; j < 4; j++) {
            scattered[4 * (5 - i) + j] = CUBE_CORNERS[4 * i + j];
            uv_scattered[2 * (4 * (5 - i) + j)] = uv[2 * (4 * i + j)];
            uv_scattered[2 * (4 * (5 - i) + j) + 1] = uv[2 * (4 * i + j) + 1];
        }
    }
    CHECK_OK("create from a host's arrays",
             katachi_mesh_create_polygons_f32(CUBE_F32, 8, starts, NULL, 6, CUBE_CORNERS, 24, &m));
    CHECK_OK("create from a host's scattered faces",
             katachi_mesh_create_polygons_f32(CUBE_F32, 8, starts_scattered, sizes, 6, scattered,
                                              24, &m2));
    CHECK_ERR("starts must ascend without sizes",
              katachi_mesh_create_polygons_f32(CUBE_F32, 8, starts_scattered, NULL, 6, scattered,
                                               24, &bad),
              KATACHI_STATUS_INVALID_ARGUMENT, "ascend");
    sizes[2] = 5;
    CHECK_ERR("sizes must add up",
              katachi_mesh_create_polygons_f32(CUBE_F32, 8, starts, sizes, 6, CUBE_CORNERS, 24,
                                               &bad),
              KATACHI_STATUS_INVALID_ARGUMENT, "face");
    sizes[2] = 4;
    CHECK("out NULL after failures", bad == NULL);

    CHECK_OK("creases from a host's edge list",
             katachi_mesh_set_edge_sharpness_f32(m, edges, creases, 13, NULL, 0,
                                                 KATACHI_SHARPNESS_SCALE_CREASE, &ignored));
    CHECK("the loose creased edge is ignored and counted", ignored == 1);
    {
        /* The host's edge of each corner: the loose edge 12 is named by none. */
        uint32_t corner_edges_in[24];
        size_t c;
        for (c = 0; c < 24; c++) {
            uint32_t a = CUBE_CORNERS[c], b = CUBE_CORNERS[c % 4 == 3 ? c - 3 : c + 1], e;
            for (e = 0; e < 12; e++) {
                if ((edges[2 * e] == a && edges[2 * e + 1] == b) ||
                    (edges[2 * e] == b && edges[2 * e + 1] == a))
                    corner_edges_in[c] = e;
            }
        }
        ignored = 99;
        CHECK_OK("loose edges counted from the corners' edges",
                 katachi_mesh_set_edge_sharpness_f32(m2, edges, NULL, 13, corner_edges_in, 24,
                                                     KATACHI_SHARPNESS_SCALE_CREASE, &ignored));
        CHECK("one loose edge", ignored == 1);
        corner_edges_in[3] = 13;
        CHECK_ERR("a corner's edge out of range",
                  katachi_mesh_set_edge_sharpness_f32(m2, edges, NULL, 13, corner_edges_in, 24,
                                                      KATACHI_SHARPNESS_SCALE_CREASE, NULL),
                  KATACHI_STATUS_INVALID_ARGUMENT, "corner_edges[3]");
    }
    CHECK_OK("same creases on the scattered mesh",
             katachi_mesh_set_edge_sharpness_f32(m2, edges, creases, 13, NULL, 0,
                                                 KATACHI_SHARPNESS_SCALE_CREASE, NULL));
    creases[4] = 1.5f;
    CHECK_ERR("a crease above 1",
              katachi_mesh_set_edge_sharpness_f32(m, edges, creases, 13, NULL, 0,
                                                  KATACHI_SHARPNESS_SCALE_CREASE, NULL),
              KATACHI_STATUS_BAD_INPUT, "values[4] (edge 4-5)");
    CHECK_ERR("bad scale",
              katachi_mesh_set_edge_sharpness_f32(m, edges, creases, 13, NULL, 0, 7, NULL),
              KATACHI_STATUS_INVALID_ARGUMENT, "scale");
    {
        double sharp = -1;
        CHECK_OK("crease 0.5 is sharpness 2.5", katachi_mesh_edge_sharpness(m, 2, 3, &sharp));
        CHECK("crease 0.5 is sharpness 2.5", fabs(sharp - 2.5) < 1e-6);
        CHECK_OK("crease 1 is sharpness 10", katachi_mesh_edge_sharpness(m, 1, 0, &sharp));
        CHECK("crease 1 is sharpness 10", sharp == 10.0);
    }
    {
        float vc[8] = {0, 0, 0, 0, 0, 0, 0, 1.0f};
        double vs = 0;
        CHECK_OK("vertex creases", katachi_mesh_set_vertex_sharpness_f32(
                                       m, vc, 8, KATACHI_SHARPNESS_SCALE_CREASE));
        CHECK_OK("vertex 7's sharpness", katachi_mesh_vertex_sharpness(m, 7, &vs));
        CHECK("vertex crease 1 is sharpness 10", vs == 10.0);
        CHECK_ERR("vertex creases: wrong count",
                  katachi_mesh_set_vertex_sharpness_f32(m, vc, 7, KATACHI_SHARPNESS_SCALE_CREASE),
                  KATACHI_STATUS_INVALID_ARGUMENT, "8 vertices");
    }

    CHECK_OK("subdivide", katachi_subdivide(m, &o, &s));
    CHECK_OK("subdivide the scattered mesh", katachi_subdivide(m2, &o, &s2));
    CHECK_OK("info", katachi_subdivision_info(s, &info));
    CHECK("counts", info.vertex_count == 26 && info.face_count == 24 && info.edge_count == 48 &&
                        info.input_face_count == 6);
    CHECK("creases left: 0-1 (infinitely sharp) and 2-3 (2.5 -> 1.5), two halves each; vertex 7",
          info.sharp_edge_count == 4 && info.sharp_vertex_count == 1);
    CHECK_OK("positions as floats", katachi_subdivision_copy_positions_f32(s, pos, 26 * 3));
    CHECK_ERR("positions: short", katachi_subdivision_copy_positions_f32(s, pos, 10),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "78");
    CHECK_OK("polygons", katachi_subdivision_copy_polygons(s, poly_starts, 24, poly_sizes, 24,
                                                           poly_corners, 96));
    ok = 1;
    for (i = 0; i < 24; i++) {
        ok = ok && poly_starts[i] == 4 * i && poly_sizes[i] == 4;
    }
    CHECK("24 quads, one after the other", ok);
    CHECK_OK("polygons: NULL buffers skipped",
             katachi_subdivision_copy_polygons(s, NULL, 0, NULL, 0, poly_corners, 96));
    CHECK_OK("edges", katachi_subdivision_copy_edges(s, edge_verts, 96, corner_edges, 96));
    ok = 1;
    for (i = 0; i < 96; i++) {
        uint32_t e = corner_edges[i], next = (uint32_t)(i % 4 == 3 ? i - 3 : i + 1);
        uint32_t a = poly_corners[i], b = poly_corners[next];
        ok = ok && e < 48 &&
             ((edge_verts[2 * e] == a && edge_verts[2 * e + 1] == b) ||
              (edge_verts[2 * e] == b && edge_verts[2 * e + 1] == a));
    }
    CHECK("each corner's edge joins it to the next corner", ok);
    CHECK_OK("edge creases", katachi_subdivision_copy_edge_sharpness_f32(
                                 s, crease_out, 48, KATACHI_SHARPNESS_SCALE_CREASE));
    {
        int full = 0, half = 0, other = 0;
        for (i = 0; i < 48; i++) {
            if (crease_out[i] == 1.0f)
                full++;
            else if (fabsf(crease_out[i] - sqrtf(0.15f)) < 1e-6f)
                half++;
            else if (crease_out[i] != 0.0f)
                other++;
        }
        CHECK("creases left as Blender creases: 1 (infinitely sharp) twice, sqrt(1.5/10) twice",
              full == 2 && half == 2 && other == 0);
    }
    {
        float vs[26];
        CHECK_OK("vertex creases left", katachi_subdivision_copy_vertex_sharpness_f32(
                                            s, vs, 26, KATACHI_SHARPNESS_SCALE_SHARPNESS));
        CHECK("vertex 7 stays infinitely sharp", vs[7] == 10.0f && vs[0] == 0.0f);
    }
    CHECK_OK("carry materials", katachi_subdivision_carry_face_data(s, materials, 6, 4, mat_out, 24));
    CHECK_OK("carry smooth flags", katachi_subdivision_carry_face_data(s, smooth, 6, 1, smooth_out, 24));
    ok = 1;
    for (i = 0; i < 24; i++) {
        ok = ok && mat_out[i] == i / 4 && smooth_out[i] == smooth[i / 4];
    }
    CHECK("face data follow their faces", ok);
    CHECK_ERR("carry: bad size", katachi_subdivision_carry_face_data(s, materials, 6, 3, mat_out, 24),
              KATACHI_STATUS_INVALID_ARGUMENT, "value_size");
    CHECK_ERR("carry: wrong count", katachi_subdivision_carry_face_data(s, materials, 5, 4, mat_out, 24),
              KATACHI_STATUS_INVALID_ARGUMENT, "6 faces");
    CHECK_ERR("carry: short output", katachi_subdivision_carry_face_data(s, materials, 6, 4, mat_out, 23),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "24");
    CHECK_OK("UVs per corner", katachi_subdivision_refine_corner_data_f32(
                                   s, uv, 48, 2, KATACHI_FACE_VARYING_LINEAR_BOUNDARIES, out_uv,
                                   96 * 2));
    CHECK_OK("UVs per corner, host's order", katachi_subdivision_refine_corner_data_f32(
                                                 s2, uv_scattered, 48, 2,
                                                 KATACHI_FACE_VARYING_LINEAR_BOUNDARIES, out_uv2,
                                                 96 * 2));
    ok = 1;
    for (i = 0; i < 96 * 2; i++) {
        ok = ok && out_uv[i] == out_uv2[i];
    }
    CHECK("the host's corner order is followed", ok);
    CHECK("a face's own corners keep their UVs", out_uv[0] == 0.0f && out_uv[1] == 0.0f);
    CHECK_ERR("UVs: wrong count", katachi_subdivision_refine_corner_data_f32(
                                      s, uv, 47, 2, KATACHI_FACE_VARYING_SMOOTH, out_uv, 192),
              KATACHI_STATUS_INVALID_ARGUMENT, "24 corners");
    katachi_subdivision_free(s);
    katachi_subdivision_free(s2);
    katachi_mesh_free(m);
    katachi_mesh_free(m2);
}

/* Faces with holes cut into simple polygons for hosts that store none. */
static void test_split_faces_with_holes(void)
{
    KatachiMesh *plate = NULL;
    KatachiSubdivideOptions o = katachi_subdivide_options_default();
    KatachiSubdivision *s = NULL;
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    uint32_t starts[1];
    KatachiMesh *whole = NULL, *cut = NULL;
    KatachiMeshCounts c = katachi_mesh_counts_default();
    CHECK_OK("create the plate", katachi_mesh_create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12,
                                                     PLATE_FACE_LOOP_COUNTS, 10, PLATE_CORNERS,
                                                     48, &plate));
    o.holes = KATACHI_HOLE_METHOD_SHARP;
    CHECK_OK("subdivide, faces with holes kept", katachi_subdivide(plate, &o, &s));
    CHECK_OK("info", katachi_subdivision_info(s, &info));
    CHECK("two faces with holes", info.loop_count == info.face_count + 2);
    CHECK_ERR("no polygons while faces have holes",
              katachi_subdivision_copy_polygons(s, starts, 1, NULL, 0, NULL, 0),
              KATACHI_STATUS_INVALID_ARGUMENT, "split_faces_with_holes");
    CHECK_OK("the whole result", katachi_subdivision_mesh(s, &whole));
    CHECK_OK("cut it", katachi_mesh_split_faces_with_holes(whole, &cut, NULL, 0));
    CHECK_OK("its counts", katachi_mesh_counts(cut, &c));
    katachi_subdivision_free(s);
    o.split_faces_with_holes = 1;
    CHECK_OK("subdivide, faces with holes cut", katachi_subdivide(plate, &o, &s));
    CHECK_OK("info", katachi_subdivision_info(s, &info));
    CHECK("the faces with holes cut as katachi_mesh_split_faces_with_holes cuts them",
          info.loop_count == info.face_count && info.face_count == c.face_count &&
              info.face_count > 8 * 4 + 2 && info.corner_count == c.corner_count);
    katachi_subdivision_free(s);
    katachi_mesh_free(whole);
    katachi_mesh_free(cut);
    o.split_faces_with_holes = 2;
    CHECK_ERR("bad split flag", katachi_subdivide(plate, &o, &s), KATACHI_STATUS_INVALID_ARGUMENT,
              "split_faces_with_holes");
    katachi_mesh_free(plate);
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
    test_host_arrays();
    test_split_faces_with_holes();
    return check_finish();
}
