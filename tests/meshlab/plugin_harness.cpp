// Test harness for the katachi MeshLab plugin (MeshLab 2020.09 API).
//
// meshlabserver stops at a failing filter without saving anything, so it cannot show that
// a failed filter leaves the layer as it was. This program loads libfilter_katachi.so the
// way MeshLab does (QPluginLoader + qobject_cast), builds MeshDocuments in memory, applies
// the filter, and checks the layers, the error messages, and the faux-edge conversion.
//
//   plugin_harness PATH/TO/libfilter_katachi.so
//
// Prints one line per check and ends with "N passed, M failed"; exits 1 when a check fails.
// Run by `cargo xtask meshlab-plugin --test` (under xvfb-run, as QAction needs a GUI app).
//
// License: MIT OR Apache-2.0.

#include "faux_polygons.h"

#include <common/interfaces.h>
#include <common/meshmodel.h>

#include <QApplication>
#include <QPluginLoader>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
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
    std::string label;
    int vn = 0, fn = 0;
    bool operator==(const Snapshot &o) const {
        return positions == o.positions && faces == o.faces && label == o.label && vn == o.vn &&
               fn == o.fn;
    }
};

static Snapshot snapshot(MeshModel &m) {
    Snapshot s;
    for (auto &v : m.cm.vert) {
        for (int k = 0; k < 3; ++k) {
            uint32_t bits;
            std::memcpy(&bits, &v.P()[k], sizeof bits);
            s.positions.push_back(bits);
        }
        s.positions.push_back(v.IsD() ? 1 : 0);
    }
    for (auto &f : m.cm.face) {
        for (int k = 0; k < 3; ++k) {
            s.faces.push_back(long(f.V(k) - m.cm.vert.data()));
            s.faces.push_back(f.IsF(k) ? 1 : 0);
        }
        s.faces.push_back(f.IsD() ? 1 : 0);
    }
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
        const char *names[] = {"levels", "holeMethod", "recoverFacesWithHoles", "featureAngle",
                               "boundary", "newLayer"};
        bool all = par.size() == 6;
        for (const char *n : names) all = all && par.hasParameter(n);
        check(all, "parameters: levels, holeMethod, recoverFacesWithHoles, featureAngle, "
                   "boundary, newLayer");
        check(par.getInt("levels") == 1 && par.getBool("newLayer") &&
                  !par.getBool("recoverFacesWithHoles") && par.getFloat("featureAngle") == 0.f,
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
        par.setValue("newLayer", BoolValue(false));
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
         [](RichParameterList &p) { p.setValue("featureAngle", FloatValue(200.f)); }, "angle"},
        {"repeated vertex in a face", fill_repeated_vertex, [](RichParameterList &) {}, "face 3"},
        {"NaN coordinate", fill_nan, [](RichParameterList &) {}, "vertex 3"},
        {"empty layer", [](MeshModel &) {}, [](RichParameterList &) {}, "no faces"},
    };
    for (const Bad &b : bad) {
        for (bool new_layer : {false, true}) {
            MeshDocument md;
            MeshModel *m = md.addNewMesh("", "input");
            b.fill(*m);
            const Snapshot before = snapshot(*m);
            RichParameterList par = h.params(md);
            par.setValue("newLayer", BoolValue(new_layer));
            b.set(par);
            h.log.Clear();
            const bool ok = h.apply(md, par);
            const std::string msg = h.plugin->errorMsg().toStdString();
            const std::string where = std::string(b.what) + (new_layer ? ", new layer" : ", in place");
            check(!ok, where + ": filter fails");
            check(msg.rfind("katachi", 0) == 0 && contains(msg, b.message),
                  where + ": errorMessage names the problem (" + msg + ")");
            check(contains(h.logText(), msg), where + ": the message is in the log (meshlabserver prints it)");
            check(md.size() == 1 && snapshot(*m) == before, where + ": the layer is unchanged, no layer added");
        }
    }
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
    if (h.plugin) {
        const auto actions = h.plugin->actions();
        check(actions.size() == 1, "the plugin has one filter");
        if (!actions.empty()) {
            h.action = actions.front();
            test_filter(h);
        }
    }
    std::printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
