"""Settings the user edits: `scene.ppm` (render settings handed to the core) and
`object.ppm` (the revolve flag). Names match the core's settings keys so that
scripts can set them and `core_settings` is a plain copy."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty


class PPMSceneSettings(bpy.types.PropertyGroup):
    photons_per_pass: IntProperty(
        name="Photons per Pass", default=200_000, min=1000, soft_max=10_000_000,
        description="Photons traced in each photon pass")
    passes: IntProperty(
        name="Passes", default=200, min=1, soft_max=100_000,
        description="Photon passes; the render ends after these or the time limit, whichever comes first")
    time_limit: FloatProperty(
        name="Time Limit", default=0.0, min=0.0, unit='TIME_ABSOLUTE', subtype='TIME_ABSOLUTE',
        description="Seconds of rendering per view layer (0 = no limit)")
    target_error: FloatProperty(
        name="Target Error", default=0.0, min=0.0, max=1.0, soft_max=0.2, precision=3,
        description="Stop once the estimated error (noise and bias, the mean over pixels relative to the image's "
                    "mean brightness) is at most this, e.g. 0.02 for 2%; or at the passes or time limit, whichever "
                    "comes first (0 = off)")
    error_confidence: FloatProperty(
        name="Confidence", default=0.95, min=0.5, max=0.999,
        description="Confidence of the error estimate: the estimate is an upper bound at this confidence")
    error_passes: BoolProperty(
        name="Error Passes", default=False,
        description="Write the error estimate as render passes: Error (each pixel's bound at the confidence, "
                    "relative to its brightness), Bias (signed: the image minus the truth, expected) and Noise "
                    "(the noise's bound), both in luminance")
    caustic_pass: BoolProperty(
        name="Caustic",
        description="Write a Caustic pass: the light of photons that came to the surface by mirrors and glass "
                    "only (part of the Indirect light), e.g. to grade caustics in the compositor",
        default=False,
    )
    denoising_data: BoolProperty(
        name="Denoising Data", default=False,
        description="Write Denoising Albedo and Denoising Normal passes, as Cycles' Denoising Data: the guides "
                    "the compositor's Denoise node takes with the image")
    denoise: BoolProperty(
        name="Denoise", default=False,
        description="Denoise the finished image with Blender's own Open Image Denoise, guided by the denoising "
                    "albedo and normal (Combined is then the denoised image; with Denoising Data also the noisy "
                    "one, as Noisy Image). Smooths noise, and may smear sharp caustics")
    viewport_passes: IntProperty(
        name="Viewport Passes", default=1000, min=0, soft_max=100_000,
        description="Photon passes in the viewport's Rendered shading before it stops refining (0 = no limit)")
    viewport_time_limit: FloatProperty(
        name="Viewport Time Limit", default=0.0, min=0.0, unit='TIME_ABSOLUTE', subtype='TIME_ABSOLUTE',
        description="Seconds the viewport refines after each change (0 = no limit)")
    viewport_photons_per_pass: IntProperty(
        name="Viewport Photons per Pass", default=50_000, min=1000, soft_max=10_000_000,
        description="Photons in each of the viewport's passes: fewer than a render's, so that the image refines "
                    "several times a second")
    alpha: FloatProperty(
        name="Alpha", default=0.7, min=0.01, max=0.99,  # the core needs alpha < 1
        description="Radius reduction: the fraction of new photons kept each pass (Hachisuka 2008)")
    threshold: IntProperty(
        name="Threshold (P)", default=30, min=1, soft_max=1000,
        description="Photons a hit point gathers before its radius shrinks; 1 = classic PPM")
    max_bounces: IntProperty(
        name="Max Bounces", default=12, min=1, max=1000,
        description="Longest photon path and eye specular chain (with Cycles Light Paths off)")
    cycles_light_paths: BoolProperty(
        name="Cycles Light Paths", default=False,
        description="Limit bounces as the scene's Cycles settings do (Render Properties > Light Paths > Max "
                    "Bounces: total, diffuse, glossy, transmission, volume), to match a Cycles render; off, light "
                    "bounces up to Max Bounces times of any kind. Lights' and the world's own Max Bounces "
                    "are honoured either way")
    samples_per_pixel: IntProperty(
        name="Samples per Pixel", default=4, min=1, soft_max=64,
        description="Jittered eye samples per pixel (anti-aliasing)")
    adaptive_samples: IntProperty(
        name="Adaptive Samples", default=4, min=1, max=64,
        description="Stochastic hit points: up to this many eye samples a pixel each pass where the error "
                    "estimate finds the pixel noisiest (edges, small lights); 1 = one everywhere. At equal time "
                    "4 had a quarter of the error (relative MSE) of 1 on the Cornell boxes")
    photon_guiding: BoolProperty(
        name="Photon Guiding", default=False,
        description="Send lamps' photons (point, sphere, spot and area lamps) where the error estimate finds "
                    "the image noisiest. Helps where lamps light much the camera does not see (a lamp in a large "
                    "room or outdoors, the camera close on a detail): half the error at equal time in such a "
                    "scene. In a closed room every photon is seen anyway, and guiding's cost loses up to a fifth "
                    "of the passes")
    volume_beams: BoolProperty(
        name="Volume Beams", default=True,
        description="In fog of one density, camera rays sample its direct light all along their way through it, "
                    "and light focused into it by glass and mirrors travels as photon beams that every camera "
                    "ray crossing them gathers. Off, both happen only where a ray or a photon scatters, which in "
                    "thin fog is rarely: about twice the noise at equal time in god rays and in a volumetric "
                    "caustic's cone. Media whose density varies (smoke, textured clouds) are rendered the same "
                    "either way")
    seed: IntProperty(name="Seed", default=0, min=0,
                      description="Random seed; same seed and threads give the same image")
    animated_seed: BoolProperty(
        name="Animated Seed", default=True,
        description="A different noise pattern in every frame of an animation (seed + frame), as Cycles' "
                    "Animated Seed; off, every frame has the same pattern")
    threads: IntProperty(name="Threads", default=0, min=0, max=1024, description="Worker threads (0 = all cores)")
    dof_mode: EnumProperty(
        name="Depth of Field",
        items=[('OFF', "Off", "Pinhole camera, everything sharp"),
               ('POST', "Post Process", "Blur the finished image by depth"),
               ('LENS', "Lens", "Sample the camera aperture")],
        default='OFF', description="How the camera's depth of field is rendered")
    hit_points: EnumProperty(
        name="Hit Points",
        items=[('AUTO', "Auto", "Stochastic: at equal time, 0.32-0.37 of fixed hit points' relative MSE on the "
                                "Cornell boxes (bench/README.md)"),
               ('FIXED', "Fixed", "One eye pass (PPM): fastest per pass, anti-aliasing from samples per pixel"),
               ('STOCHASTIC', "Stochastic", "New eye samples every pass (SPPM): converges anti-aliasing, "
                                           "glossy surfaces and lens blur")],
        default='AUTO', description="Keep the eye pass's hit points, or draw new ones every pass")


class PPMObjectSettings(bpy.types.PropertyGroup):
    revolve: BoolProperty(
        name="Bezier Revolve", default=False,
        description="Render this curve as the exact surface of revolution of its Bezier profile about local Y")


# The core's settings keys that scene.ppm carries one-to-one.
CORE_KEYS = ("photons_per_pass", "alpha", "threshold", "max_bounces", "samples_per_pixel", "seed", "threads",
             "target_error", "error_confidence", "adaptive_samples", "photon_guiding", "volume_beams")


def core_settings(settings):
    """The keyword arguments for ppm_core.Renderer from scene.ppm.

    AUTO picks stochastic hit points: at equal time they had 0.32-0.37 of fixed
    hit points' relative MSE on the Cornell boxes (bench/run.py ablation_hit_points), converge the
    light's edges and glossy surfaces that fixed ones freeze, and LENS depth of
    field needs them."""
    args = {key: getattr(settings, key) for key in CORE_KEYS}
    if settings.animated_seed:
        args["seed"] = frame_seed(settings.seed, settings.id_data.frame_current)
    args["dof_mode"] = settings.dof_mode.lower()
    args["hit_points"] = "fixed" if settings.hit_points == 'FIXED' else "stochastic"
    return args


def frame_seed(seed, frame):
    """The seed of one frame: frames differ, and a negative frame gives a valid seed too."""
    return (seed + frame * 0x9E3779B1) % 2**63


def render_settings(scene):
    """The keyword arguments for ppm_core.Renderer of a render of `scene`: its PPM settings, its film
    and its light paths (F12, the viewport, the farm and the benchmarks start from these)."""
    return {**core_settings(scene.ppm), **film_settings(scene), **light_path_settings(scene)}


def media_settings(settings, warn):
    """`settings` (render_settings') for a scene with media (fog, a world volume, a volume-only
    material): these render with stochastic hit points for now, so Fixed gives way, warned."""
    if settings["hit_points"] == "fixed":
        warn("media render with stochastic hit points only (for now); Hit Points 'Fixed' is ignored")
    return {**settings, "hit_points": "stochastic"}


def film_settings(scene):
    """Alpha as Cycles renders it: Film > Transparent, and its Transparent Glass (Cycles' own setting,
    read where the Cycles add-on is present). Cycles counts glass up to a roughness of 0.1 as
    transparent (`film_transparent_roughness`); PPM counts smooth glass only."""
    cycles = getattr(scene, "cycles", None)
    return {"transparent_background": bool(scene.render.film_transparent),
            "transparent_glass": bool(getattr(cycles, "film_transparent_glass", False))}


def light_path_settings(scene):
    """Cycles' Light Paths > Max Bounces when the user asks for them (scene.ppm.cycles_light_paths),
    read where the Cycles add-on is present; without it, Cycles' defaults."""
    if not scene.ppm.cycles_light_paths:
        return {"light_path_limits": False}
    cycles = getattr(scene, "cycles", None)
    limits = {"total_bounces": 12, "diffuse_bounces": 4, "glossy_bounces": 4, "transmission_bounces": 12,
              "volume_bounces": 0}
    if cycles is not None:
        limits = {"total_bounces": cycles.max_bounces, "diffuse_bounces": cycles.diffuse_bounces,
                  "glossy_bounces": cycles.glossy_bounces, "transmission_bounces": cycles.transmission_bounces,
                  "volume_bounces": cycles.volume_bounces}
    return {"light_path_limits": True, **limits}


classes = (PPMSceneSettings, PPMObjectSettings)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.ppm = PointerProperty(type=PPMSceneSettings)
    bpy.types.Object.ppm = PointerProperty(type=PPMObjectSettings)


def unregister():
    del bpy.types.Object.ppm
    del bpy.types.Scene.ppm
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
