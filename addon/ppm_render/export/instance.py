"""One depsgraph instance as every exporter of an object receives it, so that the light, mesh and
revolve exporters share one shape (as Cycles' sync_light, sync_mesh and sync_camera do): the
evaluated object, a name unique in the core scene (warnings name it), its world matrix, the
object id the core reports for its primitives, Object Info's Random, and for the Attribute node's
instancer attributes the object and particle settings that instanced it."""

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Instance:
    obj: object         # the evaluated Blender object
    name: str
    matrix: np.ndarray  # 4x4 object-to-world, a copy (the depsgraph reuses its records)
    object_id: int
    random: float = 0.0  # Object Info's Random (object_info.py)
    instancer: object = None  # the object whose collection, particles or geometry nodes made it
    particle_settings: object = None  # of the particle system that made it
    persistent_id: tuple = ()  # the depsgraph's id of an instance, the same from one evaluation to the next
