"""PPM against Cycles, light kind by light kind, in the running Blender.

One .blend per light kind: a diffuse floor (albedo 0.5) seen from straight
above by a perspective camera, lit by a single light kind (point, sphere,
spot, area square/disk/rectangle/ellipse, sun, emissive mesh, world, a light's node tree with a
Blackbody at 3200 K and 9000 K, compared channel by channel). The
lights sit behind the camera or out of frame so only the floor is compared. Two
camera variants (orthographic with shift; vertical sensor fit with shift and a
tilt) under the point light check that the camera looks where Cycles' does;
a single plane has no indirect light, so both renderers compute the same
integral. The same saved file is rendered by Cycles (no clamping, no
denoising, no adaptive sampling, fixed seed) and by PPM; the mean radiance of
4x3 image blocks must agree within 3%.

    .venv/bin/python tests/blenders/cycles_compare.py [--json out.json]          # Blender 5.0 (bpy)
    .venvs/bpy-4.5/bin/python tests/blenders/cycles_compare.py [--json out.json] # 4.5; likewise 4.2, 5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/cycles_compare.py -- [--json out.json]

tests/blenders/test_blender_versions.py runs it in every Blender version through the installed zip.
"""

import argparse
import glob
import json
import math
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKOUT_ADDON = os.path.join(ROOT, "addon")
if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # blender -P does not add the script's folder
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
# Blender 3.4 from Debian has no numpy and no ppm_core: borrow the .venv's (same Python 3.11).
for site in glob.glob(os.path.join(ROOT, ".venv", "lib", "python%d.%d" % sys.version_info[:2], "site-packages")):
    if site not in sys.path:
        sys.path.append(site)

import bpy
import numpy as np

import cycles_references

WIDTH, HEIGHT = 64, 48
BLOCKS = (3, 4)  # rows, columns
ALBEDO = 0.5
TOLERANCE = 0.03
DARK = 1e-4  # radiance below which a block counts as black
KINDS = ("point", "sphere", "spot", "spot_radius", "area_spread", "area_square", "area_rectangle", "area_disk",
         "area_ellipse", "sun", "sun_hemisphere", "emissive_mesh", "world", "light_nodes", "light_blackbody",
         "light_blackbody_hot", "camera_ortho_shift", "camera_vertical_fit_shift")
# A Blackbody sets a light's hue, which the mean of the channels would hide: these kinds also
# compare R, G and B block by block.
PER_CHANNEL_KINDS = {"light_blackbody", "light_blackbody_hot"}
# An Empty as the scene camera: Cycles of bpy 5.2.3 crashes on it (SIGSEGV, measured), so the
# comparison runs up to 5.0 (5.1 untested); PPM renders it in every version (tests/addon).
KINDS_CAMERA_EMPTY = ("camera_empty",)
# Light `exposure` and `normalize`, new in Blender 4.5 (the sphere without Cycles' soft falloff, see the README).
KINDS_EXPOSURE = ("area_exposure_unnormalized", "sphere_exposure_unnormalized", "sun_exposure_unnormalized")


def kinds_for_this_blender():
    return (KINDS + (KINDS_EXPOSURE if "normalize" in bpy.types.Light.bl_rna.properties else ())
            + (KINDS_CAMERA_EMPTY if bpy.app.version < (5, 1, 0) else ()))


def reset():
    """An empty factory scene. An installed PPM add-on stays enabled (the preferences are kept);
    otherwise the checkout's add-on is registered."""
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)
    if not hasattr(bpy.types.Scene, "ppm"):
        sys.path.insert(0, CHECKOUT_ADDON)
        import ppm_render

        ppm_render.register()


def shader_material(name, node_type, **inputs):
    """A material whose Surface is one shader node of `node_type`, its inputs set by name."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    shader = nodes.new(node_type)
    for socket, value in inputs.items():
        shader.inputs[socket].default_value = value
    mat.node_tree.links.new(shader.outputs[0], out.inputs["Surface"])
    return mat


def diffuse_material(name, rgb):
    return shader_material(name, "ShaderNodeBsdfDiffuse", Color=(*rgb, 1.0))


def glossy_material(name, rgb):
    """A perfect mirror of colour `rgb` (a Glossy BSDF of roughness 0)."""
    glossy = "ShaderNodeBsdfGlossy" if bpy.app.version < (4, 0, 0) else "ShaderNodeBsdfAnisotropic"
    return shader_material(name, glossy, Color=(*rgb, 1.0), Roughness=0.0)


def glass_material(name, ior):
    """Smooth clear glass (a Glass BSDF of roughness 0)."""
    return shader_material(name, "ShaderNodeBsdfGlass", Roughness=0.0, IOR=ior)


def emission_material(name, rgb, strength):
    return shader_material(name, "ShaderNodeEmission", Color=(*rgb, 1.0), Strength=strength)


def plane(name, half, z, material, flip=False):
    mesh = bpy.data.meshes.new(name)
    corners = [(-half, -half, z), (half, -half, z), (half, half, z), (-half, half, z)]
    mesh.from_pydata(corners, [], [(3, 2, 1, 0) if flip else (0, 1, 2, 3)])
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def ball(name, location, radius, material):
    """A smooth UV sphere of `material`."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=radius, location=location)
    obj = bpy.context.object
    obj.name = name
    bpy.ops.object.shade_smooth()
    obj.data.materials.append(material)
    return obj


def cube(name, location, size, material):
    """A cube of edge `size` of `material`."""
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    obj = bpy.context.object
    obj.name = name
    obj.data.materials.append(material)
    return obj


def side_camera(location, lens):
    """The scene camera at `location`, looking along +Y and 10 degrees down."""
    scene = bpy.context.scene
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location, cam.rotation_euler = location, (math.radians(80), 0.0, 0.0)
    cam.data.lens = lens
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def set_exr_output(scene):
    """The compared image size, written as 32-bit EXR where render.filepath says."""
    render = scene.render
    render.resolution_x, render.resolution_y, render.resolution_percentage = WIDTH, HEIGHT, 100
    render.image_settings.file_format, render.image_settings.color_depth = "OPEN_EXR", "32"
    render.use_file_extension = False


def add_light(kind, energy, location, rotation=(0.0, 0.0, 0.0), **props):
    data = bpy.data.lights.new(kind, kind)
    data.energy = energy
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(kind, data)
    obj.location, obj.rotation_euler = location, rotation
    bpy.context.scene.collection.objects.link(obj)
    return obj


def set_world(strength):
    world = bpy.data.worlds.new("World")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    bg = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bg.inputs["Strength"].default_value = strength
    bpy.context.scene.world = world


def build(kind):
    """The scene for one light kind; the camera at z = 1.5 looks straight down at the floor."""
    reset()
    scene = bpy.context.scene
    plane("floor", 10.0, 0.0, diffuse_material("floor", (ALBEDO,) * 3))
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.lens, cam.data.sensor_width = 30.0, 36.0
    cam.location = (0.1, -0.2, 1.5)  # off-centre so the image is not symmetric
    scene.collection.objects.link(cam)
    scene.camera = cam
    set_world(0.0) if kind != "world" else set_world(0.5)
    tilt = (math.radians(25), 0.0, math.radians(30))  # a tilted area light: its cosine falloff shows
    if kind == "camera_ortho_shift":  # the point light's falloff tells where the camera looks
        cam.data.type, cam.data.ortho_scale, cam.data.shift_x, cam.data.shift_y = "ORTHO", 1.7, 0.2, -0.1
    elif kind == "camera_vertical_fit_shift":
        cam.data.sensor_fit, cam.data.sensor_height, cam.data.shift_y = "VERTICAL", 20.0, 0.25
        cam.rotation_euler = (math.radians(15), 0.0, math.radians(10))
    elif kind == "camera_empty":  # any object can be the camera; Cycles gives it a default lens
        empty = bpy.data.objects.new("viewer", None)
        empty.location, empty.rotation_euler = cam.location, (math.radians(10), 0.0, math.radians(20))
        scene.collection.objects.link(empty)
        scene.camera = empty
    if kind == "point" or kind.startswith("camera_"):
        add_light("POINT", 100.0, (0.3, 0.2, 2.2), shadow_soft_size=0.0)
    elif kind == "sphere":
        add_light("POINT", 100.0, (0.3, 0.2, 2.2), shadow_soft_size=0.3)
    elif kind == "light_nodes":  # Emission strength and colour in the light's node tree scale its power
        lamp = add_light("POINT", 100.0, (0.3, 0.2, 2.2), shadow_soft_size=0.3)
        if bpy.app.version < (5, 1, 0):  # 5.1+ always uses a light's nodes (use_nodes warns there)
            lamp.data.use_nodes = True
        emission = next(n for n in lamp.data.node_tree.nodes if n.bl_idname == "ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 2.5
        emission.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    elif kind.startswith("light_blackbody"):  # Emission Color from a Blackbody node, through a reroute
        lamp = add_light("POINT", 100.0, (0.3, 0.2, 2.2), shadow_soft_size=0.3)
        if bpy.app.version < (5, 1, 0):
            lamp.data.use_nodes = True
        tree = lamp.data.node_tree
        emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 2.5
        emission.inputs["Color"].default_value = (0.0, 1.0, 0.0, 1.0)  # unused: the Blackbody drives it
        blackbody, reroute = tree.nodes.new("ShaderNodeBlackbody"), tree.nodes.new("NodeReroute")
        # 3200 K (a tungsten lamp) and 9000 K (a blue sky) lie in different intervals of Cycles' fit.
        blackbody.inputs["Temperature"].default_value = 9000.0 if kind == "light_blackbody_hot" else 3200.0
        tree.links.new(blackbody.outputs["Color"], reroute.inputs[0])
        tree.links.new(reroute.outputs[0], emission.inputs["Color"])
    elif kind == "spot":
        add_light("SPOT", 300.0, (0.0, 0.0, 2.5), spot_size=math.radians(40), spot_blend=0.3, shadow_soft_size=0.0)
    elif kind == "spot_radius":  # a sphere in a cone: soft edges and, over the post, a soft shadow
        add_light("SPOT", 300.0, (0.0, 0.0, 2.5), spot_size=math.radians(40), spot_blend=0.3, shadow_soft_size=0.4)
        post = plane("post", 0.1, 1.2, diffuse_material("post", (0.5, 0.5, 0.5)))
        post.location = (0.2, -0.1, 0.0)
    elif kind == "area_exposure_unnormalized":
        add_light("AREA", 50.0, (0.2, 0.1, 2.0), tilt, shape="RECTANGLE", size=0.8, size_y=0.4,
                  exposure=1.5, normalize=False)
    elif kind == "sphere_exposure_unnormalized":
        add_light("POINT", 100.0, (0.3, 0.2, 2.2), shadow_soft_size=0.3, exposure=-0.5, normalize=False,
                  use_soft_falloff=False)
    elif kind == "area_spread":  # a soft box's grid: 90 degrees
        add_light("AREA", 50.0, (0.2, 0.1, 2.0), tilt, shape="RECTANGLE", size=0.8, size_y=0.4,
                  spread=math.radians(90))
    elif kind.startswith("area_"):
        shape = kind[5:].upper()
        add_light("AREA", 50.0, (0.2, 0.1, 2.0), tilt, shape=shape, size=0.8, size_y=0.4)
    elif kind == "sun_exposure_unnormalized":
        add_light("SUN", 200.0, (0, 0, 5), (math.radians(30), 0.0, math.radians(20)), angle=math.radians(5),
                  exposure=0.7, normalize=False)
    elif kind == "sun":
        add_light("SUN", 2.0, (0, 0, 5), (math.radians(30), 0.0, math.radians(20)), angle=math.radians(5))
    elif kind == "sun_hemisphere":  # Blender's largest sun angle
        add_light("SUN", 2.0, (0, 0, 5), (math.radians(30), 0.0, math.radians(20)), angle=math.pi)
    elif kind == "emissive_mesh":
        panel = plane("panel", 0.4, 2.0, emission_material("glow", (1.0, 0.9, 0.8), 3.0), flip=True)
        panel.rotation_euler = (math.radians(20), 0.0, 0.0)
    set_exr_output(scene)
    scene.render.film_transparent = False
    return scene


def configure_cycles(scene, samples, bounces=4):
    """Cycles as a reference (see ../shared/BLENDER_NOTES.md): no clamping, denoising or adaptivity."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 1
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    # PPM averages its eye samples over each pixel's square: the same box filter, where Cycles'
    # default Blackman-Harris (1.5 px) would move light across the edges of the compared blocks.
    c.pixel_filter_type, c.filter_width = "BOX", 1.0
    c.caustics_reflective = c.caustics_refractive = True
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = bounces
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 2


def configure_ppm(scene, passes):
    """The sampling is pinned (seed, eye samples, no adaptive eye samples): a small bright reflection
    (a sun in a mirror ball or a clear coat) makes a case's mean noise-bound, and another sampling
    pattern moves it by up to 10% at 32 passes (glossy_mirror, seeds 1-4, with or without adaptive
    samples). Adaptive sampling's own checks: tests/core/test_adaptive_samples.py, bench adaptive."""
    scene.render.engine = "PPM"
    scene.ppm.passes = passes
    scene.ppm.photons_per_pass = 20_000
    scene.ppm.samples_per_pixel = 4
    scene.ppm.adaptive_samples = 1
    scene.ppm.seed = int(os.environ.get("PPM_SEED", "1"))  # another, to see how much of a block is noise
    scene.ppm.threads = 2


def read_image(path):
    """(H, W, 4) float32 of an image file read by Blender, rows bottom-up as Blender stores them."""
    image = bpy.data.images.load(path, check_existing=False)
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)


def render_to_array(scene, path, channels=3):
    """Renders with write_still and reads the EXR back with Blender (no pixels in background mode otherwise).
    Cycles' image of a scene it rendered before in this Blender version is read from cycles_references."""
    scene.render.filepath = path
    cycles = scene.render.engine == "CYCLES"
    if cycles:
        case = os.path.splitext(os.path.basename(path))[0]
        rgba, key = cycles_references.lookup(case)
        if rgba is not None:
            cycles_references.found.append(case)
            return rgba[..., :channels]
    bpy.ops.render.render(write_still=True)
    rgba = read_image(path)
    if cycles:
        cycles_references.store(case, key, rgba)
    return rgba[..., :channels]


def render_with_both_engines(name, workdir, samples, passes, bounces=4, channels=3, configure=None):
    """{"CYCLES": rgb, "PPM": rgb} of the scene just built (RGBA with channels=4), saved once and opened
    for each engine; `configure(scene, engine)`, if given, adjusts each after the standard settings."""
    blend = os.path.join(workdir, f"{name}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    images = {}
    for engine in ("CYCLES", "PPM"):
        bpy.ops.wm.open_mainfile(filepath=blend)
        scene = bpy.context.scene
        configure_cycles(scene, samples, bounces) if engine == "CYCLES" else configure_ppm(scene, passes)
        if configure is not None:
            configure(scene, engine)
        images[engine] = render_to_array(scene, os.path.join(workdir, f"{name}_{engine}.exr"), channels)
    return images


def block_means(rgb, channel=None):
    """4x3 block means of the mean of the channels, or of one channel."""
    rows, cols = BLOCKS
    h, w = HEIGHT // rows, WIDTH // cols
    values = rgb.mean(axis=2) if channel is None else rgb[..., channel]
    return np.array([[values[r * h:(r + 1) * h, c * w:(c + 1) * w].mean() for c in range(cols)]
                     for r in range(rows)])


def worst_block_error(images, channel=None):
    cycles, ppm = (block_means(images[e], channel) for e in ("CYCLES", "PPM"))
    return float(np.abs((ppm - cycles) / np.maximum(cycles, DARK)).max())


def block_comparison(name, workdir, samples, passes, bounces=4, per_channel=False, configure=None):
    """Renders the scene just built with both engines (`configure` as for render_with_both_engines):
    their 4x3 block means and the worst relative error (absolute below DARK); with per_channel, the
    worst over R, G and B too."""
    images = render_with_both_engines(name, workdir, samples, passes, bounces, configure=configure)
    cycles, ppm = (block_means(images[e]) for e in ("CYCLES", "PPM"))
    row = {"blender": bpy.app.version_string, "cycles_mean": float(cycles.mean()), "ppm_mean": float(ppm.mean()),
           "max_block_error": worst_block_error(images), "blocks_cycles": cycles.round(5).tolist(),
           "blocks_ppm": ppm.round(5).tolist()}
    if per_channel:
        row["max_block_error_rgb"] = [worst_block_error(images, c) for c in range(3)]
        row["max_block_error"] = max(row["max_block_error"], *row["max_block_error_rgb"])
    return row


def run_cases(label, cases, compare_one, describe):
    """compare_one(case, workdir) for each case in one temporary folder, printing
    "<label>: Blender <version> <case> <describe(row)> (<seconds>)" for each; the rows."""
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for case in cases:
            start = time.monotonic()
            row = {"case": case, **compare_one(case, workdir)}
            rows.append(row)
            print(f"{label}: Blender {row['blender']} {case:28s} {describe(row)} "
                  f"({time.monotonic() - start:.1f} s)", flush=True)
    return rows


def describe_blocks(row):
    return (f"cycles {row['cycles_mean']:.5f} ppm {row['ppm_mean']:.5f} "
            f"worst block {100 * row['max_block_error']:.2f}%")


def run_as_script(label, compare_cases, failed):
    """main() of a comparison script: runs it, unregisters the checkout's add-on, prints the rows
    `failed` picks and exits 1 if there are any."""
    try:
        rows = compare_cases()
    finally:
        unregister_checkout_addon()
    bad = [row for row in rows if failed(row)]
    for row in bad:
        print(f"{label}: {row['case']}: " + ", ".join(f"{k} {v}" for k, v in row.items() if k.startswith(
            ("blocks", "alpha_"))), flush=True)
    if bad:
        sys.exit(1)


def beyond_tolerance(row):
    return row["max_block_error"] > TOLERANCE


# Kinds that need more passes than the rest. A spread area light's direct light is noisy: each
# sample picks a point anywhere on the light, and from most of them the narrowed beam misses (at
# 24 passes a corner block was 5% off, at 256 passes within 1.3%).
MIN_PASSES = {"area_spread": 128}


def compare(kind, workdir, samples=256, passes=32):
    """Cycles and PPM block means for one light kind, rendered from the same saved .blend."""
    build(kind)
    row = block_comparison(kind, workdir, samples, max(passes, MIN_PASSES.get(kind, 0)),
                           per_channel=kind in PER_CHANNEL_KINDS)
    row["mean_error"] = (row["ppm_mean"] - row["cycles_mean"]) / max(row["cycles_mean"], DARK)
    return {"kind": kind, **row}


def compare_kinds(kinds, samples, passes=32):
    """compare() for each kind, printing a line each."""
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for kind in kinds:
            row = compare(kind, workdir, samples=samples, passes=passes)
            rows.append(row)
            print(f"cycles_compare: Blender {row['blender']} {kind:15s} cycles {row['cycles_mean']:.5f} "
                  f"ppm {row['ppm_mean']:.5f} mean {100 * row['mean_error']:+.2f}% "
                  f"worst block {100 * row['max_block_error']:.2f}%" + "".join(
                      f" {c} {100 * e:.2f}%" for c, e in zip("RGB", row.get("max_block_error_rgb", ()))), flush=True)
    return rows


def unregister_checkout_addon():
    """The bpy modules 4.2 and 4.5 crash or hang at exit while a script-registered class is still
    registered (an installed add-on is unregistered by Blender itself)."""
    module = sys.modules.get("ppm_render")
    if module is not None and os.path.dirname(os.path.dirname(module.__file__)) == CHECKOUT_ADDON:
        if hasattr(bpy.types.Scene, "ppm"):
            module.unregister()


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else \
        (sys.argv[1:] if os.path.basename(sys.argv[0]) == os.path.basename(__file__) else [])
    parser = argparse.ArgumentParser()
    parser.add_argument("--json")
    parser.add_argument("--kinds", nargs="*", default=list(kinds_for_this_blender()))
    parser.add_argument("--samples", type=int, default=256)
    args = parser.parse_args(argv)
    try:
        rows = compare_kinds(args.kinds, args.samples)
    finally:
        unregister_checkout_addon()
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    failed = [r["kind"] for r in rows if r["max_block_error"] > TOLERANCE]
    if failed:
        print(f"cycles_compare: more than {100 * TOLERANCE:.0f}% off: {', '.join(failed)}", flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
