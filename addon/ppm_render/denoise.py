"""Denoising with the Intel Open Image Denoise library Blender itself ships (the one its Denoise
node and Cycles use), called through its C API with ctypes: nothing extra in the add-on.

Official Blender builds (4.2 and later, and bpy) load `libOpenImageDenoise.so.2` into the process
from their `lib` folder; Debian's Blender 3.4 has none, and there `available()` says why not.
The filter is OIDN's "RT" for HDR renders, with Cycles' Denoising Albedo and Normal as guides
(premultiplied RGB, as Cycles denoises it; alpha is left as it is).
"""

import ctypes
import os
import sys

import numpy as np

DEVICE_CPU = 1  # OIDN_DEVICE_TYPE_CPU
FORMAT_FLOAT3 = 3  # OIDN_FORMAT_FLOAT3
NAMES = {"linux": ("libOpenImageDenoise.so.2", "libOpenImageDenoise.so.1"),
         "darwin": ("libOpenImageDenoise.2.dylib", "libOpenImageDenoise.1.dylib"),
         "win32": ("OpenImageDenoise.dll",)}

_library = None  # the loaded library, or the reason there is none (a str)


def blender_library_folders():
    """Where a Blender build keeps its shared libraries: next to the binary, or in the bpy module."""
    folders = []
    try:
        import bpy

        folders.append(os.path.join(os.path.dirname(bpy.__file__), "lib"))
        if bpy.app.binary_path:
            home = os.path.dirname(bpy.app.binary_path)
            folders += [os.path.join(home, "lib"), os.path.join(home, "blender.shared"), home]
    except (ImportError, AttributeError):
        pass
    return folders


def load():
    """The OIDN library (ctypes.CDLL); raises RuntimeError saying why there is none."""
    global _library
    if _library is None:
        _library = find_library()
    if isinstance(_library, str):
        raise RuntimeError(_library)
    return _library


def find_library():
    names = NAMES.get(sys.platform if sys.platform in NAMES else "linux")
    candidates = list(names)  # already in the process (bpy loads it), or on the loader's path
    candidates += [os.path.join(folder, name) for folder in blender_library_folders() for name in names]
    for candidate in candidates:
        if os.sep in candidate and not os.path.exists(candidate):
            continue
        try:
            return declare(ctypes.CDLL(candidate))
        except (OSError, AttributeError):
            continue
    return ("this Blender has no Open Image Denoise library (official Blender builds have one; "
            "Debian's does not)")


def declare(lib):
    """Argument and result types of the calls used (OIDN 1.x and 2.x share them)."""
    p, s = ctypes.c_void_p, ctypes.c_size_t
    lib.oidnNewDevice.restype, lib.oidnNewDevice.argtypes = p, [ctypes.c_int]
    lib.oidnCommitDevice.argtypes = [p]
    lib.oidnNewFilter.restype, lib.oidnNewFilter.argtypes = p, [p, ctypes.c_char_p]
    lib.oidnSetSharedFilterImage.argtypes = [p, ctypes.c_char_p, p, ctypes.c_int, s, s, s, s, s]
    lib.oidnCommitFilter.argtypes = [p]
    lib.oidnExecuteFilter.argtypes = [p]
    lib.oidnGetDeviceError.restype = ctypes.c_int
    lib.oidnGetDeviceError.argtypes = [p, ctypes.POINTER(ctypes.c_char_p)]
    lib.oidnReleaseFilter.argtypes = [p]
    lib.oidnReleaseDevice.argtypes = [p]
    set_bool = getattr(lib, "oidnSetFilterBool", None) or lib.oidnSetFilter1b  # 2.x, 1.x
    set_bool.argtypes = [p, ctypes.c_char_p, ctypes.c_bool]
    lib.set_filter_bool = set_bool
    return lib


def available():
    """(True, "") or (False, why not)."""
    try:
        load()
        return True, ""
    except RuntimeError as error:
        return False, str(error)


def denoise(color, albedo=None, normal=None):
    """`color` (H, W, 3 or 4) linear HDR, premultiplied; optional (H, W, 3) albedo and normal guides
    (normal needs albedo, as OIDN requires). Returns a new array of color's shape with RGB denoised
    and alpha, if any, unchanged. Raises RuntimeError with OIDN's message if it fails."""
    lib = load()
    color = np.asarray(color, dtype=np.float32)
    h, w = color.shape[:2]
    rgb = np.ascontiguousarray(color[..., :3])
    images = {"color": rgb}
    if albedo is not None:
        images["albedo"] = np.ascontiguousarray(albedo, dtype=np.float32)
        if normal is not None:
            images["normal"] = np.ascontiguousarray(normal, dtype=np.float32)
    for name, image in images.items():
        if image.shape != (h, w, 3):
            raise ValueError(f"denoise: {name} has shape {image.shape}, expected {(h, w, 3)}")
    output = np.empty_like(rgb)
    device = lib.oidnNewDevice(DEVICE_CPU)
    if not device:
        raise RuntimeError("Open Image Denoise: no CPU device")
    try:
        lib.oidnCommitDevice(device)
        check(lib, device)
        filt = lib.oidnNewFilter(device, b"RT")
        try:
            for name, image in (*images.items(), ("output", output)):
                lib.oidnSetSharedFilterImage(filt, name.encode(), image.ctypes.data, FORMAT_FLOAT3, w, h, 0, 12,
                                             12 * w)
            lib.set_filter_bool(filt, b"hdr", True)
            lib.oidnCommitFilter(filt)
            check(lib, device)
            lib.oidnExecuteFilter(filt)
            check(lib, device)
        finally:
            lib.oidnReleaseFilter(filt)
    finally:
        lib.oidnReleaseDevice(device)
    result = color.copy()
    result[..., :3] = output
    return result


def check(lib, device):
    message = ctypes.c_char_p()
    if lib.oidnGetDeviceError(device, ctypes.byref(message)) != 0:
        text = message.value.decode(errors="replace") if message.value else "unknown error"
        raise RuntimeError(f"Open Image Denoise: {text}")
