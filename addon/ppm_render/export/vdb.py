"""OpenVDB files (.vdb) -> the core's sparse voxel grids (Scene.add_sparse_grid).

A reader of its own, in Python with numpy and zlib, rather than OpenVDB linked into the core: Blender
loads its own OpenVDB (and c-blosc) into its process, and a second copy there may clash with it. It
reads what Volume objects hold: float and vec3s grids (trees 5-4-3), file versions 222 and later
(OpenVDB 3 on), saved as float or half, uncompressed, ZIP or Blosc (LZ4; decompressed by the core's
ppm_core.blosc_decompress). The format as OpenVDB's io/Archive.cc, tree/*Node.h and
io/Compression.h write it: a header, then per grid a descriptor, compression flags, metadata, a
transform, the tree's topology (root tiles and children; internal nodes' child and value masks and
tile values; leaves' value masks) and then every leaf's values. Little-endian, as every producer.

A grid becomes bricks of 8^3 values (its leaves, z fastest), constant bricks for its tiles, and the
4x4 matrix from index space (voxel centres at integers) to the file's world space, which is the
Volume object's local space in Blender.
"""
from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass, field

import numpy as np

MAGIC = 0x56444220
MIN_VERSION = 222  # per-grid compression flags and per-node metadata bytes (OpenVDB 3.0)
ZIP, ACTIVE_MASK, BLOSC = 0x1, 0x2, 0x4
VALUE_TYPES = {"Tree_float_5_4_3": 1, "Tree_vec3s_5_4_3": 3}  # tree type -> channels
HALF_SUFFIX = "_HalfFloat"
LEAF, INTERNAL4, INTERNAL5 = 3, 4, 5  # log2 of the nodes' edges in their children
MAX_TILE_BRICKS = 1 << 22  # constant bricks a grid's tiles may become in all (a root tile alone is 512^3)


class VdbError(ValueError):
    """A file this reader cannot read, with the reason."""


@dataclass
class Grid:
    name: str
    grid_class: str
    channels: int
    index_to_object: np.ndarray  # 4x4, column vectors
    background: np.ndarray
    origins: np.ndarray = None  # (bricks, 3) int32
    values: np.ndarray = None  # (bricks, 512, channels) float32
    tile_origins: list = field(default_factory=list)  # the constant bricks' origins
    tile_values: list = field(default_factory=list)
    skipped_tiles: int = 0  # tiles beyond MAX_TILE_BRICKS (a root tile): left out

    def constant_bricks(self):
        """(origins (m, 3) int32, values (m, channels) float32) of the tiles' bricks."""
        if not self.tile_origins:
            return np.zeros((0, 3), np.int32), np.zeros((0, self.channels), np.float32)
        return (np.concatenate(self.tile_origins).astype(np.int32),
                np.concatenate(self.tile_values).astype(np.float32).reshape(-1, self.channels))

    def index_box(self):
        """(lo, hi) index coordinates of every brick, leaves and tiles (hi exclusive); None if empty."""
        origins = [o for o in (self.origins, *self.tile_origins) if o is not None and len(o)]
        if not origins:
            return None
        every = np.concatenate(origins)
        return every.min(axis=0), every.max(axis=0) + 8


class Reader:
    def __init__(self, data):
        self.data = memoryview(data)
        self.at = 0

    def take(self, n):
        if n < 0 or self.at + n > len(self.data):
            raise VdbError("the file ends before its data does (truncated?)")
        out = self.data[self.at:self.at + n]
        self.at += n
        return out

    def unpack(self, fmt):
        size = struct.calcsize(fmt)
        values = struct.unpack("<" + fmt, self.take(size))
        return values if len(values) > 1 else values[0]

    def string(self):
        return bytes(self.take(self.unpack("I"))).decode("utf-8", "replace")

    def metadata(self):
        """A MetaMap: {name: (type, raw bytes)}, every entry skipped by its size."""
        out = {}
        for _ in range(self.unpack("I")):
            name, kind = self.string(), self.string()
            out[name] = (kind, bytes(self.take(self.unpack("I"))))
        return out

    def mask(self, log2):
        """A node mask of 2^(3 log2) bits as booleans (bit n: byte n >> 3, bit n & 7)."""
        return np.unpackbits(np.frombuffer(self.take((1 << (3 * log2)) // 8), np.uint8), bitorder="little").astype(bool)


def read(path, names=None, blosc=None):
    """{name: Grid} of the float and vec3s grids in the .vdb file at `path` (only `names`, if given).
    `blosc(bytes) -> bytes` decompresses a Blosc chunk (ppm_core.blosc_decompress). VdbError for a
    file it cannot read."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as error:
        raise VdbError(f"cannot be read: {error.strerror or error}") from error
    return read_bytes(data, names, blosc)


def read_bytes(data, names=None, blosc=None):
    """read()'s grids from the file's bytes."""
    try:
        return _read(data, names, blosc)
    except VdbError:
        raise
    except (struct.error, ValueError, IndexError, OverflowError, MemoryError) as error:  # corrupt data read on
        raise VdbError(f"corrupt ({type(error).__name__}: {error})") from error


def _read(data, names, blosc):
    r = Reader(data)
    if len(data) < 8 or r.unpack("q") != MAGIC:
        raise VdbError("not an OpenVDB file")
    version = r.unpack("I")
    if version < MIN_VERSION:
        raise VdbError(f"file format {version} is older than OpenVDB 3's ({MIN_VERSION})")
    r.unpack("II")  # library version
    seekable = r.unpack("B") != 0
    r.take(36)  # UUID
    r.metadata()
    grids, instances = {}, []
    for _ in range(r.unpack("i")):
        unique, tree_type, parent = r.string(), r.string(), r.string()
        _, _, end = r.unpack("qqq")
        name = unique.split("\x1e")[0]
        half = tree_type.endswith(HALF_SUFFIX)
        tree_type = tree_type[:-len(HALF_SUFFIX)] if half else tree_type
        wanted = tree_type in VALUE_TYPES and (names is None or name in names) and name not in grids
        if not wanted and seekable:
            r.at = end
            continue
        if tree_type not in VALUE_TYPES:  # a stream file's grids are read in turn: this one cannot be
            raise VdbError(f"its grid '{name}' ({tree_type}) cannot be skipped in a stream file")
        grid = read_grid(r, name, VALUE_TYPES[tree_type], half, bool(parent), blosc)
        if not wanted:
            continue
        if parent:
            instances.append((grid, parent.split("\x1e")[0]))
        grids[name] = grid
        if seekable:
            r.at = end
    for grid, parent in instances:  # an instance shares its parent's tree
        source = grids.get(parent)
        if source is not None:
            grid.origins, grid.values = source.origins, source.values
            grid.tile_origins, grid.tile_values = source.tile_origins, source.tile_values
    return grids


def read_grid(r, name, channels, half, instance, blosc):
    flags = r.unpack("I")
    meta = r.metadata()
    kind, raw = meta.get("is_saved_as_half_float", ("bool", b"\0"))
    half = half or (kind == "bool" and raw[:1] not in (b"", b"\0"))
    grid_class = meta.get("class", ("string", b"unknown"))[1].decode("utf-8", "replace")
    index_to_object = transform(r)
    grid = Grid(name, grid_class, channels, index_to_object, np.zeros(channels, np.float32))
    if instance:
        return grid
    Tree(r, grid, flags, half, blosc).read()
    return grid


def transform(r):
    """The 4x4 index-to-object matrix (column vectors) of a grid's map."""
    kind = r.string()
    m = np.eye(4)
    if kind in ("ScaleMap", "UniformScaleMap"):
        scale = r.unpack("3d")
        r.take(12 * 8)  # voxel size, inverse scale, its square, 1 / (2 scale): derived
        m[:3, :3] = np.diag(scale)
    elif kind in ("ScaleTranslateMap", "UniformScaleTranslateMap"):
        translation, scale = r.unpack("3d"), r.unpack("3d")
        r.take(12 * 8)
        m[:3, :3], m[:3, 3] = np.diag(scale), translation
    elif kind == "TranslationMap":
        m[:3, 3] = r.unpack("3d")
    elif kind in ("AffineMap", "UnitaryMap"):
        m = np.array(r.unpack("16d")).reshape(4, 4).T  # stored row-vector, translation in the last row
    else:
        raise VdbError(f"its transform ({kind}) is not linear; only linear maps are read")
    if not np.all(np.isfinite(m)):
        raise VdbError("its transform is not finite")
    return m


class Tree:
    """A grid's topology then its leaves' values, into `grid`."""

    def __init__(self, r, grid, flags, half, blosc):
        self.r, self.grid, self.flags, self.half, self.blosc = r, grid, flags, half, blosc
        self.c = grid.channels
        self.leaves = []  # (origin, value mask)
        self.tile_bricks = 0

    def read(self):
        r, c = self.r, self.c
        r.unpack("i")  # buffer count (1)
        self.grid.background = np.array(r.unpack(f"{c}f"), np.float32).reshape(c)
        tiles, children = r.unpack("II")
        for _ in range(tiles):
            origin = np.array(r.unpack("3i"), np.int32)
            value = np.array(r.unpack(f"{c}f"), np.float32)
            r.unpack("B")
            self.tile(origin, 1 << 12, value)
        for _ in range(children):
            self.internal(np.array(r.unpack("3i"), np.int32), INTERNAL5)
        self.read_leaves()

    def tile(self, origin, edge, value):
        """A constant region `edge` voxels wide from `origin`, as constant bricks (none where it holds
        the background, which the core's grid reads as 0 like everywhere outside its bricks)."""
        if np.all(value == self.grid.background):
            return
        per_axis = edge // 8
        if self.tile_bricks + per_axis ** 3 > MAX_TILE_BRICKS:
            self.grid.skipped_tiles += 1
            return
        self.tile_bricks += per_axis ** 3
        steps = np.arange(per_axis, dtype=np.int32) * 8
        block = np.stack(np.meshgrid(steps, steps, steps, indexing="ij"), axis=-1).reshape(-1, 3) + origin
        self.grid.tile_origins.append(block)
        self.grid.tile_values.append(np.tile(value.reshape(1, -1), (len(block), 1)))

    def internal(self, origin, log2):
        """An internal node of 2^(3 log2) slots at `origin`: masks, tile values, then its children."""
        child_log2 = LEAF if log2 == INTERNAL4 else INTERNAL4
        span = 1 << (child_log2 if log2 == INTERNAL4 else child_log2 + LEAF)  # voxels a slot covers
        children, active = self.r.mask(log2), self.r.mask(log2)
        values = self.value_record(log2, active)
        slots = np.arange(1 << (3 * log2))
        offsets = np.stack([slots >> (2 * log2), (slots >> log2) & ((1 << log2) - 1), slots & ((1 << log2) - 1)], 1)
        for n in np.flatnonzero(~children & np.any(values != self.grid.background, axis=1)):
            self.tile(origin + offsets[n] * span, span, values[n])
        for n in np.flatnonzero(children):
            child = origin + offsets[n] * span
            if log2 == INTERNAL4:
                self.leaves.append((child, self.r.mask(LEAF)))
            else:
                self.internal(child, INTERNAL4)

    def read_leaves(self):
        count = len(self.leaves)
        self.grid.origins = np.array([o for o, _ in self.leaves], np.int32).reshape(count, 3)
        values = np.empty((count, 512, self.c), np.float32)
        for k, (_, mask) in enumerate(self.leaves):
            self.r.mask(LEAF)  # the mask again
            values[k] = self.value_record(LEAF, mask)
        self.grid.values = values

    def value_record(self, log2, active):
        """The values (count, channels) of a node of 2^(3 log2) slots: the stored ones where `active`, the
        inactive ones rebuilt from the record's metadata byte."""
        r, c, bg, count = self.r, self.c, self.grid.background, 1 << (3 * log2)
        meta = r.unpack("b")
        inactive0, inactive1 = (bg if meta == 0 else -bg), bg
        if meta in (2, 4, 5):
            inactive0 = np.array(r.unpack(f"{c}f"), np.float32)
        if meta == 5:
            inactive1 = np.array(r.unpack(f"{c}f"), np.float32)
        selection = r.mask(log2) if meta in (3, 4, 5) else None
        stored = int(active.sum()) if (self.flags & ACTIVE_MASK) and meta != 6 else count
        data = self.values(stored)
        if stored == count:
            return data
        out = np.where(selection[:, None], inactive1, inactive0) if selection is not None else \
            np.broadcast_to(inactive0, (count, c)).copy()
        out[active] = data
        return out

    def values(self, count):
        """`count` stored values (count, channels) float32, decompressed."""
        if self.half and count == 0:
            return np.zeros((0, self.c), np.float32)
        element = np.float16 if self.half else np.float32
        nbytes = count * self.c * np.dtype(element).itemsize
        if self.flags & (BLOSC | ZIP):
            size = self.r.unpack("q")
            raw = self.r.take(abs(size) if size <= 0 else size)
            if size > 0:
                raw = self.decompress(raw, nbytes)
        else:
            raw = self.r.take(nbytes)
        if len(raw) != nbytes:
            raise VdbError(f"a node's values are {len(raw)} bytes, not {nbytes}")
        return np.frombuffer(raw, element).astype(np.float32).reshape(count, self.c)

    def decompress(self, raw, nbytes):
        if self.flags & BLOSC:
            if self.blosc is None:
                raise VdbError("Blosc-compressed, and no Blosc decompressor was given")
            try:
                return self.blosc(bytes(raw))
            except ValueError as error:
                raise VdbError(str(error)) from error
        try:
            return zlib.decompress(raw, bufsize=max(nbytes, 1))
        except zlib.error as error:
            raise VdbError(f"corrupt ZIP data: {error}") from error
