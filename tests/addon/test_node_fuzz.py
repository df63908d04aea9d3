"""Fuzzing the node program compiler: random networks of texture and utility nodes (any node type
the add-on reads, and some it does not, with random settings, random and extreme input values, links
between any outputs and inputs, node groups) on a material's sockets. Export never crashes: each
material is described and added to a core scene, whose program then runs at points, finite where
its inputs are (a NaN in gives what it gives, but never a crash), or it warns."""

import math
import os

import bpy
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ppm_core
from ppm_render.export import material as material_export
from ppm_render.export import node_program

# The node types this Blender has, of those the compiler reads (older ones such as Separate HSV are
# gone from 4.x) and some it does not.
NODE_TYPES = [t for t in sorted(set(node_program.NODES) | {"ShaderNodeAttribute", "ShaderNodeVertexColor",
                                                          "ShaderNodeWavelength", "ShaderNodeRGBCurve",
                                                          "ShaderNodeFloatCurve"}) if hasattr(bpy.types, t)]
VALUES = (0.0, 0.5, 1.0, -1.0, 2.5, 1e-30, 1e30, -1e30, math.inf, -math.inf, math.nan, 15.0, 100.0)
SOCKETS = ("Base Color", "Roughness", "Metallic", "Normal", "Alpha", "Emission Color", "Coat Weight")


def set_enums(node, draw):
    """Every enum property of the node set to a random item of it."""
    for prop in node.bl_rna.properties:
        if prop.type == "ENUM" and not prop.is_readonly and not prop.is_enum_flag:
            items = [item.identifier for item in prop.enum_items]
            if items:
                try:
                    setattr(node, prop.identifier, draw(st.sampled_from(items)))
                except (TypeError, ValueError, AttributeError):
                    pass
        elif prop.type in ("INT", "BOOLEAN") and not prop.is_readonly and prop.identifier in (
                "turbulence_depth", "offset_frequency", "squash_frequency", "use_clamp", "clamp", "invert",
                "normalize", "clamp_factor", "clamp_result"):
            setattr(node, prop.identifier, draw(st.integers(0, 10)) if prop.type == "INT" else draw(st.booleans()))


def set_inputs(node, draw):
    for socket in node.inputs:
        if not hasattr(socket, "default_value"):
            continue
        value = draw(st.sampled_from(VALUES))
        try:
            current = socket.default_value
            socket.default_value = type(current)(value) if isinstance(current, (int, float)) else [value] * len(current)
        except (TypeError, ValueError, OverflowError):
            pass


@st.composite
def networks(draw):
    """A material with a Principled BSDF whose sockets random node networks drive."""
    mat = bpy.data.materials.new("fuzzed")
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    made = []
    for _ in range(draw(st.integers(1, 8))):
        node = tree.nodes.new(draw(st.sampled_from(NODE_TYPES)))
        set_enums(node, draw)
        set_inputs(node, draw)
        made.append(node)
    for _ in range(draw(st.integers(1, 14))):  # links from an earlier node to a later one or the BSDF
        i = draw(st.integers(0, len(made) - 1))
        source = made[i]
        targets = made[i + 1:] + [bsdf]
        target = draw(st.sampled_from(targets))
        if not source.outputs or not target.inputs:
            continue
        output = draw(st.sampled_from(list(source.outputs)))
        inputs = [s for s in target.inputs if s.name in SOCKETS] if target is bsdf else list(target.inputs)
        if inputs:
            tree.links.new(output, draw(st.sampled_from(inputs)))
    return mat


# Derandomised by default, as the core's fuzz is: `make test` must not turn up a new input on a CI run
# (a random run in Blender 4.2 once hung inside Scene.run_program, 2026-12-03). Random runs:
# PPM_NODE_FUZZ_EXAMPLES=2000 pytest tests/addon/test_node_fuzz.py
EXAMPLES = int(os.environ.get("PPM_NODE_FUZZ_EXAMPLES", "200"))


@settings(max_examples=EXAMPLES, deadline=None, derandomize="PPM_NODE_FUZZ_EXAMPLES" not in os.environ,
          database=None, suppress_health_check=list(HealthCheck))
@given(networks())
def test_random_networks_export_and_run_without_crashing(mat):
    scene = ppm_core.Scene()
    warnings = []
    exporter = material_export.MaterialExporter(scene, warnings.append)
    exporter.index(mat)  # describes and adds it: any failure here raises
    params = exporter.describe(mat)
    program = params.get("program")
    if program is not None:
        points = np.array([[0.1, 0.2, 0.3], [1e3, -1e3, 5.0], [0.0, 0.0, 0.0]])
        normals = np.tile([0.0, 0.0, 1.0], (3, 1))
        values = scene.run_program(program, points, normal=normals, incoming=normals, uv=points[:, :2])
        assert values.shape == (3, len(program["outputs"]), 3)
    bpy.data.materials.remove(mat)


@pytest.fixture(autouse=True)
def fresh_file():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield
