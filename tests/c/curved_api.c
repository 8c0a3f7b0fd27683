/*
 * Curved meshing of trimmed Bézier patches through the C ABI (C99): the input built from
 * arrays (a bicubic patch, a square with a circular hole, two regions sharing a curve), the
 * result's counts, quality, nodes, elements and per-element data, writing MSH, and bad input
 * named in the message with nothing returned.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"

/* A bicubic patch over the unit square with a bump: Q_ij = (i/3, j/3, z_ij), u-major. */
static void bumpy_patch(double pts[16 * 3])
{
    int i, j;
    for (i = 0; i < 4; i++) {
        for (j = 0; j < 4; j++) {
            double *p = pts + 3 * (i * 4 + j);
            p[0] = i / 3.0;
            p[1] = j / 3.0;
            p[2] = (i > 0 && i < 3 && j > 0 && j < 3) ? 0.3 : 0.0;
        }
    }
}

#define CX 0.5
#define CY 0.5
#define R 0.2

/* The four clockwise cubic quarter arcs of the circle of radius R around (CX, CY). */
static void circle_arc(int k, double out[8])
{
    const double kappa = 0.5522847498307934;
    /* Directions at angles 0, -90, -180, -270 degrees (clockwise). */
    const double ex[4] = {1, 0, -1, 0}, ey[4] = {0, -1, 0, 1};
    double ax = ex[k], ay = ey[k], bx = ex[(k + 1) % 4], by = ey[(k + 1) % 4];
    /* Clockwise tangent at direction (x, y) is (y, -x). */
    out[0] = CX + R * ax;
    out[1] = CY + R * ay;
    out[2] = CX + R * (ax + kappa * ay);
    out[3] = CY + R * (ay - kappa * ax);
    out[4] = CX + R * (bx - kappa * by);
    out[5] = CY + R * (by + kappa * bx);
    out[6] = CX + R * bx;
    out[7] = CY + R * by;
}

/* Patch 0, curves 0-3 the square (0.1, 0.1)-(0.9, 0.9) counter-clockwise, 4-7 the hole. */
static KatachiCurvedInput *square_with_hole(double size)
{
    KatachiCurvedInput *in = NULL;
    double pts[48], arc[8];
    const double sq[5][2] = {{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.1, 0.9}, {0.1, 0.1}};
    uint32_t id = 99, k;
    uint32_t loop_sizes[2] = {4, 4};
    uint32_t curves[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    CHECK_OK("input_new", katachi_curved_input_new(&in));
    bumpy_patch(pts);
    CHECK_OK("add_patch", katachi_curved_input_add_patch(in, 3, 3, pts, 16, &id));
    CHECK("patch id 0", id == 0);
    for (k = 0; k < 4; k++) {
        double seg[4] = {sq[k][0], sq[k][1], sq[k + 1][0], sq[k + 1][1]};
        CHECK_OK("add a side", katachi_curved_input_add_curve(in, seg, 2, &id));
        CHECK("side ids in order", id == k);
    }
    for (k = 0; k < 4; k++) {
        circle_arc((int)k, arc);
        CHECK_OK("add an arc", katachi_curved_input_add_curve(in, arc, 4, NULL));
    }
    CHECK_OK("add_region", katachi_curved_input_add_region(in, 0, loop_sizes, 2, curves, NULL, 8,
                                                           &id));
    CHECK("region id 0", id == 0);
    CHECK_OK("isotropic metric", katachi_curved_input_set_metric_isotropic(in, size));
    return in;
}

static void test_square_with_hole(void)
{
    KatachiCurvedInput *in = square_with_hole(0.12);
    KatachiCurvedMesh *m = NULL;
    KatachiCurvedOptions o = katachi_curved_options_default();
    KatachiCurvedInfo info = katachi_curved_info_default();
    double *xyz, *uv, *angles;
    uint32_t *el, *regions, *kinds;
    uint32_t e, j, curved = 0, bad_ids = 0, on_circle = 0, off_circle = 0;
    double worst_straight = 180.0;
    FILE *f;
    char head[16] = {0};

    CHECK("default order 2", o.order == 2);
    CHECK("default B = 2", o.radius_edge_bound == 2.0);
    o.order = 3;
    o.sampled_quality = 0;
    CHECK_OK("mesh", katachi_curved_mesh(in, &o, &m));
    CHECK_OK("info", katachi_curved_mesh_info(m, &info));
    CHECK("order 3", info.order == 3 && info.nodes_per_element == 10);
    CHECK("some elements", info.element_count > 50 && info.node_count > info.element_count);
    CHECK("curved elements along the hole", info.curved_element_count >= 8);
    CHECK("guaranteed angle arcsin(1/4)", fabs(info.guaranteed_angle_degrees - 14.4775) < 1e-3);
    CHECK("the bound holds", info.min_angle_degrees >= info.guaranteed_angle_degrees - 1e-9);
    CHECK("median above 40 degrees", info.median_min_angle_degrees > 40.0);
    CHECK("nothing below the bound", info.share_below_14_48 == 0.0);
    CHECK("valid in parameter space", info.min_scaled_jacobian > 0.0);
    CHECK("valid on the surface", info.min_scaled_jacobian_surface > 0.0);

    /* (NULL, 0) asks the size. */
    CHECK_ERR("nodes: size query", katachi_curved_mesh_copy_nodes(m, 0, NULL, 0),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "3 per node");
    CHECK_ERR("nodes: bad space", katachi_curved_mesh_copy_nodes(m, 7, NULL, 0),
              KATACHI_STATUS_INVALID_ARGUMENT, "space is 7");

    xyz = malloc(sizeof(double) * 3 * info.node_count);
    uv = malloc(sizeof(double) * 3 * info.node_count);
    el = malloc(sizeof(uint32_t) * 10 * info.element_count);
    regions = malloc(sizeof(uint32_t) * info.element_count);
    kinds = malloc(sizeof(uint32_t) * info.element_count);
    angles = malloc(sizeof(double) * info.element_count);
    CHECK_OK("surface nodes", katachi_curved_mesh_copy_nodes(m, KATACHI_CURVED_SPACE_SURFACE, xyz,
                                                             3 * info.node_count));
    CHECK_OK("parameter nodes", katachi_curved_mesh_copy_nodes(
                                    m, KATACHI_CURVED_SPACE_PARAMETER, uv, 3 * info.node_count));
    CHECK_OK("elements", katachi_curved_mesh_copy_elements(m, el, 10 * info.element_count));
    CHECK_OK("element data",
             katachi_curved_mesh_copy_element_data(m, regions, info.element_count, kinds,
                                                   info.element_count, angles,
                                                   info.element_count));
    CHECK_ERR("element data: short buffer",
              katachi_curved_mesh_copy_element_data(m, regions, 1, NULL, 0, NULL, 0),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "regions");
    for (e = 0; e < info.element_count; e++) {
        const uint32_t *n = el + 10 * e;
        for (j = 0; j < 10; j++) {
            bad_ids += n[j] >= info.node_count;
        }
        if (bad_ids) {
            continue;
        }
        if (kinds[e] == 1) {
            /* Edge 0 (corner 0, nodes 3 and 4, corner 1) is on the curve: on the hole here. */
            const uint32_t edge[4] = {n[0], n[3], n[4], n[1]};
            curved++;
            for (j = 0; j < 4; j++) {
                double dx = uv[3 * edge[j]] - CX, dy = uv[3 * edge[j] + 1] - CY;
                /* The cubic arcs are within 2.8e-4 R of the circle. */
                if (fabs(sqrt(dx * dx + dy * dy) - R) < 3e-4 * R) {
                    on_circle++;
                } else {
                    off_circle++;
                }
            }
        } else if (angles[e] < worst_straight) {
            worst_straight = angles[e];
        }
    }
    CHECK("element node ids in range", bad_ids == 0);
    CHECK("kinds agree with the info", curved == info.curved_element_count);
    CHECK("curved edges on the circle", on_circle == 4 * curved && off_circle == 0);
    CHECK("straight elements meet the bound",
          info.exempt_element_count > 0 || worst_straight >= info.guaranteed_angle_degrees - 1e-9);
    for (e = 0; e < info.element_count; e++) {
        if (regions[e] != 0) {
            break;
        }
    }
    CHECK("one region", e == info.element_count);

    CHECK_OK("write msh", katachi_curved_mesh_write(m, "katachi_curved_api.msh",
                                                    KATACHI_CURVED_SPACE_SURFACE));
    f = fopen("katachi_curved_api.msh", "rb");
    CHECK("msh written", f != NULL);
    if (f != NULL) {
        CHECK("MSH 4.1", fread(head, 1, 15, f) == 15 && strncmp(head, "$MeshFormat\n4.1", 15) == 0);
        fclose(f);
    }
    remove("katachi_curved_api.msh");
    CHECK_ERR("write: unknown extension",
              katachi_curved_mesh_write(m, "katachi_curved_api.stl", 0),
              KATACHI_STATUS_INVALID_ARGUMENT, ".msh");
    CHECK_ERR("write: NULL path", katachi_curved_mesh_write(m, NULL, 0),
              KATACHI_STATUS_NULL_POINTER, "path");

    free(xyz);
    free(uv);
    free(el);
    free(regions);
    free(kinds);
    free(angles);
    katachi_curved_mesh_free(m);
    katachi_curved_input_free(in);
}

/* Two regions glued along a wavy cubic (curve 1), used forwards by the left region and
 * backwards by the right one: one call, the curve's nodes shared. */
static void test_two_regions(void)
{
    KatachiCurvedInput *in = NULL;
    KatachiCurvedMesh *m = NULL;
    KatachiCurvedOptions o = katachi_curved_options_default();
    KatachiCurvedInfo info = katachi_curved_info_default();
    double pts[48];
    const double c[7][8] = {
        {0.1, 0.1, 0.5, 0.1},
        {0.5, 0.1, 0.3, 0.4, 0.7, 0.6, 0.5, 0.9},
        {0.5, 0.9, 0.1, 0.9},
        {0.1, 0.9, 0.1, 0.1},
        {0.5, 0.1, 0.9, 0.1},
        {0.9, 0.1, 0.9, 0.9},
        {0.9, 0.9, 0.5, 0.9},
    };
    uint32_t k, left_sizes[1] = {4}, right_sizes[1] = {4};
    uint32_t left[4] = {0, 1, 2, 3}, right[4] = {4, 5, 6, 1};
    uint8_t right_rev[4] = {0, 0, 0, 1};
    uint32_t *regions, e, count[2] = {0, 0};
    CHECK_OK("input_new", katachi_curved_input_new(&in));
    bumpy_patch(pts);
    CHECK_OK("add_patch", katachi_curved_input_add_patch(in, 3, 3, pts, 16, NULL));
    for (k = 0; k < 7; k++) {
        CHECK_OK("add a curve", katachi_curved_input_add_curve(in, c[k], k == 1 ? 4 : 2, NULL));
    }
    CHECK_OK("left region",
             katachi_curved_input_add_region(in, 0, left_sizes, 1, left, NULL, 4, NULL));
    CHECK_OK("right region",
             katachi_curved_input_add_region(in, 0, right_sizes, 1, right, right_rev, 4, NULL));
    {
        const double dir[3] = {1.0, 0.3, 0.0};
        CHECK_OK("directional metric",
                 katachi_curved_input_set_metric_directional(in, dir, 0.2, 0.05));
    }
    o.sampled_quality = 0;
    CHECK_OK("mesh two regions", katachi_curved_mesh(in, &o, &m));
    CHECK_OK("info", katachi_curved_mesh_info(m, &info));
    CHECK("curved elements on both sides", info.curved_element_count >= 2);
    CHECK("the bound holds", info.min_angle_degrees >= info.guaranteed_angle_degrees - 1e-9);
    regions = malloc(sizeof(uint32_t) * info.element_count);
    CHECK_OK("regions", katachi_curved_mesh_copy_element_data(m, regions, info.element_count,
                                                              NULL, 0, NULL, 0));
    for (e = 0; e < info.element_count; e++) {
        if (regions[e] < 2) {
            count[regions[e]]++;
        }
    }
    CHECK("both regions meshed", count[0] > 0 && count[1] > 0 &&
                                     count[0] + count[1] == info.element_count);
    free(regions);
    katachi_curved_mesh_free(m);
    katachi_curved_input_free(in);
}

static void test_bad_input(void)
{
    KatachiCurvedInput *in = square_with_hole(0.12);
    KatachiCurvedMesh *m = (KatachiCurvedMesh *)&m; /* not NULL: must be reset */
    KatachiCurvedOptions o = katachi_curved_options_default();
    KatachiCurvedInfo info = katachi_curved_info_default();
    double pts[48] = {0}, open_seg[4] = {0.9, 0.9, 0.2, 0.9};
    double flat[48] = {0};
    uint32_t sizes[1] = {3}, uses[3] = {0, 1, 8};

    o.order = 11;
    CHECK_ERR("order 11", katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_INVALID_ARGUMENT,
              "options->order");
    CHECK("out reset", m == NULL);
    o = katachi_curved_options_default();
    o.small_angle_degrees = 200.0;
    CHECK_ERR("small angle 200", katachi_curved_mesh(in, &o, &m),
              KATACHI_STATUS_INVALID_ARGUMENT, "options->small_angle_degrees");
    o = katachi_curved_options_default();
    o.struct_size = 4;
    CHECK_ERR("struct_size", katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_INVALID_ARGUMENT,
              "katachi_curved_options_default");
    o = katachi_curved_options_default();
    o.max_sites = 20;
    CHECK_ERR("site budget", katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_BAD_INPUT,
              "options.max_sites");
    CHECK("no mesh", m == NULL);
    o = katachi_curved_options_default();
    CHECK_ERR("NULL input", katachi_curved_mesh(NULL, &o, &m), KATACHI_STATUS_NULL_POINTER,
              "input");
    CHECK_ERR("NULL options", katachi_curved_mesh(in, NULL, &m), KATACHI_STATUS_NULL_POINTER,
              "options");
    CHECK_ERR("NULL out", katachi_curved_mesh(in, &o, NULL), KATACHI_STATUS_NULL_POINTER, "out");

    CHECK_ERR("patch point count", katachi_curved_input_add_patch(in, 3, 3, flat, 15, NULL),
              KATACHI_STATUS_INVALID_ARGUMENT, "16 control points");
    CHECK_ERR("curve of one point", katachi_curved_input_add_curve(in, flat, 1, NULL),
              KATACHI_STATUS_INVALID_ARGUMENT, "at least 2");
    CHECK_ERR("NULL curve points", katachi_curved_input_add_curve(in, NULL, 3, NULL),
              KATACHI_STATUS_NULL_POINTER, "points_uv");
    CHECK_ERR("loop sizes that do not add up",
              katachi_curved_input_add_region(in, 0, sizes, 1, uses, NULL, 2, NULL),
              KATACHI_STATUS_INVALID_ARGUMENT, "use_count is 2");

    katachi_curved_input_free(in);

    /* A loop that does not close: curve 2 ends at (0.2, 0.9), not where curve 0 starts. */
    CHECK_OK("input_new", katachi_curved_input_new(&in));
    bumpy_patch(pts);
    CHECK_OK("patch", katachi_curved_input_add_patch(in, 3, 3, pts, 16, NULL));
    {
        const double seg[2][4] = {{0.1, 0.1, 0.9, 0.1}, {0.9, 0.1, 0.9, 0.9}};
        CHECK_OK("side 0", katachi_curved_input_add_curve(in, seg[0], 2, NULL));
        CHECK_OK("side 1", katachi_curved_input_add_curve(in, seg[1], 2, NULL));
        CHECK_OK("side 2", katachi_curved_input_add_curve(in, open_seg, 2, NULL));
    }
    uses[2] = 2;
    CHECK_OK("a region that does not close",
             katachi_curved_input_add_region(in, 0, sizes, 1, uses, NULL, 3, NULL));
    CHECK_ERR("loop not closed", katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_BAD_INPUT,
              "region 0, loop 0 is not closed: use 2 (curve 2)");
    katachi_curved_input_free(in);

    /* Every metric setter: wrong sample counts are refused at once, tensors that are not
     * positive definite when meshing, naming the sample. */
    in = square_with_hole(0.12);
    {
        const double lo3[3] = {0, 0, -1}, hi3[3] = {1, 1, 1}, lo2[2] = {0, 0}, hi2[2] = {1, 1};
        const uint32_t n3[3] = {2, 2, 2}, n2[2] = {2, 2};
        double sizes[8], tensors[8 * 6], uvt[4 * 3];
        const double not_spd[6] = {1, 0, 0, -1, 0, 1};
        uint32_t k;
        for (k = 0; k < 8; k++) {
            const double t[6] = {100, 0, 0, 100, 0, 100};
            sizes[k] = 0.1;
            memcpy(tensors + 6 * k, t, sizeof t);
        }
        for (k = 0; k < 4; k++) {
            uvt[3 * k] = 40.0;
            uvt[3 * k + 1] = 0.0;
            uvt[3 * k + 2] = 40.0 + 10.0 * k;
        }
        CHECK_ERR("size grid: count", katachi_curved_input_set_metric_size_grid(in, lo3, hi3, n3,
                                                                                sizes, 7),
                  KATACHI_STATUS_INVALID_ARGUMENT, "8 samples");
        CHECK_OK("size grid", katachi_curved_input_set_metric_size_grid(in, lo3, hi3, n3, sizes, 8));
        CHECK_ERR("tensor grid: count",
                  katachi_curved_input_set_metric_tensor_grid(in, lo3, hi3, n3, tensors, 9),
                  KATACHI_STATUS_INVALID_ARGUMENT, "8 samples");
        tensors[6 * 5 + 3] = -1.0;
        CHECK_OK("tensor grid", katachi_curved_input_set_metric_tensor_grid(in, lo3, hi3, n3,
                                                                            tensors, 8));
        CHECK_ERR("tensor grid: a sample not positive definite",
                  katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_BAD_INPUT, "metric");
        CHECK_OK("tensor", katachi_curved_input_set_metric_tensor(in, not_spd));
        CHECK_ERR("tensor not positive definite", katachi_curved_mesh(in, &o, &m),
                  KATACHI_STATUS_BAD_INPUT, "metric");
        CHECK_ERR("uv tensor grid: count",
                  katachi_curved_input_set_metric_uv_tensor_grid(in, lo2, hi2, n2, uvt, 3),
                  KATACHI_STATUS_INVALID_ARGUMENT, "4 samples");
        CHECK_OK("uv tensor grid",
                 katachi_curved_input_set_metric_uv_tensor_grid(in, lo2, hi2, n2, uvt, 4));
        o.sampled_quality = 0;
        CHECK_OK("mesh with the uv tensor grid", katachi_curved_mesh(in, &o, &m));
        CHECK_OK("info", katachi_curved_mesh_info(m, &info));
        CHECK("the bound holds", info.min_angle_degrees >= info.guaranteed_angle_degrees - 1e-9);
        katachi_curved_mesh_free(m);
        o = katachi_curved_options_default();
        info = katachi_curved_info_default();
    }
    katachi_curved_input_free(in);

    in = square_with_hole(-1.0);
    CHECK_ERR("negative size", katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_BAD_INPUT,
              "metric");
    katachi_curved_input_free(in);

    /* A collapsed patch (all control points equal). */
    CHECK_OK("input_new", katachi_curved_input_new(&in));
    CHECK_OK("a collapsed patch", katachi_curved_input_add_patch(in, 3, 3, flat, 16, NULL));
    {
        const double tri[3][4] = {{0.2, 0.2, 0.8, 0.2}, {0.8, 0.2, 0.5, 0.8}, {0.5, 0.8, 0.2, 0.2}};
        uint32_t s[1] = {3}, u[3] = {0, 1, 2}, k;
        for (k = 0; k < 3; k++) {
            CHECK_OK("a side", katachi_curved_input_add_curve(in, tri[k], 2, NULL));
        }
        CHECK_OK("region", katachi_curved_input_add_region(in, 0, s, 1, u, NULL, 3, NULL));
    }
    CHECK_ERR("degenerate patch", katachi_curved_mesh(in, &o, &m), KATACHI_STATUS_BAD_INPUT,
              "patch 0");
    katachi_curved_input_free(in);

    info.struct_size = 8;
    CHECK_ERR("info of NULL", katachi_curved_mesh_info(NULL, &info), KATACHI_STATUS_NULL_POINTER,
              "mesh");
    katachi_curved_mesh_free(NULL);
    katachi_curved_input_free(NULL);
}

int main(void)
{
    printf("katachi %s, curved meshing from C99\n", katachi_version_string());
    test_square_with_hole();
    test_two_regions();
    test_bad_input();
    return check_finish();
}
