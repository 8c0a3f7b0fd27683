// katachi-reference shim: OpenMesh 9 Catmull-Clark (CatmullClarkT) on a double-precision PolyMesh.
#include "shim_internal.hpp"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>

#include <chrono>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};

typedef OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits> Mesh;

// OpenMesh prints its complaints (e.g. "PolyMeshT::add_face: complex edge") to the process-wide
// omerr() stream. The shim connects its own buffer to omerr() once, for good, next to std::cerr
// (disconnecting std::cerr would leak OpenMesh's target object, and swapping std::cerr's buffer
// would race with other writers), and serialises its OpenMesh calls so that each call can read
// the messages it caused. OpenMesh's messages therefore still reach stderr too.
std::mutex g_openmesh_mutex;
std::once_flag g_omerr_once;
std::ostringstream *g_omerr_sink = nullptr;

void redirect_omerr() {
    std::call_once(g_omerr_once, [] {
        // Never freed: omerr() may outlive any static of ours at exit.
        g_omerr_sink = new std::ostringstream();
        ::omerr().connect(*g_omerr_sink);
    });
}

std::string take_omerr() {
    ::omerr().flush();
    std::string text = g_omerr_sink->str();
    g_omerr_sink->str(std::string());
    g_omerr_sink->clear();
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
}

void openmesh_catmull_clark(kr_result &r, const kr_mesh *mesh, uint32_t level) {
    kr::check_mesh(mesh, level);

    std::lock_guard<std::mutex> lock(g_openmesh_mutex);
    redirect_omerr();
    take_omerr();  // drop anything left over

    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    Mesh m;
    std::vector<Mesh::VertexHandle> vh;
    vh.reserve(mesh->num_vertices);
    for (uint32_t v = 0; v < mesh->num_vertices; ++v) {
        const double *p = mesh->positions + 3 * v;
        vh.push_back(m.add_vertex(Mesh::Point(p[0], p[1], p[2])));
    }
    std::vector<Mesh::VertexHandle> face;
    uint32_t corner = 0;
    for (uint32_t f = 0; f < mesh->num_faces; ++f) {
        const uint32_t n = mesh->face_sizes[f];
        face.clear();
        std::string verts;
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t v = mesh->face_vertices[corner + k];
            face.push_back(vh[v]);
            verts += (k ? " " : "") + std::to_string(v);
        }
        corner += n;
        Mesh::FaceHandle fh = m.add_face(face);
        if (!fh.is_valid()) {
            std::string why = take_omerr();
            throw kr::Rejected("OpenMesh rejected face " + std::to_string(f) + " (vertices " +
                               verts + "): " +
                               (why.empty() ? std::string("add_face returned an invalid handle")
                                            : why));
        }
    }

    const auto t1 = Clock::now();
    if (level > 0) {
        OpenMesh::Subdivider::Uniform::CatmullClarkT<Mesh, double> subdivider;
        if (!subdivider.attach(m)) {
            throw kr::Rejected("OpenMesh CatmullClarkT::attach failed: " + take_omerr());
        }
        bool ok = subdivider(level);
        subdivider.detach();
        if (!ok) {
            throw kr::Rejected("OpenMesh CatmullClarkT failed: " + take_omerr());
        }
    }
    const auto t2 = Clock::now();
    r.f64[{KR_F64_TIMINGS, 0}] = {std::chrono::duration<double>(t1 - t0).count(),
                                  std::chrono::duration<double>(t2 - t1).count()};
    r.warnings = take_omerr();

    const uint32_t key = level;
    auto &pos = r.f64[{KR_F64_POSITIONS, key}];
    pos.reserve(3 * m.n_vertices());
    for (auto v : m.vertices()) {
        const Mesh::Point &p = m.point(v);
        pos.push_back(p[0]);
        pos.push_back(p[1]);
        pos.push_back(p[2]);
    }
    auto &sizes = r.u32[{KR_U32_FACE_SIZES, key}];
    auto &fverts = r.u32[{KR_U32_FACE_VERTICES, key}];
    sizes.reserve(m.n_faces());
    for (auto f : m.faces()) {
        uint32_t n = 0;
        for (auto v : m.fv_range(f)) {
            fverts.push_back(static_cast<uint32_t>(v.idx()));
            ++n;
        }
        sizes.push_back(n);
    }
}

}  // namespace

extern "C" uint32_t kr_openmesh_catmull_clark(const kr_mesh *mesh, uint32_t level,
                                              kr_result **out) {
    return kr::guarded(out, [&](kr_result &r) { openmesh_catmull_clark(r, mesh, level); });
}
