"""A dynamic scene (Scene.dynamic: the BVH built object by object) finds the hits a whole-scene BVH
does, and replace_mesh moves or reshapes one object in place: the scene then renders, bit for bit,
what a scene built afresh with the object there renders, lights from emissive meshes included. Where
it cannot replace, it says why and leaves the scene as it was."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from render_checks import cube_arrays


def soup_scene(dynamic, rng):
    s = ppm_core.Scene()
    s.dynamic = dynamic
    m = s.add_material("grey")
    n = 600
    corners = rng.uniform(-1, 1, size=(n, 1, 3)) + rng.normal(scale=0.08, size=(n, 3, 3))
    for k in range(3):  # three interleaved meshes, then spheres
        part = corners[k::3]
        s.add_mesh(f"m{k}", part.reshape(-1, 3), np.arange(3 * len(part)).reshape(-1, 3), materials=m,
                   object_id=k)
    for i, c in enumerate(rng.uniform(-1, 1, size=(20, 3))):
        s.add_sphere(f"s{i}", tuple(c), 0.05, m, object_id=10 + i)
    return s


def test_a_dynamic_scene_finds_every_hit_a_whole_scene_bvh_does():
    static, dynamic = soup_scene(False, np.random.default_rng(2)), soup_scene(True, np.random.default_rng(2))
    rng = np.random.default_rng(3)
    o = rng.normal(size=(20000, 3))
    o *= 3.0 / np.linalg.norm(o, axis=1)[:, None]
    d = rng.uniform(-1, 1, size=o.shape) - o
    a, b = static.intersect(o, d), dynamic.intersect(o, d)
    for key in ("t", "normal", "primitive", "object"):
        np.testing.assert_array_equal(a[key], b[key])
    assert 0.2 < (a["primitive"] >= 0).mean() < 0.95


BOX_SPOTS = ((0.3, 0.2, -0.6), (-0.4, -0.1, -0.55))  # the small box's centre before and after
LAMP_SPOTS = ((0.0, 0.0, 0.9), (0.25, -0.2, 0.9))    # the emissive panel's centre before and after


def box_arrays(center):
    return cube_arrays(0.2, center)


def panel_arrays(center):
    x, y, z = center
    v = np.array([[x - 0.2, y - 0.2, z], [x + 0.2, y - 0.2, z], [x + 0.2, y + 0.2, z], [x - 0.2, y + 0.2, z]])
    return v, np.array([[0, 2, 1], [0, 3, 2]])  # facing down


def room(box_at, lamp_at, dynamic=True):
    """A closed grey room (its walls one object), a red box and an emissive panel (objects 5, 7)."""
    s = ppm_core.Scene()
    s.dynamic = dynamic
    wall = s.add_material("wall", "diffuse", base_color=(0.6, 0.6, 0.6))
    red = s.add_material("red", "diffuse", base_color=(0.8, 0.1, 0.1))
    lamp = s.add_material("lamp", "diffuse", base_color=(0.0, 0.0, 0.0), emission=(20.0, 20.0, 20.0))
    vertices, triangles = cube_arrays(1.0)
    s.add_mesh("room", vertices, triangles[:, ::-1], materials=wall, object_id=1)  # facing in
    s.add_mesh("box", *box_arrays(box_at), materials=red, object_id=5)
    s.add_mesh("panel", *panel_arrays(lamp_at), materials=lamp, object_id=7)
    s.set_camera(core_scenes.look_at((0.0, -0.9, 0.0), (0.0, 0.0, -0.3)), 32, 24, fov=math.radians(70))
    return s, (wall, red, lamp)


def render(scene):
    r = ppm_core.Renderer(scene, photons_per_pass=4000, seed=9, threads=1)
    r.run(passes=3)
    return r.image()


def test_a_replaced_mesh_renders_as_a_scene_built_with_it_there():
    moved, materials = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    before = render(moved)
    moved.replace_mesh("box", *box_arrays(BOX_SPOTS[1]), materials=materials[1], object_id=5)
    moved.replace_mesh("panel", *panel_arrays(LAMP_SPOTS[1]), materials=materials[2], object_id=7)
    after = render(moved)
    fresh, _ = room(BOX_SPOTS[1], LAMP_SPOTS[1])
    np.testing.assert_array_equal(after, render(fresh))
    assert np.abs(after - before).mean() > 0.01  # the box and the light moved
    # The whole-scene BVH sees the same scene.
    static, _ = room(BOX_SPOTS[1], LAMP_SPOTS[1], dynamic=False)
    np.testing.assert_array_equal(after, render(static))


def test_what_cannot_be_replaced_is_refused_naming_the_mesh_and_the_scene_is_kept():
    scene, (wall, red, lamp) = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    box = dict(materials=red, object_id=5)
    expected = render(scene)
    vertices, triangles = box_arrays(BOX_SPOTS[1])
    refusals = [
        (dict(triangles=triangles[:-1], **box), "has 11 triangles where its object has 12"),
        (dict(triangles=triangles, normals=np.tile([0.0, 0.0, 1.0], (8, 1)), **box), "other attributes"),
        (dict(triangles=triangles, materials=red, object_id=99), "object 99 has no mesh in the scene"),
        (dict(triangles=triangles, materials=99, object_id=5), "material"),
        (dict(triangles=np.full_like(triangles, 8), **box), "uses vertex 8"),
    ]
    for arguments, message in refusals:
        with pytest.raises(ValueError, match=message):
            scene.replace_mesh("box", vertices, **arguments)
    np.testing.assert_array_equal(render(scene), expected)

    spheres = ppm_core.Scene()
    spheres.dynamic = True
    grey = spheres.add_material("grey")
    spheres.add_sphere("ball", (0.0, 0.0, 0.0), 1.0, grey, object_id=3)
    spheres.build()
    spheres.add_mesh("ball's lid", vertices, triangles, materials=grey, object_id=3)
    for built in (False, True):  # (found by scanning, or through the object's BVH slots)
        if built:
            spheres.build()
        with pytest.raises(ValueError, match="not a triangle mesh alone"):
            spheres.replace_mesh("ball", vertices, triangles, materials=grey, object_id=3)
    spheres.add_mesh("another lid", vertices, triangles, materials=grey, object_id=4)
    spheres.add_mesh("a lid in two parts", vertices, triangles, materials=grey, object_id=4)
    spheres.add_mesh("something else", vertices, triangles, materials=grey, object_id=5)
    spheres.add_mesh("a lid in three parts", vertices, triangles, materials=grey, object_id=4)
    for built in (False, True):
        if built:
            spheres.build()
        with pytest.raises(ValueError, match="added by more than one add_mesh"):
            spheres.replace_mesh("lid", vertices, np.vstack([triangles] * 3), materials=grey, object_id=4)


@pytest.mark.parametrize("dynamic", [True, False])
@pytest.mark.parametrize("built", [True, False])
def test_a_mesh_is_replaced_in_any_scene_built_or_not(dynamic, built):
    """Outside a built dynamic scene the BVH is built afresh: the same image."""
    scene, (_, red, _) = room(BOX_SPOTS[0], LAMP_SPOTS[0], dynamic=dynamic)
    if built:
        scene.build()
    scene.replace_mesh("box", *box_arrays(BOX_SPOTS[1]), materials=red, object_id=5)
    fresh, _ = room(BOX_SPOTS[1], LAMP_SPOTS[0], dynamic=dynamic)
    np.testing.assert_array_equal(render(scene), render(fresh))


def test_a_thousand_replacements_keep_the_scene_memory_flat():
    scene, (_, red, _) = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    scene.build()

    def memory():
        return ppm_core.Renderer(scene, photons_per_pass=10).stats()["memory"]["scene"]

    figures = []
    for i in range(1000):
        scene.replace_mesh("box", *box_arrays(BOX_SPOTS[i % 2]), materials=red, object_id=5)
        scene.build()
        if i in (9, 999):
            figures.append(memory())
    assert figures[0] == figures[1]
