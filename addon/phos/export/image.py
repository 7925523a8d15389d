# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender images → core images (linear RGBA float, rows bottom-up).

The pixels of an image are read once per frame (foreach_get into float32)
and added to the core once, shared by every Image Texture node using it;
each node's interpolation, extension and projection travel with its
instruction in the material's shader program (nodes.py).

Reading and converting a 4096 × 2048 HDR takes about 0.4 s, every export.
The converted pixels of an image read from a file are therefore kept
between exports (the next F12, the viewport's next export) while the file
is the same (path, size and modification time), the image is not edited
in Blender (is_dirty) and its colour settings are the same: ConvertedCache.
"""

import collections
import os

import bpy
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


class _Warnings:
    """Collects the warnings of a conversion, to repeat them when it is reused."""

    def __init__(self):
        self.messages = []

    def warn(self, message):
        self.messages.append(message)


class ConvertedCache:
    """Converted pixels by image file, least recently used dropped first
    beyond `budget` bytes (they are a copy beside Blender's own buffer)."""

    def __init__(self, budget):
        self.budget, self.bytes = budget, 0
        self.entries = collections.OrderedDict()  # key → (data, warnings)
        self.conversions = 0                      # _read_pixels calls, for the tests

    @staticmethod
    def key(image):
        """What the conversion of a file image depends on, or None for an
        image that is not a file's, is packed or edited, or whose file
        cannot be read."""
        if image.source != 'FILE' or image.is_dirty or image.packed_file is not None:
            return None
        path = bpy.path.abspath(image.filepath, library=image.library)
        try:
            st = os.stat(path)
        except (OSError, ValueError):
            return None
        cs = image.colorspace_settings
        return (path, st.st_size, st.st_mtime_ns, cs.name, getattr(cs, "is_data", False), image.alpha_mode,
                getattr(image, "use_half_precision", False))

    def pixels(self, image, ctx, owner):
        """_read_pixels of the image, from the cache where it holds."""
        key = self.key(image)
        if key is not None and key in self.entries:
            self.entries.move_to_end(key)
            data, warnings = self.entries[key]
        else:
            collected = _Warnings()
            data = _read_pixels(image, collected, owner)
            self.conversions += 1
            warnings = collected.messages
            if key is not None and data is not None:
                self._keep(key, data, warnings)
        for message in warnings:
            ctx.warn(message)
        return data

    def _keep(self, key, data, warnings):
        size = data[0].nbytes
        if size > self.budget:
            return
        self.entries[key] = (data, warnings)
        self.bytes += size
        while self.bytes > self.budget:
            _, (old, _) = self.entries.popitem(last=False)
            self.bytes -= old[0].nbytes

    def clear(self):
        self.entries.clear()
        self.bytes = 0


# 512 MiB: two 4k float HDRs and a 4k 8-bit texture set's worth.
CONVERTED = ConvertedCache(512 << 20)


def _sky_settings(node, model, ctx):
    """The phos_sky_desc fields of a Sky Texture node (Blender's names
    across versions: 5.0 renamed dust_density to aerosol_density), with the
    texture laid out as the running Blender's Cycles lays it out."""
    if model in (core.PHOS_SKY_PREETHAM, core.PHOS_SKY_HOSEK_WILKIE):
        return {"model": model, "turbidity": float(node.turbidity), "ground_albedo": float(node.ground_albedo),
                "sun_direction": tuple(float(v) for v in node.sun_direction)}
    aerosol = getattr(node, "aerosol_density", None)
    if aerosol is None:
        aerosol = getattr(node, "dust_density", 1.0)
    layout = core.PHOS_SKY_LAYOUT_SPHERE if ctx.at_least(5, 0) else core.PHOS_SKY_LAYOUT_HEMISPHERE
    return {"model": model, "layout": layout, "sun_elevation": float(node.sun_elevation), "sun_rotation": float(node.sun_rotation),
            "sun_size": float(node.sun_size), "sun_intensity": float(node.sun_intensity),
            "sun_disc": int(bool(node.sun_disc)), "altitude": float(node.altitude),
            "air_density": float(node.air_density), "aerosol_density": float(aerosol),
            "ozone_density": float(node.ozone_density)}


# Computed skies by their settings, the few most recent (a viewport
# session edits one world; each texture is 1 or 2 MiB).
SKIES = collections.OrderedDict()
SKIES_KEPT = 8


def _baked_sky(settings):
    key = tuple(sorted(settings.items()))
    if key in SKIES:
        SKIES.move_to_end(key)
        return SKIES[key]
    textured = settings["model"] in (core.PHOS_SKY_SINGLE_SCATTERING, core.PHOS_SKY_MULTIPLE_SCATTERING)
    baked = core.sky_bake(settings, texture=textured)
    SKIES[key] = baked
    while len(SKIES) > SKIES_KEPT:
        SKIES.popitem(last=False)
    return baked


def add_sky(node, model, ctx, owner):
    """(core image id or None, data floats) of a Sky Texture node: the model
    computed by the core once per setting (and kept between exports), its
    texture added to the scene once per export; None if the settings are
    out of the model's range (warned)."""
    settings = _sky_settings(node, model, ctx)
    try:
        pixels, width, height, data = _baked_sky(settings)
    except core.PhosError as ex:
        ctx.warn("Phos: %s: node '%s': %s; the node is treated as unlinked" % (owner, node.name, ex))
        return None
    if pixels is None:
        return None, data
    # The texture depends on the sky, not on the sun's disc.
    key = ("sky",) + tuple(sorted((k, v) for k, v in settings.items()
                                  if k not in ("sun_size", "sun_intensity", "sun_disc", "sun_rotation")))
    if key not in ctx.images:
        ctx.images[key] = ctx.core.add_image(pixels, width, height)
        ctx.stats["images"] += 1
    return ctx.images[key], data


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
        ctx.image_pixels[key] = CONVERTED.pixels(image, ctx, owner)
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
