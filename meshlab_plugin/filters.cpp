// katachi MeshLab plugin: the filters "katachi: Solid-aware subdivision" and
// "katachi: Cut by polyline".
//
// Subdivision converts MeshLab's mesh (triangles, polygons marked by faux edges) into a
// katachi mesh, calls katachi_subdivide through include/katachi.h, and writes the result
// back as triangles with faux edges. The cut passes the layer's triangles, the stroke and
// the view (cut_view.h) to katachi_cut_by_stroke and writes the cut mesh back, with the
// layer's per-face, per-wedge and per-vertex data carried over by katachi's face origins and
// interpolation. All the geometry is katachi's: this file only moves data and maps errors.
//
// License: MIT OR Apache-2.0.

#include "filters.h"
#include "cut_view.h"
#include "faux_polygons.h"

#include <katachi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <QString>

using katachi_meshlab::FauxTriangles;
using katachi_meshlab::Polygons;

namespace {

// Parameter names: the names in .mlx filter scripts and, in pymeshlab, the keyword
// arguments. Each is the label the dialog shows, as pymeshlab spells a name (lower case,
// spaces as underscores, no brackets), so a pymeshlab user finds the GUI's words.
const char *const kLevels = "levels";                          // Levels
const char *const kHoleMethod = "faces_with_holes";            // Faces with holes
const char *const kRecoverHoles = "recover_faces_with_holes";  // Recover faces with holes
const char *const kFeatureAngle = "feature_angle_degrees";     // Feature angle (degrees)
const char *const kBoundary = "boundary";                      // Boundary
const char *const kNewLayer = "new_layer";                     // New layer
// Cut by polyline. The view comes first: meshlabserver 2020.09 cannot read a shot from a
// script (its reader asserts), and a script may leave out only the first parameter.
const char *const kShot = "view";                              // View
const char *const kViewXml = "view_as_text";                   // View as text
const char *const kStroke = "stroke";                          // Stroke
const char *const kMode = "faces_to_cut";                      // Faces to cut
const char *const kOpenCut = "open_the_cut";                   // Open the cut

struct MeshDeleter {
    void operator()(KatachiMesh *m) const { katachi_mesh_free(m); }
};
struct SubdivisionDeleter {
    void operator()(KatachiSubdivision *s) const { katachi_subdivision_free(s); }
};
struct CutDeleter {
    void operator()(KatachiCut *c) const { katachi_cut_free(c); }
};
using MeshPtr = std::unique_ptr<KatachiMesh, MeshDeleter>;
using SubdivisionPtr = std::unique_ptr<KatachiSubdivision, SubdivisionDeleter>;
using CutPtr = std::unique_ptr<KatachiCut, CutDeleter>;

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

/// A layer's triangles in katachi's terms: its vertices and faces without the deleted ones,
/// in the layer's order, and the corners face after face as indices into those vertices.
struct LayerTriangles {
    std::vector<const CVertexO *> verts;
    std::vector<const CFaceO *> faces;
    std::vector<double> positions; // 3 per vertex
    std::vector<uint32_t> corners; // 3 per face
};

/// Reads the layer `src` (nothing in it changes); false, with `error`, when a face refers
/// to a deleted or missing vertex.
bool read_layer(MeshModel *src, LayerTriangles &out, QString &error) {
    CMeshO &cm = src->cm;
    std::vector<uint32_t> vertex_index(cm.vert.size(), UINT32_MAX);
    out.verts.reserve(size_t(cm.vn));
    out.positions.reserve(3 * size_t(cm.vn));
    for (size_t i = 0; i < cm.vert.size(); ++i) {
        if (cm.vert[i].IsD()) continue;
        vertex_index[i] = uint32_t(out.verts.size());
        out.verts.push_back(&cm.vert[i]);
        for (int k = 0; k < 3; ++k) out.positions.push_back(double(cm.vert[i].P()[k]));
    }
    out.faces.reserve(size_t(cm.fn));
    out.corners.reserve(3 * size_t(cm.fn));
    for (size_t f = 0; f < cm.face.size(); ++f) {
        const CFaceO &face = cm.face[f];
        if (face.IsD()) continue;
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
            out.corners.push_back(vertex_index[vi]);
        }
        out.faces.push_back(&face);
    }
    return true;
}

/// A katachi mesh of simple faces (`sizes` corners each, one loop per face); null, with
/// `error` set, when katachi refuses it.
MeshPtr create_mesh(const std::vector<double> &positions, const std::vector<uint32_t> &sizes,
                    const std::vector<uint32_t> &corners, QString &error) {
    const std::vector<uint32_t> face_loop_counts(sizes.size(), 1u);
    KatachiMesh *raw = nullptr;
    const KatachiStatus st = katachi_mesh_create(
        positions.data(), uint32_t(positions.size() / 3), sizes.data(), uint32_t(sizes.size()),
        face_loop_counts.data(), uint32_t(face_loop_counts.size()), corners.data(),
        uint32_t(corners.size()), &raw);
    MeshPtr mesh(raw);
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        mesh.reset();
    }
    return mesh;
}

} // namespace

namespace katachi_meshlab {

const std::vector<int> &filter_ids() {
    static const std::vector<int> ids = {SUBDIVIDE, CUT};
    return ids;
}

QString filter_name(int filter) {
    switch (filter) {
    case SUBDIVIDE: return "katachi: Solid-aware subdivision";
    case CUT: return "katachi: Cut by polyline";
    default: return QString();
    }
}

QString filter_info(int filter) {
    switch (filter) {
    case SUBDIVIDE:
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
    case CUT:
        return QString(
                   "Cuts the current layer along a polyline drawn over a view of it, with the "
                   "katachi kernel (%1): mesh vertices near the stroke move onto it (parallel "
                   "to the screen), the stroke is simplified so that no triangle is crossed "
                   "twice, and each triangle is split into at most three (four where the "
                   "stroke ends inside it), so the cut adds no slivers. Only the faces seen "
                   "from the view are cut, or every face under the stroke; the cut can be "
                   "opened into a slit or separate pieces.<br>"
                   "The result is triangles. Face colour, quality and selection follow the "
                   "face each new triangle lies in; wedge texture coordinates and vertex "
                   "colour, quality and texture coordinates are interpolated. The vertices "
                   "along the cut are selected.<br>"
                   "The stroke is in pixels of the view's viewport, origin at its bottom-left "
                   "corner, y up (vcg::Shot::Project's convention).<br>See: <i>J. Mitani, "
                   "H. Suzuki</i>, <b>\"Mesh cutting by hand drawn stroke achieved by a "
                   "simple implementation\"</b>.")
            .arg(QString::fromUtf8(katachi_version_string()));
    default: return QString();
    }
}


int post_condition(int filter) {
    if (filter == CUT)
        return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE | MeshModel::MM_VERTFLAGSELECT |
               MeshModel::MM_FACEFLAGSELECT;
    return MeshModel::MM_GEOMETRY_AND_TOPOLOGY_CHANGE | MeshModel::MM_POLYGONAL;
}

void add_parameters(int filter, RichParameterList &par) {
    if (filter == CUT) {
        // The current 3D view when MeshLab's GUI has one; otherwise an invalid shot, which
        // the filter refuses unless 'View as text' is given.
        Shotm view;
        katachi_meshlab::current_view_shot(view);
        par.addParam(RichShotParameter(
            kShot, view, "View",
            "The camera the stroke was drawn in: by default the current 3D view when the "
            "dialog opened; 'Get shot' with 'Current Trackball' takes the view again (after "
            "you turn the model), 'Current Raster' takes a raster's camera. Filter scripts "
            "cannot hold it (MeshLab 2020.09 cannot read a shot from a script): they leave it "
            "out and give 'View as text'."));
        par.addParam(RichString(
            kViewXml, "", "View as text",
            "Optional. MeshLab's camera as XML: the text Windows > Copy shot puts on the "
            "clipboard, or a <VCGCamera .../> element from a MeshLab project. When given, it "
            "is used instead of 'View'."));
        par.addParam(RichString(
            kStroke, "", "Stroke",
            "The polyline, as x y pairs separated by spaces, commas or semicolons, e.g. "
            "'120 300; 250 310; 400 290'. Pixels of the view's viewport (its ViewportPx, the "
            "3D view's size), origin at the BOTTOM-left corner, x right, y UP: what "
            "vcg::Shot::Project gives for a 3D point. For a point read off a screenshot or a "
            "mouse position (origin top-left, y down), use y = height - y. A stroke whose last "
            "point is within 2 pixels of its first is closed (a loop)."));
        par.addParam(RichEnum(kMode, 0,
                              QStringList() << "Visible only" << "Through all",
                              "Faces to cut",
                              "Visible only: the faces seen from the view (front-facing, not "
                              "hidden). Through all: every face under the stroke, front and "
                              "back, each sheet with its own path."));
        par.addParam(RichBool(kOpenCut, false, "Open the cut",
                              "Duplicate the vertices along the cut, so the mesh gets a slit "
                              "(or falls apart where the cut runs from border to border or "
                              "closes a loop). Unchecked, the cut only adds the edges."));
        par.addParam(RichBool(kNewLayer, true, "New layer",
                              "Put the result in a new layer and keep the input; unchecked, "
                              "the current layer is replaced."));
        return;
    }
    par.addParam(RichInt(kLevels, 1, "Levels",
                         "Subdivision levels, 1 to 8. Each level multiplies the face count by "
                         "about four."));
    par.addParam(RichEnum(kHoleMethod, 0,
                          QStringList() << "Smooth [a]" << "Sharp [b]",
                          "Faces with holes",
                          "How a face with holes is refined: Smooth [a] bridges its loops and "
                          "subdivides smoothly; Sharp [b] keeps the loops sharp and the face "
                          "planar."));
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
    par.addParam(RichBool(kNewLayer, true, "New layer",
                          "Put the result in a new layer and keep the input; unchecked, the "
                          "current layer is replaced."));
}


bool subdivide(MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
               const Note &note, Outputs &outputs, QString &error) {
    MeshModel *src = md.mm();

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
    LayerTriangles layer;
    if (!read_layer(src, layer, error)) return false;
    FauxTriangles tris;
    tris.corners = std::move(layer.corners);
    tris.faux.reserve(layer.faces.size());
    for (const CFaceO *face : layer.faces) {
        uint8_t faux = 0;
        for (int i = 0; i < 3; ++i)
            if (face->IsF(i)) faux |= uint8_t(1u << i);
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

    MeshPtr input = create_mesh(layer.positions, polys.sizes, polys.corners, error);
    if (!input) return false;

    // 2. Subdivide.
    if (cb) cb(20, "katachi: subdividing");
    KatachiSubdivision *raw_sub = nullptr;
    KatachiStatus st = katachi_subdivide(input.get(), &options, &raw_sub);
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
    KatachiMesh *raw = nullptr;
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
    update_box_and_normals(*dst);
    note(QString("katachi: %1 levels: %2 vertices, %3 faces (%4 triangles)")
             .arg(levels)
             .arg(nv)
             .arg(result.polygon_count)
             .arg(nf));
    outputs.counts["vertex_count"] = nv;
    outputs.counts["face_count"] = result.polygon_count;
    outputs.counts["triangle_count"] = nf;
    if (cb) cb(100, "katachi: done");
    return true;
}

namespace {

/// Per-element data of a layer that a cut carries over, in katachi's order (vertices and
/// faces of the layer without the deleted ones; corners face after face).
struct LayerData {
    bool vert_color = false, vert_quality = false, vert_tex = false;
    bool face_color = false, face_quality = false, face_select = false;
    bool wedge_tex = false; // MeshLab 2020.09's faces have no wedge colours (CFaceO)
    std::vector<double> vcolor, vquality, vtex; // 4, 1, 2 per vertex
    std::vector<short> vtex_n;                  // texture index per vertex
    std::vector<double> wtex;                   // 2 per corner
    std::vector<short> wtex_n;                  // texture index per face (its first wedge)
};

/// What the cut gives back, in MeshLab's form, ready to be written into a layer.
struct CutResult {
    std::vector<double> positions;   // 3 x vertex count
    std::vector<uint32_t> triangles; // 3 x face count
    std::vector<uint32_t> origin;    // input face of each face
    std::vector<uint8_t> faux;       // faux-edge mask of each face
    std::vector<uint8_t> selected;   // per vertex: on the cut
    std::vector<double> vcolor, vquality, vtex, wtex;
    std::vector<short> vtex_n;
};

QString number(double x) { return QString::number(x, 'g', 6); }

} // namespace

bool cut_by_polyline(MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
                     const Note &note, Outputs &outputs, QString &error) {
    using katachi_meshlab::CutView;
    MeshModel *src = md.mm();
    CMeshO &cm = src->cm;
    if (cb) cb(2, "katachi: reading the stroke and the view");

    // 1. The parameters: stroke, view, options. Nothing in the document changes before 5.
    std::vector<double> stroke;
    if (!katachi_meshlab::parse_stroke(par.getString(kStroke), stroke, error)) return false;
    Shotm shot = par.getShotf(kShot);
    const QString view_xml = par.getString(kViewXml).trimmed();
    const bool from_xml = !view_xml.isEmpty();
    if (from_xml && !katachi_meshlab::parse_camera_xml(view_xml, shot, error)) return false;
    KatachiCutOptions options = katachi_cut_options_default();
    options.mode = uint32_t(par.getEnum(kMode)); // katachi refuses values it does not know
    options.open = par.getBool(kOpenCut) ? 1 : 0;
    const bool new_layer = par.getBool(kNewLayer);

    // 2. The layer -> katachi (triangles as they are, so katachi's face origins are the
    //    layer's faces and its corners the layer's wedges).
    if (cb) cb(5, "katachi: reading the mesh");
    LayerTriangles layer;
    if (!read_layer(src, layer, error)) return false;
    std::vector<const CVertexO *> &verts = layer.verts;
    std::vector<const CFaceO *> &faces = layer.faces;
    const std::vector<double> &positions = layer.positions;
    const std::vector<uint32_t> &corners = layer.corners;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t i = 0; i < positions.size(); ++i) {
        const double x = positions[i];
        if (std::isfinite(x)) {
            lo[i % 3] = std::min(lo[i % 3], x);
            hi[i % 3] = std::max(hi[i % 3], x);
        }
    }
    if (faces.empty()) {
        error = QString("katachi: layer '%1' has no faces to cut").arg(src->label());
        return false;
    }
    for (int k = 0; k < 3; ++k)
        if (!(lo[k] <= hi[k])) lo[k] = hi[k] = 0.0;

    // 3. The view in katachi's terms (cut_view.h); the stroke flipped to y down.
    CutView view;
    if (!katachi_meshlab::view_from_shot(vcg::Shotd::Construct(shot),
                                         vcg::Matrix44d::Construct(cm.Tr), lo, hi, view, error))
        return false;
    katachi_meshlab::stroke_to_katachi(stroke, view.viewport[3]);

    LayerData in;
    in.vert_color = src->hasDataMask(MeshModel::MM_VERTCOLOR);
    in.vert_quality = src->hasDataMask(MeshModel::MM_VERTQUALITY);
    in.vert_tex = src->hasDataMask(MeshModel::MM_VERTTEXCOORD);
    in.face_color = src->hasDataMask(MeshModel::MM_FACECOLOR);
    in.face_quality = src->hasDataMask(MeshModel::MM_FACEQUALITY);
    in.wedge_tex = src->hasDataMask(MeshModel::MM_WEDGTEXCOORD);
    for (const CFaceO *f : faces) in.face_select = in.face_select || f->IsS();
    for (const CVertexO *v : verts) {
        if (in.vert_color)
            for (int k = 0; k < 4; ++k) in.vcolor.push_back(double(v->cC()[k]));
        if (in.vert_quality) in.vquality.push_back(double(v->cQ()));
        if (in.vert_tex) {
            in.vtex.push_back(double(v->cT().U()));
            in.vtex.push_back(double(v->cT().V()));
            in.vtex_n.push_back(v->cT().N());
        }
    }
    for (const CFaceO *f : faces) {
        if (in.wedge_tex) in.wtex_n.push_back(f->cWT(0).N());
        for (int k = 0; k < 3; ++k) {
            if (in.wedge_tex) {
                in.wtex.push_back(double(f->cWT(k).U()));
                in.wtex.push_back(double(f->cWT(k).V()));
            }
        }
    }

    // 4. Cut, and read everything back. Any failure leaves the document untouched.
    if (cb) cb(15, "katachi: cutting");
    const uint32_t vertex_count = uint32_t(verts.size());
    const uint32_t face_count = uint32_t(faces.size());
    MeshPtr input = create_mesh(positions, std::vector<uint32_t>(face_count, 3u), corners, error);
    if (!input) return false;
    KatachiCut *raw_cut = nullptr;
    KatachiStatus st =
        katachi_cut_by_stroke(input.get(), stroke.data(), uint32_t(stroke.size() / 2),
                              view.view_proj, view.viewport, &options, &raw_cut);
    CutPtr cut(raw_cut);
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    KatachiCutInfo info = katachi_cut_info_default();
    if ((st = katachi_cut_info(cut.get(), &info)) != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    QString view_line = QString("katachi: view: %1, %2 x %3 pixels%4; view-projection "
                                "(column-major, katachi's pixels top-left, y down):")
                            .arg(view.orthographic ? "orthographic" : "perspective")
                            .arg(view.viewport[2])
                            .arg(view.viewport[3])
                            .arg(from_xml ? " (from 'View as text')" : "");
    for (double x : view.view_proj) view_line += " " + QString::number(x, 'g', 17);
    outputs.vectors["view_proj"].assign(view.view_proj, view.view_proj + 16);
    outputs.vectors["viewport"].assign(view.viewport, view.viewport + 4);
    outputs.counts["path_count"] = info.path_count;
    outputs.counts["new_face_count"] = info.new_face_count;
    outputs.counts["new_vertex_count"] = info.new_vertex_count;
    outputs.counts["split_face_count"] = info.split_face_count;
    outputs.counts["moved_vertex_count"] = info.moved_vertex_count;
    outputs.numbers["max_move_px"] = info.max_move_px;
    const QString mode_name = options.mode == KATACHI_CUT_MODE_THROUGH_ALL ? "through all"
                                                                           : "visible only";
    if (info.path_count == 0 && info.moved_vertex_count == 0 && info.new_face_count == 0) {
        note(view_line);
        note(QString("katachi: cut by polyline (%1): the stroke meets no face it may cut (%2 "
                     "of %3 stroke points over no such face); the layer is unchanged%4")
                 .arg(mode_name)
                 .arg(info.dropped_off_mesh_count)
                 .arg(stroke.size() / 2)
                 .arg(new_layer ? " and no layer was added" : ""));
        if (cb) cb(100, "katachi: done");
        return true;
    }

    CutResult out;
    KatachiMesh *raw = nullptr;
    st = katachi_cut_mesh(cut.get(), &raw);
    MeshPtr result(raw);
    std::vector<uint32_t> loop_sizes(info.face_count), loops_per_face(info.face_count);
    std::vector<uint32_t> offsets(size_t(info.path_count) + 1), path(info.path_vertex_count);
    std::vector<uint32_t> pieces(info.path_count), closed(info.path_count);
    out.positions.resize(3 * size_t(info.vertex_count));
    out.triangles.resize(info.corner_count);
    out.origin.resize(info.face_count);
    if (st == KATACHI_STATUS_OK)
        st = katachi_mesh_copy_positions(result.get(), out.positions.data(),
                                         out.positions.size());
    if (st == KATACHI_STATUS_OK)
        st = katachi_mesh_copy_faces(result.get(), loop_sizes.data(), loop_sizes.size(),
                                     loops_per_face.data(), loops_per_face.size(),
                                     out.triangles.data(), out.triangles.size());
    if (st == KATACHI_STATUS_OK)
        st = katachi_cut_copy_face_origin(cut.get(), out.origin.data(), out.origin.size());
    if (st == KATACHI_STATUS_OK)
        st = katachi_cut_copy_paths(cut.get(), offsets.data(), offsets.size(), path.data(),
                                    path.size());
    if (st == KATACHI_STATUS_OK)
        st = katachi_cut_copy_path_pieces(cut.get(), pieces.data(), closed.data(),
                                          pieces.size());
    auto vertex_data = [&](const std::vector<double> &values, uint32_t dim,
                           std::vector<double> &dst) {
        if (st != KATACHI_STATUS_OK || values.empty()) return;
        dst.resize(size_t(info.vertex_count) * dim);
        st = katachi_cut_interpolate_vertex_data(cut.get(), values.data(), values.size(), dim,
                                                 dst.data(), dst.size());
    };
    auto corner_data = [&](const std::vector<double> &values, uint32_t dim,
                           std::vector<double> &dst) {
        if (st != KATACHI_STATUS_OK || values.empty()) return;
        dst.resize(size_t(info.corner_count) * dim);
        st = katachi_cut_interpolate_corner_data(cut.get(), values.data(), values.size(), dim,
                                                 dst.data(), dst.size());
    };
    vertex_data(in.vcolor, 4, out.vcolor);
    vertex_data(in.vquality, 1, out.vquality);
    vertex_data(in.vtex, 2, out.vtex);
    corner_data(in.wtex, 2, out.wtex);
    if (st != KATACHI_STATUS_OK) {
        error = katachi_error(st);
        return false;
    }
    for (size_t f = 0; f < loop_sizes.size(); ++f)
        if (loop_sizes[f] != 3 || loops_per_face[f] != 1 || out.origin[f] >= face_count) {
            error = QString("katachi: the cut returned face %1 with %2 corners (origin %3); "
                            "triangles were expected")
                        .arg(f)
                        .arg(loop_sizes[f])
                        .arg(out.origin[f]);
            return false;
        }
    for (uint32_t v : out.triangles)
        if (v >= info.vertex_count) {
            error = QString("katachi: the cut returned a corner at vertex %1 of %2")
                        .arg(v)
                        .arg(info.vertex_count);
            return false;
        }

    // The cut's edges: not faux; the vertices along them selected. Opening the cut gives
    // path vertices copies at the very same places (ids after the split vertices): they are
    // selected too, and count as their originals for the faux edges below.
    std::set<std::pair<uint32_t, uint32_t>> cut_edges;
    std::map<std::tuple<double, double, double>, uint32_t> path_at;
    auto place = [&](uint32_t v) {
        return std::make_tuple(out.positions[3 * size_t(v)], out.positions[3 * size_t(v) + 1],
                               out.positions[3 * size_t(v) + 2]);
    };
    out.selected.assign(info.vertex_count, 0);
    for (uint32_t i = 0; i < info.path_count; ++i) {
        const uint32_t b = offsets[i], e = offsets[i + 1];
        for (uint32_t k = b; k < e; ++k) {
            const uint32_t v = path[k];
            if (v >= info.vertex_count) continue;
            out.selected[v] = 1;
            path_at.emplace(place(v), v);
            const bool last = k + 1 == e;
            if (last && !closed[i]) continue;
            const uint32_t w = last ? path[b] : path[k + 1];
            cut_edges.emplace(std::min(v, w), std::max(v, w));
        }
    }
    std::vector<uint32_t> original(info.vertex_count);
    for (uint32_t v = 0; v < info.vertex_count; ++v) {
        original[v] = v;
        if (!options.open || out.selected[v]) continue;
        const auto at = path_at.find(place(v));
        if (at != path_at.end()) {
            out.selected[v] = 1;
            original[v] = at->second;
        }
    }
    // Faux edges survive where both ends are layer vertices (or their copies), the face the
    // triangle lies in had that edge faux, and the cut does not run along it.
    out.faux.assign(info.face_count, 0);
    bool any_faux = false;
    for (uint32_t f = 0; f < info.face_count; ++f) {
        const CFaceO *from = faces[out.origin[f]];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = original[out.triangles[3 * f + k]];
            const uint32_t b = original[out.triangles[3 * f + (k + 1) % 3]];
            if (a >= vertex_count || b >= vertex_count ||
                cut_edges.count({std::min(a, b), std::max(a, b)}))
                continue;
            for (int j = 0; j < 3; ++j) {
                const uint32_t x = corners[3 * size_t(out.origin[f]) + j];
                const uint32_t y = corners[3 * size_t(out.origin[f]) + (j + 1) % 3];
                if (from->IsF(j) && ((x == a && y == b) || (x == b && y == a))) {
                    out.faux[f] |= uint8_t(1u << k);
                    any_faux = true;
                }
            }
        }
    }
    // Texture indices: layer vertices keep theirs; a new vertex takes that of the first
    // corner of the layer face it first appears in.
    if (in.vert_tex) {
        out.vtex_n.assign(info.vertex_count, -1);
        for (uint32_t v = 0; v < vertex_count; ++v) out.vtex_n[v] = in.vtex_n[v];
        for (uint32_t f = 0; f < info.face_count; ++f)
            for (int k = 0; k < 3; ++k) {
                short &n = out.vtex_n[out.triangles[3 * f + k]];
                if (n < 0) n = in.vtex_n[corners[3 * size_t(out.origin[f])]];
            }
    }

    // 5. Only now touch the document: nothing below can fail.
    if (cb) cb(80, "katachi: writing the result");
    MeshModel *dst = src;
    if (new_layer) {
        dst = md.addNewMesh("", QString("%1 (katachi cut)").arg(src->label()), true);
        dst->cm.Tr = cm.Tr;
        dst->cm.textures = cm.textures;
        dst->cm.normalmaps = cm.normalmaps;
        int mask = 0;
        if (in.vert_color) mask |= MeshModel::MM_VERTCOLOR;
        if (in.vert_quality) mask |= MeshModel::MM_VERTQUALITY;
        if (in.vert_tex) mask |= MeshModel::MM_VERTTEXCOORD;
        if (in.face_color) mask |= MeshModel::MM_FACECOLOR;
        if (in.face_quality) mask |= MeshModel::MM_FACEQUALITY;
        if (in.wedge_tex) mask |= MeshModel::MM_WEDGTEXCOORD;
        if (src->hasDataMask(MeshModel::MM_POLYGONAL) && any_faux)
            mask |= MeshModel::MM_POLYGONAL;
        if (mask != 0) dst->updateDataMask(mask);
    }
    // Face data read from the layer before it is cleared.
    const size_t nf = out.origin.size(), nv = out.positions.size() / 3;
    std::vector<vcg::Color4b> fcolor;
    std::vector<Scalarm> fquality;
    std::vector<uint8_t> fselect;
    for (uint32_t o : out.origin) {
        if (in.face_color) fcolor.push_back(faces[o]->cC());
        if (in.face_quality) fquality.push_back(faces[o]->cQ());
        if (in.face_select) fselect.push_back(faces[o]->IsS() ? 1 : 0);
    }
    std::vector<short> wtex_n;
    if (in.wedge_tex)
        for (uint32_t o : out.origin) wtex_n.push_back(in.wtex_n[o]);
    faces.clear();
    verts.clear();
    if (!new_layer) dst->cm.Clear();
    CMeshO &m = dst->cm;
    auto channel = [](double x) {
        return (unsigned char)(std::lround(std::min(255.0, std::max(0.0, x))));
    };
    auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(m, nv);
    for (size_t i = 0; i < nv; ++i, ++vi) {
        vi->P() = Point3m(Scalarm(out.positions[3 * i]), Scalarm(out.positions[3 * i + 1]),
                          Scalarm(out.positions[3 * i + 2]));
        if (out.selected[i])
            vi->SetS();
        else
            vi->ClearS();
        if (in.vert_color)
            vi->C() = vcg::Color4b(channel(out.vcolor[4 * i]), channel(out.vcolor[4 * i + 1]),
                                   channel(out.vcolor[4 * i + 2]),
                                   channel(out.vcolor[4 * i + 3]));
        if (in.vert_quality) vi->Q() = Scalarm(out.vquality[i]);
        if (in.vert_tex) {
            vi->T().U() = Scalarm(out.vtex[2 * i]);
            vi->T().V() = Scalarm(out.vtex[2 * i + 1]);
            vi->T().N() = out.vtex_n[i];
        }
    }
    auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(m, nf);
    for (size_t f = 0; f < nf; ++f, ++fi) {
        for (int k = 0; k < 3; ++k) {
            fi->V(k) = &m.vert[out.triangles[3 * f + k]];
            if (out.faux[f] & (1u << k))
                fi->SetF(k);
            else
                fi->ClearF(k);
            if (in.wedge_tex) {
                fi->WT(k).U() = Scalarm(out.wtex[6 * f + 2 * k]);
                fi->WT(k).V() = Scalarm(out.wtex[6 * f + 2 * k + 1]);
                fi->WT(k).N() = wtex_n[f];
            }
        }
        if (in.face_color) fi->C() = fcolor[f];
        if (in.face_quality) fi->Q() = fquality[f];
        if (in.face_select && fselect[f])
            fi->SetS();
        else
            fi->ClearS();
    }
    update_box_and_normals(*dst);

    // 6. The report.
    uint32_t selected = 0, closed_paths = 0;
    for (uint8_t s : out.selected) selected += s;
    for (uint32_t c : closed) closed_paths += c ? 1 : 0;
    outputs.counts["closed_path_count"] = closed_paths;
    outputs.counts["selected_vertex_count"] = selected;
    note(view_line);
    note(QString("katachi: cut by polyline (%1%2): %3 -> %4 triangles (%5 new faces, %6 faces "
                 "split), %7 new vertices; %8 cut path(s)%9 through %10 vertices, selected")
             .arg(mode_name)
             .arg(options.open ? ", opened" : "")
             .arg(face_count)
             .arg(nf)
             .arg(info.new_face_count)
             .arg(info.split_face_count)
             .arg(info.new_vertex_count)
             .arg(info.path_count)
             .arg(closed_paths ? QString(" (%1 closed)").arg(closed_paths) : QString())
             .arg(selected));
    note(QString("katachi: %1 vertices moved onto the stroke, the largest by %2 (%3 pixels; "
                 "mean edge %4 = %5 pixels)")
             .arg(info.moved_vertex_count)
             .arg(number(info.max_move_world))
             .arg(number(info.max_move_px))
             .arg(number(info.mean_edge_length_world))
             .arg(number(info.mean_edge_length_px)));
    note(QString("katachi: stroke points dropped: %1 in preprocessing, %2 by the first "
                 "normalization, %3 by the second, %4 over no face to cut (of %5 points, %6 "
                 "piece(s))")
             .arg(info.dropped_preprocessing_count)
             .arg(info.dropped_first_normalization_count)
             .arg(info.dropped_second_normalization_count)
             .arg(info.dropped_off_mesh_count)
             .arg(stroke.size() / 2)
             .arg(info.piece_count));
    if (info.snaps_refused_count || info.clipped_face_count || info.degenerate_face_count ||
        info.rerouted_count || info.unjoined_count || info.ends_moved_to_edges_count)
        note(QString("katachi: %1 snap(s) refused (they would fold a face), %2 stroke end(s) "
                     "moved onto an edge, %3 face(s) crossing the eye plane and %4 degenerate "
                     "face(s) left uncut, %5 stretch(es) rerouted along edges, %6 unjoined")
                 .arg(info.snaps_refused_count)
                 .arg(info.ends_moved_to_edges_count)
                 .arg(info.clipped_face_count)
                 .arg(info.degenerate_face_count)
                 .arg(info.rerouted_count)
                 .arg(info.unjoined_count));
    if (cb) cb(100, "katachi: done");
    return true;
}

bool run(int filter, MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb,
         const Note &note, Outputs &outputs, QString &error) {
    if (filter != SUBDIVIDE && filter != CUT) {
        error = QString("katachi: unknown filter %1").arg(filter);
        return false;
    }
    if (md.mm() == nullptr) {
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
    return filter == CUT ? cut_by_polyline(md, par, cb, note, outputs, error)
                         : subdivide(md, par, cb, note, outputs, error);
}

} // namespace katachi_meshlab
