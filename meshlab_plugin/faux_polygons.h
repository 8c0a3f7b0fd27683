// katachi MeshLab plugin: polygons <-> triangles with faux edges.
//
// MeshLab stores every mesh as triangles. A polygon is a group of triangles joined by
// "faux" edges (vcg's per-face-edge FAUX flag): an edge between two triangles of the same
// polygon. These functions convert between that form and katachi's polygon arrays. They are
// topology bookkeeping only (which triangles form which polygon, and in what order its
// corners run); no coordinate is read, so they hold no geometry.
//
// Independent of MeshLab and Qt, so the test harness can check them on plain arrays.
//
// License: MIT OR Apache-2.0.

#ifndef KATACHI_MESHLAB_FAUX_POLYGONS_H
#define KATACHI_MESHLAB_FAUX_POLYGONS_H

#include <cstddef>
#include <cstdint>
#include <vector>

namespace katachi_meshlab {

/// Triangles in MeshLab's form: three vertex indices each, and per triangle a 3-bit mask
/// whose bit i says that edge i (from corner i to corner i+1) is faux.
struct FauxTriangles {
    std::vector<uint32_t> corners; // 3 x triangle count
    std::vector<uint8_t> faux;     // 1 x triangle count
};

/// Simple polygons, as katachi_mesh_create takes them with one loop per face.
struct Polygons {
    std::vector<uint32_t> sizes;   // corners of each polygon
    std::vector<uint32_t> corners; // vertex indices, polygon after polygon
    /// Groups of triangles joined by faux edges whose outline is not one simple loop (a
    /// polygon with holes or a pinched outline). Their triangles are kept as separate
    /// triangles, and this counts such groups.
    std::size_t groups_kept_as_triangles = 0;
    /// Faux edges with no matching faux edge on a neighbouring triangle (a faux edge on the
    /// boundary, a non-manifold or inconsistently oriented faux edge); treated as real edges.
    std::size_t unmatched_faux_edges = 0;
};

/// Rebuilds polygons from faux edges. A triangle without faux edges is a polygon of its own.
/// Two triangles are joined across an edge when both mark that edge faux and traverse it in
/// opposite directions, and nothing else uses it. Each group of joined triangles becomes one
/// polygon when its outline is a single simple loop (corners in the triangles' orientation,
/// starting at the first outline edge of the group's first triangle); otherwise its
/// triangles stay separate. Polygons come in the order of their first triangle.
Polygons polygons_from_faux_triangles(const FauxTriangles &tris);

/// Splits polygons into triangle fans (corner 0, k+1, k+2) with faux interior edges: a quad
/// becomes a pair of triangles sharing one faux edge. Triangles stay triangles.
/// Also fills `tri_polygon` with each triangle's polygon.
FauxTriangles faux_triangles_from_polygons(const std::vector<uint32_t> &sizes,
                                           const std::vector<uint32_t> &corners,
                                           std::vector<uint32_t> *tri_polygon = nullptr);

} // namespace katachi_meshlab

#endif
