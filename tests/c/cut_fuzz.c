/*
 * The stroke cut through the C ABI on random input with numbers of every magnitude (C99):
 * small meshes with some coordinates huge, tiny or the largest finite, views whose matrix and
 * viewport entries are the same, strokes of ordinary, extreme and mixed points, both modes,
 * opened or not. Run under valgrind by `cargo xtask ctest`, so a read out of bounds or a use
 * of uninitialised memory fails the run. Every call must end in success with finite
 * positions, or in a typed failure (bad input, bad topology, an invalid argument) with a
 * message; never an internal error. Cases: KATACHI_CUT_FUZZ_CASES (default 150).
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "check.h"

static uint64_t state = 0x9e3779b97f4a7c15ull;

static uint64_t next_u64(void)
{
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
}

/* Uniform in [0, 1). */
static double unit(void) { return (double)(next_u64() >> 11) / 9007199254740992.0; }

static uint32_t below(uint32_t n) { return (uint32_t)(next_u64() % n); }

/* A number of any magnitude: mostly ordinary, else a power of ten from 1e-308 to 1e308, the
 * largest finite double, zero or the smallest normal one, of either sign. */
static double magnitude(double ordinary)
{
    double x;
    switch (below(6)) {
    case 0: x = pow(10.0, (double)((int)below(617) - 308)); break;
    case 1: x = below(2) ? DBL_MAX : DBL_MIN; break;
    case 2: x = 0.0; break;
    default: return (unit() - 0.5) * 2.0 * ordinary;
    }
    return below(2) ? -x : x;
}

/* An n × n grid of unit squares (two triangles each), some positions extreme. */
#define N 3
#define NV ((N + 1) * (N + 1))
#define NF (2 * N * N)

static KatachiMesh *random_mesh(void)
{
    double p[NV * 3];
    uint32_t corners[NF * 3], loop_sizes[NF], face_loops[NF];
    uint32_t i, j, k = 0;
    KatachiMesh *m = NULL;
    for (j = 0; j <= N; j++) {
        for (i = 0; i <= N; i++) {
            double *q = p + 3 * (j * (N + 1) + i);
            q[0] = (double)i;
            q[1] = (double)j;
            q[2] = 0.0;
        }
    }
    for (i = below(3); i > 0; i--) {
        p[below(NV * 3)] = magnitude(4.0);
    }
    for (j = 0; j < N; j++) {
        for (i = 0; i < N; i++) {
            uint32_t v = j * (N + 1) + i;
            uint32_t t[6] = {v, v + 1, v + N + 2, v, v + N + 2, v + N + 1};
            memcpy(corners + k, t, sizeof t);
            k += 6;
        }
    }
    for (i = 0; i < NF; i++) {
        loop_sizes[i] = 3;
        face_loops[i] = 1;
    }
    if (katachi_mesh_create(p, NV, loop_sizes, NF, face_loops, NF, corners, NF * 3, &m) !=
        KATACHI_STATUS_OK) {
        return NULL;
    }
    return m;
}

int main(void)
{
    const char *env = getenv("KATACHI_CUT_FUZZ_CASES");
    unsigned long cases = env ? strtoul(env, NULL, 10) : 150;
    unsigned long c, ok = 0, refused = 0, internal = 0, non_finite = 0, silent = 0;
    for (c = 0; c < cases; c++) {
        KatachiMesh *mesh = random_mesh();
        KatachiCut *cut = NULL;
        KatachiCutOptions o = katachi_cut_options_default();
        /* Seen from above, x and y in [-0.5, 3.5] over 400 × 400 pixels. */
        double vp[16] = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, -0.1, 0, -0.75, -0.75, 0, 1};
        double viewport[4] = {0.0, 0.0, 400.0, 400.0};
        double stroke[2 * 8];
        uint32_t i, n = 2 + below(7);
        KatachiStatus s;
        if (mesh == NULL) {
            continue;
        }
        for (i = below(3); i > 0; i--) {
            vp[below(16)] = magnitude(1.0);
        }
        for (i = below(2) * (1 + below(2)); i > 0; i--) {
            viewport[below(4)] = magnitude(400.0);
        }
        for (i = 0; i < n; i++) {
            int extreme = below(4) == 0;
            stroke[2 * i] = extreme ? magnitude(400.0) : 400.0 * unit();
            stroke[2 * i + 1] = extreme ? magnitude(400.0) : 400.0 * unit();
        }
        o.mode = below(2);
        o.open = below(2);
        s = katachi_cut_by_stroke(mesh, stroke, n, vp, viewport, &o, &cut);
        if (s == KATACHI_STATUS_OK) {
            KatachiCutInfo info = katachi_cut_info_default();
            KatachiMesh *out = NULL;
            ok++;
            if (katachi_cut_info(cut, &info) == KATACHI_STATUS_OK &&
                katachi_cut_mesh(cut, &out) == KATACHI_STATUS_OK) {
                double *q = malloc(sizeof(double) * 3 * (info.vertex_count + 1));
                if (q != NULL &&
                    katachi_mesh_copy_positions(out, q, 3 * (size_t)info.vertex_count) ==
                        KATACHI_STATUS_OK) {
                    for (i = 0; i < 3 * info.vertex_count; i++) {
                        non_finite += !isfinite(q[i]);
                    }
                }
                free(q);
                katachi_mesh_free(out);
            }
            katachi_cut_free(cut);
        } else {
            const char *m = katachi_last_error_message();
            refused++;
            internal += s == KATACHI_STATUS_INTERNAL_ERROR;
            silent += m == NULL || m[0] == '\0' || cut != NULL;
            if (s == KATACHI_STATUS_INTERNAL_ERROR) {
                printf("case %lu: %s\n", c, m);
            }
        }
        katachi_mesh_free(mesh);
    }
    printf("%lu cases: %lu cut, %lu refused\n", cases, ok, refused);
    CHECK("no internal error on any input", internal == 0);
    CHECK("every result has finite positions", non_finite == 0);
    CHECK("every refusal has a message and no result", silent == 0);
    CHECK("some inputs cut and some are refused", ok > 0 && refused > 0);
    return check_finish();
}
