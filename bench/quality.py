# SPDX-License-Identifier: GPL-3.0-or-later
"""Image quality against render time: Phos and Cycles against a converged
reference of the same scene, measured in one Blender process.

    blender -b --factory-startup --python bench/quality.py -- COMMAND [options]

Commands (each takes --scene NAME, a script in scenes/, and --resolution W H):

    reference   render, or extend, the scene's reference: Cycles in chunks
                of --chunk-samples samples, each with its own seed, until
                the reference holds --chunks chunks (or, with
                --reference-engine PHOS or a scene that names it, Phos with
                consistent methods only: progressive caustics, path-traced
                gathers). Kept in --reference-dir
                (make bench names it; not in git), as the per-pixel sum and
                sum of squares of the chunk images, so that the reference's
                own noise is known and can be taken out of every error.
    sweep       Phos over a grid of settings (--grid "samples=4,16
                final_gather_rays=8,32 ..."; scene.phos property names),
                one CSV row per combination: render time, the part of it
                that does not grow with the pixel count, relative MSE.
    equal-time  Phos at the given settings (default: the engine's
                defaults), then Cycles given the same wall time.
    bench       what `make bench` runs per scene: equal time at the
                defaults (PHOTON, PATH, Cycles), fixed budgets (--budgets
                seconds; Phos picks the samples, and fewer photons where
                the maps alone would overrun, to fit each), and the path
                tracer's time and variance per sample against Cycles' at
                equal samples. Writes --csv and, beside it, the images
                (bench_<scene>.npz) for bench/plots.py. --parts official
                (for the official builds): at the time Phos PHOTON takes
                at its defaults (or at the first value of each --grid
                setting), Phos raw and through the Denoise node, Cycles
                plain, with path guiding, and with OpenImageDenoise.

--pass NAME (reference and sweep; Phos references only) scores one of
Phos's light passes instead of the image: --pass Caustics compares the
caustic estimate alone, where the image's other light (paths that find a
caustic only after a second diffuse bounce, say) would bury it in its own
noise. Its references are kept apart (<scene>_<W>x<H>_phos_ppm_caustics.npz).

Relative MSE (Rousselle et al. 2011): the mean over pixels and RGB channels
of (x - r)^2 / (r^2 + 0.01), minus the reference's own share, the same sum
with the variance of the reference mean (from its chunks) in the numerator:
E[(x - r)^2] = E[(x - truth)^2] + var(r) for a reference independent of x.

Render time is measured from Blender's render_pre to render_post handlers,
export to last pixel, for both engines alike (Blender's start-up and file
writing excluded). docs/benchmarks.md describes the method and the results.
"""

import argparse
import csv
import importlib
import itertools
import json
import os
import platform
import sys
import tempfile
import time

import bpy
import numpy as np

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO_DIR, "scenes"))
sys.path.insert(0, os.path.join(REPO_DIR, "tests", "blender"))
import _common  # noqa: E402
import exrread  # noqa: E402  (multilayer EXR passes, numpy only)

RELATIVE_EPSILON = 0.01      # the denominator's offset of relative MSE
FULL_HD_PIXELS = 1920 * 1080  # Blender's default output size
REFERENCE_SEED_BASE = 1000000  # chunk k of a reference renders with seed BASE + k
PHOTON_SETTING_NAMES = ("global_photons", "caustic_photons", "global_estimate_photons",
                        "caustic_estimate_photons", "final_gather_rays", "max_radius",
                        "caustic_sample_share", "irradiance_cache", "ic_accuracy", "ic_rays", "ic_min_spacing",
                        "ic_max_spacing")
# The passes --pass scores: the light components whose sum is the image
# (core/include/phos.h), by their names in Blender.
LIGHT_PASSES = ("Emission", "Direct", "Specular", "Caustics", "Indirect")


def log(msg):
    print("[bench] %s" % msg, flush=True)


# ------------------------------------------------------------------ scenes

def build_scene(name):
    """A fresh scene from scenes/<name>.py; returns (scene, its module)."""
    bpy.ops.wm.read_factory_settings(use_empty=False)
    module = importlib.import_module(name)
    scene = bpy.context.scene
    module.build(scene)
    if not _common.enable_addon():
        raise RuntimeError("the Phos add-on could not be enabled from %s" % _common.ADDON_DIR)
    return scene, module


def configure(scene, module, engine, resolution, samples, seed, integrator="PHOTON", settings=None):
    """Both engines configured as the scene scripts do (equal bounces, filter,
    caustics on, no denoising or clamping); then Phos's `settings`."""
    _common.configure_output(scene, resolution)
    _common.configure_cycles(scene, samples, module.MAX_BOUNCES, seed=seed)
    _common.configure_phos(scene, samples, module.MAX_BOUNCES, seed=seed, integrator=integrator,
                           photon_settings=settings)
    scene.render.engine = engine


# --------------------------------------------------------------- rendering

class _Clock:
    """Wall time from render_pre to render_post (export to last pixel)."""

    def __init__(self):
        self.start = self.end = None

    def pre(self, *_args):
        self.start = time.perf_counter()

    def post(self, *_args):
        self.end = time.perf_counter()


def timed_render(scene):
    """Render the scene into Render Result; returns the seconds from
    render_pre to render_post (export to last pixel)."""
    clock = _Clock()
    handlers = bpy.app.handlers
    handlers.render_pre.append(clock.pre)
    handlers.render_post.append(clock.post)
    try:
        bpy.ops.render.render()
    finally:
        handlers.render_pre.remove(clock.pre)
        handlers.render_post.remove(clock.post)
    return clock.end - clock.start


def render_layers(scene, phos_passes=()):
    """Render with the view layer's Phos passes named in phos_passes (the
    add-on's use_pass_<name>, e.g. "caustics") on, and every other of
    them as it was; returns ({pass name: float64 (h, w, channels)}, seconds).
    Rows go up, as in render's images and the references."""
    vl = scene.view_layers[0]
    for name in phos_passes:
        setattr(vl.phos, "use_pass_" + name, True)
    seconds = timed_render(scene)
    fmt = scene.render.image_settings
    # The output format as it was, media type first: from 5.0 it limits
    # which file formats may be set.
    saved = [(name, getattr(fmt, name)) for name in ("media_type", "file_format", "color_mode", "color_depth",
                                                     "exr_codec", "use_exr_interleave") if hasattr(fmt, name)]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "result.exr")
        _common.set_multilayer_exr(fmt)
        bpy.data.images["Render Result"].save_render(path, scene=scene)
        layers = exrread.read_passes(path)
    for name, value in saved:
        setattr(fmt, name, value)
    return {k: v.astype(np.float64) for k, v in layers.items()}, seconds


def render(scene, pass_name=None):
    """Render the scene; returns (linear RGB float64 array (h, w, 3), seconds):
    the image, or the Phos light pass pass_name (LIGHT_PASSES)."""
    if pass_name:
        layers, seconds = render_layers(scene, (pass_name.lower(),))
        rgb = layers[pass_name][..., :3]
        _last_image[0] = rgb
        return rgb, seconds
    seconds = timed_render(scene)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "result.exr")
        fmt = scene.render.image_settings
        fmt.file_format, fmt.color_mode, fmt.color_depth = "OPEN_EXR", "RGBA", "32"
        bpy.data.images["Render Result"].save_render(path, scene=scene)
        img = bpy.data.images.load(path, check_existing=False)
        try:
            w, h = img.size
            a = np.empty(w * h * img.channels, np.float32)
            img.pixels.foreach_get(a)
            rgb = a.reshape(h, w, img.channels)[:, :, :3].astype(np.float64)
        finally:
            bpy.data.images.remove(img)
    _last_image[0] = rgb
    return rgb, seconds


_last_image = [None]  # the last render's image, for the bench's strips


# --------------------------------------------------------------- reference

# A Phos reference must come from methods that converge to the exact
# image as its samples grow, never from the estimate being measured: the
# caustics by progressive photon mapping (a new map every sample, the
# radius shrinking), the indirect light by unbiased path-traced gathers,
# no irradiance cache. Fixed-k PHOTON with more photons would be PHOTON
# judging itself: its own blur would never count.
CONSISTENT_PHOS_REFERENCE = {"use_progressive_caustics": True, "photon_view": "PATH_TRACED",
                             "irradiance_cache": "OFF"}


# What a consistent Phos reference uses where its scene names none: 20 000
# caustic photons a sample; the gathers' paths read a fixed caustic map of
# 4 M photons (20 nearest) at their later diffuse vertices, light a diffuse
# bounce has already blurred; one gather ray a sample.
PHOS_REFERENCE_SETTINGS = dict(CONSISTENT_PHOS_REFERENCE, progressive_caustic_photons=20000,
                               caustic_photons=4000000, caustic_estimate_photons=20, final_gather_rays=1)
# The progressive radius shrinks over one chunk's samples only (each chunk
# is a render of its own); more chunks average the noise, not that blur.
# So a Phos reference's chunks are long: its remaining blur is that of
# 2048 samples, the radius² down by 2048^(1 − α) = 45× from the first.
PHOS_REFERENCE_CHUNK_SAMPLES = 2048


def reference_recipe(module, engine=None):
    """How a scene's reference is rendered: Cycles (engine "CYCLES"), or,
    for a scene Cycles cannot converge (a small lamp's caustic through
    glass, found only by hitting the lamp), Phos PHOTON with only
    consistent methods (CONSISTENT_PHOS_REFERENCE) and the scene's
    BENCH_REFERENCE settings (PHOS_REFERENCE_SETTINGS in chunks of
    PHOS_REFERENCE_CHUNK_SAMPLES where it names none), each chunk its own
    seed and so its own photon maps. `engine` ("CYCLES" or "PHOS", None:
    the scene's) asks for the other kind, in as many chunks as --chunks
    asks. A Phos recipe that is not consistent is refused."""
    recipe = getattr(module, "BENCH_REFERENCE", {"engine": "CYCLES", "settings": {}})
    if engine == "PHOS" and recipe["engine"] != "PHOS":
        recipe = {"engine": "PHOS"}
    elif engine == "CYCLES" and recipe["engine"] != "CYCLES":
        recipe = {"engine": "CYCLES", "settings": {}}
    if recipe["engine"] == "PHOS":
        recipe = dict({"chunk_samples": PHOS_REFERENCE_CHUNK_SAMPLES, "settings": dict(PHOS_REFERENCE_SETTINGS)},
                      **recipe)
        settings = recipe.get("settings", {})
        wrong = sorted(name for name, value in CONSISTENT_PHOS_REFERENCE.items() if settings.get(name) != value)
        if wrong:
            raise SystemExit("%s's reference is Phos without %s: a reference must come from methods that "
                             "converge as samples grow (bench/quality.py, CONSISTENT_PHOS_REFERENCE)"
                             % (module.__name__, ", ".join("%s = %r" % (n, CONSISTENT_PHOS_REFERENCE[n])
                                                          for n in wrong)))
    return recipe


def reference_path(ref_dir, scene_name, resolution, engine="CYCLES", pass_name=None):
    """The cached reference's file. A Phos reference's name says it is the
    consistent one ("_phos_ppm"), so that one rendered by an older recipe
    (fixed-k PHOTON) is never read as it; a pass's reference ends in the
    pass's name."""
    suffix = "" if engine == "CYCLES" else "_" + engine.lower() + "_ppm"
    if pass_name:
        suffix += "_" + pass_name.lower()
    return os.path.join(ref_dir, "%s_%dx%d%s.npz" % (scene_name, resolution[0], resolution[1], suffix))


class Reference:
    """Cycles chunk images of one scene: their per-pixel sum and sum of squares."""

    def __init__(self, total, total_sq, chunks, chunk_samples, meta):
        self.total, self.total_sq = total, total_sq
        self.chunks, self.chunk_samples, self.meta = chunks, chunk_samples, meta

    @classmethod
    def load(cls, path):
        if not os.path.isfile(path):
            return None
        z = np.load(path, allow_pickle=False)
        return cls(z["total"], z["total_sq"], int(z["chunks"]), int(z["chunk_samples"]),
                   json.loads(str(z["meta"])))

    def save(self, path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        tmp = path + ".tmp.npz"
        np.savez_compressed(tmp, total=self.total, total_sq=self.total_sq, chunks=self.chunks,
                            chunk_samples=self.chunk_samples, meta=json.dumps(self.meta))
        os.replace(tmp, path)

    @property
    def mean(self):
        return self.total / self.chunks

    @property
    def variance_of_mean(self):
        """Per pixel and channel: the variance of the reference mean, from
        the spread of its chunks (0 with a single chunk: unknown)."""
        if self.chunks < 2:
            return np.zeros_like(self.total)
        m = self.mean
        var_chunk = np.maximum(self.total_sq / self.chunks - m * m, 0.0) * self.chunks / (self.chunks - 1)
        return var_chunk / self.chunks

    def relative_mse(self, image):
        """(relative MSE of image, the reference's own share that was taken out)."""
        r = self.mean
        denom = r * r + RELATIVE_EPSILON
        own = float(np.mean(self.variance_of_mean / denom))
        raw = float(np.mean((image - r) ** 2 / denom))
        return raw - own, own


def machine_description():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "blender": bpy.app.version_string,
            "date": time.strftime("%Y-%m-%d")}


def command_reference(args):
    scene, module = build_scene(args.scene)
    recipe = reference_recipe(module, getattr(args, "reference_engine", None))
    engine = recipe["engine"]
    check_pass(args, engine)
    path = reference_path(args.reference_dir, args.scene, args.resolution, engine, args.pass_name)
    ref = Reference.load(path)
    chunks = recipe.get("chunks", args.chunks)
    chunk_samples = recipe.get("chunk_samples", args.chunk_samples)
    if ref is not None and ref.chunk_samples != chunk_samples:
        raise SystemExit("%s holds chunks of %d samples, not %d" % (path, ref.chunk_samples, chunk_samples))
    start = ref.chunks if ref else 0
    for k in range(start, chunks):
        configure(scene, module, "PHOS" if engine == "PHOS" else "CYCLES", args.resolution, chunk_samples,
                  REFERENCE_SEED_BASE + k, "PHOTON", recipe.get("settings"))
        image, seconds = render(scene, args.pass_name)
        if ref is None:
            meta = dict(machine_description(), scene=args.scene, resolution=list(args.resolution),
                        engine=engine, render_pass=args.pass_name or "Combined",
                        settings=recipe.get("settings", {}), seed_base=REFERENCE_SEED_BASE,
                        max_bounces=module.MAX_BOUNCES)
            ref = Reference(np.zeros_like(image), np.zeros_like(image), 0, chunk_samples, meta)
        ref.total += image
        ref.total_sq += image * image
        ref.chunks += 1
        ref.meta["seconds"] = ref.meta.get("seconds", 0.0) + seconds
        ref.save(path)  # after every chunk: an interrupted reference keeps what it has
        _, own = ref.relative_mse(ref.mean)
        log("%s: chunk %d/%d (%d samples) in %.1f s; reference noise (relative variance) %.3g"
            % (args.scene, ref.chunks, chunks, chunk_samples, seconds, own))
    if ref is None:
        raise SystemExit("no reference rendered (--chunks 0?)")
    log("%s: reference of %d samples in %s" % (args.scene, ref.chunks * ref.chunk_samples, path))


def check_pass(args, engine):
    """--pass scores a Phos light pass, which Cycles' references do not have."""
    if args.pass_name and engine != "PHOS":
        raise SystemExit("--pass %s needs a Phos reference (--reference-engine PHOS): Cycles renders no such pass"
                         % args.pass_name)


def load_reference(args):
    module = importlib.import_module(args.scene)
    engine = reference_recipe(module, getattr(args, "reference_engine", None))["engine"]
    check_pass(args, engine)
    path = reference_path(args.reference_dir, args.scene, args.resolution, engine, args.pass_name)
    ref = Reference.load(path)
    if ref is None:
        raise SystemExit("no reference %s: run the reference command first" % path)
    return ref


# ----------------------------------------------------------- measurements

def parse_grid(text):
    """'samples=4,16 final_gather_rays=8' -> [('samples', [4, 16]), ...]"""
    grid = []
    for item in (text or "").split():
        name, _, values = item.partition("=")
        grid.append((name, [_number(v) for v in values.split(",") if v]))
    return grid


def _number(text):
    """A grid value: an int, a float, or an enum item's identifier ('ON')."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def phos_stage_seconds(stage_name, missing=0.0):
    """The time Phos's last render spent in a stage, by its phos.h name
    (the add-on's stage times); `missing` if it did not run it."""
    engine = sys.modules.get(_common.ADDON_NAME + ".engine")
    core = sys.modules.get(_common.ADDON_NAME + ".core")
    if not engine or not core:
        return missing
    return getattr(engine, "last_render_seconds", {}).get(getattr(core, stage_name), missing)


def phos_tile_seconds(seconds):
    """The time Phos's last render spent on its tiles; all of `seconds` if
    the add-on kept none."""
    return phos_stage_seconds("PHOS_STAGE_RENDERING", seconds)


def phos_measurement(scene, module, args, ref, settings, integrator):
    """Render Phos with settings (scene.phos properties; 'samples' among
    them); returns one CSV row. The add-on's stage times split the render
    time into the part that grows with the pixel count (the tiles) and the
    part that does not (export, BVH, photon maps, radiance photons); the
    first is scaled to Full HD for full_hd_seconds."""
    settings = dict(settings)
    samples = int(settings.pop("samples", scene.phos.bl_rna.properties["samples"].default))
    # Every photon setting not given is the engine's default, not what an
    # earlier measurement of this process left on the scene.
    props = scene.phos.bl_rna.properties
    settings = dict({name: props[name].default for name in PHOTON_SETTING_NAMES}, **settings)
    configure(scene, module, "PHOS", args.resolution, samples, args.seed, integrator, settings)
    image, seconds = render(scene, args.pass_name)
    tiles = phos_tile_seconds(seconds)
    fixed = max(seconds - tiles, 0.0)
    rel, own = ref.relative_mse(image)
    row = {"scene": args.scene, "engine": "PHOS", "integrator": integrator, "samples": samples,
           "render_pass": args.pass_name or "Combined"}
    row.update(settings)
    tracing = phos_stage_seconds("PHOS_STAGE_TRACING_PHOTONS")
    kept = getattr(sys.modules.get(_common.ADDON_NAME + ".engine"), "last_render_seconds", {})
    emitted = kept.get("photons_emitted", 0)
    row.update(tracing_seconds=tracing, tracing_share=tracing / seconds if seconds > 0 else 0.0,
               photon_yield=kept.get("photons_stored", 0) / emitted if emitted else "")
    row.update(seconds=seconds, fixed_seconds=fixed,
               full_hd_seconds=fixed + tiles * FULL_HD_PIXELS / (args.resolution[0] * args.resolution[1]),
               relative_mse=rel, reference_share=own, mean_ratio=float(image.mean() / ref.mean.mean()))
    return row


def cycles_measurement(scene, module, args, ref, seconds):
    """Cycles given `seconds` of wall time in all: its time limit is what is
    left after its own fixed cost (sync, kernel set-up), measured by a render
    of 1 sample at 16 x 16."""
    configure(scene, module, "CYCLES", (16, 16), 1, args.seed)
    _, fixed = render(scene)
    configure(scene, module, "CYCLES", args.resolution, 1 << 20, args.seed)
    scene.cycles.time_limit = max(seconds - fixed, 0.1)
    image, measured = render(scene)
    scene.cycles.time_limit = 0.0
    rel, own = ref.relative_mse(image)
    return {"scene": args.scene, "engine": "CYCLES", "integrator": "", "samples": "",
            "seconds": measured, "fixed_seconds": fixed, "relative_mse": rel, "reference_share": own,
            "mean_ratio": float(image.mean() / ref.mean.mean())}


# Cycles as artists run it: the blender.org and PyPI builds have path
# guiding and OpenImageDenoise (Debian's have neither). scene.cycles
# settings on top of the reference configuration (_common.configure_cycles).
CYCLES_CONFIGS = {
    "cycles": {},
    "cycles_guiding": {"use_guiding": True, "use_surface_guiding": True, "use_volume_guiding": False},
    "cycles_oidn": {"use_denoising": True, "denoiser": "OPENIMAGEDENOISE",
                    "denoising_input_passes": "RGB_ALBEDO_NORMAL", "denoising_prefilter": "ACCURATE"},
}


def _apply_cycles_config(scene, config):
    """Sets `config`'s Cycles settings; returns the values they replaced."""
    before = {name: getattr(scene.cycles, name) for name in CYCLES_CONFIGS[config]}
    for name, value in CYCLES_CONFIGS[config].items():
        setattr(scene.cycles, name, value)
    return before


def cycles_config_measurement(scene, module, args, ref, seconds, config):
    """Cycles in configuration `config` (CYCLES_CONFIGS) given `seconds` in
    all: its time limit is what is left after its fixed cost and, when it
    denoises, the denoiser's time (measured by a pilot), so that the image
    it delivers took the same wall time as Phos's."""
    configure(scene, module, "CYCLES", (16, 16), 1, args.seed)
    before = _apply_cycles_config(scene, config)
    _, fixed = render(scene)
    overhead = 0.0
    if CYCLES_CONFIGS[config].get("use_denoising"):
        configure(scene, module, "CYCLES", args.resolution, 1 << 20, args.seed)
        _apply_cycles_config(scene, config)
        scene.cycles.time_limit = 0.5
        _, pilot = render(scene)
        overhead = max(pilot - 0.5 - fixed, 0.0)
    configure(scene, module, "CYCLES", args.resolution, 1 << 20, args.seed)
    _apply_cycles_config(scene, config)
    scene.cycles.time_limit = max(seconds - fixed - overhead, 0.1)
    image, measured = render(scene)
    scene.cycles.time_limit = 0.0
    for name, value in before.items():
        setattr(scene.cycles, name, value)
    rel, own = ref.relative_mse(image)
    return {"scene": args.scene, "engine": "CYCLES", "integrator": config, "samples": "",
            "seconds": measured, "fixed_seconds": fixed, "relative_mse": rel, "reference_share": own,
            "mean_ratio": float(image.mean() / ref.mean.mean())}


def phos_denoised_measurement(scene, module, args, ref, settings, integrator):
    """Phos at `settings`, through the compositor's Denoise node fed with
    its Denoising Albedo and Denoising Normal passes (the time includes the
    compositing)."""
    vl = scene.view_layers[0]
    _common.denoise_in_compositor(scene)
    try:
        row = phos_measurement(scene, module, args, ref, settings, integrator)
    finally:
        scene.render.use_compositing = False
        vl.phos.use_pass_denoising_albedo = vl.phos.use_pass_denoising_normal = False
        vl.cycles.denoising_store_passes = False
    row["integrator"] = integrator + " + Denoise node"
    return row


def write_rows(path, rows):
    if not rows:
        return
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fields = []
    for row in rows:
        fields += [k for k in row if k not in fields]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    log("wrote %s" % path)


def _format_row(row):
    keys = [k for k in row if k not in ("scene", "engine", "reference_share")]
    return "  ".join("%s=%s" % (k, ("%.4g" % row[k]) if isinstance(row[k], float) else row[k]) for k in keys)


def command_sweep(args):
    ref = load_reference(args)
    scene, module = build_scene(args.scene)
    grid = parse_grid(args.grid)
    names = [n for n, _ in grid]
    rows = []
    for values in itertools.product(*[v for _, v in grid]):
        row = phos_measurement(scene, module, args, ref, dict(zip(names, values)), args.integrator)
        log(_format_row(row))
        rows.append(row)
        write_rows(args.csv, rows)


def command_equal_time(args):
    ref = load_reference(args)
    scene, module = build_scene(args.scene)
    rows = []
    settings = dict(s for name, v in parse_grid(args.grid) for s in [(name, v[0])])
    for integrator in args.integrators:
        row = phos_measurement(scene, module, args, ref, settings, integrator)
        log(_format_row(row))
        rows.append(row)
        crow = cycles_measurement(scene, module, args, ref, row["seconds"])
        crow["integrator"] = "vs " + integrator
        log(_format_row(crow))
        rows.append(crow)
        # Cycles' time limit cannot make its render end exactly when Phos's
        # did; its relative MSE falls as 1 / time, so the ratio of
        # relative MSE x time is the ratio at equal time.
        ratio = row["relative_mse"] * row["seconds"] / (crow["relative_mse"] * crow["seconds"])
        row["vs_cycles"] = crow["vs_cycles"] = ratio
        log("%s %s: relative MSE Phos / Cycles at equal time (%.1f s, %.1f s) = %.3g"
            % (args.scene, integrator, row["seconds"], crow["seconds"], ratio))
    write_rows(args.csv, rows)


# ------------------------------------------------------------------ bench

CACHE_RAYS_MAX_SCALE = 16   # the most a budget multiplies the records' rays by


def _samples_for(scene, module, args, ref, integrator, settings, budget):
    """Settings that fit `budget` seconds: a pilot at 8 samples gives the
    fixed time and the time per sample; photon counts are scaled down
    where the maps alone would take more than a third of the budget.
    Where the irradiance cache's pre-pass takes less than its share, its
    records get more rays (up to CACHE_RAYS_MAX_SCALE × the default, in
    powers of two) until the fixed time is a third of the budget: a
    record's noise is an error no number of samples removes, so a larger
    budget spent on samples alone stops lowering the error."""
    settings = dict(settings)
    pilot = phos_measurement(scene, module, args, ref, dict(settings, samples=8), integrator)
    fixed = pilot["fixed_seconds"]
    fill = phos_stage_seconds("PHOS_STAGE_FILLING_IRRADIANCE_CACHE")
    per_sample = max(pilot["seconds"] - fixed, 1e-3) / 8.0
    if integrator == "PHOTON" and fixed > budget / 3.0:
        scale = budget / 3.0 / fixed
        for name in ("global_photons", "caustic_photons"):
            default = scene.phos.bl_rna.properties[name].default
            settings[name] = max(1000, int(settings.get(name, default) * scale))
        fixed *= scale
    elif fill > 0.0:
        rays = settings.get("ic_rays", scene.phos.bl_rna.properties["ic_rays"].default)
        scale = 1
        while scale < CACHE_RAYS_MAX_SCALE and fixed + fill * scale <= budget / 3.0:
            scale *= 2
        if scale > 1:
            settings["ic_rays"] = rays * scale
            fixed += fill * (scale - 1)
    settings["samples"] = max(1, int((budget - fixed) / per_sample))
    return settings



def _path_speed_row(scene, module, args, ref, engine, samples):
    """One PATH measurement of an engine at S + 1 samples, its time per
    sample the difference to a 1-sample render, divided by S."""
    if engine == "PHOS":
        one = phos_measurement(scene, module, args, ref, {"samples": 1}, "PATH")["seconds"]
        row = phos_measurement(scene, module, args, ref, {"samples": samples + 1}, "PATH")
    else:
        configure(scene, module, "CYCLES", args.resolution, 1, args.seed)
        _, one = render(scene)
        configure(scene, module, "CYCLES", args.resolution, samples + 1, args.seed)
        image, seconds = render(scene)
        rel, own = ref.relative_mse(image)
        row = {"scene": args.scene, "engine": "CYCLES", "integrator": "PATH", "samples": samples + 1,
               "seconds": seconds, "fixed_seconds": one, "relative_mse": rel, "reference_share": own,
               "mean_ratio": float(image.mean() / ref.mean.mean())}
    row.update(seconds_per_sample=(row["seconds"] - one) / samples,
               variance_per_sample=row["relative_mse"] * int(row["samples"]))
    return row


def command_bench(args):
    ref = load_reference(args)
    scene, module = build_scene(args.scene)
    rows, images = [], {"reference": ref.mean}
    machine = dict(machine_description(), reference_engine=ref.meta.get("engine", "CYCLES"),
                   reference_samples=ref.chunks * ref.chunk_samples)

    def add(row, kind, budget=None, image=None, label=None):
        row.update(kind=kind, budget=budget if budget is not None else "", **machine)
        rows.append(row)
        log(_format_row(row))
        if image is not None:
            images[label] = image
        write_rows(args.csv, rows)

    # Equal time at the defaults, and the images for the strips. Each of
    # --equal-reps repetitions renders Phos, then Cycles in Phos's time, both
    # with the repetition's own seed (args.seed + k): one seed's error is one
    # draw, and a few fireflies in a half-second render move it, Phos's as
    # much as Cycles'. The ratio reported is that of the mean MSE x time
    # over the repetitions, which estimates the ratio of the expected
    # errors at equal time; the rows and images kept are the repetition of
    # median ratio.
    for integrator in ("PHOTON", "PATH") if "equal" in args.parts else ():
        reps = []
        for k in range(max(1, args.equal_reps)):
            rep_args = argparse.Namespace(**dict(vars(args), seed=args.seed + k))
            row = phos_measurement(scene, module, rep_args, ref, {}, integrator)
            image = _last_image[0]
            crow = cycles_measurement(scene, module, rep_args, ref, row["seconds"])
            ratio = row["relative_mse"] * row["seconds"] / (crow["relative_mse"] * crow["seconds"])
            crow["integrator"] = "vs " + integrator
            reps.append((ratio, row, image, crow, _last_image[0]))
        mean_ratio = (sum(r[1]["relative_mse"] * r[1]["seconds"] for r in reps) /
                      sum(r[3]["relative_mse"] * r[3]["seconds"] for r in reps))
        ratio, row, image, crow, cycles_image = sorted(reps, key=lambda r: r[0])[len(reps) // 2]
        for r in (row, crow):
            r.update(vs_cycles=mean_ratio, equal_reps=len(reps),
                     rep_ratios=" ".join("%.3g" % rep[0] for rep in reps),
                     rep_phos_mse=" ".join("%.3g" % rep[1]["relative_mse"] for rep in reps),
                     rep_cycles_mse=" ".join("%.3g" % rep[3]["relative_mse"] for rep in reps))
        add(row, "equal_time", image=image, label=integrator)
        add(crow, "equal_time", image=cycles_image, label="CYCLES vs " + integrator)
        log("%s %s: relative MSE x time, Phos / Cycles at equal time (%.1f s) = %.3g over %d seeds (each: %s; "
            "relative MSE, Phos: %s, Cycles: %s)" % (args.scene, integrator, row["seconds"], mean_ratio, len(reps),
                                                     row["rep_ratios"], row["rep_phos_mse"], row["rep_cycles_mse"]))

    # Fixed budgets.
    for budget in args.budgets if "budgets" in args.parts else ():
        for integrator in ("PHOTON", "PATH"):
            settings = _samples_for(scene, module, args, ref, integrator, {}, budget)
            add(phos_measurement(scene, module, args, ref, settings, integrator), "budget", budget)
        add(cycles_measurement(scene, module, args, ref, budget), "budget", budget)

    # The path tracers at equal samples: time and variance per sample, both
    # measured the same way, as the difference between a render of S + 1
    # samples and one of 1 (whatever each engine spends before and after its
    # samples cancels), the engines alternating --path-reps times; the row
    # of each engine is its median repetition (a shared machine's load
    # moves single runs by 20 % and more).
    samples = args.path_samples
    runs = {"PHOS": [], "CYCLES": []}
    for _ in range(args.path_reps if "path" in args.parts else 0):
        for engine in runs:
            runs[engine].append(_path_speed_row(scene, module, args, ref, engine, samples))
    kept = {}
    for engine, reps in runs.items():  # not `rows`: add() appends to the table's rows
        if reps:
            kept[engine] = sorted(reps, key=lambda r: r["seconds_per_sample"])[len(reps) // 2]
            add(kept[engine], "path_speed")
    if len(kept) == 2:
        # Error x time per sample: what equal time converges to as the
        # budget grows, free of start-up and of one short render's fireflies.
        p, c = kept["PHOS"], kept["CYCLES"]
        log("%s PATH: variance x time per sample, Phos / Cycles = %.3g (variance %.3g, time %.3g)"
            % (args.scene, p["variance_per_sample"] * p["seconds_per_sample"] /
               (c["variance_per_sample"] * c["seconds_per_sample"]),
               p["variance_per_sample"] / c["variance_per_sample"], p["seconds_per_sample"] / c["seconds_per_sample"]))
    # Cycles as artists run it (the official builds), and Phos through the
    # same denoiser, all at the time Phos PHOTON takes at its defaults, or
    # at the settings --grid gives (the first value of each).
    if "official" in args.parts:
        settings = {name: values[0] for name, values in parse_grid(args.grid)}
        row = phos_measurement(scene, module, args, ref, settings, "PHOTON")
        add(row, "official")
        add(phos_denoised_measurement(scene, module, args, ref, settings, "PHOTON"), "official")
        for config in CYCLES_CONFIGS:
            add(cycles_config_measurement(scene, module, args, ref, row["seconds"], config), "official")
    if "equal" in args.parts:  # beside the CSV, by its name: bench_<scene>.npz for `make bench`'s run
        np.savez_compressed(os.path.splitext(os.path.abspath(args.csv))[0] + ".npz",
                            **{k.replace(" ", "_"): v.astype(np.float32) for k, v in images.items()})


def main():
    p = argparse.ArgumentParser(prog="quality.py", description=__doc__.splitlines()[0])
    p.add_argument("command", choices=("reference", "sweep", "equal-time", "bench"))
    p.add_argument("--budgets", type=float, nargs="+", default=[4.0, 16.0, 64.0])
    p.add_argument("--path-samples", type=int, default=64)
    p.add_argument("--equal-reps", type=int, default=1,
                   help="bench: repetitions of each equal-time pair, seeds seed..seed+N-1; "
                        "the ratio of their mean MSE x time is reported")
    p.add_argument("--path-reps", type=int, default=5,
                   help="alternating repetitions of the PATH time per sample; the median is kept")
    p.add_argument("--parts", nargs="+", default=["equal", "budgets", "path"],
                   choices=("equal", "budgets", "path", "official"),
                   help="bench: which measurements to make (official: Cycles with path guiding and "
                        "OpenImageDenoise, and Phos through the Denoise node, for the official builds)")
    p.add_argument("--scene", required=True)
    p.add_argument("--resolution", type=int, nargs=2, default=(128, 128), metavar=("W", "H"))
    p.add_argument("--reference-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "phos-bench"))
    p.add_argument("--reference-engine", choices=("CYCLES", "PHOS"), default=None,
                   help="the reference's kind (default: the scene's BENCH_REFERENCE, else Cycles); "
                        "PHOS is progressive caustics and path-traced gathers only")
    p.add_argument("--chunks", type=int, default=16)
    p.add_argument("--chunk-samples", type=int, default=256)
    p.add_argument("--grid", default="")
    p.add_argument("--integrator", default="PHOTON", choices=("PATH", "PHOTON"))
    p.add_argument("--integrators", nargs="+", default=["PHOTON", "PATH"])
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--pass", dest="pass_name", choices=LIGHT_PASSES, default=None,
                   help="reference, sweep: score this Phos light pass instead of the image "
                        "(a Phos reference only)")
    p.add_argument("--csv", default=os.path.join(REPO_DIR, "out", "bench", "quality.csv"))
    args = p.parse_args(_common.script_argv())
    args.resolution = tuple(args.resolution)
    if args.pass_name and args.command not in ("reference", "sweep"):
        raise SystemExit("--pass is for the reference and sweep commands: the others compare with Cycles")
    {"reference": command_reference, "sweep": command_sweep, "equal-time": command_equal_time,
     "bench": command_bench}[args.command](args)


def run_main(main):
    """Run a bench script's main inside Blender so that any failure (an
    argument error, an exception) exits non-zero: Blender itself would
    print the traceback and exit 0, and make would go on."""
    try:
        main()
    except SystemExit as ex:
        if ex.code not in (None, 0):
            print("[bench] %s" % ex.code if isinstance(ex.code, str) else "[bench] failed", flush=True)
            sys.exit(1)
        raise
    except Exception:
        import traceback
        traceback.print_exc()
        sys.exit(1)


if __name__ == "__main__":
    run_main(main)
