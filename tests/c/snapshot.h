/*
 * Snapshot: everything a caller can read back from a mesh through the copy-out functions,
 * to compare meshes (a clone, a file read back) and to prove that failing calls change
 * nothing. Shared by the C link tests.
 */
#ifndef KATACHI_TEST_SNAPSHOT_H
#define KATACHI_TEST_SNAPSHOT_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "katachi.h"

/* Everything a caller can read back from a mesh, to prove failing calls change nothing. */
typedef struct Snapshot {
    KatachiMeshCounts counts;
    double *positions;
    uint32_t *loop_sizes, *face_loop_counts, *corners, *sharp_edges;
    double *edge_sharpness, *vertex_sharpness;
} Snapshot;

static inline void *alloc(size_t n, size_t size)
{
    void *p = calloc(n == 0 ? 1 : n, size);
    if (p == NULL) {
        printf("FAIL out of memory\n");
        exit(1);
    }
    return p;
}

static inline Snapshot snapshot(const KatachiMesh *m)
{
    Snapshot s;
    KatachiStatus st;
    s.counts = katachi_mesh_counts_default();
    st = katachi_mesh_counts(m, &s.counts);
    s.positions = alloc(3 * (size_t)s.counts.vertex_count, sizeof(double));
    s.loop_sizes = alloc(s.counts.loop_count, sizeof(uint32_t));
    s.face_loop_counts = alloc(s.counts.face_count, sizeof(uint32_t));
    s.corners = alloc(s.counts.corner_count, sizeof(uint32_t));
    s.sharp_edges = alloc(2 * (size_t)s.counts.sharp_edge_count, sizeof(uint32_t));
    s.edge_sharpness = alloc(s.counts.sharp_edge_count, sizeof(double));
    s.vertex_sharpness = alloc(s.counts.vertex_count, sizeof(double));
    st |= katachi_mesh_copy_positions(m, s.positions, 3 * (size_t)s.counts.vertex_count);
    st |= katachi_mesh_copy_faces(m, s.loop_sizes, s.counts.loop_count, s.face_loop_counts,
                                  s.counts.face_count, s.corners, s.counts.corner_count);
    st |= katachi_mesh_copy_sharp_edges(m, s.sharp_edges, s.edge_sharpness,
                                        s.counts.sharp_edge_count);
    st |= katachi_mesh_copy_vertex_sharpness(m, s.vertex_sharpness, s.counts.vertex_count);
    if (st != KATACHI_STATUS_OK) {
        printf("FAIL snapshot: %s\n", katachi_last_error_message());
        exit(1);
    }
    return s;
}

static inline int snapshots_equal(const Snapshot *a, const Snapshot *b)
{
    const KatachiMeshCounts *c = &a->counts;
    return memcmp(&a->counts, &b->counts, sizeof a->counts) == 0 &&
           memcmp(a->positions, b->positions, 3 * c->vertex_count * sizeof(double)) == 0 &&
           memcmp(a->loop_sizes, b->loop_sizes, c->loop_count * sizeof(uint32_t)) == 0 &&
           memcmp(a->face_loop_counts, b->face_loop_counts, c->face_count * sizeof(uint32_t)) == 0 &&
           memcmp(a->corners, b->corners, c->corner_count * sizeof(uint32_t)) == 0 &&
           memcmp(a->sharp_edges, b->sharp_edges, 2 * c->sharp_edge_count * sizeof(uint32_t)) == 0 &&
           memcmp(a->edge_sharpness, b->edge_sharpness, c->sharp_edge_count * sizeof(double)) == 0 &&
           memcmp(a->vertex_sharpness, b->vertex_sharpness, c->vertex_count * sizeof(double)) == 0;
}

static inline void snapshot_free(Snapshot *s)
{
    free(s->positions);
    free(s->loop_sizes);
    free(s->face_loop_counts);
    free(s->corners);
    free(s->sharp_edges);
    free(s->edge_sharpness);
    free(s->vertex_sharpness);
}

#endif /* KATACHI_TEST_SNAPSHOT_H */
