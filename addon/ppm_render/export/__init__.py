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

import numpy as np

from . import bezier, camera, light, material, mesh, object_info, world
from .instance import Instance

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME"}
CURVE_TYPES = {"CURVE", "SURFACE", "FONT"}


class Cancelled(Exception):
    """The user pressed Esc during the export."""


class Exporter:
    """State of one export: the core scene, materials, mesh cache, warnings and object ids. `lights`
    and `objects` choose what of the depsgraph's instances it adds; either way every instance gets
    its object id, so that names are the same whatever is exported."""

    def __init__(self, core_scene, warn, view_layer=None, scene=None, lights=True, objects=True):
        self.scene = core_scene
        self.warn = warn
        self.lights, self.objects = lights, objects
        self.attributes = object_info.AttributeTable(view_layer, scene)
        self.materials = material.MaterialExporter(self.scene, warn, self.attributes)
        self.meshes = {}
        self.next_id = 0
        self.triangles = 0
        self.curves_with_mesh = set()
        self.plain_curves = []
        self.skipped = {}  # warning -> number of instances it applies to
        self.placed = {}  # original object name -> (Instance, material names, MeshData); None: an instance
        self.instances = {}  # instance_identity -> the same for an instance's mesh (None: not unique)
        self.instancers = set()  # original names of the objects that made them

    def describe_object(self, item, slots):
        """Object info for the node programs of the object's materials, if any has one."""
        if any(i in self.materials.with_program for i in slots):
            object_info.add_object_info(self.scene, item, self.attributes)

    def object_id(self):
        self.next_id += 1
        return self.next_id - 1

    def slot_materials(self, obj):
        slots = [self.materials.index(slot.material) for slot in obj.material_slots]
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

    def add_geometry(self, item):
        obj = item.obj
        key = self.mesh_key(obj)
        slots = self.slot_materials(obj)
        if key not in self.meshes:
            self.meshes[key] = self.read_mesh(obj, slots)
        data = self.meshes[key]
        self.describe_object(item, slots)
        if data is not None:
            dropped = data.add_to_scene(self.scene, item, slots)
            self.triangles += len(data.triangles) - dropped
            if dropped:
                self.skip(obj, f"{dropped} of its {len(data.triangles)} triangles have a corner that is not "
                               "finite (NaN or Inf); left out")
        name = obj.original.name
        if item.instancer is not None or name in self.placed:
            self.placed[name] = None  # an instance (or one of several): see `instances`
        else:
            self.placed[name] = (detached(item), key[1], data)
        if item.instancer is not None:
            self.instancers.add(item.instancer.original.name)
            identity = instance_identity(item.instancer, obj, item.persistent_id)
            self.instances[identity] = None if identity in self.instances else (detached(item), key[1], data)

    def replace_object(self, obj, reshaped):
        """Moves the evaluated mesh object `obj` to its new matrix in the exported (dynamic) core scene,
        reading its mesh again if `reshaped`, with its object info. False where it cannot (an instance,
        not a mesh, other materials, another triangle count): the scene then needs a whole export.
        Raises ValueError where the core refuses. (The evaluated objects and meshes of earlier
        depsgraphs may be freed: only the object's local mesh arrays are kept, not their addresses.)"""
        placed = self.placed.get(obj.original.name)
        materials = self.mesh_key(obj)[1]
        if placed is None or obj.type != "MESH" or materials != placed[1]:
            return False
        slots = self.slot_materials(obj)
        data = self.read_mesh(obj, slots) if reshaped else placed[2]
        item = dataclasses.replace(placed[0], obj=obj, matrix=np.array(obj.matrix_world, dtype=float))
        if data is None or not data.replace_in_scene(self.scene, item, slots):
            return False
        self.describe_object(item, slots)
        self.placed[obj.original.name] = (detached(item), materials, data)
        return True

    def is_instancer(self, obj):
        """Does the evaluated object `obj` make instances of exported meshes?"""
        return obj.original.name in self.instancers

    def is_placed(self, obj):
        """Is the evaluated object `obj` exported as one mesh of its own (replace_object)?"""
        return self.placed.get(obj.original.name) is not None

    def replace_instances(self, depsgraph, reshaped):
        """Puts every exported mesh instance whose matrix changed at its new one (reading the mesh again
        where its object's or its instancer's original name is in `reshaped`); False where the instances
        are not the exported ones (added, gone, or not unique): the scene then needs a whole export."""
        seen, meshes = set(), {}
        for instance in depsgraph.object_instances:
            if not instance.is_instance or instance.object.type not in GEOMETRY_TYPES:
                continue
            obj, instancer = instance.object, instance.parent
            identity = instance_identity(instancer, obj, tuple(instance.persistent_id))
            placed = self.instances.get(identity)
            if placed is None or identity in seen:
                return False
            seen.add(identity)
            item, materials, data = placed
            matrix = np.array(instance.matrix_world, dtype=float)
            fresh = obj.original.name in reshaped or instancer.original.name in reshaped
            if not fresh and (data is None or np.array_equal(matrix, item.matrix)):
                continue  # unmoved, or without triangles to move
            key, slots = self.mesh_key(obj), self.slot_materials(obj)
            if key[1] != materials:
                return False
            if fresh:  # read once for the instances sharing it
                if key not in meshes:
                    meshes[key] = self.read_mesh(obj, slots)
                data = meshes[key]
            item = dataclasses.replace(item, obj=obj, matrix=matrix, instancer=instancer,
                                       particle_settings=getattr(instance.particle_system, "settings", None))
            if data is None or not data.replace_in_scene(self.scene, item, slots):
                return False
            self.describe_object(item, slots)
            self.instances[identity] = (detached(item), materials, data)
        return len(seen) == len(self.instances)

    def add_revolve(self, item):
        slots = self.slot_materials(item.obj)
        index = self.materials.without_emission(slots[0], f"'{item.name}'")
        self.describe_object(item, slots)
        bezier.add_revolve(self.scene, item, index, self.warn)

    def skip(self, obj, what):
        """Notes a warning about `obj` (once per object, counting its instances)."""
        kind = "light" if obj.type == "LIGHT" else "object"
        message = f"{kind} '{obj.original.name}': {what}"
        self.skipped[message] = self.skipped.get(message, 0) + 1

    def report_skips(self):
        for message, count in self.skipped.items():
            self.warn(message + (f" (in {count} instances)" if count > 1 else ""))

    def guarded(self, obj, export, *args):
        """Runs export(*args); what the core refuses about `obj` is left out with a warning."""
        try:
            export(*args)
        except ValueError as error:  # the core's message starts with the name this module gave it
            self.skip(obj, "not rendered: " + re.sub(r"^[a-z ]+ '[^']*': ", "", str(error), count=1))

    def visit(self, instance):
        """Exports one depsgraph instance."""
        self.guarded(instance.object, self.visit_unchecked, instance)

    def visit_unchecked(self, instance):
        obj = instance.object
        # For an instance: the object instanced (a curve lists its own evaluated mesh so) and the
        # object instancing it (an empty with a collection, a particle or Geometry Nodes host).
        instanced = instance.instance_object if instance.is_instance else None
        instancer = instance.parent if instance.is_instance else None
        object_id = self.object_id()
        name = obj.name if instanced is None else f"{instanced.name}/{obj.name}.{object_id}"
        particles = getattr(instance.particle_system, "settings", None) if instance.is_instance else None
        item = Instance(obj, name, np.array(instance.matrix_world, dtype=float), object_id,
                        object_info.random_of(instance), instancer, particles,
                        tuple(instance.persistent_id) if instance.is_instance else ())
        if obj.type == "LIGHT":
            if self.lights:
                light.add_light(self.scene, item, self.warn)
        elif not self.objects:
            return
        elif instanced is not None and instanced.type in CURVE_TYPES and instanced.original == obj.original:
            # The evaluated geometry of a curve, listed as a MESH instance of the curve itself.
            self.curves_with_mesh.add(instanced.original.name)
            if not bezier.is_revolve(instanced):
                self.add_geometry(item)
        elif bezier.is_revolve(obj):
            self.add_revolve(item)
        elif obj.type in CURVE_TYPES and instanced is None:
            self.plain_curves.append(item)  # exported later unless a MESH instance shows up
        elif obj.type in GEOMETRY_TYPES:
            if instanced is None and not getattr(instance, "show_self", True):
                return
            self.add_geometry(item)

    def finish_curves(self):
        for item in self.plain_curves:
            if item.obj.original.name not in self.curves_with_mesh:
                self.guarded(item.obj, self.add_geometry, item)


def detached(item):
    """`item` without its Blender objects, to be kept past this depsgraph: Blender frees evaluated
    objects at its next evaluation, and Python references kept to them are not safe. While the
    viewport's session kept them, Blender 3.4 crashed in about 1 of 8 runs of tests/gui's viewport
    script on a loaded machine (in Python's allocator, on the main thread); without them, in none of 14."""
    return dataclasses.replace(item, obj=None, instancer=None, particle_settings=None)


def instance_identity(instancer, obj, persistent_id):
    """What names a depsgraph instance from one evaluation to the next: its instancer's and its object's
    original names and its persistent id."""
    return instancer.original.name, obj.original.name, persistent_id


def build_scene(core_module, depsgraph, frame, warn, cancelled=lambda: False):
    """(ppm_core.Scene, camera arguments) of the evaluated depsgraph, seen through the scene camera in
    `frame`. Raises Cancelled as soon as `cancelled()` is true."""
    scene = depsgraph.scene
    if scene.camera is None:
        raise ValueError(f"scene '{scene.name}' has no active camera")
    if scene.render.use_motion_blur:
        warn("motion blur is not rendered: objects and the camera stand where they are at the frame "
             "(Cycles blurs them over the shutter)")
    core_scene = export_scene(core_module, depsgraph, warn, cancelled)
    camera_object = scene.camera.evaluated_get(depsgraph)
    camera_args = camera.camera_arguments(camera_object, frame, warn, scene.ppm.dof_mode)
    core_scene.set_camera(**camera_args)
    return core_scene, camera_args


def export_scene(core_module, depsgraph, warn, cancelled=lambda: False, lights=True):
    """The ppm_core.Scene of the evaluated depsgraph's objects, world and (with `lights`) lights,
    without a camera."""
    return scene_exporter(core_module, depsgraph, warn, cancelled, lights).scene


def scene_exporter(core_module, depsgraph, warn, cancelled=lambda: False, lights=True, world_warn=None,
                   dynamic=False):
    """The Exporter once it has exported the scene (export_scene): its `scene`, its `materials` for
    updates in place and the count of textures before the world's (export_world). `world_warn`: where
    the world's warnings go (`warn` by default). `dynamic`: a core scene whose objects can be moved in
    place afterwards (Exporter.replace_object; its BVH is built object by object)."""
    core_scene = core_module.Scene()
    core_scene.dynamic = dynamic
    exporter = Exporter(core_scene, warn, depsgraph.view_layer, depsgraph.scene, lights=lights)
    visit_instances(exporter, depsgraph, cancelled)
    exporter.finish_curves()
    exporter.plain_curves = []  # evaluated objects: not to be kept (see detached)
    exporter.report_skips()
    exporter.world_textures = exporter.scene.texture_count  # the world's textures come after this
    world.add_world(exporter.scene, depsgraph.scene.world, world_warn or warn, exporter.attributes)
    return exporter


def export_world(core_scene, depsgraph, warn, world_textures, attributes=None):
    """Replaces `core_scene`'s world with the evaluated depsgraph's: the textures from `world_textures`
    on (the last world's) are removed first, so edits leave no textures behind. Its objects, lights
    and BVH stay: the viewport's update when only the world changed."""
    core_scene.remove_textures_from(world_textures)
    world.add_world(core_scene, depsgraph.scene.world, warn, attributes)


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
