// katachi MeshLab plugin: the view and the stroke of "katachi: Cut by polyline" (see
// cut_view.h for the conventions).
//
// License: MIT OR Apache-2.0.

#include "cut_view.h"

#include <QApplication>
#include <QDomDocument>
#include <QDomElement>
#include <QMdiArea>
#include <QMdiSubWindow>
#include <QMetaObject>
#include <QRegularExpression>
#include <QStringList>
#include <QWidget>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace katachi_meshlab {

namespace {

bool finite(double x) { return std::isfinite(x); }

/// m = a · b for row-major 4 × 4 arrays.
void multiply(const double a[4][4], const double b[4][4], double m[4][4]) {
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) s += a[r][k] * b[k][c];
            m[r][c] = s;
        }
}

const char *const kChooseView =
    "choose a view (in the filter's dialog: Get shot with Current Trackball), or give "
    "MeshLab's view text in 'View as text' (in scripts)";

} // namespace

bool view_from_shot(const vcg::Shotd &shot, const vcg::Matrix44d &model, const double lo[3],
                    const double hi[3], CutView &view, QString &error) {
    const vcg::Camera<double> &cam = shot.Intrinsics;
    const int width = cam.ViewportPx[0], height = cam.ViewportPx[1];
    if (width <= 0 || height <= 0) {
        error = QString("katachi: the view has no viewport (%1 × %2 pixels): %3")
                    .arg(width)
                    .arg(height)
                    .arg(kChooseView);
        return false;
    }
    const double psx = cam.PixelSizeMm[0], psy = cam.PixelSizeMm[1];
    if (!(finite(psx) && finite(psy) && psx > 0.0 && psy > 0.0)) {
        error = QString("katachi: the view's pixel size is %1 × %2 mm; it must be positive: %3")
                    .arg(psx)
                    .arg(psy)
                    .arg(kChooseView);
        return false;
    }
    const double cx = cam.CenterPx[0], cy = cam.CenterPx[1];
    if (!(finite(cx) && finite(cy))) {
        error = QString("katachi: the view's centre (%1, %2) is not finite").arg(cx).arg(cy);
        return false;
    }
    const bool ortho = cam.cameraType == vcg::Camera<double>::ORTHO;
    const double focal = cam.FocalMm;
    if (!ortho && !(finite(focal) && focal > 0.0)) {
        error = QString("katachi: the view's focal length is %1 mm; a perspective view needs a "
                        "positive one")
                    .arg(focal);
        return false;
    }
    // vcg::Camera::Project distorts when k[0] != 0; a matrix cannot.
    if (!ortho && cam.k[0] != 0.0) {
        error = QString("katachi: the view has radial lens distortion (k1 = %1), which a "
                        "view-projection matrix cannot express; use an undistorted camera")
                    .arg(cam.k[0]);
        return false;
    }

    // E: layer coordinates -> eye coordinates = Rot · T(−viewpoint) · model (homogeneous).
    const vcg::Matrix44d rot = shot.Extrinsics.Rot();
    const vcg::Point3d tra = shot.Extrinsics.Tra();
    double rt[4][4], m[4][4], e[4][4];
    for (int r = 0; r < 4; ++r) {
        double t = rot.ElementAt(r, 3);
        for (int c = 0; c < 3; ++c) {
            rt[r][c] = rot.ElementAt(r, c);
            t -= rot.ElementAt(r, c) * tra[c];
        }
        rt[r][3] = t;
        for (int c = 0; c < 4; ++c) m[r][c] = model.ElementAt(r, c);
    }
    multiply(rt, m, e);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            if (!finite(e[r][c])) {
                error = QString("katachi: the view's rotation or viewpoint, or the layer's "
                                "transform, has a non-finite entry");
                return false;
            }

    // Distances along the view direction of the box's corners (d = −e.z / e.w).
    double dmin = HUGE_VAL, dmax = -HUGE_VAL;
    for (int i = 0; i < 8; ++i) {
        const double p[4] = {(i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1],
                             (i & 4) ? hi[2] : lo[2], 1.0};
        double ez = 0.0, ew = 0.0;
        for (int k = 0; k < 4; ++k) {
            ez += e[2][k] * p[k];
            ew += e[3][k] * p[k];
        }
        if (ew == 0.0 || !finite(ez) || !finite(ew)) continue;
        const double d = -ez / ew;
        dmin = std::min(dmin, d);
        dmax = std::max(dmax, d);
    }
    if (!(dmin <= dmax)) dmin = dmax = 1.0;

    // P: eye coordinates -> clip coordinates (rows act on (e.x, e.y, e.z, e.w)).
    double p[4][4] = {};
    const double sx = 2.0 / (psx * width), sy = 2.0 / (psy * height);
    const double ox = 2.0 * cx / width - 1.0, oy = 2.0 * cy / height - 1.0;
    if (ortho) {
        // pixel = c.xy / PixelSizeMm + CenterPx; depth linear in the distance.
        double pad = std::max(0.5 * (dmax - dmin),
                              1e-3 * std::max(std::fabs(dmin), std::fabs(dmax)));
        if (!(pad > 0.0)) pad = 1.0;
        const double n = dmin - pad, f = dmax + pad;
        p[0][0] = sx;
        p[0][3] = ox;
        p[1][1] = sy;
        p[1][3] = oy;
        p[2][2] = -2.0 / (f - n);
        p[2][3] = -(f + n) / (f - n);
        p[3][3] = 1.0;
    } else {
        // pixel = FocalMm · c.xy / (c.z · PixelSizeMm) + CenterPx with c.z = −e.z = clip.w;
        // depth as OpenGL's glFrustum, planes around the box (only the order matters).
        double f = 2.0 * dmax, n;
        if (!(f > 0.0)) f = 1.0;
        n = dmin > 0.0 ? 0.5 * dmin : 1e-4 * f;
        n = std::min(n, 0.5 * f);
        p[0][0] = focal * sx;
        p[0][2] = -ox;
        p[1][1] = focal * sy;
        p[1][2] = -oy;
        p[2][2] = -(f + n) / (f - n);
        p[2][3] = -2.0 * f * n / (f - n);
        p[3][2] = -1.0;
    }
    double vp[4][4];
    multiply(p, e, vp);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) view.view_proj[4 * c + r] = vp[r][c];
    view.viewport[0] = 0.0;
    view.viewport[1] = 0.0;
    view.viewport[2] = double(width);
    view.viewport[3] = double(height);
    view.orthographic = ortho;
    return true;
}

bool parse_stroke(const QString &text, std::vector<double> &xy, QString &error) {
    xy.clear();
    static const QRegularExpression separators("[\\s,;]+");
    const QStringList tokens = text.split(separators, Qt::SkipEmptyParts);
    for (int i = 0; i < tokens.size(); ++i) {
        bool ok = false;
        const double v = tokens[i].toDouble(&ok);
        if (!ok) {
            error = QString("katachi: stroke: '%1' (number %2) is not a number; give x y pairs "
                            "such as '10 20; 30 40'")
                        .arg(tokens[i])
                        .arg(i + 1);
            return false;
        }
        xy.push_back(v);
    }
    if (xy.size() % 2 != 0) {
        error = QString("katachi: stroke: %1 numbers, an odd count; give x y pairs such as "
                        "'10 20; 30 40'")
                    .arg(xy.size());
        return false;
    }
    return true;
}

void stroke_to_katachi(std::vector<double> &xy, double height) {
    for (size_t i = 1; i < xy.size(); i += 2) xy[i] = height - xy[i];
}

namespace {

/// The numbers of attribute `name` (separated by white space); false with `error` set when
/// it is missing, has fewer than `count` numbers, or one is not a finite number.
bool attribute_numbers(const QDomElement &e, const char *name, int count, bool required,
                       std::vector<double> &out, QString &error) {
    out.clear();
    if (!e.hasAttribute(name)) {
        if (!required) return true;
        error = QString("katachi: the camera XML's VCGCamera has no %1 attribute").arg(name);
        return false;
    }
    const QStringList parts = e.attribute(name).split(QRegularExpression("\\s+"),
                                                      Qt::SkipEmptyParts);
    for (const QString &s : parts) {
        bool ok = false;
        const double v = s.toDouble(&ok);
        if (!ok || !std::isfinite(v)) {
            error = QString("katachi: the camera XML's %1 holds '%2', not a finite number")
                        .arg(name)
                        .arg(s);
            return false;
        }
        out.push_back(v);
    }
    if (int(out.size()) < count) {
        error = QString("katachi: the camera XML's %1 has %2 number(s); it needs %3")
                    .arg(name)
                    .arg(out.size())
                    .arg(count);
        return false;
    }
    return true;
}

} // namespace

bool parse_camera_xml(const QString &text, Shotm &shot, QString &error) {
    QDomDocument doc;
    QString msg;
    int line = 0, column = 0;
    if (!doc.setContent(text.trimmed(), &msg, &line, &column)) {
        error = QString("katachi: the camera XML does not parse: %1 (line %2, column %3)")
                    .arg(msg)
                    .arg(line)
                    .arg(column);
        return false;
    }
    QDomElement cam = doc.documentElement();
    if (cam.tagName() != "VCGCamera")
        cam = doc.elementsByTagName("VCGCamera").item(0).toElement();
    if (cam.isNull()) {
        error = "katachi: the camera XML holds no <VCGCamera> element (copy the view with "
                "MeshLab's Windows > Copy shot)";
        return false;
    }
    if (cam.attribute("BinaryData", "0").trimmed() == "1") {
        error = "katachi: the camera XML is in the binary form (BinaryData=\"1\"); give the "
                "text form";
        return false;
    }
    std::vector<double> tra, rot, viewport, center, pixel, focal, lens, type;
    if (!attribute_numbers(cam, "TranslationVector", 3, true, tra, error) ||
        !attribute_numbers(cam, "RotationMatrix", 16, true, rot, error) ||
        !attribute_numbers(cam, "ViewportPx", 2, true, viewport, error) ||
        !attribute_numbers(cam, "CenterPx", 2, true, center, error) ||
        !attribute_numbers(cam, "PixelSizeMm", 2, true, pixel, error) ||
        !attribute_numbers(cam, "FocalMm", 1, true, focal, error) ||
        !attribute_numbers(cam, "LensDistortion", 2, false, lens, error) ||
        !attribute_numbers(cam, "CameraType", 1, false, type, error))
        return false;
    for (double v : viewport)
        if (v != std::floor(v) || std::fabs(v) > 1e9) {
            error = QString("katachi: the camera XML's ViewportPx holds %1, not a whole "
                            "number of pixels")
                        .arg(v);
            return false;
        }
    // vcg's camera types: 0 perspective, 1 orthographic, 2 isometric, 3 cavalier.
    const double camera_type = type.empty() ? 0.0 : type[0];
    if (!(camera_type == 0.0 || camera_type == 1.0 || camera_type == 2.0 || camera_type == 3.0)) {
        error = QString("katachi: the camera XML's CameraType is %1; vcg knows 0 (perspective), "
                        "1 (orthographic), 2 (isometric) and 3 (cavalier)")
                    .arg(camera_type);
        return false;
    }
    // The meaning of each attribute is vcg's (wrap/qt/shot_qt.h, ReadShotFromQDomNode): the
    // translation vector is minus the viewpoint, the rotation matrix is row-major.
    Shotm s;
    s.Extrinsics.SetTra(Point3m(Scalarm(-tra[0]), Scalarm(-tra[1]), Scalarm(-tra[2])));
    vcg::Matrix44<Scalarm> r;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) r[y][x] = Scalarm(rot[size_t(x + 4 * y)]);
    s.Extrinsics.SetRot(r);
    vcg::Camera<Scalarm> &c = s.Intrinsics;
    c.cameraType = static_cast<decltype(c.cameraType)>(int(camera_type));
    c.FocalMm = Scalarm(focal[0]);
    c.ViewportPx = vcg::Point2<int>(int(viewport[0]), int(viewport[1]));
    c.CenterPx = vcg::Point2<Scalarm>(Scalarm(center[0]), Scalarm(center[1]));
    c.PixelSizeMm = vcg::Point2<Scalarm>(Scalarm(pixel[0]), Scalarm(pixel[1]));
    c.k[0] = lens.empty() ? 0 : Scalarm(lens[0]);
    c.k[1] = lens.empty() ? 0 : Scalarm(lens[1]);
    shot = s;
    return true;
}

void ShotReceiver::takeShot(QString name, Shotm shot) {
    if (name != tag_) return;
    shot_ = shot;
    received_ = true;
}

namespace {

bool is_glarea(const QObject *o) {
    return o != nullptr && std::strcmp(o->metaObject()->className(), "GLArea") == 0;
}

/// MeshLab's current 3D view: in the MDI area's current sub-window, the view that last had
/// the focus, else its first view; without an MDI area, the only view.
QWidget *current_glarea() {
    const QWidgetList all = QApplication::allWidgets();
    std::vector<QWidget *> areas;
    for (QWidget *w : all)
        if (is_glarea(w)) areas.push_back(w);
    if (areas.empty()) return nullptr;
    for (QWidget *w : all) {
        auto *mdi = qobject_cast<QMdiArea *>(w);
        if (mdi == nullptr) continue;
        QMdiSubWindow *sub = mdi->currentSubWindow();
        if (sub == nullptr) continue;
        QWidget *focus = sub->widget() ? sub->widget()->focusWidget() : nullptr;
        QWidget *first = nullptr;
        for (QWidget *a : areas)
            if (sub->isAncestorOf(a)) {
                if (a == focus) return a;
                if (first == nullptr) first = a;
            }
        if (first != nullptr) return first;
    }
    return areas.size() == 1 ? areas.front() : nullptr;
}

} // namespace

bool current_view_shot(Shotm &shot) {
    QWidget *area = current_glarea();
    if (area == nullptr) return false;
    ShotReceiver receiver("katachi: current view");
    const QMetaObject::Connection link =
        QObject::connect(area, SIGNAL(transmitShot(QString, Shotm)), &receiver,
                         SLOT(takeShot(QString, Shotm)), Qt::DirectConnection);
    if (!link) return false;
    const bool asked = QMetaObject::invokeMethod(area, "sendViewerShot", Qt::DirectConnection,
                                                 Q_ARG(QString, "katachi: current view"));
    QObject::disconnect(link);
    if (!asked || !receiver.received()) return false;
    shot = receiver.shot();
    return true;
}

} // namespace katachi_meshlab
