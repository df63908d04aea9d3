"""Evaluated Blender geometry -> core triangle meshes, with numpy and foreach_get.

`MeshData.from_object` reads an evaluated object's mesh once (loop triangles,
per-corner normals, the active UV map and, for tangent-space normal maps, its
MikkTSpace tangents, per-triangle material slots) in its local space;
`add_to_scene` transforms it by an instance's matrix. Instances of the same
data share one MeshData, so a forest of instances reads its mesh once.
Per-corner normals cover flat, smooth and custom normals alike.
"""

import bpy
import numpy as np

from . import visibility

HAS_CORNER_NORMALS = bpy.app.version >= (4, 1, 0)


def _read(collection, attribute, count, width, dtype):
    out = np.empty(count * width, dtype=dtype)
    if count:
        collection.foreach_get(attribute, out)
    return out.reshape(count, width) if width > 1 else out


def _corner_normals(mesh):
    """(loops, 3) normals as Cycles shades them: flat, smooth or custom."""
    if HAS_CORNER_NORMALS:
        return _read(mesh.corner_normals, "vector", len(mesh.loops), 3, np.float32)
    mesh.calc_normals_split()  # Blender < 4.1: split normals honour auto smooth and custom normals
    return _read(mesh.loops, "normal", len(mesh.loops), 3, np.float32)


def _corner_uvs_of(layer, count):
    data = layer.uv if hasattr(layer, "uv") else layer.data
    return _read(data, "vector" if hasattr(layer, "uv") else "uv", count, 2, np.float32)


def _corner_uvs(mesh):
    layer = mesh.uv_layers.active
    return None if layer is None else _corner_uvs_of(layer, len(mesh.loops))


def _corner_tangents(mesh):
    """(loops, 4): the active UV map's tangents (Blender's MikkTSpace, as Cycles' normal maps use)
    and bitangent signs; None without a UV map, or where Blender cannot compute them (n-gons:
    the caller then uses triangle_tangents)."""
    layer = mesh.uv_layers.active
    if layer is None:
        return None
    try:
        mesh.calc_tangents(uvmap=layer.name)
    except RuntimeError:
        return None
    count = len(mesh.loops)
    tangents = np.empty((count, 4), dtype=np.float32)
    tangents[:, :3] = _read(mesh.loops, "tangent", count, 3, np.float32)
    tangents[:, 3] = _read(mesh.loops, "bitangent_sign", count, 1, np.float32)
    mesh.free_tangents()
    return tangents


ATTRIBUTE_READS = {  # data type -> (property, width)
    "FLOAT_COLOR": ("color", 4), "BYTE_COLOR": ("color", 4), "FLOAT_VECTOR": ("vector", 3), "FLOAT": ("value", 1),
    "FLOAT2": ("vector", 2), "INT": ("value", 1), "BOOLEAN": ("value", 1),
}


def _render_color_attribute(mesh):
    """The colour attribute Cycles reads for a Color Attribute node without a name."""
    attributes = getattr(mesh, "color_attributes", None)
    if attributes is not None and len(attributes):
        index = getattr(attributes, "render_color_index", 0)
        return attributes[index if 0 <= index < len(attributes) else 0]
    return None


def _corner_attribute(mesh, name, loops, triangles):
    """(T, 3, 4) values of attribute `name` ("": the render colour attribute; a UV map's name: its
    UVs, as Cycles' Attribute node reads one) at each triangle corner, colours as scene-linear RGBA,
    vectors (x, y, z, 1), floats (v, v, v, 1); None if the mesh has none of that name."""
    layer = _render_color_attribute(mesh) if not name else mesh.attributes.get(name)
    if layer is None and name and name in mesh.uv_layers:
        uvs = _corner_uvs_of(mesh.uv_layers[name], len(mesh.loops))[loops]
        return np.concatenate([uvs, np.zeros(uvs.shape[:2] + (1,)), np.ones(uvs.shape[:2] + (1,))], axis=2)
    if layer is None or layer.data_type not in ATTRIBUTE_READS:
        return None
    prop, width = ATTRIBUTE_READS[layer.data_type]
    values = _read(layer.data, prop, len(layer.data), width, np.float64).reshape(len(layer.data), width)
    rgba = np.zeros((len(values), 4))
    rgba[:, 3] = values[:, 3] if width == 4 else 1.0
    rgba[:, :3] = values if width == 1 else 0.0
    if width > 1:
        rgba[:, :min(width, 3)] = values[:, :3]
    if layer.domain == "CORNER":
        out = rgba[loops]
    elif layer.domain == "POINT":
        out = rgba[triangles]
    elif layer.domain == "FACE":
        faces = _read(mesh.loop_triangles, "polygon_index", len(triangles), 1, np.int32)
        out = np.repeat(rgba[faces][:, None, :], 3, axis=1)
    else:
        return None
    return np.nan_to_num(out, nan=0.0, posinf=0.0, neginf=0.0).clip(-1e29, 1e29)


class MeshData:
    """Local-space triangles of one evaluated mesh."""

    def __init__(self, positions, triangles, normals, uvs, slots, tangents=None):
        self.positions = positions      # (V, 3) float64
        self.triangles = triangles      # (T, 3) int32 vertex indices
        self.normals = normals          # (T, 3, 3) per-corner
        self.uvs = uvs                  # (T, 3, 2) per-corner or None
        self.slots = slots              # (T,) material slot index
        self.tangents = tangents        # (T, 3, 4) per-corner tangent and bitangent sign, or None
        self.tangents_missing = False   # asked for, but the mesh has no UV map
        self.tangents_radial = False    # generated-coordinate tangents: carried as normals are
        self.colors = None              # (T, 3, 4) the attribute its materials' programs read, or None
        self.attribute_missing = False  # asked for, but the mesh has no such attribute
        self._compact = None            # compact(), made once
        self.open_volume_edges = None   # open_edges() of its Volume materials' slots, once counted

    @classmethod
    def from_object(cls, obj, tangents=None, attribute=None):
        """Reads `obj`'s evaluated mesh (modifiers applied); None if it has no triangles. `tangents`:
        also its tangents, "uv" (the UV map's, for normal maps and UV tangents) or "radial_x", "_y",
        "_z" (about that axis of its generated coordinates, Cycles' default for anisotropy).
        `attribute`: also that attribute's values at the corners (see _corner_attribute)."""
        mesh = obj.to_mesh()
        try:
            if mesh is None:
                return None
            mesh.calc_loop_triangles()
            count = len(mesh.loop_triangles)
            if count == 0:
                return None
            tris = mesh.loop_triangles
            triangles = _read(tris, "vertices", count, 3, np.int32)
            loops = _read(tris, "loops", count, 3, np.int32)
            slots = _read(tris, "material_index", count, 1, np.int32)
            positions = _read(mesh.vertices, "co", len(mesh.vertices), 3, np.float32).astype(np.float64)
            normals = _corner_normals(mesh)[loops]
            uvs = _corner_uvs(mesh)
            data = cls(positions, triangles, normals, None if uvs is None else uvs[loops], slots)
            if tangents and tangents.startswith("radial_"):
                data.tangents = radial_tangents(mesh, positions, triangles, tangents[-1])
                data.tangents_radial = True
            elif tangents:
                corner_tangents = _corner_tangents(mesh)
                if corner_tangents is not None:
                    data.tangents = corner_tangents[loops]
                elif data.uvs is not None:  # n-gons: Blender refuses them, Cycles triangulates first
                    data.tangents = triangle_tangents(positions, triangles, data.normals, data.uvs)
                data.tangents_missing = data.tangents is None
            if attribute is not None:
                data.colors = _corner_attribute(mesh, attribute, loops, triangles)
                data.attribute_missing = data.colors is None
            return data
        finally:
            obj.to_mesh_clear()

    def open_edges(self, slots):
        """Edges of the triangles in material `slots` that do not join exactly two of them: 0 where those
        triangles close a volume (by vertex index: a seam of split vertices counts as open)."""
        chosen = self.triangles[np.isin(self.slots, slots)]
        if len(chosen) == 0:
            return 0
        edges = np.sort(np.concatenate([chosen[:, [0, 1]], chosen[:, [1, 2]], chosen[:, [2, 0]]]), axis=1)
        _, counts = np.unique(edges, axis=0, return_counts=True)
        return int(np.count_nonzero(counts != 2))

    def add_to_scene(self, core_scene, item, material_indices):
        """Adds the mesh as one Instance (transformed by its matrix), with slot -> core material
        mapping, its object's ray visibility and holdout.

        Returns the number of triangles left out because a corner is not finite (NaN or Inf in the
        mesh or the matrix). A matrix that flattens the mesh to a line or a point (a zero scale, the
        usual way to hide an object in an animation) adds nothing, as in Cycles; one zero axis
        leaves a flat mesh that is rendered."""
        arguments, dropped = self.scene_arguments(item, material_indices)
        if arguments is not None:
            core_scene.add_mesh(**arguments)
        return dropped

    def replace_in_scene(self, core_scene, item, material_indices):
        """Puts the mesh in place of the one add_to_scene added for the same object (Scene.replace_mesh,
        in a dynamic scene), at the Instance's matrix. False where that cannot be, and the scene then
        needs a whole export: the matrix now flattens the mesh or makes a corner not finite."""
        arguments, dropped = self.scene_arguments(item, material_indices)
        if arguments is None or dropped:
            return False
        core_scene.replace_mesh(**arguments)
        return True

    def compact(self):
        """The corner attributes (normals, uvs, tangents, colors) as the core stores them most compactly:
        (V, k) one a vertex where every corner of each vertex carries the same value (a smooth mesh's
        normals, UVs without seams), else (T, 3, k) one a corner; made once for the instances sharing it."""
        if self._compact is None:
            vertices = len(self.positions)
            self._compact = {name: shared_per_vertex(values, self.triangles, vertices, fill)
                             for name, values, fill in (("normals", self.normals, (0.0, 0.0, 1.0)),
                                                        ("uvs", self.uvs, 0.0), ("tangents", self.tangents, 0.0),
                                                        ("colors", self.colors, 0.0))}
        return self._compact

    def scene_arguments(self, item, material_indices):
        """(Scene.add_mesh's keyword arguments, or None where nothing is added; triangles left out)."""
        m = item.matrix
        if np.isfinite(m).all() and flattens_to_a_line(m[:3, :3]):
            return None, 0
        with np.errstate(invalid="ignore", over="ignore"):
            positions = self.positions @ m[:3, :3].T + m[:3, 3]
        finite = np.isfinite(positions).all(axis=1)[self.triangles].all(axis=1)
        kept = int(finite.sum())
        if kept == 0:
            return None, len(self.triangles)
        triangles, slots, attributes = self.triangles, self.slots, dict(self.compact())
        if kept < len(triangles):
            triangles, slots = triangles[finite], slots[finite]
            attributes = {name: values if values is None or values.ndim == 2 else values[finite]  # (V, k): kept
                          for name, values in attributes.items()}
            positions = np.where(np.isfinite(positions), positions, 0.0)  # unused vertices only
        normals = attributes["normals"]
        shape = normals.shape
        normals = unit_rows(normals.reshape(-1, 3) @ float32_directions(normal_matrix(m[:3, :3])).T)
        normals = normals.astype(np.float64).reshape(shape)  # what the core reads (its own conversion is slower)
        slots = np.clip(slots, 0, len(material_indices) - 1)
        materials = np.asarray(material_indices, dtype=np.int64)[slots]
        tangents = attributes["tangents"]
        if tangents is not None:
            tangents = world_tangents(tangents, normal_matrix(m[:3, :3]) if self.tangents_radial else m[:3, :3])
        arguments = dict(name=item.name, positions=positions, triangles=triangles, normals=normals,
                         uvs=attributes["uvs"], materials=materials, object_id=item.object_id, tangents=tangents,
                         colors=attributes["colors"], **visibility.object_flags(item.obj))
        return arguments, len(self.triangles) - kept


def shared_per_vertex(corner_values, triangles, vertex_count, fill):
    """(T, 3, k) corner values as (V, k) vertex values where every corner of each vertex carries the same
    (unused vertices `fill`), else unchanged; None stays None. A mesh whose vertex count equals its corner
    count keeps them per corner (the core reads such an array so)."""
    if corner_values is None or vertex_count == triangles.size:
        return corner_values
    k = corner_values.shape[-1]
    per_vertex = np.empty((vertex_count, k), dtype=corner_values.dtype)
    per_vertex[:] = fill
    per_vertex[triangles.reshape(-1)] = corner_values.reshape(-1, k)
    return per_vertex if np.array_equal(per_vertex[triangles], corner_values) else corner_values


def radial_tangents(mesh, positions, triangles, axis):
    """(T, 3, 4) tangents about `axis` of the generated coordinates (the mesh's texture space mapped
    to [0, 1]), as Cycles' Tangent node in Radial mode: around Z, (-(y - 1/2), x - 1/2, 0)."""
    location = np.asarray(getattr(mesh, "texspace_location", (0.0, 0.0, 0.0)), dtype=np.float64)
    size = np.asarray(getattr(mesh, "texspace_size", (1.0, 1.0, 1.0)), dtype=np.float64)
    with np.errstate(invalid="ignore", over="ignore"):  # corners that are not finite are left out later
        g = (positions - location) / np.where(np.abs(size) > 1e-30, 2.0 * size, 1.0)  # generated - 1/2
    zero = np.zeros(len(g))
    columns = {"x": (zero, -g[:, 2], g[:, 1]), "y": (-g[:, 2], zero, g[:, 0]), "z": (-g[:, 1], g[:, 0], zero)}
    per_vertex = np.stack(columns[axis] + (np.ones(len(g)),), axis=1)
    return per_vertex[triangles].astype(np.float32)


def triangle_tangents(positions, triangles, normals, uvs):
    """(T, 3, 4) tangents from the UV gradient of each triangle, summed over the triangles that share
    a vertex and its UV, made orthogonal to each corner's normal; the bitangent sign from the summed
    bitangent. MikkTSpace's construction in outline, for meshes Blender computes none for (n-gons)."""
    p = positions[triangles]                              # (T, 3, 3)
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d1, d2 = uvs[:, 1] - uvs[:, 0], uvs[:, 2] - uvs[:, 0]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    r = np.where(np.abs(det) > 1e-20, 1.0 / np.where(det == 0.0, 1.0, det), 0.0)[:, None]
    t = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * r
    b = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * r
    # Corners sharing a vertex and a UV share the sum of their triangles' gradients.
    keys = np.concatenate([triangles.reshape(-1, 1).astype(np.float64), uvs.reshape(-1, 2)], axis=1)
    _, group = np.unique(keys, axis=0, return_inverse=True)
    group = group.reshape(-1)
    t_sum, b_sum = (np.zeros((group.max() + 1, 3)) for _ in range(2))
    np.add.at(t_sum, group, np.repeat(t, 3, axis=0))
    np.add.at(b_sum, group, np.repeat(b, 3, axis=0))
    n = normals.reshape(-1, 3).astype(np.float64)
    tangent = t_sum[group]
    tangent -= n * np.sum(n * tangent, axis=1, keepdims=True)
    tangent /= row_lengths(tangent)
    sign = np.where(np.sum(np.cross(n, tangent) * b_sum[group], axis=1) < 0.0, -1.0, 1.0)
    return np.concatenate([tangent, sign[:, None]], axis=1).reshape(-1, 3, 4).astype(np.float32)


def world_tangents(tangents, m):
    """Corner tangents carried by `m` (directions), unit length; a mirroring `m` flips the bitangent
    sign, since the bitangent is sign * normal x tangent and the normal is carried by the inverse
    transpose."""
    out = np.empty(tangents.shape, dtype=np.float64)
    directions = unit_rows(tangents[..., :3].reshape(-1, 3) @ float32_directions(m).T)
    out[..., :3] = directions.reshape(tangents.shape[:-1] + (3,))
    out[..., 3] = tangents[..., 3] * (1.0 if np.linalg.det(m) >= 0.0 else -1.0)
    return out


def row_lengths(vectors):
    """The lengths of an (N, 3) array's rows as an (N, 1) column, at least 1e-30 (to divide by).
    np.linalg.norm(axis=1) takes about ten times as long on millions of rows."""
    return np.maximum(np.sqrt(np.einsum("ij,ij->i", vectors, vectors)), 1e-30)[:, None]


def unit_rows(vectors):
    """(N, 3) directions made unit length; rows that are not finite, too long for their type or zero
    become zero. (np.nan_to_num first took four times as long as the rest on millions of rows.)"""
    lengths = np.sqrt(np.einsum("ij,ij->i", vectors, vectors))
    usable = np.isfinite(lengths) & (lengths > 0.0)
    out = vectors / np.where(usable, lengths, 1.0)[:, None]
    out[~usable] = 0.0
    return out


def float32_directions(m):
    """A 3x3 matrix that carries directions as `m` does (up to a positive scale) in float32: corner
    normals and tangents are float32, and a float32 product takes BLAS's path (a float64 one on
    millions of rows is 20 times slower). The scale keeps tiny and huge matrices in float32's range."""
    largest = np.abs(m).max()
    if np.isfinite(largest) and largest > 0.0:
        m = m / largest
    return m.astype(np.float32)


def normal_matrix(m):
    """The matrix that carries normals through `m`: the inverse transpose, scaled by |det m| so that
    it exists for a singular `m` too (its cofactor matrix; normals are normalised afterwards)."""
    a, b, c = m[:, 0], m[:, 1], m[:, 2]
    cofactor = np.array([_cross(b, c), _cross(c, a), _cross(a, b)]).T
    return cofactor if np.linalg.det(m) >= 0.0 else -cofactor


def flattens_to_a_line(m):
    """Is the finite 3x3 `m` of rank 0 or 1 (up to rounding)? Its 2x2 minors (the cofactors) then
    vanish against its largest entry squared; np.linalg.matrix_rank's SVD takes 60 us a call."""
    largest = np.abs(m).max()
    return largest == 0.0 or np.abs(normal_matrix(m)).max() <= 1e-15 * largest * largest


def _cross(u, v):
    """u x v of two 3-vectors (np.cross costs 50 us a call: an instance moved in the viewport pays it)."""
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
