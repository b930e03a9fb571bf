"""Subdiv Interpolate: a Blender extension on the Python package ``subdiv``.

The operator ``object.subdiv_interpolate`` (Object ▸ Subdiv Interpolate) turns the active mesh
object into a Catmull-Clark control cage whose limit surface passes through the mesh's vertices,
and gives the cage a Subdivision Surface modifier with the limit surface on, so that Blender
shows the interpolating surface at once.

What Blender's modifier computes, and so what the library is asked for
-----------------------------------------------------------------------
Blender evaluates its Subdivision Surface modifier with OpenSubdiv. Reading Blender's converter
(``intern/opensubdiv/internal/topology/topology_refiner_factory.cc``,
``blenkernel/intern/subdiv.cc``), the surface it shows is OpenSubdiv's Catmull-Clark surface
with:

- edge sharpness 10·c² of the ``crease_edge`` attribute c, vertex sharpness 10·c² of
  ``crease_vert``, the uniform crease rule;
- a vertex with exactly two edges gets, on top, the smaller sharpness of its two edges (a
  Blender rule, not OpenSubdiv's: a plane with creased borders keeps sharp corners); a vertex of
  a loose edge is infinitely sharp;
- ``boundary_smooth`` 'ALL' → OpenSubdiv's boundary "edge only" (our ``edge-only``),
  'PRESERVE_CORNERS' → "edge and corner" (our ``edge-and-corner``);
- ``uv_smooth`` → OpenSubdiv's face-varying linear interpolation (``UV_SMOOTH`` below).

The add-on hands the library exactly that surface (the tags with Blender's two rules applied,
the boundary option) and writes the cage's tags back so that Blender's rules give the library's
surface again (``_written_vertex_sharpness``).

Data in and out
---------------
Positions, faces of any size (CSR), edge and vertex creases, UV maps, material indices and smooth
shading are read and written with ``foreach_get``/``foreach_set`` on NumPy arrays. ``cheng``'s
cage has the input's topology and vertex order: it is a copy of the mesh (UV maps, materials,
attributes, edge order unchanged) with new positions. ``fair``'s cage is the input refined once;
its faces, tags and first UV map come from the library, the other UV maps are refined by
``subdiv.subdivide`` with the same options, and each child face takes its parent's material and
shading.

The library call runs in a worker thread (it releases the GIL); the main thread meanwhile moves
Blender's progress indicator from the solver's residuals (``subdiv.interpolate(progress=...)``).
Nothing is changed before the library succeeds: on an error the operator reports the library's
message and returns ``{'CANCELLED'}`` with the mesh untouched; on success it is one undo step.
"""

import math
import threading
import warnings

import bpy
import numpy as np

# The Subdivision Surface modifier's ``boundary_smooth`` → the library's ``boundary``
# (Blender: BKE_subdiv_vtx_boundary_interpolation_from_subsurf).
BOUNDARY_SMOOTH = {"ALL": "edge-only", "PRESERVE_CORNERS": "edge-and-corner"}

# ``uv_smooth`` → the library's ``fvar`` (Blender: BKE_subdiv_fvar_interpolation_from_uv_smooth,
# then OpenSubdiv's Sdc::Options::FVarLinearInterpolation, whose names ours follow).
UV_SMOOTH = {
    "NONE": "linear-all",  # FVAR_LINEAR_ALL
    "PRESERVE_CORNERS": "linear-corners-only",  # FVAR_LINEAR_CORNERS_ONLY
    "PRESERVE_CORNERS_AND_JUNCTIONS": "linear-corners-plus1",  # FVAR_LINEAR_CORNERS_PLUS1
    "PRESERVE_CORNERS_JUNCTIONS_AND_CONCAVE": "linear-corners-plus2",  # FVAR_LINEAR_CORNERS_PLUS2
    "PRESERVE_BOUNDARIES": "linear-boundaries",  # FVAR_LINEAR_BOUNDARIES
    "SMOOTH_ALL": "linear-none",  # FVAR_LINEAR_NONE
}

# OpenSubdiv's infinite sharpness; Blender's crease 1.
INFINITE = 10.0

# Blender ignores edge sharpness below this (topology_refiner_factory.cc).
SHARPNESS_EPSILON = 1e-6


def crease_to_sharpness(c):
    """Blender's crease c ∈ [0, 1] → OpenSubdiv sharpness 10·c² (BKE_subdiv_crease_to_sharpness)."""
    c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
    return INFINITE * c * c


def sharpness_to_crease(s):
    """The inverse: c = √(s/10), clamped to [0, 1] (sharpness ≥ 10 is crease 1)."""
    return np.sqrt(np.clip(np.asarray(s, dtype=np.float64) / INFINITE, 0.0, 1.0))


# ---------------------------------------------------------------------------------------------
# Reading a Blender mesh
# ---------------------------------------------------------------------------------------------


class MeshData:
    """A Blender mesh as NumPy arrays (the fields below), read with ``foreach_get``."""

    def __init__(self, mesh):
        n, n_edges = len(mesh.vertices), len(mesh.edges)
        n_faces, n_corners = len(mesh.polygons), len(mesh.loops)
        co = np.empty(3 * n, dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        #: (n, 3) float64 positions.
        self.positions = co.reshape(n, 3).astype(np.float64)
        starts = np.empty(n_faces, dtype=np.int32)
        mesh.polygons.foreach_get("loop_start", starts)
        sizes = np.empty(n_faces, dtype=np.int32)
        mesh.polygons.foreach_get("loop_total", sizes)
        #: Face f is ``corner_vertices[offsets[f]:offsets[f + 1]]`` (Blender keeps a face's
        #: corners contiguous and the faces in corner order).
        self.offsets = np.append(starts, n_corners).astype(np.int64)
        self.sizes = sizes
        self.corner_vertices = np.empty(n_corners, dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", self.corner_vertices)
        corner_edges = np.empty(n_corners, dtype=np.int32)
        mesh.loops.foreach_get("edge_index", corner_edges)
        edges = np.empty(2 * n_edges, dtype=np.int32)
        mesh.edges.foreach_get("vertices", edges)
        #: (e, 2) vertex pairs of the edges.
        self.edges = edges.reshape(n_edges, 2)
        #: Edges of no face (Blender's loose edges).
        self.loose_edges = np.bincount(corner_edges, minlength=n_edges) == 0
        self.material_index = np.empty(n_faces, dtype=np.int32)
        mesh.polygons.foreach_get("material_index", self.material_index)
        self.use_smooth = np.empty(n_faces, dtype=bool)
        mesh.polygons.foreach_get("use_smooth", self.use_smooth)
        #: Edge and vertex creases c ∈ [0, 1] (zeros without the attributes).
        self.edge_crease = float_attribute(mesh, "crease_edge", "EDGE", n_edges)
        self.vertex_crease = float_attribute(mesh, "crease_vert", "POINT", n)
        #: Every UV map: name → (corners, 2) float32 values, one per face corner.
        self.uv_maps = {}
        for layer in mesh.uv_layers:
            uv = np.empty(2 * n_corners, dtype=np.float32)
            layer.uv.foreach_get("vector", uv)
            self.uv_maps[layer.name] = uv.reshape(n_corners, 2)

    def faces(self):
        """The faces for :class:`subdiv.Mesh`: ``(m, k)`` when all have k corners, else CSR."""
        if len(self.sizes) and np.all(self.sizes == self.sizes[0]):
            return self.corner_vertices.astype(np.int64).reshape(len(self.sizes), int(self.sizes[0]))
        return None

    def sharpness(self):
        """The edge and vertex sharpness of the surface Blender's modifier shows
        (see the module doc): ``(edge_sharpness (e,), vertex_sharpness (n,))``."""
        n = len(self.positions)
        edge = crease_to_sharpness(self.edge_crease)
        edge[edge < SHARPNESS_EPSILON] = 0.0
        edge[self.loose_edges] = 0.0
        vertex = crease_to_sharpness(self.vertex_crease)
        # A vertex of two (face) edges: plus the smaller sharpness of the two.
        face_edges = self.edges[~self.loose_edges]
        two = np.bincount(face_edges.ravel(), minlength=n) == 2
        smaller = smallest_incident(face_edges, edge[~self.loose_edges], n)
        vertex[two] = np.minimum(vertex[two] + smaller[two], INFINITE)
        # A vertex of a loose edge: infinitely sharp.
        vertex[np.unique(self.edges[self.loose_edges])] = INFINITE
        return edge, vertex


def float_attribute(mesh, name, domain, size):
    """The float attribute ``name`` on ``domain`` as a float64 array, zeros when absent."""
    values = np.zeros(size, dtype=np.float32)
    attribute = mesh.attributes.get(name)
    if attribute is not None and attribute.domain == domain and attribute.data_type == "FLOAT":
        attribute.data.foreach_get("value", values)
    return values.astype(np.float64)


def smallest_incident(edges, values, n):
    """Per vertex, the smallest value of its edges (inf for a vertex of none)."""
    smallest = np.full(n, np.inf)
    np.minimum.at(smallest, edges[:, 0], values)
    np.minimum.at(smallest, edges[:, 1], values)
    return smallest


def weld_uvs(corner_vertices, uv):
    """A per-corner UV map as a face-varying channel ``(values (p, 2), index per corner)``:
    corners of one vertex with bit-equal UVs share a value (a seam where they differ)."""
    keys = np.empty(len(uv), dtype=[("v", np.int32), ("u", np.float32), ("w", np.float32)])
    keys["v"], keys["u"], keys["w"] = corner_vertices, uv[:, 0], uv[:, 1]
    _, first, index = np.unique(keys, return_index=True, return_inverse=True)
    return uv[first].astype(np.float64), index.astype(np.int64).ravel()


def library_mesh(subdiv, data, use_creases, uvs=None):
    """The :class:`subdiv.Mesh` of ``data``: with Blender's effective tags when
    ``use_creases``, with the UV channel ``uvs`` when given."""
    tags = None
    if use_creases:
        edge, vertex = data.sharpness()
        sharp = np.flatnonzero(edge > 0)
        corners = np.flatnonzero(vertex > 0)
        if len(sharp) or len(corners):
            tags = {
                "creases": list(zip(data.edges[sharp, 0].tolist(), data.edges[sharp, 1].tolist(), edge[sharp].tolist())),
                "corners": list(zip(corners.tolist(), vertex[corners].tolist())),
            }
    faces = data.faces()
    if faces is not None:
        return subdiv.Mesh(data.positions, faces, tags=tags, uvs=uvs)
    return subdiv.Mesh.from_csr(data.positions, data.offsets, data.corner_vertices.astype(np.int64), tags=tags, uvs=uvs)


# ---------------------------------------------------------------------------------------------
# Writing the cage
# ---------------------------------------------------------------------------------------------


def edge_indices(edges, n, a, b):
    """The indices in ``edges`` ((e, 2) vertex pairs of a mesh of ``n`` vertices) of the edges
    (a[i], b[i]), either orientation; -1 where there is none."""
    keys = np.minimum(edges[:, 0], edges[:, 1]).astype(np.int64) * n + np.maximum(edges[:, 0], edges[:, 1])
    order = np.argsort(keys)
    sorted_keys = keys[order]
    a, b = np.asarray(a, dtype=np.int64), np.asarray(b, dtype=np.int64)
    wanted = np.minimum(a, b) * n + np.maximum(a, b)
    if len(keys) == 0:
        return np.full(len(wanted), -1)
    at = np.minimum(np.searchsorted(sorted_keys, wanted), len(keys) - 1)
    return np.where(sorted_keys[at] == wanted, order[at], -1)


def set_float_attribute(mesh, name, domain, values):
    """Writes ``values`` to the float attribute ``name`` (created when absent)."""
    attribute = mesh.attributes.get(name)
    if attribute is not None and (attribute.domain != domain or attribute.data_type != "FLOAT"):
        mesh.attributes.remove(attribute)
        attribute = None
    if attribute is None:
        attribute = mesh.attributes.new(name, "FLOAT", domain)
    attribute.data.foreach_set("value", np.asarray(values, dtype=np.float32))


def write_creases(mesh, tags):
    """The cage's tags as Blender creases (c = √(s/10)), such that Blender's rules (the module
    doc) give back the library's sharpness; no attribute is created for a cage without tags."""
    n, n_edges = len(mesh.vertices), len(mesh.edges)
    edges = np.empty(2 * n_edges, dtype=np.int32)
    mesh.edges.foreach_get("vertices", edges)
    edges = edges.reshape(n_edges, 2)
    creases = (tags or {}).get("creases", [])
    corners = (tags or {}).get("corners", [])
    if not creases and not corners and mesh.attributes.get("crease_edge") is None and mesh.attributes.get("crease_vert") is None:
        return
    edge_sharpness = np.zeros(n_edges)
    if creases:
        a, b, s = (np.array(column) for column in zip(*creases))
        index = edge_indices(edges, n, a, b)
        edge_sharpness[index[index >= 0]] = s[index >= 0]
    vertex_sharpness = np.zeros(n)
    if corners:
        v, s = (np.array(column) for column in zip(*corners))
        vertex_sharpness[v.astype(np.int64)] = s
    set_float_attribute(mesh, "crease_edge", "EDGE", sharpness_to_crease(edge_sharpness))
    corner_edges = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", corner_edges)
    loose = np.bincount(corner_edges, minlength=n_edges) == 0
    written = _written_vertex_sharpness(vertex_sharpness, edges[~loose], edge_sharpness[~loose], n)
    set_float_attribute(mesh, "crease_vert", "POINT", sharpness_to_crease(written))


def _written_vertex_sharpness(vertex, edges, edge, n):
    """The vertex sharpness to store so that Blender's two-edge rule (sharpness plus the smaller
    of the two edges') gives ``vertex``: ``vertex − min`` at vertices of two edges, ≥ 0;
    infinitely sharp stays so."""
    two = np.bincount(edges.ravel(), minlength=n) == 2
    smaller = smallest_incident(edges, edge, n)
    written = vertex.copy()
    written[two] = np.maximum(vertex[two] - np.minimum(smaller[two], INFINITE), 0.0)
    written[vertex >= INFINITE] = INFINITE
    return written


def new_mesh(name, control, data, uv_maps):
    """A Blender mesh of a refined cage (``fair``): the library's faces, its positions, the
    refined UV maps ``{name: (corners, 2)}``, each child face with its parent's material and
    shading (Catmull-Clark's split makes one quad per parent corner, in corner order)."""
    positions = np.ascontiguousarray(control.vertices, dtype=np.float32)
    offsets = np.asarray(control.face_offsets, dtype=np.int64)
    indices = np.asarray(control.face_indices, dtype=np.int32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.loops.add(len(indices))
    mesh.loops.foreach_set("vertex_index", indices)
    mesh.polygons.add(len(offsets) - 1)
    mesh.polygons.foreach_set("loop_start", offsets[:-1].astype(np.int32))
    mesh.update(calc_edges=True)
    parent = np.repeat(np.arange(len(data.sizes)), data.sizes)
    if len(parent) != len(offsets) - 1:
        raise RuntimeError("the refined cage does not have one face per input corner")
    mesh.polygons.foreach_set("material_index", data.material_index[parent])
    mesh.polygons.foreach_set("use_smooth", data.use_smooth[parent])
    for uv_name, uv in uv_maps.items():
        layer = mesh.uv_layers.new(name=uv_name)
        layer.uv.foreach_set("vector", np.ascontiguousarray(uv, dtype=np.float32).ravel())
    return mesh


def configure_modifier(obj, boundary_smooth, uv_smooth, use_creases, quality):
    """The object's (first) Subdivision Surface modifier, added when it has none (levels 1,
    render 2), set to show the limit surface with the options the cage was computed for."""
    modifier = next((m for m in obj.modifiers if m.type == "SUBSURF"), None)
    if modifier is None:
        modifier = obj.modifiers.new("Subdivision", "SUBSURF")
        modifier.levels, modifier.render_levels = 1, 2
    modifier.subdivision_type = "CATMULL_CLARK"
    modifier.use_limit_surface = True
    modifier.quality = max(modifier.quality, quality)
    modifier.boundary_smooth = boundary_smooth
    modifier.uv_smooth = uv_smooth
    modifier.use_creases = use_creases
    return modifier


def modifier_quality(data, edge, vertex, boundary_smooth):
    """Blender's ``quality`` (OpenSubdiv's adaptive isolation level) for the cage.

    Blender evaluates the limit surface with OpenSubdiv's patches, refined adaptively around
    irregular features to this level. At extraordinary vertices its end-cap patches take the
    limit point exactly at any level, but semi-sharp features, darts (which decaying creases
    also make) and the smooth corners of boundary 'ALL' (a boundary vertex of one face) are
    only approached, by a factor of about 4 per level (measured in
    crates/python/tests/test_blender_extension.py: 7e-4·d at 3, 1e-6·d at 8 on a grid's
    corner). So: the highest level, 10, when the mesh has tags or such corners; Blender's
    default 3 otherwise (the cheapest evaluation)."""
    if np.any(edge > 0) or np.any(vertex > 0):
        return 10
    if boundary_smooth == "ALL":
        face_edges = data.edges[~data.loose_edges]
        if np.any(np.bincount(face_edges.ravel(), minlength=len(data.positions)) == 2):
            return 10  # a vertex of two edges: a boundary corner (or an interior valence 2)
    return 3


# ---------------------------------------------------------------------------------------------
# The library call, off the main thread
# ---------------------------------------------------------------------------------------------


def run_with_progress(window_manager, work, tolerance, start=10, end=90):
    """Runs ``work(progress)`` in a worker thread and moves Blender's progress indicator (on
    the main thread: bpy is not thread-safe) from ``start`` to ``end`` as the solver's relative
    residual falls from 1 to ``tolerance``. Returns ``work``'s result or raises its exception."""
    state = {"fraction": 0.0, "result": None, "error": None}
    floor = math.log10(max(tolerance, 1e-300))

    def progress(iteration, residual):
        if residual > 0 and math.isfinite(residual):
            fraction = min(1.0, max(0.0, math.log10(residual) / floor)) if floor < 0 else 1.0
            state["fraction"] = max(state["fraction"], fraction)

    def target():
        try:
            state["result"] = work(progress)
        except BaseException as error:  # handed to the main thread
            state["error"] = error

    worker = threading.Thread(target=target, name="subdiv-interpolate", daemon=True)
    worker.start()
    while worker.is_alive():
        worker.join(0.05)
        if window_manager is not None:
            window_manager.progress_update(start + (end - start) * state["fraction"])
    if state["error"] is not None:
        raise state["error"]
    return state["result"]


# ---------------------------------------------------------------------------------------------
# The operator
# ---------------------------------------------------------------------------------------------


class OBJECT_OT_subdiv_interpolate(bpy.types.Operator):
    """Make a Catmull-Clark cage whose limit surface passes through this mesh's vertices"""

    bl_idname = "object.subdiv_interpolate"
    bl_label = "Subdiv Interpolate"
    bl_options = {"REGISTER", "UNDO"}

    method: bpy.props.EnumProperty(
        name="Method",
        items=[
            ("CHENG", "Cheng", "Exact: the cage has the mesh's topology (Cheng et al., A·M = P)"),
            ("FAIR", "Fair", "The fairest cage among those of the mesh refined once (more vertices)"),
        ],
        default="CHENG",
    )
    tolerance: bpy.props.FloatProperty(
        name="Tolerance",
        description="Largest distance of the limit surface from a vertex, relative to the bounding-box diagonal",
        default=1e-6,
        min=1e-12,
        max=1e-2,
        precision=9,
    )
    new_object: bpy.props.BoolProperty(
        name="New Object",
        description="Put the cage in a new object <name>_cage (off: replace this object's mesh)",
        default=True,
    )
    use_creases: bpy.props.BoolProperty(
        name="Use Creases",
        description="Honour the edge and vertex creases (and the modifier's)",
        default=True,
    )

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            cls.poll_message_set("The active object must be a mesh")
            return False
        if obj.mode != "OBJECT":
            cls.poll_message_set("Works in Object Mode")
            return False
        return True

    def execute(self, context):
        obj = context.active_object
        mesh = obj.data
        if mesh.shape_keys is not None:
            self.report({"ERROR"}, "the mesh has shape keys: apply or remove them first")
            return {"CANCELLED"}
        if len(mesh.polygons) == 0:
            self.report({"ERROR"}, "the mesh has no faces")
            return {"CANCELLED"}
        source_modifier = next((m for m in obj.modifiers if m.type == "SUBSURF"), None)
        boundary_smooth = source_modifier.boundary_smooth if source_modifier else "ALL"
        uv_smooth = source_modifier.uv_smooth if source_modifier else "PRESERVE_BOUNDARIES"
        window_manager = context.window_manager
        window_manager.progress_begin(0, 100)
        try:
            computed = self.compute(mesh, boundary_smooth, uv_smooth, window_manager)
        except Exception as error:  # the library's message, nothing changed
            self.report({"ERROR"}, str(error) or type(error).__name__)
            return {"CANCELLED"}
        finally:
            window_manager.progress_end()
        result, refined_uvs, data, caught = computed
        for warning in caught:
            self.report({"WARNING"}, str(warning.message))
        self.write(context, obj, result, refined_uvs, data, boundary_smooth, uv_smooth)
        error = result.error
        self.report({"INFO"}, f"{obj.name}: max error {error['max_rel']:.2e}·d ({result.method})")
        return {"FINISHED"}

    def compute(self, mesh, boundary_smooth, uv_smooth, window_manager):
        """Reads the mesh and runs the library (UV maps refined too for ``fair``). Raises the
        library's exception; changes nothing."""
        import subdiv

        options = {
            "boundary": BOUNDARY_SMOOTH[boundary_smooth],
            "fvar": UV_SMOOTH[uv_smooth],
            "crease_method": "uniform",
        }
        method = self.method.lower()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            data = MeshData(mesh)
            source = library_mesh(subdiv, data, self.use_creases)
            window_manager.progress_update(10)
            result = run_with_progress(
                window_manager,
                lambda progress: subdiv.interpolate(source, method, tol=self.tolerance, progress=progress, **options),
                self.tolerance,
            )
            refined_uvs = {}
            if method != "cheng":
                # The cage is the input refined once: each UV map refined by the same rules.
                for name, uv in data.uv_maps.items():
                    channel = library_mesh(subdiv, data, self.use_creases, uvs=weld_uvs(data.corner_vertices, uv))
                    values, index = subdiv.subdivide(channel, "catmull-clark", 1, **options).uvs
                    refined_uvs[name] = np.asarray(values)[np.asarray(index)]
            result.error  # measured now, so that a failure of the measure also changes nothing
        return result, refined_uvs, data, caught

    def write(self, context, obj, result, refined_uvs, data, boundary_smooth, uv_smooth):
        """The cage: into a new object ``<name>_cage`` or into ``obj``'s mesh."""
        control = result.control
        same_topology = control.n_vertices == len(data.positions) and control.n_faces == len(data.sizes)
        tags = control.tags if self.use_creases else None
        if same_topology:
            cage = obj.data.copy() if self.new_object else obj.data
            positions = np.ascontiguousarray(control.vertices, dtype=np.float32)
            cage.vertices.foreach_set("co", positions.ravel())
        else:
            cage = new_mesh(obj.data.name + ("_cage" if self.new_object else ""), control, data, refined_uvs)
            for material in obj.data.materials:
                cage.materials.append(material)
        if self.use_creases:
            write_creases(cage, tags)
        cage.update()
        edge, vertex = data.sharpness() if self.use_creases else (np.zeros(0), np.zeros(0))
        quality = modifier_quality(data, edge, vertex, boundary_smooth)
        if self.new_object:
            cage.name = obj.data.name + "_cage"
            target = bpy.data.objects.new(obj.name + "_cage", cage)
            target.matrix_world = obj.matrix_world.copy()
            collections = obj.users_collection or (context.scene.collection,)
            for collection in collections:
                collection.objects.link(target)
            for selected in context.selected_objects:
                selected.select_set(False)
            target.select_set(True)
            context.view_layer.objects.active = target
        else:
            target = obj
            if cage is not obj.data:  # fair: a new mesh takes the old one's place and name
                old, name = obj.data, obj.data.name
                old.name = name + ".replaced"
                cage.name = name
                obj.data = cage
                if old.users == 0:
                    bpy.data.meshes.remove(old)
        configure_modifier(target, boundary_smooth, uv_smooth, self.use_creases, quality)


def menu_entry(self, context):
    self.layout.separator()
    self.layout.operator(OBJECT_OT_subdiv_interpolate.bl_idname, icon="MOD_SUBSURF")


classes = (OBJECT_OT_subdiv_interpolate,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_object.append(menu_entry)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(menu_entry)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
