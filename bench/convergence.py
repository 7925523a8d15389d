# SPDX-License-Identifier: GPL-3.0-or-later
"""Noise reduction in Phos as the course's slides list it (Jensen 2002,
"Biased Monte Carlo Ray Tracing": better sampling, adaptive sampling,
filtering), each measured against a converged Cycles reference.

    blender -b --factory-startup --python bench/convergence.py -- --out DIR [options]

Parts (--parts, all by default):

    samplers    relative MSE against samples per pixel (--spp) for each
                sampler (RANDOM, STRATIFIED, HALTON, SOBOL), PATH on the
                Cornell box, averaged over --seeds seeds, in two variants:
                direct light only (max_bounces 0 in both engines: the
                camera hit, its light sample and the emission its BSDF
                ray finds; the reference is the scene rendered as
                `cornell_box_direct`) and full (the scene's MAX_BOUNCES).
                convergence_samplers.csv, and the fitted convergence rate,
                -d log(MSE) / d log(spp), per sampler and variant in
                convergence_slopes.csv (1 for plain Monte Carlo).
    adaptive    PATH on the Cornell box: adaptive sampling (--thresholds,
                --adaptive-samples as the budget, --adaptive-min-samples)
                against a ladder of plain renders (--ladder samples); the
                plain error at the adaptive render's time is read off the
                ladder (log-log interpolation of relative MSE against
                time), and the mean samples per pixel the adaptive render
                took comes from its Sample Count pass. convergence_adaptive.csv.
    filters     PHOTON and PATH (--filter-integrators) at --filter-samples
                samples on --filter-scenes, for each filter and target
                (--filters, --targets): relative MSE, the filter's energy
                balance (the sum of the Combined RGB over the Noisy Image
                pass's, minus 1) and its time. PHOTON's first render of a
                scene saves its photon maps and irradiance cache, the
                others load them: every filter sees the same noisy image.
                convergence_filters.csv, and the images of the slides'
                strip per scene and integrator
                (convergence_strip_<scene>[_path].npz: unfiltered, 3x3
                lowpass, 3x3 median, the energy-preserving filter of
                lowest error, that filter on the indirect irradiance, and
                the reference), which bench/plots.py draws.

Beside relative MSE every part gives surface_mse, the same error over
the pixels farther than 2 pixels from any reference pixel above 1 (a
visible lamp and its reflections in mirrors and glass): a lamp caught by
one sample of a pixel whose reference is dark weighs thousands of times a
pixel's share of relative MSE, so at low sample counts such rare samples
make most of the whole image's error and hide how the lit surfaces
converge.

References are quality.py's (cached in --reference-dir, rendered or
extended to --ref-chunks chunks when missing). Render time is quality.py's:
Blender's render_pre to render_post.
"""

import argparse
import importlib
import math
import os
import sys
import tempfile
import types

import bpy
import numpy as np

BENCH_DIR = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, BENCH_DIR)
import quality  # noqa: E402
from quality import log  # noqa: E402

import _common  # noqa: E402  (scenes/, on sys.path through quality)

SAMPLERS = ("RANDOM", "STRATIFIED", "HALTON", "SOBOL")
FILTERS = ("NONE", "LOWPASS", "MEDIAN", "ADAPTIVE_WIDTH", "DIFFUSION", "SPLATTING")
ENERGY_PRESERVING = ("ADAPTIVE_WIDTH", "DIFFUSION", "SPLATTING")
TARGETS = ("ALL", "INDIRECT_IRRADIANCE", "INDIRECT")
SAMPLER_SCENE = "cornell_box"
# Direct light only: max_bounces 0 in both engines. Phos stops a path whose
# bounce count exceeds max_bounces after collecting the emission its last
# BSDF ray finds (camera_path.c), as Cycles does; the two agree in
# brightness at 0 (the direct-only rows' mean_ratio).
DIRECT_MAX_BOUNCES = 0
STUDY_SETTINGS = ("sampler", "use_adaptive_sampling", "adaptive_threshold", "adaptive_min_samples",
                  "time_limit", "filter", "filter_target", "photon_map_file_mode", "ic_file_mode")


# ------------------------------------------------------------------ scenes

def direct_variant(name):
    """The scene `name` with max_bounces DIRECT_MAX_BOUNCES, as a module
    `<name>_direct` that quality.py's build_scene, configure and reference
    take like any scene (its reference file is named after it)."""
    variant = name + "_direct"
    if variant not in sys.modules:
        base = importlib.import_module(name)
        module = types.ModuleType(variant, "%s, direct light only" % name)
        module.__dict__.update((k, v) for k, v in vars(base).items() if not k.startswith("__"))
        module.MAX_BOUNCES = DIRECT_MAX_BOUNCES
        sys.modules[variant] = module
    return variant


def ensure_reference(args, scene_name):
    """quality.py's reference of the scene at --resolution, rendered or
    extended to --ref-chunks chunks if it holds fewer; returns it."""
    ns = argparse.Namespace(scene=scene_name, resolution=args.resolution, reference_dir=args.reference_dir,
                            chunks=args.ref_chunks, chunk_samples=args.chunk_samples,
                            reference_engine=None, pass_name=None)  # the scene's own reference, whole image
    engine = quality.reference_recipe(importlib.import_module(scene_name))["engine"]
    ref = quality.Reference.load(quality.reference_path(args.reference_dir, scene_name, args.resolution, engine))
    if ref is None or ref.chunks < args.ref_chunks:
        quality.command_reference(ns)
    return quality.load_reference(ns)


def setup(scene, module, args, integrator, samples, seed=0, **settings):
    """quality.configure for Phos, every setting this study varies back at
    its default, then `settings` (scene.phos properties)."""
    props = scene.phos.bl_rna.properties
    defaults = {name: props[name].default for name in quality.PHOTON_SETTING_NAMES}
    quality.configure(scene, module, "PHOS", args.resolution, samples, seed, integrator, defaults)
    for name in STUDY_SETTINGS:
        setattr(scene.phos, name, props[name].default)
    for name, value in settings.items():
        setattr(scene.phos, name, value)


def render_passes(scene, passes=()):
    """Render with the view layer's Phos passes `passes` (use_pass_<name>)
    on and the other noise passes off; returns ({pass name: float64 (h, w,
    channels)}, seconds) (quality.render_layers)."""
    vl = scene.view_layers[0]
    for name in ("sample_count", "noisy_image"):
        setattr(vl.phos, "use_pass_" + name, name in passes)
    return quality.render_layers(scene, passes)


EMITTER_RADIANCE = 1.0   # a reference pixel above this (any channel) sees an emitter
EMITTER_MARGIN = 2       # pixels around such a pixel that its edge can reach (filter, blur)


def away_from_emitters(ref):
    """Per pixel: farther than EMITTER_MARGIN pixels from every pixel of
    the reference brighter than EMITTER_RADIANCE (a visible lamp and its
    reflections in mirrors and glass; lit surfaces stay below 1 in the
    bench scenes)."""
    bright = (ref.mean > EMITTER_RADIANCE).any(axis=-1)
    m = EMITTER_MARGIN
    padded = np.pad(bright, m)
    h, w = bright.shape
    near = np.zeros_like(bright)
    for dy in range(2 * m + 1):
        for dx in range(2 * m + 1):
            near |= padded[dy:dy + h, dx:dx + w]
    return ~near


def surface_mse(ref, image):
    """Relative MSE over the pixels away from emitters (away_from_emitters),
    the reference's own share there taken out. A lamp, or its reflection,
    caught by one sample of a pixel whose reference is dark weighs
    thousands of times a pixel's share of relative MSE: at low sample
    counts such rare samples make most of the whole image's error, and
    hide how the lit surfaces converge."""
    keep = away_from_emitters(ref)
    r = ref.mean[keep]
    denom = r * r + quality.RELATIVE_EPSILON
    own = float(np.mean(ref.variance_of_mean[keep] / denom))
    return float(np.mean((image[keep] - r) ** 2 / denom)) - own


def worst_share(ref, image, fraction=0.01):
    """The share of the image's relative squared error (the reference's
    own not taken out) in its worst `fraction` of pixels."""
    r = ref.mean
    e = ((image - r) ** 2 / (r * r + quality.RELATIVE_EPSILON)).sum(axis=-1).ravel()
    k = max(1, int(len(e) * fraction))
    return float(np.sort(e)[-k:].sum() / max(e.sum(), 1e-30))


def fit_rate(spp, mse):
    """-slope of the least-squares line through (log spp, log MSE), over the
    points of positive MSE; nan with fewer than two."""
    pts = [(math.log(s), math.log(e)) for s, e in zip(spp, mse) if e > 0.0]
    if len(pts) < 2:
        return float("nan")
    x, y = np.array(pts).T
    return float(-np.polyfit(x, y, 1)[0])


# ---------------------------------------------------------------- samplers

def part_samplers(args, rows, slope_rows):
    variants = (("direct", direct_variant(SAMPLER_SCENE)), ("full", SAMPLER_SCENE))
    for variant, scene_name in variants:
        ref = ensure_reference(args, scene_name)
        scene, module = quality.build_scene(scene_name)
        for sampler in SAMPLERS:
            results = []
            for spp in args.spp:
                errors, surface, seconds, images = [], [], [], []
                for seed in range(args.seeds):
                    setup(scene, module, args, "PATH", spp, seed, sampler=sampler)
                    image, t = quality.render(scene)
                    errors.append(ref.relative_mse(image)[0])
                    surface.append(surface_mse(ref, image))
                    seconds.append(t)
                    images.append(image)
                # The seeds' mean image has 1/seeds of one image's variance:
                # its error stays above the mean error / seeds only by bias.
                mean_image_mse = ref.relative_mse(np.mean(images, axis=0))[0]
                row = {"variant": variant, "scene": SAMPLER_SCENE, "max_bounces": module.MAX_BOUNCES,
                       "sampler": sampler, "samples": spp, "seeds": args.seeds,
                       "relative_mse": float(np.mean(errors)), "relative_mse_min": min(errors),
                       "relative_mse_max": max(errors), "surface_mse": float(np.mean(surface)),
                       "seed_mean_image_mse": mean_image_mse, "reference_share": ref.relative_mse(ref.mean)[1],
                       "seconds": float(np.mean(seconds)), "mean_ratio": float(np.mean(images) / ref.mean.mean())}
                rows.append(row)
                results.append(row)
                log("samplers %s %s %4d spp: relative MSE %.4g (seeds %.3g..%.3g), surfaces %.4g, seed-mean "
                    "image %.3g, brightness / reference %.4f"
                    % (variant, sampler, spp, row["relative_mse"], min(errors), max(errors), row["surface_mse"],
                       mean_image_mse, row["mean_ratio"]))
                quality.write_rows(os.path.join(args.out, "convergence_samplers.csv"), rows)
            slope = {"variant": variant, "sampler": sampler}
            for metric in ("relative_mse", "surface_mse"):
                pts = [(r["samples"], r[metric]) for r in results]
                high = [pt for pt in pts if pt[0] >= args.rate_from]
                slope[metric + "_rate"] = fit_rate(*zip(*pts))
                slope[metric + "_rate_high"] = fit_rate(*zip(*high)) if len(high) > 1 else float("nan")
            slope.update(spp_range="%d-%d" % (args.spp[0], args.spp[-1]),
                         high_range="%d-%d" % (max(args.rate_from, args.spp[0]), args.spp[-1]))
            slope_rows.append(slope)
            log("samplers %s %s: convergence rate (relative MSE) %.3f over %s spp, %.3f over %s; surfaces %.3f, %.3f"
                % (variant, sampler, slope["relative_mse_rate"], slope["spp_range"], slope["relative_mse_rate_high"],
                   slope["high_range"], slope["surface_mse_rate"], slope["surface_mse_rate_high"]))
            quality.write_rows(os.path.join(args.out, "convergence_slopes.csv"), slope_rows)


# ---------------------------------------------------------------- adaptive

def interpolate_loglog(points, x):
    """y at x on the log-log polyline through points [(x, y)] (sorted by
    x), extended by its end segments; nan with fewer than two points."""
    pts = sorted(p for p in points if p[0] > 0.0 and p[1] > 0.0)
    if len(pts) < 2:
        return float("nan")
    lx, ly = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    i = int(np.clip(np.searchsorted(lx, math.log(x)), 1, len(pts) - 1))
    t = (math.log(x) - lx[i - 1]) / (lx[i] - lx[i - 1]) if lx[i] != lx[i - 1] else 0.0
    return float(math.exp(ly[i - 1] + t * (ly[i] - ly[i - 1])))


def part_adaptive(args, rows):
    ref = ensure_reference(args, SAMPLER_SCENE)
    scene, module = quality.build_scene(SAMPLER_SCENE)
    out = os.path.join(args.out, "convergence_adaptive.csv")

    def measure(samples, adaptive, threshold=None):
        settings = {"use_adaptive_sampling": adaptive}
        if adaptive:
            settings.update(adaptive_threshold=threshold, adaptive_min_samples=args.adaptive_min_samples)
        setup(scene, module, args, "PATH", samples, args.seed, **settings)
        layers, seconds = render_passes(scene, ("sample_count",))
        mean_spp = float(layers["Sample Count"].mean()) * samples
        rel, own = ref.relative_mse(layers["Combined"][..., :3])
        row = {"scene": SAMPLER_SCENE, "integrator": "PATH", "adaptive": int(adaptive),
               "threshold": threshold if adaptive else "",
               "min_samples": args.adaptive_min_samples if adaptive else "", "samples": samples,
               "mean_spp": mean_spp, "seconds": seconds, "tile_seconds": quality.phos_tile_seconds(seconds),
               "relative_mse": rel, "surface_mse": surface_mse(ref, layers["Combined"][..., :3]),
               "worst_1pct_share": worst_share(ref, layers["Combined"][..., :3]), "reference_share": own}
        log("adaptive %s: %s" % ("on" if adaptive else "off", quality._format_row(row)))
        return row

    # Plain and adaptive renders alternate, so that a change of the
    # machine's load during the part moves both alike.
    plain, adaptive = [], []
    pending = list(args.thresholds)
    for samples in args.ladder:
        plain.append(measure(samples, False))
        rows.append(plain[-1])
        if pending:
            adaptive.append(measure(args.adaptive_samples, True, pending.pop(0)))
            rows.append(adaptive[-1])
        quality.write_rows(out, rows)
    for threshold in pending:
        adaptive.append(measure(args.adaptive_samples, True, threshold))
        rows.append(adaptive[-1])
    by_time = [(r["seconds"], r["relative_mse"]) for r in plain]
    by_spp = [(r["samples"], r["relative_mse"]) for r in plain]
    for row in adaptive:
        at_time = interpolate_loglog(by_time, row["seconds"])
        at_spp = interpolate_loglog(by_spp, row["mean_spp"])
        row.update(plain_mse_equal_time=at_time, vs_plain_equal_time=row["relative_mse"] / at_time,
                   plain_mse_equal_spp=at_spp, vs_plain_equal_spp=row["relative_mse"] / at_spp)
        log("adaptive threshold %g: %.1f mean spp in %.1f s, relative MSE %.4g; plain at that time %.4g "
            "(adaptive / plain %.3g), plain at those samples %.4g (%.3g)"
            % (row["threshold"], row["mean_spp"], row["seconds"], row["relative_mse"], at_time,
               row["vs_plain_equal_time"], at_spp, row["vs_plain_equal_spp"]))
    quality.write_rows(out, rows)


# ----------------------------------------------------------------- filters

def part_filters(args, rows):
    for scene_name in args.filter_scenes:
        ref = ensure_reference(args, scene_name)
        scene, module = quality.build_scene(scene_name)
        for integrator in args.filter_integrators:
            filter_scene(args, rows, ref, scene, module, integrator)


def filter_scene(args, rows, ref, scene, module, integrator):
    out = os.path.join(args.out, "convergence_filters.csv")
    scene_name = module.__name__
    images, errors = {}, {}
    combos = [("NONE", "ALL")] + [(f, t) for f in args.filters if f != "NONE" for t in args.targets]
    with tempfile.TemporaryDirectory() as tmp:
        for i, (filter_name, target) in enumerate(combos):
            # The filter runs after the samples: PHOTON's first render saves
            # its photon maps and irradiance cache, the others load them (the
            # same seed: every render's noisy image is the first's).
            mode = "NONE" if integrator != "PHOTON" else "SAVE" if i == 0 else "LOAD"
            setup(scene, module, args, integrator, args.filter_samples, args.seed, filter=filter_name,
                  filter_target=target, photon_map_file_mode=mode, ic_file_mode=mode,
                  photon_map_file=os.path.join(tmp, "maps.phospmf"), ic_file=os.path.join(tmp, "cache.phosirc"))
            layers, seconds = render_passes(scene, ("noisy_image",))
            image = layers["Combined"][..., :3]
            # Without a filter the FILTERING stage does not run and leaves
            # the Noisy Image pass empty: the image is its own noisy image.
            noisy = image if filter_name == "NONE" else layers["Noisy Image"][..., :3]
            rel, own = ref.relative_mse(image)
            noisy_rel = ref.relative_mse(noisy)[0]
            key = "%s/%s" % (filter_name, target)
            row = {"scene": scene_name, "integrator": integrator, "samples": args.filter_samples,
                   "filter": filter_name, "target": "" if filter_name == "NONE" else target,
                   "relative_mse": rel, "noisy_mse": noisy_rel, "vs_unfiltered": rel / noisy_rel,
                   "surface_mse": surface_mse(ref, image), "noisy_surface_mse": surface_mse(ref, noisy),
                   "energy_balance": float(image.sum() / noisy.sum() - 1.0),
                   "changed": float(np.abs(image - noisy).sum() / noisy.sum()),
                   "seconds": seconds, "maps": {"SAVE": "computed", "LOAD": "loaded"}.get(mode, ""),
                   "filter_seconds": quality.phos_stage_seconds("PHOS_STAGE_FILTERING"),
                   "reference_share": own}
            rows.append(row)
            images[key], errors[key] = image.astype(np.float32), rel
            log("filters %s %s %s: %s" % (scene_name, integrator, key, quality._format_row(row)))
            quality.write_rows(out, rows)
    # The slides' strip: unfiltered, 3x3 lowpass, 3x3 median, the
    # energy-preserving filter of lowest error over the whole image, and
    # that filter on the indirect irradiance alone.
    best = min((f for f in ENERGY_PRESERVING if "%s/ALL" % f in errors),
               key=lambda f: errors["%s/ALL" % f], default=None)
    panels = [("NONE/ALL", "unfiltered"), ("LOWPASS/ALL", "3x3 lowpass"), ("MEDIAN/ALL", "3x3 median")]
    if best:
        name = best.lower().replace("_", " ")
        panels += [("%s/ALL" % best, name), ("%s/INDIRECT_IRRADIANCE" % best, "%s, indirect irradiance" % name)]
    panels = [(k, label) for k, label in panels if k in images]
    suffix = "" if integrator == "PHOTON" else "_" + integrator.lower()
    np.savez_compressed(os.path.join(args.out, "convergence_strip_%s%s.npz" % (scene_name, suffix)),
                        reference=ref.mean.astype(np.float32), labels=np.array([lb for _, lb in panels]),
                        errors=np.array([errors[k] for k, _ in panels]), samples=args.filter_samples,
                        integrator=integrator, **{"panel%d" % i: images[k] for i, (k, _) in enumerate(panels)})


# -------------------------------------------------------------------- main

def main():
    p = argparse.ArgumentParser(prog="convergence.py", description=__doc__.splitlines()[0])
    p.add_argument("--out", default=os.path.join(quality.REPO_DIR, "out", "bench"))
    p.add_argument("--parts", nargs="+", default=["samplers", "adaptive", "filters"],
                   choices=("samplers", "adaptive", "filters"))
    p.add_argument("--resolution", type=int, nargs=2, default=(128, 128), metavar=("W", "H"))
    p.add_argument("--reference-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "phos-bench"))
    p.add_argument("--ref-chunks", type=int, default=16, help="chunks a reference must hold (rendered if fewer)")
    p.add_argument("--chunk-samples", type=int, default=256)
    p.add_argument("--seed", type=int, default=0, help="Phos's seed in the adaptive and filter parts")
    p.add_argument("--spp", type=int, nargs="+", default=[1, 2, 4, 8, 10, 16, 32, 64, 128])
    p.add_argument("--seeds", type=int, default=8, help="seeds each sampler's error is averaged over")
    p.add_argument("--rate-from", type=int, default=8, help="rate_high fits the samples from this count on")
    p.add_argument("--thresholds", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    p.add_argument("--adaptive-samples", type=int, default=1024)
    p.add_argument("--adaptive-min-samples", type=int, default=16)
    p.add_argument("--ladder", type=int, nargs="+", default=[32, 64, 128, 256, 512, 1024],
                   help="samples of the plain renders the adaptive ones are compared with")
    p.add_argument("--filter-samples", type=int, default=16)
    p.add_argument("--filter-scenes", nargs="+", default=["cornell_box", "procedural_materials"])
    p.add_argument("--filter-integrators", nargs="+", default=["PHOTON", "PATH"], choices=("PHOTON", "PATH"))
    p.add_argument("--filters", nargs="+", default=list(FILTERS), choices=FILTERS)
    p.add_argument("--targets", nargs="+", default=list(TARGETS), choices=TARGETS)
    args = p.parse_args(_common.script_argv())
    args.resolution = tuple(args.resolution)
    args.spp = sorted(set(args.spp))
    os.makedirs(args.out, exist_ok=True)
    if "samplers" in args.parts:
        part_samplers(args, [], [])
    if "adaptive" in args.parts:
        part_adaptive(args, [])
    if "filters" in args.parts:
        part_filters(args, [])


if __name__ == "__main__":
    quality.run_main(main)
