"""A dynamic scene (Scene.dynamic: the BVH built object by object) finds the hits a whole-scene BVH
does, and a built one takes edits at the cost of the objects edited: replace_mesh moves or reshapes an
object (with any number of triangles), add_mesh, add_sphere and add_bezier_revolve add objects and
remove_object removes them. The scene then renders, bit for bit, what a scene built afresh with the
objects there renders, lights from emissive meshes included, and its build() builds the BVH subtrees
of the edited objects alone. Where it cannot replace, it says why and leaves the scene as it was."""

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


@pytest.mark.parametrize("layout", ["copies", "compact"])
def test_a_replaced_mesh_renders_as_a_scene_built_with_it_there(layout):
    moved, materials = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    moved.geometry_layout = layout
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
        (dict(triangles=triangles, materials=red, object_id=99), "object 99 has no mesh in the scene"),
        (dict(triangles=triangles, materials=99, object_id=5), "material"),
        (dict(triangles=np.full_like(triangles, 8), **box), "uses vertex 8"),
        (dict(triangles=triangles[:0], **box), "has no triangles"),
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


def test_a_mesh_added_in_parts_is_replaced_whole_where_its_first_part_was():
    """Object 4's triangles come from three add_mesh calls with another object's between them."""
    vertices, triangles = box_arrays((0.0, 0.0, 0.0))

    def lids(parts_of_4):
        s = ppm_core.Scene()
        s.dynamic = True
        grey = s.add_material("grey")
        s.add_mesh("lid", vertices, np.vstack([triangles] * parts_of_4), materials=grey, object_id=4)
        s.add_mesh("something else", vertices + 2.0, triangles, materials=grey, object_id=5)
        return s, grey

    scene, grey = lids(1)
    scene.add_mesh("a lid's second part", vertices, triangles, materials=grey, object_id=4)
    scene.build()
    scene.replace_mesh("lid", vertices, np.vstack([triangles] * 2), materials=grey, object_id=4)
    scene.build()
    fresh, _ = lids(2)
    fresh.build()
    origins = np.array([[0.0, 0.0, 3.0], [2.0, 2.0, 5.0]])
    hits, expected = scene.intersect(origins, [[0, 0, -1.0]] * 2), fresh.intersect(origins, [[0, 0, -1.0]] * 2)
    for key in ("t", "primitive", "object"):
        np.testing.assert_array_equal(hits[key], expected[key])
    assert scene.primitive_count == fresh.primitive_count == 36


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


def panel_with_uvs(center, rows):
    """The emissive panel as a grid of rows x rows quads, with UVs (another count and other attributes)."""
    x, y, z = center
    u, v = np.meshgrid(np.linspace(0, 1, rows + 1), np.linspace(0, 1, rows + 1))
    vertices = np.stack([x - 0.2 + 0.4 * u.ravel(), y - 0.2 + 0.4 * v.ravel(), np.full(u.size, z)], axis=1)
    quads = [(i * (rows + 1) + j, i * (rows + 1) + j + 1, (i + 1) * (rows + 1) + j + 1, (i + 1) * (rows + 1) + j)
             for i in range(rows) for j in range(rows)]
    triangles = np.array([t for a, b, c, d in quads for t in ((a, c, b), (a, d, c))])  # facing down
    return dict(positions=vertices, triangles=triangles, uvs=np.stack([u.ravel(), v.ravel()], axis=1))


def test_a_mesh_reshaped_with_other_triangles_renders_as_a_scene_built_with_it_and_builds_only_its_subtree():
    scene, (_, _, lamp) = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    scene.build()
    assert scene.subtrees_built == 3
    scene.replace_mesh("panel", **panel_with_uvs(LAMP_SPOTS[1], 3), materials=lamp, object_id=7)
    scene.build()
    assert scene.subtrees_built == 1 and scene.primitive_count == 12 + 12 + 18

    fresh = ppm_core.Scene()
    fresh.dynamic = True
    wall = fresh.add_material("wall", "diffuse", base_color=(0.6, 0.6, 0.6))
    red = fresh.add_material("red", "diffuse", base_color=(0.8, 0.1, 0.1))
    fresh_lamp = fresh.add_material("lamp", "diffuse", base_color=(0.0, 0.0, 0.0), emission=(20.0, 20.0, 20.0))
    vertices, triangles = cube_arrays(1.0)
    fresh.add_mesh("room", vertices, triangles[:, ::-1], materials=wall, object_id=1)
    fresh.add_mesh("box", *box_arrays(BOX_SPOTS[0]), materials=red, object_id=5)
    fresh.add_mesh("panel", **panel_with_uvs(LAMP_SPOTS[1], 3), materials=fresh_lamp, object_id=7)
    fresh.set_camera(core_scenes.look_at((0.0, -0.9, 0.0), (0.0, 0.0, -0.3)), 32, 24, fov=math.radians(70))
    np.testing.assert_array_equal(render(scene), render(fresh))
    # And back to the two triangles without UVs: the same as the room built so.
    scene.replace_mesh("panel", *panel_arrays(LAMP_SPOTS[0]), materials=lamp, object_id=7)
    np.testing.assert_array_equal(render(scene), render(room(BOX_SPOTS[0], LAMP_SPOTS[0])[0]))


def revolve_points():
    return [(0.0, 0.0), (0.1, 0.0), (0.1, 0.1), (0.0, 0.15)]


def test_objects_added_to_and_removed_from_a_built_scene_render_as_a_scene_built_with_them():
    """A cube, a sphere and a revolve added to the built room, then the box and the revolve removed."""
    def add_extras(s, materials):
        s.add_mesh("cube", *cube_arrays(0.1, (-0.3, 0.3, -0.8)), materials=materials[1], object_id=20)
        s.add_sphere("ball", (0.35, 0.35, -0.8), 0.12, materials[0], object_id=21)
        m = np.eye(4)
        m[:3, 3] = (0.0, 0.4, -1.0)
        s.add_bezier_revolve("vase", revolve_points(), matrix=m, material=materials[0], object_id=22)

    scene, materials = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    before = render(scene)
    add_extras(scene, materials)
    scene.build()
    assert scene.subtrees_built == 3  # the room, the box and the panel kept theirs
    fresh, fresh_materials = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    add_extras(fresh, fresh_materials)
    added = render(scene)
    np.testing.assert_array_equal(added, render(fresh))
    assert np.abs(added - before).mean() > 0.005

    assert scene.remove_object(5) == 12 and scene.remove_object(22) >= 1
    assert scene.remove_object(99) == 0
    scene.build()
    assert scene.subtrees_built == 0
    for object_id in (5, 22):
        assert fresh.remove_object(object_id) > 0
    rebuilt = ppm_core.Scene()  # removing in an unbuilt scene, or not adding at all: the same
    rebuilt.dynamic = True
    for name, kind, color in (("wall", "diffuse", (0.6, 0.6, 0.6)), ("red", "diffuse", (0.8, 0.1, 0.1))):
        rebuilt.add_material(name, kind, base_color=color)
    rebuilt.add_material("lamp", "diffuse", base_color=(0.0, 0.0, 0.0), emission=(20.0, 20.0, 20.0))
    vertices, triangles = cube_arrays(1.0)
    rebuilt.add_mesh("room", vertices, triangles[:, ::-1], materials=0, object_id=1)
    rebuilt.add_mesh("panel", *panel_arrays(LAMP_SPOTS[0]), materials=2, object_id=7)
    rebuilt.add_mesh("cube", *cube_arrays(0.1, (-0.3, 0.3, -0.8)), materials=1, object_id=20)
    rebuilt.add_sphere("ball", (0.35, 0.35, -0.8), 0.12, 0, object_id=21)
    rebuilt.set_camera(core_scenes.look_at((0.0, -0.9, 0.0), (0.0, 0.0, -0.3)), 32, 24, fov=math.radians(70))
    removed = render(scene)
    np.testing.assert_array_equal(removed, render(fresh))
    np.testing.assert_array_equal(removed, render(rebuilt))


def random_edit(rng, live, next_id):
    """One random edit as (method, arguments): an object added (a mesh or a sphere), removed or given
    another mesh. `live`: object id -> "mesh" or "sphere", kept up to date. Returns it and the next id."""
    kind = int(rng.integers(3)) if live else 0
    n = int(rng.integers(1, 40))
    corners = rng.uniform(-1, 1, size=(1, 3)) + rng.normal(scale=0.1, size=(n, 3, 3))
    mesh = dict(positions=corners.reshape(-1, 3), triangles=np.arange(3 * n).reshape(-1, 3), materials=0)
    if kind == 0 and rng.random() < 0.2:
        live[next_id] = "sphere"
        return ("add_sphere", dict(name=f"s{next_id}", center=tuple(rng.uniform(-1, 1, 3)), radius=0.05,
                                   material=0, object_id=next_id)), next_id + 1
    if kind == 0:
        live[next_id] = "mesh"
        return ("add_mesh", dict(name=f"m{next_id}", object_id=next_id, **mesh)), next_id + 1
    meshes = [k for k, v in live.items() if v == "mesh"]
    if kind == 1 or not meshes:
        object_id = list(live)[int(rng.integers(len(live)))]
        del live[object_id]
        return ("remove_object", dict(object_id=object_id)), next_id
    object_id = meshes[int(rng.integers(len(meshes)))]
    return ("replace_mesh", dict(name=f"m{object_id}", object_id=object_id, **mesh)), next_id


@pytest.mark.parametrize("layout", ["copies", "compact"])
def test_random_edits_of_a_built_dynamic_scene_find_the_hits_of_a_scene_built_afresh(layout):
    """The same edits applied to a dynamic scene (its BVH kept object by object; its triangles copied
    beside it or not) and to a static one (built afresh at every build)."""
    rng = np.random.default_rng(11)
    dynamic, static = soup_scene(True, np.random.default_rng(2)), soup_scene(False, np.random.default_rng(2))
    dynamic.geometry_layout = layout
    live, next_id = {k: "mesh" for k in range(3)}, 100
    live.update({10 + i: "sphere" for i in range(20)})
    o = rng.normal(size=(3000, 3))
    o *= 3.0 / np.linalg.norm(o, axis=1)[:, None]
    d = rng.uniform(-1, 1, size=o.shape) - o
    dynamic.build()
    rebuilt = []
    for _ in range(60):
        for _ in range(int(rng.integers(1, 4))):
            (method, arguments), next_id = random_edit(rng, live, next_id)
            results = [getattr(s, method)(**arguments) for s in (dynamic, static)]
            assert results[0] == results[1]
        dynamic.build()
        rebuilt.append(dynamic.subtrees_built)
        a, b = dynamic.intersect(o, d), static.intersect(o, d)
        for key in ("t", "primitive", "object"):
            np.testing.assert_array_equal(a[key], b[key])
    assert len(live) > 5 and max(rebuilt) <= 3  # the edited objects' subtrees alone


def test_a_thousand_objects_added_and_removed_keep_the_scene_memory_flat():
    scene, (_, red, _) = room(BOX_SPOTS[0], LAMP_SPOTS[0])
    scene.build()

    def memory():
        return ppm_core.Renderer(scene, photons_per_pass=10).stats()["memory"]["scene"]

    figures = []
    for i in range(1000):
        scene.add_mesh("cube", *cube_arrays(0.1, (0.0, 0.3, -0.8)), materials=red, object_id=100 + i)
        scene.build()
        assert scene.remove_object(100 + i) == 12
        scene.replace_mesh("box", *(box_arrays(BOX_SPOTS[0]) if i % 2 else panel_arrays(BOX_SPOTS[1])),
                           materials=red, object_id=5)
        scene.build()
        if i in (9, 999):
            figures.append(memory())
    assert figures[0] == figures[1]
