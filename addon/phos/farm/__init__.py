# SPDX-License-Identifier: GPL-3.0-or-later
"""Render farms for Phos: caches made once, frames and regions on many machines.

    python3 -m phos.farm submit scene.blend --frames 1-250 [--regions 2x2] [--local N | --slurm-args ...]
    python3 -m phos.farm status JOB_DIR
    python3 -m phos.farm resubmit JOB_DIR TASK...

A job is a graph of tasks, each one run of `blender -b` (docs/farm.md):
one cache task that traces the photon maps and fills the irradiance cache
for the camera path of every key frame and renders nothing; then a task
per frame, or per region of each frame, that loads those caches; then a
stitch task per frame split into regions. The graph is built once
(job.py) and run by Slurm (slurm.py), by local processes (local.py), or
by Flamenco through its own job type (flamenco/phos_farm.js), which
builds the same graph.

Nothing here imports bpy but blender_task.py, which runs inside each
task's Blender: the command line works with any Python 3 on the
submitting machine, with this add-on's folder on PYTHONPATH.
"""
