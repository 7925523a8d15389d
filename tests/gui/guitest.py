# SPDX-License-Identifier: GPL-3.0-or-later
"""What the GUI tests share (tests/gui/test_*.py, run by tools/test-gui.sh under
Xvfb): checks collected and written as JSON to the file named after "--",
and steps run from a timer, since Blender's GUI must draw between them.

A test defines step(n) → the next step number (the same number waits, None
ends the test); every area is redrawn between steps, and an exception or
the time limit fails the test."""

import json
import os
import sys
import tempfile
import time
import traceback

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "blender"))

RESULT = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else os.path.join(tempfile.gettempdir(),
                                                                                    "phos_gui.json")
TIMEOUT = 120.0
_checks = []


def check(name, ok, detail=""):
    _checks.append({"check": name, "ok": bool(ok), "detail": detail})
    print("GUI %s: %s %s" % ("PASS" if ok else "FAIL", name, detail), flush=True)


def finish():
    with open(RESULT, "w") as f:
        json.dump(_checks, f, indent=1)
    failed = not _checks or not all(c["ok"] for c in _checks)
    os._exit(1 if failed else 0)


def area(kind):
    """The first area of a kind in the first window: (window, area, its WINDOW region)."""
    window = bpy.context.window_manager.windows[0]
    found = next(a for a in window.screen.areas if a.type == kind)
    return window, found, next(r for r in found.regions if r.type == 'WINDOW')


def run(step):
    """Run step(n) from a timer until it returns None."""
    state = {"step": 0, "t0": time.monotonic()}

    def tick():
        try:
            if time.monotonic() - state["t0"] > TIMEOUT:
                check("finished within %.0f s" % TIMEOUT, False, "stuck at step %d" % state["step"])
                finish()
            state["step"] = step(state["step"])
            if state["step"] is None:
                finish()
            for window in bpy.context.window_manager.windows:
                for a in window.screen.areas:
                    a.tag_redraw()
        except Exception:
            traceback.print_exc()
            check("no exception", False, traceback.format_exc(limit=3))
            finish()
        return 0.25

    bpy.app.timers.register(tick, first_interval=1.0, persistent=True)
