/*
 * Shapes with known counts, as the flat arrays katachi_mesh_create takes; shared by the
 * C and C++ link tests. They match katachi's own generated shapes (src/mesh/shapes.rs).
 */
#ifndef KATACHI_TEST_SHAPES_H
#define KATACHI_TEST_SHAPES_H

#include <stdint.h>

/* The unit cube centred at the origin: vertex i has x = ±0.5 by bit 0, y by bit 1, z by bit 2.
 * 8 vertices, 6 quads, 12 edges, χ = 2. */
static const double CUBE_POSITIONS[8 * 3] = {
    -0.5, -0.5, -0.5, 0.5, -0.5, -0.5, -0.5, 0.5, -0.5, 0.5, 0.5, -0.5,
    -0.5, -0.5, 0.5,  0.5, -0.5, 0.5,  -0.5, 0.5, 0.5,  0.5, 0.5, 0.5,
};
static const uint32_t CUBE_LOOP_SIZES[6] = {4, 4, 4, 4, 4, 4};
static const uint32_t CUBE_FACE_LOOP_COUNTS[6] = {1, 1, 1, 1, 1, 1};
static const uint32_t CUBE_CORNERS[24] = {
    0, 2, 3, 1, /* z = -0.5 */
    4, 5, 7, 6, /* z = +0.5 */
    0, 1, 5, 4, /* y = -0.5 */
    2, 6, 7, 3, /* y = +0.5 */
    0, 4, 6, 2, /* x = -0.5 */
    1, 3, 7, 5, /* x = +0.5 */
};

/* A 2 × 2 × 0.25 square plate with a 1 × 1 square through hole. Its top and bottom faces are
 * faces with holes (an outer loop plus a clockwise hole loop): 16 vertices, 10 faces,
 * 12 loops, 48 corners, 24 edges, χ = 0, genus 1.
 * Vertices: 0..3 outer bottom, 4..7 outer top, 8..11 inner bottom, 12..15 inner top. */
static const double PLATE_POSITIONS[16 * 3] = {
    -1.0, -1.0, 0.0,  1.0, -1.0, 0.0,  1.0, 1.0, 0.0,  -1.0, 1.0, 0.0,
    -1.0, -1.0, 0.25, 1.0, -1.0, 0.25, 1.0, 1.0, 0.25, -1.0, 1.0, 0.25,
    -0.5, -0.5, 0.0,  0.5, -0.5, 0.0,  0.5, 0.5, 0.0,  -0.5, 0.5, 0.0,
    -0.5, -0.5, 0.25, 0.5, -0.5, 0.25, 0.5, 0.5, 0.25, -0.5, 0.5, 0.25,
};
static const uint32_t PLATE_LOOP_SIZES[12] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4};
static const uint32_t PLATE_FACE_LOOP_COUNTS[10] = {2, 2, 1, 1, 1, 1, 1, 1, 1, 1};
static const uint32_t PLATE_CORNERS[48] = {
    4, 5, 6, 7,     15, 14, 13, 12, /* top: outer loop, hole */
    3, 2, 1, 0,     8, 9, 10, 11,   /* bottom: outer loop, hole */
    0, 1, 5, 4,     9, 8, 12, 13,   /* outer wall 0, hole wall 0 */
    1, 2, 6, 5,     10, 9, 13, 14,  /* outer wall 1, hole wall 1 */
    2, 3, 7, 6,     11, 10, 14, 15, /* outer wall 2, hole wall 2 */
    3, 0, 4, 7,     8, 11, 15, 12,  /* outer wall 3, hole wall 3 */
};

/* The same plate with its top and bottom split into four quads each, so that file formats
 * without faces with holes can store it: 16 vertices, 16 quads, 32 edges, χ = 0, genus 1. */
static const uint32_t FRAME_LOOP_SIZES[16] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4};
static const uint32_t FRAME_FACE_LOOP_COUNTS[16] = {1, 1, 1, 1, 1, 1, 1, 1,
                                                    1, 1, 1, 1, 1, 1, 1, 1};
static const uint32_t FRAME_CORNERS[64] = {
    4, 5, 13, 12,   5, 6, 14, 13,   6, 7, 15, 14,   7, 4, 12, 15, /* top ring */
    1, 0, 8, 9,     2, 1, 9, 10,    3, 2, 10, 11,   0, 3, 11, 8,  /* bottom ring */
    0, 1, 5, 4,     9, 8, 12, 13,   1, 2, 6, 5,     10, 9, 13, 14,
    2, 3, 7, 6,     11, 10, 14, 15, 3, 0, 4, 7,     8, 11, 15, 12,
};

#endif /* KATACHI_TEST_SHAPES_H */
