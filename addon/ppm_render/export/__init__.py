"""The evaluated depsgraph -> one ppm_core.Scene.

Walks `depsgraph.object_instances` once (real objects, particles, collection
instances, Geometry Nodes instances), copying each instance's matrix because
Blender reuses the instance records, and hands every data kind to its own
module: mesh, material, light, camera, world, bezier. Curves come twice in
the depsgraph (the CURVE object and a MESH instance of its evaluated
geometry): a revolve curve is exported exactly and its MESH instance (the
Screw preview) skipped; any other curve is exported through that MESH instance.

Esc is honoured between objects (`cancelled` raises Cancelled).

Where Cycles renders a frame, so does this exporter: an object or light the core
refuses (its message names what is wrong) is left out, and so are triangles
with a corner that is not finite; each such object gets one warning, however
many instances it has. Only a scene without a camera object fails.
"""

import dataclasses
import re
import sys

import bpy
import numpy as np

from . import bezier, camera, light, material, mesh, object_info, smoke, unrendered, volume_object, world
from .instance import Instance

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT"}
CURVE_TYPES = {"CURVE", "SURFACE", "FONT"}
# Object types with no mesh to read (to_mesh() raises on them): left out, each with a warning.
UNRENDERED_TYPES = {
    "CURVES": "hair curves are not rendered yet; left out",
    "POINTCLOUD": "point clouds are not rendered yet; left out",
    "GREASEPENCIL": "Grease Pencil is not rendered; left out",
    "GPENCIL": "Grease Pencil is not rendered; left out",
}


class Cancelled(Exception):
    """The user pressed Esc during the export."""


@dataclasses.dataclass(frozen=True)
class PassIndices:
    """Blender's Pass Index of each core object id and of each core material, for the Object Index and
    Material Index passes (0 where Blender has none: the default material, lights)."""
    objects: np.ndarray
    materials: np.ndarray


@dataclasses.dataclass
class Exported:
    """What the export made of one depsgraph instance, kept to update it in place (the viewport): the
    Instance without its Blender objects (see detached), its material slots' names, what it is ("mesh",
    "revolve", or "none": nothing of its own, such as a revolve's Screw preview), its local mesh for a
    "mesh", and whether the core scene has primitives of it (its object id's)."""
    item: Instance
    materials: tuple
    kind: str
    data: object = None
    added: bool = False


class Exporter:
    dynamic = False  # the core scene it fills: see sync.SyncingExporter
    """State of one export: the core scene, materials, mesh cache, warnings and object ids. `lights`
    and `objects` choose what of the depsgraph's instances it adds; either way every instance gets
    its object id, so that names are the same whatever is exported. `exported` records what it made
    of every instance, so that a dynamic core scene can follow later depsgraphs in place (sync)."""

    def __init__(self, core_scene, warn, view_layer=None, scene=None, lights=True, objects=True):
        self.scene = core_scene
        self.warn = warn
        self.lights, self.objects = lights, objects
        self.attributes = object_info.AttributeTable(view_layer, scene)
        self.grid_names = smoke.GridNames()  # the slots of the grids materials read
        self.materials = material.MaterialExporter(self.scene, warn, self.attributes, self.grid_names)
        # Cycles 5.0 on reads a volume's grids one voxel at a time, picked by the trilinear weights.
        stochastic = bpy.app.version >= (5, 0, 0)
        self.smoke = smoke.SmokeGrids(self.scene, scene.frame_current if scene is not None else 0, warn, stochastic)
        module = getattr(core_scene, "core_module", None) or sys.modules[type(core_scene).__module__]
        self.volumes = volume_object.VolumeObjects(self.scene, warn, module.blosc_decompress, stochastic)
        self.meshes = {}  # mesh_key -> MeshData, for this depsgraph's instances sharing one
        self.next_id = 0
        self.triangles = 0
        self.curves_with_mesh = set()
        self.plain_curves = []
        self.skipped = {}  # warning -> number of instances it applies to
        self.exported = {}  # identity_of(instance) -> Exported; None where two instances had one identity
        self.instanced = set()  # original names of the objects instanced, and of those instancing them
        self.touched = set()  # original names of the objects the last update in place exported again
        self.object_pass_index = {}  # object id -> its Blender object's Pass Index (the Object Index pass)
        # (object name, its volume materials, lo, hi): the world-space box of each object with a medium
        self.media_bounds = []

    def describe_object(self, item, slots):
        """Object info for the node programs of the object's materials, if any has one (with the grids
        of a smoke domain or a Volume object that they read)."""
        if any(i in self.materials.with_program for i in slots):
            read = {self.grid_names.names[k] for i in slots for k in self.materials.grid_slots_of.get(i, ())}
            volume = item.obj.type == "VOLUME"
            source = self.volumes if volume else self.smoke
            grids = source.indices(item.obj, sorted(read), self.grid_names) if read else None
            density = volume_object.density_scale(item) if volume else 1.0
            object_info.add_object_info(self.scene, item, self.attributes, grids, density)

    def object_id(self):
        self.next_id += 1
        return self.next_id - 1

    def pass_indices(self):
        """The Pass Index of every core object id and core material (passes.index_passes)."""
        objects = np.zeros(self.next_id, dtype=np.float32)
        for object_id, index in self.object_pass_index.items():
            objects[object_id] = index
        return PassIndices(objects, self.materials.pass_index_table())

    def slot_materials(self, obj):
        grids = obj.type == "VOLUME" or smoke.gas_domain(obj) is not None
        slots = [self.materials.index(slot.material, grids) for slot in obj.material_slots]
        return slots or [self.materials.index(None)]

    def mesh_key(self, obj):
        """What instances sharing one MeshData have in common: the evaluated data and the materials."""
        return (obj.data.as_pointer() if obj.data is not None else obj.as_pointer(),
                tuple(s.material.name if s.material else "" for s in obj.material_slots))

    def read_mesh(self, obj, slots):
        """Reads `obj`'s evaluated mesh with the tangents and attribute its materials need, warning
        where they cannot be had."""
        kinds = sorted({self.materials.tangents[i] for i in slots if i in self.materials.tangents})
        if len(kinds) > 1:
            self.skip(obj, f"its materials need different tangents ({', '.join(kinds)}); using {kinds[-1]}")
        names = sorted({self.materials.attributes[i] for i in slots if i in self.materials.attributes})
        if len(names) > 1:
            self.skip(obj, f"its materials read different attributes ({', '.join(names)}); all read "
                           f"'{names[0] or 'the render colour attribute'}'")
        data = mesh.MeshData.from_object(obj, kinds[-1] if kinds else None, names[0] if names else None)
        if data is not None and data.tangents_missing:
            self.skip(obj, "its normal map or anisotropy needs UV tangents, but it has no UV map; "
                           "rendered without them")
        if data is not None and data.attribute_missing:
            self.skip(obj, f"it has no attribute '{names[0]}' that its materials read; they read black")
        return data

    def mesh_of(self, obj, slots):
        """The MeshData of `obj` (read once for the instances sharing its data and materials)."""
        key = self.mesh_key(obj)
        if key not in self.meshes:
            self.meshes[key] = self.read_mesh(obj, slots)
        return self.meshes[key]

    def add_geometry(self, item):
        """Adds a mesh instance; returns its record."""
        obj = item.obj
        slots = self.slot_materials(obj)
        data = self.mesh_of(obj, slots)
        self.describe_object(item, slots)
        self.check_volume_closed(obj, data, slots)
        self.note_medium_bounds(item, data, slots)
        added = self.put_mesh(data, item, slots, False)
        return Exported(detached(item), self.mesh_key(obj)[1], "mesh", data, added)

    def check_volume_closed(self, obj, data, slots):
        """Warns where a material with a Volume output is on faces that do not close: a path entering
        through the hole never leaves the medium (as in Cycles, which this renders the same)."""
        volume_slots = [k for k, index in enumerate(slots) if index in self.materials.with_volume]
        if data is None or not volume_slots:
            return
        if data.open_volume_edges is None:
            data.open_volume_edges = data.open_edges(volume_slots)
        if data.open_volume_edges:
            self.skip(obj, f"the faces carrying its Volume material are not closed ({data.open_volume_edges} edges "
                           "bound one face, or more than two): light entering through the opening never leaves "
                           "the medium (as in Cycles); close the mesh")

    def note_medium_bounds(self, item, data, slots):
        volumes = frozenset(i for i in slots if i in self.materials.with_volume)
        if data is None or len(data.positions) == 0 or not volumes:
            return
        with np.errstate(invalid="ignore", over="ignore"):
            positions = data.positions @ item.matrix[:3, :3].T + item.matrix[:3, 3]
        if np.isfinite(positions).all():
            self.media_bounds.append((item.obj.original.name, volumes, positions.min(axis=0), positions.max(axis=0)))

    def warn_overlapping_media(self, most=5):
        """Warns where two objects with the same Volume material may overlap (their boxes do): Cycles
        adds each object's volume, the medium twice there; the core adds different media where they
        overlap (a smoke ball in a fog room) but counts one medium once."""
        boxes = sorted(self.media_bounds, key=lambda box: box[2][0])  # swept along x
        pairs = []
        for i, (name_a, volumes_a, lo_a, hi_a) in enumerate(boxes):
            for name_b, volumes_b, lo_b, hi_b in boxes[i + 1:]:
                if lo_b[0] >= hi_a[0] or len(pairs) > most:
                    break
                if volumes_a & volumes_b and (np.minimum(hi_a, hi_b) > np.maximum(lo_a, lo_b)).all():
                    pairs.append((name_a, name_b))
        for name_a, name_b in pairs[:most]:
            self.warn(f"objects '{name_a}' and '{name_b}': their media (one Volume material) may overlap; where "
                      "they do it is rendered once (Cycles adds it twice)")
        if len(pairs) > most:
            self.warn("more objects whose media (one Volume material) may overlap")

    def put_mesh(self, data, item, slots, replacing):
        """Adds `data` at `item`'s matrix, or `replacing`, in place of the object's triangles in the core
        scene (removing them where none are left); returns whether the object has triangles now."""
        arguments, dropped = (None, 0) if data is None else data.scene_arguments(item, slots)
        if dropped:
            self.skip(item.obj, f"{dropped} of its {len(data.triangles)} triangles have a corner that is not "
                                "finite (NaN or Inf); left out")
        if arguments is None:
            if replacing:
                self.scene.remove_object(item.object_id)
            return False
        (self.scene.replace_mesh if replacing else self.scene.add_mesh)(**arguments)
        self.triangles += len(arguments["triangles"])
        return True

    def add_volume(self, item):
        """Adds a Volume object (a box around its grids, carrying its material's medium); returns its record."""
        obj = item.obj
        grids, why = self.volumes.grids(obj)
        if grids is None:
            self.skip(obj, why + "; left out")
        slots = self.slot_materials(obj) if grids is not None else []
        if grids is not None and not any(i in self.materials.with_volume for i in slots):
            self.skip(obj, "it has no material with a Volume output (Cycles renders its default volume); left out")
            grids = None
        data = volume_object.box_mesh(grids) if grids is not None else None
        if data is None:
            return Exported(detached(item), (), "volume")
        self.describe_object(item, slots)
        self.note_medium_bounds(item, data, slots)
        added = self.put_mesh(data, item, slots, False)
        return Exported(detached(item), self.mesh_key(obj)[1], "volume", data, added)

    def add_revolve(self, item):
        slots = self.slot_materials(item.obj)
        index = self.materials.without_emission(slots[0], f"'{item.name}'")
        self.describe_object(item, slots)
        added = bezier.add_revolve(self.scene, item, index, self.warn) > 0
        return Exported(detached(item), self.mesh_key(item.obj)[1], "revolve", added=added)

    def skip(self, obj, what):
        """Notes a warning about `obj` (once per object, counting its instances)."""
        kind = "light" if obj.type == "LIGHT" else "object"
        message = f"{kind} '{obj.original.name}': {what}"
        self.skipped[message] = self.skipped.get(message, 0) + 1

    def report_skips(self):
        for message, count in self.skipped.items():
            self.warn(message + (f" (in {count} instances)" if count > 1 else ""))

    def guarded(self, obj, export, *args):
        """Returns export(*args); what the core refuses about `obj` is left out with a warning (None)."""
        try:
            return export(*args)
        except ValueError as error:  # the core's message starts with the name this module gave it
            self.skip(obj, "not rendered: " + re.sub(r"^[a-z ]+ '[^']*': ", "", str(error), count=1))
            return None

    def role(self, instance):
        """What a depsgraph instance is to the export: "light", "mesh", "revolve", "volume" (a Volume
        object), "curve" (a curve whose geometry may come as a MESH instance of its own:
        finish_curves), "none" (a revolve's Screw preview), "unrendered" (a kind of geometry the
        core has not: UNRENDERED_TYPES) or None (nothing: a camera, an empty, an object not shown)."""
        obj = instance.object
        # For an instance: the object instanced (a curve lists its own evaluated mesh so) and the
        # object instancing it (an empty with a collection, a particle or Geometry Nodes host).
        instanced = instance.instance_object if instance.is_instance else None
        if obj.type == "LIGHT":
            return "light"
        if instanced is not None and instanced.type in CURVE_TYPES and instanced.original == obj.original:
            # The evaluated geometry of a curve, listed as a MESH instance of the curve itself.
            self.curves_with_mesh.add(instanced.original.name)
            return "none" if bezier.is_revolve(instanced) else "mesh"
        if bezier.is_revolve(obj):
            return "revolve"
        if obj.type == "VOLUME" and (instanced is not None or getattr(instance, "show_self", True)):
            return "volume"
        if obj.type in CURVE_TYPES and instanced is None:
            return "curve"
        shown = instanced is not None or getattr(instance, "show_self", True)
        if obj.type in GEOMETRY_TYPES and shown:
            return "mesh"
        if obj.type in UNRENDERED_TYPES and shown:
            return "unrendered"
        return None

    def instance_item(self, instance):
        """The Instance of a depsgraph instance, with a new object id."""
        obj = instance.object
        instanced = instance.instance_object if instance.is_instance else None
        object_id = self.object_id()
        self.object_pass_index[object_id] = obj.pass_index
        name = obj.name if instanced is None else f"{instanced.name}/{obj.name}.{object_id}"
        particles = getattr(instance.particle_system, "settings", None) if instance.is_instance else None
        if instance.is_instance:
            self.instanced.update((obj.original.name, instance.parent.original.name))
        return Instance(obj, name, np.array(instance.matrix_world, dtype=float), object_id,
                        object_info.random_of(instance), instance.parent if instance.is_instance else None,
                        particles, tuple(instance.persistent_id) if instance.is_instance else ())

    def visit(self, instance, role=None):
        """Exports one depsgraph instance (`role`: role(instance), if known). Every instance takes an
        object id, so that the ids are those of an export of everything."""
        role = role or self.role(instance)
        item = self.instance_item(instance)
        obj, identity = instance.object, identity_of(instance)
        if role is not None and (self.lights if role == "light" else self.objects):
            for message in unrendered.object_features(obj):
                self.skip(obj, message)
        if role == "light":
            if self.lights:
                self.guarded(obj, light.add_light, self.scene, item, self.warn)
        elif role is None or not self.objects:
            return
        elif role == "unrendered":
            self.skip(obj, UNRENDERED_TYPES[obj.type])
        elif role == "curve":
            self.plain_curves.append((identity, item))  # exported later unless a MESH instance shows up
        elif role == "none":
            self.record(identity, Exported(detached(item), (), "none"))
        else:
            export = {"mesh": self.add_geometry, "revolve": self.add_revolve, "volume": self.add_volume}[role]
            self.record(identity, self.guarded(obj, export, item) or Exported(detached(item), (), role))

    def record(self, identity, exported):
        self.exported[identity] = None if identity in self.exported else exported

    def finish_curves(self):
        for identity, item in self.plain_curves:
            if item.obj.original.name in self.curves_with_mesh:
                self.record(identity, Exported(detached(item), (), "none"))
            else:
                self.record(identity, self.guarded(item.obj, self.add_geometry, item)
                            or Exported(detached(item), (), "mesh"))
        self.plain_curves = []  # evaluated objects: not to be kept (see detached)


def detached(item):
    """`item` without its Blender objects, to be kept past this depsgraph: Blender frees evaluated
    objects at its next evaluation, and Python references kept to them are not safe. While the
    viewport's session kept them, Blender 3.4 crashed in about 1 of 8 runs of tests/gui's viewport
    script on a loaded machine (in Python's allocator, on the main thread); without them, in none of 14."""
    return dataclasses.replace(item, obj=None, instancer=None, particle_settings=None)


def identity_of(instance):
    """What names a depsgraph instance from one evaluation to the next: its instancer's and its object's
    original names and its persistent id (an object itself: no instancer, no id)."""
    if not instance.is_instance:
        return "", instance.object.original.name, ()
    return instance.parent.original.name, instance.object.original.name, tuple(instance.persistent_id)


def build_scene(core_module, depsgraph, frame, warn, cancelled=lambda: False):
    """(ppm_core.Scene, camera arguments, PassIndices) of the evaluated depsgraph, seen through the
    scene camera in `frame`. Raises Cancelled as soon as `cancelled()` is true."""
    scene = depsgraph.scene
    if scene.camera is None:
        raise ValueError(f"scene '{scene.name}' has no active camera")
    if scene.render.use_motion_blur:
        warn("motion blur is not rendered: objects and the camera stand where they are at the frame "
             "(Cycles blurs them over the shutter)")
    for message in unrendered.view_layer_features(depsgraph.view_layer, scene):
        warn(message)
    exporter = scene_exporter(core_module, depsgraph, warn, cancelled)
    camera_object = scene.camera.evaluated_get(depsgraph)
    camera_args = camera.camera_arguments(camera_object, frame, warn, scene.ppm.dof_mode)
    exporter.scene.set_camera(**camera_args)
    return exporter.scene, camera_args, exporter.pass_indices()


def export_scene(core_module, depsgraph, warn, cancelled=lambda: False, lights=True):
    """The ppm_core.Scene of the evaluated depsgraph's objects, world and (with `lights`) lights,
    without a camera."""
    return scene_exporter(core_module, depsgraph, warn, cancelled, lights).scene


def scene_exporter(core_module, depsgraph, warn, cancelled=lambda: False, lights=True, world_warn=None,
                   exporter_class=None):
    """The Exporter once it has exported the scene (export_scene): its `scene`, its `materials` for
    updates in place and the count of textures before the world's (export_world). `world_warn`: where
    the world's warnings go (`warn` by default). `exporter_class`: Exporter, or one that keeps the
    core scene in step with later depsgraphs (sync.SyncingExporter: a dynamic core scene, whose BVH
    is built object by object)."""
    exporter_class = exporter_class or Exporter
    core_scene = core_module.Scene()
    core_scene.dynamic = exporter_class.dynamic
    exporter = exporter_class(core_scene, warn, depsgraph.view_layer, depsgraph.scene, lights=lights)
    visit_instances(exporter, depsgraph, cancelled)
    exporter.finish_curves()
    exporter.report_skips()
    exporter.warn_overlapping_media()
    exporter.world_textures = exporter.scene.texture_count  # the world's textures come after this
    world.add_world(exporter.scene, depsgraph.scene.world, world_warn or warn, exporter.attributes,
                    sun_count(depsgraph))
    return exporter


def export_world(core_scene, depsgraph, warn, world_textures, attributes=None):
    """Replaces `core_scene`'s world with the evaluated depsgraph's: the textures from `world_textures`
    on (the last world's) are removed first, so edits leave no textures behind. Its objects, lights
    and BVH stay: the viewport's update when only the world changed."""
    core_scene.remove_textures_from(world_textures)
    world.add_world(core_scene, depsgraph.scene.world, warn, attributes, sun_count(depsgraph))


def sun_count(depsgraph):
    """The sun lamps among the depsgraph's objects."""
    return sum(1 for obj in depsgraph.objects if obj.type == "LIGHT" and obj.data.type == "SUN")


def export_lights(core_scene, depsgraph, warn, cancelled=lambda: False):
    """Replaces `core_scene`'s lights with the evaluated depsgraph's; its objects and world stay (and so
    does its BVH, if built): the viewport's update when only lights changed."""
    core_scene.remove_lights()
    exporter = Exporter(core_scene, warn, depsgraph.view_layer, depsgraph.scene, objects=False)
    visit_instances(exporter, depsgraph, cancelled)
    exporter.report_skips()


def visit_instances(exporter, depsgraph, cancelled):
    for instance in depsgraph.object_instances:
        if cancelled():
            raise Cancelled()
        exporter.visit(instance)
