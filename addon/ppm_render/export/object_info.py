"""What node programs know of an object (Scene.set_object_info): its transform (Texture Coordinate's
Object), its texture space (Generated), Object Info's Random, Pass Index and Color, and the Attribute
node's object and instancer attributes, as Cycles has them.

Cycles' Random: for an object, Jenkins' hash of a hash of its name; for an instance (particles,
collection instances, geometry nodes), the depsgraph instance's random_id; as a fraction of 2^32 - 1.

Attributes by name (Blender's rule, as its manual states it): a custom property of that name, else
a property at that RNA path ("color" is the viewport display colour); on the object, then on its
data (the mesh); an Instancer attribute first on the particle settings and the object that instances
it. A number is (v, v, v, 1), 1 to 4 numbers fill (0, 0, 0, 1); anything else, or nothing found,
reads 0, alpha too. View Layer attributes are looked up on the view layer, the scene, then its world,
and are constants of the render.
"""

import functools
import math
import numbers

MASK = 0xFFFFFFFF


def _rotate(x, k):
    return ((x << k) | (x >> (32 - k))) & MASK


def hash_uint2(x, y):
    """Bob Jenkins' lookup3 of two words (Cycles' hash_uint2)."""
    a = b = c = (0xDEADBEEF + (2 << 2) + 13) & MASK
    b, a = (b + y) & MASK, (a + x) & MASK
    for rotations in ((14, 11, 25), (16, 4, 14)):
        c ^= b
        c = (c - _rotate(b, rotations[0])) & MASK
        a ^= c
        a = (a - _rotate(c, rotations[1])) & MASK
        b ^= a
        b = (b - _rotate(a, rotations[2])) & MASK
    c ^= b
    return (c - _rotate(b, 24)) & MASK


def hash_string(text):
    """Cycles' hash of a name: h * 37 + byte over its UTF-8 bytes."""
    h = 0
    for byte in text.encode():
        h = (h * 37 + byte) & MASK
    return h


@functools.lru_cache(maxsize=4096)
def random_of_name(name):
    return hash_uint2(hash_string(name), 0) / MASK


def random_of(instance):
    """Object Info's Random for a depsgraph instance, as Cycles computes it."""
    return (instance.random_id & MASK) / MASK if instance.is_instance else random_of_name(instance.object.name)


MAX_OBJECT_ID = (1 << 24) - 1  # the core's limit (kMaxObjectId), less the id worlds are baked for


def rgba(value):
    """A property's value as Cycles reads an attribute from it (see the module's comment), or None."""
    if isinstance(value, (bool, numbers.Real)):
        return (float(value),) * 3 + (1.0,)
    try:
        items = list(value.to_list() if hasattr(value, "to_list") else value)
    except TypeError:
        return None
    if isinstance(value, str) or not 1 <= len(items) <= 4 or not all(isinstance(v, (bool, numbers.Real))
                                                                      for v in items):
        return None
    return tuple(float(v) for v in items) + (0.0, 0.0, 0.0, 1.0)[len(items):]


def property_rgba(owner, name):
    """`owner`'s custom property `name`, else its RNA property at path `name`, as rgba(); or None."""
    if owner is None or not name:
        return None
    try:
        value = owner.get(name)
    except (AttributeError, TypeError):
        value = None
    if value is None:
        try:
            value = owner.path_resolve(name)
        except (ValueError, TypeError, AttributeError):
            return None
    return rgba(value)


def find_rgba(owners, name):
    """The first of `owners` that has attribute `name`, as rgba(); (0, 0, 0, 0) if none has it."""
    for owner in owners:
        found = property_rgba(owner, name)
        if found is not None:
            return found
    return (0.0, 0.0, 0.0, 0.0)


class AttributeTable:
    """The Attribute node's object and instancer attributes of one export, a slot per (type, name)
    that every object's info fills; view-layer ones, constants of the render."""

    def __init__(self, view_layer=None, scene=None):
        self.slots = []
        self.view_layer, self.scene = view_layer, scene

    def slot(self, kind, name):
        """The slot of attribute `name` of type "OBJECT" or "INSTANCER"."""
        if (kind, name) not in self.slots:
            self.slots.append((kind, name))
        return self.slots.index((kind, name))

    def view_layer_value(self, name):
        scene = self.scene
        return find_rgba((self.view_layer, scene, getattr(scene, "world", None)), name)

    def values(self, item):
        """Every slot's value for `item` (an Instance), as (n, 4) rows; non-finite numbers read 0."""
        obj = item.obj
        data = getattr(obj, "data", None)
        rows = []
        for kind, name in self.slots:
            owners = (obj, data)
            if kind == "INSTANCER":
                owners = (item.particle_settings, item.instancer, getattr(item.instancer, "data", None)) + owners
            rows.append([v if math.isfinite(v) else 0.0 for v in find_rgba(owners, name)])
        return rows


def add_object_info(core_scene, item, attributes=None, grids=None, volume_density=1.0):
    """Tells the core about object `item` (an Instance) for its materials' node programs (beyond the
    core's limit of ids, its Generated and Object coordinates are the world's). `attributes`: the
    export's AttributeTable; `grids`: its grids' indices by slot (smoke.SmokeGrids,
    volume_object.VolumeObjects); `volume_density`: volume_object.density_scale's."""
    if item.object_id >= MAX_OBJECT_ID:
        return
    obj = item.obj
    data = getattr(obj, "data", None)
    location = tuple(getattr(data, "texspace_location", (0.0, 0.0, 0.0)))
    size = tuple(getattr(data, "texspace_size", (1.0, 1.0, 1.0)))
    color = [c if math.isfinite(c) else 0.0 for c in tuple(getattr(obj, "color", (1.0, 1.0, 1.0, 1.0)))]
    rows = attributes.values(item) if attributes is not None and attributes.slots else None
    core_scene.set_object_info(item.object_id, item.matrix, texspace_location=location, texspace_size=size,
                               random=item.random, pass_index=float(getattr(obj, "pass_index", 0)), color=color,
                               attributes=rows, grids=grids, volume_density=volume_density)
