// katachi MeshLab plugin: polygons <-> triangles with faux edges (see faux_polygons.h).
//
// License: MIT OR Apache-2.0.

#include "faux_polygons.h"

#include <numeric>
#include <unordered_map>

namespace katachi_meshlab {

namespace {

constexpr uint32_t kNone = UINT32_MAX;
constexpr uint32_t kMany = UINT32_MAX - 1;

uint64_t edge_key(uint32_t from, uint32_t to) { return (uint64_t(from) << 32) | to; }

uint32_t find_root(std::vector<uint32_t> &parent, uint32_t t) {
    while (parent[t] != t) {
        parent[t] = parent[parent[t]];
        t = parent[t];
    }
    return t;
}

} // namespace

Polygons polygons_from_faux_triangles(const FauxTriangles &tris) {
    const std::size_t n = tris.faux.size();
    Polygons out;

    // Directed edge -> the half-edge (3 x triangle + side) that runs along it; kMany when
    // several do (a non-manifold or inconsistently oriented edge).
    std::unordered_map<uint64_t, uint32_t> half_edges;
    half_edges.reserve(3 * n);
    for (std::size_t t = 0; t < n; ++t) {
        for (int i = 0; i < 3; ++i) {
            const uint32_t a = tris.corners[3 * t + i], b = tris.corners[3 * t + (i + 1) % 3];
            auto ins = half_edges.emplace(edge_key(a, b), uint32_t(3 * t + i));
            if (!ins.second) ins.first->second = kMany;
        }
    }
    auto twin_of = [&](uint32_t h) -> uint32_t {
        const uint32_t t = h / 3, i = h % 3;
        const uint32_t a = tris.corners[3 * t + i], b = tris.corners[3 * t + (i + 1) % 3];
        auto it = half_edges.find(edge_key(b, a));
        if (it == half_edges.end() || it->second == kMany) return kNone;
        // A faux edge joins only when its reverse is unique too.
        if (half_edges.at(edge_key(a, b)) == kMany) return kNone;
        return it->second;
    };

    // joined[h]: half-edge h is interior to a polygon (faux on both sides).
    std::vector<bool> joined(3 * n, false);
    std::vector<uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    for (std::size_t t = 0; t < n; ++t) {
        for (uint32_t i = 0; i < 3; ++i) {
            if (!(tris.faux[t] & (1u << i))) continue;
            const uint32_t h = uint32_t(3 * t + i);
            const uint32_t g = twin_of(h);
            if (g == kNone || !(tris.faux[g / 3] & (1u << (g % 3))) || g / 3 == t) {
                ++out.unmatched_faux_edges;
                continue;
            }
            joined[h] = true;
            const uint32_t ra = find_root(parent, uint32_t(t)), rb = find_root(parent, g / 3);
            if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
        }
    }

    // Members of each group, in triangle order; groups in the order of their first triangle
    // (the root is the group's smallest triangle).
    std::vector<std::vector<uint32_t>> members(n);
    for (std::size_t t = 0; t < n; ++t) members[find_root(parent, uint32_t(t))].push_back(uint32_t(t));

    out.sizes.reserve(n);
    out.corners.reserve(3 * n);
    std::unordered_map<uint32_t, uint32_t> next; // outline: start vertex -> end vertex
    for (std::size_t r = 0; r < n; ++r) {
        const std::vector<uint32_t> &group = members[r];
        if (group.empty()) continue;
        auto keep_triangles = [&]() {
            for (uint32_t t : group) {
                out.sizes.push_back(3);
                out.corners.insert(out.corners.end(), tris.corners.begin() + 3 * t,
                                   tris.corners.begin() + 3 * t + 3);
            }
        };
        if (group.size() == 1) {
            keep_triangles();
            continue;
        }
        next.clear();
        bool simple = true;
        uint32_t first = kNone;
        std::size_t outline_edges = 0;
        for (uint32_t t : group) {
            for (uint32_t i = 0; i < 3; ++i) {
                if (joined[3 * t + i]) continue;
                const uint32_t a = tris.corners[3 * t + i], b = tris.corners[3 * t + (i + 1) % 3];
                if (!next.emplace(a, b).second) simple = false; // the outline passes a twice
                if (first == kNone) first = a;
                ++outline_edges;
            }
        }
        if (!simple || first == kNone) {
            ++out.groups_kept_as_triangles;
            keep_triangles();
            continue;
        }
        // Walk the outline from `first`; it must come back after visiting every edge.
        std::vector<uint32_t> loop;
        uint32_t v = first;
        do {
            loop.push_back(v);
            auto it = next.find(v);
            if (it == next.end()) break;
            v = it->second;
        } while (v != first && loop.size() <= outline_edges);
        if (v != first || loop.size() != outline_edges || loop.size() < 3) {
            ++out.groups_kept_as_triangles; // several loops (a polygon with holes) or broken
            keep_triangles();
            continue;
        }
        out.sizes.push_back(uint32_t(loop.size()));
        out.corners.insert(out.corners.end(), loop.begin(), loop.end());
    }
    return out;
}

FauxTriangles faux_triangles_from_polygons(const std::vector<uint32_t> &sizes,
                                           const std::vector<uint32_t> &corners,
                                           std::vector<uint32_t> *tri_polygon) {
    FauxTriangles out;
    std::size_t tri_count = 0;
    for (uint32_t s : sizes) tri_count += s >= 3 ? s - 2 : 0;
    out.corners.reserve(3 * tri_count);
    out.faux.reserve(tri_count);
    if (tri_polygon) {
        tri_polygon->clear();
        tri_polygon->reserve(tri_count);
    }
    std::size_t at = 0;
    for (std::size_t p = 0; p < sizes.size(); ++p) {
        const uint32_t s = sizes[p];
        const uint32_t *c = corners.data() + at;
        at += s;
        if (s < 3) continue;
        // Fan k: (c0, c[k+1], c[k+2]). Edge 0 (c0 -> c[k+1]) is interior unless k == 0;
        // edge 1 is on the outline; edge 2 (c[k+2] -> c0) is interior unless k == s - 3.
        for (uint32_t k = 0; k + 2 < s; ++k) {
            out.corners.push_back(c[0]);
            out.corners.push_back(c[k + 1]);
            out.corners.push_back(c[k + 2]);
            uint8_t faux = 0;
            if (k > 0) faux |= 1u << 0;
            if (k + 3 < s) faux |= 1u << 2;
            out.faux.push_back(faux);
            if (tri_polygon) tri_polygon->push_back(uint32_t(p));
        }
    }
    return out;
}

} // namespace katachi_meshlab
