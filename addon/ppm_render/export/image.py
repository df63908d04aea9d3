"""Blender images -> core textures, in the compact form Blender keeps them (bytes stay bytes) and
without float64 copies.

Two ways in:
- Blender 5.2 and later (`imbuf.types.ImBuf.with_buffer`): a byte image file is loaded with
  `imbuf` and its bytes are handed to the core as they are, without loading the image data-block
  (which `Image.size`, `Image.pixels` and even `Image.is_float` would do). A 16k x 16k PNG adds the
  core's 1 GiB, plus the ImBuf's 1 GiB while it is copied.
- Otherwise `Image.pixels` (float32, 16 bytes a texel: Blender has no other way out), which the
  core converts to bytes (byte images) or half floats (float images), after which the float copy
  and, if this export loaded it, Blender's own image buffer are freed.
"""

import os
import tempfile
import threading
from contextlib import contextmanager, nullcontext

import bpy
import numpy as np

try:
    import imbuf
except ImportError:  # not in every build of Blender
    imbuf = None

SRGB_SPACES = ("sRGB", "sRGB 2.1")
NO_ALPHA_FORMATS = ("JPEG", "BMP", "HDR", "CINEON", "DPX")
# Negative values smaller than this share of the image's brightest (or of 1) are noise of HDR tools
# (the HDRIs Blender ships hold down to -0.004 under a sun of 32,000), clamped to 0 without a warning.
NEGLIGIBLE_NEGATIVE = 1e-3


def add_texture(core_scene, image, premultiplied=False):
    """Adds `image` to the core scene; returns (texture index, what was changed to make it usable, as
    text for a warning, or None). `premultiplied`: its colour times its alpha, in the values it is
    stored as (sRGB-encoded bytes too), as Cycles keeps images. ValueError for a tiled image (add_tiles)."""
    if image.source == "TILED":
        raise ValueError("UDIM tiles are read by an Image Texture node only")
    byte_storage = "srgb8" if image.colorspace_settings.name in SRGB_SPACES else "linear8"
    premultiplied = premultiplied and may_have_alpha(image)
    if can_read_file_bytes(image) and not premultiplied:
        index = add_file_bytes(core_scene, image, byte_storage)
        if index is not None:
            return index, None  # bytes are always usable
    index = add_pixels(core_scene, image, byte_storage, premultiplied)
    return index, repairs(core_scene.texture_info(index))


def add_tiles(core_scene, image, premultiplied=False):
    """Adds each UDIM tile of a tiled image; returns ([(tile number, texture index)], what was changed,
    or None). Blender gives Python the first tile's pixels only, so each tile's file (or packed file)
    is read: from Blender 5.2 on, a byte file through imbuf; otherwise as an image data-block loaded for
    the export and removed after, which only the main thread may do (background renders, scripts): an
    interactive render's thread must not add or remove data-blocks. ValueError where none is read."""
    pattern = bpy.path.abspath(image.filepath, library=image.library)
    packed = packed_tiles(image)
    main_thread = threading.current_thread() is threading.main_thread()
    pairs, found, unread = [], [], []
    for tile in image.tiles:
        path = pattern.replace("<UDIM>", str(tile.number))
        index, repaired = add_tile(core_scene, image, tile.number, path, packed.get(tile.number), premultiplied)
        if repaired:
            found.append(f"tile {tile.number}: {repaired}")
        if index is None:
            unread.append(tile.number)
        else:
            pairs.append((tile.number, index))
    if not pairs:
        why = "" if main_thread else " (an interactive render before Blender 5.2 reads float or alpha tiles " \
                                     "only in a background render: blender -b)"
        raise ValueError(f"none of its UDIM tiles could be read from '{'packed files' if packed else pattern}'{why}")
    if unread:
        found.append(f"UDIM tiles {', '.join(map(str, unread))} could not be read; they show as missing")
    return pairs, "; ".join(found) or None


def add_tile(core_scene, image, number, path, data, premultiplied):
    """(texture index, repairs) of tile `number`, from its file at `path` or its packed bytes `data`;
    (None, None) if it cannot be read (here)."""
    if imbuf is not None and hasattr(imbuf.types.ImBuf, "with_buffer") and not premultiplied:
        byte_storage = "srgb8" if image.colorspace_settings.name in SRGB_SPACES else "linear8"
        name = f"{image.name} {number}"
        index = (read_file_bytes(core_scene, name, path, byte_storage) if data is None
                 else read_buffer_bytes(core_scene, name, data, byte_storage))
        if index is not None:
            return index, None
    if threading.current_thread() is not threading.main_thread():
        return None, None
    with nullcontext(path) if data is None else unpacked_copy(data, path) as readable:
        return add_tile_image(core_scene, image, readable, premultiplied)


def packed_tiles(image):
    """{tile number: its packed file's bytes} of a tiled image's packed tiles."""
    return {packed.tile_number: packed.packed_file.data for packed in getattr(image, "packed_files", ())
            if packed.packed_file is not None}


@contextmanager
def unpacked_copy(data, path):
    """A temporary file holding `data` (named with `path`'s extension, by which some formats are known),
    removed after."""
    handle, copy = tempfile.mkstemp(prefix="ppm_tile_", suffix=os.path.splitext(path)[1])
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(data)
        yield copy
    finally:
        os.remove(copy)


def add_tile_image(core_scene, image, path, premultiplied):
    """(texture index, repairs) of the tile file at `path` read as an image data-block with `image`'s
    colour space and alpha mode, removed again; (None, None) if it cannot be loaded. Main thread only."""
    try:
        tile_image = bpy.data.images.load(path, check_existing=False)
    except RuntimeError:
        return None, None
    try:
        tile_image.colorspace_settings.name = image.colorspace_settings.name
        tile_image.alpha_mode = image.alpha_mode
        return add_texture(core_scene, tile_image, premultiplied)
    finally:
        bpy.data.images.remove(tile_image)


def repairs(info):
    """What the core changed in a texture to use it, as text, or None."""
    found = []
    if info["not_finite_texels"]:
        found.append(f"{texels(info['not_finite_texels'])} values that are not a number or infinite; "
                     "rendered black")
    if info["negative_texels"] and -info["most_negative"] > NEGLIGIBLE_NEGATIVE * max(info["max_rgb"], 1.0):
        found.append(f"{texels(info['negative_texels'])} negative colours (down to {info['most_negative']:g}); "
                     "clamped to 0")
    return "; ".join(found) or None


def may_have_alpha(image):
    """False for files whose format has no alpha (known without loading the image)."""
    return not (image.source == "FILE" and image.file_format in NO_ALPHA_FORMATS)


def can_read_file_bytes(image):
    buffer_access = imbuf is not None and hasattr(imbuf.types.ImBuf, "with_buffer")
    # A generated, sequence, movie or tiled image, or one painted on since it was loaded, is
    # not what its file holds.
    return buffer_access and image.source == "FILE" and not image.is_dirty


def texels(count):
    return "1 texel has" if count == 1 else f"{count} texels have"


def add_file_bytes(core_scene, image, byte_storage):
    """The texture index from the image file's bytes, or None if the file is not a byte image
    that imbuf reads (then the caller goes through Image.pixels)."""
    if image.packed_file is None:
        return read_file_bytes(core_scene, image.name, bpy.path.abspath(image.filepath, library=image.library),
                               byte_storage)
    return read_buffer_bytes(core_scene, image.name, image.packed_file.data, byte_storage)


def read_buffer_bytes(core_scene, name, data, byte_storage):
    """As add_file_bytes, for a file's bytes in memory (a packed file's)."""
    try:
        buffer = imbuf.load_from_buffer(data)
    except (OSError, ValueError, TypeError):
        return None
    return add_buffer_bytes(core_scene, name, buffer, byte_storage)


def read_file_bytes(core_scene, name, path, byte_storage):
    """As add_file_bytes, for the file at `path`."""
    try:
        buffer = imbuf.load(path)
    except (OSError, ValueError, TypeError):
        return None
    return add_buffer_bytes(core_scene, name, buffer, byte_storage)


def add_buffer_bytes(core_scene, name, buffer, byte_storage):
    """The texture index of an ImBuf's bytes (freed after), or None for a float one."""
    try:
        if buffer.buffer_type != "BYTE":
            return None  # float files are turned into scene-linear floats by the data-block: use it
        with buffer.with_buffer() as view:
            return core_scene.add_texture(name, view, storage=byte_storage)
    finally:
        buffer.free()


def add_pixels(core_scene, image, byte_storage, premultiplied=False):
    had_data = image.has_data  # before image.size, which loads the image
    try:
        width, height = image.size
        if width == 0 or height == 0 or len(image.pixels) != width * height * 4:
            raise ValueError(f"image '{image.name}' has no pixels (missing file?)")
        pixels = np.empty((height, width, 4), dtype=np.float32)
        image.pixels.foreach_get(pixels.reshape(-1))
        if premultiplied:
            pixels[..., :3] *= pixels[..., 3:]
        # Byte images come back as byte / 255 in their colour space; float images are scene linear.
        storage = "half" if image.is_float else byte_storage
        index = core_scene.add_texture(image.name, pixels, storage=storage, clear_unusable=True)
        del pixels
        return index
    finally:
        if not had_data:
            image.buffers_free()  # loaded only for this export: give Blender's copy back
