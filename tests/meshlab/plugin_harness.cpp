// Test harness for the katachi MeshLab plugin (MeshLab 2020.09 API).
//
// meshlabserver stops at a failing filter without saving anything, so it cannot show that
// a failed filter leaves the layer as it was. This program loads libfilter_katachi.so the
// way MeshLab does (QPluginLoader + qobject_cast), builds MeshDocuments in memory, applies
// the filters, and checks the layers, the error messages, the faux-edge conversion and,
// for the cut, the camera conversion against vcg's own Shot::Project.
//
//   plugin_harness PATH/TO/libfilter_katachi.so
//
// Prints one line per check and ends with "N passed, M failed"; exits 1 when a check fails.
// Run by `cargo xtask meshlab-plugin --test` (under xvfb-run, as QAction needs a GUI app).
//
// License: MIT OR Apache-2.0.

#include "cut_view.h"
#include "faux_polygons.h"

#include <common/interfaces.h>
#include <common/meshmodel.h>

#include <QApplication>
#include <QDomDocument>
#include <QPluginLoader>
#include <QWidget>

#include <wrap/qt/shot_qt.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

using katachi_meshlab::FauxTriangles;
using katachi_meshlab::Polygons;

static int passed = 0, failed = 0;

static void check(bool ok, const std::string &what) {
    std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
    (ok ? passed : failed)++;
}

/// Everything observable about a layer: vertices (positions and deleted flags) and faces
/// (vertex indices, faux flags, deleted flags), plus its label.
struct Snapshot {
    std::vector<uint32_t> positions; // bit patterns, so NaN equals itself
    std::vector<long> faces;
    std::vector<long> data; // flags, colours, qualities, texture coordinates (bit patterns)
    std::string label;
    int vn = 0, fn = 0;
    bool operator==(const Snapshot &o) const {
        return positions == o.positions && faces == o.faces && data == o.data &&
               label == o.label && vn == o.vn && fn == o.fn;
    }
};

static long bits(float x) {
    uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return long(b);
}

static Snapshot snapshot(MeshModel &m) {
    Snapshot s;
    for (auto &v : m.cm.vert) {
        for (int k = 0; k < 3; ++k) {
            uint32_t bits;
            std::memcpy(&bits, &v.P()[k], sizeof bits);
            s.positions.push_back(bits);
        }
        s.positions.push_back(v.IsD() ? 1 : 0);
        s.data.push_back(long(v.Flags()));
        if (m.hasDataMask(MeshModel::MM_VERTCOLOR))
            for (int k = 0; k < 4; ++k) s.data.push_back(v.C()[k]);
        if (m.hasDataMask(MeshModel::MM_VERTQUALITY)) s.data.push_back(bits(v.Q()));
        if (m.hasDataMask(MeshModel::MM_VERTTEXCOORD))
            s.data.insert(s.data.end(), {bits(v.T().U()), bits(v.T().V()), v.T().N()});
    }
    for (auto &f : m.cm.face) {
        for (int k = 0; k < 3; ++k) {
            s.faces.push_back(long(f.V(k) - m.cm.vert.data()));
            s.faces.push_back(f.IsF(k) ? 1 : 0);
        }
        s.faces.push_back(f.IsD() ? 1 : 0);
        s.data.push_back(long(f.Flags()));
        if (m.hasDataMask(MeshModel::MM_FACECOLOR))
            for (int k = 0; k < 4; ++k) s.data.push_back(f.C()[k]);
        if (m.hasDataMask(MeshModel::MM_FACEQUALITY)) s.data.push_back(bits(f.Q()));
        if (m.hasDataMask(MeshModel::MM_WEDGTEXCOORD))
            for (int k = 0; k < 3; ++k)
                s.data.insert(s.data.end(),
                              {bits(f.WT(k).U()), bits(f.WT(k).V()), f.WT(k).N()});
    }
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) s.data.push_back(bits(m.cm.Tr[r][c]));
    s.label = m.label().toStdString();
    s.vn = m.cm.vn;
    s.fn = m.cm.fn;
    return s;
}

/// Fills a layer with positions and triangles (faux mask per triangle).
static void fill(MeshModel &m, const std::vector<float> &p, const std::vector<int> &t,
                 const std::vector<int> &faux) {
    auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(m.cm, p.size() / 3);
    for (size_t i = 0; i < p.size() / 3; ++i, ++vi)
        vi->P() = Point3m(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(m.cm, t.size() / 3);
    for (size_t f = 0; f < t.size() / 3; ++f, ++fi)
        for (int k = 0; k < 3; ++k) {
            fi->V(k) = &m.cm.vert[t[3 * f + k]];
            if (faux[f] & (1 << k)) fi->SetF(k); else fi->ClearF(k);
        }
    m.UpdateBoxAndNormals();
}

/// The unit cube as 6 quads, each two triangles (a,b,c) (a,c,d) sharing a faux edge c-a.
static void fill_cube(MeshModel &m) {
    std::vector<float> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    std::vector<int> t, faux;
    for (auto &q : quads) {
        t.insert(t.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        faux.push_back(1 << 2); // edge 2 of (a,b,c): c -> a
        faux.push_back(1 << 0); // edge 0 of (a,c,d): a -> c
    }
    fill(m, p, t, faux);
}

/// A tetrahedron with one face (0, 0, 1) whose vertex repeats: katachi refuses the loop.
static void fill_repeated_vertex(MeshModel &m) {
    fill(m, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 0, 1},
         {0, 0, 0, 0});
}

/// A tetrahedron with a NaN coordinate.
static void fill_nan(MeshModel &m) {
    fill(m, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, std::nanf("")}, {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2},
         {0, 0, 0, 0});
}

static int count_faux(MeshModel &m) {
    int n = 0;
    for (auto &f : m.cm.face)
        if (!f.IsD())
            for (int k = 0; k < 3; ++k) n += f.IsF(k) ? 1 : 0;
    return n;
}

struct Harness {
    MeshFilterInterface *plugin = nullptr;
    QAction *action = nullptr;
    GLLogStream log;

    RichParameterList params(MeshDocument &md) {
        RichParameterList par;
        plugin->initParameterSet(action, md, par);
        return par;
    }
    bool apply(MeshDocument &md, RichParameterList &par) {
        plugin->setLog(&log);
        return plugin->applyFilter(action, md, par, nullptr);
    }
    std::string logText() {
        QStringList lines;
        log.print(lines);
        return lines.join("\n").toStdString();
    }
};

static bool contains(const std::string &hay, const std::string &needle) {
    return hay.find(needle) != std::string::npos;
}

/// A filter run that must fail, into a new layer and in place: `fill_layer` makes the input
/// layer, `set` sets the parameters (after new_layer). Checks that the filter fails with
/// katachi's message naming `message`, that the message is in the log, and that the layer
/// is unchanged with no layer added; `what` starts each check's name, `in_log` and
/// `unchanged` end the last two.
static void check_refused(Harness &h, const std::string &what,
                          const std::function<void(MeshModel &)> &fill_layer,
                          const std::function<void(RichParameterList &)> &set,
                          const char *message, const char *in_log, const char *unchanged) {
    for (bool new_layer : {false, true}) {
        MeshDocument md;
        MeshModel *m = md.addNewMesh("", "input");
        fill_layer(*m);
        const Snapshot before = snapshot(*m);
        RichParameterList par = h.params(md);
        par.setValue("new_layer", BoolValue(new_layer));
        set(par);
        h.log.Clear();
        const bool ok = h.apply(md, par);
        const std::string msg = h.plugin->errorMsg().toStdString();
        const std::string where = what + (new_layer ? ", new layer" : ", in place");
        check(!ok, where + ": filter fails");
        check(msg.rfind("katachi", 0) == 0 && contains(msg, message),
              where + ": errorMessage names the problem (" + msg + ")");
        check(contains(h.logText(), msg), where + in_log);
        check(md.size() == 1 && snapshot(*m) == before, where + unchanged);
    }
}

/// A label as pymeshlab spells a parameter name (MeshLab 2022+'s rule, written from its
/// documentation: lower case; spaces, slashes and dashes become underscores; brackets,
/// dots, commas, quotes, colons and plus signs go).
static std::string python_name(const QString &label) {
    std::string out;
    for (QChar qc : label.toLower()) {
        const char c = qc.toLatin1();
        if (c == ' ' || c == '/' || c == '-')
            out += '_';
        else if (!std::strchr("().,'\":+", c))
            out += c;
    }
    return out;
}

/// Every parameter's name is its label in pymeshlab's spelling, so pymeshlab users and
/// script writers see the words of the dialog.
static void check_names_are_labels(const RichParameterList &par, const std::string &what) {
    bool all = par.size() > 0;
    std::string bad;
    for (const RichParameter &p : par) {
        if (p.name().toStdString() != python_name(p.fieldDescription())) {
            all = false;
            bad += " " + p.name().toStdString() + " ('" + p.fieldDescription().toStdString() + "')";
        }
    }
    check(all, what + ": each parameter's name is its label as pymeshlab spells it" + bad);
}

static void test_faux_polygons() {
    // A quad as two triangles sharing the faux edge 2-0.
    FauxTriangles quad{{0, 1, 2, 0, 2, 3}, {1 << 2, 1 << 0}};
    Polygons p = katachi_meshlab::polygons_from_faux_triangles(quad);
    check(p.sizes == std::vector<uint32_t>{4} &&
              p.corners == std::vector<uint32_t>({0, 1, 2, 3}),
          "faux pair (0,1,2)(0,2,3) is the quad 0 1 2 3");
    // A pentagon and back.
    std::vector<uint32_t> sizes = {5, 3}, corners = {0, 1, 2, 3, 4, 4, 3, 5};
    std::vector<uint32_t> origin;
    FauxTriangles fan = katachi_meshlab::faux_triangles_from_polygons(sizes, corners, &origin);
    check(fan.faux.size() == 4 && origin == std::vector<uint32_t>({0, 0, 0, 1}),
          "pentagon + triangle fan into 3 + 1 triangles");
    check(fan.faux == std::vector<uint8_t>({1 << 2, (1 << 0) | (1 << 2), 1 << 0, 0}),
          "fan interior edges are faux, outline edges are not");
    Polygons back = katachi_meshlab::polygons_from_faux_triangles(fan);
    check(back.sizes == sizes && back.corners == corners, "fan round-trips to the polygons");
    // A square with a square hole as 4 trapezoids (o_k, o_n, i_n, i_k), each two triangles,
    // all joined by faux edges: the outline is two loops, so the triangles are kept.
    FauxTriangles ring;
    const uint32_t o[4] = {0, 1, 2, 3}, i[4] = {4, 5, 6, 7};
    for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        ring.corners.insert(ring.corners.end(), {o[k], o[n], i[n], o[k], i[n], i[k]});
        ring.faux.push_back((1 << 1) | (1 << 2)); // o_n-i_n (next trapezoid), i_n-o_k (diagonal)
        ring.faux.push_back((1 << 0) | (1 << 2)); // o_k-i_n (diagonal), i_k-o_k (previous)
    }
    Polygons rp = katachi_meshlab::polygons_from_faux_triangles(ring);
    check(rp.groups_kept_as_triangles == 1 && rp.sizes.size() == 8 &&
              rp.unmatched_faux_edges == 0,
          "a faux-joined ring (a polygon with a hole) keeps its 8 triangles");
    // The same ring cut at o1-i1 and o3-i3 is two hexagons.
    FauxTriangles halves = ring;
    halves.faux[0] &= ~(1 << 1); // o1-i1: trapezoid 0 | trapezoid 1
    halves.faux[3] &= ~(1 << 2);
    halves.faux[4] &= ~(1 << 1); // o3-i3: trapezoid 2 | trapezoid 3
    halves.faux[7] &= ~(1 << 2);
    Polygons hp = katachi_meshlab::polygons_from_faux_triangles(halves);
    check(hp.groups_kept_as_triangles == 0 && hp.sizes == std::vector<uint32_t>({6, 6}) &&
              hp.corners == std::vector<uint32_t>({0, 1, 5, 4, 7, 3, 1, 2, 3, 7, 6, 5}),
          "the ring cut in two is two hexagons, in the order of their first triangles");
    // A faux edge on the boundary is unmatched and counts as a real edge.
    FauxTriangles lone{{0, 1, 2}, {1}};
    Polygons lp = katachi_meshlab::polygons_from_faux_triangles(lone);
    check(lp.unmatched_faux_edges == 1 && lp.sizes == std::vector<uint32_t>{3},
          "an unmatched faux edge is reported and the triangle kept");
}

static void test_filter(Harness &h) {
    check(h.plugin->filterName(h.action) == "katachi: Solid-aware subdivision",
          "filter name");
    check(h.plugin->getClass(h.action) == MeshFilterInterface::Remeshing,
          "filter class is Remeshing (Filters > Remeshing, Simplification and Reconstruction)");
    {
        MeshDocument md;
        fill_cube(*md.addNewMesh("", "cube"));
        RichParameterList par = h.params(md);
        const char *names[] = {"levels",   "faces_with_holes", "recover_faces_with_holes",
                               "feature_angle_degrees", "boundary", "new_layer"};
        bool all = par.size() == 6;
        for (const char *n : names) all = all && par.hasParameter(n);
        check(all, "parameters: levels, faces_with_holes, recover_faces_with_holes, "
                   "feature_angle_degrees, boundary, new_layer");
        check_names_are_labels(par, "subdivision");
        check(par.getInt("levels") == 1 && par.getBool("new_layer") &&
                  !par.getBool("recover_faces_with_holes") &&
                  par.getFloat("feature_angle_degrees") == 0.f,
              "defaults: 1 level, new layer, no recovery, no feature angle");
    }
    // New layer: the cube stays, a new current layer holds 26 vertices and 24 quads.
    {
        MeshDocument md;
        MeshModel *cube = md.addNewMesh("", "cube");
        fill_cube(*cube);
        const Snapshot before = snapshot(*cube);
        RichParameterList par = h.params(md);
        const bool ok = h.apply(md, par);
        check(ok, "cube, new layer: filter succeeds");
        check(md.size() == 2 && md.mm() != cube, "cube, new layer: a second layer, made current");
        check(snapshot(*cube) == before, "cube, new layer: the input layer is unchanged");
        MeshModel *out = md.mm();
        check(out->cm.vn == 26 && out->cm.fn == 48 && count_faux(*out) == 48,
              "cube, new layer: 26 vertices, 24 quads as 48 triangles with 24 faux pairs");
        check(out->hasDataMask(MeshModel::MM_POLYGONAL), "cube, new layer: marked polygonal");
    }
    // In place, 2 levels: 98 vertices, 96 quads.
    {
        MeshDocument md;
        MeshModel *cube = md.addNewMesh("", "cube");
        fill_cube(*cube);
        RichParameterList par = h.params(md);
        par.setValue("new_layer", BoolValue(false));
        par.setValue("levels", IntValue(2));
        const bool ok = h.apply(md, par);
        check(ok && md.size() == 1 && cube->cm.vn == 98 && cube->cm.fn == 192 &&
                  count_faux(*cube) == 192,
              "cube, in place, 2 levels: 98 vertices, 96 quads (192 triangles)");
    }
    // Errors: the layer is untouched, no layer is added, the message is katachi's.
    struct Bad {
        const char *what;
        std::function<void(MeshModel &)> fill;
        std::function<void(RichParameterList &)> set;
        const char *message;
    };
    const Bad bad[] = {
        {"levels 9", fill_cube, [](RichParameterList &p) { p.setValue("levels", IntValue(9)); },
         "levels"},
        {"levels 0", fill_cube, [](RichParameterList &p) { p.setValue("levels", IntValue(0)); },
         "levels is 0"},
        {"feature angle 200", fill_cube,
         [](RichParameterList &p) { p.setValue("feature_angle_degrees", FloatValue(200.f)); }, "angle"},
        {"repeated vertex in a face", fill_repeated_vertex, [](RichParameterList &) {}, "face 3"},
        {"NaN coordinate", fill_nan, [](RichParameterList &) {}, "vertex 3"},
        {"empty layer", [](MeshModel &) {}, [](RichParameterList &) {}, "no faces"},
    };
    for (const Bad &b : bad)
        check_refused(h, b.what, b.fill, b.set, b.message,
                      ": the message is in the log (meshlabserver prints it)",
                      ": the layer is unchanged, no layer added");
}

// ---------------------------------------------------------------------------------------
// Cut by polyline

using katachi_meshlab::CutView;

/// Adds an n x n grid of unit squares at height z, from the origin, to the layer: each
/// square two triangles (a,b,c) (a,c,d) facing +z with the diagonal faux.
static void fill_grid(MeshModel &m, int n, float z = 0.f) {
    std::vector<float> p;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) p.insert(p.end(), {float(i), float(j), z});
    std::vector<int> t, faux;
    const int base = int(m.cm.vert.size());
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = base + j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            t.insert(t.end(), {a, b, c, a, c, d});
            faux.push_back(1 << 2);
            faux.push_back(1 << 0);
        }
    fill(m, p, t, faux);
}

/// Per-element data on a layer, all functions of the position or the face index, so that
/// where they went can be checked: face quality = face index, face colour from the index,
/// odd faces selected; vertex quality = x + 2y, vertex colour red = 20x + 10, green = 10y + 5;
/// wedge texture coordinates (x + 10 f, y), vertex texture coordinates (x, 2y).
static void add_data(MeshModel &m) {
    m.updateDataMask(MeshModel::MM_FACEQUALITY | MeshModel::MM_FACECOLOR |
                     MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR |
                     MeshModel::MM_WEDGTEXCOORD | MeshModel::MM_VERTTEXCOORD);
    int f = 0;
    for (auto &face : m.cm.face) {
        face.Q() = float(f);
        face.C() = vcg::Color4b((unsigned char)(f % 251), (unsigned char)(f / 251), 7, 255);
        if (f % 2) face.SetS(); else face.ClearS();
        for (int k = 0; k < 3; ++k) {
            face.WT(k).U() = face.V(k)->P()[0] + 10.f * float(f);
            face.WT(k).V() = face.V(k)->P()[1];
            face.WT(k).N() = 0;
        }
        ++f;
    }
    for (auto &v : m.cm.vert) {
        v.Q() = v.P()[0] + 2 * v.P()[1];
        v.C() = vcg::Color4b((unsigned char)(20 * v.P()[0] + 10),
                             (unsigned char)(10 * v.P()[1] + 5), 0, 255);
        v.T().U() = v.P()[0];
        v.T().V() = 2 * v.P()[1];
        v.T().N() = 0;
        v.ClearS();
    }
}

/// A shot looking straight down at the grid's centre (n/2, n/2) from height `h`.
static Shotm top_shot(int n, bool ortho, float h = 12.f, int w = 800, int hpx = 600) {
    Shotm s;
    const float c = 0.5f * float(n);
    if (ortho) {
        const float half_h = 0.6f * float(n), half_w = half_h * float(w) / float(hpx);
        s.Intrinsics.SetOrtho(-half_w, half_w, -half_h, half_h, vcg::Point2<int>(w, hpx));
    } else {
        s.Intrinsics.SetPerspective(50.f, float(w) / float(hpx), 20.f, vcg::Point2<int>(w, hpx));
    }
    s.LookAt(c, c, h, c, c, 0.f, 0.f, 1.f, 0.f);
    return s;
}

/// A general shot: perspective (off-centre frustum, non-square pixels) or orthographic,
/// looking at (1, 2, 0.5) from an oblique direction.
static Shotm oblique_shot(bool ortho) {
    Shotm s;
    if (ortho) {
        s.Intrinsics.SetOrtho(-3.f, 5.f, -2.f, 4.f, vcg::Point2<int>(640, 400));
    } else {
        s.Intrinsics.SetFrustum(-1.2f, 0.8f, -0.5f, 0.9f, 1.7f, vcg::Point2<int>(640, 400));
        s.Intrinsics.cameraType = vcg::Camera<float>::PERSPECTIVE;
    }
    s.LookAt(7.f, -4.f, 6.f, 1.f, 2.f, 0.5f, 0.1f, 0.2f, 1.f);
    return s;
}

/// katachi's pixel of layer point p (clip = VP p, top-left origin) and its clip w.
static vcg::Point2d katachi_pixel(const CutView &v, const vcg::Point3d &p, double *w = nullptr) {
    double c[4];
    for (int r = 0; r < 4; ++r)
        c[r] = v.view_proj[r] * p[0] + v.view_proj[4 + r] * p[1] + v.view_proj[8 + r] * p[2] +
               v.view_proj[12 + r];
    if (w) *w = c[3];
    return vcg::Point2d(v.viewport[0] + (c[0] / c[3] + 1) / 2 * v.viewport[2],
                        v.viewport[1] + (1 - c[1] / c[3]) / 2 * v.viewport[3]);
}

static vcg::Point3d world(const Matrix44m &tr, const Point3m &p) {
    return vcg::Matrix44d::Construct(tr) * vcg::Point3d::Construct(p);
}

/// A stroke through world points, in vcg pixels (origin bottom-left), as the filter's text;
/// `pixels` gets the points as the text holds them.
static std::string stroke_text(const Shotm &shot, const std::vector<vcg::Point3d> &pts,
                               std::vector<vcg::Point2d> *pixels = nullptr) {
    const vcg::Shotd s = vcg::Shotd::Construct(shot);
    std::string out;
    if (pixels) pixels->clear();
    for (const auto &p : pts) {
        const vcg::Point2d q = s.Project(p);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.4f %.4f", q[0], q[1]);
        out += (out.empty() ? "" : "; ") + std::string(buf);
        double x = 0, y = 0;
        std::sscanf(buf, "%lf %lf", &x, &y);
        if (pixels) pixels->push_back(vcg::Point2d(x, y));
    }
    return out;
}

static double distance_to_polyline(const vcg::Point2d &p, const std::vector<vcg::Point2d> &pl) {
    double best = HUGE_VAL;
    for (size_t i = 0; i + 1 < pl.size(); ++i) {
        const vcg::Point2d a = pl[i], d = pl[i + 1] - pl[i];
        double t = ((p - a) * d) / (d * d);
        t = std::max(0.0, std::min(1.0, t));
        best = std::min(best, (a + d * t - p).Norm());
    }
    return best;
}

static std::string xml_of(const Shotm &shot) {
    QDomDocument doc("ViewState");
    QDomElement root = doc.createElement("project");
    doc.appendChild(root);
    root.appendChild(WriteShotToQDomNode(shot, doc));
    return doc.toString().toStdString();
}

static bool same_shot(const Shotm &a, const Shotm &b) {
    bool same = a.Intrinsics.cameraType == b.Intrinsics.cameraType &&
                a.Intrinsics.FocalMm == b.Intrinsics.FocalMm &&
                a.Intrinsics.ViewportPx == b.Intrinsics.ViewportPx &&
                a.Intrinsics.PixelSizeMm == b.Intrinsics.PixelSizeMm &&
                a.Intrinsics.CenterPx == b.Intrinsics.CenterPx &&
                a.Intrinsics.k[0] == b.Intrinsics.k[0] && a.Intrinsics.k[1] == b.Intrinsics.k[1] &&
                a.Extrinsics.Tra() == b.Extrinsics.Tra();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            same = same && a.Extrinsics.Rot()[r][c] == b.Extrinsics.Rot()[r][c];
    return same;
}

/// The camera conversion against vcg's Shot::Project, the XML camera and the stroke text.
static void test_cut_view() {
    // Points in and around a box, through shots of every kind and a layer transform.
    Matrix44m moved;
    moved.SetRotateDeg(30, Point3m(1, 2, 3));
    moved.ElementAt(0, 3) = 0.5f;
    moved.ElementAt(1, 3) = -0.25f;
    moved.ElementAt(2, 3) = 0.75f;
    Matrix44m identity;
    identity.SetIdentity();
    const double lo[3] = {-1, -1, -1}, hi[3] = {3, 4, 2};
    struct Case {
        const char *name;
        Shotm shot;
        Matrix44m tr;
    };
    const Case cases[] = {
        {"perspective, off-centre frustum", oblique_shot(false), identity},
        {"orthographic", oblique_shot(true), identity},
        {"perspective, layer transform", oblique_shot(false), moved},
        {"orthographic, layer transform", oblique_shot(true), moved},
        {"perspective from above (SetPerspective)", top_shot(6, false), moved},
    };
    for (const Case &c : cases) {
        CutView view;
        QString error;
        const bool ok = katachi_meshlab::view_from_shot(
            vcg::Shotd::Construct(c.shot), vcg::Matrix44d::Construct(c.tr), lo, hi, view, error);
        check(ok, std::string("view_from_shot: ") + c.name + " converts" +
                      (ok ? "" : ": " + error.toStdString()));
        if (!ok) continue;
        const vcg::Shotd shot = vcg::Shotd::Construct(c.shot);
        const double height = view.viewport[3];
        double worst = 0.0;
        bool in_front = true, depth_ordered = true;
        for (int i = 0; i < 125; ++i) {
            const vcg::Point3d p(lo[0] + (hi[0] - lo[0]) * (i % 5) / 4.0,
                                 lo[1] + (hi[1] - lo[1]) * ((i / 5) % 5) / 4.0,
                                 lo[2] + (hi[2] - lo[2]) * (i / 25) / 4.0);
            const vcg::Point3d wp = world(c.tr, Point3m::Construct(p));
            const vcg::Point2d expected = shot.Project(wp);
            double w = 0;
            const vcg::Point2d got = katachi_pixel(view, p, &w);
            worst = std::max(worst, std::max(std::fabs(got[0] - expected[0]),
                                             std::fabs((height - got[1]) - expected[1])));
            in_front = in_front && (w > 0) == (shot.Depth(wp) > 0);
            // Depth: a point further along the same ray has a larger NDC z.
            const vcg::Point3d further = wp + (wp - shot.GetViewPoint()) * 0.25;
            double c1[4], c2[4];
            const vcg::Matrix44d inv = vcg::Inverse(vcg::Matrix44d::Construct(c.tr));
            const vcg::Point3d lp = inv * wp, lf = inv * further;
            for (int r = 0; r < 4; ++r) {
                c1[r] = view.view_proj[r] * lp[0] + view.view_proj[4 + r] * lp[1] +
                        view.view_proj[8 + r] * lp[2] + view.view_proj[12 + r];
                c2[r] = view.view_proj[r] * lf[0] + view.view_proj[4 + r] * lf[1] +
                        view.view_proj[8 + r] * lf[2] + view.view_proj[12 + r];
            }
            if (shot.Depth(wp) > 0) depth_ordered = depth_ordered && c2[2] / c2[3] > c1[2] / c1[3];
        }
        check(worst < 1e-6 * std::max(view.viewport[2], view.viewport[3]),
              std::string("view_from_shot: ") + c.name +
                  ": katachi's pixels are vcg's Shot::Project (y flipped), worst difference " +
                  std::to_string(worst) + " px over 125 points");
        check(in_front, std::string("view_from_shot: ") + c.name +
                            ": clip w > 0 exactly for points in front of the camera");
        check(depth_ordered, std::string("view_from_shot: ") + c.name +
                                 ": NDC depth grows away from the eye");
    }
    // Refused shots.
    {
        CutView view;
        QString error;
        Shotm none;
        bool ok = katachi_meshlab::view_from_shot(vcg::Shotd::Construct(none),
                                                  vcg::Matrix44d::Construct(identity), lo, hi,
                                                  view, error);
        check(!ok && error.contains("no viewport"),
              "an unset shot is refused: " + error.toStdString());
        Shotm distorted = oblique_shot(false);
        distorted.Intrinsics.k[0] = 0.1f;
        error.clear();
        ok = katachi_meshlab::view_from_shot(vcg::Shotd::Construct(distorted),
                                             vcg::Matrix44d::Construct(identity), lo, hi, view,
                                             error);
        check(!ok && error.contains("lens distortion"),
              "a shot with lens distortion is refused: " + error.toStdString());
    }
    // Camera XML: MeshLab's own writer, read back; and bad texts.
    for (bool ortho : {false, true}) {
        const Shotm shot = oblique_shot(ortho);
        Shotm read, vcg_read;
        QString error;
        const std::string text = xml_of(shot);
        const bool ok =
            katachi_meshlab::parse_camera_xml(QString::fromStdString(text), read, error);
        QDomDocument doc;
        doc.setContent(QString::fromStdString(text));
        ReadShotFromQDomNode(vcg_read, doc.documentElement().firstChildElement("VCGCamera"));
        check(ok && same_shot(read, vcg_read),
              std::string("camera XML (") + (ortho ? "orthographic" : "perspective") +
                  "): read as vcg's ReadShotFromQDomNode reads it");
    }
    const std::pair<const char *, const char *> bad_xml[] = {
        {"<project>", "does not parse"},
        {"<project/>", "no <VCGCamera>"},
        {"<VCGCamera TranslationVector=\"0 0 0 1\" RotationMatrix=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\" "
         "ViewportPx=\"640 400\" CenterPx=\"320 200\" FocalMm=\"20\"/>",
         "no PixelSizeMm"},
        {"<VCGCamera TranslationVector=\"0 0\" RotationMatrix=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\" "
         "ViewportPx=\"640 400\" CenterPx=\"320 200\" FocalMm=\"20\" PixelSizeMm=\"0.1 0.1\"/>",
         "TranslationVector has 2"},
        {"<VCGCamera TranslationVector=\"0 0 x\" RotationMatrix=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\" "
         "ViewportPx=\"640 400\" CenterPx=\"320 200\" FocalMm=\"20\" PixelSizeMm=\"0.1 0.1\"/>",
         "'x'"},
        {"<VCGCamera BinaryData=\"1\"/>", "binary"},
    };
    for (const auto &b : bad_xml) {
        Shotm shot;
        QString error;
        const bool ok = katachi_meshlab::parse_camera_xml(b.first, shot, error);
        check(!ok && error.contains(b.second),
              std::string("camera XML refused (") + b.second + "): " + error.toStdString());
    }
    // Stroke text.
    {
        std::vector<double> xy;
        QString error;
        bool ok = katachi_meshlab::parse_stroke("1 2, 3.5 -4;5e1\n6", xy, error);
        check(ok && xy == std::vector<double>({1, 2, 3.5, -4, 50, 6}),
              "stroke text: spaces, commas, semicolons and line breaks separate numbers");
        katachi_meshlab::stroke_to_katachi(xy, 100);
        check(xy == std::vector<double>({1, 98, 3.5, 104, 50, 94}), "stroke: y -> height - y");
        ok = katachi_meshlab::parse_stroke("1 2 3", xy, error);
        check(!ok && error.contains("odd"), "stroke text with an odd count is refused");
        ok = katachi_meshlab::parse_stroke("1 2 3 a", xy, error);
        check(!ok && error.contains("'a'"), "stroke text with a word is refused, naming it");
        ok = katachi_meshlab::parse_stroke("1 nan 3 4", xy, error);
        check(ok && std::isnan(xy[1]), "'nan' reaches katachi, which names the point");
    }
}

/// A stand-in for MeshLab's 3D view: the same class name, slot and signal.
class GLArea : public QWidget
{
    Q_OBJECT
public:
    Shotm shot;
signals:
    void transmitShot(QString, Shotm);
public slots:
    void sendViewerShot(QString name) { emit transmitShot(name, shot); }
};

static int count_selected_vertices(MeshModel &m) {
    int n = 0;
    for (auto &v : m.cm.vert) n += (!v.IsD() && v.IsS()) ? 1 : 0;
    return n;
}

static int count_border_edges(MeshModel &m) {
    std::map<std::pair<const void *, const void *>, int> uses;
    for (auto &f : m.cm.face)
        for (int k = 0; k < 3; ++k) {
            const void *a = f.V(k), *b = f.V((k + 1) % 3);
            uses[{std::min(a, b), std::max(a, b)}]++;
        }
    int n = 0;
    for (auto &u : uses) n += u.second == 1 ? 1 : 0;
    return n;
}

/// Checks the cut result `out` of a layer like `in` (add_data's per-element data):
/// face data follows the face each triangle lies in, interpolated data stays linear.
static void check_carried_data(const std::string &what, MeshModel &in, MeshModel &out) {
    // Face origins: the triangles of quality q tile input face q (its corners at their output
    // positions: input vertex v is output vertex v).
    const size_t nv_in = in.cm.vert.size();
    std::vector<double> area(in.cm.face.size(), 0.0);
    bool colours = true, selection = true, wedges = true;
    double worst_wedge = 0.0;
    double max_move = 0.0;
    for (size_t v = 0; v < nv_in; ++v)
        max_move = std::max(max_move, double((out.cm.vert[v].P() - in.cm.vert[v].P()).Norm()));
    for (auto &f : out.cm.face) {
        const int o = int(f.Q());
        if (o < 0 || size_t(o) >= area.size() || float(o) != f.Q()) {
            colours = false;
            continue;
        }
        area[size_t(o)] += double(vcg::DoubleArea(f)) / 2;
        const CFaceO &src = in.cm.face[size_t(o)];
        colours = colours && f.C() == src.cC();
        selection = selection && f.IsS() == src.IsS();
        // Wedge u = x + 10 o: within the input face, off by at most the largest snap move.
        for (int k = 0; k < 3; ++k) {
            const size_t vi = size_t(f.V(k) - out.cm.vert.data());
            const double x = vi < nv_in ? double(in.cm.vert[vi].P()[0]) : double(f.P(k)[0]);
            const double y = vi < nv_in ? double(in.cm.vert[vi].P()[1]) : double(f.P(k)[1]);
            const double du = std::fabs(double(f.WT(k).U()) - (x + 10.0 * o));
            const double dv = std::fabs(double(f.WT(k).V()) - y);
            worst_wedge = std::max(worst_wedge, std::max(du, dv));
        }
    }
    wedges = worst_wedge <= 2 * max_move + 1e-4;
    double worst_area = 0.0;
    for (size_t o = 0; o < area.size(); ++o) {
        const CFaceO &src = in.cm.face[o];
        Point3m p[3];
        for (int k = 0; k < 3; ++k) p[k] = out.cm.vert[size_t(src.cV(k) - in.cm.vert.data())].P();
        const double expected = double(((p[1] - p[0]) ^ (p[2] - p[0])).Norm()) / 2;
        worst_area = std::max(worst_area, std::fabs(area[o] - expected));
    }
    check(worst_area < 1e-5 && colours,
          what + ": the triangles with face quality q tile input face q (worst area error " +
              std::to_string(worst_area) + "), with its colour");
    check(selection, what + ": face selection follows the face each triangle lies in");
    check(wedges, what + ": wedge texture coordinates interpolated in their own face (worst " +
                      std::to_string(worst_wedge) + ", largest snap " +
                      std::to_string(max_move) + ")");
    // Vertex data: layer vertices keep theirs; new ones are linear in position (to the
    // largest snap move).
    bool kept = true;
    double worst_q = 0.0, worst_c = 0.0, worst_t = 0.0;
    for (size_t v = 0; v < out.cm.vert.size(); ++v) {
        const CVertexO &o = out.cm.vert[v];
        if (v < nv_in) {
            const CVertexO &i = in.cm.vert[v];
            kept = kept && o.cQ() == i.cQ() && o.cC() == i.cC() && o.cT().U() == i.cT().U() &&
                   o.cT().V() == i.cT().V();
            continue;
        }
        const double x = o.cP()[0], y = o.cP()[1];
        worst_q = std::max(worst_q, std::fabs(double(o.cQ()) - (x + 2 * y)));
        worst_c = std::max(worst_c, std::max(std::fabs(o.cC()[0] - (20 * x + 10)),
                                             std::fabs(o.cC()[1] - (10 * y + 5))));
        worst_t = std::max(worst_t, std::max(std::fabs(o.cT().U() - x),
                                             std::fabs(o.cT().V() - 2 * y)));
    }
    check(kept, what + ": layer vertices keep their quality, colour and texture coordinates");
    check(worst_q <= 3 * max_move + 1e-4 && worst_c <= 20 * 1.5 * max_move + 1.0 &&
              worst_t <= 2 * 1.5 * max_move + 1e-4,
          what + ": new vertices' quality, colour and texture coordinates are interpolated "
                 "(worst " + std::to_string(worst_q) + ", " + std::to_string(worst_c) + ", " +
              std::to_string(worst_t) + ")");
}

static void test_cut(Harness &h) {
    check(h.plugin->filterName(h.action) == "katachi: Cut by polyline", "cut: filter name");
    check(h.plugin->getClass(h.action) == MeshFilterInterface::Remeshing, "cut: class Remeshing");
    {
        MeshDocument md;
        fill_grid(*md.addNewMesh("", "grid"), 4);
        RichParameterList par = h.params(md);
        const char *names[] = {"view",         "view_as_text", "stroke",
                               "faces_to_cut", "open_the_cut", "new_layer"};
        bool all = par.size() == 6;
        for (const char *n : names) all = all && par.hasParameter(n);
        check(all, "cut: parameters view, view_as_text, stroke, faces_to_cut, open_the_cut, "
                   "new_layer");
        check_names_are_labels(par, "cut");
        check(par.at(0).name() == "view",
              "cut: the shot is the first parameter (so meshlabserver scripts may omit it)");
        check(!par.getShotf("view").IsValid() && par.getString("stroke").isEmpty() &&
                  par.getEnum("faces_to_cut") == 0 && !par.getBool("open_the_cut") &&
                  par.getBool("new_layer"),
              "cut: defaults without a 3D view: no shot, no stroke, visible only, not opened, "
              "new layer");
        // With a (stand-in) 3D view open, the shot defaults to its view.
        GLArea area;
        area.shot = top_shot(4, false);
        RichParameterList with_view = h.params(md);
        check(same_shot(with_view.getShotf("view"), area.shot),
              "cut: with a 3D view, the shot defaults to the current view (asked through "
              "sendViewerShot/transmitShot)");
    }

    // A 6 x 6 grid seen from above; a wavy stroke across it from outside to outside.
    const int n = 6;
    // It turns by less than the 60 degrees at which katachi splits a stroke, so it is one
    // piece whose ends lie off the mesh: every vertex of the cut lies on it.
    const std::vector<vcg::Point3d> wave = {{-0.7, 1.3, 0}, {1.45, 2.2, 0}, {3.1, 1.9, 0},
                                            {4.7, 3.0, 0},  {6.8, 2.9, 0}};
    struct Good {
        std::string what;
        bool ortho, open, through_all, in_place, two_sheets, use_xml;
        Matrix44m tr;
    };
    Matrix44m identity, shifted;
    identity.SetIdentity();
    shifted.SetIdentity();
    shifted.ElementAt(0, 3) = 1.5f; // the layer is drawn 1.5 to the right
    const Good good[] = {
        {"perspective, new layer", false, false, false, false, false, false, identity},
        {"orthographic, in place", true, false, false, true, false, false, identity},
        {"perspective, opened", false, true, false, false, false, false, identity},
        {"orthographic, layer transform", true, false, false, false, false, false, shifted},
        {"perspective, view as text", false, false, false, false, false, true, identity},
        {"two sheets, visible only", false, false, false, false, true, false, identity},
        {"two sheets, through all", false, false, true, false, true, false, identity},
    };
    size_t faces_by_shot = 0, faces_by_xml = 0;
    for (const Good &g : good) {
        const std::string what = "cut " + g.what;
        MeshDocument md;
        MeshModel *m = md.addNewMesh("", "grid");
        fill_grid(*m, n);
        if (g.two_sheets) fill_grid(*m, n, -1.f);
        add_data(*m);
        m->cm.Tr = g.tr;
        MeshDocument copy; // an untouched copy of the input
        MeshModel &reference = *copy.addNewMesh("", "reference");
        reference.updateDataMask(m);
        vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(reference.cm, m->cm, false, true);
        const Snapshot before = snapshot(*m);
        const Shotm shot = top_shot(n, g.ortho, 12.f);
        std::vector<vcg::Point3d> stroke_world = wave;
        for (auto &p : stroke_world) p = world(g.tr, Point3m::Construct(p));
        std::vector<vcg::Point2d> pixels;
        const std::string stroke = stroke_text(shot, stroke_world, &pixels);
        RichParameterList par = h.params(md);
        if (g.use_xml)
            par.setValue("view_as_text", StringValue(QString::fromStdString(xml_of(shot))));
        else
            par.setValue("view", ShotfValue(shot));
        par.setValue("stroke", StringValue(QString::fromStdString(stroke)));
        par.setValue("faces_to_cut", EnumValue(g.through_all ? 1 : 0));
        par.setValue("open_the_cut", BoolValue(g.open));
        par.setValue("new_layer", BoolValue(!g.in_place));
        h.log.Clear();
        const bool ok = h.apply(md, par);
        check(ok, what + ": the filter succeeds" +
                      (ok ? "" : " (" + h.plugin->errorMsg().toStdString() + ")"));
        if (!ok) continue;
        MeshModel *out = md.mm();
        check(g.in_place ? (md.size() == 1 && out == m) : (md.size() == 2 && out != m),
              what + (g.in_place ? ": the layer itself holds the result"
                                 : ": a new current layer, the input unchanged"));
        if (!g.in_place) check(snapshot(*m) == before, what + ": the input layer is unchanged");
        const size_t faces_in = reference.cm.face.size();
        check(size_t(out->cm.fn) > faces_in,
              what + ": the face count grows (" + std::to_string(faces_in) + " -> " +
                  std::to_string(out->cm.fn) + ")");
        if (g.use_xml) faces_by_xml = size_t(out->cm.fn);
        if (g.what == "perspective, new layer") faces_by_shot = size_t(out->cm.fn);
        // The cut: selected vertices, every one on the stroke as vcg projects it.
        const vcg::Shotd shotd = vcg::Shotd::Construct(shot);
        double worst = 0.0;
        int on_top = 0, below = 0;
        for (auto &v : out->cm.vert) {
            if (!v.IsS()) continue;
            const vcg::Point2d at = shotd.Project(world(out->cm.Tr, v.P()));
            worst = std::max(worst, distance_to_polyline(at, pixels));
            (v.P()[2] > -0.5f ? on_top : below)++;
        }
        const int selected = count_selected_vertices(*out);
        check(selected >= n && worst < 1e-2,
              what + ": " + std::to_string(selected) +
                  " vertices selected along the cut, all on the stroke (worst " +
                  std::to_string(worst) + " px)");
        if (g.two_sheets)
            check(g.through_all ? (on_top > 0 && below > 0) : (on_top > 0 && below == 0),
                  what + (g.through_all ? ": both sheets are cut" : ": only the top sheet is cut") +
                      " (" + std::to_string(on_top) + " / " + std::to_string(below) + ")");
        const int borders_before = count_border_edges(reference);
        const int borders_after = count_border_edges(*out);
        if (g.open)
            check(borders_after > borders_before && selected > 0 &&
                      out->cm.vn > reference.cm.vn + selected / 2,
                  what + ": the cut is open: border edges " + std::to_string(borders_before) +
                      " -> " + std::to_string(borders_after));
        else
            check(borders_after >= borders_before &&
                      borders_after - borders_before <= 2 * (g.two_sheets ? 2 : 1),
                  what + ": not opened: the border gains only the edges split where the cut "
                         "leaves the mesh (" + std::to_string(borders_before) + " -> " +
                      std::to_string(borders_after) + ")");
        // Faux edges: only the input's (the quads' diagonals, by vertex index), where the cut
        // leaves them whole, each marked by both its triangles.
        auto index = [](const MeshModel &mm, const CVertexO *v) {
            return long(v - mm.cm.vert.data());
        };
        std::set<std::pair<long, long>> diagonals;
        for (auto &f : reference.cm.face)
            for (int k = 0; k < 3; ++k)
                if (f.IsF(k)) {
                    const long a = index(reference, f.cV(k));
                    const long b = index(reference, f.cV((k + 1) % 3));
                    diagonals.emplace(std::min(a, b), std::max(a, b));
                }
        // An opened cut's copies (new vertices where a layer vertex is) count as that vertex.
        std::map<std::tuple<float, float, float>, long> layer_vertex_at;
        for (size_t v = 0; v < reference.cm.vert.size(); ++v) {
            const Point3m &p = out->cm.vert[v].cP();
            layer_vertex_at.emplace(std::make_tuple(p[0], p[1], p[2]), long(v));
        }
        auto layer_index = [&](const CVertexO *v) {
            const long i = index(*out, v);
            if (size_t(i) < reference.cm.vert.size()) return i;
            const auto at =
                layer_vertex_at.find(std::make_tuple(v->cP()[0], v->cP()[1], v->cP()[2]));
            return at == layer_vertex_at.end() ? i : at->second;
        };
        std::map<std::pair<long, long>, int> faux_marks, edge_uses, faux_sides;
        for (auto &f : out->cm.face)
            for (int k = 0; k < 3; ++k) {
                const long a = index(*out, f.cV(k)), b = index(*out, f.cV((k + 1) % 3));
                const auto e = std::make_pair(std::min(a, b), std::max(a, b));
                edge_uses[e]++;
                if (!f.IsF(k)) continue;
                faux_marks[e]++;
                const long la = layer_index(f.cV(k)), lb = layer_index(f.cV((k + 1) % 3));
                faux_sides[std::make_pair(std::min(la, lb), std::max(la, lb))]++;
            }
        bool kept_faux = !faux_marks.empty();
        for (auto &e : faux_marks)
            kept_faux = kept_faux && e.second == 2 && edge_uses[e.first] == 2;
        for (auto &e : faux_sides) kept_faux = kept_faux && diagonals.count(e.first) == 1;
        check(kept_faux, what + ": " + std::to_string(faux_sides.size()) + " of the " +
                             std::to_string(diagonals.size()) +
                             " quad diagonals stay faux, each on both its triangles");
        const std::string log = h.logText();
        check(contains(log, "katachi: cut by polyline (") && contains(log, "new faces") &&
                  contains(log, "vertices moved onto the stroke, the largest by") &&
                  contains(log, "stroke points dropped:") && contains(log, "katachi: view:"),
              what + ": the log has katachi's report");
        check_carried_data(what, reference, *out);
    }
    check(faces_by_xml == faces_by_shot && faces_by_xml > 0,
          "cut: 'View as text' (MeshLab's XML) gives the same cut as the shot parameter");

    // A stroke beside the mesh: success, nothing changes, no layer.
    {
        MeshDocument md;
        MeshModel *m = md.addNewMesh("", "grid");
        fill_grid(*m, n);
        const Snapshot before = snapshot(*m);
        const Shotm shot = top_shot(n, true);
        RichParameterList par = h.params(md);
        par.setValue("view", ShotfValue(shot));
        par.setValue("stroke", StringValue(QString::fromStdString(
                                   stroke_text(shot, {{-2, -2, 0}, {-1, -3, 0}, {-0.5, -4, 0}}))));
        h.log.Clear();
        const bool ok = h.apply(md, par);
        check(ok && md.size() == 1 && snapshot(*m) == before &&
                  contains(h.logText(), "meets no face"),
              "cut: a stroke beside the mesh succeeds, changes nothing and says so");
    }

    // Errors: false, katachi's message (also in the log), the layer bit-identical, no layer.
    const Shotm shot = top_shot(n, false);
    const std::string wave_text = stroke_text(shot, wave);
    struct Bad {
        const char *what;
        std::string stroke;
        std::function<void(RichParameterList &)> set;
        std::function<void(MeshModel &)> fill;
        const char *message;
    };
    auto nothing = [](RichParameterList &) {};
    auto grid = [n](MeshModel &m) {
        fill_grid(m, n);
        add_data(m);
    };
    Shotm distorted = shot;
    distorted.Intrinsics.k[0] = 0.01f;
    const Bad bad[] = {
        {"one stroke point", "100 100", nothing, grid, "the stroke has 1 point"},
        {"empty stroke", "", nothing, grid, "the stroke has 0 point"},
        {"NaN in the stroke", "100 100; nan 200; 300 300", nothing, grid, "stroke point 1"},
        {"self-intersecting stroke", "100 100; 500 500; 500 100; 100 500", nothing, grid,
         "crosses itself"},
        {"odd number count", "100 100 200", nothing, grid, "odd count"},
        {"no view", wave_text,
         [](RichParameterList &p) { p.setValue("view", ShotfValue(Shotm())); }, grid,
         "no viewport"},
        {"bad view text", wave_text,
         [](RichParameterList &p) { p.setValue("view_as_text", StringValue("<VCGCamera/>")); }, grid,
         "TranslationVector"},
        {"lens distortion", wave_text,
         [distorted](RichParameterList &p) { p.setValue("view", ShotfValue(distorted)); }, grid,
         "lens distortion"},
        {"faces to cut 7", wave_text,
         [](RichParameterList &p) { p.setValue("faces_to_cut", EnumValue(7)); }, grid,
         "options->mode is 7"},
        {"NaN vertex", wave_text, nothing,
         [n](MeshModel &m) {
             fill_grid(m, n);
             m.cm.vert[3].P()[2] = std::nanf("");
         },
         "vertex 3"},
        {"non-manifold edge under the stroke", wave_text, nothing,
         [n](MeshModel &m) {
             fill_grid(m, n);
             add_data(m);
             // A fin on the edge (2, 2)-(3, 2), which the stroke crosses: three faces share it.
             auto v = vcg::tri::Allocator<CMeshO>::AddVertices(m.cm, 1);
             v->P() = Point3m(2.5f, 2.f, 1.f);
             auto f = vcg::tri::Allocator<CMeshO>::AddFaces(m.cm, 1);
             f->V(0) = &m.cm.vert[size_t(2 * (n + 1) + 2)];
             f->V(1) = &m.cm.vert[size_t(2 * (n + 1) + 3)];
             f->V(2) = &*v;
         },
         "is non-manifold"},
        {"empty layer", wave_text, nothing, [](MeshModel &) {}, "no faces"},
    };
    for (const Bad &b : bad)
        check_refused(
            h, std::string("cut, ") + b.what, b.fill,
            [&](RichParameterList &p) {
                p.setValue("view", ShotfValue(shot));
                p.setValue("stroke", StringValue(QString::fromStdString(b.stroke)));
                b.set(p);
            },
            b.message, ": the message is in the log",
            ": the layer is bit-identical, no layer added");
}

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: plugin_harness PATH/TO/libfilter_katachi.so\n");
        return 2;
    }
    QApplication app(argc, argv);
    test_faux_polygons();

    QPluginLoader loader(QString::fromLocal8Bit(argv[1]));
    QObject *instance = loader.instance();
    check(instance != nullptr,
          "the plugin loads" + (instance ? std::string() : ": " + loader.errorString().toStdString()));
    Harness h;
    if (instance) h.plugin = qobject_cast<MeshFilterInterface *>(instance);
    check(h.plugin != nullptr, "the plugin is a MeshFilterInterface");
    test_cut_view();
    if (h.plugin) {
        const auto actions = h.plugin->actions();
        check(actions.size() == 2, "the plugin has two filters");
        QAction *subdivide = nullptr, *cut = nullptr;
        for (QAction *a : actions) {
            if (h.plugin->filterName(a) == "katachi: Solid-aware subdivision") subdivide = a;
            if (h.plugin->filterName(a) == "katachi: Cut by polyline") cut = a;
        }
        check(subdivide != nullptr && cut != nullptr,
              "the filters are 'katachi: Solid-aware subdivision' and 'katachi: Cut by polyline'");
        if (subdivide) {
            h.action = subdivide;
            test_filter(h);
        }
        if (cut) {
            h.action = cut;
            test_cut(h);
        }
    }
    std::printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}

#include "plugin_harness.moc"
