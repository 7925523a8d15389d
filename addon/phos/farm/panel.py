# SPDX-License-Identifier: GPL-3.0-or-later
"""Render Properties → Phos → Farm: the job's settings, Submit, Status.

Submit saves the file (the farm renders the .blend on disk), writes the
job into a new folder under the jobs folder, and runs the command line
(`python -m phos.farm submit`, __main__.py) with Blender's own Python:
on Slurm it returns once sbatch has the job; with local processes it
runs in the background and Status shows its progress. The panel reads
the tasks' state from the job folder, as `status` does.
"""

import os
import shlex
import subprocess

import bpy
from bpy.props import EnumProperty, IntProperty, PointerProperty, StringProperty

from . import command, status
from .blender_task import TaskError, check_regions, check_scene
from .job import Job, JobError, choose_key_frames, parse_frames, parse_regions

ENGINE = 'PHOS'


class PhosFarmSettings(bpy.types.PropertyGroup):
    frames: StringProperty(
        name="Frames", default="",
        description="Frames to render, e.g. 1-250 or 1-10,20 (empty: the scene's frame range)")
    regions: StringProperty(
        name="Regions", default="1x1",
        description="Split each frame into COLUMNSxROWS regions rendered by separate tasks and stitched "
                    "afterwards (1x1: whole frames)")
    key_frames: StringProperty(
        name="Key Frames", default="",
        description="Frames whose camera views the photon maps and the irradiance cache are made for, "
                    "once for the whole job (empty: every frame rendered)")
    caches: EnumProperty(
        name="Caches", default='SHARED',
        items=(('SHARED', "Shared", "One cache task makes the photon maps and the irradiance cache for every frame "
                "(only the camera moves)", 0),
               ('PER_FRAME', "Per Frame", "Each frame makes its own caches (objects, lights or materials "
                "animate)", 1)))
    jobs_folder: StringProperty(
        name="Jobs Folder", default="//farm", subtype='DIR_PATH',
        description="Where each job gets a folder of its own (caches, frames, logs); every node must "
                    "reach it at the same path")
    manager: EnumProperty(
        name="Run On", default='SLURM',
        items=(('SLURM', "Slurm", "Submit the job's tasks with sbatch to the Slurm cluster this machine "
                "submits to", 0),
               ('LOCAL', "This Machine", "Run the job's tasks as local Blender processes, in the background", 1)))
    local_processes: IntProperty(
        name="Processes", default=2, min=1, max=256,
        description="Tasks run at the same time on this machine")
    slurm_args: StringProperty(
        name="sbatch Options", default="",
        description="More sbatch options for every task, e.g. '-p render -c 8' (partition, CPUs per task)")
    last_job: StringProperty(name="Last Job", default="", subtype='DIR_PATH',
                             description="The folder of the job submitted last from this file")
    last_status: StringProperty(name="Status", default="")


def _scene_frames(scene, settings):
    return settings.frames.strip() or "%d-%d" % (scene.frame_start, scene.frame_end)


def _new_job_folder(settings):
    root = bpy.path.abspath(settings.jobs_folder)
    stem = os.path.splitext(os.path.basename(bpy.data.filepath))[0] or "untitled"
    n = 1
    while os.path.exists(os.path.join(root, "%s_%03d" % (stem, n))):
        n += 1
    return os.path.join(root, "%s_%03d" % (stem, n))


class PHOS_OT_farm_submit(bpy.types.Operator):
    """Save the file and submit it as a farm job: caches made once, then every frame (or region)"""

    bl_idname = "phos.farm_submit"
    bl_label = "Submit to Farm"

    def execute(self, context):
        scene = context.scene
        settings = scene.phos_farm
        if not bpy.data.filepath:
            self.report({'ERROR'}, "Phos farm: save the .blend first: the farm renders the file on disk")
            return {'CANCELLED'}
        try:
            frames = parse_frames(_scene_frames(scene, settings))
            regions = parse_regions(settings.regions)
            choose_key_frames(frames, settings.key_frames)
            check_scene(scene)
            if regions != (1, 1):
                check_regions(scene)
        except (JobError, TaskError) as ex:
            self.report({'ERROR'}, "Phos farm: %s" % ex)
            return {'CANCELLED'}
        if bpy.data.is_dirty:
            bpy.ops.wm.save_mainfile()
        job_dir = _new_job_folder(settings)
        # Values as --option=value: an sbatch option as a value would be
        # read as an option of the command line.
        cmd = [command.python(), "-m", command.MODULE, "submit", bpy.data.filepath,
               "--frames=" + _scene_frames(scene, settings), "--regions=" + settings.regions,
               "--key-frames=" + settings.key_frames, "--job-dir=" + job_dir,
               "--caches=" + settings.caches.lower().replace("_", "-"),
               "--blender=" + shlex.quote(bpy.app.binary_path or "blender")]
        if settings.manager == 'LOCAL':
            cmd += ["--local=%d" % settings.local_processes]
        else:
            cmd += ["--slurm-args=" + settings.slurm_args]
        env = command.environment()
        os.makedirs(job_dir, exist_ok=True)
        log = open(os.path.join(job_dir, "submit.log"), "wb")
        try:
            proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                    start_new_session=True)
        except OSError as ex:
            self.report({'ERROR'}, "Phos farm: cannot run %s: %s" % (cmd[0], ex.strerror))
            return {'CANCELLED'}
        finally:
            log.close()
        settings.last_job = job_dir
        if settings.manager == 'SLURM':
            try:
                code = proc.wait(120)
            except subprocess.TimeoutExpired:
                code = None
            with open(os.path.join(job_dir, "submit.log"), errors="replace") as f:
                text = f.read().strip()
            if code != 0:
                self.report({'ERROR'}, "Phos farm: %s" % (text.splitlines()[-1] if text else "sbatch timed out"))
                return {'CANCELLED'}
        settings.last_status = "submitted"
        self.report({'INFO'}, "Phos farm: job submitted to %s: %s"
                    % ("Slurm" if settings.manager == 'SLURM' else "this machine", job_dir))
        return {'FINISHED'}


class PHOS_OT_farm_status(bpy.types.Operator):
    """Read the state of the last job's tasks"""

    bl_idname = "phos.farm_status"
    bl_label = "Refresh Status"

    def execute(self, context):
        settings = context.scene.phos_farm
        job_dir = bpy.path.abspath(settings.last_job)
        if not os.path.isfile(os.path.join(job_dir, "job.json")):
            # The command line has not written the job yet, or failed
            # before: what it said so far.
            try:
                with open(os.path.join(job_dir, "submit.log"), errors="replace") as f:
                    lines = f.read().strip().splitlines()
            except OSError:
                lines = []
            settings.last_status = lines[-1] if lines else "starting"
            return {'FINISHED'}
        try:
            settings.last_status = status.summary(status.task_states(Job.load(job_dir)))
        except JobError as ex:
            settings.last_status = ""
            self.report({'ERROR'}, "Phos farm: %s" % ex)
            return {'CANCELLED'}
        return {'FINISHED'}


class PHOS_RENDER_PT_farm(bpy.types.Panel):
    """A render farm job for this file (docs/farm.md)."""

    bl_label = "Farm"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "render"
    bl_options = {'DEFAULT_CLOSED'}

    @classmethod
    def poll(cls, context):
        return context.engine == ENGINE

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        s = context.scene.phos_farm
        scene = context.scene
        col = layout.column()
        col.prop(s, "frames")
        if not s.frames.strip():
            col.label(text="The scene's frames, %d-%d" % (scene.frame_start, scene.frame_end), icon='INFO')
        col.prop(s, "regions")
        col.prop(s, "caches")
        sub = col.column()
        sub.active = s.caches == 'SHARED'
        sub.prop(s, "key_frames")
        col.prop(s, "jobs_folder")
        col.prop(s, "manager")
        if s.manager == 'LOCAL':
            col.prop(s, "local_processes")
        else:
            col.prop(s, "slurm_args")
        layout.operator(PHOS_OT_farm_submit.bl_idname, icon='EXPORT')
        if s.last_job:
            box = layout.box()
            box.label(text=os.path.basename(s.last_job.rstrip("/")), icon='FILE_FOLDER')
            row = box.row()
            row.label(text=s.last_status or "-")
            row.operator(PHOS_OT_farm_status.bl_idname, text="", icon='FILE_REFRESH')


classes = (PhosFarmSettings, PHOS_OT_farm_submit, PHOS_OT_farm_status, PHOS_RENDER_PT_farm)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.phos_farm = PointerProperty(type=PhosFarmSettings, name="Phos Farm",
                                                description="The render farm job of this scene")


def unregister():
    del bpy.types.Scene.phos_farm
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
