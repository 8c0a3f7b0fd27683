/*
 * subdivide: solid-aware Catmull-Clark subdivision of a mesh file with the katachi C library.
 *
 *     subdivide INPUT OUTPUT [LEVELS]
 *
 * Reads INPUT (.obj, .ply or .off), subdivides it LEVELS times (default: the library's
 * default, 1 level), writes OUTPUT (the format follows the extension) and prints the vertex
 * and face counts before and after. Every katachi call returns a status; when one fails,
 * katachi_last_error_message() says what was wrong and where.
 *
 * Build it against an installed katachi (`cargo xtask install --prefix P`):
 *
 *     cc -std=c99 subdivide.c $(pkg-config --cflags --libs katachi) -o subdivide
 *
 * License: MIT OR Apache-2.0.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <katachi.h>

/* Reports the failed step with katachi's message for it. */
static void report(const char *step)
{
    fprintf(stderr, "subdivide: %s: %s\n", step, katachi_last_error_message());
}

/* Prints "LABEL: V vertices, F faces"; returns 0, or 1 after reporting an error. */
static int print_counts(const char *label, const KatachiMesh *mesh)
{
    KatachiMeshCounts counts = katachi_mesh_counts_default();
    if (katachi_mesh_counts(mesh, &counts) != KATACHI_STATUS_OK) {
        report("counting");
        return 1;
    }
    printf("%s: %lu vertices, %lu faces\n", label, (unsigned long)counts.vertex_count,
           (unsigned long)counts.face_count);
    return 0;
}

int main(int argc, char **argv)
{
    KatachiSubdivideOptions options = katachi_subdivide_options_default();
    KatachiMesh *input = NULL;
    KatachiSubdivision *subdivision = NULL;
    KatachiMesh *output = NULL;
    char label[64];
    int exit_code = 1;

    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: %s INPUT OUTPUT [LEVELS]\n", argc > 0 ? argv[0] : "subdivide");
        return 2;
    }
    if (argc == 4) {
        char *end = NULL;
        unsigned long levels = strtoul(argv[3], &end, 10);
        if (argv[3][0] < '0' || argv[3][0] > '9' || *end != '\0' || levels > UINT32_MAX) {
            fprintf(stderr, "subdivide: LEVELS must be a whole number, not \"%s\"\n", argv[3]);
            return 2;
        }
        options.levels = (uint32_t)levels; /* katachi itself checks the range (1 to 8) */
    }

    if (katachi_mesh_read(argv[1], &input) != KATACHI_STATUS_OK) {
        report("reading the input");
        goto done;
    }
    if (print_counts("input", input) != 0) {
        goto done;
    }
    if (katachi_subdivide(input, &options, &subdivision) != KATACHI_STATUS_OK) {
        report("subdividing");
        goto done;
    }
    if (katachi_subdivision_mesh(subdivision, &output) != KATACHI_STATUS_OK) {
        report("taking the refined mesh");
        goto done;
    }
    sprintf(label, "after %lu level%s", (unsigned long)options.levels,
            options.levels == 1 ? "" : "s");
    if (print_counts(label, output) != 0) {
        goto done;
    }
    if (katachi_mesh_write(output, argv[2]) != KATACHI_STATUS_OK) {
        report("writing the output");
        goto done;
    }
    printf("wrote %s\n", argv[2]);
    exit_code = 0;

done:
    /* The free functions accept NULL, so one exit path serves every failure. */
    katachi_mesh_free(output);
    katachi_subdivision_free(subdivision);
    katachi_mesh_free(input);
    return exit_code;
}
