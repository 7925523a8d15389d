# SPDX-License-Identifier: GPL-3.0-or-later
"""A farm job: its settings, its task graph, and the folder it lives in.

The graph (docs/farm.md, "The job"):

    cache                       traces the photon maps and fills the
      |                         irradiance cache for every key frame's view
      +-- frame-F               regions 1x1: one task per frame
      +-- region-F-I            else one per region I of each frame F,
            +-- stitch-F        and one per frame, after its regions

With caches "per-frame" (an animation whose objects, lights or materials
move) there is no cache task: each frame or region task makes the caches
of its own frame, as a render on one machine does.

Each task is one `blender -b` run of the job's blend file with
`-- SUBCOMMAND --job-dir DIR ...` after the bootstrap below; Slurm,
local processes and Flamenco's job type (flamenco/phos_farm.js, which
writes the same arguments) only decide where and when it runs.

The job folder:

    job.json                    this job (Job.save)
    caches/                     photons.phospmf, irradiance.phosirc, caches.json
    frames/frame_0001.exr       the frames (stitched ones too)
    regions/frame_0001_r00.exr  the regions of a split frame
    tasks/NAME.json             each task's state, written by run_task
    logs/NAME.log               each task's Blender output, every attempt
"""

import itertools
import json
import os
import re
import shlex
import shutil

JOB_FILE = "job.json"
JOB_VERSION = 1
MAX_FRAME = 1048574        # Blender's last frame (MAXFRAME)
MAX_TASKS = 100000         # a typo such as 1-1000000 must not flood the manager

# The Python every task's Blender runs: find the installed Phos add-on
# (a legacy add-on "phos" or a 4.2+ extension "bl_ext.<repo>.phos"), enable
# it, and hand the arguments after `--` to its farm.blender_task.main().
# Flamenco's job type keeps the same line (tests/blender/test_farm.py
# compares them); it has no braces, which Flamenco would read as variables.
# If both a legacy add-on and an extension named phos are installed, the
# first Blender lists is taken.
BOOTSTRAP = ("import addon_utils,importlib;n=next((m.__name__ for m in addon_utils.modules() "
             "if m.__name__.rsplit('.',1)[-1]=='phos'),'');assert n,'Phos farm: error: the Phos add-on is "
             "not installed in this Blender';addon_utils.enable(n,default_set=False);"
             "importlib.import_module(n+'.farm.blender_task').main()")


class JobError(Exception):
    """A job that cannot be built or run as asked; the message says why."""


# ---------------------------------------------------------------- settings

def parse_frames(text, what="frames"):
    """'1-10, 20, 30-40' → [1, …, 10, 20, 30, …, 40]: sorted, without
    duplicates, non-negative frames only."""
    if not text or not text.strip():
        raise JobError("%s: none given; use e.g. '1-250' or '1-10,20,30-40'" % what)
    frames = set()
    for piece in text.split(","):
        piece = piece.strip()
        m = re.fullmatch(r"(\d+)(?:\s*-\s*(\d+))?", piece)
        if not m:
            raise JobError("%s: cannot read '%s' in '%s'; expected frames such as '7' or ranges such as "
                           "'1-250' (non-negative whole numbers), separated by commas" % (what, piece, text))
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) is not None else first
        if last > MAX_FRAME:
            raise JobError("%s: frame %d in '%s' is past Blender's last frame %d" % (what, last, text, MAX_FRAME))
        if first > last:
            raise JobError("%s: the range '%s' ends before it starts" % (what, piece))
        if last - first + 1 + len(frames) > MAX_TASKS:
            raise JobError("%s: '%s' has more than %d frames" % (what, text, MAX_TASKS))
        frames.update(range(first, last + 1))
    return sorted(frames)


def format_frames(frames):
    """[1, 2, 3, 7] → '1-3,7'."""
    pieces, i = [], 0
    while i < len(frames):
        j = i
        while j + 1 < len(frames) and frames[j + 1] == frames[j] + 1:
            j += 1
        pieces.append(str(frames[i]) if i == j else "%d-%d" % (frames[i], frames[j]))
        i = j + 1
    return ",".join(pieces)


def parse_regions(text):
    """'CxR' → (columns, rows), both at least 1."""
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text or "")
    if not m:
        raise JobError("regions: cannot read '%s'; expected COLUMNSxROWS such as '1x1' or '2x2'" % text)
    columns, rows = int(m.group(1)), int(m.group(2))
    if columns < 1 or rows < 1:
        raise JobError("regions: '%s' needs at least one column and one row" % text)
    if columns * rows > MAX_TASKS:
        raise JobError("regions: '%s' makes more than %d regions per frame" % (text, MAX_TASKS))
    return columns, rows


def choose_key_frames(frames, text):
    """The frames whose views the caches are made for: every frame to
    render by default, else the given ones, which must be among them."""
    if not text or not text.strip():
        return list(frames)
    keys = parse_frames(text, "key frames")
    outside = sorted(set(keys) - set(frames))
    if outside:
        raise JobError("key frames: %s not among the frames to render (%s)"
                       % (format_frames(outside), format_frames(frames)))
    return keys


def region_border(index, columns, rows):
    """Region `index` of a columns × rows split as Blender's border
    (min_x, max_x, min_y, max_y), fractions of the frame; index 0 is the
    bottom-left region, then along the bottom row. Neighbours share their
    edge value exactly, so Blender's border rects tile the frame."""
    c, r = index % columns, index // columns
    return c / columns, (c + 1) / columns, r / rows, (r + 1) / rows


# ------------------------------------------------------------------- tasks

class Task:
    """One run of Blender: its name, the stage it belongs to (cache,
    render, stitch), the arguments after `--`, the tasks it waits for."""

    def __init__(self, name, stage, args, after):
        self.name, self.stage, self.args, self.after = name, stage, list(args), list(after)

    def __repr__(self):
        return "Task(%r)" % self.name


STAGES = ("cache", "render", "stitch")
CACHES = ("shared", "per-frame")


class Job:
    """A farm job's settings (as job.json keeps them) and its task graph."""

    def __init__(self, blend_file, job_dir, frames, regions=(1, 1), key_frames=None,
                 blender="blender", blender_args=(), manager="local", manager_args=(), manager_ids=None,
                 caches="shared"):
        self.blend_file = os.path.abspath(blend_file)
        self.job_dir = os.path.abspath(job_dir)
        self.frames = list(frames)
        self.regions = tuple(regions)
        self.key_frames = list(key_frames) if key_frames is not None else list(self.frames)
        self.blender = blender               # a command, split as a shell would (a path with spaces quoted)
        self.blender_args = list(blender_args)
        self.manager = manager
        self.manager_args = list(manager_args)  # sbatch options of every task, resubmissions too
        self.manager_ids = dict(manager_ids or {})
        self._tasks = None
        if caches not in CACHES:
            raise JobError("caches: '%s' is not one of %s" % (caches, ", ".join(CACHES)))
        self.caches = caches
        if not self.frames:
            raise JobError("frames: none given")
        per_frame = 1 if not self.split else self.regions[0] * self.regions[1] + 1
        if (caches == "shared") + len(self.frames) * per_frame > MAX_TASKS:
            raise JobError("%d frames with regions %dx%d make more than %d tasks; render fewer frames or "
                           "regions per job" % (len(self.frames), self.regions[0], self.regions[1], MAX_TASKS))

    # The graph ---------------------------------------------------------

    @property
    def split(self):
        return self.regions != (1, 1)

    def _args(self, subcommand, *extra):
        return [subcommand, "--job-dir", self.job_dir] + [str(e) for e in extra]

    def tasks(self):
        """Every task in an order that runs each after what it waits for."""
        if self._tasks is None:
            self._tasks = self._make_tasks()
            self._by_name = {t.name: t for t in self._tasks}
        return self._tasks

    def _make_tasks(self):
        regions = "%dx%d" % self.regions
        out, after, own = [], [], []
        if self.caches == "shared":
            out.append(Task("cache", "cache", self._args("cache", "--frames", format_frames(self.frames),
                                                         "--key-frames", format_frames(self.key_frames)), []))
            after = ["cache"]
        else:
            own = ["--caches", "per-frame"]
        for f in self.frames:
            if not self.split:
                out.append(Task("frame-%d" % f, "render", self._args("frame", "--frame", f, *own), after))
                continue
            names = []
            for i in range(self.regions[0] * self.regions[1]):
                names.append("region-%d-%d" % (f, i))
                out.append(Task(names[-1], "render", self._args("region", "--frame", f, "--region", i, "--regions",
                                                                regions, *own), after))
            out.append(Task("stitch-%d" % f, "stitch", self._args("stitch", "--frame", f, "--regions", regions), names))
        return out

    def task(self, name):
        self.tasks()
        if name in self._by_name:
            return self._by_name[name]
        raise JobError("job %s has no task '%s' (its tasks: %s)"
                       % (self.job_dir, name, ", ".join(t.name for t in self.tasks()[:4]) + ", …"))

    def rerun(self, names, done=lambda name: False):
        """The tasks to run again for `names`, in the job's order: those;
        the stitch of every split frame one of them renders a region of
        (it read the old region); and, after the cache task, every task
        not `done` (after a failed cache task, none started)."""
        wanted = {self.task(n).name for n in names}
        for t in self.tasks():
            if t.stage == "stitch" and any(a in wanted for a in t.after):
                wanted.add(t.name)
            elif "cache" in wanted and t.stage != "cache" and not done(t.name):
                wanted.add(t.name)
        return [t.name for t in self.tasks() if t.name in wanted]

    def stage_tasks(self, stage):
        return [t for t in self.tasks() if t.stage == stage]

    def blender_command(self, task, threads=None):
        """The command line of `task`: Blender in the background on the
        job's blend file, the bootstrap, the task's arguments."""
        cmd = shlex.split(self.blender) + ["-b"] + self.blender_args
        if threads:
            cmd += ["-t", str(threads)]
        return cmd + [self.blend_file, "--python-exit-code", "1", "--python-expr", BOOTSTRAP, "--"] + task.args

    # The folder ---------------------------------------------------------

    def path(self, *parts):
        return os.path.join(self.job_dir, *parts)

    def clear(self):
        """Remove what an earlier job left in this folder (submit --overwrite):
        its job.json and the folders below, nothing else."""
        for sub in ("caches", "frames", "regions", "tasks", "logs"):
            shutil.rmtree(self.path(sub), ignore_errors=True)
        for name in (JOB_FILE, "submit.log"):
            if os.path.exists(self.path(name)):
                os.remove(self.path(name))

    def make_folders(self):
        for sub in ("caches", "frames", "regions", "tasks", "logs"):
            os.makedirs(self.path(sub), exist_ok=True)

    def save(self):
        data = {"version": JOB_VERSION, "blend_file": self.blend_file, "frames": format_frames(self.frames),
                "regions": "%dx%d" % self.regions, "key_frames": format_frames(self.key_frames),
                "blender": self.blender, "blender_args": self.blender_args, "manager": self.manager,
                "manager_args": self.manager_args, "manager_ids": self.manager_ids, "caches": self.caches}
        write_json_atomically(self.path(JOB_FILE), data)

    @classmethod
    def load(cls, job_dir):
        path = os.path.join(job_dir, JOB_FILE)
        try:
            with open(path) as f:
                data = json.load(f)
        except OSError as ex:
            raise JobError("%s is not a farm job folder: %s" % (job_dir, ex.strerror))
        except ValueError as ex:
            raise JobError("%s is damaged: %s" % (path, ex))
        if data.get("version") != JOB_VERSION:
            raise JobError("%s was written by another version of Phos's farm (version %s, this one reads %d)"
                           % (path, data.get("version"), JOB_VERSION))
        try:
            return cls(data["blend_file"], job_dir, parse_frames(data["frames"]), parse_regions(data["regions"]),
                       parse_frames(data["key_frames"], "key frames"), data["blender"], data["blender_args"],
                       data["manager"], data["manager_args"], data["manager_ids"], data["caches"])
        except (KeyError, TypeError) as ex:
            raise JobError("%s is damaged: %s is missing or wrong" % (path, ex))


_tmp_names = itertools.count()


def write_json_atomically(path, data):
    """Write `data` so that a reader never sees half a file, even if the
    writer is killed (a requeued task). Each call writes a temporary file
    of its own: a signal handler may write the same file while the code it
    interrupted was writing it."""
    tmp = "%s.%d.%d.tmp" % (path, os.getpid(), next(_tmp_names))
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, path)


def read_json(path, default=None):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return default
