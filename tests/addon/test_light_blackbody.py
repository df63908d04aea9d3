"""A light's Emission Color driven by a Blackbody node is Cycles' Blackbody colour (the Cycles
agreement itself: tests/blenders/cycles_compare.py, kinds light_blackbody and light_blackbody_hot),
and so is the core's Blackbody instruction, which a varying Temperature compiles to (its Cycles
agreement: nodes_compare.py's blackbody_varying)."""

import numpy as np
import pytest

from conftest import bpy
from ppm_render import core
from ppm_render.export import light
from ppm_render.export.blackbody import blackbody_rgb

# Cycles' Blackbody colour, read back from renders of an Emission of strength 1 in Blender 3.4,
# 4.2, 4.5, 5.0 and 5.2 (all five alike to 0.01%): one temperature per interval of its fit, and
# either side of the range it holds constant.
CYCLES_RENDERED = {
    500.0: (5.4133, 0.0, 0.0),
    1000.0: (4.6014, 0.0390, 0.0),
    2000.0: (2.5201, 0.6469, 0.0204),
    3200.0: (1.6794, 0.8660, 0.3259),
    6500.0: (1.0426, 0.9841, 1.0353),
    9000.0: (0.9041, 0.9940, 1.3430),
    20000.0: (0.8263, 0.9945, 1.5663),
}


@pytest.mark.parametrize("kelvin", sorted(CYCLES_RENDERED))
def test_the_colour_is_the_one_cycles_renders(kelvin):
    assert blackbody_rgb(kelvin) == pytest.approx(CYCLES_RENDERED[kelvin], abs=1e-4)


def test_warm_is_red_and_hot_is_blue_at_the_same_luminance():
    warm, hot = blackbody_rgb(2000.0), blackbody_rgb(12000.0)
    assert warm[0] > warm[1] > warm[2] and hot[2] > hot[1] > hot[0]
    for r, g, b in (warm, hot):  # Rec.709 luminance: the temperature moves the hue, not the power
        assert 0.2126 * r + 0.7152 * g + 0.0722 * b == pytest.approx(1.0, abs=1e-3)


def test_beyond_the_fit_cycles_holds_its_end_colours():
    assert blackbody_rgb(50000.0) == blackbody_rgb(12000.0)
    assert blackbody_rgb(0.0) == blackbody_rgb(-10.0) == blackbody_rgb(799.0)
    assert min(blackbody_rgb(799.0)) == 0.0  # the fit's negative green and blue, clamped


def lamp_tree(strength=2.0):
    """A point light's node tree and its Emission node, whose own Color (green) is not a Blackbody's."""
    data = bpy.data.lights.new("lamp", "POINT")
    if bpy.app.version < (5, 1, 0):
        data.use_nodes = True
    tree = data.node_tree
    emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
    emission.inputs["Strength"].default_value = strength
    emission.inputs["Color"].default_value = (0.0, 1.0, 0.0, 1.0)
    return data, tree, emission


def blackbody_node(tree, kelvin):
    node = tree.nodes.new("ShaderNodeBlackbody")
    node.inputs["Temperature"].default_value = kelvin
    return node


def exported(data):
    """(colour, warnings) node_emission gives the light."""
    warnings = []
    return light.node_emission(data, "lamp", warnings.append), warnings


def test_a_blackbody_through_reroutes_colours_the_light():
    data, tree, emission = lamp_tree(strength=2.0)
    first, second = tree.nodes.new("NodeReroute"), tree.nodes.new("NodeReroute")
    tree.links.new(blackbody_node(tree, 2000.0).outputs["Color"], first.inputs[0])
    tree.links.new(first.outputs[0], second.inputs[0])
    tree.links.new(second.outputs[0], emission.inputs["Color"])
    color, warnings = exported(data)
    assert warnings == []
    assert color == pytest.approx(tuple(2.0 * c for c in blackbody_rgb(2000.0)))


def test_a_blackbody_with_a_linked_temperature_warns_and_uses_the_sockets_value():
    data, tree, emission = lamp_tree(strength=2.0)
    blackbody = blackbody_node(tree, 2000.0)
    value = tree.nodes.new("ShaderNodeValue")
    tree.links.new(value.outputs[0], blackbody.inputs["Temperature"])
    tree.links.new(blackbody.outputs["Color"], emission.inputs["Color"])
    color, warnings = exported(data)
    assert len(warnings) == 1 and "light 'lamp'" in warnings[0] and "'Color'" in warnings[0]
    assert "Temperature" in warnings[0] and color == pytest.approx((0.0, 2.0, 0.0))


def test_a_muted_blackbody_warns():
    data, tree, emission = lamp_tree()
    blackbody = blackbody_node(tree, 2000.0)
    blackbody.mute = True
    tree.links.new(blackbody.outputs["Color"], emission.inputs["Color"])
    _, warnings = exported(data)
    assert len(warnings) == 1 and "'Color'" in warnings[0]


def test_a_muted_link_is_ignored_as_cycles_does():
    data, tree, emission = lamp_tree(strength=2.0)
    link = tree.links.new(blackbody_node(tree, 2000.0).outputs["Color"], emission.inputs["Color"])
    link.is_muted = True
    color, warnings = exported(data)
    assert warnings == [] and color == pytest.approx((0.0, 2.0, 0.0))


def test_a_reroute_fed_by_nothing_warns():
    """Cycles reads black from it up to 4.5 and the socket's value from 5.0 on: PPM warns."""
    data, tree, emission = lamp_tree()
    tree.links.new(tree.nodes.new("NodeReroute").outputs[0], emission.inputs["Color"])
    _, warnings = exported(data)
    assert len(warnings) == 1 and "'Color'" in warnings[0]


def test_the_cores_instruction_for_a_varying_temperature_gives_the_same_colours():
    """A Temperature that varies reaches the core's Blackbody instruction with the fit as data."""
    from ppm_render.export.blackbody import kernel_rec709_to_scene_linear, program_data

    ppm_core = core.load()
    scene = ppm_core.Scene()
    for kelvin in sorted(CYCLES_RENDERED) + [799.0, 800.0, 965.0, 6365.0, 11999.0, 12000.0]:
        program = {"constants": [(kelvin,) * 3], "data": program_data(), "registers": 3, "outputs": [2],
                   "code": [{"op": "blackbody", "in": [1], "out": [2], "data": 0}]}
        colour = scene.run_program(program, np.zeros((1, 3)))[0, 0]
        assert colour == pytest.approx(blackbody_rgb(kelvin, kernel_rec709_to_scene_linear()), abs=2e-5), kelvin
