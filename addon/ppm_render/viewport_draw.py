"""Drawing a viewport image with Blender's `gpu` module, in the scene's display colour space.

The image is uploaded once per new pass as a half-float texture and drawn over its window of the
region (the whole region, or its render region; a preview image of a quarter or half resolution is
stretched, as Cycles shows its first, coarse samples) between the engine's bind_display_space_shader
and unbind_display_space_shader, which apply the scene's view transform and look. The built-in image
shader is `IMAGE` from Blender 4.0 on and `2D_IMAGE` before; `bgl` is not used (5.0 has none).
"""

import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader


def image_shader():
    try:
        return gpu.shader.from_builtin("IMAGE")
    except ValueError:  # Blender 3.x
        return gpu.shader.from_builtin("2D_IMAGE")


class DrawnImage:
    """The texture of one ViewportImage, and the quad it is drawn on."""

    def __init__(self, image):
        self.image = image
        rgba = np.ascontiguousarray(image.rgba[::-1], dtype=np.float32)  # GPU rows run bottom-up
        height, width = rgba.shape[:2]
        pixels = gpu.types.Buffer("FLOAT", width * height * 4, rgba.ravel())
        self.texture = gpu.types.GPUTexture((width, height), format="RGBA16F", data=pixels)
        self.shader = image_shader()
        corners = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))
        self.batch = batch_for_shader(self.shader, "TRI_FAN", {"pos": corners, "texCoord": corners})

    def draw(self, engine, scene):
        """Draws the image over its window of the region (all of it, or its render region)."""
        x, y, width, height = self.image.window
        gpu.state.blend_set("ALPHA_PREMULT")
        engine.bind_display_space_shader(scene)
        with gpu.matrix.push_pop():
            gpu.matrix.translate((x, y))
            gpu.matrix.scale((width, height))
            self.shader.uniform_sampler("image", self.texture)
            self.batch.draw(self.shader)
        engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")
