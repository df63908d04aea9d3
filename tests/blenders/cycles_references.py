"""Cycles' renders of the comparison scenes, kept per Blender version and found again by a fingerprint of
the scene as Cycles reads it: a comparison takes the image this Blender's Cycles rendered for exactly this
scene and these settings instead of rendering it on every test run (Cycles was half of each version's
comparison time).

The fingerprint hashes every property of every data-block Cycles can read (the scene and its render and
Cycles settings, objects, meshes' geometry and attributes, materials', worlds' and node groups' nodes and
links, lights, cameras, images' files or pixels), paths by file name and contents, so a case that changes
in any way misses and is rendered by Cycles as before. With RECORD set (in_blender.py sets it), a miss
writes the image to cycles_references/<Blender version>/<case>.npz for the next run and is listed in
`rendered`; test_blender_versions.py fails until what a run wrote is committed. PPM_LIVE_CYCLES=1 in the
environment renders every case again and rewrites what it records; PPM_FINGERPRINT_DUMP=<folder> writes
what each lookup hashed, to see why a case misses. Images are kept as half floats (relative
rounding 2^-11, far below every comparison's tolerance) unless a value is beyond half's range.
"""

import hashlib
import os
import warnings

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
STORE = os.path.join(HERE, "cycles_references")
RECORD = False  # write what misses (in_blender.py, in each Blender version the tests run)
LIVE = os.environ.get("PPM_LIVE_CYCLES") == "1"
DUMP = os.environ.get("PPM_FINGERPRINT_DUMP")  # a folder: each lookup writes what it hashed there
found, rendered = [], []  # case names, this process

# The data-block kinds Cycles reads (attribute names of bpy.data; those a version lacks are passed over).
DATA = ("scenes", "objects", "collections", "meshes", "curves", "metaballs", "lattices", "materials",
        "node_groups", "worlds", "lights", "cameras", "images", "textures", "volumes", "actions", "particles",
        "lightprobes", "hair_curves", "pointclouds")
# Properties that change between runs or processes without changing the image, the editors' and the
# depsgraph's state, and settings of what Cycles' final render does not use (baking, the viewport's
# display, keying sets: some of these hold values their enums lack and make Blender print warnings).
IGNORED = {"rna_type", "session_uid", "is_evaluated", "original", "users", "use_fake_user", "use_extra_user",
            "tag", "is_runtime_data", "preview", "bindcode", "is_dirty", "has_data", "depsgraph",
            "tool_settings", "statistics", "is_missing", "library_weak_reference", "override_library",
            "asset_data", "id_data", "bl_rna", "is_embedded_data", "is_editmode", "select", "show_expanded",
            "location_absolute", "dimensions", "bake", "display", "keying_sets_all", "animation_visualization",
            "ppm",  # PPM's own settings
            # A fluid domain's simulated grids: reading them through the file's own (not the evaluated)
            # object crashes Blender 3.4. They follow from the domain's settings, which are hashed.
            "density_grid", "velocity_grid", "flame_grid", "color_grid", "heat_grid", "temperature_grid"}
MAX_DEPTH = 8
ATTRIBUTE_VALUE = {"FLOAT_VECTOR": ("vector", 3), "FLOAT2": ("vector", 2), "FLOAT_COLOR": ("color", 4),
                   "BYTE_COLOR": ("color", 4), "FLOAT": ("value", 1), "INT": ("value", 1),
                   "BOOLEAN": ("value", 1), "INT8": ("value", 1), "QUATERNION": ("value", 4),
                   "UV": ("uv", 2)}


def fingerprint(lines=None):
    """sha256 of the current file's data as Cycles reads it; `lines`, if a list, receives what is hashed
    (to find what differs between two fingerprints)."""
    bpy.context.view_layer.update()  # objects' world matrices as the render will see them
    digest = hashlib.sha256()
    out = lines if lines is not None else []
    with warnings.catch_warnings():  # deprecated properties are read too
        warnings.simplefilter("ignore", DeprecationWarning)
        _data_blocks(out)
    for line in out:
        digest.update(line.encode("utf-8", "replace"))
        digest.update(b"\n")
    return digest.hexdigest()


def _data_blocks(out):
    for kind in DATA:
        blocks = getattr(bpy.data, kind, None)
        for block in sorted(blocks or (), key=lambda b: b.name):
            if kind == "images" and block.type in {"RENDER_RESULT", "COMPOSITING"}:
                continue
            _walk(block, f"{kind}[{block.name}]", 0, {}, out)
            if kind == "meshes":
                _mesh_arrays(block, f"{kind}[{block.name}]", out)
            elif kind == "images":
                out.append(f"{kind}[{block.name}] content {_image_content(block)}")


def _walk(struct, path, depth, seen, out):
    """Every property of `struct` as "path value" lines; other data-blocks by name, structs reached
    twice (a link's nodes) by where they were first met."""
    key = (struct.as_pointer(), type(struct).__name__)
    if key in seen:
        out.append(f"{path} = {seen[key]}")
        return
    seen[key] = path
    mesh = isinstance(struct, bpy.types.Mesh)
    for prop in struct.bl_rna.properties:
        name = prop.identifier
        if name in IGNORED or (mesh and prop.type in {"COLLECTION", "POINTER"} and not _is_id(prop)):
            continue  # a mesh's data: _mesh_arrays
        try:
            value = getattr(struct, name)
        except Exception as error:  # noqa: BLE001 - a property this build cannot read is still a line
            out.append(f"{path}.{name} ! {type(error).__name__}")
            continue
        _value(value, prop, f"{path}.{name}", depth, seen, out)


def _is_id(prop):
    """Does the pointer property `prop` point to a data-block (its type derives from ID)?"""
    kind = prop.fixed_type if prop.type == "POINTER" else None
    while kind is not None and kind.identifier != "ID":
        kind = kind.base
    return kind is not None


def _value(value, prop, path, depth, seen, out):
    if isinstance(value, bpy.types.ID) and value.is_embedded_data:  # a material's or world's node tree
        _walk(value, path, depth + 1, seen, out)
    elif isinstance(value, bpy.types.ID):
        out.append(f"{path} -> {type(value).__name__}[{value.name}]")
    elif prop.type == "POINTER":
        if value is None or depth >= MAX_DEPTH:
            out.append(f"{path} = {value is None}")
        else:
            _walk(value, path, depth + 1, seen, out)
    elif prop.type == "COLLECTION":
        out.append(f"{path} len {len(value)}")
        if depth < MAX_DEPTH:
            for i, item in enumerate(value):
                if isinstance(item, bpy.types.ID):
                    out.append(f"{path}[{i}] -> {type(item).__name__}[{item.name}]")
                else:
                    _walk(item, f"{path}[{i}]", depth + 1, seen, out)
    elif prop.type == "STRING":
        out.append(f"{path} = {_portable(value)!r}")
    elif isinstance(value, (set, frozenset)):  # an enum of flags
        out.append(f"{path} = {sorted(value)!r}")
    elif getattr(prop, "is_array", False) or hasattr(value, "__len__") and not isinstance(value, str):
        out.append(f"{path} = {tuple(_flat(value))!r}")
    else:
        out.append(f"{path} = {value!r}")


def _flat(value):
    for item in value:
        if hasattr(item, "__len__") and not isinstance(item, str):
            yield from _flat(item)
        else:
            yield item


def _portable(text):
    """A file path by its name alone: the checkout, the temporary folder and Blender's own data folder
    differ between machines (the contents of image files are hashed apart)."""
    if isinstance(text, bytes):  # a byte string (a node's script, a text's bytes)
        return hashlib.sha256(text).hexdigest()
    if text.startswith(("/", "//")) or text[1:3] in (":\\", ":/"):
        return os.path.basename(text.rstrip("/\\"))
    return text


def _mesh_arrays(mesh, path, out):
    """A mesh's geometry and attributes, read in bulk (a walk of its vertices would take seconds), in an
    order of their own: Blender 3.4 makes one UV sphere with its faces, edges and corners in another
    order in each process. Each face is its corners from its lowest vertex on (winding kept), the faces
    and edges sorted; face and corner attributes follow their faces."""
    co = _read(mesh.vertices, "co", 3)
    starts, totals = (_read(mesh.polygons, f, 1).astype(np.int64) for f in ("loop_start", "loop_total"))
    corners = _read(mesh.loops, "vertex_index", 1).astype(np.int64)
    faces = []  # (its corners' vertices from the lowest on, its corner indices in that order, its index)
    for index, (start, total) in enumerate(zip(starts, totals)):
        loops = np.arange(start, start + total)
        turn = int(np.argmin(corners[loops])) if total else 0
        loops = np.roll(loops, -turn)
        faces.append((tuple(corners[loops]), loops, index))
    faces.sort(key=lambda face: face[0])
    face_order = np.array([face[2] for face in faces], dtype=np.int64)
    corner_order = np.concatenate([face[1] for face in faces]) if faces else np.zeros(0, np.int64)
    edges = np.sort(_read(mesh.edges, "vertices", 2).reshape(-1, 2), axis=1)
    edge_order = np.lexsort((edges[:, 1], edges[:, 0])) if len(edges) else np.zeros(0, np.int64)
    order = {"POINT": None, "FACE": face_order, "CORNER": corner_order, "EDGE": edge_order}
    faces_text = ";".join(",".join(map(str, face[0])) for face in faces)
    out.append(f"{path}.vertices {_digest(co)}")
    out.append(f"{path}.faces {hashlib.sha256(faces_text.encode()).hexdigest()}")
    out.append(f"{path}.edges {_digest(edges[edge_order])}")
    for field in ("use_smooth", "material_index"):
        out.append(f"{path}.faces.{field} {_digest(_read(mesh.polygons, field, 1)[face_order])}")
    out.append(f"{path}.materials {[m.name if m else None for m in mesh.materials]}")
    # Names starting with "." are Blender's own (corners' vertices and edges, selection): the topology above.
    layers = [(layer.name, layer.domain, layer.data_type, layer.data) for layer in getattr(mesh, "attributes", ())
              if not layer.name.startswith(".")]
    layers += [(layer.name, "CORNER", "UV", layer.data) for layer in mesh.uv_layers]  # 3.4: not attributes
    for name, domain, data_type, data in layers:
        field, width = ATTRIBUTE_VALUE.get(data_type, (None, 0))
        values = _read(data, field, width).reshape(len(data), -1) if field else np.zeros((len(data), 0))
        if order.get(domain) is not None and len(values) == len(order[domain]):
            values = values[order[domain]]
        out.append(f"{path}.attributes[{name}] {domain} {data_type} {_digest(values)}")


def _read(items, field, width):
    values = np.zeros(len(items) * width, dtype=np.float64)
    if len(items):
        items.foreach_get(field, values)
    return values


def _digest(values):
    return hashlib.sha256(np.ascontiguousarray(values, dtype=np.float64).tobytes()).hexdigest()


def _image_content(image):
    """The image's file, packed bytes or (generated or edited) pixels, hashed."""
    if image.packed_file is not None:
        return hashlib.sha256(bytes(image.packed_file.data)).hexdigest()
    if image.source in {"FILE", "SEQUENCE", "TILED"} and not image.is_dirty:
        path = bpy.path.abspath(image.filepath, library=image.library)
        if os.path.isfile(path):
            with open(path, "rb") as f:
                return hashlib.sha256(f.read()).hexdigest()
        return "missing"
    pixels = np.zeros(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return hashlib.sha256(pixels.tobytes()).hexdigest()


def _path(case):
    return os.path.join(STORE, bpy.app.version_string.split(" ")[0], case + ".npz")


def lookup(case):
    """(the stored image, the fingerprint of the current scene); the image is None if none is stored for
    exactly this scene."""
    lines = [] if DUMP else None
    key = fingerprint(lines)
    if DUMP:  # what was hashed, to find why a case misses
        with open(os.path.join(DUMP, case + ".txt"), "w") as f:
            f.write("\n".join(lines))
    path = _path(case)
    if LIVE or not os.path.isfile(path):
        return None, key
    with np.load(path) as stored:
        if str(stored["fingerprint"]) != key:
            return None, key
        return stored["rgba"].astype(np.float32), key


def store(case, key, rgba):
    """Keeps Cycles' image of `case` for the scene fingerprinted `key` (with RECORD set); a miss, unless
    every case is rendered on purpose (LIVE)."""
    if not LIVE:
        rendered.append(case)
    if not RECORD:
        return
    os.makedirs(os.path.dirname(_path(case)), exist_ok=True)
    finite = np.nan_to_num(rgba, nan=0.0, posinf=0.0, neginf=0.0)
    compact = rgba.astype(np.float16) if np.abs(finite).max(initial=0.0) < 6e4 else rgba.astype(np.float32)
    np.savez_compressed(_path(case), fingerprint=np.array(key), rgba=compact)
