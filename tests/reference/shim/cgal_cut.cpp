// katachi-reference shim: the exact stroke cut through CGAL 5 (Constrained_Delaunay_triangulation_2
// over Exact_predicates_exact_constructions_kernel). See kr_cgal_stroke_cut in katachi_reference.h.
//
// Why EPECK (and not EPICK with Exact_intersections_tag): the points this cut inserts are
// constructed (a stroke segment clipped against a triangle edge). With EPICK they would be rounded
// to double and land a little off the edge, inside or outside the triangle, so the two faces of an
// edge could not be shown to share them, and a point outside the triangle would break its
// triangulation. With EPECK every constructed point lies exactly on its edge, two faces compute
// the very same point for their common edge, and the triangulation's own intersection vertices
// (where the stroke crosses itself) are exact too. The cost (lazy exact numbers) only hits the few
// faces the stroke crosses.
#include "shim_internal.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace {

typedef CGAL::Exact_predicates_exact_constructions_kernel K;
typedef K::FT FT;
typedef K::Point_2 Point;
typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> Vb;
typedef CGAL::Constrained_triangulation_face_base_2<K> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_intersections_tag> Cdt;

const uint32_t UNSET = UINT32_MAX;

struct Vec3 {
    double x, y, z;
};
Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

// The smallest interior angle of triangle (a, b, c) in degrees; 0 if an edge has zero length.
double min_angle_deg(Vec3 a, Vec3 b, Vec3 c) {
    const double pi = 3.14159265358979323846;
    auto angle = [](Vec3 u, Vec3 v) { return std::atan2(norm(cross(u, v)), dot(u, v)); };
    if (norm(b - a) == 0.0 || norm(c - b) == 0.0 || norm(a - c) == 0.0) return 0.0;
    double m = std::min({angle(b - a, c - a), angle(c - b, a - b), angle(a - c, b - c)});
    return m * (180.0 / pi);
}

// A point inserted on a mesh edge, shared by every face of that edge.
struct EdgePoint {
    Point screen;     // exact, on the edge's screen segment
    FT s;             // exact screen parameter from the smaller vertex id to the larger
    uint32_t vertex;  // output vertex
};

uint64_t edge_key(uint32_t a, uint32_t b) {
    return (uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b));
}

struct Cutter {
    const kr_mesh &mesh;
    std::vector<Vec3> pos;           // input positions
    std::vector<double> sx, sy, w;   // screen position and clip w of each input vertex
    std::vector<bool> projectable;   // w > 0 and finite screen coordinates
    std::vector<Point> stroke;       // stroke points (consecutive duplicates removed)
    std::vector<std::array<double, 4>> seg_box;  // xmin, xmax, ymin, ymax of each segment

    std::map<uint64_t, std::vector<EdgePoint>> edge_points;
    std::vector<Vec3> out_pos;                       // input positions, then new vertices
    std::vector<uint32_t> new_vertex_source;         // 3 per new vertex: kind, a, b
    std::map<uint32_t, std::vector<std::array<uint32_t, 3>>> pieces;  // replaced face -> triangles
    uint32_t crossed = 0, behind = 0, degenerate = 0, fallback = 0;

    explicit Cutter(const kr_mesh &m) : mesh(m) {}

    std::array<uint32_t, 3> corners(uint32_t f) const {
        return {mesh.face_vertices[3 * f], mesh.face_vertices[3 * f + 1],
                mesh.face_vertices[3 * f + 2]};
    }

    Point screen(uint32_t v) const { return Point(sx[v], sy[v]); }

    uint32_t add_vertex(Vec3 p, uint32_t kind, uint32_t a, uint32_t b) {
        out_pos.push_back(p);
        new_vertex_source.insert(new_vertex_source.end(), {kind, a, b});
        return uint32_t(out_pos.size() - 1);
    }

    // The output vertex of screen point `p` on edge (a, b), created (and lifted, perspective-
    // correct along the edge) the first time any face of the edge asks for it.
    uint32_t edge_vertex(uint32_t a, uint32_t b, const Point &p) {
        auto &list = edge_points[edge_key(a, b)];
        for (const EdgePoint &e : list) {
            if (e.screen == p) return e.vertex;
        }
        const uint32_t u = std::min(a, b), v = std::max(a, b);
        const double dx = sx[v] - sx[u], dy = sy[v] - sy[u];
        // Exact: the divisor is formed from the exact corner coordinates, not from dx or dy.
        FT s = std::abs(dx) >= std::abs(dy) ? (p.x() - FT(sx[u])) / (FT(sx[v]) - FT(sx[u]))
                                            : (p.y() - FT(sy[u])) / (FT(sy[v]) - FT(sy[u]));
        // Screen parameter s -> parameter t along the 3D edge: interpolate with 1/w.
        const double sd = CGAL::to_double(s);
        const double t = (sd / w[v]) / ((1.0 - sd) / w[u] + sd / w[v]);
        const Vec3 pu = pos[u], pv = pos[v];
        const Vec3 q = {pu.x + t * (pv.x - pu.x), pu.y + t * (pv.y - pu.y),
                        pu.z + t * (pv.z - pu.z)};
        const uint32_t id = add_vertex(q, 1, u, v);
        list.push_back({p, s, id});
        return id;
    }

    // Clips stroke segment k to the closed triangle (a, b, c) (orientation sign `sigma`):
    // Cyrus-Beck in exact arithmetic. Returns false if they do not meet.
    bool clip(size_t k, const std::array<Point, 3> &tri, int sigma, Point &p0, Point &p1) const {
        const Point &p = stroke[k], &q = stroke[k + 1];
        const FT dx = q.x() - p.x(), dy = q.y() - p.y();
        FT t0 = 0, t1 = 1;
        for (int i = 0; i < 3; ++i) {
            const Point &a = tri[i], &b = tri[(i + 1) % 3];
            const FT ex = b.x() - a.x(), ey = b.y() - a.y();
            // f(t) = sigma * cross(b - a, p + t d - a) >= 0 inside
            FT n0 = ex * (p.y() - a.y()) - ey * (p.x() - a.x());
            FT n1 = ex * dy - ey * dx;
            if (sigma < 0) {
                n0 = -n0;
                n1 = -n1;
            }
            const CGAL::Sign s1 = CGAL::sign(n1);
            if (s1 == CGAL::ZERO) {
                if (CGAL::sign(n0) == CGAL::NEGATIVE) return false;
            } else {
                const FT t = -n0 / n1;
                if (s1 == CGAL::POSITIVE) {
                    if (t > t0) t0 = t;
                } else {
                    if (t < t1) t1 = t;
                }
            }
            if (t0 > t1) return false;
        }
        p0 = Point(p.x() + t0 * dx, p.y() + t0 * dy);
        p1 = Point(p.x() + t1 * dx, p.y() + t1 * dy);
        return true;
    }

    // Records the triangles of face f's triangulation (if it split f) with output vertex ids;
    // `flip` reverses them so that they keep the orientation of the input face.
    void record(uint32_t f, const Cdt &cdt, bool flip) {
        std::vector<std::array<uint32_t, 3>> tris;
        for (auto it = cdt.finite_faces_begin(); it != cdt.finite_faces_end(); ++it) {
            std::array<uint32_t, 3> t = {it->vertex(0)->info(), it->vertex(1)->info(),
                                         it->vertex(2)->info()};
            if (flip) std::swap(t[1], t[2]);
            tris.push_back(t);
        }
        if (tris.size() > 1) pieces[f] = std::move(tris);
    }

    // Face f in screen space: the stroke's pieces inside it as constraints.
    void cut_screen_face(uint32_t f) {
        const auto c = corners(f);
        const std::array<Point, 3> tri = {screen(c[0]), screen(c[1]), screen(c[2])};
        const double xmin = std::min({sx[c[0]], sx[c[1]], sx[c[2]]});
        const double xmax = std::max({sx[c[0]], sx[c[1]], sx[c[2]]});
        const double ymin = std::min({sy[c[0]], sy[c[1]], sy[c[2]]});
        const double ymax = std::max({sy[c[0]], sy[c[1]], sy[c[2]]});
        const CGAL::Orientation orient = CGAL::orientation(tri[0], tri[1], tri[2]);
        const int sigma = orient == CGAL::LEFT_TURN ? 1 : -1;

        std::vector<std::pair<Point, Point>> found;
        for (size_t k = 0; k + 1 < stroke.size(); ++k) {
            const auto &bx = seg_box[k];
            if (bx[1] < xmin || bx[0] > xmax || bx[3] < ymin || bx[2] > ymax) continue;
            Point p0, p1;
            if (clip(k, tri, sigma, p0, p1)) found.emplace_back(p0, p1);
        }
        if (found.empty()) return;
        ++crossed;

        Cdt cdt;
        for (int i = 0; i < 3; ++i) cdt.insert(tri[i])->info() = c[i];
        for (const auto &piece : found) {
            if (piece.first == piece.second) {
                cdt.insert(piece.first);
            } else {
                cdt.insert_constraint(piece.first, piece.second);
            }
        }
        // Classify every vertex: corner, on an edge (shared through edge_points), or inside.
        FT area = CGAL::area(tri[0], tri[1], tri[2]);
        for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
            const Point &p = v->point();
            uint32_t id = UNSET;
            for (int i = 0; i < 3 && id == UNSET; ++i) {
                if (p == tri[i]) id = c[i];
            }
            for (int i = 0; i < 3 && id == UNSET; ++i) {
                const int j = (i + 1) % 3;
                if (CGAL::collinear(tri[i], tri[j], p)) id = edge_vertex(c[i], c[j], p);
            }
            if (id == UNSET) {
                // Inside: perspective-correct barycentrics (screen barycentrics over w).
                double mu[3], sum = 0.0;
                for (int i = 0; i < 3; ++i) {
                    const FT li = CGAL::area(p, tri[(i + 1) % 3], tri[(i + 2) % 3]) / area;
                    mu[i] = CGAL::to_double(li) / w[c[i]];
                    sum += mu[i];
                }
                Vec3 q = {0, 0, 0};
                for (int i = 0; i < 3; ++i) {
                    const Vec3 pc = pos[c[i]];
                    q.x += mu[i] / sum * pc.x;
                    q.y += mu[i] / sum * pc.y;
                    q.z += mu[i] / sum * pc.z;
                }
                id = add_vertex(q, 0, f, f);
            }
            v->info() = id;
        }
        record(f, cdt, sigma < 0);
    }

    // Face f could not be cut in screen space (a corner behind the eye, or no area on screen) but
    // a neighbour put points on its edges: split it in its own parameter domain, the triangle
    // (0,0), (1,0), (0,1), with each edge point at its exact screen parameter along the edge.
    void split_fallback_face(uint32_t f) {
        const auto c = corners(f);
        bool any = false;
        for (int i = 0; i < 3; ++i) {
            auto it = edge_points.find(edge_key(c[i], c[(i + 1) % 3]));
            if (it != edge_points.end() && !it->second.empty()) any = true;
        }
        if (!any) return;
        ++fallback;
        const std::array<Point, 3> dom = {Point(0, 0), Point(1, 0), Point(0, 1)};
        Cdt cdt;
        for (int i = 0; i < 3; ++i) cdt.insert(dom[i])->info() = c[i];
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3;
            auto it = edge_points.find(edge_key(c[i], c[j]));
            if (it == edge_points.end()) continue;
            // s runs from the smaller vertex id to the larger.
            const Point &from = c[i] < c[j] ? dom[i] : dom[j];
            const Point &to = c[i] < c[j] ? dom[j] : dom[i];
            for (const EdgePoint &e : it->second) {
                Point p(from.x() + e.s * (to.x() - from.x()), from.y() + e.s * (to.y() - from.y()));
                cdt.insert(p)->info() = e.vertex;
            }
        }
        record(f, cdt, false);
    }

    void run(kr_result &r) {
        using Clock = std::chrono::steady_clock;
        const auto t0 = Clock::now();
        const uint32_t nf = mesh.num_faces;
        std::vector<bool> screen_face(nf, false);
        for (uint32_t f = 0; f < nf; ++f) {
            const auto c = corners(f);
            if (!projectable[c[0]] || !projectable[c[1]] || !projectable[c[2]]) {
                ++behind;
            } else if (CGAL::collinear(screen(c[0]), screen(c[1]), screen(c[2]))) {
                ++degenerate;
            } else {
                screen_face[f] = true;
                cut_screen_face(f);
            }
        }
        for (uint32_t f = 0; f < nf; ++f) {
            if (!screen_face[f]) split_fallback_face(f);
        }
        const auto t1 = Clock::now();

        // Output: faces in input order, each either kept or replaced by its pieces.
        auto &sizes = r.u32[{KR_U32_FACE_SIZES, 0}];
        auto &fverts = r.u32[{KR_U32_FACE_VERTICES, 0}];
        auto &origin = r.u32[{KR_U32_FACE_ORIGIN, 0}];
        auto &new_faces = r.u32[{KR_U32_CUT_NEW_FACES, 0}];
        auto &angles = r.f64[{KR_F64_CUT_MIN_ANGLES, 0}];
        uint64_t net_new = 0;
        for (uint32_t f = 0; f < nf; ++f) {
            auto it = pieces.find(f);
            if (it == pieces.end()) {
                const auto c = corners(f);
                fverts.insert(fverts.end(), c.begin(), c.end());
                sizes.push_back(3);
                origin.push_back(f);
                continue;
            }
            net_new += it->second.size() - 1;
            for (const auto &t : it->second) {
                new_faces.push_back(uint32_t(sizes.size()));
                angles.push_back(min_angle_deg(out_pos[t[0]], out_pos[t[1]], out_pos[t[2]]));
                fverts.insert(fverts.end(), t.begin(), t.end());
                sizes.push_back(3);
                origin.push_back(f);
            }
        }
        auto &p = r.f64[{KR_F64_POSITIONS, 0}];
        p.reserve(3 * out_pos.size());
        for (const Vec3 &v : out_pos) p.insert(p.end(), {v.x, v.y, v.z});
        r.u32[{KR_U32_CUT_VERTEX_SOURCE, 0}] = new_vertex_source;
        r.u32[{KR_U32_CUT_COUNTS, 0}] = {
            crossed, uint32_t(pieces.size()), uint32_t(net_new),
            uint32_t(out_pos.size() - mesh.num_vertices), behind, degenerate, fallback};
        r.f64[{KR_F64_TIMINGS, 0}] = {std::chrono::duration<double>(t1 - t0).count()};
    }
};

void check_finite(const double *v, size_t n, const char *what) {
    for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(v[i])) {
            throw kr::BadArgument(std::string(what) + " has a non-finite value at index " +
                                  std::to_string(i));
        }
    }
}

void stroke_cut(kr_result &r, const kr_mesh *mesh, const kr_view *view, const double *stroke_px,
                uint32_t num_points, uint32_t mode) {
    kr::check_mesh(mesh, 0);
    if (view == nullptr) throw kr::BadArgument("view is null");
    if (mode != KR_CUT_THROUGH_ALL) {
        throw kr::BadArgument("cut mode " + std::to_string(mode) +
                              " is not supported; the exact cut is through-all only "
                              "(KR_CUT_THROUGH_ALL)");
    }
    for (uint32_t f = 0; f < mesh->num_faces; ++f) {
        if (mesh->face_sizes[f] != 3) {
            throw kr::BadArgument("face " + std::to_string(f) + " has " +
                                  std::to_string(mesh->face_sizes[f]) +
                                  " corners; the exact cut takes triangles only");
        }
    }
    check_finite(view->view_proj, 16, "the view-projection matrix");
    check_finite(view->viewport, 4, "the viewport");
    if (!(view->viewport[2] > 0.0) || !(view->viewport[3] > 0.0)) {
        throw kr::BadArgument("the viewport's width and height must be positive");
    }
    if (num_points < 2) {
        throw kr::BadArgument("the stroke has " + std::to_string(num_points) +
                              " points; at least 2 are needed");
    }
    if (stroke_px == nullptr) throw kr::BadArgument("stroke points are null");
    check_finite(stroke_px, 2 * size_t(num_points), "the stroke");

    Cutter cut(*mesh);
    for (uint32_t i = 0; i < num_points; ++i) {
        Point p(stroke_px[2 * i], stroke_px[2 * i + 1]);
        if (cut.stroke.empty() || cut.stroke.back() != p) cut.stroke.push_back(p);
    }
    if (cut.stroke.size() < 2) {
        throw kr::BadArgument("the stroke has zero length (all its points coincide)");
    }
    for (size_t k = 0; k + 1 < cut.stroke.size(); ++k) {
        const Point &p = cut.stroke[k], &q = cut.stroke[k + 1];
        const double px = CGAL::to_double(p.x()), py = CGAL::to_double(p.y());
        const double qx = CGAL::to_double(q.x()), qy = CGAL::to_double(q.y());
        cut.seg_box.push_back({std::min(px, qx), std::max(px, qx), std::min(py, qy),
                               std::max(py, qy)});
    }

    // Projection: clip = VP * [x, y, z, 1] (column-major), screen with a top-left origin.
    const double *m = view->view_proj;
    const double *vp = view->viewport;
    const uint32_t nv = mesh->num_vertices;
    cut.pos.resize(nv);
    cut.sx.resize(nv);
    cut.sy.resize(nv);
    cut.w.resize(nv);
    cut.projectable.resize(nv);
    for (uint32_t v = 0; v < nv; ++v) {
        const double *p = mesh->positions + 3 * v;
        cut.pos[v] = {p[0], p[1], p[2]};
        double clip[4];
        for (int i = 0; i < 4; ++i) {
            clip[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
        }
        const double x = vp[0] + (clip[0] / clip[3] + 1.0) * 0.5 * vp[2];
        const double y = vp[1] + (1.0 - clip[1] / clip[3]) * 0.5 * vp[3];
        cut.w[v] = clip[3];
        cut.sx[v] = x;
        cut.sy[v] = y;
        cut.projectable[v] = clip[3] > 0.0 && std::isfinite(x) && std::isfinite(y);
    }
    cut.out_pos = cut.pos;
    cut.run(r);
}

}  // namespace

extern "C" uint32_t kr_cgal_stroke_cut(const kr_mesh *mesh, const kr_view *view,
                                       const double *stroke_px, uint32_t num_stroke_points,
                                       uint32_t mode, kr_result **out) {
    return kr::guarded(
        out, [&](kr_result &r) { stroke_cut(r, mesh, view, stroke_px, num_stroke_points, mode); });
}
