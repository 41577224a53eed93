"""Reads the colour of the EXR files dacrt writes: one part of scanlines, ZIP, ZIPS or none.

A render cut short keeps its exact sums (32-bit integer channels named exact.*), on which
Blender's own reader prints two lines per channel (and which, with the bare `samples` channel of
earlier versions, it refused outright). This reader takes the R, G and B channels of any file
dacrt writes as the float32 numbers in it, bit for bit, and says nothing about the others. Needs
numpy (Blender ships it); imports no bpy.
"""

import struct
import zlib

import numpy as np

_MAGIC = 20000630
_TILED, _LONG_NAMES, _DEEP, _MULTIPART = 0x200, 0x400, 0x800, 0x1000
_LINES_PER_BLOCK = {0: 1, 2: 1, 3: 16}  # NO, ZIPS, ZIP compression
_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}  # UINT, HALF, FLOAT


def _text(data, at):
    end = data.index(b"\0", at)
    return data[at:end].decode("utf-8", "replace"), end + 1


def _header(data, path):
    magic, version = struct.unpack_from("<II", data, 0)
    if magic != _MAGIC:
        raise ValueError(f"{path}: not an OpenEXR file")
    if version & (_TILED | _DEEP | _MULTIPART):
        raise ValueError(f"{path}: only single-part scanline EXR files are read")
    attributes, at = {}, 8
    while True:
        name, at = _text(data, at)
        if not name:
            return attributes, at
        kind, at = _text(data, at)
        (size,) = struct.unpack_from("<i", data, at)
        attributes[name] = (kind, data[at + 4:at + 4 + size])
        at += 4 + size


def _channels(value):
    """[(name, dtype)] in file order (sorted by name, as OpenEXR stores them)."""
    channels, at = [], 0
    while value[at] != 0:
        name, at = _text(value, at)
        (pixel_type,) = struct.unpack_from("<i", value, at)
        x_sampling, y_sampling = struct.unpack_from("<ii", value, at + 8)
        if (x_sampling, y_sampling) != (1, 1) or pixel_type not in _TYPES:
            raise ValueError(f"channel {name}: subsampled or of unknown type")
        channels.append((name, _TYPES[pixel_type]))
        at += 16
    return channels


def _unzip(block, expected):
    """OpenEXR's ZIP: zlib, then a delta predictor over bytes, then two halves interleaved."""
    raw = np.frombuffer(zlib.decompress(block), dtype=np.uint8)
    if raw.size != expected:
        raise ValueError("a ZIP block decompresses to the wrong size")
    deltas = raw.astype(np.int64)
    deltas[1:] -= 128
    undone = (np.cumsum(deltas) & 0xFF).astype(np.uint8)
    out = np.empty_like(undone)
    half = (undone.size + 1) // 2
    out[0::2], out[1::2] = undone[:half], undone[half:]
    return out.tobytes()


def read_rgb(path):
    """The image in path as float32 H×W×3, rows top-down (the file's order)."""
    planes = read_channels(path, ["R", "G", "B"])
    return np.stack([planes[c] for c in "RGB"], axis=-1)


def read_channels(path, wanted):
    """The channels named in wanted, each float32 H×W, rows top-down, by name."""
    with open(path, "rb") as file:
        data = file.read()
    attributes, at = _header(data, path)
    channels = _channels(attributes["channels"][1])
    compression = attributes["compression"][1][0]
    if compression not in _LINES_PER_BLOCK:
        raise ValueError(f"{path}: compression {compression} is not read (NO, ZIPS, ZIP are)")
    x0, y0, x1, y1 = struct.unpack("<iiii", attributes["dataWindow"][1])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    names = [name for name, _ in channels]
    missing = [name for name in wanted if name not in names]
    if missing:
        raise ValueError(f"{path}: no channel {', '.join(missing)} (it has {', '.join(names)})")
    lines_per_block = _LINES_PER_BLOCK[compression]
    blocks = (height + lines_per_block - 1) // lines_per_block
    offsets = struct.unpack_from(f"<{blocks}Q", data, at)
    line_bytes = sum(dtype.itemsize for _, dtype in channels) * width
    planes = {name: np.empty((height, width), dtype=np.float32) for name in wanted}
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        lines = min(lines_per_block, y1 + 1 - y)
        block = data[offset + 8:offset + 8 + size]
        if size < lines * line_bytes:  # OpenEXR stores a block raw when ZIP would not shrink it
            block = _unzip(block, lines * line_bytes)
        # A block holds, line after line, each channel's values of that line in turn.
        at = 0
        for line in range(y - y0, y - y0 + lines):
            for name, dtype in channels:
                count = width * dtype.itemsize
                if name in planes:
                    planes[name][line] = np.frombuffer(block, dtype=dtype, count=width,
                                                       offset=at).astype(np.float32)
                at += count
    return planes
