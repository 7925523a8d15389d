# SPDX-License-Identifier: GPL-3.0-or-later
"""What the X server's screen shows (the GUI tests, bench/viewport.py):
XGetImage through Xlib, on a connection of its own, so it reads what
Blender drew and swapped, whichever way Blender's GPU backend drew it, and
may be called from any thread."""

import ctypes
import ctypes.util

import numpy as np


class _XImage(ctypes.Structure):
    """The head of Xlib's XImage (X11/Xlib.h), up to what is read here."""
    _fields_ = [("width", ctypes.c_int), ("height", ctypes.c_int), ("xoffset", ctypes.c_int),
                ("format", ctypes.c_int), ("data", ctypes.POINTER(ctypes.c_uint8)),
                ("byte_order", ctypes.c_int), ("bitmap_unit", ctypes.c_int), ("bitmap_bit_order", ctypes.c_int),
                ("bitmap_pad", ctypes.c_int), ("depth", ctypes.c_int), ("bytes_per_line", ctypes.c_int),
                ("bits_per_pixel", ctypes.c_int)]


class Screen:
    """A connection to the X server of $DISPLAY."""

    def __init__(self):
        x11 = self.x11 = ctypes.CDLL(ctypes.util.find_library("X11"))
        x11.XOpenDisplay.restype = ctypes.c_void_p
        x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
        x11.XDefaultRootWindow.restype = ctypes.c_ulong
        x11.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
        x11.XGetImage.restype = ctypes.POINTER(_XImage)
        x11.XGetImage.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_int, ctypes.c_uint,
                                  ctypes.c_uint, ctypes.c_ulong, ctypes.c_int]
        x11.XFree.argtypes = [ctypes.c_void_p]
        self.display = x11.XOpenDisplay(None)
        if not self.display:
            raise RuntimeError("cannot open the X display")
        self.root = x11.XDefaultRootWindow(self.display)

    def grab(self, x, y, width, height):
        """RGB uint8 pixels (height, width, 3) of a screen rectangle, rows
        top-down as X counts them, or None if the server refused."""
        img = self.x11.XGetImage(self.display, self.root, x, y, width, height, 0xFFFFFFFF, 2)  # ZPixmap
        if not img:
            return None
        im = img.contents
        row = im.bytes_per_line
        raw = np.ctypeslib.as_array(im.data, shape=(height * row,)).copy()
        self.x11.XFree(ctypes.cast(im.data, ctypes.c_void_p))
        self.x11.XFree(ctypes.cast(img, ctypes.c_void_p))
        bgrx = raw.reshape(height, row)[:, :width * 4].reshape(height, width, 4)
        return bgrx[..., 2::-1]  # 24-bit TrueColor as Xvfb serves it: B, G, R, pad


def region_rect(window, region):
    """A Blender region's rectangle on the screen (x, y from the top-left,
    width, height), for Screen.grab."""
    top = window.y + window.height - (region.y + region.height)
    return window.x + region.x, top, region.width, region.height
