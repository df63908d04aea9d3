"""What node programs know of an object (Scene.set_object_info): its transform (Texture Coordinate's
Object), its texture space (Generated) and Object Info's Random and Pass Index, as Cycles has them.

Cycles' Random: for an object, Jenkins' hash of a hash of its name; for an instance (particles,
collection instances, geometry nodes), the depsgraph instance's random_id; as a fraction of 2^32 - 1.
"""

import functools

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


MAX_OBJECT_ID = 1 << 24  # the core's limit (kMaxObjectId)


def add_object_info(core_scene, item):
    """Tells the core about object `item` (an Instance) for its materials' node programs (beyond the
    core's limit of ids, its Generated and Object coordinates are the world's)."""
    if item.object_id >= MAX_OBJECT_ID:
        return
    data = getattr(item.obj, "data", None)
    location = tuple(getattr(data, "texspace_location", (0.0, 0.0, 0.0)))
    size = tuple(getattr(data, "texspace_size", (1.0, 1.0, 1.0)))
    core_scene.set_object_info(item.object_id, item.matrix, texspace_location=location, texspace_size=size,
                               random=item.random, pass_index=float(getattr(item.obj, "pass_index", 0)))
