"""Media that vary in space through ppm_core (Scene.add_medium with a node program and terms): the
transmittance of a density ramp against its closed form, a field of ones against the homogeneous
medium, a step in density against two boxes, each object's own coordinates, a glowing field's photons,
and bad fields refused with a message. The tracker itself is tested in free_path_test.cpp."""

from __future__ import annotations

import numpy as np
import pytest
from test_media import box, camera, emitter_seen_through, emitting_panel
from test_node_program import op

import ppm_core
from core_scenes import look_at, quad

FOG = {"sigma_s": (0.8, 0.8, 0.8), "sigma_a": (0.1, 0.2, 0.3)}


def step_program(at, low, high, axis=0, coordinate="position"):
    """A program whose one output is `low` where `coordinate`'s `axis` is below `at`, else `high`."""
    code = [op("coord", coordinate, out=[4]), op("separate", axis, ins=[4], out=[5]),
            op("math", "greater_than", ins=[5, 1], out=[6]),  # 0 or 1
            op("math", "multiply_add", ins=[6, 2, 3], out=[7])]  # (high - low) s + low
    return {"constants": [(at,) * 3, (high - low,) * 3, (low,) * 3], "code": code, "outputs": [7], "registers": 8}


def ones():
    """A program that gives 1 wherever it runs, which the core cannot know without running it."""
    return step_program(-1e9, 0.0, 1.0)


def pixel_mean_and_error(pixels):
    return pixels.mean(axis=0), pixels.std(axis=0) / np.sqrt(len(pixels))


@pytest.mark.accuracy
def test_a_linear_density_transmits_exp_minus_its_integral():
    """An emitter (radiance 2) seen through a 1.5 m slab whose absorption grows linearly across it,
    sigma_a (y + 0.75) per channel: each channel reads 2 exp(-1.125 sigma_a) (the integral of the
    ramp over the slab), within 4 standard errors of the 64 pixels' mean (ratio tracking is noisy, not
    biased). A density taken as its mean or its peak would read 0.9x or 1.6-3x of it."""
    sigma_a = np.array([0.2, 0.7, 1.5])
    program = {"constants": [(0.75,) * 3], "code": [op("coord", "position", out=[2]),
                                                    op("separate", 1, ins=[2], out=[3]),
                                                    op("math", "add", ins=[3, 1], out=[4])],
               "outputs": [4], "registers": 5}
    scene = ppm_core.Scene()
    scene.add_medium("ramp", program=program, terms=[{"sigma_a": tuple(sigma_a), "input": 0}])
    slab = scene.add_material("ramp", "diffuse", medium="ramp", surface=False)
    box(scene, "slab", (-1.0, -0.75, -1.0), (1.0, 0.75, 1.0), slab, 0)
    scene.set_object_info(0, np.eye(4))
    pixels = emitter_seen_through(scene, panel_y=3, eye_y=-4, object_id=1, passes=400)
    mean, error = pixel_mean_and_error(pixels)
    expected = 2.0 * np.exp(-1.125 * sigma_a)
    assert np.all(np.abs(mean - expected) < 4.0 * error + 1e-4), (mean, expected, error)


def fog_box_scene(medium):
    """A 2 m fog box (a boundary only) of `medium` (add_medium keywords) above a floor, a point light
    above: the beam, the floor's shadow and the fog's glow."""
    scene = ppm_core.Scene()
    scene.add_medium("fog", anisotropy=0.3, **medium)
    fog = scene.add_material("fog", "diffuse", medium="fog", surface=False)
    box(scene, "fog", (-1, -1, -1), (1, 1, 1), fog, 0)
    scene.set_object_info(0, np.eye(4))
    floor = scene.add_material("floor", "diffuse", base_color=(0.8, 0.8, 0.8))
    quad(scene, "floor", [[-4, -4, -1.5], [4, -4, -1.5], [4, 4, -1.5], [-4, 4, -1.5]], floor, object_id=1)
    scene.add_light("point", position=(0.5, -0.5, 2.0), power=300.0)
    camera(scene, (0, -6, 0.5), (0, 0, 0), size=24, fov=0.6)
    return scene


def render_regions(scene, passes=128, **settings):
    """Mean radiance of the fog's middle, the left and right halves and the floor's rows."""
    r = ppm_core.Renderer(scene, **{"hit_points": "stochastic", "seed": 3, "threads": 2,
                                    "photons_per_pass": 20000, **settings})
    r.run(passes=passes)
    image = r.image()[..., :3].astype(np.float64)
    return np.array([image[s].mean() for s in (np.s_[6:18, 6:18], np.s_[:, :12], np.s_[:, 12:], np.s_[18:, :])])


@pytest.mark.accuracy
def test_a_field_of_ones_renders_as_the_homogeneous_medium():
    """The same fog twice: homogeneous, and as a term times a program that gives 1 everywhere (so the
    core tracks it: delta tracking for the eye's and photons' free paths, ratio tracking for shadow
    rays, sigma_s looked up where a hit point lies). Every region agrees within 3% (two seeds of the
    homogeneous fog: within 0.7%); direct light by photons alone too."""
    homogeneous = render_regions(fog_box_scene(FOG))
    tracked = render_regions(fog_box_scene({"program": ones(), "terms": [{**FOG, "input": 0}]}))
    by_photons = render_regions(fog_box_scene({"program": ones(), "terms": [{**FOG, "input": 0}]}),
                                direct_light="photons")
    np.testing.assert_allclose(tracked, homogeneous, rtol=0.03)
    np.testing.assert_allclose(by_photons, homogeneous, rtol=0.03)


@pytest.mark.accuracy
def test_a_step_in_density_renders_as_two_boxes():
    """Fog 0.5x as dense where x < 0 and 1.5x where x >= 0, as one field, against two homogeneous boxes
    1 mm apart at x = 0 (boxes that share a face are ill-defined: which face a ray meets first): every
    region within 3% (the field counted at its mean density everywhere: the halves 10-30% apart).
    The boxes render at 0.3 of the radius over 512 passes: at the default radius the thin box's gather
    balls by the gap count the thick one beyond as empty (its half 6.6% bright at 128 passes; at 0.3
    of the radius within 1.6% of 0.15 of it over 4096 passes, to which the field is within 1.4%)."""
    field = fog_box_scene({"program": step_program(0.0, 0.5, 1.5), "terms": [{**FOG, "input": 0}]})
    two = ppm_core.Scene()
    for name, scale, lo, hi, object_id in (("thin", 0.5, -1, -5e-4, 0), ("thick", 1.5, 5e-4, 1, 2)):
        two.add_medium(name, anisotropy=0.3, **{k: tuple(scale * np.array(v)) for k, v in FOG.items()})
        material = two.add_material(name, "diffuse", medium=name, surface=False)
        box(two, name, (lo, -1, -1), (hi, 1, 1), material, object_id)
    floor = two.add_material("floor", "diffuse", base_color=(0.8, 0.8, 0.8))
    quad(two, "floor", [[-4, -4, -1.5], [4, -4, -1.5], [4, 4, -1.5], [-4, 4, -1.5]], floor, object_id=1)
    two.add_light("point", position=(0.5, -0.5, 2.0), power=300.0)
    camera(two, (0, -6, 0.5), (0, 0, 0), size=24, fov=0.6)
    np.testing.assert_allclose(render_regions(field), render_regions(two, passes=512, volume_radius_scale=0.3),
                               rtol=0.03)


@pytest.mark.accuracy
def test_a_thin_fog_beside_a_dense_one_reads_its_own_density():
    """Fog 0.1x as dense where x < 0 and 2x where x >= 0, one field: photons lie in proportion to the
    density where they are, so a gather ball by the step on the thin side holds the dense side's too;
    each hit point divides its photons by the ball's mean density over its own (16 points and its
    centre). The thin half at the default radius is within 3% of its value at 0.2 of the radius over
    1024 passes (without the division: 9.5% bright against its own render so; at 0.15 of the radius
    over 4096 passes the two estimates' thin halves agree within 1.6%)."""
    def field():
        return fog_box_scene({"program": step_program(0.0, 0.1, 2.0), "terms": [{**FOG, "input": 0}]})
    thin = render_regions(field())[1]
    converged = render_regions(field(), passes=1024, volume_radius_scale=0.2)[1]
    assert abs(thin / converged - 1.0) < 0.03, (thin, converged)


def test_each_object_reads_its_own_coordinates():
    """One absorbing medium, dense (1 per metre) where Generated x > 0.5, on two boxes 6 m apart: each
    box is dense in its own right half (Cycles' volume stack knows each entry's object). Seen along y
    through 2 m: exp(-2) there (the mean of 6144 ratio-tracking samples, each 0 or 1 where the
    density is the majorant: within 10%, 3 standard errors), and exactly 1 in each left half."""
    scene = ppm_core.Scene()
    scene.add_medium("ink", program=step_program(0.5, 0.0, 1.0, coordinate="generated"),
                     terms=[{"sigma_a": (1.0, 1.0, 1.0), "input": 0}])
    ink = scene.add_material("ink", "diffuse", medium="ink", surface=False)
    for object_id, x in ((0, -3.0), (1, 3.0)):
        box(scene, f"box {object_id}", (x - 1, -1, -1), (x + 1, 1, 1), ink, object_id)
        matrix = np.eye(4)
        matrix[0, 3] = x
        scene.set_object_info(object_id, matrix)  # texture space: the box, (-1, 1) in object space
    emitting_panel(scene, 3, 9, 2, radiance=1.0)
    scene.set_camera(look_at((0, -5, 0), (0, 0, 0)), 80, 8, projection="orthographic", ortho_scale=10.0)
    r = ppm_core.Renderer(scene, hit_points="stochastic", seed=1, threads=2, photons_per_pass=1000)
    r.run(passes=64)
    image = r.image()[..., 0]  # x from -5 to 5 in 80 columns
    x = (np.arange(80) + 0.5) / 80 * 10.0 - 5.0
    dense = ((x > -2.9) & (x < -2.1)) | ((x > 3.1) & (x < 3.9))  # each box's right half: x > -3, x > 3
    clear = ((x > -3.9) & (x < -3.1)) | ((x > 2.1) & (x < 2.9))
    assert dense.sum() == 12 and clear.sum() == 12
    np.testing.assert_allclose(image[:, dense].mean(), np.exp(-2.0), rtol=0.1)
    np.testing.assert_allclose(image[:, clear], 1.0, rtol=1e-6)


@pytest.mark.accuracy
def test_a_glowing_half_lights_the_floor_as_a_glowing_half_box():
    """A box whose emission is a field, 3 per metre where x >= 0 and 0 elsewhere, against a homogeneous
    half box of the same emission: the same floor and the same glow seen (its photons start anywhere in
    the box, each carrying the emission where it starts over the bound's; every region within 3%)."""
    def scene_of(field):
        scene = ppm_core.Scene()
        if field:
            scene.add_medium("glow", sigma_a=(0.2, 0.2, 0.2), program=step_program(0.0, 0.0, 1.0),
                             terms=[{"emission": (3.0, 2.0, 1.0), "input": 0}])
        else:
            scene.add_medium("glow", sigma_a=(0.2, 0.2, 0.2), emission=(3.0, 2.0, 1.0))
        glow = scene.add_material("glow", "diffuse", medium="glow", surface=False)
        box(scene, "glow", (-1 if field else 5e-4, -1, -1), (1, 1, 1), glow, 0)
        if not field:  # the half without emission still absorbs (1 mm apart, see the step's test)
            scene.add_medium("dark", sigma_a=(0.2, 0.2, 0.2))
            dark = scene.add_material("dark", "diffuse", medium="dark", surface=False)
            box(scene, "dark", (-1, -1, -1), (-5e-4, 1, 1), dark, 2)
        scene.set_object_info(0, np.eye(4))
        floor = scene.add_material("floor", "diffuse", base_color=(0.8, 0.8, 0.8))
        quad(scene, "floor", [[-4, -4, -1.5], [4, -4, -1.5], [4, 4, -1.5], [-4, 4, -1.5]], floor, object_id=1)
        camera(scene, (0, -6, 0.5), (0, 0, 0), size=24, fov=0.6)
        return scene
    np.testing.assert_allclose(render_regions(scene_of(True)), render_regions(scene_of(False)), rtol=0.03)


def test_bad_fields_are_refused_with_a_message():
    scene = ppm_core.Scene()
    with pytest.raises(ValueError, match="give a program and the terms"):
        scene.add_medium("a", terms=[{"sigma_s": 1.0, "input": 0}])
    with pytest.raises(ValueError, match="not one of the program's 1 outputs"):
        scene.add_medium("b", program=ones(), terms=[{"sigma_s": 1.0, "input": 1}])
    with pytest.raises(ValueError, match="terms\\[0\\].sigma_a"):
        scene.add_medium("c", program=ones(), terms=[{"sigma_a": float("nan"), "input": 0}])
    with pytest.raises(ValueError, match="no field 'density'"):
        scene.add_medium("d", program=ones(), terms=[{"density": 1.0}])
    with pytest.raises(ValueError, match="needs terms"):
        scene.add_medium("e", program=ones(), terms=[])
    scene.add_medium("cloud", program=ones(), terms=[{"sigma_s": 1.0, "input": 0}])
    with pytest.raises(ValueError, match="world medium must be homogeneous"):
        scene.set_world_medium("cloud")
    assert scene.media == ["cloud"]


@pytest.mark.parametrize("operation, offset, transmitted", [("add", -100.0, 1.0), ("exponent", 80.0, 0.0)])
def test_a_negative_or_huge_field_renders_finite(operation, offset, transmitted):
    """A program whose output is negative everywhere (x - 100) counts as no medium; one of 5.5e34
    (e^(x + 80) in floats; programs give no NaN or Inf, as Cycles' safe maths) as opaque (the
    coefficients' cap, 1e30 per metre): the emitter behind reads 2 or 0, exactly, and the render
    stays finite."""
    code = [op("coord", "position", out=[2]), op("separate", 0, ins=[2], out=[3]),
            op("math", "add", ins=[3, 1], out=[4]), op("math", operation, ins=[4, 4], out=[5])]
    program = {"constants": [(offset,) * 3], "code": code, "outputs": [5 if operation == "exponent" else 4],
               "registers": 6}
    scene = ppm_core.Scene()
    scene.add_medium("odd", program=program, terms=[{"sigma_a": (1.0, 1.0, 1.0), "input": 0}])
    slab = scene.add_material("odd", "diffuse", medium="odd", surface=False)
    box(scene, "slab", (-1.0, -0.5, -1.0), (1.0, 0.5, 1.0), slab, 0)
    scene.set_object_info(0, np.eye(4))
    pixels = emitter_seen_through(scene, panel_y=3, eye_y=-4, object_id=1)
    assert np.all(np.isfinite(pixels))
    np.testing.assert_allclose(pixels, 2.0 * transmitted, atol=1e-6)
