/*
 * C99 test of file names and line endings through katachi_mesh_read / katachi_mesh_write, as
 * Windows users meet them (and the same on Linux): names with spaces and non-ASCII letters in
 * folders with them, given as UTF-8, land on disk under exactly that name (checked through the
 * wide-character API on Windows, so a detour through the ANSI code page would be caught); on
 * Windows, `\` and mixed separators; the OBJ, OFF and PLY katachi writes end their lines with
 * LF on every platform (the same bytes everywhere), and files with CRLF line ends read as the
 * LF ones. Run by `cargo xtask ctest` under valgrind and by `cargo xtask windows-test` under
 * Wine.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef _WIN32
#include <sys/stat.h>
#endif

#include "katachi.h"

#include "check.h"
#include "shapes.h"
#include "snapshot.h"
#include "tempdir.h"

static char dir[256];

/* A folder with a space, a Latin letter with a diaeresis and a CJK character. */
#define FOLDER "sub folder \xc3\xbc \xe5\xbd\xa2"
static const char *const NAMES[4] = {
    "with spaces.obj",
    "\xc3\xbcml\xc3\xa4ut \xc3\xa9 \xe5\xbd\xa2\xe7\x8a\xb6.off", /* "ümläut é 形状.off" */
    "\xce\x95\xce\xbb\xce\xbb\xce\xb7\xce\xbd\xce\xb9\xce\xba\xce\xac name.ply", /* "Ελληνικά name.ply" */
    "emoji \xf0\x9f\x99\x82.obj", /* outside the BMP: a UTF-16 surrogate pair on Windows */
};

#ifdef _WIN32
/* UTF-8 → UTF-16 for the wide-character file functions; exits on a conversion failure. */
static wchar_t *wide(const char *utf8)
{
    static wchar_t buf[2][1024];
    static int which = 0;
    wchar_t *w = buf[which ^= 1];
    if (MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, utf8, -1, w, 1024) == 0) {
        printf("FAIL cannot convert %s to UTF-16\n", utf8);
        exit(1);
    }
    return w;
}
#endif

/* fopen with a UTF-8 name on every platform. */
static FILE *open_utf8(const char *path, const char *mode)
{
#ifdef _WIN32
    return _wfopen(wide(path), wide(mode));
#else
    return fopen(path, mode);
#endif
}

static int mkdir_utf8(const char *path)
{
#ifdef _WIN32
    return _wmkdir(wide(path));
#else
    return mkdir(path, 0700);
#endif
}

static int rmdir_utf8(const char *path)
{
#ifdef _WIN32
    return _wrmdir(wide(path));
#else
    return temp_dir_remove(path);
#endif
}

static int remove_utf8(const char *path)
{
#ifdef _WIN32
    return _wremove(wide(path));
#else
    return remove(path);
#endif
}

/* The whole file, NUL-terminated (binary files may hold NULs; *len says how long). NULL if it
 * cannot be read. */
static char *read_all(const char *path, size_t *len)
{
    FILE *f = open_utf8(path, "rb");
    char *buf = NULL;
    size_t cap = 0, n = 0, got;
    if (f == NULL) return NULL;
    do {
        if (n + 4096 + 1 > cap) {
            char *grown;
            cap = 2 * cap + 4096 + 1;
            grown = (char *)realloc(buf, cap);
            if (grown == NULL) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = grown;
        }
        got = fread(buf + n, 1, 4096, f);
        n += got;
    } while (got > 0);
    fclose(f);
    buf[n] = '\0';
    *len = n;
    return buf;
}

static void write_all(const char *path, const char *bytes, size_t len)
{
    FILE *f = open_utf8(path, "wb");
    if (f == NULL || fwrite(bytes, 1, len, f) != len || fclose(f) != 0) {
        printf("FAIL cannot write %s\n", path);
        exit(1);
    }
}

static KatachiMesh *cube(void)
{
    KatachiMesh *m = NULL;
    if (katachi_mesh_create(CUBE_POSITIONS, 8, CUBE_LOOP_SIZES, 6, CUBE_FACE_LOOP_COUNTS, 6,
                            CUBE_CORNERS, 24, &m) != KATACHI_STATUS_OK) {
        printf("FAIL create: %s\n", katachi_last_error_message());
        exit(1);
    }
    return m;
}

/* Whether the mesh at `path` reads back as `m`: counts, faces and positions bit-exact. */
static int reads_as(const char *label, const char *path, const KatachiMesh *m)
{
    KatachiMesh *back = NULL;
    Snapshot a, b;
    int same;
    char name[512];
    snprintf(name, sizeof name, "%s: read", label);
    if (!CHECK_OK(name, katachi_mesh_read(path, &back))) return 0;
    a = snapshot(m);
    b = snapshot(back);
    same = a.counts.vertex_count == b.counts.vertex_count &&
           a.counts.face_count == b.counts.face_count &&
           a.counts.corner_count == b.counts.corner_count &&
           memcmp(a.positions, b.positions, 3 * a.counts.vertex_count * sizeof(double)) == 0 &&
           memcmp(a.corners, b.corners, a.counts.corner_count * sizeof(uint32_t)) == 0;
    snapshot_free(&a);
    snapshot_free(&b);
    katachi_mesh_free(back);
    return same;
}

static void test_names(void)
{
    KatachiMesh *m = cube();
    char folder[512], path[1024], label[1200];
    size_t len = 0;
    char *bytes;
    int i;
    snprintf(folder, sizeof folder, "%s/%s", dir, FOLDER);
    if (mkdir_utf8(folder) != 0) {
        printf("FAIL cannot make %s\n", folder);
        exit(1);
    }
    for (i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/%s", folder, NAMES[i]);
        snprintf(label, sizeof label, "%s", NAMES[i]);
        CHECK_OK(label, katachi_mesh_write(m, path));
        /* Opened by its UTF-16 name on Windows: the file has exactly the name asked for. */
        bytes = read_all(path, &len);
        snprintf(label, sizeof label, "%s: on disk under exactly that name, not empty", NAMES[i]);
        CHECK(label, bytes != NULL && len > 0);
        free(bytes);
        snprintf(label, sizeof label, "%s: reads back as written", NAMES[i]);
        CHECK(label, reads_as(label, path, m));
    }
    /* A missing file with such a name: the message names it as given. */
    snprintf(path, sizeof path, "%s/missing \xe5\xbd\xa2.obj", folder);
    {
        KatachiMesh *none = NULL;
        CHECK_ERR("a missing non-ASCII file: I/O error naming it", katachi_mesh_read(path, &none),
                  KATACHI_STATUS_IO_ERROR, "missing \xe5\xbd\xa2.obj");
        CHECK("a missing non-ASCII file: no mesh", none == NULL);
    }
    katachi_mesh_free(m);
}

#ifdef _WIN32
/* `\` separators, all of them or mixed with `/`, as Windows programs pass paths. */
static void test_separators(void)
{
    KatachiMesh *m = cube();
    char back[1024], fwd[1024], mixed[1024];
    size_t i;
    snprintf(fwd, sizeof fwd, "%s/%s/back slashes.obj", dir, FOLDER);
    snprintf(back, sizeof back, "%s", fwd);
    for (i = 0; back[i] != '\0'; i++)
        if (back[i] == '/') back[i] = '\\';
    snprintf(mixed, sizeof mixed, "%s\\%s/back slashes.obj", dir, FOLDER);
    CHECK("the path has only `\\` separators", strchr(back, '/') == NULL);
    CHECK_OK("write through `\\` separators", katachi_mesh_write(m, back));
    CHECK("read through `/` separators", reads_as("read through `/`", fwd, m));
    CHECK("read through mixed separators", reads_as("read through mixed", mixed, m));
    CHECK("read through `\\` separators", reads_as("read through `\\`", back, m));
    CHECK("the file is one file, at its place", remove_utf8(fwd) == 0);
    {
        KatachiMesh *none = NULL;
        snprintf(back, sizeof back, "%s\\no such folder\\x.off", dir);
        CHECK_ERR("a missing folder in a `\\` path: I/O error naming the path",
                  katachi_mesh_read(back, &none), KATACHI_STATUS_IO_ERROR,
                  "\\no such folder\\x.off");
    }
    katachi_mesh_free(m);
}
#endif

/* `text` with every "\n" made "\r\n" (malloc'd; *len its length). */
static char *crlf(const char *text, size_t n, size_t *len)
{
    char *out = (char *)malloc(2 * n + 1);
    size_t i, j = 0;
    if (out == NULL) exit(1);
    for (i = 0; i < n; i++) {
        if (text[i] == '\n') out[j++] = '\r';
        out[j++] = text[i];
    }
    out[j] = '\0';
    *len = j;
    return out;
}

static void test_line_endings(void)
{
    static const char *const formats[2] = {"obj", "off"};
    /* An ASCII PLY quad, as a Windows editor may save it (CRLF). */
    static const char ply_lf[] = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\n"
                                 "property double y\nproperty double z\nelement face 1\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    KatachiMesh *m = cube();
    KatachiMesh *quad = NULL;
    char path[1024], crlf_path[1024], label[256];
    char *bytes, *windows;
    size_t len = 0, wlen = 0;
    int i;
    for (i = 0; i < 2; i++) {
        snprintf(path, sizeof path, "%s/lines.%s", dir, formats[i]);
        snprintf(crlf_path, sizeof crlf_path, "%s/crlf.%s", dir, formats[i]);
        snprintf(label, sizeof label, "%s: write", formats[i]);
        CHECK_OK(label, katachi_mesh_write(m, path));
        bytes = read_all(path, &len);
        snprintf(label, sizeof label, "%s: lines end in LF, no CR anywhere", formats[i]);
        CHECK(label, bytes != NULL && len > 0 && memchr(bytes, '\r', len) == NULL &&
                         bytes[len - 1] == '\n');
        if (bytes == NULL) continue;
        windows = crlf(bytes, len, &wlen);
        write_all(crlf_path, windows, wlen);
        snprintf(label, sizeof label, "%s: the file with CRLF line ends reads as the LF one",
                 formats[i]);
        CHECK(label, reads_as(label, crlf_path, m));
        free(windows);
        free(bytes);
        remove_utf8(path);
        remove_utf8(crlf_path);
    }
    /* Binary PLY (katachi's default): the header's lines end in LF. */
    snprintf(path, sizeof path, "%s/lines.ply", dir);
    CHECK_OK("ply: write", katachi_mesh_write(m, path));
    bytes = read_all(path, &len);
    CHECK("ply: the header's lines end in LF, no CR in it",
          bytes != NULL && strstr(bytes, "\nend_header\n") != NULL &&
              memchr(bytes, '\r', (size_t)(strstr(bytes, "end_header") - bytes)) == NULL);
    free(bytes);
    remove_utf8(path);
    /* ASCII PLY with CRLF reads as with LF. */
    snprintf(path, sizeof path, "%s/quad_lf.ply", dir);
    snprintf(crlf_path, sizeof crlf_path, "%s/quad_crlf.ply", dir);
    write_all(path, ply_lf, strlen(ply_lf));
    windows = crlf(ply_lf, strlen(ply_lf), &wlen);
    write_all(crlf_path, windows, wlen);
    free(windows);
    if (CHECK_OK("ascii ply (LF): read", katachi_mesh_read(path, &quad))) {
        CHECK("ascii ply: the file with CRLF line ends reads as the LF one",
              reads_as("ascii ply (CRLF)", crlf_path, quad));
        katachi_mesh_free(quad);
    }
    remove_utf8(path);
    remove_utf8(crlf_path);
    katachi_mesh_free(m);
}

int main(void)
{
    char path[1024];
    int i;
    if (temp_dir_make(dir, sizeof dir) != 0) {
        printf("FAIL cannot make a temporary directory %s\n", dir);
        return 1;
    }
    printf("katachi %s, file names and line endings from C99 in %s\n", katachi_version_string(),
           dir);
    test_names();
#ifdef _WIN32
    test_separators();
#endif
    test_line_endings();
    for (i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/%s/%s", dir, FOLDER, NAMES[i]);
        remove_utf8(path);
    }
    snprintf(path, sizeof path, "%s/%s", dir, FOLDER);
    CHECK("the folders are empty at the end",
          rmdir_utf8(path) == 0 && temp_dir_remove(dir) == 0);
    return check_finish();
}
