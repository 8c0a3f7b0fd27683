/*
 * C99 link test of katachi_mesh_read / katachi_mesh_write: round trips through .obj, .off and
 * .ply in a fresh temporary directory (positions bit-exact, faces unchanged, sharpness kept
 * by OBJ), faces with holes, and bad paths and files. Run by `cargo xtask ctest` under
 * valgrind, and by `cargo xtask windows-test` under Wine.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "katachi.h"

#include "check.h"
#include "shapes.h"
#include "snapshot.h"
#include "tempdir.h"

static char dir[256];

static int sentinel_object;
#define SENTINEL ((KatachiMesh *)(void *)&sentinel_object)

/* dir/name, in a static buffer (one at a time is enough here). */
static const char *path_in_dir(const char *name)
{
    static char buf[512];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) return 0;
    fclose(f);
    return 1;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (f == NULL || fputs(text, f) < 0 || fclose(f) != 0) {
        printf("FAIL cannot write %s\n", path);
        exit(1);
    }
}

static KatachiMesh *create(const double *pos, uint32_t nv, const uint32_t *ls, uint32_t nl,
                           const uint32_t *flc, uint32_t nf, const uint32_t *cs, uint32_t nc)
{
    KatachiMesh *m = NULL;
    if (katachi_mesh_create(pos, nv, ls, nl, flc, nf, cs, nc, &m) != KATACHI_STATUS_OK) {
        printf("FAIL create: %s\n", katachi_last_error_message());
        exit(1);
    }
    return m;
}

/* Writes `m` to dir/name, reads it back, and checks the two agree: positions bit-exact and the
 * face layout unchanged; with `with_sharpness`, edge and vertex sharpness too. Returns the mesh
 * read (or NULL). */
static KatachiMesh *round_trip(const char *label, const KatachiMesh *m, const char *name,
                               int with_sharpness)
{
    char check_name[256];
    char path[512];
    KatachiMesh *back = SENTINEL;
    Snapshot a, b;
    int same;
    snprintf(path, sizeof path, "%s", path_in_dir(name));

    snprintf(check_name, sizeof check_name, "%s: write %s", label, name);
    if (!CHECK_OK(check_name, katachi_mesh_write(m, path))) return NULL;
    snprintf(check_name, sizeof check_name, "%s: read %s back", label, name);
    if (!CHECK_OK(check_name, katachi_mesh_read(path, &back))) return NULL;
    a = snapshot(m);
    b = snapshot(back);
    same = a.counts.vertex_count == b.counts.vertex_count &&
           a.counts.face_count == b.counts.face_count &&
           a.counts.loop_count == b.counts.loop_count &&
           a.counts.corner_count == b.counts.corner_count &&
           memcmp(a.positions, b.positions, 3 * a.counts.vertex_count * sizeof(double)) == 0 &&
           memcmp(a.loop_sizes, b.loop_sizes, a.counts.loop_count * sizeof(uint32_t)) == 0 &&
           memcmp(a.face_loop_counts, b.face_loop_counts, a.counts.face_count * sizeof(uint32_t)) == 0 &&
           memcmp(a.corners, b.corners, a.counts.corner_count * sizeof(uint32_t)) == 0;
    snprintf(check_name, sizeof check_name, "%s: %s keeps positions bit-exact and faces", label,
             name);
    CHECK(check_name, same);
    if (with_sharpness) {
        snprintf(check_name, sizeof check_name, "%s: %s keeps edge and vertex sharpness", label,
                 name);
        CHECK(check_name, snapshots_equal(&a, &b));
    }
    snapshot_free(&a);
    snapshot_free(&b);
    remove(path);
    return back;
}

static void test_round_trips(void)
{
    static const char *const formats[3] = {"obj", "off", "ply"};
    static const uint32_t sharp_pairs[6] = {0, 1, 1, 3, 3, 2};
    static const double sharp_values[3] = {10.0, 2.5, 0.5};
    KatachiMesh *cube = create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6,
                               CUBE_CORNERS, 24);
    KatachiMesh *frame = create(PLATE_POSITIONS, 16, FRAME_LOOP_SIZES, 16, FRAME_FACE_LOOP_COUNTS,
                                16, FRAME_CORNERS, 64);
    KatachiMesh *back;
    KatachiMeshInfo info = katachi_mesh_info_default();
    char name[64];
    int i;

    for (i = 0; i < 3; i++) {
        snprintf(name, sizeof name, "cube.%s", formats[i]);
        katachi_mesh_free(round_trip("cube", cube, name, 0));
        snprintf(name, sizeof name, "frame.%s", formats[i]);
        back = round_trip("plate (quads, genus 1)", frame, name, 0);
        if (back != NULL) {
            CHECK_OK("plate read back: inspect", katachi_mesh_inspect(back, &info));
            CHECK("plate read back: 32 edges, χ = 0, genus 1, closed",
                  info.edge_count == 32 && info.euler_characteristic == 0 && info.genus == 1 &&
                      info.is_closed);
            katachi_mesh_free(back);
        }
    }

    /* OBJ keeps sharpness as OpenSubdiv tags. */
    CHECK_OK("cube: sharpen three edges",
             katachi_mesh_set_edge_sharpnesses(cube, sharp_pairs, sharp_values, 3));
    CHECK_OK("cube: sharpen a corner", katachi_mesh_set_vertex_sharpness(cube, 7, 3.0));
    katachi_mesh_free(round_trip("sharp cube", cube, "sharp.obj", 1));

    katachi_mesh_free(frame);
    katachi_mesh_free(cube);
}

static void test_faces_with_holes(void)
{
    static const char *const names[3] = {"plate.obj", "plate.off", "plate.ply"};
    KatachiMesh *plate = create(PLATE_POSITIONS, 16, PLATE_LOOP_SIZES, 12, PLATE_FACE_LOOP_COUNTS,
                                10, PLATE_CORNERS, 48);
    KatachiMeshCounts c = katachi_mesh_counts_default();
    char label[128];
    int i;
    /* None of the three formats can store a face with holes; katachi refuses rather than
     * change the topology, names the face, and writes nothing. */
    for (i = 0; i < 3; i++) {
        const char *path = path_in_dir(names[i]);
        snprintf(label, sizeof label, "plate with holes: %s is refused", names[i]);
        CHECK_ERR(label, katachi_mesh_write(plate, path), KATACHI_STATUS_INVALID_ARGUMENT,
                  "face 0 has 1 hole");
        snprintf(label, sizeof label, "plate with holes: no %s was written", names[i]);
        CHECK(label, !file_exists(path_in_dir(names[i])));
    }
    CHECK_OK("plate with holes: unchanged after the refusals", katachi_mesh_counts(plate, &c));
    CHECK("plate with holes: still 12 loops", c.loop_count == 12 && c.face_count == 10);
    katachi_mesh_free(plate);
}

static void test_bad_paths_and_files(void)
{
    KatachiMesh *cube = create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6,
                               CUBE_CORNERS, 24);
    KatachiMesh *m;
    const char *p;

    m = SENTINEL;
    CHECK_ERR("read: path NULL", katachi_mesh_read(NULL, &m), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_read: path is NULL");
    CHECK("read: *out is NULL after failure", m == NULL);
    CHECK_ERR("read: out NULL", katachi_mesh_read(path_in_dir("x.obj"), NULL),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_read: out is NULL");
    CHECK_ERR("write: mesh NULL", katachi_mesh_write(NULL, path_in_dir("x.obj")),
              KATACHI_STATUS_NULL_POINTER, "katachi_mesh_write: mesh is NULL");
    CHECK_ERR("write: path NULL", katachi_mesh_write(cube, NULL), KATACHI_STATUS_NULL_POINTER,
              "katachi_mesh_write: path is NULL");

    m = SENTINEL;
    CHECK_ERR("read: empty path", katachi_mesh_read("", &m), KATACHI_STATUS_INVALID_ARGUMENT,
              "path is the empty string");
    CHECK("read: *out is NULL after an empty path", m == NULL);
    CHECK_ERR("write: empty path", katachi_mesh_write(cube, ""), KATACHI_STATUS_INVALID_ARGUMENT,
              "path is the empty string");
    m = SENTINEL;
    CHECK_ERR("read: path not UTF-8", katachi_mesh_read("/tmp/\xff\xfe.obj", &m),
              KATACHI_STATUS_INVALID_ARGUMENT, "path is not valid UTF-8");
    CHECK("read: *out is NULL after a bad path", m == NULL);
    CHECK_ERR("write: path not UTF-8", katachi_mesh_write(cube, "/tmp/\xc3(.off"),
              KATACHI_STATUS_INVALID_ARGUMENT, "path is not valid UTF-8");

    m = SENTINEL;
    p = path_in_dir("missing.obj");
    CHECK_ERR("read: missing file", katachi_mesh_read(p, &m), KATACHI_STATUS_IO_ERROR, p);
    CHECK("read: *out is NULL for a missing file", m == NULL);
    CHECK_ERR("write: into a missing directory",
              katachi_mesh_write(cube, path_in_dir("no/such/dir/cube.obj")),
              KATACHI_STATUS_IO_ERROR, "no/such/dir/cube.obj");

    p = path_in_dir("cube.stl");
    CHECK_ERR("write: unknown extension", katachi_mesh_write(cube, p), KATACHI_STATUS_IO_ERROR,
              "unknown file format");
    CHECK("write: nothing written for an unknown extension", !file_exists(p));
    write_text(p, "solid cube\nendsolid cube\n");
    m = SENTINEL;
    CHECK_ERR("read: unknown extension", katachi_mesh_read(p, &m), KATACHI_STATUS_IO_ERROR,
              "unknown file format");
    CHECK("read: message names the file", MESSAGE_HAS("cube.stl"));
    CHECK("read: *out is NULL for an unknown extension", m == NULL);
    remove(p);
    p = path_in_dir("no_extension");
    CHECK_ERR("write: no extension", katachi_mesh_write(cube, p), KATACHI_STATUS_IO_ERROR,
              "unknown file format");

    p = path_in_dir("bad.off");
    write_text(p, "OFF\nthis is not a count line\n");
    m = SENTINEL;
    CHECK_ERR("read: malformed OFF", katachi_mesh_read(p, &m), KATACHI_STATUS_IO_ERROR, "bad.off:");
    CHECK("read: *out is NULL for a malformed file", m == NULL);
    remove(p);
    p = path_in_dir("bad_index.off");
    write_text(p, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    m = SENTINEL;
    CHECK_ERR("read: a face with a vertex index out of range", katachi_mesh_read(p, &m),
              KATACHI_STATUS_IO_ERROR, "bad_index.off:6:");
    CHECK("read: the message carries the validation fault", MESSAGE_HAS("out of range"));
    CHECK("read: *out is NULL for an invalid mesh", m == NULL);
    remove(p);

    katachi_mesh_free(cube);
}

int main(void)
{
    if (temp_dir_make(dir, sizeof dir) != 0) {
        printf("FAIL cannot make a temporary directory %s\n", dir);
        return 1;
    }
    printf("katachi %s, file I/O from C99 in %s\n", katachi_version_string(), dir);
    test_round_trips();
    test_faces_with_holes();
    test_bad_paths_and_files();
    if (temp_dir_remove(dir) != 0) {
        CHECK("the temporary directory is empty at the end", 0);
    }
    return check_finish();
}
