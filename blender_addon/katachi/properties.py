"""The operators' properties (their redo panels), kept apart from the operators' logic.

Each enum's identifiers map to a katachi constant (``ffi.KATACHI_*``); the defaults are
katachi's, and the UV default is Blender's Subdivision Surface default (Keep Boundaries).
"""

import math

from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
)
from bpy.types import PropertyGroup

from . import ffi

HOLE_METHODS = (
    ("SMOOTH", "Smooth [a]",
     "Bridge each hole to its face's outer loop and subdivide smoothly (seed 001 method [a])"),
    ("SHARP", "Sharp [b]",
     "Keep hole loops sharp: the face stays planar around its holes (seed 001 method [b])"),
)
HOLE_VALUES = {"SMOOTH": ffi.KATACHI_HOLE_METHOD_SMOOTH, "SHARP": ffi.KATACHI_HOLE_METHOD_SHARP}

BOUNDARY_MODES = (
    ("EDGE_ONLY", "Smooth Corners",
     "Boundary edges sharp, boundary corners smoothed (OpenSubdiv edge-only; Blender's 'All')"),
    ("EDGE_AND_CORNER", "Keep Corners",
     "As Smooth Corners, and a boundary vertex with a single face stays put "
     "(OpenSubdiv edge-and-corner; Blender's 'Keep Corners')"),
)
BOUNDARY_VALUES = {
    "EDGE_ONLY": ffi.KATACHI_BOUNDARY_EDGE_ONLY,
    "EDGE_AND_CORNER": ffi.KATACHI_BOUNDARY_EDGE_AND_CORNER,
}

CREASE_METHODS = (
    ("UNIFORM", "Uniform", "Semi-sharp creases lose 1 sharpness per level (OpenSubdiv uniform)"),
    ("CHAIKIN", "Chaikin",
     "Semi-sharp creases averaged with their neighbours along the crease (OpenSubdiv Chaikin)"),
)
CREASE_VALUES = {
    "UNIFORM": ffi.KATACHI_CREASE_METHOD_UNIFORM,
    "CHAIKIN": ffi.KATACHI_CREASE_METHOD_CHAIKIN,
}

UV_MODES = (
    ("SMOOTH_ALL", "All", "UVs smoothed everywhere, seams and corners included"),
    ("PRESERVE_CORNERS", "Keep Corners", "UVs smoothed, UV island corners kept in place"),
    ("PRESERVE_BOUNDARIES", "Keep Boundaries",
     "UVs linear along UV island boundaries (Blender's default)"),
    ("NONE", "None", "UVs interpolated linearly (bilinear)"),
)
UV_VALUES = {
    "SMOOTH_ALL": ffi.KATACHI_FACE_VARYING_SMOOTH,
    "PRESERVE_CORNERS": ffi.KATACHI_FACE_VARYING_LINEAR_CORNERS_ONLY,
    "PRESERVE_BOUNDARIES": ffi.KATACHI_FACE_VARYING_LINEAR_BOUNDARIES,
    "NONE": ffi.KATACHI_FACE_VARYING_LINEAR_ALL,
}


class SubdivideProperties:
    """Mixed into the operator: its settings, shown in the redo panel."""

    levels: IntProperty(
        name="Levels",
        description="Catmull-Clark subdivision levels (each multiplies the face count by about 4)",
        default=1, min=1, max=8, soft_max=4,
    )
    holes: EnumProperty(
        name="Holes", description="How faces with holes are subdivided",
        items=HOLE_METHODS, default="SMOOTH",
    )
    recover_holes: BoolProperty(
        name="Recover Faces with Holes",
        description="First merge coplanar regions (a Boolean's triangles and n-gon fans) back "
        "into faces with holes, so that holes stay round and planar faces stay flat",
        default=False,
    )
    coplanar_angle: FloatProperty(
        name="Coplanar Angle",
        description="Largest angle between faces merged into one face with holes",
        subtype="ANGLE", default=1e-3, min=0.0, max=1.5, soft_max=0.1, precision=4,
    )
    boundary: EnumProperty(
        name="Boundary", description="How open boundaries are subdivided",
        items=BOUNDARY_MODES, default="EDGE_ONLY",
    )
    crease_method: EnumProperty(
        name="Creases", description="How semi-sharp creases (edge crease below 1) fade",
        items=CREASE_METHODS, default="UNIFORM",
    )
    uv_smooth: EnumProperty(
        name="UV Smooth", description="How UV maps are interpolated",
        items=UV_MODES, default="PRESERVE_BOUNDARIES",
    )

    def katachi_options(self, lib):
        """These settings as a ``KatachiSubdivideOptions`` (from the library's defaults)."""
        o = lib.katachi_subdivide_options_default()
        o.levels = self.levels
        o.holes = HOLE_VALUES[self.holes]
        o.boundary = BOUNDARY_VALUES[self.boundary]
        o.crease_method = CREASE_VALUES[self.crease_method]
        o.recover_faces_with_holes = 1 if self.recover_holes else 0
        o.coplanar_angle_tolerance = self.coplanar_angle
        return o

    def draw_properties(self, layout):
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(self, "levels")
        layout.prop(self, "holes")
        layout.prop(self, "recover_holes")
        row = layout.row()
        row.active = self.recover_holes
        row.prop(self, "coplanar_angle")
        layout.prop(self, "boundary")
        layout.prop(self, "crease_method")
        layout.prop(self, "uv_smooth")



# ---------------------------------------------------------------------------- stroke cut

CUT_MODES = (
    ("VISIBLE_ONLY", "Visible Only",
     "Cut only the faces seen from the view: front-facing and not hidden by nearer faces"),
    ("THROUGH_ALL", "Through All",
     "Cut every face under the stroke, back faces and hidden sheets too (each sheet gets "
     "its own cut)"),
)
CUT_MODE_VALUES = {
    "VISIBLE_ONLY": ffi.KATACHI_CUT_MODE_VISIBLE_ONLY,
    "THROUGH_ALL": ffi.KATACHI_CUT_MODE_THROUGH_ALL,
}

CUT_VIEWS = (
    ("VIEW", "3D View", "Project through the 3D Viewport the operator runs in (or the first "
     "one of the screen)"),
    ("CAMERA", "Camera", "Project through a camera (Camera, or the scene camera when empty) "
     "at the scene's render resolution"),
)


class KATACHI_PG_stroke_point(PropertyGroup):
    """One point of a drawn stroke, in pixels from the view's top-left corner, y down."""

    co: FloatVectorProperty(name="Point", size=2, default=(0.0, 0.0))


class CutProperties:
    """Mixed into the cut operators: the cut's settings, shown in the redo panel."""

    mode: EnumProperty(
        name="Cut", description="Which faces under the stroke are cut",
        items=CUT_MODES, default="VISIBLE_ONLY",
    )
    open: BoolProperty(
        name="Open",
        description="Open the cut: the faces on either side of it no longer share its "
        "vertices (a slit, or separate pieces when the cut runs across or around the mesh)",
        default=False,
    )
    keep_polygons: BoolProperty(
        name="Keep Uncut Faces",
        description="Faces the cut does not touch stay as they were (quads and n-gons); "
        "off: the whole mesh comes back as katachi's triangles",
        default=True,
    )
    snap_vertex: FloatProperty(
        name="Snap to Points",
        description="Move a vertex onto a stroke point closer than this many mean edge "
        "lengths on screen (seed 002 §3.2)",
        default=0.3, min=0.0, max=0.5,
    )
    snap_segment: FloatProperty(
        name="Snap to Stroke",
        description="Move a vertex onto the stroke when closer than this many mean edge "
        "lengths on screen (seed 002 §3.2)",
        default=0.3, min=0.0, max=0.5,
    )
    corner_angle: FloatProperty(
        name="Corner Angle",
        description="Where the stroke turns by more than this, the cut has a sharp corner "
        "(seed 002 §3.4)",
        subtype="ANGLE", default=math.radians(60.0), min=0.0, max=math.pi,
    )

    def cut_options(self, lib):
        """These settings as a ``KatachiCutOptions`` (from the library's defaults)."""
        o = lib.katachi_cut_options_default()
        o.mode = CUT_MODE_VALUES[self.mode]
        o.open = 1 if self.open else 0
        o.snap_vertex_ratio = self.snap_vertex
        o.snap_segment_ratio = self.snap_segment
        o.corner_angle_degrees = math.degrees(self.corner_angle)
        return o

    def draw_cut_properties(self, layout):
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(self, "mode")
        layout.prop(self, "open")
        layout.prop(self, "keep_polygons")
        layout.prop(self, "snap_vertex")
        layout.prop(self, "snap_segment")
        layout.prop(self, "corner_angle")
