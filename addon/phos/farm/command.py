# SPDX-License-Identifier: GPL-3.0-or-later
"""How to start the farm's command line from anywhere: a Slurm node's
batch script (slurm.py) and the Farm panel (panel.py) run
`PYTHON -m phos.farm ...` with the folder holding this add-on on
PYTHONPATH.

The module is named after the add-on's folder, `phos`, whatever name
Blender imported it under: an extension is imported as
`bl_ext.<repository>.phos`, a name plain Python cannot import, but its
folder `<repository>/phos` is the package `phos` for a Python whose path
holds `<repository>`.
"""

import os
import shutil
import sys

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = os.path.basename(PACKAGE_DIR)
PACKAGE_PARENT = os.path.dirname(PACKAGE_DIR)
MODULE = PACKAGE + ".farm"


def python():
    """A Python to run the command line with: this one if it is a Python
    executable (not a Blender that embeds one), else python3 on PATH."""
    exe = sys.executable or ""
    if os.path.basename(exe).startswith("python") and os.path.isfile(exe):
        return exe
    return shutil.which("python3") or "python3"


def environment(env=None):
    """`env` (default: this process's) with the add-on's folder first on
    PYTHONPATH."""
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = PACKAGE_PARENT + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env
