/*
 * C99 link test of the mesh part of the katachi C ABI: versions, statuses and messages,
 * creating meshes (faces with holes included), counts, copy-out, sharpness, inspect, and bad
 * input through every pointer and index parameter. Run by `cargo xtask ctest` under valgrind.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "katachi.h"

#include "check.h"
#include "shapes.h"
#include "snapshot.h"

#define LEN(a) (sizeof(a) / sizeof((a)[0]))

/* A non-NULL pointer that no call may return: out-handles must be NULL after a failure. */
static int sentinel_object;
#define SENTINEL ((KatachiMesh *)(void *)&sentinel_object)

static KatachiMesh *make_cube(void)
{
    KatachiMesh *m = NULL;
    KatachiStatus s = katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6,
                                          CUBE_FACE_LOOP_COUNTS, 6, CUBE_CORNERS, 24, &m);
    if (s != KATACHI_STATUS_OK || m == NULL) {
        printf("FAIL cannot build the cube: %s\n", katachi_last_error_message());
        exit(1);
    }
    return m;
}

static void test_versions_and_statuses(void)
{
    char expected[64];
    CHECK("KATACHI_ABI_VERSION == katachi_abi_version()",
          katachi_abi_version() == KATACHI_ABI_VERSION);
    snprintf(expected, sizeof expected, "%d.%d.%d", KATACHI_VERSION_MAJOR, KATACHI_VERSION_MINOR,
             KATACHI_VERSION_PATCH);
    CHECK("version macros == katachi_version_string()",
          strcmp(katachi_version_string(), expected) == 0);
    CHECK("KatachiStatus is 4 bytes", sizeof(KatachiStatus) == 4);
    CHECK("status values", KATACHI_STATUS_OK == 0 && KATACHI_STATUS_NULL_POINTER == 1 &&
                               KATACHI_STATUS_INVALID_ARGUMENT == 2 &&
                               KATACHI_STATUS_BUFFER_TOO_SMALL == 3 &&
                               KATACHI_STATUS_BAD_INPUT == 4 && KATACHI_STATUS_BAD_TOPOLOGY == 5 &&
                               KATACHI_STATUS_IO_ERROR == 6 && KATACHI_STATUS_INTERNAL_ERROR == 7 &&
                               KATACHI_STATUS_CANCELLED == 8);
    CHECK("katachi_status_name(OK)",
          strcmp(katachi_status_name(KATACHI_STATUS_OK), "KATACHI_STATUS_OK") == 0);
    CHECK("katachi_status_name(BUFFER_TOO_SMALL)",
          strcmp(katachi_status_name(KATACHI_STATUS_BUFFER_TOO_SMALL),
                 "KATACHI_STATUS_BUFFER_TOO_SMALL") == 0);
    CHECK("katachi_status_name(INTERNAL_ERROR)",
          strcmp(katachi_status_name(KATACHI_STATUS_INTERNAL_ERROR),
                 "KATACHI_STATUS_INTERNAL_ERROR") == 0);
    CHECK("katachi_status_name(unknown)",
          strcmp(katachi_status_name(99), "KATACHI_STATUS_UNKNOWN") == 0);
}

static void test_last_error_message(void)
{
    KatachiMesh *m = NULL;
    CHECK("no message before any failure", strcmp(katachi_last_error_message(), "") == 0);
    CHECK_ERR("a failing call leaves a message", katachi_mesh_clone(NULL, &m),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_clone: mesh is NULL");
    /* Functions that cannot fail leave the message alone, so it can be printed with them. */
    (void)katachi_status_name(KATACHI_STATUS_NULL_POINTER);
    (void)katachi_abi_version();
    (void)katachi_version_string();
    (void)katachi_mesh_counts_default();
    (void)katachi_mesh_info_default();
    katachi_mesh_free(NULL);
    CHECK("infallible calls keep the message",
          strcmp(katachi_last_error_message(), check_message) == 0);
    CHECK("the message is stable across reads",
          katachi_last_error_message() == katachi_last_error_message());
    m = make_cube();
    CHECK("a successful call clears the message", strcmp(katachi_last_error_message(), "") == 0);
    katachi_mesh_free(m);
}

static void test_cube(void)
{
    KatachiMesh *m = make_cube();
    KatachiMeshCounts c = katachi_mesh_counts_default();
    KatachiMeshInfo info = katachi_mesh_info_default();
    double pos[24];
    uint32_t ls[6], flc[6], cs[24];

    CHECK("counts_default sets struct_size", c.struct_size == sizeof(KatachiMeshCounts));
    CHECK("info_default sets struct_size", info.struct_size == sizeof(KatachiMeshInfo));
    CHECK("info_default genus is -1", info.genus == -1 && !info.is_closed);
    CHECK_OK("cube: counts", katachi_mesh_counts(m, &c));
    CHECK("cube: 8 vertices, 6 faces, 6 loops, 24 corners",
          c.vertex_count == 8 && c.face_count == 6 && c.loop_count == 6 && c.corner_count == 24);
    CHECK("cube: no sharp edges or vertices", c.sharp_edge_count == 0 && c.sharp_vertex_count == 0);
    CHECK("counts keeps struct_size", c.struct_size == sizeof(KatachiMeshCounts));

    CHECK_OK("cube: copy positions", katachi_mesh_copy_positions(m, pos, LEN(pos)));
    CHECK("cube: positions bit-exact", memcmp(pos, CUBE_POSITIONS, sizeof pos) == 0);
    CHECK_OK("cube: copy faces",
             katachi_mesh_copy_faces(m, ls, LEN(ls), flc, LEN(flc), cs, LEN(cs)));
    CHECK("cube: loop sizes", memcmp(ls, CUBE_LOOP_SIZES, sizeof ls) == 0);
    CHECK("cube: face loop counts", memcmp(flc, CUBE_FACE_LOOP_COUNTS, sizeof flc) == 0);
    CHECK("cube: corners", memcmp(cs, CUBE_CORNERS, sizeof cs) == 0);

    CHECK_OK("cube: inspect", katachi_mesh_inspect(m, &info));
    CHECK("cube: 12 edges, χ = 2, genus 0", info.edge_count == 12 &&
                                                 info.euler_characteristic == 2 && info.genus == 0);
    CHECK("cube: closed, manifold, 1 component, no boundary",
          info.is_closed && info.is_manifold && info.component_count == 1 &&
              info.boundary_edge_count == 0 && info.boundary_loop_count == 0);
    CHECK("cube: no defects", info.non_manifold_edge_count == 0 &&
                                  info.inconsistent_edge_count == 0 &&
                                  info.non_manifold_vertex_count == 0 &&
                                  info.unreferenced_vertex_count == 0 &&
                                  info.coincident_vertex_count == 0 &&
                                  info.zero_area_face_count == 0 && info.faces_with_holes_count == 0);
    CHECK("cube: bounding box", info.has_bounding_box && info.bounding_box_min[0] == -0.5 &&
                                    info.bounding_box_min[2] == -0.5 &&
                                    info.bounding_box_max[1] == 0.5 &&
                                    info.bounding_box_max[2] == 0.5);
    CHECK("inspect keeps struct_size", info.struct_size == sizeof(KatachiMeshInfo));
    katachi_mesh_free(m);
}

static void test_plate_with_holes(void)
{
    KatachiMesh *m = NULL;
    KatachiMeshCounts c = katachi_mesh_counts_default();
    KatachiMeshInfo info = katachi_mesh_info_default();
    double pos[48];
    uint32_t ls[12], flc[10], cs[48];

    CHECK_OK("plate: create (faces with holes)",
             katachi_mesh_create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12, PLATE_FACE_LOOP_COUNTS,
                                 10, PLATE_CORNERS, 48, &m));
    CHECK("plate: handle", m != NULL);
    CHECK_OK("plate: counts", katachi_mesh_counts(m, &c));
    CHECK("plate: 16 vertices, 10 faces, 12 loops, 48 corners",
          c.vertex_count == 16 && c.face_count == 10 && c.loop_count == 12 && c.corner_count == 48);
    CHECK_OK("plate: copy positions", katachi_mesh_copy_positions(m, pos, LEN(pos)));
    CHECK("plate: positions bit-exact", memcmp(pos, PLATE_POSITIONS, sizeof pos) == 0);
    CHECK_OK("plate: copy faces",
             katachi_mesh_copy_faces(m, ls, LEN(ls), flc, LEN(flc), cs, LEN(cs)));
    CHECK("plate: layout round-trips (outer loop first, then the hole)",
          memcmp(ls, PLATE_LOOP_SIZES, sizeof ls) == 0 &&
              memcmp(flc, PLATE_FACE_LOOP_COUNTS, sizeof flc) == 0 &&
              memcmp(cs, PLATE_CORNERS, sizeof cs) == 0);
    CHECK_OK("plate: inspect", katachi_mesh_inspect(m, &info));
    CHECK("plate: 2 faces with holes", info.faces_with_holes_count == 2);
    CHECK("plate: 24 edges, χ = 0, genus 1",
          info.edge_count == 24 && info.euler_characteristic == 0 && info.genus == 1);
    CHECK("plate: closed and manifold, 1 component",
          info.is_closed && info.is_manifold && info.component_count == 1);
    katachi_mesh_free(m);
}

static void test_other_shapes(void)
{
    KatachiMesh *m = NULL;
    KatachiMeshInfo info = katachi_mesh_info_default();
    KatachiMeshCounts c = katachi_mesh_counts_default();
    /* The cube without its +x face: an open box with one boundary loop. */
    static const uint32_t box_flc[5] = {1, 1, 1, 1, 1};
    /* Three quads sharing the edge 0-1: a non-manifold fin. */
    static const double fin_pos[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                          1, -1, 0, 0, -1, 0, 1, 0, 1, 0, 0, 1};
    static const uint32_t fin_ls[3] = {4, 4, 4};
    static const uint32_t fin_flc[3] = {1, 1, 1};
    static const uint32_t fin_cs[12] = {0, 1, 2, 3, 1, 0, 5, 4, 0, 1, 6, 7};
    double d = 1.0;

    CHECK_OK("open box: create",
             katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 5, box_flc, 5,
                                 CUBE_CORNERS, 20, &m));
    CHECK_OK("open box: inspect", katachi_mesh_inspect(m, &info));
    CHECK("open box: 1 boundary loop of 4 edges, open, χ = 1, no genus",
          info.boundary_loop_count == 1 && info.boundary_edge_count == 4 && !info.is_closed &&
              info.euler_characteristic == 1 && info.genus == -1);
    katachi_mesh_free(m);

    CHECK_OK("fin: create (non-manifold meshes are valid input)",
             katachi_mesh_create(fin_pos, 8, fin_ls, 3, fin_flc, 3, fin_cs, 12, &m));
    CHECK_OK("fin: inspect tolerates defects", katachi_mesh_inspect(m, &info));
    CHECK("fin: a non-manifold edge, not manifold",
          info.non_manifold_edge_count == 1 && !info.is_manifold);
    katachi_mesh_free(m);

    /* An empty mesh: every array NULL with count 0. */
    CHECK_OK("empty: create", katachi_mesh_create(NULL, 0, NULL, 0, NULL, 0, NULL, 0, &m));
    CHECK_OK("empty: counts", katachi_mesh_counts(m, &c));
    CHECK("empty: zero counts", c.vertex_count == 0 && c.face_count == 0 && c.corner_count == 0);
    CHECK_OK("empty: copy positions into NULL, 0", katachi_mesh_copy_positions(m, NULL, 0));
    CHECK_OK("empty: copy faces into NULLs",
             katachi_mesh_copy_faces(m, NULL, 0, NULL, 0, NULL, 0));
    CHECK_OK("empty: copy sharp edges into NULLs", katachi_mesh_copy_sharp_edges(m, NULL, NULL, 0));
    CHECK_OK("empty: copy vertex sharpness into NULL",
             katachi_mesh_copy_vertex_sharpness(m, NULL, 0));
    CHECK_OK("empty: set all vertex sharpness from NULL, 0",
             katachi_mesh_set_all_vertex_sharpness(m, NULL, 0));
    CHECK_OK("empty: set no edge sharpness", katachi_mesh_set_edge_sharpnesses(m, NULL, NULL, 0));
    CHECK_OK("empty: inspect", katachi_mesh_inspect(m, &info));
    CHECK("empty: no bounding box", !info.has_bounding_box && info.vertex_count == 0);
    CHECK_ERR("empty: any vertex is out of range", katachi_mesh_vertex_sharpness(m, 0, &d),
              KATACHI_STATUS_INVALID_ARGUMENT, "vertex = 0 is out of range (the mesh has 0 vertices)");
    katachi_mesh_free(m);
}

static void test_clone(void)
{
    KatachiMesh *m = make_cube();
    KatachiMesh *copy = NULL;
    Snapshot a, b;
    double s = -1.0;
    CHECK_OK("set an edge sharpness before cloning", katachi_mesh_set_edge_sharpness(m, 0, 1, 3.0));
    CHECK_OK("clone", katachi_mesh_clone(m, &copy));
    CHECK("clone: a new handle", copy != NULL && copy != m);
    a = snapshot(m);
    b = snapshot(copy);
    CHECK("clone: same arrays and attributes", snapshots_equal(&a, &b));
    snapshot_free(&b);
    CHECK_OK("clone: change the copy", katachi_mesh_set_edge_sharpness(copy, 0, 1, 0.0));
    CHECK_OK("clone: read the original", katachi_mesh_edge_sharpness(m, 1, 0, &s));
    CHECK("clone: the original keeps its sharpness", s == 3.0);
    b = snapshot(m);
    CHECK("clone: the original is unchanged", snapshots_equal(&a, &b));
    snapshot_free(&a);
    snapshot_free(&b);
    katachi_mesh_free(copy);
    katachi_mesh_free(m);
}

static void test_sharpness(void)
{
    KatachiMesh *m = make_cube();
    KatachiMeshCounts c = katachi_mesh_counts_default();
    double s = -1.0;
    uint32_t edges[6];
    double values[3];
    double vs[8];
    static const uint32_t bulk_edges[6] = {7, 5, 2, 0, 4, 6};
    static const double bulk_values[3] = {1.5, 10.0, 0.25};
    static const double all_vs[8] = {0, 1, 2, 3, 4, 5, 6, 10};

    CHECK_OK("edge sharpness of a smooth edge", katachi_mesh_edge_sharpness(m, 0, 1, &s));
    CHECK("a smooth edge reads 0", s == 0.0);
    CHECK_OK("set edge sharpness", katachi_mesh_set_edge_sharpness(m, 1, 0, 2.5));
    CHECK_OK("get it back in the other order", katachi_mesh_edge_sharpness(m, 0, 1, &s));
    CHECK("edge sharpness is 2.5", s == 2.5);
    CHECK_OK("a pair that is no edge reads", katachi_mesh_edge_sharpness(m, 0, 7, &s));
    CHECK("a pair that is no edge reads 0", s == 0.0);
    CHECK_OK("set many edges", katachi_mesh_set_edge_sharpnesses(m, bulk_edges, bulk_values, 3));
    CHECK_OK("counts after sharpening", katachi_mesh_counts(m, &c));
    CHECK("4 sharp edges", c.sharp_edge_count == 4);
    CHECK_ERR("copy sharp edges: room for 3 of 4",
              katachi_mesh_copy_sharp_edges(m, edges, values, 3), KATACHI_STATUS_BUFFER_TOO_SMALL,
              "capacity is 3 edges, but the mesh has 4 sharp edges");
    {
        uint32_t e4[8];
        double v4[4];
        static const uint32_t expect_e[8] = {0, 1, 0, 2, 4, 6, 5, 7};
        static const double expect_v[4] = {2.5, 10.0, 0.25, 1.5};
        CHECK_OK("copy 4 sharp edges", katachi_mesh_copy_sharp_edges(m, e4, v4, 4));
        CHECK("sharp edges sorted, smaller vertex first",
              memcmp(e4, expect_e, sizeof e4) == 0 && memcmp(v4, expect_v, sizeof v4) == 0);
    }
    CHECK_OK("smooth an edge again", katachi_mesh_set_edge_sharpness(m, 0, 1, 0.0));
    CHECK_OK("counts after smoothing", katachi_mesh_counts(m, &c));
    CHECK("3 sharp edges", c.sharp_edge_count == 3);

    CHECK_OK("vertex sharpness", katachi_mesh_vertex_sharpness(m, 7, &s));
    CHECK("a smooth vertex reads 0", s == 0.0);
    CHECK_OK("set vertex sharpness", katachi_mesh_set_vertex_sharpness(m, 7, 10.0));
    CHECK_OK("get vertex sharpness", katachi_mesh_vertex_sharpness(m, 7, &s));
    CHECK("vertex sharpness is 10", s == 10.0);
    CHECK_OK("set all vertex sharpness", katachi_mesh_set_all_vertex_sharpness(m, all_vs, 8));
    CHECK_OK("copy vertex sharpness", katachi_mesh_copy_vertex_sharpness(m, vs, LEN(vs)));
    CHECK("vertex sharpness round-trips", memcmp(vs, all_vs, sizeof vs) == 0);
    CHECK_OK("counts after vertex sharpness", katachi_mesh_counts(m, &c));
    CHECK("7 sharp vertices", c.sharp_vertex_count == 7);
    katachi_mesh_free(m);
}

/* katachi_mesh_create with one thing wrong at a time; *out must come back NULL. */
static void test_create_bad_input(void)
{
    KatachiMesh *m;
    double pos[24];
    uint32_t cs[24], ls[6], flc[6];

#define CREATE(p, nv, l, nl, f, nf, c, nc) katachi_mesh_create((p), (nv), (l), (nl), (f), (nf), (c), (nc), &m)
#define EXPECT_FAIL(name, call, status, substring) \
    do {                                           \
        m = SENTINEL;                              \
        CHECK_ERR(name, call, status, substring);  \
        CHECK(name ": *out is NULL", m == NULL);   \
    } while (0)

    EXPECT_FAIL("create: positions NULL",
                CREATE(NULL, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_NULL_POINTER,
                "katachi_mesh_create: positions is NULL but vertex_count is 8");
    EXPECT_FAIL("create: loop_sizes NULL",
                CREATE(CUBE_POSITIONS, 8, NULL, 6, CUBE_FACE_LOOP_COUNTS, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_NULL_POINTER, "loop_sizes is NULL but loop_count is 6");
    EXPECT_FAIL("create: face_loop_counts NULL",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, NULL, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_NULL_POINTER, "face_loop_counts is NULL but face_count is 6");
    EXPECT_FAIL("create: corners NULL",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, NULL, 24),
                KATACHI_STATUS_NULL_POINTER, "corners is NULL but corner_count is 24");
    CHECK_ERR("create: out NULL",
              katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6,
                                  CUBE_CORNERS, 24, NULL),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_create: out is NULL");

    memcpy(pos, CUBE_POSITIONS, sizeof pos);
    pos[3 * 3 + 1] = NAN;
    EXPECT_FAIL("create: NaN coordinate",
                CREATE(pos, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_BAD_INPUT, "vertex 3: coordinate y is NaN");
    pos[3 * 3 + 1] = 0.5;
    pos[5 * 3 + 2] = -INFINITY;
    EXPECT_FAIL("create: infinite coordinate",
                CREATE(pos, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_BAD_INPUT, "vertex 5: coordinate z is -inf");

    memcpy(flc, CUBE_FACE_LOOP_COUNTS, sizeof flc);
    flc[2] = 2; /* 7 loops claimed, 6 given */
    EXPECT_FAIL("create: face loop counts do not add up",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, flc, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_BAD_INPUT, "loop counts add up to 7, but 6 loop sizes");
    memcpy(ls, CUBE_LOOP_SIZES, sizeof ls);
    ls[5] = 5; /* 25 corners claimed, 24 given */
    EXPECT_FAIL("create: loop sizes do not add up",
                CREATE(CUBE_POSITIONS, 8, ls, 6, CUBE_FACE_LOOP_COUNTS, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_BAD_INPUT, "loop sizes add up to 25, but 24 corner indices");
    flc[2] = 0;
    flc[3] = 2;
    EXPECT_FAIL("create: a face without loops",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, flc, 6, CUBE_CORNERS, 24),
                KATACHI_STATUS_BAD_INPUT, "face 2 has no loops");

    memcpy(cs, CUBE_CORNERS, sizeof cs);
    cs[13] = 8;
    EXPECT_FAIL("create: vertex index out of range",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, cs, 24),
                KATACHI_STATUS_BAD_INPUT,
                "face 3, loop 0: vertex index 8 is out of range (the mesh has 8 vertices)");
    cs[13] = 0xFFFFFFFFu;
    EXPECT_FAIL("create: vertex index 2^32 - 1",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, cs, 24),
                KATACHI_STATUS_BAD_INPUT, "vertex index 4294967295 is out of range");
    memcpy(cs, CUBE_CORNERS, sizeof cs);
    cs[5] = 4; /* face 1 is 4 4 7 6 */
    EXPECT_FAIL("create: repeated vertex in a loop",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, cs, 24),
                KATACHI_STATUS_BAD_INPUT, "face 1, loop 0: vertex 4 appears more than once");
    cs[6] = 4;
    cs[7] = 4; /* face 1 is 4 4 4 4 */
    EXPECT_FAIL("create: degenerate loop",
                CREATE(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6, cs, 24),
                KATACHI_STATUS_BAD_INPUT, "at least 3 distinct vertices");
#undef EXPECT_FAIL
#undef CREATE
}

/* Every other function, NULL in each pointer parameter, bad indices, short buffers, bad
 * struct sizes; then proof that the mesh did not change. */
static void test_bad_arguments(void)
{
    KatachiMesh *m = make_cube();
    KatachiMesh *out = SENTINEL;
    KatachiMeshCounts c = katachi_mesh_counts_default();
    KatachiMeshInfo info = katachi_mesh_info_default();
    Snapshot before, after;
    double s = 42.0;
    double pos[24];
    uint32_t ls[6], flc[6], cs[24];
    uint32_t e[8];
    double v[8];
    size_t i;
    int untouched;
    static const uint32_t bad_pairs[6] = {0, 1, 0, 7, 2, 3}; /* 0-7 is a diagonal, no edge */
    static const uint32_t far_pairs[4] = {0, 1, 3, 99};
    static const uint32_t same_pairs[2] = {5, 5};
    static const double ok_values[3] = {1.0, 2.0, 3.0};
    static const double bad_values[3] = {1.0, -2.0, 3.0};
    static const double vs_bad[8] = {0, 0, -1, 0, 0, 0, 0, 0};

    CHECK_OK("sharpen 2-3 before the failures", katachi_mesh_set_edge_sharpness(m, 2, 3, 4.0));
    CHECK_OK("sharpen vertex 6 before the failures", katachi_mesh_set_vertex_sharpness(m, 6, 1.0));
    before = snapshot(m);

    /* katachi_mesh_clone */
    CHECK_ERR("clone: mesh NULL", katachi_mesh_clone(NULL, &out), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_clone: mesh is NULL");
    CHECK("clone: *out is NULL after failure", out == NULL);
    CHECK_ERR("clone: out NULL", katachi_mesh_clone(m, NULL), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_clone: out is NULL");

    /* katachi_mesh_counts */
    CHECK_ERR("counts: mesh NULL", katachi_mesh_counts(NULL, &c), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_counts: mesh is NULL");
    CHECK_ERR("counts: counts NULL", katachi_mesh_counts(m, NULL), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_counts: counts is NULL");
    c.struct_size = 4;
    c.vertex_count = 12345;
    CHECK_ERR("counts: struct_size too small", katachi_mesh_counts(m, &c),
              KATACHI_STATUS_INVALID_ARGUMENT, "counts->struct_size is 4");
    CHECK("counts: message says how to fix it", MESSAGE_HAS("katachi_mesh_counts_default"));
    CHECK("counts: untouched after failure", c.vertex_count == 12345 && c.struct_size == 4);
    c.struct_size = 0;
    CHECK_ERR("counts: struct_size 0", katachi_mesh_counts(m, &c), KATACHI_STATUS_INVALID_ARGUMENT,
              "struct_size is 0");

    /* katachi_mesh_copy_positions */
    for (i = 0; i < LEN(pos); i++) pos[i] = -7.0;
    CHECK_ERR("copy positions: mesh NULL", katachi_mesh_copy_positions(NULL, pos, 24),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_copy_positions: mesh is NULL");
    CHECK_ERR("copy positions: positions NULL", katachi_mesh_copy_positions(m, NULL, 24),
              KATACHI_STATUS_NULL_POINTER, "positions is NULL");
    CHECK_ERR("copy positions: buffer one short", katachi_mesh_copy_positions(m, pos, 23),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "room for 23 values, but 24 are needed");
    CHECK_ERR("copy positions: size query with NULL, 0", katachi_mesh_copy_positions(m, NULL, 0),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "24 are needed");
    untouched = 1;
    for (i = 0; i < LEN(pos); i++) untouched &= pos[i] == -7.0;
    CHECK("copy positions: a short buffer is untouched", untouched);

    /* katachi_mesh_copy_faces */
    memset(cs, 0xAB, sizeof cs);
    CHECK_ERR("copy faces: mesh NULL", katachi_mesh_copy_faces(NULL, ls, 6, flc, 6, cs, 24),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_copy_faces: mesh is NULL");
    CHECK_ERR("copy faces: loop_sizes NULL", katachi_mesh_copy_faces(m, NULL, 6, flc, 6, cs, 24),
              KATACHI_STATUS_NULL_POINTER, "loop_sizes is NULL");
    CHECK_ERR("copy faces: face_loop_counts NULL",
              katachi_mesh_copy_faces(m, ls, 6, NULL, 6, cs, 24), KATACHI_STATUS_NULL_POINTER,
              "face_loop_counts is NULL");
    CHECK_ERR("copy faces: corners NULL", katachi_mesh_copy_faces(m, ls, 6, flc, 6, NULL, 24),
              KATACHI_STATUS_NULL_POINTER, "corners is NULL");
    CHECK_ERR("copy faces: corners short", katachi_mesh_copy_faces(m, ls, 6, flc, 6, cs, 20),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "corners has room for 20 values, but 24 are needed");
    CHECK_ERR("copy faces: loop_sizes short", katachi_mesh_copy_faces(m, ls, 5, flc, 6, cs, 24),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "loop_sizes has room for 5 values, but 6");
    CHECK_ERR("copy faces: face_loop_counts short",
              katachi_mesh_copy_faces(m, ls, 6, flc, 0, cs, 24), KATACHI_STATUS_BUFFER_TOO_SMALL,
              "face_loop_counts has room for 0 values, but 6");
    untouched = 1;
    for (i = 0; i < LEN(cs); i++) untouched &= cs[i] == 0xABABABABu;
    CHECK("copy faces: nothing written on failure", untouched);

    /* katachi_mesh_edge_sharpness */
    CHECK_ERR("edge sharpness: mesh NULL", katachi_mesh_edge_sharpness(NULL, 0, 1, &s),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_edge_sharpness: mesh is NULL");
    CHECK_ERR("edge sharpness: sharpness NULL", katachi_mesh_edge_sharpness(m, 0, 1, NULL),
              KATACHI_STATUS_NULL_POINTER, "sharpness is NULL");
    CHECK_ERR("edge sharpness: b out of range", katachi_mesh_edge_sharpness(m, 0, 99, &s),
              KATACHI_STATUS_INVALID_ARGUMENT, "b = 99 is out of range (the mesh has 8 vertices)");
    CHECK_ERR("edge sharpness: a out of range", katachi_mesh_edge_sharpness(m, 8, 1, &s),
              KATACHI_STATUS_INVALID_ARGUMENT, "a = 8 is out of range");
    CHECK_ERR("edge sharpness: a == b", katachi_mesh_edge_sharpness(m, 3, 3, &s),
              KATACHI_STATUS_INVALID_ARGUMENT, "a and b are both vertex 3");
    CHECK("edge sharpness: output untouched on failure", s == 42.0);

    /* katachi_mesh_set_edge_sharpness */
    CHECK_ERR("set edge sharpness: mesh NULL", katachi_mesh_set_edge_sharpness(NULL, 0, 1, 1.0),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_set_edge_sharpness: mesh is NULL");
    CHECK_ERR("set edge sharpness: out of range", katachi_mesh_set_edge_sharpness(m, 0, 8, 1.0),
              KATACHI_STATUS_INVALID_ARGUMENT, "b = 8 is out of range");
    CHECK_ERR("set edge sharpness: no such edge", katachi_mesh_set_edge_sharpness(m, 0, 7, 1.0),
              KATACHI_STATUS_BAD_INPUT, "there is no edge between vertices 0 and 7");
    CHECK_ERR("set edge sharpness: negative", katachi_mesh_set_edge_sharpness(m, 0, 1, -1.0),
              KATACHI_STATUS_BAD_INPUT, "sharpness -1 is invalid");
    CHECK_ERR("set edge sharpness: NaN", katachi_mesh_set_edge_sharpness(m, 0, 1, NAN),
              KATACHI_STATUS_BAD_INPUT, "sharpness NaN is invalid");

    /* katachi_mesh_set_edge_sharpnesses */
    CHECK_ERR("set edges: mesh NULL",
              katachi_mesh_set_edge_sharpnesses(NULL, bad_pairs, ok_values, 3),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_set_edge_sharpnesses: mesh is NULL");
    CHECK_ERR("set edges: edges NULL", katachi_mesh_set_edge_sharpnesses(m, NULL, ok_values, 3),
              KATACHI_STATUS_NULL_POINTER, "edges is NULL but count is 3");
    CHECK_ERR("set edges: sharpness NULL", katachi_mesh_set_edge_sharpnesses(m, bad_pairs, NULL, 3),
              KATACHI_STATUS_NULL_POINTER, "sharpness is NULL but count is 3");
    CHECK_ERR("set edges: one pair is no edge (all or nothing)",
              katachi_mesh_set_edge_sharpnesses(m, bad_pairs, ok_values, 3),
              KATACHI_STATUS_BAD_INPUT, "no edge between vertices 0 and 7");
    CHECK_ERR("set edges: an index out of range",
              katachi_mesh_set_edge_sharpnesses(m, far_pairs, ok_values, 2),
              KATACHI_STATUS_INVALID_ARGUMENT, "edges[3] = 99 is out of range");
    CHECK_ERR("set edges: a pair with one vertex twice",
              katachi_mesh_set_edge_sharpnesses(m, same_pairs, ok_values, 1),
              KATACHI_STATUS_INVALID_ARGUMENT, "edges[0] and edges[1] are both vertex 5");
    CHECK_ERR("set edges: a negative value",
              katachi_mesh_set_edge_sharpnesses(m, CUBE_CORNERS, bad_values, 3),
              KATACHI_STATUS_BAD_INPUT, "sharpness -2 is invalid");

    /* katachi_mesh_copy_sharp_edges */
    memset(e, 0xCD, sizeof e);
    CHECK_ERR("copy sharp edges: mesh NULL", katachi_mesh_copy_sharp_edges(NULL, e, v, 4),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_copy_sharp_edges: mesh is NULL");
    CHECK_ERR("copy sharp edges: edges NULL", katachi_mesh_copy_sharp_edges(m, NULL, v, 4),
              KATACHI_STATUS_NULL_POINTER, "edges is NULL");
    CHECK_ERR("copy sharp edges: sharpness NULL", katachi_mesh_copy_sharp_edges(m, e, NULL, 4),
              KATACHI_STATUS_NULL_POINTER, "sharpness is NULL");
    CHECK_ERR("copy sharp edges: capacity 0", katachi_mesh_copy_sharp_edges(m, e, v, 0),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "capacity is 0 edges, but the mesh has 1 sharp edges");
    CHECK("copy sharp edges: untouched on failure", e[0] == 0xCDCDCDCDu);

    /* katachi_mesh_vertex_sharpness and its setters */
    CHECK_ERR("vertex sharpness: mesh NULL", katachi_mesh_vertex_sharpness(NULL, 0, &s),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_vertex_sharpness: mesh is NULL");
    CHECK_ERR("vertex sharpness: sharpness NULL", katachi_mesh_vertex_sharpness(m, 0, NULL),
              KATACHI_STATUS_NULL_POINTER, "sharpness is NULL");
    CHECK_ERR("vertex sharpness: out of range", katachi_mesh_vertex_sharpness(m, 8, &s),
              KATACHI_STATUS_INVALID_ARGUMENT, "vertex = 8 is out of range (the mesh has 8 vertices)");
    CHECK("vertex sharpness: output untouched on failure", s == 42.0);
    CHECK_ERR("set vertex sharpness: mesh NULL", katachi_mesh_set_vertex_sharpness(NULL, 0, 1.0),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_set_vertex_sharpness: mesh is NULL");
    CHECK_ERR("set vertex sharpness: out of range",
              katachi_mesh_set_vertex_sharpness(m, 0xFFFFFFFFu, 1.0),
              KATACHI_STATUS_INVALID_ARGUMENT, "vertex = 4294967295 is out of range");
    CHECK_ERR("set vertex sharpness: infinite", katachi_mesh_set_vertex_sharpness(m, 1, INFINITY),
              KATACHI_STATUS_BAD_INPUT, "vertex 1: sharpness inf is invalid");
    CHECK_ERR("copy vertex sharpness: mesh NULL", katachi_mesh_copy_vertex_sharpness(NULL, v, 8),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_copy_vertex_sharpness: mesh is NULL");
    CHECK_ERR("copy vertex sharpness: sharpness NULL",
              katachi_mesh_copy_vertex_sharpness(m, NULL, 8), KATACHI_STATUS_NULL_POINTER,
              "sharpness is NULL");
    CHECK_ERR("copy vertex sharpness: short", katachi_mesh_copy_vertex_sharpness(m, v, 7),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "room for 7 values, but 8 are needed");
    CHECK_ERR("set all vertex sharpness: mesh NULL",
              katachi_mesh_set_all_vertex_sharpness(NULL, vs_bad, 8), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_set_all_vertex_sharpness: mesh is NULL");
    CHECK_ERR("set all vertex sharpness: sharpness NULL",
              katachi_mesh_set_all_vertex_sharpness(m, NULL, 8), KATACHI_STATUS_NULL_POINTER,
              "sharpness is NULL but count is 8");
    CHECK_ERR("set all vertex sharpness: wrong count",
              katachi_mesh_set_all_vertex_sharpness(m, vs_bad, 7), KATACHI_STATUS_INVALID_ARGUMENT,
              "count is 7, but the mesh has 8 vertices");
    CHECK_ERR("set all vertex sharpness: a negative value (all or nothing)",
              katachi_mesh_set_all_vertex_sharpness(m, vs_bad, 8), KATACHI_STATUS_BAD_INPUT,
              "vertex 2: sharpness -1 is invalid");

    /* katachi_mesh_inspect */
    CHECK_ERR("inspect: mesh NULL", katachi_mesh_inspect(NULL, &info), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_inspect: mesh is NULL");
    CHECK_ERR("inspect: info NULL", katachi_mesh_inspect(m, NULL), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_inspect: info is NULL");
    info.struct_size = (uint32_t)sizeof(KatachiMeshInfo) - 8;
    info.edge_count = 777;
    CHECK_ERR("inspect: struct_size too small", katachi_mesh_inspect(m, &info),
              KATACHI_STATUS_INVALID_ARGUMENT, "info->struct_size is");
    CHECK("inspect: message names the fix", MESSAGE_HAS("katachi_mesh_info_default"));
    CHECK("inspect: untouched on failure", info.edge_count == 777);

    /* Nothing above changed the mesh. */
    after = snapshot(m);
    CHECK("the mesh is unchanged after every failed call", snapshots_equal(&before, &after));
    CHECK("the sharpness set before the failures is still there",
          after.counts.sharp_edge_count == 1 && after.edge_sharpness[0] == 4.0 &&
              after.vertex_sharpness[6] == 1.0);
    snapshot_free(&before);
    snapshot_free(&after);
    katachi_mesh_free(m);
}

int main(void)
{
    printf("katachi %s (ABI %u), mesh API from C99\n", katachi_version_string(),
           (unsigned)katachi_abi_version());
    test_versions_and_statuses();
    test_last_error_message();
    test_cube();
    test_plate_with_holes();
    test_other_shapes();
    test_clone();
    test_sharpness();
    test_create_bad_input();
    test_bad_arguments();
    return check_finish();
}
