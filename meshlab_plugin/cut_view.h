// katachi MeshLab plugin: the view and the stroke of "katachi: Cut by polyline", in katachi's
// conventions.
//
// MeshLab describes a view as a vcg::Shot: intrinsics (viewport in pixels, focal length and
// pixel size in mm, the principal point in pixels, perspective or orthographic) and
// extrinsics (a rotation whose rows are the camera axes, and the viewpoint). vcg projects a
// world point p to viewport pixels with Shot::Project:
//
//   e = Rot · (p − viewpoint)           (eye coordinates: x right, y up, looking down −z)
//   c = (e.x, e.y, −e.z)                (c.z > 0 in front of the eye)
//   q = FocalMm · c.xy / c.z            (perspective; orthographic: q = c.xy)
//   pixel = q / PixelSizeMm + CenterPx  (origin at the viewport's BOTTOM-left, y UP)
//
// katachi wants a column-major OpenGL-style view-projection matrix (clip = VP · [p, 1], in
// front iff clip.w > 0) and pixels with the origin at the TOP-left, y down. With the viewport
// [0, 0, W, H] the matrix below reproduces Shot::Project exactly (up to rounding), and a
// vcg pixel (u, v) is katachi's (u, H − v). Depth (which katachi uses only to order faces
// along a ray) comes from near and far planes fitted around the layer's bounding box.
//
// No geometry is computed here beyond this change of conventions; the harness checks it
// against vcg's own Shot::Project.
//
// License: MIT OR Apache-2.0.

#ifndef KATACHI_MESHLAB_CUT_VIEW_H
#define KATACHI_MESHLAB_CUT_VIEW_H

#include "meshlab_api.h"

#include <QObject>
#include <QString>

#include <vcg/math/matrix44.h>
#include <vcg/math/shot.h>

#include <vector>

namespace katachi_meshlab {

/// A view in katachi's terms, as katachi_cut_by_stroke takes it.
struct CutView {
    /// clip = view_proj · [x, y, z, 1], column-major (element (row r, column c) at 4c + r).
    double view_proj[16];
    /// x0, y0, width, height, in pixels, origin top-left, y down: [0, 0, W, H].
    double viewport[4];
    /// Whether the shot is orthographic (vcg::Camera::ORTHO); every other camera type
    /// projects as a perspective one, as in vcg::Camera::Project.
    bool orthographic;
};

/// Converts `shot` into katachi's view of a layer whose points are placed in the world by
/// `model` (MeshLab's per-layer transform `cm.Tr`: world = model · p) and whose positions
/// span the box [lo, hi] (layer coordinates; it sets the near and far planes). Returns false
/// with `error` set when the shot cannot be one (no viewport, a pixel size or focal length
/// that is not positive, non-finite entries, lens distortion that no matrix can express).
bool view_from_shot(const vcg::Shotd &shot, const vcg::Matrix44d &model, const double lo[3],
                    const double hi[3], CutView &view, QString &error);

/// Parses the stroke parameter: numbers separated by spaces, commas, semicolons or line
/// breaks, taken in pairs as x y (C locale: '.' is the decimal point; "nan" and "inf" are
/// numbers, and katachi refuses them with its own message). Returns false with `error` set
/// when a token is not a number or the count is odd.
bool parse_stroke(const QString &text, std::vector<double> &xy, QString &error);

/// Turns stroke points in vcg's viewport convention (origin bottom-left, y up) into
/// katachi's (origin top-left, y down) for a viewport `height` pixels high: y ← height − y.
void stroke_to_katachi(std::vector<double> &xy, double height);

/// Reads a shot from MeshLab's camera XML: the text of Windows ▸ Copy shot (a ViewState
/// document), a MeshLab project's <VCGCamera …/> element, or any XML holding one; the first
/// VCGCamera element is used. Every attribute is checked before vcg reads it; the binary
/// form (BinaryData="1") is refused. Returns false with `error` set on failure.
bool parse_camera_xml(const QString &text, Shotm &shot, QString &error);

/// The shot of MeshLab's current 3D view, when the plugin runs inside MeshLab's GUI: the
/// view (a GLArea) in the MDI area's current window that last had the focus, or the only
/// one there is. It is asked through Qt's meta-object system, as MeshLab's own shot widget
/// does (slot sendViewerShot(QString), answered by signal transmitShot(QString, Shotm)).
/// Returns false when there is no such view (meshlabserver, a test program).
bool current_view_shot(Shotm &shot);

/// Receives GLArea::transmitShot. Internal to current_view_shot; public for moc.
class ShotReceiver : public QObject
{
    Q_OBJECT
public:
    explicit ShotReceiver(const QString &tag) : tag_(tag) {}
    bool received() const { return received_; }
    const Shotm &shot() const { return shot_; }

public slots:
    // The parameter type is spelled Shotm, as in GLArea's signal, so that Qt's string-based
    // connection matches the two signatures.
    void takeShot(QString name, Shotm shot);

private:
    QString tag_;
    bool received_ = false;
    Shotm shot_;
};

} // namespace katachi_meshlab

#endif
