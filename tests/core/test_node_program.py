"""Node programs through ppm_core: a material's inputs computed per shading point (Scene.add_material
with `program`, Scene.run_program), object info for Generated and Object coordinates, a program's
normal, its textured emission lighting the scene, and bad programs refused with a message. Value
for value agreement with Cycles is tests/blenders/nodes_compare.py's."""

import numpy as np
import pytest

import ppm_core

MODES = ppm_core.node_modes()


def op(name, mode=0, ins=(), out=(), **fields):
    """An instruction; `mode` a name of node_modes()[name] or a number."""
    if isinstance(mode, str):
        mode = MODES[name].index(mode)
    return {"op": name, "mode": mode, "in": list(ins), "out": list(out), **fields}


def checker_program(scale=2.0, first=(0.9, 0.1, 0.1), second=(0.1, 0.1, 0.9)):
    """A Checker texture of the Generated coordinates: registers 1-3 constants."""
    return {"constants": [first, second, (scale,) * 3],
            "code": [op("coord", "generated", out=[4]), op("checker", ins=[4, 1, 2, 3], out=[5, 6])],
            "outputs": [5], "registers": 7}


def test_modes_name_every_operation_the_compiler_uses():
    assert MODES["math"][:4] == ["add", "subtract", "multiply", "divide"] and len(MODES["math"]) == 41
    assert "soft_light" in MODES["mix"] and "generated" in MODES["coord"] and "f1" in MODES["voronoi"]


def test_generated_and_object_coordinates_come_from_the_objects_texture_space_and_transform():
    scene = ppm_core.Scene()
    matrix = np.eye(4)
    matrix[:3, :3] *= 2.0
    matrix[:3, 3] = (1.0, 0.0, 0.0)  # object space: world shrunk by 2 about (1, 0, 0)
    scene.set_object_info(3, matrix, texspace_location=(0.0, 0.0, 0.0), texspace_size=(1.0, 1.0, 1.0))
    program = {"code": [op("coord", "generated", out=[1]), op("coord", "object", out=[2])], "outputs": [1, 2],
               "registers": 3}
    points = np.array([[1.0, 0.0, 0.0], [3.0, 2.0, -2.0]])
    out = scene.run_program(program, points, object=3)
    np.testing.assert_allclose(out[:, 1], [[0.0, 0.0, 0.0], [1.0, 1.0, -1.0]], atol=1e-6)  # Object
    np.testing.assert_allclose(out[:, 0], [[0.5, 0.5, 0.5], [1.0, 1.0, 0.0]], atol=1e-6)  # Generated
    # An object never described: at the origin, unscaled, texture space [-1, 1].
    np.testing.assert_allclose(scene.run_program(program, points, object=9)[1, 0], [2.0, 1.5, -0.5], atol=1e-6)
    # Scaled to nothing along an axis, an object still has coordinates (from its origin).
    matrix[2, 2] = 0.0
    scene.set_object_info(4, matrix)
    assert np.all(np.isfinite(scene.run_program(program, points, object=4)))


def test_object_color_and_attributes_are_read_per_object_by_slot():
    scene = ppm_core.Scene()
    scene.set_object_info(2, np.eye(4), color=(0.1, 0.2, 0.3, 0.4), attributes=[(1, 2, 3, 4), (0.5, 0.5, 0.5, 1)])
    program = {"code": [op("coord", "object_color", out=[1]), op("coord", "object_alpha", out=[2]),
                        op("coord", "object_attribute", out=[3], data=1),
                        op("coord", "object_attribute_mean", out=[4], data=0),
                        op("coord", "object_attribute_alpha", out=[5], data=0),
                        op("coord", "object_attribute", out=[6], data=7)],  # a slot the object lacks
               "outputs": [1, 2, 3, 4, 5, 6], "registers": 7}
    out = scene.run_program(program, np.zeros((1, 3)), object=2)[0]
    np.testing.assert_allclose(out, [[0.1, 0.2, 0.3], [0.4] * 3, [0.5] * 3, [2.0] * 3, [4.0] * 3, [0.0] * 3],
                               atol=1e-6)
    plain = scene.run_program(program, np.zeros((1, 3)), object=5)[0]  # never described: white, no attributes
    np.testing.assert_allclose(plain, [[1.0] * 3, [1.0] * 3] + [[0.0] * 3] * 4, atol=1e-6)
    with pytest.raises(ValueError, match="finite"):
        scene.set_object_info(3, np.eye(4), attributes=[(np.nan, 0, 0, 1)])


def test_the_world_object_id_is_kept_apart_from_the_table_of_objects():
    """A world's network is baked for object 2^24 - 1 (export/world.py); that id must not make a
    table of 2^24 objects (5 GB and 18 s, as it once did)."""
    import resource

    world = (1 << 24) - 1
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB
    scene = ppm_core.Scene()
    scene.set_object_info(world, np.eye(4), texspace_location=(1.0, 1.0, 1.0), texspace_size=(1.0, 1.0, 1.0))
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 100_000
    program = {"code": [op("coord", "generated", out=[1])], "outputs": [1], "registers": 2}
    points = np.array([[1.0, 2.0, 3.0]])
    np.testing.assert_allclose(scene.run_program(program, points, object=world)[0, 0], [0.5, 1.0, 1.5], atol=1e-6)
    np.testing.assert_allclose(scene.run_program(program, points, object=7)[0, 0], [1.0, 1.5, 2.0], atol=1e-6)
    with pytest.raises(ValueError, match="go up to"):
        scene.set_object_info(world + 1, np.eye(4))


def quad_scene(program, coloured=True, **material):
    """A 2 x 2 m quad at z = 0 (object 0, texture space its own) seen from above: diffuse, its colour
    the program's first output if `coloured`, else white."""
    scene = ppm_core.Scene()
    lobes = [{"kind": "diffuse", "color": 1.0, **({"color_input": 0} if coloured else {})}]
    mat = scene.add_material("quad", "mixture", lobes=lobes, program=program, **material)
    corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    scene.add_mesh("quad", corners, np.array([[0, 1, 2], [0, 2, 3]]), uvs=(corners[:, :2] + 1) / 2,
                   materials=mat, object_id=0)
    scene.set_object_info(0, np.eye(4), texspace_location=(0, 0, 0), texspace_size=(1, 1, 1))
    camera = np.eye(4)
    camera[2, 3] = 2.0
    scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=2.0)
    return scene


def test_a_checker_program_colours_a_diffuse_surface_cell_by_cell():
    scene = quad_scene(checker_program())
    scene.add_light("sun", power=np.pi, direction=(0.0, 0.0, -1.0))  # radiance = albedo exactly
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=1)
    renderer.run(passes=4)
    image = renderer.image()[..., :3]
    # Generated runs 0..1 across the quad, scale 2: four cells of 8 x 8 pixels.
    top_left, top_right = image[2:6, 2:6].mean(axis=(0, 1)), image[2:6, 10:14].mean(axis=(0, 1))
    assert top_left == pytest.approx((0.1, 0.1, 0.9), abs=0.02) or top_left == pytest.approx((0.9, 0.1, 0.1), abs=0.02)
    assert not np.allclose(top_left, top_right, atol=0.2)  # neighbouring cells differ
    np.testing.assert_allclose(image[2:6, 2:6].mean(axis=(0, 1)), image[10:14, 10:14].mean(axis=(0, 1)), atol=0.02)


def test_a_colour_the_program_cannot_bound_is_kept_an_albedo():
    # UV * 3 on a diffuse colour: up to 3, which would make light; the core keeps it within [0, 1].
    program = {"constants": [(3.0,) * 3], "code": [op("coord", "uv", out=[2]), op("vector_math", "multiply",
                                                                                  ins=[2, 1, 1, 1], out=[3, 0])],
               "outputs": [3], "registers": 4}
    scene = quad_scene(program)
    scene.add_light("sun", power=np.pi, direction=(0.0, 0.0, -1.0))
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=1)
    renderer.run(passes=2)
    assert renderer.image()[..., :3].max() <= 1.02


def test_a_programs_emission_lights_as_its_mean():
    # Emission of a checker of 0 and 2 (cells of the quad): the floor below gets the light of 1.
    def floor_light(program, emission):
        scene = ppm_core.Scene()
        lamp = scene.add_material("lamp", "emission", base_color=(0, 0, 0), emission=(emission,) * 3,
                                  program=program, emission_input=0 if program else -1)
        floor = scene.add_material("floor", base_color=(0.5, 0.5, 0.5))
        quad = np.array([[-0.5, -0.5, 1.0], [0.5, -0.5, 1.0], [0.5, 0.5, 1.0], [-0.5, 0.5, 1.0]])
        scene.add_mesh("lamp", quad, np.array([[0, 2, 1], [0, 3, 2]]), materials=lamp, object_id=1)
        scene.set_object_info(1, np.eye(4), texspace_location=(0, 0, 1), texspace_size=(0.5, 0.5, 1))
        ground = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], dtype=float)
        scene.add_mesh("floor", ground, np.array([[0, 1, 2], [0, 2, 3]]), materials=floor, object_id=2)
        camera = np.eye(4)
        camera[2, 3] = 3.0
        scene.set_camera(camera, 24, 24, projection="orthographic", ortho_scale=4.0)
        renderer = ppm_core.Renderer(scene, photons_per_pass=50_000, threads=2, seed=4)
        renderer.run(passes=6)
        image = renderer.image()[..., :3].mean(axis=2)
        around = np.ones(image.shape, bool)
        around[6:18, 6:18] = False
        return image[around].mean()

    textured = floor_light(checker_program(4.0, (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)), 2.0)
    assert textured == pytest.approx(floor_light(None, 1.0), rel=0.05)


LIGHT_PATH = ("is_camera_ray", "is_shadow_ray", "is_diffuse_ray", "is_glossy_ray", "is_reflection_ray",
              "is_transmission_ray", "ray_depth")


@pytest.mark.parametrize("ray, expected", [
    ("camera", (1, 0, 0, 0, 0, 0, 0)), ("diffuse", (0, 0, 1, 0, 1, 0, 1)), ("glossy", (0, 0, 0, 1, 1, 0, 1)),
    ("transmission", (0, 0, 0, 1, 0, 1, 1)), ("shadow", (0, 1, 0, 0, 0, 0, 1)), ("emission", (0,) * 7)])
def test_light_path_outputs_follow_cycles_flags_for_each_kind_of_ray(ray, expected):
    # Cycles: a refraction is a glossy transmission; diffuse and glossy bounces are reflections.
    program = {"code": [op("coord", name, out=[i + 1]) for i, name in enumerate(LIGHT_PATH)],
               "outputs": list(range(1, 8)), "registers": 8}
    out = ppm_core.Scene().run_program(program, np.zeros((1, 3)), ray=ray)
    assert tuple(out[0, :, 0]) == expected


def test_an_emitter_hidden_from_camera_rays_by_light_path_still_lights_the_floor():
    # The artists' trick: emission times (1 - Is Camera Ray). The camera sees black where the lamp is,
    # its photons (emission sampled at the light) light the floor as a plain lamp does.
    def render(program):
        scene = ppm_core.Scene()
        lamp = scene.add_material("lamp", "emission", base_color=(0, 0, 0), emission=(1.0,) * 3, program=program,
                                  emission_input=0 if program else -1)
        floor = scene.add_material("floor", base_color=(0.5, 0.5, 0.5))
        quad = np.array([[-0.5, -0.5, 1.0], [0.5, -0.5, 1.0], [0.5, 0.5, 1.0], [-0.5, 0.5, 1.0]])
        scene.add_mesh("lamp", quad, np.array([[0, 2, 1], [0, 3, 2]]), materials=lamp, object_id=1)
        ground = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], dtype=float)
        scene.add_mesh("floor", ground, np.array([[0, 1, 2], [0, 2, 3]]), materials=floor, object_id=2)
        camera = np.eye(4)
        camera[2, 3] = 3.0
        scene.set_camera(camera, 24, 24, projection="orthographic", ortho_scale=4.0)
        renderer = ppm_core.Renderer(scene, photons_per_pass=50_000, threads=2, seed=4)
        renderer.run(passes=6)
        image = renderer.image()[..., :3].mean(axis=2)
        around = np.ones(image.shape, bool)
        around[6:18, 6:18] = False
        return image[10:14, 10:14].mean(), image[around].mean()

    hidden_lamp, hidden_floor = render({"constants": [(1.0,) * 3], "code": [
        op("coord", "is_camera_ray", out=[2]), op("math", "subtract", ins=[1, 2, 1], out=[3])],
        "outputs": [3], "registers": 4})
    plain_lamp, plain_floor = render(None)
    assert plain_lamp == pytest.approx(1.0, abs=0.01) and hidden_lamp < 0.01
    assert hidden_floor == pytest.approx(plain_floor, rel=0.05) and plain_floor > 0.01


def test_a_bumped_normal_changes_how_a_grazing_sun_lights_the_surface():
    # Height = 0.3 x: the normal tilts towards -x, away from a sun in the +x sky.
    def lit(distance):
        program = {"constants": [(0.3,) * 3, (0.0,) * 3, (1.0,) * 3, (distance,) * 3],
                   "code": [op("coord", "shading_normal", out=[5])], "registers": 6}
        heights = []
        for side in (0, 1, 2):
            if side:
                program["code"].append(op("bump_offset", side, ins=[3]))  # filter width: register 3, 1.0
            program["code"] += [op("coord", "position", out=[program["registers"]]),
                                op("math", "multiply", ins=[program["registers"], 1, 2],
                                   out=[program["registers"] + 1])]
            heights.append(program["registers"] + 1)
            program["registers"] += 2
        program["code"] += [op("bump_offset", 0, ins=[3]),
                            op("bump", ins=[3, 4, *heights, 5, 3], out=[program["registers"]])]
        program["outputs"] = [program["registers"]]
        program["registers"] += 1
        scene = quad_scene(program, coloured=False, normal_map={"input": 0, "space": "direct", "softening": "none"})
        scene.add_light("sun", power=1.0, direction=(-0.8, 0.0, -0.6))  # from +x, 37 degrees up
        renderer = ppm_core.Renderer(scene, photons_per_pass=10_000, threads=2, seed=2)
        renderer.run(passes=2)
        return float(renderer.image()[..., :3].mean())

    flat, bumped = lit(0.0), lit(1.0)
    # Normal (-0.3, 0, 1)/|.|: cos to the sun (0.8, 0, 0.6) drops from 0.6 to 0.335.
    assert bumped / flat == pytest.approx((0.6 - 0.3 * 0.8) / np.hypot(0.3, 1.0) / 0.6, rel=0.05)


@pytest.mark.parametrize("program, message", [
    ({"code": [{"op": "teleport"}]}, "unknown node program operation"),
    ({"code": [op("coord", "uv", out=[300])]}, "register"),
    ({"code": [op("coord", "uv", out=[1])], "constants": [(1, 1, 1)], "outputs": [1], "registers": 2},
     "constant"),
    ({"code": [op("image", ins=[0], out=[1, 2], data=5)], "outputs": [1], "registers": 3}, "texture"),
    ({"code": [], "outputs": [1], "registers": 1}, "output"),
    ({"outputs": list(range(9)), "constants": [(0, 0, 0)] * 9, "registers": 10}, "at most 8"),
    ({"code": [op("coord", "uv", out=[1], colour=1)], "registers": 2}, "unknown node program instruction key"),
    ({"constants": [(float("nan"),) * 3], "registers": 2}, "not finite"),
    ({"code": [op("noise", extra=6, ins=[0] * 9, out=[1, 2])], "registers": 3}, "mode"),
])
def test_bad_programs_are_refused_with_a_message(program, message):
    scene = ppm_core.Scene()
    with pytest.raises(ValueError, match=message):
        scene.add_material("patterned", "mixture", lobes=[{"kind": "diffuse"}], program=program)


@pytest.mark.parametrize("detail,octaves", [(1e30, 15.0), (1e3, 15.0), (-5.0, 0.0)])
def test_a_wave_texture_sums_at_most_fifteen_octaves(detail, octaves):
    """The Wave texture's distortion sums `detail` octaves of noise; a script may set 10^30 (Blender's
    socket stops at 15), which once ran for hours inside Blender (the add-on's node fuzz, Blender 4.2)."""

    def wave(detail):
        # Wave (bands along Y, sine, Blender 4.x's fBM): vector, scale, distortion, detail, detail
        # scale, detail roughness, phase.
        return {"constants": [(1.0,) * 3, (15.0,) * 3, (detail,) * 3, (2.0,) * 3, (0.5,) * 3, (0.0,) * 3],
                "code": [op("coord", "generated", out=[7]), op("wave", 2, ins=[7, 1, 2, 3, 4, 5, 6], out=[8, 9])],
                "outputs": [8], "registers": 10}

    scene = ppm_core.Scene()
    points = np.array([[0.1, 0.2, 0.3], [1e3, -1e3, 5.0]])
    values = scene.run_program(wave(detail), points)
    assert np.isfinite(values).all()
    np.testing.assert_array_equal(values, scene.run_program(wave(octaves), points))
