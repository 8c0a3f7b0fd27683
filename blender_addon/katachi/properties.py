"""The Subdivide operator's properties (its redo panel), kept apart from the operator's logic.

Each enum's identifiers map to a katachi constant (``ffi.KATACHI_*``); the defaults are
katachi's, and the UV default is Blender's Subdivision Surface default (Keep Boundaries).
"""

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

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

