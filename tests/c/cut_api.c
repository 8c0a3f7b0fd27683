/*
 * The stroke cut through the C ABI (C99): katachi_cut_by_stroke on a grid seen from above,
 * its result handle (info, mesh, face origins, paths, moved vertices, dropped stroke points),
 * carrying UVs and vertex data through the cut, opening, closed strokes, and bad input.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "snapshot.h"

/* A 4 × 4 grid of unit squares in the plane z = 0, each square two counter-clockwise
 * triangles: vertex j*5 + i is (i, j, 0); 25 vertices, 32 triangles, 96 corners. */
#define GRID_N 4
#define GRID_V ((GRID_N + 1) * (GRID_N + 1))
#define GRID_F (2 * GRID_N * GRID_N)

static double grid_positions[GRID_V * 3];
static uint32_t grid_corners[GRID_F * 3];

static void make_grid_positions(void)
{
    uint32_t i, j;
    for (j = 0; j <= GRID_N; j++) {
        for (i = 0; i <= GRID_N; i++) {
            grid_positions[3 * (j * (GRID_N + 1) + i)] = (double)i;
            grid_positions[3 * (j * (GRID_N + 1) + i) + 1] = (double)j;
            grid_positions[3 * (j * (GRID_N + 1) + i) + 2] = 0.0;
        }
    }
}

static KatachiMesh *make_grid(void)
{
    KatachiMesh *m = NULL;
    uint32_t loop_sizes[GRID_F], face_loops[GRID_F];
    uint32_t i, j, k = 0;
    make_grid_positions();
    for (j = 0; j < GRID_N; j++) {
        for (i = 0; i < GRID_N; i++) {
            uint32_t v = j * (GRID_N + 1) + i;
            uint32_t tris[6] = {v, v + 1, v + GRID_N + 2, v, v + GRID_N + 2, v + GRID_N + 1};
            memcpy(grid_corners + k, tris, sizeof tris);
            k += 6;
        }
    }
    for (i = 0; i < GRID_F; i++) {
        loop_sizes[i] = 3;
        face_loops[i] = 1;
    }
    CHECK_OK("create the grid", katachi_mesh_create(grid_positions, GRID_V, loop_sizes, GRID_F,
                                                    face_loops, GRID_F, grid_corners,
                                                    GRID_F * 3, &m));
    return m;
}

/* Seen from above, orthographic: x in [-0.5, 4.5] and y in [-0.5, 4.5] fill a 500 × 500
 * viewport, so world (x, y) is pixel (50 + 100 x, 450 - 100 y) (top-left origin, y down).
 * Column-major; OpenGL NDC; the eye looks down -z. */
static const double VIEW_PROJ[16] = {
    0.4, 0.0, 0.0,  0.0, /* column 0 */
    0.0, 0.4, 0.0,  0.0, /* column 1 */
    0.0, 0.0, -0.1, 0.0, /* column 2 */
    -0.8, -0.8, 0.0, 1.0, /* column 3 */
};
static const double VIEWPORT[4] = {0.0, 0.0, 500.0, 500.0};

static double px_x(double x) { return 50.0 + 100.0 * x; }
static double px_y(double y) { return 450.0 - 100.0 * y; }

/* The straight stroke from A to B (pixels), sampled at 11 points, with a point 1 px after
 * point 3 (index 4) that preprocessing drops. Both ends are off the grid. */
#define AX 20.0
#define AY 330.0
#define BX 480.0
#define BY 140.0
#define STROKE_POINTS 12

static void make_stroke(double *s)
{
    int i, k = 0;
    for (i = 0; i <= 10; i++) {
        double t = i / 10.0;
        s[2 * k] = AX + t * (BX - AX);
        s[2 * k + 1] = AY + t * (BY - AY);
        k++;
        if (i == 3) {
            double len = hypot(BX - AX, BY - AY);
            s[2 * k] = s[2 * (k - 1)] + (BX - AX) / len;
            s[2 * k + 1] = s[2 * (k - 1) + 1] + (BY - AY) / len;
            k++;
        }
    }
}

/* Distance in pixels from pixel (x, y) to the stroke's line, and its parameter along it. */
static double line_distance(double x, double y, double *t)
{
    double dx = BX - AX, dy = BY - AY, len2 = dx * dx + dy * dy;
    *t = ((x - AX) * dx + (y - AY) * dy) / len2;
    return fabs((x - AX) * dy - (y - AY) * dx) / sqrt(len2);
}

/* Whether u-w is an edge of a face of the triangle mesh `corners`. */
static int is_edge(const uint32_t *corners, uint32_t face_count, uint32_t u, uint32_t w)
{
    uint32_t f, k;
    for (f = 0; f < face_count; f++) {
        for (k = 0; k < 3; k++) {
            uint32_t a = corners[3 * f + k], b = corners[3 * f + (k + 1) % 3];
            if ((a == u && b == w) || (a == w && b == u)) {
                return 1;
            }
        }
    }
    return 0;
}

static int contains(const uint32_t *list, uint32_t n, uint32_t x)
{
    uint32_t i;
    for (i = 0; i < n; i++) {
        if (list[i] == x) {
            return 1;
        }
    }
    return 0;
}

static void test_grid_cut(void)
{
    KatachiMesh *grid = make_grid();
    Snapshot before = snapshot(grid), after;
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = NULL;
    KatachiCutInfo info = katachi_cut_info_default();
    KatachiMesh *out = NULL;
    KatachiMeshCounts counts = katachi_mesh_counts_default();
    KatachiMeshInfo mi = katachi_mesh_info_default();
    double stroke[2 * STROKE_POINTS];
    double *pos, *from, *to, *pixels, *uv_in, *uv_out, *vd_out;
    uint32_t *ls, *flc, *corners, *origin, *offsets, *path, *moved, *pieces, *closed;
    uint32_t *dropped[4];
    uint32_t dropped_count[4];
    uint32_t i, k, s;
    int ok;

    make_stroke(stroke);
    CHECK("defaults: visible-only, closed cut, no limit, the paper's ratios",
          o.struct_size == sizeof(KatachiCutOptions) && o.mode == KATACHI_CUT_MODE_VISIBLE_ONLY &&
              o.open == 0 && o.max_faces_split == UINT32_MAX && o.snap_vertex_ratio == 0.3 &&
              o.snap_segment_ratio == 0.3 && o.corner_angle_degrees == 60.0 &&
              o.min_stroke_px == 2.0 && o.depth_eps_rel == 1e-4);
    CHECK("info default", info.struct_size == sizeof(KatachiCutInfo) && info.face_count == 0);
    if (!CHECK_OK("cut the grid",
                  katachi_cut_by_stroke(grid, stroke, STROKE_POINTS, VIEW_PROJ, VIEWPORT, &o,
                                        &cut))) {
        katachi_mesh_free(grid);
        snapshot_free(&before);
        return;
    }
    after = snapshot(grid);
    CHECK("the input mesh is unchanged by a cut", snapshots_equal(&before, &after));
    snapshot_free(&after);

    CHECK_OK("info", katachi_cut_info(cut, &info));
    printf("     cut: %u vertices (%u new), %u faces (%u new, %u split), %u moved (max %.3g px), "
           "%u paths of %u vertices, dropped %u/%u/%u/%u, L = %.4g px\n",
           info.vertex_count, info.new_vertex_count, info.face_count, info.new_face_count,
           info.split_face_count, info.moved_vertex_count, info.max_move_px, info.path_count,
           info.path_vertex_count, info.dropped_preprocessing_count,
           info.dropped_first_normalization_count, info.dropped_second_normalization_count,
           info.dropped_off_mesh_count, info.mean_edge_length_px);
    CHECK("input counts", info.input_vertex_count == GRID_V && info.input_corner_count == GRID_F * 3);
    CHECK("result counts add up",
          info.vertex_count == GRID_V + info.new_vertex_count &&
              info.face_count == GRID_F + info.new_face_count &&
              info.corner_count == 3 * info.face_count);
    CHECK("something was split", info.new_vertex_count > 0 && info.split_face_count > 0 &&
                                     info.new_face_count >= info.split_face_count);
    CHECK("at most 3 pieces per split triangle (seed 002)",
          info.new_face_count <= 2 * info.split_face_count);
    CHECK("one piece, one open path", info.piece_count == 1 && info.path_count == 1);
    CHECK("every path stretch is an edge", info.unjoined_count == 0);
    CHECK("nothing clipped or degenerate",
          info.clipped_face_count == 0 && info.degenerate_face_count == 0);
    /* L: the mean screen length of edges of 100 px and 100·√2 px; 100 px per world unit. */
    CHECK("L is a mean of the grid's screen edge lengths, 100 times the world one",
          info.mean_edge_length_px > 100.0 && info.mean_edge_length_px < 100.0 * sqrt(2.0) &&
              fabs(info.mean_edge_length_px - 100.0 * info.mean_edge_length_world) < 1e-9);

    /* The result mesh. */
    CHECK_OK("result mesh", katachi_cut_mesh(cut, &out));
    CHECK_OK("result counts", katachi_mesh_counts(out, &counts));
    CHECK("the mesh has the info's counts",
          counts.vertex_count == info.vertex_count && counts.face_count == info.face_count &&
              counts.corner_count == info.corner_count && counts.loop_count == info.face_count);
    CHECK_OK("inspect the result", katachi_mesh_inspect(out, &mi));
    CHECK("still one manifold disk (V - E + F unchanged)",
          mi.is_manifold && mi.component_count == 1 && mi.euler_characteristic == 1 &&
              mi.boundary_loop_count == 1 && mi.zero_area_face_count == 0);
    pos = alloc(3 * (size_t)info.vertex_count, sizeof *pos);
    ls = alloc(info.face_count, sizeof *ls);
    flc = alloc(info.face_count, sizeof *flc);
    corners = alloc(info.corner_count, sizeof *corners);
    CHECK_OK("result positions", katachi_mesh_copy_positions(out, pos, 3 * (size_t)info.vertex_count));
    CHECK_OK("result faces", katachi_mesh_copy_faces(out, ls, info.face_count, flc, info.face_count,
                                                   corners, info.corner_count));

    /* Face origins: the input's triangles keep their slots; appended pieces name theirs. */
    origin = alloc(info.face_count, sizeof *origin);
    CHECK_ERR("face origin: short buffer",
              katachi_cut_copy_face_origin(cut, origin, info.face_count - 1),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "faces");
    CHECK_OK("face origin", katachi_cut_copy_face_origin(cut, origin, info.face_count));
    ok = 1;
    for (i = 0; i < info.face_count; i++) {
        ok = ok && (i < GRID_F ? origin[i] == i : origin[i] < GRID_F);
    }
    CHECK("face origins: slot kept, pieces name an input face", ok);
    /* Every face lies inside its origin: its centroid is in the origin triangle's square cell. */
    ok = 1;
    for (i = 0; i < info.face_count; i++) {
        double cx = 0, cy = 0;
        uint32_t cell = origin[i] / 2;
        for (k = 0; k < 3; k++) {
            cx += pos[3 * corners[3 * i + k]] / 3.0;
            cy += pos[3 * corners[3 * i + k] + 1] / 3.0;
        }
        ok = ok && cx >= (double)(cell % GRID_N) - 0.35 && cx <= (double)(cell % GRID_N) + 1.35 &&
             cy >= (double)(cell / GRID_N) - 0.35 && cy <= (double)(cell / GRID_N) + 1.35;
    }
    CHECK("each face lies in (the snapped cell of) its origin", ok);

    /* Moved vertices: onto the stroke, parallel to the screen, within the snap distance. */
    moved = alloc(info.moved_vertex_count, sizeof *moved);
    from = alloc(3 * (size_t)info.moved_vertex_count, sizeof *from);
    to = alloc(3 * (size_t)info.moved_vertex_count, sizeof *to);
    pixels = alloc(info.moved_vertex_count, sizeof *pixels);
    CHECK("some vertices snapped", info.moved_vertex_count > 0);
    if (info.moved_vertex_count > 0) {
        CHECK_ERR("moved: short buffer",
                  katachi_cut_copy_moved_vertices(cut, moved, from, to, pixels,
                                                  info.moved_vertex_count - 1),
                  KATACHI_STATUS_BUFFER_TOO_SMALL, "moved_vertex_count");
    }
    CHECK_OK("moved vertices", katachi_cut_copy_moved_vertices(cut, moved, from, to, pixels,
                                                               info.moved_vertex_count));
    ok = 1;
    {
        double largest = 0.0;
        for (i = 0; i < info.moved_vertex_count; i++) {
            uint32_t v = moved[i];
            double t, d = line_distance(px_x(to[3 * i]), px_y(to[3 * i + 1]), &t);
            double dpx = hypot(px_x(to[3 * i]) - px_x(from[3 * i]),
                               px_y(to[3 * i + 1]) - px_y(from[3 * i + 1]));
            ok = ok && v < GRID_V && (i == 0 || moved[i - 1] < v);
            ok = ok && memcmp(from + 3 * i, grid_positions + 3 * v, 3 * sizeof(double)) == 0;
            ok = ok && memcmp(to + 3 * i, pos + 3 * v, 3 * sizeof(double)) == 0;
            ok = ok && d < 1e-9 && fabs(to[3 * i + 2]) < 1e-12;
            ok = ok && fabs(dpx - pixels[i]) < 1e-9 && pixels[i] <= 0.3 * info.mean_edge_length_px + 1e-9;
            if (pixels[i] > largest) {
                largest = pixels[i];
            }
        }
        CHECK("moved vertices: ascending, from = input, to = output, on the stroke, z kept, "
              "within 0.3 L",
              ok);
        CHECK("max_move_px is the largest move", largest == info.max_move_px);
    }
    ok = 1;
    for (i = 0; i < GRID_V; i++) {
        if (!contains(moved, info.moved_vertex_count, i)) {
            ok = ok && memcmp(pos + 3 * i, grid_positions + 3 * i, 3 * sizeof(double)) == 0;
        }
    }
    CHECK("vertices not moved keep their positions bit for bit", ok);

    /* Paths: result vertices along the stroke's line, in stroke order, joined by edges. */
    offsets = alloc(info.path_count + 1, sizeof *offsets);
    path = alloc(info.path_vertex_count, sizeof *path);
    pieces = alloc(info.path_count, sizeof *pieces);
    closed = alloc(info.path_count, sizeof *closed);
    CHECK_ERR("paths: short offsets", katachi_cut_copy_paths(cut, offsets, info.path_count, path,
                                                             info.path_vertex_count),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "offsets");
    CHECK_ERR("paths: size query", katachi_cut_copy_paths(cut, offsets, info.path_count + 1, NULL, 0),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "vertices");
    CHECK_OK("paths", katachi_cut_copy_paths(cut, offsets, info.path_count + 1, path,
                                             info.path_vertex_count));
    CHECK("path offsets", offsets[0] == 0 && offsets[info.path_count] == info.path_vertex_count);
    CHECK_OK("path pieces", katachi_cut_copy_path_pieces(cut, pieces, closed, info.path_count));
    CHECK("the path is piece 0, open", pieces[0] == 0 && closed[0] == 0);
    {
        double last_t = -1.0;
        ok = info.path_vertex_count >= 2;
        for (k = offsets[0]; k < offsets[1]; k++) {
            uint32_t v = path[k];
            double t, d = line_distance(px_x(pos[3 * v]), px_y(pos[3 * v + 1]), &t);
            ok = ok && v < info.vertex_count && d < 1e-9 && t > last_t;
            last_t = t;
            if (k > offsets[0]) {
                ok = ok && is_edge(corners, info.face_count, path[k - 1], v);
            }
        }
        CHECK("path vertices lie on the stroke in stroke order, consecutive ones share an edge",
              ok);
        /* Both ends are on the grid's boundary (the stroke starts and ends off the grid): a
         * boundary vertex of the input (which snapping may have slid off the line x = 0), or
         * a new vertex on a boundary edge. */
        ok = 1;
        for (k = 0; k < 2; k++) {
            uint32_t v = path[k == 0 ? offsets[0] : offsets[1] - 1];
            const double *p = v < GRID_V ? grid_positions + 3 * v : pos + 3 * v;
            ok = ok && (fabs(p[0]) < 1e-12 || fabs(p[0] - GRID_N) < 1e-12 || fabs(p[1]) < 1e-12 ||
                        fabs(p[1] - GRID_N) < 1e-12);
        }
        CHECK("the path runs boundary to boundary", ok);
    }

    /* Dropped stroke points, by stage. */
    dropped_count[0] = info.dropped_preprocessing_count;
    dropped_count[1] = info.dropped_first_normalization_count;
    dropped_count[2] = info.dropped_second_normalization_count;
    dropped_count[3] = info.dropped_off_mesh_count;
    ok = 1;
    for (s = 0; s < 4; s++) {
        dropped[s] = alloc(dropped_count[s], sizeof(uint32_t));
        ok = ok && katachi_cut_copy_dropped_points(cut, s, dropped[s], dropped_count[s]) ==
                       KATACHI_STATUS_OK;
        for (i = 0; i < dropped_count[s]; i++) {
            ok = ok && dropped[s][i] < STROKE_POINTS && (i == 0 || dropped[s][i - 1] < dropped[s][i]);
        }
    }
    CHECK("dropped points: four stages, ascending stroke indices", ok);
    ok = 1;
    for (i = 0; i < STROKE_POINTS; i++) {
        int stages = 0;
        for (s = 0; s < 4; s++) {
            stages += contains(dropped[s], dropped_count[s], i);
        }
        ok = ok && stages <= 1;
    }
    CHECK("a point is dropped by at most one stage", ok);
    CHECK("preprocessing drops the point 1 px after point 3",
          dropped_count[0] == 1 && dropped[0][0] == 4);
    CHECK("the ends, off the grid, are dropped as off-mesh",
          contains(dropped[3], dropped_count[3], 0) &&
              contains(dropped[3], dropped_count[3], STROKE_POINTS - 1));
    CHECK("points inside faces are dropped by the first normalization", dropped_count[1] > 0);
    CHECK_ERR("dropped points: stage 9", katachi_cut_copy_dropped_points(cut, 9, dropped[0], 99),
              KATACHI_STATUS_INVALID_ARGUMENT, "stage is 9");
    for (s = 0; s < 4; s++) {
        free(dropped[s]);
    }

    /* Corner data: UV = (x, y) of the input positions, a linear function of position. A result
     * corner at an input vertex gets that vertex's UV exactly (its position before snapping);
     * at a new vertex, the blend over its source triangle, measured on the result positions:
     * (x, y) itself where no corner of that triangle moved, within the largest move elsewhere. */
    uv_in = alloc(GRID_F * 3 * 2, sizeof *uv_in);
    uv_out = alloc(2 * (size_t)info.corner_count, sizeof *uv_out);
    for (i = 0; i < GRID_F * 3; i++) {
        uv_in[2 * i] = grid_positions[3 * grid_corners[i]];
        uv_in[2 * i + 1] = grid_positions[3 * grid_corners[i] + 1];
    }
    CHECK_ERR("corner data: size query",
              katachi_cut_interpolate_corner_data(cut, uv_in, GRID_F * 3 * 2, 2, NULL, 0),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "corner_count");
    CHECK_ERR("corner data: wrong value count",
              katachi_cut_interpolate_corner_data(cut, uv_in, GRID_F * 3 * 2 - 1, 2, uv_out,
                                                  2 * (size_t)info.corner_count),
              KATACHI_STATUS_INVALID_ARGUMENT, "96 corners");
    CHECK_ERR("corner data: dim 0",
              katachi_cut_interpolate_corner_data(cut, uv_in, GRID_F * 3 * 2, 0, uv_out,
                                                  2 * (size_t)info.corner_count),
              KATACHI_STATUS_INVALID_ARGUMENT, "dim");
    CHECK_ERR("corner data: NULL values",
              katachi_cut_interpolate_corner_data(cut, NULL, GRID_F * 3 * 2, 2, uv_out,
                                                  2 * (size_t)info.corner_count),
              KATACHI_STATUS_NULL_POINTER, "values");
    CHECK_OK("corner data", katachi_cut_interpolate_corner_data(cut, uv_in, GRID_F * 3 * 2, 2, uv_out,
                                                                2 * (size_t)info.corner_count));
    {
        int at_input = 1, exact_new = 1, near_new = 1;
        for (i = 0; i < info.corner_count; i++) {
            uint32_t v = corners[i], f = origin[i / 3];
            double u = uv_out[2 * i], w = uv_out[2 * i + 1];
            if (v < GRID_V) {
                at_input = at_input && u == grid_positions[3 * v] && w == grid_positions[3 * v + 1];
            } else {
                int src_moved = 0;
                for (k = 0; k < 3; k++) {
                    src_moved |= contains(moved, info.moved_vertex_count, grid_corners[3 * f + k]);
                }
                if (!src_moved) {
                    exact_new = exact_new && fabs(u - pos[3 * v]) < 1e-12 &&
                                fabs(w - pos[3 * v + 1]) < 1e-12;
                }
                near_new = near_new && hypot(u - pos[3 * v], w - pos[3 * v + 1]) <=
                                           info.max_move_world + 1e-12;
            }
        }
        CHECK("UVs at input vertices are the input's, exactly", at_input);
        CHECK("UVs at new vertices in unmoved triangles are their (x, y)", exact_new);
        CHECK("UVs at new vertices are within the largest move of their (x, y)", near_new);
    }

    /* Vertex data: the input positions themselves. */
    vd_out = alloc(3 * (size_t)info.vertex_count, sizeof *vd_out);
    CHECK_ERR("vertex data: wrong value count",
              katachi_cut_interpolate_vertex_data(cut, grid_positions, GRID_V * 3 - 3, 3, vd_out,
                                                  3 * (size_t)info.vertex_count),
              KATACHI_STATUS_INVALID_ARGUMENT, "25 vertices");
    CHECK_ERR("vertex data: short output",
              katachi_cut_interpolate_vertex_data(cut, grid_positions, GRID_V * 3, 3, vd_out, 3),
              KATACHI_STATUS_BUFFER_TOO_SMALL, "vertex_count");
    CHECK_OK("vertex data", katachi_cut_interpolate_vertex_data(cut, grid_positions, GRID_V * 3, 3,
                                                                vd_out, 3 * (size_t)info.vertex_count));
    ok = memcmp(vd_out, grid_positions, sizeof grid_positions) == 0;
    for (i = GRID_V; i < info.vertex_count; i++) {
        ok = ok && hypot(vd_out[3 * i] - pos[3 * i], vd_out[3 * i + 1] - pos[3 * i + 1]) <=
                       info.max_move_world + 1e-12 &&
             vd_out[3 * i + 2] == 0.0;
    }
    CHECK("vertex data: input vertices keep theirs, new ones are blends", ok);

    free(pos);
    free(ls);
    free(flc);
    free(corners);
    free(origin);
    free(moved);
    free(from);
    free(to);
    free(pixels);
    free(offsets);
    free(path);
    free(pieces);
    free(closed);
    free(uv_in);
    free(uv_out);
    free(vd_out);
    katachi_mesh_free(out);
    katachi_cut_free(cut);
    after = snapshot(grid);
    CHECK("the input mesh is unchanged after reading the result", snapshots_equal(&before, &after));
    snapshot_free(&after);
    snapshot_free(&before);
    katachi_mesh_free(grid);
}

/* Opening: a boundary-to-boundary cut splits the disk in two; a closed stroke cuts out a disk. */
static void test_open_and_closed(void)
{
    KatachiMesh *grid = make_grid();
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = NULL;
    KatachiCutInfo info = katachi_cut_info_default();
    KatachiMesh *out = NULL;
    KatachiMeshInfo mi = katachi_mesh_info_default();
    double stroke[2 * STROKE_POINTS];
    double loop[2 * 25];
    uint32_t pieces[4], closed[4];
    int i;

    make_stroke(stroke);
    o.open = 1;
    o.mode = KATACHI_CUT_MODE_THROUGH_ALL;
    CHECK_OK("open cut", katachi_cut_by_stroke(grid, stroke, STROKE_POINTS, VIEW_PROJ, VIEWPORT, &o,
                                               &cut));
    CHECK_OK("open cut: info", katachi_cut_info(cut, &info));
    CHECK_OK("open cut: mesh", katachi_cut_mesh(cut, &out));
    CHECK_OK("open cut: inspect", katachi_mesh_inspect(out, &mi));
    CHECK("open cut: two disks", mi.component_count == 2 && mi.euler_characteristic == 2 &&
                                     mi.boundary_loop_count == 2 && mi.is_manifold);
    CHECK("open cut: path vertices were duplicated",
          info.vertex_count == GRID_V + info.new_vertex_count &&
              mi.vertex_count == info.vertex_count);
    {
        /* Every copy sits where its original does, and every other vertex is its own
           original. Boundary to boundary, every path vertex splits in two (its ends too). */
        uint32_t *orig = alloc(info.vertex_count, sizeof *orig);
        double *pos = alloc(3 * (size_t)info.vertex_count, sizeof *pos);
        uint32_t v, copies = 0;
        int same = 1;
        CHECK_ERR("vertex original: short buffer",
                  katachi_cut_copy_vertex_original(cut, orig, info.vertex_count - 1),
                  KATACHI_STATUS_BUFFER_TOO_SMALL, "vertices");
        CHECK_OK("vertex original", katachi_cut_copy_vertex_original(cut, orig, info.vertex_count));
        CHECK_OK("open cut: positions",
                 katachi_mesh_copy_positions(out, pos, 3 * (size_t)info.vertex_count));
        for (v = 0; v < info.vertex_count; v++) {
            if (orig[v] != v) {
                copies++;
                same = same && orig[v] < v && orig[orig[v]] == orig[v] &&
                       pos[3 * v] == pos[3 * orig[v]] && pos[3 * v + 1] == pos[3 * orig[v] + 1] &&
                       pos[3 * v + 2] == pos[3 * orig[v] + 2];
            }
        }
        CHECK("open cut: copies sit on their originals", same && copies > 0);
        CHECK("open cut: one copy per path vertex", copies == info.path_vertex_count);
        free(orig);
        free(pos);
    }
    katachi_mesh_free(out);
    out = NULL;
    katachi_cut_free(cut);
    cut = NULL;

    /* A circle of radius 1.3 around the grid's centre, counter-clockwise on screen. */
    for (i = 0; i < 24; i++) {
        double a = 2.0 * 3.14159265358979323846 * i / 24.0;
        loop[2 * i] = px_x(2.0 + 1.3 * cos(a));
        loop[2 * i + 1] = px_y(2.0 + 1.3 * sin(a));
    }
    loop[48] = loop[0];
    loop[49] = loop[1];
    o = katachi_cut_options_default();
    o.open = 1;
    CHECK_OK("closed stroke", katachi_cut_by_stroke(grid, loop, 25, VIEW_PROJ, VIEWPORT, &o, &cut));
    CHECK_OK("closed stroke: info", katachi_cut_info(cut, &info));
    CHECK("closed stroke: one path", info.path_count == 1);
    CHECK_OK("closed stroke: pieces", katachi_cut_copy_path_pieces(cut, pieces, closed, 4));
    CHECK("closed stroke: the path is closed", closed[0] == 1);
    CHECK_OK("closed stroke: mesh", katachi_cut_mesh(cut, &out));
    CHECK_OK("closed stroke: inspect", katachi_mesh_inspect(out, &mi));
    CHECK("closed stroke opened: a disk and an annulus",
          mi.component_count == 2 && mi.euler_characteristic == 1 && mi.boundary_loop_count == 3);
    katachi_mesh_free(out);
    katachi_cut_free(cut);

    /* A stroke that misses the grid: success, nothing cut. */
    {
        const double away[4] = {5.0, 480.0, 40.0, 495.0};
        CHECK_OK("stroke off the mesh", katachi_cut_by_stroke(grid, away, 2, VIEW_PROJ, VIEWPORT,
                                                              &o, &cut));
        CHECK_OK("stroke off the mesh: info", katachi_cut_info(cut, &info));
        CHECK("stroke off the mesh: nothing cut",
              info.path_count == 0 && info.face_count == GRID_F && info.vertex_count == GRID_V &&
                  info.moved_vertex_count == 0 && info.dropped_off_mesh_count == 2);
        katachi_cut_free(cut);
    }
    katachi_mesh_free(grid);
}

/* Without snapping nothing moves, so a linear function of position carried as corner data
 * (UV = (x, y)) equals (x, y) at every result corner, and as vertex data equals the
 * positions. On the grid's quads, which the cut triangulates first. */
static void test_interpolation_without_snapping(void)
{
    KatachiMesh *quads = NULL;
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = NULL;
    KatachiCutInfo info = katachi_cut_info_default();
    KatachiMesh *out = NULL;
    double stroke[2 * STROKE_POINTS];
    uint32_t loop_sizes[GRID_N * GRID_N], face_loops[GRID_N * GRID_N];
    uint32_t quad_corners[4 * GRID_N * GRID_N];
    double uv_in[2 * 4 * GRID_N * GRID_N];
    double *uv_out, *vd_out, *pos;
    uint32_t *ls, *flc, *corners, *origin;
    uint32_t i, j;
    int ok;

    make_grid_positions();
    for (j = 0; j < GRID_N; j++) {
        for (i = 0; i < GRID_N; i++) {
            uint32_t f = j * GRID_N + i, v = j * (GRID_N + 1) + i;
            uint32_t q[4] = {v, v + 1, v + GRID_N + 2, v + GRID_N + 1};
            memcpy(quad_corners + 4 * f, q, sizeof q);
            loop_sizes[f] = 4;
            face_loops[f] = 1;
        }
    }
    for (i = 0; i < 4 * GRID_N * GRID_N; i++) {
        uv_in[2 * i] = grid_positions[3 * quad_corners[i]];
        uv_in[2 * i + 1] = grid_positions[3 * quad_corners[i] + 1];
    }
    CHECK_OK("create the quad grid",
             katachi_mesh_create(grid_positions, GRID_V, loop_sizes, GRID_N * GRID_N, face_loops,
                                 GRID_N * GRID_N, quad_corners, 4 * GRID_N * GRID_N, &quads));
    make_stroke(stroke);
    o.snap_vertex_ratio = 0.0;
    o.snap_segment_ratio = 0.0;
    CHECK_OK("cut the quads without snapping",
             katachi_cut_by_stroke(quads, stroke, STROKE_POINTS, VIEW_PROJ, VIEWPORT, &o, &cut));
    CHECK_OK("info", katachi_cut_info(cut, &info));
    CHECK("nothing moved; quads became triangles, some split",
          info.moved_vertex_count == 0 && info.input_corner_count == 4 * GRID_N * GRID_N &&
              info.face_count == 2 * GRID_N * GRID_N + info.new_face_count &&
              info.new_vertex_count > 0 && info.path_count == 1);
    CHECK_OK("mesh", katachi_cut_mesh(cut, &out));
    pos = alloc(3 * (size_t)info.vertex_count, sizeof *pos);
    ls = alloc(info.face_count, sizeof *ls);
    flc = alloc(info.face_count, sizeof *flc);
    corners = alloc(info.corner_count, sizeof *corners);
    origin = alloc(info.face_count, sizeof *origin);
    uv_out = alloc(2 * (size_t)info.corner_count, sizeof *uv_out);
    vd_out = alloc(3 * (size_t)info.vertex_count, sizeof *vd_out);
    CHECK_OK("positions", katachi_mesh_copy_positions(out, pos, 3 * (size_t)info.vertex_count));
    CHECK_OK("faces", katachi_mesh_copy_faces(out, ls, info.face_count, flc, info.face_count,
                                              corners, info.corner_count));
    CHECK_OK("face origin", katachi_cut_copy_face_origin(cut, origin, info.face_count));
    ok = 1;
    for (i = 0; i < info.face_count; i++) {
        ok = ok && origin[i] < GRID_N * GRID_N;
    }
    CHECK("every result face comes from an input quad", ok);
    CHECK_OK("corner data", katachi_cut_interpolate_corner_data(cut, uv_in, sizeof uv_in / sizeof *uv_in,
                                                                2, uv_out,
                                                                2 * (size_t)info.corner_count));
    ok = 1;
    for (i = 0; i < info.corner_count; i++) {
        uint32_t v = corners[i];
        ok = ok && fabs(uv_out[2 * i] - pos[3 * v]) < 1e-12 &&
             fabs(uv_out[2 * i + 1] - pos[3 * v + 1]) < 1e-12;
        if (v < GRID_V) {
            ok = ok && uv_out[2 * i] == pos[3 * v] && uv_out[2 * i + 1] == pos[3 * v + 1];
        }
    }
    CHECK("UV = (x, y) at every result corner (exactly at input vertices)", ok);
    CHECK_OK("vertex data", katachi_cut_interpolate_vertex_data(cut, grid_positions, GRID_V * 3, 3,
                                                                vd_out,
                                                                3 * (size_t)info.vertex_count));
    ok = 1;
    for (i = 0; i < 3 * info.vertex_count; i++) {
        ok = ok && fabs(vd_out[i] - pos[i]) < 1e-12;
    }
    CHECK("vertex data: positions carried as data equal the result's positions", ok);
    free(pos);
    free(ls);
    free(flc);
    free(corners);
    free(origin);
    free(uv_out);
    free(vd_out);
    katachi_mesh_free(out);
    katachi_cut_free(cut);
    katachi_mesh_free(quads);
}

/* The cut in the input's own layout (katachi_cut_polygons) on the quad grid, with the host's
 * edges numbered the kernel's way first (NULL), then given back: the same arrays; quads the
 * stroke misses come back whole, every corner's edge joins it to the next corner, UVs carried
 * as floats equal the positions (no snapping). */
static void test_polygons_layout(void)
{
    KatachiMesh *quads = NULL;
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = NULL;
    KatachiCutPolygons *a = NULL, *b = NULL, *bad = NULL;
    KatachiCutPolygonsInfo ia = katachi_cut_polygons_info_default();
    KatachiCutPolygonsInfo ib = katachi_cut_polygons_info_default();
    double stroke[2 * STROKE_POINTS];
    uint32_t loop_sizes[GRID_N * GRID_N], face_loops[GRID_N * GRID_N];
    uint32_t quad_corners[4 * GRID_N * GRID_N];
    uint32_t materials[GRID_N * GRID_N];
    float uv_in[2 * 4 * GRID_N * GRID_N];
    float *pos, *uv_out;
    uint32_t *starts, *sizes, *corners, *edges, *corner_edges, *fo, *eo, *co, *path, *mat_out;
    uint32_t *edges_b, *corner_edges_b;
    uint32_t i, j, f;
    int ok;

    make_grid_positions();
    for (j = 0; j < GRID_N; j++) {
        for (i = 0; i < GRID_N; i++) {
            uint32_t q, v = j * (GRID_N + 1) + i;
            uint32_t c[4] = {v, v + 1, v + GRID_N + 2, v + GRID_N + 1};
            f = j * GRID_N + i;
            for (q = 0; q < 4; q++) {
                quad_corners[4 * f + q] = c[q];
            }
            loop_sizes[f] = 4;
            face_loops[f] = 1;
            materials[f] = 100 + f;
        }
    }
    for (i = 0; i < 4 * GRID_N * GRID_N; i++) {
        uv_in[2 * i] = (float)grid_positions[3 * quad_corners[i]];
        uv_in[2 * i + 1] = (float)grid_positions[3 * quad_corners[i] + 1];
    }
    CHECK_OK("create the quad grid",
             katachi_mesh_create(grid_positions, GRID_V, loop_sizes, GRID_N * GRID_N, face_loops,
                                 GRID_N * GRID_N, quad_corners, 4 * GRID_N * GRID_N, &quads));
    make_stroke(stroke);
    o.snap_vertex_ratio = 0.0;
    o.snap_segment_ratio = 0.0;
    if (!CHECK_OK("cut the quads",
                  katachi_cut_by_stroke(quads, stroke, STROKE_POINTS, VIEW_PROJ, VIEWPORT, &o,
                                        &cut))) {
        katachi_mesh_free(quads);
        return;
    }
    CHECK_OK("polygons, edges numbered by first use",
             katachi_cut_polygons(cut, quads, NULL, 0, NULL, 0, 1, &a));
    CHECK_OK("its info", katachi_cut_polygons_info(a, &ia));
    printf("     polygons: %u vertices, %u faces (%u kept), %u corners, %u edges (%u on the path)\n",
           ia.vertex_count, ia.face_count, ia.kept_face_count, ia.corner_count, ia.edge_count,
           ia.path_edge_count);
    CHECK("some quads kept, some cut into triangles after them",
          ia.kept_face_count > 0 && ia.kept_face_count < GRID_N * GRID_N &&
              ia.face_count > GRID_N * GRID_N && ia.path_edge_count > 0);
    pos = alloc(3 * (size_t)ia.vertex_count, sizeof *pos);
    starts = alloc(ia.face_count, sizeof *starts);
    sizes = alloc(ia.face_count, sizeof *sizes);
    corners = alloc(ia.corner_count, sizeof *corners);
    edges = alloc(2 * (size_t)ia.edge_count, sizeof *edges);
    corner_edges = alloc(ia.corner_count, sizeof *corner_edges);
    fo = alloc(ia.face_count, sizeof *fo);
    eo = alloc(ia.edge_count, sizeof *eo);
    co = alloc(ia.corner_count, sizeof *co);
    path = alloc(ia.path_edge_count, sizeof *path);
    mat_out = alloc(ia.face_count, sizeof *mat_out);
    uv_out = alloc(2 * (size_t)ia.corner_count, sizeof *uv_out);
    CHECK_OK("positions", katachi_cut_polygons_copy_positions_f32(a, pos, 3 * (size_t)ia.vertex_count));
    CHECK_OK("polygons", katachi_cut_polygons_copy_polygons(a, starts, ia.face_count, sizes,
                                                            ia.face_count, corners, ia.corner_count));
    CHECK_OK("edges", katachi_cut_polygons_copy_edges(a, edges, 2 * (size_t)ia.edge_count,
                                                      corner_edges, ia.corner_count));
    CHECK_OK("origins", katachi_cut_polygons_copy_origins(a, fo, ia.face_count, eo, ia.edge_count,
                                                          co, ia.corner_count));
    CHECK_OK("path edges", katachi_cut_polygons_copy_path_edges(a, path, ia.path_edge_count));
    ok = 1;
    for (f = 0; f < ia.face_count; f++) {
        uint32_t k, n = sizes[f], s0 = starts[f];
        ok = ok && (f == 0 ? s0 == 0 : s0 == starts[f - 1] + sizes[f - 1]);
        ok = ok && (f >= GRID_N * GRID_N || fo[f] == f) && fo[f] < GRID_N * GRID_N;
        ok = ok && (n == 3 || (n == 4 && memcmp(corners + s0, quad_corners + 4 * f, sizeof(uint32_t) * 4) == 0));
        for (k = 0; k < n; k++) {
            uint32_t u = corners[s0 + k], w = corners[s0 + (k + 1) % n];
            uint32_t e = corner_edges[s0 + k];
            ok = ok && e < ia.edge_count &&
                 ((edges[2 * e] == u && edges[2 * e + 1] == w) || (edges[2 * e] == w && edges[2 * e + 1] == u));
            ok = ok && (co[s0 + k] == UINT32_MAX ? u >= GRID_V : quad_corners[co[s0 + k]] == u);
        }
    }
    CHECK("faces in their slots, kept quads whole, every corner's edge and origin right", ok);
    CHECK_OK("carry materials", katachi_cut_polygons_carry_face_data(a, materials, GRID_N * GRID_N, 4,
                                                                     mat_out, ia.face_count));
    ok = 1;
    for (f = 0; f < ia.face_count; f++) {
        ok = ok && mat_out[f] == 100 + fo[f];
    }
    CHECK("materials follow the faces", ok);
    CHECK_OK("carry UVs", katachi_cut_polygons_carry_corner_data_f32(a, uv_in, 2 * 4 * GRID_N * GRID_N, 2,
                                                                    uv_out, 2 * (size_t)ia.corner_count));
    ok = 1;
    for (i = 0; i < ia.corner_count; i++) {
        ok = ok && fabs(uv_out[2 * i] - pos[3 * corners[i]]) < 1e-5 &&
             fabs(uv_out[2 * i + 1] - pos[3 * corners[i] + 1]) < 1e-5;
    }
    CHECK("UV = (x, y) at every corner", ok);

    /* The host's edges given back: the same arrays. */
    {
        uint32_t *host_ce = alloc(4 * GRID_N * GRID_N, sizeof *host_ce);
        KatachiCutPolygons *all = NULL;
        KatachiCutPolygonsInfo iall = katachi_cut_polygons_info_default();
        CHECK_OK("every face as triangles",
                 katachi_cut_polygons(cut, quads, NULL, 0, NULL, 0, 0, &all));
        CHECK_OK("its info", katachi_cut_polygons_info(all, &iall));
        CHECK("no face kept", iall.kept_face_count == 0 && iall.corner_count % 3 == 0 &&
                                  iall.face_count > ia.face_count);
        katachi_cut_polygons_free(all);
        /* The host's edges, numbered by first use in corner order (as the kernel does). */
        {
            uint32_t *hedges = alloc(2 * (size_t)4 * GRID_N * GRID_N, sizeof *hedges);
            uint32_t ne = 0, k;
            for (k = 0; k < 4 * GRID_N * GRID_N; k++) {
                uint32_t fq = k / 4, u = quad_corners[k], w = quad_corners[4 * fq + (k % 4 + 1) % 4], e;
                for (e = 0; e < ne; e++) {
                    if ((hedges[2 * e] == u && hedges[2 * e + 1] == w) || (hedges[2 * e] == w && hedges[2 * e + 1] == u)) {
                        break;
                    }
                }
                if (e == ne) {
                    hedges[2 * ne] = u;
                    hedges[2 * ne + 1] = w;
                    ne++;
                }
                host_ce[k] = e;
            }
            CHECK_OK("polygons with the host's edges",
                     katachi_cut_polygons(cut, quads, hedges, ne, host_ce, 4 * GRID_N * GRID_N, 1, &b));
            CHECK_OK("its info", katachi_cut_polygons_info(b, &ib));
            edges_b = alloc(2 * (size_t)ib.edge_count, sizeof *edges_b);
            corner_edges_b = alloc(ib.corner_count, sizeof *corner_edges_b);
            CHECK_OK("its edges", katachi_cut_polygons_copy_edges(b, edges_b, 2 * (size_t)ib.edge_count,
                                                                  corner_edges_b, ib.corner_count));
            CHECK("the same edges as the kernel's numbering",
                  memcmp(&ia, &ib, sizeof ia) == 0 &&
                      memcmp(edges, edges_b, sizeof(uint32_t) * 2 * ia.edge_count) == 0 &&
                      memcmp(corner_edges, corner_edges_b, sizeof(uint32_t) * ia.corner_count) == 0);
            {
                uint32_t *ev = alloc(ne, sizeof *ev), *eout = alloc(ib.edge_count, sizeof *eout);
                uint32_t vv[GRID_V], *vout = alloc(ib.vertex_count, sizeof *vout);
                double *pd = alloc(3 * (size_t)ib.vertex_count, sizeof *pd);
                uint32_t k;
                for (k = 0; k < ne; k++) {
                    ev[k] = k + 1;
                }
                for (k = 0; k < GRID_V; k++) {
                    vv[k] = k + 1;
                }
                CHECK_OK("carry edge data", katachi_cut_polygons_carry_edge_data(b, ev, ne, 4, eout, ib.edge_count));
                CHECK_OK("carry vertex data", katachi_cut_polygons_carry_vertex_data(b, vv, GRID_V, 4, vout, ib.vertex_count));
                CHECK_OK("positions as doubles", katachi_cut_polygons_copy_positions(b, pd, 3 * (size_t)ib.vertex_count));
                ok = 1;
                for (k = 0; k < ib.edge_count; k++) {
                    ok = ok && (k < ne ? eout[k] == k + 1 : eout[k] <= ne);
                }
                for (k = 0; k < ib.vertex_count; k++) {
                    ok = ok && vout[k] == (k < GRID_V ? k + 1 : 0);
                }
                for (k = 0; k < 3 * ib.vertex_count; k++) {
                    ok = ok && (float)pd[k] == pos[k];
                }
                CHECK("host edges keep their data, input vertices theirs, new vertices none; positions", ok);
                free(ev);
                free(eout);
                free(vout);
                free(pd);
            }
            host_ce[5] = host_ce[6];
            CHECK_ERR("a corner's edge that does not join it to the next corner",
                      katachi_cut_polygons(cut, quads, hedges, ne, host_ce, 4 * GRID_N * GRID_N, 1, &bad),
                      KATACHI_STATUS_INVALID_ARGUMENT, "corner 5");
            CHECK("no handle on failure", bad == NULL);
            host_ce[5] = ne + 7;
            CHECK_ERR("a corner's edge out of range",
                      katachi_cut_polygons(cut, quads, hedges, ne, host_ce, 4 * GRID_N * GRID_N, 1, &bad),
                      KATACHI_STATUS_INVALID_ARGUMENT, "corner 5");
            CHECK_ERR("keep_polygons 2",
                      katachi_cut_polygons(cut, quads, NULL, 0, NULL, 0, 2, &bad),
                      KATACHI_STATUS_INVALID_ARGUMENT, "keep_polygons");
            CHECK_ERR("NULL out", katachi_cut_polygons(cut, quads, NULL, 0, NULL, 0, 1, NULL),
                      KATACHI_STATUS_NULL_POINTER, "out");
            CHECK_ERR("a short buffer",
                      katachi_cut_polygons_copy_edges(b, edges_b, 1, NULL, 0),
                      KATACHI_STATUS_BUFFER_TOO_SMALL, "edges");
            CHECK_ERR("face data of the wrong count",
                      katachi_cut_polygons_carry_face_data(b, materials, 3, 4, mat_out, ia.face_count),
                      KATACHI_STATUS_INVALID_ARGUMENT, "value_count");
            free(hedges);
            free(edges_b);
            free(corner_edges_b);
        }
        free(host_ce);
    }
    katachi_cut_polygons_free(a);
    katachi_cut_polygons_free(b);
    katachi_cut_polygons_free(NULL);
    free(pos);
    free(starts);
    free(sizes);
    free(corners);
    free(edges);
    free(corner_edges);
    free(fo);
    free(eo);
    free(co);
    free(path);
    free(mat_out);
    free(uv_out);
    katachi_cut_free(cut);
    katachi_mesh_free(quads);
}

static void test_bad_input(void)
{
    KatachiMesh *grid = make_grid();
    Snapshot before = snapshot(grid), after;
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = (KatachiCut *)&o; /* not NULL: must be reset */
    KatachiCutInfo info = katachi_cut_info_default();
    KatachiMesh *m = (KatachiMesh *)&o;
    double stroke[2 * STROKE_POINTS];
    double bad[2 * STROKE_POINTS];
    const double zero[16] = {0};
    /* A Z whose first and last segments cross. */
    const double zed[8] = {100.0, 100.0, 400.0, 400.0, 400.0, 100.0, 100.0, 400.0};
    uint32_t f[1];
    double d[1];
    int all_null = 1;

    make_stroke(stroke);
#define CUT(opts, pts, n, vp) katachi_cut_by_stroke(grid, (pts), (n), (vp), VIEWPORT, (opts), &cut)
#define RESET_OUT() (all_null = all_null && cut == NULL, cut = (KatachiCut *)&o)
    CHECK_ERR("NULL mesh", katachi_cut_by_stroke(NULL, stroke, STROKE_POINTS, VIEW_PROJ, VIEWPORT,
                                                 &o, &cut),
              KATACHI_STATUS_NULL_POINTER, "mesh is NULL");
    RESET_OUT();
    CHECK_ERR("NULL stroke", CUT(&o, NULL, STROKE_POINTS, VIEW_PROJ), KATACHI_STATUS_NULL_POINTER,
              "stroke_px is NULL but point_count is 12");
    RESET_OUT();
    CHECK_ERR("NULL matrix", CUT(&o, stroke, STROKE_POINTS, NULL), KATACHI_STATUS_NULL_POINTER,
              "view_proj");
    RESET_OUT();
    CHECK_ERR("NULL viewport",
              katachi_cut_by_stroke(grid, stroke, STROKE_POINTS, VIEW_PROJ, NULL, &o, &cut),
              KATACHI_STATUS_NULL_POINTER, "viewport");
    RESET_OUT();
    CHECK_ERR("NULL options", CUT(NULL, stroke, STROKE_POINTS, VIEW_PROJ),
              KATACHI_STATUS_NULL_POINTER, "options");
    RESET_OUT();
    CHECK_ERR("NULL out", katachi_cut_by_stroke(grid, stroke, STROKE_POINTS, VIEW_PROJ, VIEWPORT,
                                                &o, NULL),
              KATACHI_STATUS_NULL_POINTER, "out");
    o.struct_size = 8;
    CHECK_ERR("struct_size too small", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ),
              KATACHI_STATUS_INVALID_ARGUMENT, "options->struct_size is 8");
    RESET_OUT();
    o = katachi_cut_options_default();
    o.mode = 7;
    CHECK_ERR("mode 7", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ), KATACHI_STATUS_INVALID_ARGUMENT,
              "options->mode is 7, which is not one of KATACHI_CUT_MODE_VISIBLE_ONLY (0)");
    RESET_OUT();
    o = katachi_cut_options_default();
    o.open = 2;
    CHECK_ERR("open 2", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ), KATACHI_STATUS_INVALID_ARGUMENT,
              "options->open is 2");
    RESET_OUT();
    o = katachi_cut_options_default();
    o.snap_vertex_ratio = 0.9;
    CHECK_ERR("snap ratio 0.9", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ),
              KATACHI_STATUS_INVALID_ARGUMENT, "options->snap_vertex_ratio");
    RESET_OUT();
    o = katachi_cut_options_default();
    o.corner_angle_degrees = 200.0;
    CHECK_ERR("corner angle 200", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ),
              KATACHI_STATUS_INVALID_ARGUMENT, "options->corner_angle_degrees");
    RESET_OUT();
    o = katachi_cut_options_default();
    o.min_stroke_px = -1.0;
    CHECK_ERR("negative min_stroke_px", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ),
              KATACHI_STATUS_INVALID_ARGUMENT, "options->min_stroke_px");
    RESET_OUT();
    o = katachi_cut_options_default();
    memcpy(bad, stroke, sizeof bad);
    bad[3] = NAN;
    CHECK_ERR("NaN stroke point", CUT(&o, bad, STROKE_POINTS, VIEW_PROJ), KATACHI_STATUS_BAD_INPUT,
              "stroke point 1");
    RESET_OUT();
    CHECK_ERR("1-point stroke", CUT(&o, stroke, 1, VIEW_PROJ), KATACHI_STATUS_BAD_INPUT,
              "a cut needs at least 2");
    RESET_OUT();
    CHECK_ERR("0-point stroke", CUT(&o, NULL, 0, VIEW_PROJ), KATACHI_STATUS_BAD_INPUT,
              "a cut needs at least 2");
    RESET_OUT();
    CHECK_ERR("singular matrix", CUT(&o, stroke, STROKE_POINTS, zero), KATACHI_STATUS_BAD_INPUT,
              "singular");
    RESET_OUT();
    memcpy(bad, VIEW_PROJ, 16 * sizeof(double));
    bad[13] = INFINITY;
    CHECK_ERR("infinite matrix entry", CUT(&o, stroke, STROKE_POINTS, bad), KATACHI_STATUS_BAD_INPUT,
              "column 3, row 1");
    RESET_OUT();
    CHECK_ERR("self-intersecting stroke", CUT(&o, zed, 4, VIEW_PROJ), KATACHI_STATUS_BAD_INPUT,
              "crosses itself");
    RESET_OUT();
    {
        const double flat[4] = {0.0, 0.0, 500.0, 0.0};
        CHECK_ERR("viewport without area",
                  katachi_cut_by_stroke(grid, stroke, STROKE_POINTS, VIEW_PROJ, flat, &o, &cut),
                  KATACHI_STATUS_BAD_INPUT, "viewport");
        RESET_OUT();
    }
    o.max_faces_split = 1;
    CHECK_ERR("max_faces_split exceeded", CUT(&o, stroke, STROKE_POINTS, VIEW_PROJ),
              KATACHI_STATUS_BAD_INPUT, "the cut would split");
    RESET_OUT();
    CHECK("out is NULL after every failure", all_null);
#undef CUT
#undef RESET_OUT

    after = snapshot(grid);
    CHECK("failing cuts leave the mesh unchanged", snapshots_equal(&before, &after));
    snapshot_free(&after);
    snapshot_free(&before);

    {
        KatachiMesh *empty = NULL;
        CHECK_OK("empty mesh created",
                 katachi_mesh_create(NULL, 0, NULL, 0, NULL, 0, NULL, 0, &empty));
        o = katachi_cut_options_default();
        CHECK_ERR("empty mesh", katachi_cut_by_stroke(empty, stroke, STROKE_POINTS, VIEW_PROJ,
                                                      VIEWPORT, &o, &cut),
                  KATACHI_STATUS_BAD_INPUT, "empty");
        CHECK("out NULL for the empty mesh", cut == NULL);
        katachi_mesh_free(empty);
    }

    /* Accessors on a NULL handle. */
    CHECK_ERR("info of NULL", katachi_cut_info(NULL, &info), KATACHI_STATUS_NULL_POINTER,
              "cut is NULL");
    CHECK_ERR("mesh of NULL", katachi_cut_mesh(NULL, &m), KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK("mesh out reset", m == NULL);
    CHECK_ERR("origin of NULL", katachi_cut_copy_face_origin(NULL, f, 1),
              KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK_ERR("paths of NULL", katachi_cut_copy_paths(NULL, f, 1, f, 1),
              KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK_ERR("pieces of NULL", katachi_cut_copy_path_pieces(NULL, f, f, 1),
              KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK_ERR("moved of NULL", katachi_cut_copy_moved_vertices(NULL, f, d, d, d, 0),
              KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK_ERR("dropped of NULL", katachi_cut_copy_dropped_points(NULL, 0, f, 1),
              KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK_ERR("corner data of NULL", katachi_cut_interpolate_corner_data(NULL, d, 1, 1, d, 1),
              KATACHI_STATUS_NULL_POINTER, "cut");
    CHECK_ERR("vertex data of NULL", katachi_cut_interpolate_vertex_data(NULL, d, 1, 1, d, 1),
              KATACHI_STATUS_NULL_POINTER, "cut");
    katachi_cut_free(NULL);

    /* A too-small info struct is refused and left alone. */
    o = katachi_cut_options_default();
    CHECK_OK("a cut for the info test", katachi_cut_by_stroke(grid, stroke, STROKE_POINTS,
                                                              VIEW_PROJ, VIEWPORT, &o, &cut));
    info.struct_size = 8;
    info.face_count = 77;
    CHECK_ERR("info: struct_size too small", katachi_cut_info(cut, &info),
              KATACHI_STATUS_INVALID_ARGUMENT, "katachi_cut_info_default");
    CHECK("info untouched", info.face_count == 77);
    CHECK_ERR("info: NULL", katachi_cut_info(cut, NULL), KATACHI_STATUS_NULL_POINTER, "info");
    katachi_cut_free(cut);
    katachi_mesh_free(grid);
}

/* Numbers of huge but finite magnitude from the caller (1e300, DBL_MAX): a stroke point, a
 * matrix entry, a viewport value are typed errors naming what is wrong; a mesh coordinate
 * gives a cut with finite positions or a typed error. Never an internal error, and (under
 * valgrind) no read out of bounds. */
static void test_extreme_numbers(void)
{
    KatachiMesh *grid = make_grid();
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = NULL;
    const double huge[3] = {1e300, DBL_MAX, -DBL_MAX};
    double vp[16], viewport[4];
    double s2[4] = {20.0, 330.0, 0.0, 0.0};
    double s3[6] = {20.0, 330.0, 250.0, 240.0, 0.0, 140.0};
    int i, k, mode;
    for (i = 0; i < 3; i++) {
        for (mode = 0; mode < 2; mode++) {
            o.mode = (uint32_t)mode;
            s2[2] = huge[i];
            s2[3] = huge[i];
            CHECK_ERR("a stroke point at a huge coordinate",
                      katachi_cut_by_stroke(grid, s2, 2, VIEW_PROJ, VIEWPORT, &o, &cut),
                      KATACHI_STATUS_BAD_INPUT, "stroke point 1");
            CHECK("no result", cut == NULL);
            s3[4] = huge[i];
            CHECK_ERR("the last of three stroke points at a huge coordinate",
                      katachi_cut_by_stroke(grid, s3, 3, VIEW_PROJ, VIEWPORT, &o, &cut),
                      KATACHI_STATUS_BAD_INPUT, "beyond");
            memcpy(vp, VIEW_PROJ, sizeof vp);
            for (k = 0; k < 16; k++) {
                vp[k] *= huge[i];
            }
            CHECK_ERR("a matrix of huge entries",
                      katachi_cut_by_stroke(grid, s3, 2, vp, VIEWPORT, &o, &cut),
                      KATACHI_STATUS_BAD_INPUT, "view-projection matrix entry");
            for (k = 0; k < 4; k++) {
                memcpy(viewport, VIEWPORT, sizeof viewport);
                viewport[k] = fabs(huge[i]);
                CHECK_ERR("a viewport value of huge magnitude",
                          katachi_cut_by_stroke(grid, s3, 2, VIEW_PROJ, viewport, &o, &cut),
                          KATACHI_STATUS_BAD_INPUT, "viewport");
            }
        }
    }
    katachi_mesh_free(grid);
    /* A grid vertex under the stroke moved far off the plane, and one far aside. */
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 2; k++) {
            KatachiMesh *m = NULL;
            uint32_t loop_sizes[GRID_F], face_loops[GRID_F], j;
            KatachiStatus st;
            double s[4] = {20.0, 330.0, 480.0, 140.0};
            make_grid_positions();
            grid_positions[3 * 12 + (k == 0 ? 2 : 0)] = huge[i];
            for (j = 0; j < GRID_F; j++) {
                loop_sizes[j] = 3;
                face_loops[j] = 1;
            }
            CHECK_OK("a grid with a huge coordinate",
                     katachi_mesh_create(grid_positions, GRID_V, loop_sizes, GRID_F, face_loops,
                                         GRID_F, grid_corners, GRID_F * 3, &m));
            for (mode = 0; mode < 2; mode++) {
                o.mode = (uint32_t)mode;
                st = katachi_cut_by_stroke(m, s, 2, VIEW_PROJ, VIEWPORT, &o, &cut);
                CHECK("a huge coordinate cuts or is bad input",
                      st == KATACHI_STATUS_OK || st == KATACHI_STATUS_BAD_INPUT);
                if (st == KATACHI_STATUS_OK) {
                    KatachiCutInfo info = katachi_cut_info_default();
                    KatachiMesh *out = NULL;
                    double *q;
                    int finite = 1;
                    uint32_t v;
                    CHECK_OK("info", katachi_cut_info(cut, &info));
                    CHECK_OK("mesh", katachi_cut_mesh(cut, &out));
                    q = malloc(sizeof(double) * 3 * info.vertex_count);
                    CHECK_OK("positions", katachi_mesh_copy_positions(out, q, 3 * (size_t)info.vertex_count));
                    for (v = 0; v < 3 * info.vertex_count; v++) {
                        finite = finite && isfinite(q[v]);
                    }
                    CHECK("every position is finite", finite);
                    free(q);
                    katachi_mesh_free(out);
                    katachi_cut_free(cut);
                    cut = NULL;
                }
            }
            katachi_mesh_free(m);
        }
    }
    make_grid_positions();
}

/* What the progress callback of test_progress_and_cancel saw and when it says stop. */
struct Progress {
    uint32_t calls, last_done, total, stop_at, in_order;
};

static uint32_t on_step(uint32_t done, uint32_t total, void *user)
{
    struct Progress *p = (struct Progress *)user;
    p->in_order = p->in_order && done == p->last_done + 1 && done <= total;
    p->calls++;
    p->last_done = done;
    p->total = total;
    return p->stop_at != 0 && done >= p->stop_at;
}

/* katachi_cut_by_stroke_with_progress: every step reported in order on a long spiral stroke
 * (5,000 points; the Rust tests run 200,000); a callback that returns non-zero at step k
 * cancels there with KATACHI_STATUS_CANCELLED, no result and no further call; NULL progress
 * is katachi_cut_by_stroke. */
static void test_progress_and_cancel(void)
{
    KatachiMesh *grid = make_grid();
    KatachiCutOptions o = katachi_cut_options_default();
    KatachiCut *cut = NULL;
    KatachiCutInfo info = katachi_cut_info_default();
    struct Progress p = {0, 0, 0, 0, 1};
    double s[STROKE_POINTS * 2];
    enum { LONG = 5000 };
    double *spiral = malloc(sizeof(double) * 2 * LONG);
    double t = 6.283185307179586, k = 4.0 / 6.283185307179586;
    uint32_t i, stop, total;
    for (i = 0; i < LONG; i++) {
        double r = k * t;
        spiral[2 * i] = 250.0 + r * cos(t);
        spiral[2 * i + 1] = 250.0 + r * sin(t);
        t += 2.5 / sqrt(r * r + k * k);
    }
    o.mode = KATACHI_CUT_MODE_THROUGH_ALL;
    CHECK_OK("a long spiral with progress",
             katachi_cut_by_stroke_with_progress(grid, spiral, LONG, VIEW_PROJ, VIEWPORT, &o,
                                                 on_step, &p, &cut));
    CHECK("every step reported, in order", p.in_order && p.calls == p.total && p.total >= 5);
    CHECK_OK("info", katachi_cut_info(cut, &info));
    CHECK("the spiral splits faces", info.split_face_count > 0);
    katachi_cut_free(cut);
    cut = NULL;
    total = p.total;
    make_stroke(s);
    o.open = 1;
    for (stop = 1; stop <= total; stop++) {
        struct Progress q = {0, 0, 0, 0, 1};
        q.stop_at = stop;
        cut = (KatachiCut *)(void *)&q; /* must be reset */
        CHECK_ERR("cancelled by the callback",
                  katachi_cut_by_stroke_with_progress(grid, s, STROKE_POINTS, VIEW_PROJ, VIEWPORT,
                                                      &o, on_step, &q, &cut),
                  KATACHI_STATUS_CANCELLED, "cancelled");
        CHECK("no result after cancelling", cut == NULL);
        CHECK("no call after the one that cancelled", q.calls == stop);
    }
    CHECK_OK("NULL progress",
             katachi_cut_by_stroke_with_progress(grid, s, STROKE_POINTS, VIEW_PROJ, VIEWPORT, &o,
                                                 NULL, NULL, &cut));
    katachi_cut_free(cut);
    free(spiral);
    katachi_mesh_free(grid);
}

int main(void)
{
    printf("katachi %s, stroke cut from C99\n", katachi_version_string());
    test_grid_cut();
    test_open_and_closed();
    test_interpolation_without_snapping();
    test_polygons_layout();
    test_bad_input();
    test_extreme_numbers();
    test_progress_and_cancel();
    return check_finish();
}
