"""Where a cut's stroke comes from and how it is seen, in katachi's terms.

katachi takes a stroke in pixels from the viewport's top-left corner with y down, a
view-projection matrix (column-major, ``clip = M · [x, y, z, 1]``, OpenGL depth) and the
viewport ``x0, y0, width, height``. Blender's region coordinates start at the bottom-left
corner with y up, so a region point ``(x, y)`` is katachi's ``(x, height - y)``.

A :class:`View` is a world-space view-projection matrix and the pixel size of what it
shows: a 3D Viewport's region (``RegionView3D.perspective_matrix``, its window matrix
times its view matrix) or a camera at the scene's render resolution
(``Object.calc_matrix_camera`` times the inverse of the camera's placement). katachi cuts
the mesh in object space, so the object's ``matrix_world`` is folded into the matrix.

Annotations: Blender 3.x keeps them in ``Scene.grease_pencil`` (legacy Grease Pencil data,
``bpy.types.GreasePencil``), Blender 4.3 and later in ``Scene.annotation``
(``bpy.types.Annotation``), with the same layers → active frame → strokes → points (``co``)
shape. A stroke drawn with placement 3D Cursor or Surface holds world positions, projected
here through the view; Blender 3.x also tells a stroke drawn in View placement
(``display_mode == 'SCREEN'``: percentages of the region, y up), which is read as such.
Blender 4.3+ does not tell the two apart from Python: there every stroke is taken as 3D.
"""

from mathutils import Matrix, Vector


class StrokeError(Exception):
    """A stroke or view the cut cannot use (said in the user's terms)."""


class View:
    """A world view-projection ``matrix`` (4 × 4) showing ``width`` × ``height`` pixels."""

    def __init__(self, matrix, width, height, label):
        self.matrix = Matrix(matrix)
        self.width = float(width)
        self.height = float(height)
        self.label = label
        if self.width <= 0 or self.height <= 0:
            raise StrokeError(f"{label} has no size ({width} × {height} pixels)")

    def for_object(self, matrix_world):
        """katachi's ``view_proj`` (16 doubles, column-major) and ``viewport`` for an object
        placed by ``matrix_world``."""
        m = self.matrix @ matrix_world
        return [m[r][c] for c in range(4) for r in range(4)], [0.0, 0.0, self.width, self.height]

    def project(self, co):
        """A world point in katachi pixels (top-left, y down), or None behind the eye."""
        clip = self.matrix @ Vector((co[0], co[1], co[2], 1.0))
        if clip.w <= 0.0:
            return None
        x, y = clip.x / clip.w, clip.y / clip.w
        return (x + 1.0) * 0.5 * self.width, (1.0 - y) * 0.5 * self.height

    def row_major(self):
        return [self.matrix[r][c] for r in range(4) for c in range(4)]


def find_view3d(context):
    """``(region, region_3d)`` of the context's 3D Viewport, or of the first one on the
    screen (scripts, background mode), or ``(None, None)``."""
    area = context.area
    if area is not None and area.type == "VIEW_3D":
        region = context.region
        if region is None or region.type != "WINDOW":
            region = next((r for r in area.regions if r.type == "WINDOW"), None)
        return region, area.spaces.active.region_3d
    screen = context.screen
    if screen is None and context.window is not None:
        screen = context.window.screen
    for area in screen.areas if screen is not None else ():
        if area.type == "VIEW_3D":
            region = next((r for r in area.regions if r.type == "WINDOW"), None)
            if region is not None:
                return region, area.spaces.active.region_3d
    return None, None


def region_view(region, region_3d):
    """The :class:`View` of a 3D Viewport's main region."""
    return View(region_3d.perspective_matrix, region.width, region.height, "the 3D Viewport")


def context_view(context):
    region, rv3d = find_view3d(context)
    if region is None or rv3d is None:
        raise StrokeError("there is no 3D Viewport to project through (use View: Camera)")
    return region_view(region, rv3d)


def camera_view(context, name=""):
    """The :class:`View` of camera object ``name`` (the scene camera when empty) at the
    scene's render resolution and pixel aspect."""
    scene = context.scene
    if name:
        cam = scene.objects.get(name)
        if cam is None:
            raise StrokeError(f"there is no object {name!r} in scene {scene.name!r}")
    else:
        cam = scene.camera
        if cam is None:
            raise StrokeError(f"scene {scene.name!r} has no camera")
    if cam.type != "CAMERA":
        raise StrokeError(f"{cam.name} is a {cam.type.lower()}, not a camera")
    r = scene.render
    width = int(r.resolution_x * r.resolution_percentage / 100)
    height = int(r.resolution_y * r.resolution_percentage / 100)
    depsgraph = context.evaluated_depsgraph_get()
    evaluated = cam.evaluated_get(depsgraph)
    projection = evaluated.calc_matrix_camera(
        depsgraph, x=width, y=height, scale_x=r.pixel_aspect_x, scale_y=r.pixel_aspect_y
    )
    loc, rot, _ = evaluated.matrix_world.decompose()  # a camera's scale does not count
    placement = Matrix.Translation(loc) @ rot.to_matrix().to_4x4()
    return View(projection @ placement.inverted(), width, height, f"camera {cam.name}")


def stored_view(row_major, size):
    """A :class:`View` from an operator's stored matrix (16 floats, row after row) and size."""
    m = Matrix([row_major[4 * r:4 * r + 4] for r in range(4)])
    return View(m, size[0], size[1], "the stored view")


# ---------------------------------------------------------------------------- annotations


def annotation_data(scene):
    """The scene's annotation data-block (3.x: ``grease_pencil``; 4.3+: ``annotation``)."""
    if hasattr(scene, "annotation"):
        return scene.annotation
    return getattr(scene, "grease_pencil", None)


def _active_layer(layers):
    layer = getattr(layers, "active", None)
    if layer is not None:
        return layer
    i = getattr(layers, "active_index", -1)
    return layers[i] if 0 <= i < len(layers) else None


def annotation_stroke(scene, index=-1):
    """The points of stroke ``index`` (-1: the last drawn) of the active annotation layer at
    the current frame: ``(points, space, description)``, ``points`` a list of ``co``
    triples and ``space`` ``'3DSPACE'`` or ``'SCREEN'``."""
    data = annotation_data(scene)
    if data is None:
        raise StrokeError(
            f"scene {scene.name!r} has no annotations: draw a stroke with the Annotate tool"
        )
    layer = _active_layer(data.layers)
    if layer is None:
        raise StrokeError(f"annotations {data.name!r} have no active layer")
    frame = layer.active_frame
    if frame is None or len(frame.strokes) == 0:
        raise StrokeError(
            f"annotation layer {layer.info!r} has no stroke at frame {scene.frame_current}"
        )
    n = len(frame.strokes)
    if not -n <= index < n:
        raise StrokeError(
            f"annotation layer {layer.info!r} has {n} strokes at frame "
            f"{scene.frame_current}, so stroke index {index} does not exist"
        )
    stroke = frame.strokes[index]
    space = getattr(stroke, "display_mode", "3DSPACE")
    if space not in ("3DSPACE", "SCREEN"):
        raise StrokeError(
            f"annotation stroke {index} of layer {layer.info!r} was drawn in a 2D editor "
            f"({space}), not in the 3D Viewport"
        )
    co = [0.0] * (3 * len(stroke.points))
    stroke.points.foreach_get("co", co)
    points = [tuple(co[3 * i:3 * i + 3]) for i in range(len(stroke.points))]
    return points, space, f"annotation stroke {index} of layer {layer.info!r}"


def annotation_pixels(points, space, view, what="the annotation stroke"):
    """``points`` (from :func:`annotation_stroke`) as katachi pixels through ``view``: a
    flat list ``x0, y0, x1, y1, …``."""
    out = []
    if space == "SCREEN":  # percentages of the view, from the bottom-left corner
        for x, y, _ in points:
            out.append(x / 100.0 * view.width)
            out.append((1.0 - y / 100.0) * view.height)
        return out
    for i, co in enumerate(points):
        p = view.project(co)
        if p is None:
            raise StrokeError(f"point {i} of {what} is behind {view.label}")
        out.extend(p)
    return out


def region_pixels(points, region_height):
    """Region points (bottom-left origin, y up) as katachi pixels, flat."""
    out = []
    for x, y in points:
        out.append(float(x))
        out.append(float(region_height) - float(y))
    return out
