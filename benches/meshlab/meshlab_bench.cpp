// katachi's MeshLab 2020.09 filters against MeshLab's own, timed as MeshLab times a filter
// (its log's "Applied filter ... in N msec" is the time of applyFilter), side by side in one
// process, in interleaved rounds. `cargo xtask meshlab-bench` builds and runs this:
//
//   meshlab_bench PATH/TO/libfilter_katachi.so MESHLAB_PLUGIN_DIR [ROUNDS]
//
// The plugins are loaded as MeshLab loads them (QPluginLoader + qobject_cast): ours, and from
// MeshLab's plugin directory filter_meshing ("Subdivision Surfaces: Catmull-Clark") and
// filter_layer ("Duplicate Current layer").
//
// - subdivide L1 / L2: a torus of 384 x 256 quads (two faux-joined triangles each, MeshLab's
//   polygonal form); katachi's "Solid-aware subdivision" in place at 1 and 2 levels against
//   MeshLab's Catmull-Clark applied once and twice (its levels), each on a fresh copy;
// - cut 330k / 1.3M: an icosphere of 327,680 and 1,310,720 triangles seen by a perspective
//   camera, a 50-point stroke across the visible side; katachi's "Cut by polyline" into a new
//   layer against "Duplicate Current layer" (a copy into a new layer: the least a filter
//   that makes a new layer does).
//
// Prints `BENCH\tMeshLab 2020.09\tCASE\tVARIANT\tROUND\tSECONDS\tnotes` per run and
// `BENCH-DONE` at the end (the lines bench_table.rs reads). License: MIT OR Apache-2.0.

#include <common/interfaces.h>
#include <common/meshmodel.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QPluginLoader>

#include <vcg/complex/append.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

struct Filter {
    MeshFilterInterface *plugin = nullptr;
    QAction *action = nullptr;
    std::unique_ptr<GLLogStream> log = std::make_unique<GLLogStream>();

    RichParameterList params(MeshDocument &md) {
        RichParameterList par;
        plugin->initParameterSet(action, md, par);
        return par;
    }
    /// Applies the filter to md's current layer; returns MeshLab's time for it (seconds).
    double apply(MeshDocument &md, RichParameterList &par) {
        plugin->setLog(log.get());
        QElapsedTimer t;
        t.start();
        const bool ok = plugin->applyFilter(action, md, par, nullptr);
        const double s = double(t.nsecsElapsed()) * 1e-9;
        if (!ok) {
            std::fprintf(stderr, "filter %s failed: %s\n",
                         qUtf8Printable(plugin->filterName(action)),
                         qUtf8Printable(plugin->errorMsg()));
            std::exit(1);
        }
        log->Clear();
        return s;
    }
};

Filter find(const QString &library, const QString &name, std::vector<QPluginLoader *> &keep) {
    auto *loader = new QPluginLoader(library);
    keep.push_back(loader);
    QObject *instance = loader->instance();
    if (!instance) {
        std::fprintf(stderr, "cannot load %s: %s\n", qUtf8Printable(library),
                     qUtf8Printable(loader->errorString()));
        std::exit(1);
    }
    Filter f;
    f.plugin = qobject_cast<MeshFilterInterface *>(instance);
    if (!f.plugin) {
        std::fprintf(stderr, "%s is not a filter plugin\n", qUtf8Printable(library));
        std::exit(1);
    }
    for (QAction *a : f.plugin->actions())
        if (f.plugin->filterName(a) == name) f.action = a;
    if (!f.action) {
        std::fprintf(stderr, "%s has no filter '%s'\n", qUtf8Printable(library),
                     qUtf8Printable(name));
        std::exit(1);
    }
    return f;
}

/// A torus of m x n quads, each two triangles sharing a faux edge (MeshLab's quads).
void fill_torus(CMeshO &cm, int m, int n) {
    auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(cm, size_t(m) * n);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j, ++vi) {
            const double a = 2 * M_PI * i / m, b = 2 * M_PI * j / n, w = 1.0 + 0.3 * std::cos(b);
            vi->P() = Point3m(Scalarm(w * std::cos(a)), Scalarm(w * std::sin(a)),
                              Scalarm(0.3 * std::sin(b)));
        }
    auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(cm, 2 * size_t(m) * n);
    auto id = [&](int i, int j) { return &cm.vert[size_t((i % m) * n + (j % n))]; };
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j) {
            CVertexO *q[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
            fi->V(0) = q[0], fi->V(1) = q[1], fi->V(2) = q[2];
            fi->ClearF(0), fi->ClearF(1), fi->SetF(2); // q2-q0 is the diagonal
            ++fi;
            fi->V(0) = q[0], fi->V(1) = q[2], fi->V(2) = q[3];
            fi->SetF(0), fi->ClearF(1), fi->ClearF(2);
            ++fi;
        }
}

/// An icosphere of radius 1: the icosahedron with each triangle split into 4, `levels` times
/// (20 x 4^levels triangles).
void fill_icosphere(CMeshO &cm, int levels) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<vcg::Point3d> p = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0},
                                   {0, -1, t}, {0, 1, t},  {0, -1, -t}, {0, 1, -t},
                                   {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (auto &q : p) q.Normalize();
    std::vector<int> tri = {0, 11, 5, 0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                            4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4,  3, 4,  2, 3, 2, 6, 3,
                            6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6, 2,  10, 8,  6, 7, 9, 8, 1};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto middle = [&](int a, int b) {
            auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            vcg::Point3d m = (p[size_t(a)] + p[size_t(b)]) * 0.5;
            m.Normalize();
            p.push_back(m);
            return mid[key] = int(p.size()) - 1;
        };
        std::vector<int> next;
        next.reserve(tri.size() * 4);
        for (size_t f = 0; f < tri.size(); f += 3) {
            const int a = tri[f], b = tri[f + 1], c = tri[f + 2];
            const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        tri.swap(next);
    }
    auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(cm, p.size());
    for (size_t i = 0; i < p.size(); ++i, ++vi) vi->P() = Point3m::Construct(p[i]);
    auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(cm, tri.size() / 3);
    for (size_t f = 0; f < tri.size(); f += 3, ++fi)
        for (int k = 0; k < 3; ++k) fi->V(k) = &cm.vert[size_t(tri[f + size_t(k)])];
}

/// A fresh document whose one layer is a copy of `base` (with its faux flags).
void copy_into(MeshDocument &md, MeshModel &base) {
    MeshModel *m = md.addNewMesh("", "input");
    m->updateDataMask(&base);
    vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(m->cm, base.cm, false, true);
    m->UpdateBoxAndNormals();
}

void report(const char *case_name, const char *variant, int round, double seconds,
          const std::string &notes) {
    std::printf("BENCH\t2020.09\t%s\t%s\t%d\t%.6f\t%s\n", case_name, variant, round, seconds,
                notes.c_str());
    std::fflush(stdout);
}

/// Runs each variant once per round on a fresh copy of `base`, in an order that rotates.
void rounds(const char *case_name, MeshModel &base, int n,
            const std::vector<std::pair<const char *, std::function<double(MeshDocument &)>>> &v) {
    for (int r = 0; r < n; ++r)
        for (size_t k = 0; k < v.size(); ++k) {
            const auto &[name, run] = v[(k + size_t(r)) % v.size()];
            MeshDocument md;
            copy_into(md, base);
            const double s = run(md);
            report(case_name, name, r, s,
                   "input_faces=" + std::to_string(base.cm.fn) +
                       " output_faces=" + std::to_string(md.mm()->cm.fn));
        }
}

} // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: meshlab_bench PATH/TO/libfilter_katachi.so MESHLAB_PLUGIN_DIR "
                     "[ROUNDS]\n");
        return 2;
    }
    QApplication app(argc, argv);
    const int n_rounds = argc > 3 ? std::atoi(argv[3]) : 5;
    const QString dir = QString::fromLocal8Bit(argv[2]);
    std::vector<QPluginLoader *> loaders;
    Filter katachi = find(QString::fromLocal8Bit(argv[1]), "katachi: Solid-aware subdivision",
                          loaders);
    Filter cut = find(QString::fromLocal8Bit(argv[1]), "katachi: Cut by polyline", loaders);
    Filter catmull =
        find(dir + "/libfilter_meshing.so", "Subdivision Surfaces: Catmull-Clark", loaders);
    Filter duplicate = find(dir + "/libfilter_layer.so", "Duplicate Current layer", loaders);
    std::printf("katachi meshlab bench: MeshLab 2020.09 plugins, %d rounds\n", n_rounds);

    {
        MeshDocument holder;
        MeshModel *torus = holder.addNewMesh("", "torus");
        fill_torus(torus->cm, 384, 256);
        torus->updateDataMask(MeshModel::MM_POLYGONAL);
        for (int levels : {1, 2}) {
            const std::string name = "subdivide L" + std::to_string(levels);
            rounds(name.c_str(), *torus, n_rounds,
                   {{"katachi",
                     [&](MeshDocument &md) {
                         RichParameterList par = katachi.params(md);
                         par.setValue("levels", IntValue(levels));
                         par.setValue("new_layer", BoolValue(false));
                         return katachi.apply(md, par);
                     }},
                    {"host", [&](MeshDocument &md) {
                         double s = 0;
                         for (int l = 0; l < levels; ++l) {
                             RichParameterList par = catmull.params(md);
                             s += catmull.apply(md, par);
                         }
                         return s;
                     }}});
        }
    }
    for (auto [name, level] : {std::make_pair("cut 330k", 7), std::make_pair("cut 1.3M", 8)}) {
        MeshDocument holder;
        MeshModel *sphere = holder.addNewMesh("", "sphere");
        fill_icosphere(sphere->cm, level);
        sphere->UpdateBoxAndNormals();
        Shotm shot;
        shot.Intrinsics.SetPerspective(40.f, 800.f / 600.f, 20.f, vcg::Point2<int>(800, 600));
        shot.LookAt(0.f, -4.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 1.f);
        const vcg::Shotd s = vcg::Shotd::Construct(shot);
        // 50 points across the visible side (world points in front of the sphere, projected).
        std::string stroke;
        for (int i = 0; i < 50; ++i) {
            const double u = -1.2 + 2.4 * i / 49.0, v = 0.08 * std::sin(6.0 * i / 49.0);
            const vcg::Point2d q = s.Project(vcg::Point3d(u, -1.5, v));
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.4f %.4f", q[0], q[1]);
            stroke += (stroke.empty() ? "" : "; ") + std::string(buf);
        }
        rounds(name, *sphere, n_rounds,
               {{"katachi",
                 [&](MeshDocument &md) {
                     RichParameterList par = cut.params(md);
                     par.setValue("view", ShotfValue(shot));
                     par.setValue("stroke", StringValue(QString::fromStdString(stroke)));
                     par.setValue("new_layer", BoolValue(true));
                     return cut.apply(md, par);
                 }},
                {"host", [&](MeshDocument &md) {
                     RichParameterList par = duplicate.params(md);
                     return duplicate.apply(md, par);
                 }}});
    }
    std::printf("BENCH-DONE\n");
    return 0;
}

