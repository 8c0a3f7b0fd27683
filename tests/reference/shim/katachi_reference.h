/*
 * katachi-reference shim: a C interface over OpenSubdiv 3.5 (Far) and OpenMesh 9 (CatmullClarkT),
 * and an exact stroke cut through CGAL 5.
 *
 * Only the Rust crate `katachi-reference` calls this; bindgen reads this header in build.rs.
 *
 * Conventions:
 *  - Every entry point returns a status (KR_STATUS_*) and, through `out`, a result handle, also on
 *    failure (then it holds the error message). The caller frees it with kr_result_free. `*out` is
 *    NULL only when even the handle could not be allocated.
 *  - No C++ exception leaves the shim: every entry point catches everything.
 *  - Arrays in a result are keyed by (array id, level): see KR_F64_* and KR_U32_*.
 *  - Indices are uint32_t, coordinates double.
 */
#ifndef KATACHI_REFERENCE_SHIM_H
#define KATACHI_REFERENCE_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes. */
#define KR_STATUS_OK 0u
/* The library rejected the input (OpenSubdiv's factory failed, OpenMesh refused a face). */
#define KR_STATUS_REJECTED 1u
/* The arguments are malformed (null pointers, indices out of range, sizes that do not add up). */
#define KR_STATUS_BAD_ARGUMENT 2u
/* A C++ exception was caught (including std::bad_alloc). */
#define KR_STATUS_EXCEPTION 3u

/* Sdc::Options::VtxBoundaryInterpolation */
#define KR_BOUNDARY_NONE 0u
#define KR_BOUNDARY_EDGE_ONLY 1u
#define KR_BOUNDARY_EDGE_AND_CORNER 2u

/* Sdc::Options::CreasingMethod */
#define KR_CREASE_UNIFORM 0u
#define KR_CREASE_CHAIKIN 1u

/* Sdc::Options::FVarLinearInterpolation */
#define KR_FVAR_NONE 0u
#define KR_FVAR_CORNERS_ONLY 1u
#define KR_FVAR_CORNERS_PLUS1 2u
#define KR_FVAR_CORNERS_PLUS2 3u
#define KR_FVAR_BOUNDARIES 4u
#define KR_FVAR_ALL 5u

/* The highest refinement level the shim accepts. */
#define KR_MAX_LEVEL 10u

/* double arrays of a result. */
/* Vertex positions, 3 per vertex. Last level always; every level with level_info. */
#define KR_F64_POSITIONS 0u
/* Face-varying values, 2 per face corner in KR_U32_FACE_VERTICES order. Last level, fvar only. */
#define KR_F64_FVAR 1u
/* Sharpness of each edge of the level (OpenSubdiv's float, widened). level_info only. */
#define KR_F64_EDGE_SHARPNESS 2u
/* Sharpness of each vertex of the level. level_info only. */
#define KR_F64_VERTEX_SHARPNESS 3u
/* Seconds spent inside the library (steady clock), stored under level 0. OpenSubdiv:
 * [TopologyRefinerFactory::Create, RefineUniform, PrimvarRefinerReal::Interpolate (all levels)];
 * OpenMesh: [building the PolyMesh, CatmullClarkT]. The shim's own copying is not counted. */
#define KR_F64_TIMINGS 4u

/* Exact stroke cut (kr_cgal_stroke_cut): minimum angle in degrees (in 3D) of each new triangle,
 * in KR_U32_CUT_NEW_FACES order. Level 0. */
#define KR_F64_CUT_MIN_ANGLES 5u

/* Max-flow (kr_boost_bk_max_flow): [the maximum flow] (exact: flows stay below 2^53). Level 0. */
#define KR_F64_FLOW 6u

/* uint32_t arrays of a result. */
/* Corner count of each face. Last level always; every level with level_info. */
#define KR_U32_FACE_SIZES 0u
/* Vertices of each face, concatenated. Last level always; every level with level_info. */
#define KR_U32_FACE_VERTICES 1u
/* [vertices, edges, faces, face-varying values] of the level. Every level of an OpenSubdiv run;
 * the edge count of the last level is 0 unless level_info (no full topology there). */
#define KR_U32_COUNTS 2u
/* The two vertices of each edge, in OpenSubdiv's edge order. level_info only. */
#define KR_U32_EDGE_VERTICES 3u
/* Sdc::Crease::Rule of each vertex (1 smooth, 2 dart, 4 crease, 8 corner). level_info only. */
#define KR_U32_VERTEX_RULE 4u
/* Per edge: bit 0 boundary, bit 1 non-manifold, bit 2 infinitely sharp, bit 3 semi-sharp. */
#define KR_U32_EDGE_FLAGS 5u
/* Per vertex: bit 0 boundary, bit 1 non-manifold, bit 2 infinitely sharp, bit 3 semi-sharp. */
#define KR_U32_VERTEX_FLAGS 6u
/* Refinement of level l into l + 1, stored under the parent level l (level_info only): */
/* child vertex (at l + 1) of each face of l */
#define KR_U32_FACE_CHILD_VERTEX 7u
/* child vertex of each edge of l */
#define KR_U32_EDGE_CHILD_VERTEX 8u
/* child vertex of each vertex of l */
#define KR_U32_VERTEX_CHILD_VERTEX 9u
/* child faces of each face of l, concatenated (as many as the face has corners) */
#define KR_U32_FACE_CHILD_FACES 10u
/* the two child edges of each edge of l */
#define KR_U32_EDGE_CHILD_EDGES 11u
/* Parent face (at l - 1) of each face of level l >= 1, stored under the child level l. */
#define KR_U32_FACE_PARENT_FACE 12u
/* Exact stroke cut, all at level 0 (positions, face sizes and face vertices are the cut mesh's): */
/* source face of each output face */
#define KR_U32_FACE_ORIGIN 13u
/* the output faces that replace a split input face (all pieces of every split face) */
#define KR_U32_CUT_NEW_FACES 14u
/* 3 per new vertex (new vertices follow the input ones): [0, face, face] inside that face, or
 * [1, u, v] on the edge u < v */
#define KR_U32_CUT_VERTEX_SOURCE 15u
/* [faces crossed on screen, faces split, new triangles (pieces minus the faces they replace),
 *  new vertices, faces with a corner behind the eye (w <= 0), faces with no area on screen,
 *  faces of those two kinds split only because a neighbour put points on their edges] */
#define KR_U32_CUT_COUNTS 16u

/* Max-flow (kr_boost_bk_max_flow): per node, 1 if it is on the minimum cut's source side (Boost's
 * black: the source search tree at the end), else 0. Level 0. */
#define KR_U32_FLOW_SOURCE_SIDE 17u

/* Exact stroke cut modes. */
/* Every face under the stroke is cut, front and back (the only mode the reference implements). */
#define KR_CUT_THROUGH_ALL 0u

typedef struct kr_mesh {
    uint32_t num_vertices;
    const double *positions; /* 3 * num_vertices */
    uint32_t num_faces;
    const uint32_t *face_sizes;    /* num_faces, each >= 3 */
    uint32_t num_face_vertices;    /* sum of face_sizes */
    const uint32_t *face_vertices; /* num_face_vertices */
} kr_mesh;

typedef struct kr_creases {
    uint32_t num_edges;
    const uint32_t *edge_vertices; /* 2 * num_edges, each pair an existing edge */
    const double *edge_sharpness;  /* num_edges */
    uint32_t num_corners;
    const uint32_t *corner_vertices; /* num_corners */
    const double *corner_sharpness;  /* num_corners */
} kr_creases;

typedef struct kr_osd_options {
    uint32_t boundary; /* KR_BOUNDARY_* */
    uint32_t crease;   /* KR_CREASE_* */
    uint32_t fvar;     /* KR_FVAR_* */
    uint32_t level_info; /* non-zero: keep topology, tags and maps of every level */
} kr_osd_options;

typedef struct kr_fvar {
    uint32_t num_values;
    const double *values;    /* 2 * num_values */
    const uint32_t *indices; /* one per face corner of the base mesh (num_face_vertices) */
} kr_fvar;

/* A view: clip = view_proj * [x, y, z, 1] (column-major), ndc = clip.xyz / clip.w, pixels
 * (x0 + (ndc.x + 1) / 2 * width, y0 + (1 - ndc.y) / 2 * height): top-left origin, y down. */
typedef struct kr_view {
    double view_proj[16];
    double viewport[4]; /* x0, y0, width, height */
} kr_view;

/* A flow network: nodes 0..num_nodes with capacities from the source and to the sink, and
 * edges between two nodes with a capacity in each direction. */
typedef struct kr_flow_network {
    uint32_t num_nodes;
    const int64_t *source_caps; /* num_nodes, >= 0 */
    const int64_t *sink_caps;   /* num_nodes, >= 0 */
    uint32_t num_edges;
    const uint32_t *edge_nodes; /* 2 * num_edges: a, b */
    const int64_t *edge_caps;   /* 2 * num_edges: capacity a -> b, then b -> a; >= 0 */
} kr_flow_network;

typedef struct kr_result kr_result;

/*
 * OpenSubdiv uniform Catmull-Clark refinement to `level` (0..=KR_MAX_LEVEL): a Far::TopologyRefiner
 * built with TopologyRefinerFactory<TopologyDescriptor>, RefineUniform (with full topology in the
 * last level only when options->level_info asks for it), positions (and the optional face-varying
 * channel) interpolated level by level with Far::PrimvarRefinerReal<double>. `creases` and `fvar`
 * may be NULL. Any warning from the factory (e.g. a crease on a vertex pair that is not an edge)
 * fails the call with KR_STATUS_REJECTED.
 */
uint32_t kr_osd_catmark(const kr_mesh *mesh, const kr_creases *creases, const kr_osd_options *options,
                        uint32_t level, const kr_fvar *fvar, kr_result **out);

/*
 * OpenMesh 9 OpenMesh::Subdivider::Uniform::CatmullClarkT on a PolyMesh_ArrayKernelT with
 * double-precision points, `level` steps (0..=KR_MAX_LEVEL).
 */
uint32_t kr_openmesh_catmull_clark(const kr_mesh *mesh, uint32_t level, kr_result **out);

/*
 * Exact stroke cut of a triangle mesh (CGAL 5 Constrained_Delaunay_triangulation_2 over
 * Exact_predicates_exact_constructions_kernel with Exact_intersections_tag). Every face whose
 * corners are all in front of the eye (w > 0) and whose screen image has an area and meets the
 * stroke (`num_stroke_points` pixel points, 2 doubles each) gets the stroke's pieces clipped to
 * it as constraints of a constrained Delaunay triangulation of its screen image; new vertices are
 * lifted onto the face with perspective-correct barycentrics (interpolated with 1 / w). A point on
 * an edge is made once per edge and shared by all its faces; faces that cannot be cut on screen
 * but have such points on their edges are split in their own parameter domain, so the output has
 * no cracks. Output faces keep the input order (a split face's pieces in its place) and
 * orientation. `mode` must be KR_CUT_THROUGH_ALL. Fewer than 2 stroke points, a zero-length
 * stroke, non-finite values, a non-positive viewport size or non-triangle faces are
 * KR_STATUS_BAD_ARGUMENT. KR_F64_TIMINGS holds [seconds spent cutting].
 */
uint32_t kr_cgal_stroke_cut(const kr_mesh *mesh, const kr_view *view, const double *stroke_px,
                            uint32_t num_stroke_points, uint32_t mode, kr_result **out);

/*
 * Boost.Graph 1.74 boykov_kolmogorov_max_flow on an adjacency_list<vecS, vecS, directedS> holding
 * the network plus a source and a sink vertex (each edge an arc pair with edge_reverse). The graph
 * is built once and the max-flow call repeated `repeats` (>= 1) times; KR_F64_TIMINGS holds the
 * seconds of each call (the library's own time: not the graph's construction), KR_F64_FLOW the
 * flow, KR_U32_FLOW_SOURCE_SIDE the source side of the last call.
 */
uint32_t kr_boost_bk_max_flow(const kr_flow_network *network, uint32_t repeats, kr_result **out);

/* The error message of a failed call ("" after success). Valid until kr_result_free. */
const char *kr_result_message(const kr_result *result);

/* Warnings the library printed during the call, one per line ("" if none). */
const char *kr_result_warnings(const kr_result *result);

/* An array of the result, or NULL (and *len = 0) if the result has no such array. */
const double *kr_result_f64(const kr_result *result, uint32_t array, uint32_t level, size_t *len);
const uint32_t *kr_result_u32(const kr_result *result, uint32_t array, uint32_t level, size_t *len);

/* Frees a result; NULL is allowed. */
void kr_result_free(kr_result *result);

#ifdef __cplusplus
}
#endif

#endif /* KATACHI_REFERENCE_SHIM_H */
