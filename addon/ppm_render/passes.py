"""The render result's passes: declared for the compositor (declare), and written after a render.

Combined; Depth, Normal, Object Index and Material Index render passes, when the view
layer enables them; the error estimate's passes when scene.ppm.error_passes asks for them;
Denoising Albedo and Normal (scene.ppm.denoising_data) from the core's
Renderer.denoising_features, the normal in Cycles' camera space; Cycles' Diffuse, Glossy,
Transmission and Volume light passes and the Caustic pass from Renderer.component_passes.

All come from the core's own primary ray through each pixel centre
(`Scene.camera_rays`) and its batch ray caster (`Scene.intersect`, camera rays),
as Cycles writes its data passes at the camera ray's first hit. Depth is Cycles'
Z pass: the distance of the hit along the view axis (1e10 where nothing is hit);
Normal is the world-space normal (zero where nothing is hit); IndexOB and
IndexMA are the Pass Index of the object and of the material hit (0 where
nothing is). Rows come out bottom-up, as Blender stores them.
"""

import numpy as np

from . import denoise

MISS_DEPTH = 1e10  # what Cycles writes for the background
ERROR_PASSES = ("Error", "Bias", "Noise")
DENOISING_PASSES = (("Denoising Normal", 3, "XYZ", "VECTOR"), ("Denoising Albedo", 3, "RGB", "COLOR"))
NOISY_PASS = ("Noisy Image", 4, "RGBA", "COLOR")
# Cycles' light passes: (pass name, the view layer's toggle).
COMPONENT_PASSES = tuple((prefix + part, f"use_pass_{kind}_{word}")
                         for prefix, kind in (("Diff", "diffuse"), ("Gloss", "glossy"), ("Trans", "transmission"))
                         for part, word in (("Dir", "direct"), ("Ind", "indirect"), ("Col", "color")))
# Cycles' volume light passes, radiance without a Color pass; their toggles are the Cycles add-on's
# (view_layer.cycles).
VOLUME_PASSES = (("VolumeDir", "use_pass_volume_direct"), ("VolumeInd", "use_pass_volume_indirect"))
CAUSTIC_PASS = "Caustic"


def component_passes_wanted(view_layer, settings):
    """The light passes the view layer asks for, and the Caustic pass if scene.ppm asks for it."""
    wanted = [name for name, toggle in COMPONENT_PASSES if getattr(view_layer, toggle, False)]
    cycles = getattr(view_layer, "cycles", None)
    wanted += [name for name, toggle in VOLUME_PASSES if getattr(cycles, toggle, False)]
    return wanted + ([CAUSTIC_PASS] if settings.caustic_pass else [])


def component_passes(parts, wanted):
    """The core's Renderer.component_passes (radiance, top row first) as Blender's passes, bottom row
    first: as Cycles, each Diffuse, Glossy and Transmission Direct and Indirect pass is divided by its
    Color pass (0 where the colour is), so that (Dir + Ind) * Col is the light again. Volume and
    Caustic stay radiance."""
    out = {}
    for name in wanted:
        light = np.asarray(parts[name], dtype=np.float32)
        if name[-3:] in ("Dir", "Ind") and name[:-3] + "Col" in parts:
            color = np.asarray(parts[name[:-3] + "Col"], dtype=np.float32)
            with np.errstate(divide="ignore", invalid="ignore"):
                light = np.where(color > 0.0, light / color, 0.0).astype(np.float32)
        out[name] = light[::-1]
    return out


def camera_hits(core_scene):
    """Each pixel centre's camera ray ("origins", "directions") and what it meets (Scene.intersect's
    dict): cast once for all the data passes."""
    origins, directions = core_scene.camera_rays()
    return {**core_scene.intersect(origins, directions, ray_kind="camera"), "origins": origins,
            "directions": directions}


def depth_and_normal(hits, args):
    """(H, W) depth along the view axis and (H, W, 3) world normals, bottom row first."""
    origins, directions = hits["origins"], hits["directions"]
    t = np.asarray(hits["t"])
    hit = np.isfinite(t)
    m = np.asarray(args["matrix"], dtype=float)
    eye, view_axis = m[:3, 3], -m[:3, 2] / np.linalg.norm(m[:3, 2])
    depth = np.full(t.shape, MISS_DEPTH, dtype=np.float32)
    points = origins[hit] + t[hit, None] * directions[hit]
    depth[hit] = (points - eye) @ view_axis
    normal = np.where(hit[:, None], np.asarray(hits["normal"]), 0.0).astype(np.float32)
    h, w = args["height"], args["width"]
    return depth.reshape(h, w), normal.reshape(h, w, 3)


def index_passes(hits, args, pass_indices):
    """(H, W) Object Index and (H, W) Material Index, bottom row first (export.PassIndices)."""
    shape = (args["height"], args["width"])
    return (lookup(pass_indices.objects, hits["object"]).reshape(shape),
            lookup(pass_indices.materials, hits["material"]).reshape(shape))


def lookup(table, ids):
    """table[id] where 0 <= id < len(table), else 0 (a miss is -1)."""
    ids = np.asarray(ids)
    known = (ids >= 0) & (ids < len(table))
    out = np.zeros(ids.shape, dtype=np.float32)
    out[known] = np.asarray(table, dtype=np.float32)[ids[known]]
    return out


def camera_space(normals, matrix):
    """World-space normals (..., 3) in Cycles' camera space: x right, y up, z along the view (a
    surface facing the camera has z = -1), from the camera's world matrix."""
    axes = np.asarray(matrix, dtype=float)[:3, :3]
    axes = axes / np.linalg.norm(axes, axis=0)
    to_camera = np.stack([axes[:, 0], axes[:, 1], -axes[:, 2]])
    return (np.asarray(normals, dtype=float) @ to_camera.T).astype(np.float32)


def error_passes(error):
    """The core's Renderer.error() (top row first) as ERROR_PASSES, bottom row first: Error is each
    pixel's bound (abs(bias) + noise) over its luminance (0 where it is black), Bias and Noise are in
    luminance. Before two passes Noise and Error are inf, as the core says."""
    bias, noise, value = (np.asarray(error[key], dtype=np.float32)[::-1] for key in ("bias", "noise", "luminance"))
    bound = np.abs(bias) + noise
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(value > 0.0, bound / np.abs(value), 0.0).astype(np.float32)
    return {"Error": relative, "Bias": bias, "Noise": noise}


def write_pass(result, name, pixels):
    """Copies a bottom-up (H, W[, C]) array into a named pass of the result, if it exists."""
    render_pass = result.layers[0].passes.get(name)
    if render_pass is None:
        return
    flat = np.ascontiguousarray(pixels, dtype=np.float32)
    try:
        render_pass.rect.foreach_set(flat.ravel())
    except (TypeError, ValueError, RuntimeError):
        render_pass.rect.foreach_set(flat.reshape(flat.shape[0] * flat.shape[1], -1))


def write_pixels(result, rgba):
    """Copies a (H, W, 4) top-row-first image into the Combined pass (Blender rows run bottom-up)."""
    pixels = np.ascontiguousarray(rgba[::-1], dtype=np.float32)
    rect = result.layers[0].passes["Combined"].rect
    try:
        rect.foreach_set(pixels.ravel())  # Blender 4.x+/5.0 want a flat array
    except (TypeError, ValueError, RuntimeError):
        rect.foreach_set(pixels.reshape(-1, 4))  # 3.4 wants (pixels, channels)


def declare(engine, scene, renderlayer):
    """RenderEngine.update_render_passes: registers every pass the engine will write for this layer."""
    engine.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
    data = (("use_pass_z", "Depth", 1, "Z", "VALUE"), ("use_pass_normal", "Normal", 3, "XYZ", "VECTOR"),
            ("use_pass_object_index", "IndexOB", 1, "X", "VALUE"),
            ("use_pass_material_index", "IndexMA", 1, "X", "VALUE"),
            # Cycles' names: what camera rays see at no bounce
            ("use_pass_emit", "Emit", 3, "RGB", "COLOR"), ("use_pass_environment", "Env", 3, "RGB", "COLOR"))
    for toggle, name, channels, chan_id, kind in data:
        if getattr(renderlayer, toggle):
            engine.register_pass(scene, renderlayer, name, channels, chan_id, kind)
    for name in component_passes_wanted(renderlayer, scene.ppm):
        engine.register_pass(scene, renderlayer, name, 3, "RGB", "COLOR")
    if scene.ppm.error_passes:
        for name in ERROR_PASSES:
            engine.register_pass(scene, renderlayer, name, 1, "X", "VALUE")
    if scene.ppm.denoising_data:
        noisy = (NOISY_PASS,) if scene.ppm.denoise else ()
        for name, channels, chan_id, kind in DENOISING_PASSES + noisy:
            engine.register_pass(scene, renderlayer, name, channels, chan_id, kind)


def write_data_passes(view_layer, result, core_scene, camera_args, pass_indices):
    """Depth, Normal, IndexOB and IndexMA, as the view layer asks, from one cast of camera rays."""
    geometry = view_layer.use_pass_z or view_layer.use_pass_normal
    indices = view_layer.use_pass_object_index or view_layer.use_pass_material_index
    if not (geometry or indices):
        return
    hits = camera_hits(core_scene)
    if geometry:
        depth, normal = depth_and_normal(hits, camera_args)
        write_pass(result, "Depth", depth)
        write_pass(result, "Normal", normal)
    if indices:
        objects, materials = index_passes(hits, camera_args, pass_indices)
        write_pass(result, "IndexOB", objects)
        write_pass(result, "IndexMA", materials)


def write_render_passes(engine, renderer, result, settings, light_and_components, camera_args, line):
    """The passes made from the finished render, as asked: the error estimate's, Emit and Env
    (`light_and_components[0]`), the components (Cycles' Diffuse, Glossy and Transmission ones,
    Caustic: `light_and_components[1]`) and the denoising ones. `engine` is the RenderEngine (its
    warnings and stats line), `line` the render's final stats line."""
    light_passes, components = light_and_components
    if settings.error_passes:
        for name, pixels in error_passes(renderer.error()).items():
            write_pass(result, name, pixels)
    if light_passes:
        for name, pixels in renderer.light_passes().items():
            write_pass(result, name, pixels[::-1])  # passes run bottom-up
    if components:
        write_components(engine, renderer, result, components)
    write_denoising(engine, renderer, result, settings, camera_args, line)


def write_components(engine, renderer, result, wanted):
    try:
        parts = renderer.component_passes()
    except RuntimeError as error:  # streamed hit points keep none: the frame is rendered all the same
        engine.warn(f"light passes skipped: {error}")
        return
    for name, pixels in component_passes(parts, wanted).items():
        write_pass(result, name, pixels)


def write_denoising(engine, renderer, result, settings, camera_args, line):
    """Denoising Albedo and Normal passes, and the denoised Combined (denoise.py), as asked;
    `line` is the render's final stats line, shown again after them."""
    use_denoiser = settings.denoise
    if use_denoiser:
        use_denoiser, why = denoise.available()
        if not use_denoiser:
            engine.warn(f"Denoise skipped: {why}; the image is the noisy one")
    if not (use_denoiser or settings.denoising_data):
        return
    engine.update_stats("", "Denoising data")
    features = renderer.denoising_features()
    albedo, normal = features["albedo"], camera_space(features["normal"], camera_args["matrix"])
    if settings.denoising_data:  # passes run bottom-up, the core's arrays top-down
        write_pass(result, "Denoising Albedo", albedo[::-1])
        write_pass(result, "Denoising Normal", normal[::-1])
    if use_denoiser:
        engine.update_stats("", "Denoising")
        image = renderer.image()
        if settings.denoising_data:
            write_pass(result, "Noisy Image", image[::-1])
        try:
            write_pixels(result, denoise.denoise(image, albedo, normal))
            engine.update_result(result)
            line += " | denoised"
        except RuntimeError as error:  # the frame is kept, noisy: a farm job goes on
            engine.warn(f"Denoise failed ({error}); the image is the noisy one")
    engine.update_stats("", line)
