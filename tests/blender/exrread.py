# SPDX-License-Identifier: GPL-3.0-or-later
"""Read the channels of an OpenEXR file with numpy only (Blender's Python
has no EXR module, and bpy.data.images gives one layer of a multilayer EXR).

Enough for the files Blender writes: single-part scanline images, channels
of HALF, FLOAT or UINT, compression NONE, ZIPS or ZIP (Blender's default
for lossless output). Multilayer EXRs name channels "ViewLayer.Pass.R".
"""

import struct
import zlib

import numpy as np

_COMPRESSION_LINES = {0: 1, 2: 1, 3: 16}  # NONE, ZIPS, ZIP: scanlines per chunk
_PIXEL_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


def _read_header(data):
    magic, version = struct.unpack_from("<ii", data, 0)
    if magic != 20000630:
        raise ValueError("not an OpenEXR file")
    if version & 0x1A00:  # tiled, deep or multi-part
        raise ValueError("only single-part scanline EXR files are supported")
    pos, header = 8, {}
    while True:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        pos = end + 1
        if not name:
            return header, pos
        end = data.index(b"\0", pos)
        pos = end + 1
        size, = struct.unpack_from("<i", data, pos)
        pos += 4
        header[name] = data[pos:pos + size]
        pos += size


def _channel_list(raw):
    channels, p = [], 0
    while raw[p] != 0:
        end = raw.index(b"\0", p)
        pixel_type, = struct.unpack_from("<i", raw, end + 1)
        channels.append((raw[p:end].decode(), _PIXEL_TYPES[pixel_type]))
        p = end + 1 + 16  # type, pLinear + 3 reserved, x and y sampling
    return channels


def _unzip(block):
    """Undo EXR's ZIP: zlib, then the byte predictor, then the two-halves interleave."""
    b = np.frombuffer(zlib.decompress(block), np.uint8)
    b = (np.cumsum(b.astype(np.int64) - 128) + 128).astype(np.uint8)  # d[i] = d[i-1] + b[i] - 128
    out = np.empty_like(b)
    half = (len(b) + 1) // 2
    out[0::2], out[1::2] = b[:half], b[half:]
    return out.tobytes()


def read_channels(path):
    """{channel name: float32 array (height, width)}, rows bottom-up as in Blender."""
    with open(path, "rb") as f:
        data = f.read()
    header, pos = _read_header(data)
    channels = _channel_list(header["channels"])
    x0, y0, x1, y1 = struct.unpack("<iiii", header["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    compression = header["compression"][0]
    if compression not in _COMPRESSION_LINES:
        raise ValueError("EXR compression %d is not supported (use NONE, ZIPS or ZIP)" % compression)
    lines = _COMPRESSION_LINES[compression]
    chunks = -(-height // lines)
    offsets = struct.unpack_from("<%dQ" % chunks, data, pos)
    line_bytes = sum(dt.itemsize for _, dt in channels) * width
    out = {name: np.zeros((height, width), np.float32) for name, _ in channels}
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        block = data[offset + 8:offset + 8 + size]
        n = min(lines, y1 + 1 - y)
        if compression != 0 and size < line_bytes * n:  # stored uncompressed when that is smaller
            block = _unzip(block)
        q = 0
        for row in range(y - y0, y - y0 + n):
            for name, dt in channels:
                out[name][row] = np.frombuffer(block, dt, width, q)
                q += dt.itemsize * width
    return {name: a[::-1].copy() for name, a in out.items()}  # EXR rows go down


def read_passes(path, layer=None):
    """Passes of a multilayer EXR: {pass name: float32 (height, width, channels)}.

    Channels are ordered RGBA (or XYZ...) as Blender names them; `layer`
    picks a view layer (default: the first one found)."""
    order = {c: i for i, c in enumerate("RGBAXYZWUV")}
    grouped = {}
    for name, pixels in read_channels(path).items():
        parts = name.split(".")
        if len(parts) < 3:
            continue
        lay, pas, ch = ".".join(parts[:-2]), parts[-2], parts[-1]
        if layer is None:
            layer = lay
        if lay == layer:
            grouped.setdefault(pas, {})[ch] = pixels
    return {pas: np.stack([chs[c] for c in sorted(chs, key=lambda c: order.get(c, 99))], axis=-1)
            for pas, chs in grouped.items()}
