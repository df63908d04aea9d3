"""The viewport's exported scene kept in step with the depsgraph: objects moved, reshaped, added and
removed in the dynamic core scene in place, without exporting the rest again (viewport.py)."""

import dataclasses

import numpy as np

from . import UNRENDERED_TYPES, Exported, Exporter, detached, identity_of


class SyncingExporter(Exporter):
    """An Exporter whose core scene is dynamic (its BVH built object by object), brought up to later
    depsgraphs by update_placed and sync."""

    dynamic = True

    def is_placed(self, obj):
        """Is the evaluated object `obj` exported on its own, neither instanced nor instancing (so that
        moving or reshaping it changes nothing else: update_placed)?"""
        record = self.exported.get(("", obj.original.name, ()))
        return record is not None and record.kind == "mesh" and obj.original.name not in self.instanced

    def update_placed(self, objects, reshaped, warn):
        """Moves the evaluated mesh objects `objects` (each is_placed) to their new matrices in the exported
        dynamic core scene, reading a mesh again where its object's original name is in `reshaped` or its
        materials changed; warnings about them go to `warn`. Raises ValueError where the core refuses.
        (The evaluated objects and meshes of earlier depsgraphs may be freed: only the objects' local mesh
        arrays are kept, not their addresses.)"""
        self.begin_update(warn)
        for obj in objects:
            identity = ("", obj.original.name, ())
            self.touched.add(obj.original.name)
            self.update(identity, self.exported[identity], obj, np.array(obj.matrix_world, dtype=float), None, None,
                        obj.original.name in reshaped)
        self.report_skips()

    def begin_update(self, warn):
        """Before an update in place: this depsgraph's meshes and warnings, which go to `warn`."""
        self.warn = self.materials.warn = warn
        self.meshes, self.skipped, self.touched = {}, {}, set()

    def update(self, identity, record, obj, matrix, instancer, particles, fresh):
        """Brings an exported instance to `matrix`, its mesh read again if `fresh` or its materials changed;
        returns whether it changed anything. Raises ValueError where the core refuses."""
        item = dataclasses.replace(record.item, obj=obj, matrix=matrix, instancer=instancer,
                                   particle_settings=particles)
        materials = self.mesh_key(obj)[1]
        unchanged = not fresh and materials == record.materials
        if record.kind == "none" or (unchanged and np.array_equal(matrix, record.item.matrix)):
            return False
        if record.kind in ("revolve", "volume"):
            self.scene.remove_object(item.object_id)
            self.exported[identity] = (self.add_revolve if record.kind == "revolve" else self.add_volume)(item)
            return True
        slots = self.slot_materials(obj)
        data = record.data if unchanged else self.mesh_of(obj, slots)
        self.describe_object(item, slots)
        added = self.put_mesh(data, item, slots, record.added)
        self.exported[identity] = Exported(detached(item), materials, "mesh", data, added)
        return True

    def sync(self, depsgraph, reshaped, warn):
        """Brings the exported dynamic core scene's objects up to the evaluated depsgraph in place: what is
        new is exported, what is gone removed, what moved put at its matrix, with its mesh read again
        where its object's or its instancer's original name is in `reshaped` or its materials changed.
        Warnings about them go to `warn`, and `touched` names the objects whose earlier warnings are stale.
        Lights are left to export_lights. False where an instance's identity is not unique, a new material
        reads an object attribute none read before, or the core refuses: the scene then needs a whole
        export."""
        self.begin_update(warn)
        self.curves_with_mesh, self.instanced = set(), set()
        attribute_slots = len(self.attributes.slots)
        seen = set()
        try:
            for instance in depsgraph.object_instances:
                role = self.role(instance)
                if role == "unrendered":
                    self.skip(instance.object, UNRENDERED_TYPES[instance.object.type])
                if role in (None, "light", "unrendered"):
                    continue
                identity = identity_of(instance)
                if identity in seen or (identity in self.exported and self.exported[identity] is None):
                    return False
                seen.add(identity)
                record = self.exported.get(identity)
                if record is None or (record.kind != role and role != "curve"):
                    self.touched.add(instance.object.original.name)
                    if record is not None:  # another kind of object now (a curve made a revolve, say)
                        self.scene.remove_object(self.exported.pop(identity).item.object_id)
                    self.visit(instance, role)
                    continue
                obj, instancer = instance.object, instance.parent if instance.is_instance else None
                names = {obj.original.name} | ({instancer.original.name} if instancer is not None else set())
                if instancer is not None:
                    self.instanced |= names
                particles = getattr(instance.particle_system, "settings", None) if instancer is not None else None
                if self.update(identity, record, obj, np.array(instance.matrix_world, dtype=float), instancer,
                               particles, bool(names & reshaped)):
                    self.touched.add(obj.original.name)
            self.finish_curves()
            for identity in set(self.exported) - seen:
                self.touched.add(identity[1])
                self.scene.remove_object(self.exported.pop(identity).item.object_id)
        except ValueError:
            return False
        self.report_skips()
        return len(self.attributes.slots) == attribute_slots
