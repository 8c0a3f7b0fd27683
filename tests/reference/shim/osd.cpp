// katachi-reference shim: OpenSubdiv 3.5 uniform Catmull-Clark refinement with double-precision
// primvar interpolation (Far::PrimvarRefinerReal<double>).
#include "shim_internal.hpp"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/sdc/options.h>
#include <opensubdiv/sdc/types.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

// A position with double coordinates, in the shape PrimvarRefinerReal expects.
struct Vertex3 {
    double p[3];
    void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(const Vertex3 &src, double weight) {
        p[0] += weight * src.p[0];
        p[1] += weight * src.p[1];
        p[2] += weight * src.p[2];
    }
};

// A face-varying value (a UV) with double coordinates.
struct Vertex2 {
    double p[2];
    void Clear(void * = nullptr) { p[0] = p[1] = 0.0; }
    void AddWithWeight(const Vertex2 &src, double weight) {
        p[0] += weight * src.p[0];
        p[1] += weight * src.p[1];
    }
};

// OpenSubdiv reports through process-wide callbacks; they are always invoked on the thread that
// called into OpenSubdiv, so a thread-local sink keeps concurrent calls apart.
thread_local std::string *t_sink = nullptr;

void on_warning(const char *message) {
    if (t_sink != nullptr) {
        try {
            t_sink->append(message);
            t_sink->push_back('\n');
        } catch (...) {
        }
    }
}

void on_error(Far::ErrorType, const char *message) {
    if (t_sink != nullptr) {
        try {
            t_sink->append("error: ");
            t_sink->append(message);
            t_sink->push_back('\n');
        } catch (...) {
        }
    }
}

std::once_flag g_callbacks_once;

// Sets the thread's sink for the duration of one call.
struct SinkScope {
    explicit SinkScope(std::string &sink) {
        std::call_once(g_callbacks_once, [] {
            Far::SetWarningCallback(on_warning);
            Far::SetErrorCallback(on_error);
        });
        t_sink = &sink;
    }
    ~SinkScope() { t_sink = nullptr; }
    SinkScope(const SinkScope &) = delete;
    SinkScope &operator=(const SinkScope &) = delete;
};

float sharpness_to_float(double s, const char *what, uint32_t i) {
    if (!std::isfinite(s) || s < 0.0) {
        throw kr::BadArgument(std::string(what) + " " + std::to_string(i) +
                              " has sharpness " + std::to_string(s) +
                              "; it must be finite and >= 0");
    }
    return static_cast<float>(s);
}

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point from, Clock::time_point to) {
    return std::chrono::duration<double>(to - from).count();
}

uint32_t to_u32(Far::Index i) {
    return static_cast<uint32_t>(i);  // INDEX_INVALID (-1) becomes 0xffffffff
}

void store_level_info(kr_result &r, const Far::TopologyRefiner &refiner, int l, int last) {
    const Far::TopologyLevel &lev = refiner.GetLevel(l);
    const uint32_t key = static_cast<uint32_t>(l);
    const int nv = lev.GetNumVertices(), ne = lev.GetNumEdges(), nf = lev.GetNumFaces();

    auto &sizes = r.u32[{KR_U32_FACE_SIZES, key}];
    auto &fverts = r.u32[{KR_U32_FACE_VERTICES, key}];
    sizes.clear();
    fverts.clear();
    for (int f = 0; f < nf; ++f) {
        Far::ConstIndexArray fv = lev.GetFaceVertices(f);
        sizes.push_back(static_cast<uint32_t>(fv.size()));
        for (int k = 0; k < fv.size(); ++k) fverts.push_back(to_u32(fv[k]));
    }

    auto &ev = r.u32[{KR_U32_EDGE_VERTICES, key}];
    auto &es = r.f64[{KR_F64_EDGE_SHARPNESS, key}];
    auto &ef = r.u32[{KR_U32_EDGE_FLAGS, key}];
    for (int e = 0; e < ne; ++e) {
        Far::ConstIndexArray v = lev.GetEdgeVertices(e);
        ev.push_back(to_u32(v[0]));
        ev.push_back(to_u32(v[1]));
        es.push_back(static_cast<double>(lev.GetEdgeSharpness(e)));
        ef.push_back((lev.IsEdgeBoundary(e) ? 1u : 0u) | (lev.IsEdgeNonManifold(e) ? 2u : 0u) |
                     (lev.IsEdgeInfSharp(e) ? 4u : 0u) | (lev.IsEdgeSemiSharp(e) ? 8u : 0u));
    }

    auto &vs = r.f64[{KR_F64_VERTEX_SHARPNESS, key}];
    auto &vr = r.u32[{KR_U32_VERTEX_RULE, key}];
    auto &vf = r.u32[{KR_U32_VERTEX_FLAGS, key}];
    for (int v = 0; v < nv; ++v) {
        vs.push_back(static_cast<double>(lev.GetVertexSharpness(v)));
        vr.push_back(static_cast<uint32_t>(lev.GetVertexRule(v)));
        vf.push_back((lev.IsVertexBoundary(v) ? 1u : 0u) | (lev.IsVertexNonManifold(v) ? 2u : 0u) |
                     (lev.IsVertexInfSharp(v) ? 4u : 0u) | (lev.IsVertexSemiSharp(v) ? 8u : 0u));
    }

    if (l < last) {
        auto &fcv = r.u32[{KR_U32_FACE_CHILD_VERTEX, key}];
        auto &fcf = r.u32[{KR_U32_FACE_CHILD_FACES, key}];
        for (int f = 0; f < nf; ++f) {
            fcv.push_back(to_u32(lev.GetFaceChildVertex(f)));
            Far::ConstIndexArray cf = lev.GetFaceChildFaces(f);
            for (int k = 0; k < cf.size(); ++k) fcf.push_back(to_u32(cf[k]));
        }
        auto &ecv = r.u32[{KR_U32_EDGE_CHILD_VERTEX, key}];
        auto &ece = r.u32[{KR_U32_EDGE_CHILD_EDGES, key}];
        for (int e = 0; e < ne; ++e) {
            ecv.push_back(to_u32(lev.GetEdgeChildVertex(e)));
            Far::ConstIndexArray ce = lev.GetEdgeChildEdges(e);
            for (int k = 0; k < ce.size(); ++k) ece.push_back(to_u32(ce[k]));
        }
        auto &vcv = r.u32[{KR_U32_VERTEX_CHILD_VERTEX, key}];
        for (int v = 0; v < nv; ++v) vcv.push_back(to_u32(lev.GetVertexChildVertex(v)));
    }
    if (l > 0) {
        auto &fpf = r.u32[{KR_U32_FACE_PARENT_FACE, key}];
        for (int f = 0; f < nf; ++f) fpf.push_back(to_u32(lev.GetFaceParentFace(f)));
    }
}

void store_positions(kr_result &r, const std::vector<Vertex3> &pos, uint32_t level) {
    auto &out = r.f64[{KR_F64_POSITIONS, level}];
    out.resize(3 * pos.size());
    for (size_t i = 0; i < pos.size(); ++i) {
        out[3 * i] = pos[i].p[0];
        out[3 * i + 1] = pos[i].p[1];
        out[3 * i + 2] = pos[i].p[2];
    }
}

void osd_catmark(kr_result &r, const kr_mesh *mesh, const kr_creases *creases,
                 const kr_osd_options *options, uint32_t level, const kr_fvar *fvar) {
    kr::check_mesh(mesh, level);
    if (options == nullptr) throw kr::BadArgument("options are null");
    if (options->boundary > KR_BOUNDARY_EDGE_AND_CORNER)
        throw kr::BadArgument("unknown boundary mode " + std::to_string(options->boundary));
    if (options->crease > KR_CREASE_CHAIKIN)
        throw kr::BadArgument("unknown crease method " + std::to_string(options->crease));
    if (options->fvar > KR_FVAR_ALL)
        throw kr::BadArgument("unknown face-varying mode " + std::to_string(options->fvar));

    const int nv = static_cast<int>(mesh->num_vertices);

    // Base topology.
    std::vector<int> face_sizes(mesh->face_sizes, mesh->face_sizes + mesh->num_faces);
    std::vector<Far::Index> face_verts(mesh->face_vertices,
                                       mesh->face_vertices + mesh->num_face_vertices);

    Far::TopologyDescriptor desc;
    desc.numVertices = nv;
    desc.numFaces = static_cast<int>(mesh->num_faces);
    desc.numVertsPerFace = face_sizes.data();
    desc.vertIndicesPerFace = face_verts.data();

    // Creases and corners. OpenSubdiv stores sharpness as float.
    std::vector<Far::Index> crease_pairs, corner_verts;
    std::vector<float> crease_weights, corner_weights;
    if (creases != nullptr) {
        if (creases->num_edges > 0 &&
            (creases->edge_vertices == nullptr || creases->edge_sharpness == nullptr))
            throw kr::BadArgument("crease edge arrays are null");
        if (creases->num_corners > 0 &&
            (creases->corner_vertices == nullptr || creases->corner_sharpness == nullptr))
            throw kr::BadArgument("corner arrays are null");
        for (uint32_t i = 0; i < creases->num_edges; ++i) {
            uint32_t a = creases->edge_vertices[2 * i], b = creases->edge_vertices[2 * i + 1];
            if (a >= mesh->num_vertices || b >= mesh->num_vertices)
                throw kr::BadArgument("crease " + std::to_string(i) + " refers to vertex " +
                                      std::to_string(a >= mesh->num_vertices ? a : b) +
                                      ", but the mesh has " + std::to_string(nv) + " vertices");
            crease_pairs.push_back(static_cast<Far::Index>(a));
            crease_pairs.push_back(static_cast<Far::Index>(b));
            crease_weights.push_back(sharpness_to_float(creases->edge_sharpness[i], "crease", i));
        }
        for (uint32_t i = 0; i < creases->num_corners; ++i) {
            uint32_t v = creases->corner_vertices[i];
            if (v >= mesh->num_vertices)
                throw kr::BadArgument("corner " + std::to_string(i) + " refers to vertex " +
                                      std::to_string(v) + ", but the mesh has " +
                                      std::to_string(nv) + " vertices");
            corner_verts.push_back(static_cast<Far::Index>(v));
            corner_weights.push_back(sharpness_to_float(creases->corner_sharpness[i], "corner", i));
        }
        desc.numCreases = static_cast<int>(creases->num_edges);
        desc.creaseVertexIndexPairs = crease_pairs.data();
        desc.creaseWeights = crease_weights.data();
        desc.numCorners = static_cast<int>(creases->num_corners);
        desc.cornerVertexIndices = corner_verts.data();
        desc.cornerWeights = corner_weights.data();
    }

    // The face-varying channel.
    std::vector<Far::Index> fvar_indices;
    Far::TopologyDescriptor::FVarChannel channel;
    if (fvar != nullptr) {
        if (fvar->indices == nullptr && mesh->num_face_vertices > 0)
            throw kr::BadArgument("face-varying indices are null");
        if (fvar->values == nullptr && fvar->num_values > 0)
            throw kr::BadArgument("face-varying values are null");
        if (fvar->num_values > INT32_MAX / 4)
            throw kr::BadArgument("too many face-varying values");
        for (uint32_t i = 0; i < 2 * fvar->num_values; ++i)
            if (!std::isfinite(fvar->values[i]))
                throw kr::BadArgument("face-varying value " + std::to_string(i / 2) +
                                      " is not finite");
        for (uint32_t c = 0; c < mesh->num_face_vertices; ++c) {
            uint32_t i = fvar->indices[c];
            if (i >= fvar->num_values)
                throw kr::BadArgument("face corner " + std::to_string(c) +
                                      " refers to face-varying value " + std::to_string(i) +
                                      ", but there are " + std::to_string(fvar->num_values));
            fvar_indices.push_back(static_cast<Far::Index>(i));
        }
        channel.numValues = static_cast<int>(fvar->num_values);
        channel.valueIndices = fvar_indices.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(
        static_cast<Sdc::Options::VtxBoundaryInterpolation>(options->boundary));
    sdc.SetCreasingMethod(static_cast<Sdc::Options::CreasingMethod>(options->crease));
    sdc.SetFVarLinearInterpolation(
        static_cast<Sdc::Options::FVarLinearInterpolation>(options->fvar));

    const bool info = options->level_info != 0;
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    auto &timings = r.f64[{KR_F64_TIMINGS, 0}];
    std::unique_ptr<Far::TopologyRefiner> refiner;
    {
        SinkScope scope(r.warnings);
        const auto t0 = Clock::now();
        refiner.reset(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
        if (!refiner) {
            throw kr::Rejected("OpenSubdiv's TopologyRefinerFactory rejected the mesh" +
                               (r.warnings.empty() ? std::string() : ": " + r.warnings));
        }
        // Warnings at construction are invalid tags (a crease on a missing edge, ...): the
        // topology would silently differ from what was asked for.
        if (!r.warnings.empty()) {
            throw kr::Rejected("OpenSubdiv's TopologyRefinerFactory warned: " + r.warnings);
        }
        const auto t1 = Clock::now();
        if (level > 0) {
            Far::TopologyRefiner::UniformOptions uniform(static_cast<int>(level));
            // The last level needs its edges (and so full topology) only for level_info; faces and
            // face-varying values are there either way, and full topology costs 2-3x the refine
            // time at level 3 (measured on a 32k-quad torus).
            uniform.fullTopologyInLastLevel = info;
            refiner->RefineUniform(uniform);
        }
        timings.push_back(seconds(t0, t1));
        timings.push_back(seconds(t1, Clock::now()));
    }
    const int last = static_cast<int>(level);

    // Positions, level by level, in double precision.
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    std::vector<Vertex3> src(static_cast<size_t>(nv)), dst;
    for (int v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k) src[v].p[k] = mesh->positions[3 * v + k];
    {
        SinkScope scope(r.warnings);
        if (info) store_positions(r, src, 0);
        double interpolate = 0.0;
        for (int l = 1; l <= last; ++l) {
            // The destination's allocation is timed: a caller must make it, and katachi's
            // timing includes its own.
            const auto t0 = Clock::now();
            dst.resize(static_cast<size_t>(refiner->GetLevel(l).GetNumVertices()));
            Vertex3 *from = src.data(), *to = dst.data();
            primvar.Interpolate(l, from, to);
            interpolate += seconds(t0, Clock::now());
            src.swap(dst);
            if (info || l == last) store_positions(r, src, static_cast<uint32_t>(l));
        }
        if (last == 0) store_positions(r, src, 0);
        timings.push_back(interpolate);
    }

    // Face-varying values, expanded to one per face corner of the last level.
    if (fvar != nullptr) {
        SinkScope scope(r.warnings);
        std::vector<Vertex2> fsrc(fvar->num_values), fdst;
        for (uint32_t i = 0; i < fvar->num_values; ++i) {
            fsrc[i].p[0] = fvar->values[2 * i];
            fsrc[i].p[1] = fvar->values[2 * i + 1];
        }
        for (int l = 1; l <= last; ++l) {
            fdst.resize(static_cast<size_t>(refiner->GetLevel(l).GetNumFVarValues(0)));
            Vertex2 *from = fsrc.data(), *to = fdst.data();
            primvar.InterpolateFaceVarying(l, from, to, 0);
            fsrc.swap(fdst);
        }
        const Far::TopologyLevel &lev = refiner->GetLevel(last);
        auto &out = r.f64[{KR_F64_FVAR, static_cast<uint32_t>(last)}];
        for (int f = 0; f < lev.GetNumFaces(); ++f) {
            Far::ConstIndexArray fv = lev.GetFaceFVarValues(f, 0);
            for (int k = 0; k < fv.size(); ++k) {
                out.push_back(fsrc[static_cast<size_t>(fv[k])].p[0]);
                out.push_back(fsrc[static_cast<size_t>(fv[k])].p[1]);
            }
        }
    }

    // Topology: counts of every level, faces of the last (or every) level, and diagnostics.
    for (int l = 0; l <= last; ++l) {
        const Far::TopologyLevel &lev = refiner->GetLevel(l);
        r.u32[{KR_U32_COUNTS, static_cast<uint32_t>(l)}] = {
            static_cast<uint32_t>(lev.GetNumVertices()), static_cast<uint32_t>(lev.GetNumEdges()),
            static_cast<uint32_t>(lev.GetNumFaces()),
            static_cast<uint32_t>(fvar != nullptr ? lev.GetNumFVarValues(0) : 0)};
        if (info) {
            store_level_info(r, *refiner, l, last);
        } else if (l == last) {
            auto &sizes = r.u32[{KR_U32_FACE_SIZES, static_cast<uint32_t>(l)}];
            auto &fverts = r.u32[{KR_U32_FACE_VERTICES, static_cast<uint32_t>(l)}];
            sizes.reserve(static_cast<size_t>(lev.GetNumFaces()));
            fverts.reserve(static_cast<size_t>(lev.GetNumFaceVertices()));
            for (int f = 0; f < lev.GetNumFaces(); ++f) {
                Far::ConstIndexArray fv = lev.GetFaceVertices(f);
                sizes.push_back(static_cast<uint32_t>(fv.size()));
                for (int k = 0; k < fv.size(); ++k) fverts.push_back(to_u32(fv[k]));
            }
        }
    }
}

}  // namespace

extern "C" uint32_t kr_osd_catmark(const kr_mesh *mesh, const kr_creases *creases,
                                   const kr_osd_options *options, uint32_t level,
                                   const kr_fvar *fvar, kr_result **out) {
    return kr::guarded(out, [&](kr_result &r) { osd_catmark(r, mesh, creases, options, level, fvar); });
}
