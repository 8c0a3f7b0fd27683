// katachi MeshLab plugin: the filter "katachi: Solid-aware subdivision".
//
// The filter converts MeshLab's mesh (triangles, polygons marked by faux edges) into a
// katachi mesh, calls katachi_subdivide through include/katachi.h, and writes the result
// back as triangles with faux edges. All the geometry is katachi's: this file only moves
// data and maps errors.
//
// License: MIT OR Apache-2.0.

#include "filter_katachi.h"
#include "faux_polygons.h"

#include <katachi.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <QString>

using katachi_meshlab::FauxTriangles;
using katachi_meshlab::Polygons;

namespace {

// Parameter names: they are also the names in .mlx filter scripts, so they are stable.
const char *const kLevels = "levels";
const char *const kHoleMethod = "holeMethod";
const char *const kRecoverHoles = "recoverFacesWithHoles";
const char *const kFeatureAngle = "featureAngle";
const char *const kBoundary = "boundary";
const char *const kNewLayer = "newLayer";

struct MeshDeleter {
    void operator()(KatachiMesh *m) const { katachi_mesh_free(m); }
};
struct SubdivisionDeleter {
    void operator()(KatachiSubdivision *s) const { katachi_subdivision_free(s); }
};
using MeshPtr = std::unique_ptr<KatachiMesh, MeshDeleter>;
using SubdivisionPtr = std::unique_ptr<KatachiSubdivision, SubdivisionDeleter>;

/// katachi's message for the last failed call, with the status name when it is empty.
QString katachi_error(KatachiStatus status) {
    const char *msg = katachi_last_error_message();
    QString text = QString::fromUtf8(msg && *msg ? msg : katachi_status_name(status));
    return QString("katachi: %1").arg(text);
}

/// The result of a subdivision, in MeshLab's form, ready to be written into a layer.
struct Result {
    std::vector<double> positions; // 3 x vertex count
    FauxTriangles triangles;
    uint32_t polygon_count = 0;
};

} // namespace

KatachiFilterPlugin::KatachiFilterPlugin() {
    typeList.push_back(FP_KATACHI_SUBDIVIDE);
    for (auto id : typeList) actionList.push_back(new QAction(filterName(id), this));
}

QString KatachiFilterPlugin::pluginName() const { return "FilterKatachi"; }

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
QString KatachiFilterPlugin::filterName(ActionIDType filter) const
#else
QString KatachiFilterPlugin::filterName(FilterIDType filter) const
#endif
{
    switch (filter) {
    case FP_KATACHI_SUBDIVIDE: return "katachi: Solid-aware subdivision";
    default: return QString();
    }
}

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
QString KatachiFilterPlugin::filterInfo(ActionIDType filter) const
#else
QString KatachiFilterPlugin::filterInfo(FilterIDType filter) const
#endif
{
    switch (filter) {
    case FP_KATACHI_SUBDIVIDE:
        return QString(
                   "Catmull-Clark subdivision by the katachi kernel (%1), aware of solids: "
                   "faces with holes are refined either smoothly (method [a], loops bridged) "
                   "or kept planar with sharp loops (method [b]); the triangles a boolean "
                   "leaves on a planar face can be merged back into that face first; edges "
                   "sharper than a feature angle can be kept as creases.<br>"
                   "Polygons are read from faux edges (quads and n-gons stay polygons) and the "
                   "result is written the same way: each quad as two triangles sharing a faux "
                   "edge.<br>See: <i>Y. Yoshii, Y. Tokuyama, K. Konno</i>, <b>\"A method of "
                   "generating subdivision surfaces for solid models\"</b> (in Japanese), "
                   "faces as P loops with C loops.")
            .arg(QString::fromUtf8(katachi_version_string()));
    default: return QString();
    }
}

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
FilterPlugin::FilterClass KatachiFilterPlugin::getClass(const QAction *) const {
    return FilterPlugin::Remeshing;
}
int KatachiFilterPlugin::getPreConditions(const QAction *) const {
    return MeshModel::MM_FACENUMBER;
}
int KatachiFilterPlugin::postCondition(const QAction *) const {
    return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE | MeshModel::MM_POLYGONAL;
}
#else
MeshFilterInterface::FilterClass KatachiFilterPlugin::getClass(QAction *) {
    return MeshFilterInterface::Remeshing;
}
int KatachiFilterPlugin::getPreConditions(QAction *) const { return MeshModel::MM_FACENUMBER; }
int KatachiFilterPlugin::postCondition(QAction *) const {
    return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE | MeshModel::MM_POLYGONAL;
}
#endif

void KatachiFilterPlugin::addParameters(RichParameterList &par) const {
    par.addParam(RichInt(kLevels, 1, "Levels",
                         "Subdivision levels, 1 to 8. Each level multiplies the face count by "
                         "about four."));
    par.addParam(RichEnum(kHoleMethod, 0,
                          QStringList() << "Smooth [a]: bridge the loops"
                                        << "Sharp [b]: planar face, sharp loops",
                          "Faces with holes",
                          "How a face with holes is refined: [a] bridges its loops and "
                          "subdivides smoothly; [b] keeps the loops sharp and the face planar."));
    par.addParam(RichBool(kRecoverHoles, false, "Recover faces with holes",
                          "First merge coplanar regions (a boolean's triangles around a hole) "
                          "back into faces with holes, as the CLI's --solid does."));
    par.addParam(RichFloat(kFeatureAngle, 0.0f, "Feature angle (degrees)",
                           "Edges whose dihedral angle exceeds this many degrees stay sharp "
                           "creases (CAD models). 0 turns it off."));
    par.addParam(RichEnum(kBoundary, 0,
                          QStringList() << "Edge only" << "Edge and corner",
                          "Boundary",
                          "Boundary rule, as OpenSubdiv's: boundary edges are sharp; with "
                          "'Edge and corner' a boundary vertex with a single face is pinned too."));
    par.addParam(RichBool(kNewLayer, true, "Result in a new layer",
                          "Put the result in a new layer and keep the input; unchecked, the "
                          "current layer is replaced."));
}

#ifdef KATACHI_MESHLAB_FILTER_PLUGIN_API
RichParameterList KatachiFilterPlugin::initParameterList(const QAction *, const MeshDocument &) {
    RichParameterList par;
    addParameters(par);
    return par;
}

std::map<std::string, QVariant> KatachiFilterPlugin::applyFilter(
    const QAction *action, const RichParameterList &params, MeshDocument &md,
    unsigned int & /*postConditionMask*/, vcg::CallBackPos *cb) {
    if (ID(action) != FP_KATACHI_SUBDIVIDE)
        throw MLException("katachi: unknown filter " + action->text());
    QString error;
    if (!subdivide(md, params, cb, error)) throw MLException(error);
    return {};
}

void KatachiFilterPlugin::note(const QString &message) { log("%s", qUtf8Printable(message)); }
#else
void KatachiFilterPlugin::initParameterSet(QAction *, MeshDocument &, RichParameterList &par) {
    addParameters(par);
}

bool KatachiFilterPlugin::applyFilter(QAction *filter, MeshDocument &md,
                                      const RichParameterList &par, vcg::CallBackPos *cb) {
    errorMessage.clear();
    if (ID(filter) != FP_KATACHI_SUBDIVIDE) {
        errorMessage = "katachi: unknown filter " + filter->text();
        return false;
    }
    QString error;
    if (subdivide(md, par, cb, error)) return true;
    errorMessage = error;
    // meshlabserver prints the filter's log but not errorMessage: log it too.
    Log(GLLogStream::SYSTEM, "%s", qUtf8Printable(error));
    return false;
}

void KatachiFilterPlugin::note(const QString &message) {
    Log(GLLogStream::FILTER, "%s", qUtf8Printable(message));
}
#endif

bool KatachiFilterPlugin::subdivide(MeshDocument &md, const RichParameterList &par,
                                    vcg::CallBackPos *cb, QString &error) {
    MeshModel *src = md.mm();
    if (src == nullptr) {
        error = "katachi: there is no current mesh layer";
        return false;
    }
    if (katachi_abi_version() != KATACHI_ABI_VERSION) {
        error = QString("katachi: the plugin was built for katachi ABI %1, but the loaded "
                        "library (%2) has ABI %3; rebuild the plugin")
                    .arg(KATACHI_ABI_VERSION)
                    .arg(katachi_version_string())
                    .arg(katachi_abi_version());
        return false;
    }

    const int levels = par.getInt(kLevels);
    if (levels < 1) {
        error = QString("katachi: levels is %1; it must be 1 to 8").arg(levels);
        return false;
    }
    KatachiSubdivideOptions options = katachi_subdivide_options_default();
    options.levels = uint32_t(levels);
    options.holes = par.getEnum(kHoleMethod) == 1 ? KATACHI_HOLE_METHOD_SHARP
                                                  : KATACHI_HOLE_METHOD_SMOOTH;
    options.boundary = par.getEnum(kBoundary) == 1 ? KATACHI_BOUNDARY_EDGE_AND_CORNER
                                                   : KATACHI_BOUNDARY_EDGE_ONLY;
    options.recover_faces_with_holes = par.getBool(kRecoverHoles) ? 1 : 0;
    options.feature_angle_degrees = double(par.getFloat(kFeatureAngle));
    const bool new_layer = par.getBool(kNewLayer);

    // 1. MeshLab's layer -> katachi mesh (nothing in the layer changes).
    if (cb) cb(5, "katachi: reading the mesh");
    CMeshO &cm = src->cm;
    std::vector<uint32_t> vertex_index(cm.vert.size(), UINT32_MAX);
    std::vector<double> positions;
    positions.reserve(3 * size_t(cm.vn));
    uint32_t vertex_count = 0;
    for (size_t i = 0; i < cm.vert.size(); ++i) {
        if (cm.vert[i].IsD()) continue;
        vertex_index[i] = vertex_count++;
        for (int k = 0; k < 3; ++k) positions.push_back(double(cm.vert[i].P()[k]));
    }
    FauxTriangles tris;
    tris.corners.reserve(3 * size_t(cm.fn));
    tris.faux.reserve(size_t(cm.fn));
    for (size_t f = 0; f < cm.face.size(); ++f) {
        const CFaceO &face = cm.face[f];
        if (face.IsD()) continue;
        uint8_t faux = 0;
        for (int i = 0; i < 3; ++i) {
            const CVertexO *v = face.cV(i);
            const size_t vi = v == nullptr ? cm.vert.size() : size_t(v - cm.vert.data());
            if (vi >= cm.vert.size() || vertex_index[vi] == UINT32_MAX) {
                error = QString("katachi: face %1 of layer '%2' refers to a deleted or missing "
                                "vertex")
                            .arg(f)
                            .arg(src->label());
                return false;
            }
            tris.corners.push_back(vertex_index[vi]);
            if (face.IsF(i)) faux |= uint8_t(1u << i);
        }
        tris.faux.push_back(faux);
    }
    if (tris.faux.empty()) {
        error = QString("katachi: layer '%1' has no faces to subdivide").arg(src->label());
        return false;
    }
    const Polygons polys = katachi_meshlab::polygons_from_faux_triangles(tris);
    if (polys.groups_kept_as_triangles > 0)
        note(QString("katachi: %1 polygon(s) marked by faux edges have holes or a pinched "
                     "outline; their triangles were kept separate")
                 .arg(polys.groups_kept_as_triangles));
    if (polys.unmatched_faux_edges > 0)
        note(QString("katachi: %1 faux edge(s) had no faux neighbour and count as real edges")
                 .arg(polys.unmatched_faux_edges));

    std::vector<uint32_t> face_loop_counts(polys.sizes.size(), 1u);
    KatachiMesh *raw = nullptr;
    KatachiStatus st = katachi_mesh_create(
        positions.data(), vertex_count, polys.sizes.data(), uint32_t(polys.sizes.size()),
        face_loop_counts.data(), uint32_t(face_loop_counts.size()), polys.corners.data(),
        uint32_t(polys.corners.size()), &raw);
    MeshPtr input(raw);
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }

    // 2. Subdivide.
    if (cb) cb(20, "katachi: subdividing");
    KatachiSubdivision *raw_sub = nullptr;
    st = katachi_subdivide(input.get(), &options, &raw_sub);
    SubdivisionPtr sub(raw_sub);
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    KatachiSubdivisionInfo info = katachi_subdivision_info_default();
    if ((st = katachi_subdivision_info(sub.get(), &info)) != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    for (uint32_t i = 0; i < info.fallback_face_count; ++i) {
        char reason[512] = {0};
        if (katachi_subdivision_fallback_reason(sub.get(), i, reason, sizeof reason) ==
            KATACHI_STATUS_OK)
            note(QString("katachi: a face with holes could not be bridged (%1); method [b] "
                         "was used for it")
                     .arg(QString::fromUtf8(reason)));
    }
    raw = nullptr;
    st = katachi_subdivision_mesh(sub.get(), &raw);
    MeshPtr refined(raw);
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    sub.reset();

    // 3. Faces with holes (method [b]) cannot live in MeshLab: cut them along bridges.
    KatachiMeshCounts counts = katachi_mesh_counts_default();
    if ((st = katachi_mesh_counts(refined.get(), &counts)) != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    if (counts.loop_count != counts.face_count) {
        raw = nullptr;
        st = katachi_mesh_split_faces_with_holes(refined.get(), &raw, nullptr, 0);
        MeshPtr split(raw);
        if (st != KATACHI_STATUS_OK) {
            error = katachi_error(st);
            return false;
        }
        note(QString("katachi: %1 face(s) with holes written as simple polygons cut along "
                     "bridge edges")
                 .arg(counts.loop_count - counts.face_count));
        refined = std::move(split);
        counts = katachi_mesh_counts_default();
        if ((st = katachi_mesh_counts(refined.get(), &counts)) != KATACHI_STATUS_OK) {
            error = katachi_error(st);
            return false;
        }
    }

    if (cb) cb(80, "katachi: writing the result");
    Result result;
    result.positions.resize(3 * size_t(counts.vertex_count));
    std::vector<uint32_t> loop_sizes(counts.loop_count), loops_per_face(counts.face_count),
        corners(counts.corner_count);
    st = katachi_mesh_copy_positions(refined.get(), result.positions.data(),
                                     result.positions.size());
    if (st == KATACHI_STATUS_OK)
        st = katachi_mesh_copy_faces(refined.get(), loop_sizes.data(), loop_sizes.size(),
                                     loops_per_face.data(), loops_per_face.size(),
                                     corners.data(), corners.size());
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    if (loop_sizes.size() != loops_per_face.size()) {
        error = "katachi: the result still has faces with holes after splitting them";
        return false;
    }
    result.triangles = katachi_meshlab::faux_triangles_from_polygons(loop_sizes, corners);
    result.polygon_count = counts.face_count;

    // 4. Only now touch the document: nothing below can fail on katachi's side.
    MeshModel *dst = src;
    if (new_layer) {
        dst = md.addNewMesh("", QString("%1 (katachi subdivided)").arg(src->label()), true);
        dst->cm.Tr = src->cm.Tr;
    } else {
        dst->cm.Clear();
    }
    CMeshO &out = dst->cm;
    const size_t nv = result.positions.size() / 3;
    const size_t nf = result.triangles.faux.size();
    auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(out, nv);
    for (size_t i = 0; i < nv; ++i, ++vi)
        vi->P() = Point3m(Scalarm(result.positions[3 * i]), Scalarm(result.positions[3 * i + 1]),
                          Scalarm(result.positions[3 * i + 2]));
    auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(out, nf);
    for (size_t f = 0; f < nf; ++f, ++fi) {
        for (int k = 0; k < 3; ++k) {
            fi->V(k) = &out.vert[result.triangles.corners[3 * f + k]];
            if (result.triangles.faux[f] & (1u << k))
                fi->SetF(k);
            else
                fi->ClearF(k);
        }
    }
    dst->updateDataMask(MeshModel::MM_POLYGONAL);
    dst->UpdateBoxAndNormals();
    note(QString("katachi: %1 levels: %2 vertices, %3 faces (%4 triangles)")
             .arg(levels)
             .arg(nv)
             .arg(result.polygon_count)
             .arg(nf));
    if (cb) cb(100, "katachi: done");
    return true;
}

#ifndef KATACHI_MESHLAB_FILTER_PLUGIN_API
MESHLAB_PLUGIN_NAME_EXPORTER(KatachiFilterPlugin)
#endif
