# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender images → core images (linear RGBA float, rows bottom-up).

The pixels of an image are read once per frame (foreach_get into float32)
and added to the core once, shared by every Image Texture node using it;
each node's interpolation, extension and projection travel with its
instruction in the material's shader program (nodes.py).
"""

import numpy as np

from .. import core

# Colour spaces whose stored values are already linear: Blender 3.x's
# names, then those of 4.x and 5.x (whose configuration renamed them).
LINEAR_COLORSPACES = {'Linear', 'Linear ACES', 'Linear ACEScg', 'Non-Color', 'Raw', 'XYZ',
                      'Linear Rec.709', 'Linear Rec.2020', 'Linear CIE-XYZ E', 'Linear CIE-XYZ D65',
                      'ACEScg', 'ACES2065-1', 'Linear DCI-P3 D65', 'Linear FilmLight E-Gamut'}
SRGB_COLORSPACES = {'sRGB', 'sRGB 2.1'}


def _encoding(settings):
    """'linear', 'srgb' or None (another encoding) of an image's colour
    space: its data flag, Blender 5.3's interoperability id, then its name."""
    if getattr(settings, "is_data", False):
        return 'linear'
    interop = getattr(settings, "interop_id", "") or ""
    if interop == "data" or interop.startswith("lin_"):
        return 'linear'
    if interop.startswith("srgb_"):
        return 'srgb'
    if settings.name in SRGB_COLORSPACES:
        return 'srgb'
    return 'linear' if settings.name in LINEAR_COLORSPACES else None


def srgb_to_linear(c):
    """The sRGB EOTF (IEC 61966-2-1), elementwise on a float32 array."""
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)


def _read_pixels(image, ctx, owner):
    """(rgba float32 (w*h*4), width, height) of an image, or None if unusable."""
    if image.source not in {'FILE', 'GENERATED'}:
        ctx.warn("Phos: %s: image '%s' is a %s, which is not supported; treated as unlinked"
                 % (owner, image.name, image.source.lower()))
        return None
    width, height = image.size[:]  # loads the file if needed
    if width == 0 or height == 0 or not image.has_data:
        where = (" (file '%s')" % image.filepath) if image.filepath else ""
        ctx.warn("Phos: %s: image '%s' could not be loaded%s; treated as unlinked"
                 % (owner, image.name, where))
        return None
    channels = image.channels
    buf = np.empty(width * height * channels, dtype=np.float32)
    image.pixels.foreach_get(buf)
    buf = buf.reshape(-1, channels)
    rgba = np.empty((width * height, 4), dtype=np.float32)
    if channels >= 3:
        rgba[:, :3] = buf[:, :3]
        rgba[:, 3] = buf[:, 3] if channels >= 4 else 1.0
    elif channels == 2:
        rgba[:, :3] = buf[:, :1]
        rgba[:, 3] = buf[:, 1]
    else:
        rgba[:, :3] = buf[:, :1]
        rgba[:, 3] = 1.0

    space = image.colorspace_settings.name
    if not image.is_float:
        # 8-bit buffers come back as stored: encoded values for sRGB images.
        encoding = _encoding(image.colorspace_settings)
        if encoding == 'srgb':
            rgba[:, :3] = srgb_to_linear(rgba[:, :3])
        elif encoding is None:
            ctx.warn("Phos: %s: image '%s' uses colour space '%s', which Phos reads as linear"
                     % (owner, image.name, space))
    # Float buffers are converted to scene-linear by Blender on load.
    bad = ~np.isfinite(rgba)
    if bad.any():
        # A damaged HDR (or one written by a buggy tool) can hold NaN or
        # infinite values, which the core refuses: they count as black.
        ctx.warn("Phos: %s: image '%s' has %d pixels that are NaN or infinite; they render black"
                 % (owner, image.name, int(np.count_nonzero(bad.any(axis=1)))))
        rgba[bad] = 0.0
    return rgba.reshape(-1), width, height


def add_image(node, ctx, owner):
    """Core image id for an Image Texture node's image, or None if it cannot
    be used. The pixels go to the core once per image; interpolation,
    extension and projection are the node's (shader program flags).
    `owner` names the material or world for warnings."""
    image = node.image
    if image is None:
        return None
    key = image.original.as_pointer()
    if key in ctx.images:
        return ctx.images[key]
    if key not in ctx.image_pixels:
        ctx.image_pixels[key] = _read_pixels(image, ctx, owner)
    data = ctx.image_pixels[key]
    image_id = None
    if data is not None:
        pixels, width, height = data
        try:
            image_id = ctx.core.add_image(pixels, width, height)
        except core.PhosError as ex:
            raise core.PhosError("image '%s': %s" % (image.name, ex), ex.status) from None
        ctx.stats["images"] += 1
    ctx.images[key] = image_id
    return image_id
