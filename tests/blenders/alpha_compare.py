"""PPM against Cycles for alpha: Film > Transparent (the background, glass over it with Transparent
Glass off and on), a Holdout object, the Holdout shader, and a Holdout or a Transparent BSDF mixed
with a diffuse, in the running Blender.

A floor and two balls under a grey sky, seen from the side with the sky behind them (the
left ball matte, or a holdout; the right ball matte, glass, with the Holdout shader, or a Mix of
diffuse with a Holdout or a Transparent BSDF). The same
saved file is rendered by both engines: the mean colour (premultiplied, as Blender stores it) of
4x3 image blocks must agree within 3% (absolute below 1e-4) and their mean alpha within 0.01.

    .venv/bin/python tests/blenders/alpha_compare.py                  # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/alpha_compare.py
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare

ALPHA_TOLERANCE = 0.01
CASES = ("opaque_film", "transparent_film", "glass_over_background", "transparent_glass", "holdout_object",
         "holdout_shader", "holdout_mixed", "transparent_mixed")


def holdout_material():
    return cycles_compare.shader_material("holdout", "ShaderNodeHoldout")


def glass_material():
    return cycles_compare.glass_material("glass", 1.45)


def mixed_material(other):
    """Mix Shader, factor 0.4, of a matte blue diffuse and `other` (a Holdout or Transparent BSDF)."""
    mat = cycles_compare.diffuse_material("mixed", (0.3, 0.5, 0.7))
    tree = mat.node_tree
    out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    diffuse = out.inputs["Surface"].links[0].from_node
    mix, second = tree.nodes.new("ShaderNodeMixShader"), tree.nodes.new(other)
    mix.inputs["Fac"].default_value = 0.4
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(second.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    return mat


def build(case):
    cycles_compare.reset()
    scene = bpy.context.scene
    cycles_compare.plane("floor", 3.0, 0.0, cycles_compare.diffuse_material("floor", (cycles_compare.ALBEDO,) * 3))
    left = cycles_compare.ball("left", (-0.6, 0.0, 0.5), 0.5, cycles_compare.diffuse_material("matte", (0.7, 0.7, 0.7)))
    left.is_holdout = case == "holdout_object"
    matte = lambda: cycles_compare.diffuse_material("m", (0.3, 0.5, 0.7))  # noqa: E731
    right = {"glass_over_background": glass_material, "transparent_glass": glass_material,
             "holdout_shader": holdout_material, "holdout_mixed": lambda: mixed_material("ShaderNodeHoldout"),
             "transparent_mixed": lambda: mixed_material("ShaderNodeBsdfTransparent")}.get(case, matte)
    # Raised so that the camera sees the sky through the glass.
    cycles_compare.ball("right", (0.6, 0.0, 1.1), 0.5, right())
    # Lit by the sky alone. A point light's caustic through the glass ball is one Cycles cannot render
    # (PPM's was 5% of a block that Cycles, converged, left without it), and the glint of a sun in
    # the ball was 4% brighter in PPM than in Cycles at 2048 samples (0.003 of a sky of 0.6; not
    # explained yet): neither is what this checks.
    cycles_compare.set_world(0.6)
    cycles_compare.side_camera((0.0, -4.0, 1.3), 30.0)
    cycles_compare.set_exr_output(scene)
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.film_transparent = case != "opaque_film" and case != "holdout_object"
    scene.cycles.film_transparent_glass = case == "transparent_glass"


def block_alpha(rgba):
    return cycles_compare.block_means(np.repeat(rgba[..., 3:4], 3, axis=2))


def compare(case, workdir, samples, passes):
    build(case)
    # 12 bounces, PPM's: light leaves a glass ball after two to six.
    images = cycles_compare.render_with_both_engines(case, workdir, samples, passes, bounces=12, channels=4)
    cycles, ppm = (cycles_compare.block_means(images[e][..., :3]) for e in ("CYCLES", "PPM"))
    alpha_cycles, alpha_ppm = (block_alpha(images[e]) for e in ("CYCLES", "PPM"))
    relative = (ppm - cycles) / np.maximum(cycles, cycles_compare.DARK)
    return {"blender": bpy.app.version_string, "max_block_error": float(np.abs(relative).max()),
            "max_alpha_error": float(np.abs(alpha_ppm - alpha_cycles).max()),
            "alpha_cycles": alpha_cycles.round(4).tolist(), "alpha_ppm": alpha_ppm.round(4).tolist(),
            "blocks_cycles": cycles.round(5).tolist(), "blocks_ppm": ppm.round(5).tolist()}


def compare_cases(cases=CASES, samples=256, passes=32):
    return cycles_compare.run_cases(
        "alpha_compare", cases, lambda case, workdir: compare(case, workdir, samples, passes),
        lambda row: f"worst block colour {100 * row['max_block_error']:.2f}%, alpha {row['max_alpha_error']:.4f}")


def failed(row):
    return cycles_compare.beyond_tolerance(row) or row["max_alpha_error"] > ALPHA_TOLERANCE


def main():
    cycles_compare.run_as_script("alpha_compare", compare_cases, failed)


if __name__ == "__main__":
    main()
