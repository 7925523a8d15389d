# SPDX-License-Identifier: GPL-3.0-or-later
"""What the X server's screen shows (the GUI tests, bench/viewport.py):
XGetImage through Xlib, on a connection of its own, so it reads what
Blender drew and swapped, whichever way Blender's GPU backend drew it.

`python3 xscreen.py X Y W H FILE` (Watcher) reads a rectangle again and
again in a process of its own, for a test that watches the screen while
Blender renders: a Python thread inside Blender doing the same crashed
Blender now and then (in numpy's ctypes bridge, during a render)."""

import ctypes
import ctypes.util
import os
import shutil
import subprocess
import sys
import time

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
        raw = np.frombuffer(ctypes.string_at(im.data, height * row), dtype=np.uint8)
        self.x11.XFree(ctypes.cast(im.data, ctypes.c_void_p))
        self.x11.XFree(ctypes.cast(img, ctypes.c_void_p))
        bgrx = raw.reshape(height, row)[:, :width * 4].reshape(height, width, 4)
        return bgrx[..., 2::-1]  # 24-bit TrueColor as Xvfb serves it: B, G, R, pad


def region_rect(window, region):
    """A Blender region's rectangle on the screen (x, y from the top-left,
    width, height), for Screen.grab."""
    top = window.y + window.height - (region.y + region.height)
    return window.x + region.x, top, region.width, region.height


class Watcher:
    """A process reading a screen rectangle every `seconds` into a file of
    raw RGB frames, until stop() (or its limits, below); frames() gives
    them as (n, h, w, 3)."""

    def __init__(self, rect, path, seconds=0.02):
        self.rect, self.path = rect, path
        # The system's Python, which has numpy as Blender's does on Debian
        # (a python3 first on PATH, such as a virtualenv's, may not).
        python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else shutil.which("python3")
        self.process = subprocess.Popen([python, os.path.abspath(__file__)] + [str(v) for v in rect]
                                        + [path, str(seconds)], stdin=subprocess.PIPE)

    def stop(self):
        self.process.stdin.close()  # the watcher ends at the next frame
        self.process.wait(timeout=10)

    def frames(self):
        _, _, w, h = self.rect
        data = np.fromfile(self.path, dtype=np.uint8)
        return data[:data.size - data.size % (w * h * 3)].reshape(-1, h, w, 3)


# A watcher ends by itself after this long or this many bytes: a Blender
# that locks up must not leave it filling /tmp (a RAM disk in the chroots)
# until the run's time limit. A normal F12 test writes 0.5-1.5 GB.
MAX_WATCH_SECONDS = 120.0
MAX_WATCH_BYTES = 3 << 30


def _watch(x, y, w, h, path, seconds):
    import select
    import time
    screen = Screen()
    end = time.monotonic() + MAX_WATCH_SECONDS
    with open(path, "wb") as out:
        written = 0
        while time.monotonic() < end and written < MAX_WATCH_BYTES:
            frame = screen.grab(x, y, w, h)
            if frame is not None:
                data = np.ascontiguousarray(frame).tobytes()
                out.write(data)
                out.flush()
                written += len(data)
            ready, _, _ = select.select([sys.stdin], [], [], seconds)
            if ready and not sys.stdin.buffer.read1(1):  # closed: stop
                return


if __name__ == "__main__":
    _watch(*[int(v) for v in sys.argv[1:5]], sys.argv[5], float(sys.argv[6]))
