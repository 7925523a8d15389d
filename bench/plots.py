# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots and the Markdown summary of `make bench`, from what the benchmark
programs wrote to out/bench/ (runs with Debian's python3, numpy and
matplotlib; not inside Blender).

    python3 bench/plots.py [OUT_DIR]

Reads   bench_<scene>.csv and bench_<scene>.npz (bench/quality.py bench;
        budgets_<scene>.csv, from --parts budgets, replaces its budget rows),
        rays.csv, threads.csv, photons.csv (bench_core), kdtree.csv
        (bench_kdtree), scaling.csv (bench/scaling.py), viewport.csv
        (bench/viewport.py), official_<scene>.csv
        (quality.py bench --parts official, under an official Blender),
        convergence_*.csv and convergence_strip_<scene>.npz
        (bench/convergence.py), when present.
Writes  quality_vs_time.png (relative MSE against render time, log-log,
        a panel per scene), strip_<scene>.png (reference, Phos, Cycles and
        each one's error), scaling.png, convergence_samplers.png,
        convergence_adaptive.png, convergence_strip_<scene>.png (the
        filters side by side), and summary.md.
"""

import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RELATIVE_EPSILON = 0.01  # as in bench/quality.py
COLOURS = {"PHOTON": "tab:orange", "PATH": "tab:blue", "CYCLES": "tab:gray"}
SAMPLER_COLOURS = {"RANDOM": "tab:gray", "STRATIFIED": "tab:green", "HALTON": "tab:purple", "SOBOL": "tab:blue"}


def save_figure(fig, out_dir, name, tight=True):
    """Writes fig to out_dir/name (110 dpi), closes it and returns the
    path; tight: lay it out first (not where a colour bar spans axes)."""
    if tight:
        fig.tight_layout()
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(row, key):
    try:
        return float(row[key])
    except (KeyError, TypeError, ValueError):
        return float("nan")


def series(rows):
    """(label, [(seconds, relative MSE)]) for PHOTON, PATH and Cycles over
    the budget and equal-time rows."""
    out = {"PHOTON": [], "PATH": [], "CYCLES": []}
    for r in rows:
        if r.get("kind") not in ("budget", "equal_time"):
            continue
        label = r["integrator"] if r["engine"] == "PHOS" else "CYCLES"
        if label in out:
            out[label].append((num(r, "seconds"), num(r, "relative_mse")))
    return {k: sorted(v) for k, v in out.items() if v}


def plot_quality(scenes, out_dir):
    n = len(scenes)
    fig, axes = plt.subplots(1, n, figsize=(4.2 * n, 3.8), squeeze=False)
    for ax, (scene, rows) in zip(axes[0], scenes):
        for label, pts in series(rows).items():
            t, e = zip(*pts)
            name = {"PHOTON": "Phos PHOTON", "PATH": "Phos PATH", "CYCLES": "Cycles"}[label]
            ax.loglog(t, np.maximum(e, 1e-7), "o-", color=COLOURS[label], label=name, ms=4)
        ax.set_title(scene)
        ax.set_xlabel("render time (s)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("relative MSE")
    axes[0][0].legend()
    return save_figure(fig, out_dir, "quality_vs_time.png")


def display(img, exposure):
    """Linear RGB to an sRGB-like display image (a 2.2 gamma after the
    exposure that puts the reference's 99th percentile at 1)."""
    return np.clip(img * exposure, 0.0, 1.0) ** (1.0 / 2.2)


def plot_strip(scene, npz_path, out_dir, reference_engine):
    data = np.load(npz_path)
    ref = data["reference"].astype(np.float64)
    exposure = 1.0 / max(np.percentile(ref, 99), 1e-6)
    panels = [("reference (%s)" % {"PHOS": "Phos PHOTON"}.get(reference_engine, "Cycles"), ref)]
    for key, title in (("PHOTON", "Phos PHOTON"), ("CYCLES_vs_PHOTON", "Cycles, same time"),
                       ("PATH", "Phos PATH")):
        if key in data:
            panels.append((title, data[key].astype(np.float64)))
    errors = [(t + ": error", ((img - ref) ** 2 / (ref ** 2 + RELATIVE_EPSILON)).mean(axis=-1))
              for t, img in panels[1:]]
    top = max([np.percentile(e, 99) for _, e in errors] + [1e-6])
    fig, axes = plt.subplots(2, len(panels), figsize=(2.6 * len(panels), 5.4), squeeze=False)
    for i, (title, img) in enumerate(panels):
        axes[0][i].imshow(display(img, exposure), origin="upper")
        axes[0][i].set_title(title, fontsize=9)
    axes[1][0].axis("off")
    for i, (title, err) in enumerate(errors, start=1):
        im = axes[1][i].imshow(err, origin="upper", cmap="inferno", vmin=0.0, vmax=top)
        axes[1][i].set_title("%s %.2g" % (title, err.mean()), fontsize=8)
    for row in axes:
        for ax in row:
            ax.set_xticks([])
            ax.set_yticks([])
    fig.colorbar(im, ax=axes[1].tolist(), shrink=0.8, label="relative squared error")
    return save_figure(fig, out_dir, "strip_%s.png" % scene, tight=False)


def plot_scaling(rows, photon_rows, out_dir):
    if not rows and not photon_rows:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    if rows:
        for engine, colour in (("PHOS", COLOURS["PATH"]), ("CYCLES", COLOURS["CYCLES"])):
            for shading, style in (("flat", "o-"), ("smooth", "s--")):
                pts = sorted((num(r, "triangles"), num(r, "sync_seconds")) for r in rows
                             if r["engine"] == engine and r.get("shading", "flat") == shading)
                if pts:
                    axes[0].loglog(*zip(*pts), style, color=colour,
                                   label="%s export + BVH, %s" % (engine.title(), shading))
        axes[0].set_xlabel("triangles")
        axes[0].set_ylabel("seconds")
        axes[0].legend()
        axes[0].grid(True, which="both", alpha=0.3)
    if photon_rows:
        n = [num(r, "photons") for r in photon_rows]
        for key, label in (("trace_seconds", "trace"), ("build_seconds", "kd-tree build")):
            axes[1].loglog(n, [num(r, key) for r in photon_rows], "o-", label=label)
        ref = np.array(n) * np.log2(n)
        b = [num(r, "build_seconds") for r in photon_rows]
        axes[1].loglog(n, ref * (b[-1] / ref[-1]), "k:", label="n log n")
        axes[1].set_xlabel("photons")
        axes[1].legend()
        axes[1].grid(True, which="both", alpha=0.3)
    return save_figure(fig, out_dir, "scaling.png")


def srgb(img):
    """Linear RGB clamped to [0, 1], through the sRGB transfer function."""
    x = np.clip(img, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1.0 / 2.4) - 0.055)


def plot_samplers(rows, out_dir):
    """Relative MSE against samples per pixel per sampler, log-log: a column
    per variant (direct only, full), the error over the whole image and
    over the pixels away from lamps and their reflections."""
    variants = [v for v in ("direct", "full") if any(r["variant"] == v for r in rows)]
    metrics = (("relative_mse", "relative MSE"), ("surface_mse", "relative MSE away from lamps"))
    fig, axes = plt.subplots(2, len(variants), figsize=(4.4 * len(variants), 7.2), squeeze=False)
    for col, variant in enumerate(variants):
        for line, (metric, label) in enumerate(metrics):
            ax = axes[line][col]
            for sampler, colour in SAMPLER_COLOURS.items():
                pts = sorted((num(r, "samples"), num(r, metric)) for r in rows
                             if r["variant"] == variant and r["sampler"] == sampler)
                if pts:
                    spp, e = zip(*pts)
                    ax.loglog(spp, np.maximum(e, 1e-9), "o-", color=colour, label=sampler.title(), ms=3)
                    if sampler == "RANDOM":   # 1 / spp through Random's last (least noisy) point
                        ax.loglog(spp, e[-1] * spp[-1] / np.array(spp), "k:", lw=0.8, label="1 / spp")
            ax.set_title("%s: %s" % ({"direct": "direct light only"}.get(variant, variant), label), fontsize=9)
            ax.set_xlabel("samples per pixel")
            ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=8)
    return save_figure(fig, out_dir, "convergence_samplers.png")


def plot_adaptive(rows, out_dir):
    """Relative MSE against render time: the plain renders' ladder and the
    adaptive renders, each labelled with its threshold and mean samples."""
    fig, ax = plt.subplots(figsize=(5.2, 3.8))
    plain = sorted((num(r, "seconds"), num(r, "relative_mse")) for r in rows if r["adaptive"] == "0")
    if plain:
        ax.loglog(*zip(*plain), "o-", color=COLOURS["CYCLES"], label="adaptive off", ms=4)
    on = sorted(((num(r, "seconds"), num(r, "relative_mse"), r) for r in rows if r["adaptive"] == "1"),
                key=lambda p: p[0])
    if on:
        ax.loglog([t for t, _, _ in on], [e for _, e, _ in on], "s--", color=COLOURS["PATH"], label="adaptive on", ms=5)
        for i, (t, e, r) in enumerate(on):   # labels staggered upwards: the points lie close
            ax.annotate("%s: %.0f spp" % (r["threshold"], num(r, "mean_spp")), (t, e), fontsize=7,
                        textcoords="offset points", xytext=(-30, 10 + 11 * i),
                        arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.5"})
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("relative MSE")
    ax.set_title("PATH, Cornell box", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, out_dir, "convergence_adaptive.png")


def plot_filter_strip(npz_path, out_dir):
    """The filters side by side at the same samples, as the course's slides
    show them, then the reference (sRGB, clamped, no exposure)."""
    data = np.load(npz_path)
    labels = [str(x) for x in data["labels"]]
    panels = [("%s\nrelative MSE %.3g" % (lb, e), data["panel%d" % i]) for i, (lb, e)
              in enumerate(zip(labels, data["errors"]))] + [("reference", data["reference"])]
    fig, axes = plt.subplots(1, len(panels), figsize=(2.3 * len(panels), 2.8), squeeze=False)
    for ax, (title, img) in zip(axes[0], panels):
        ax.imshow(srgb(img.astype(np.float64)), origin="lower")   # rows go up, as Blender's
        ax.set_title(title, fontsize=8)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle("%s, %s spp" % (data["integrator"], int(data["samples"])), fontsize=9)
    name = os.path.basename(npz_path)[:-len(".npz")]
    return save_figure(fig, out_dir, name + ".png")


def convergence_section(out_dir):
    """The summary's part for bench/convergence.py, its plots drawn; [] if
    it did not run."""
    md = []
    samplers = read_csv(os.path.join(out_dir, "convergence_samplers.csv"))
    slopes = read_csv(os.path.join(out_dir, "convergence_slopes.csv"))
    if samplers:
        top = max(num(r, "samples") for r in samplers)

        def mse_at(r, spp, metric="relative_mse"):
            return g(next((num(x, metric) for x in samplers if x["variant"] == r["variant"]
                           and x["sampler"] == r["sampler"] and num(x, "samples") == spp), float("nan")))
        md += ["## Samplers (PATH, Cornell box)", "",
               "Relative MSE averaged over seeds; rate: −d log(MSE) / d log(spp), least squares over all "
               "sample counts (1 for plain Monte Carlo).", "",
               table(slopes, ["variant", "sampler", lambda r: mse_at(r, 10), lambda r: mse_at(r, top),
                              lambda r: g(num(r, "relative_mse_rate"), "%.2f"),
                              lambda r: mse_at(r, 10, "surface_mse"), lambda r: mse_at(r, top, "surface_mse"),
                              lambda r: g(num(r, "surface_mse_rate"), "%.2f")],
                     ["variant", "sampler", "10 spp", "%d spp" % top, "rate", "away from lamps: 10 spp",
                      "%d spp" % top, "rate"]), "",
               "![samplers](%s)" % os.path.basename(plot_samplers(samplers, out_dir)), ""]
    adaptive = read_csv(os.path.join(out_dir, "convergence_adaptive.csv"))
    if adaptive:
        md += ["## Adaptive sampling at equal time (PATH, Cornell box)", "",
               table([r for r in adaptive if r["adaptive"] == "1"],
                     ["threshold", "samples", lambda r: g(num(r, "mean_spp"), "%.0f"),
                      lambda r: g(num(r, "seconds"), "%.1f"), lambda r: g(num(r, "relative_mse")),
                      lambda r: g(num(r, "plain_mse_equal_time")), lambda r: g(num(r, "vs_plain_equal_time")),
                      lambda r: g(num(r, "vs_plain_equal_spp"))],
                     ["threshold", "samples", "mean spp", "seconds", "relative MSE", "plain, same time",
                      "adaptive / plain, same time", "same mean spp"]), "",
               "![adaptive](%s)" % os.path.basename(plot_adaptive(adaptive, out_dir)), ""]
    filters = read_csv(os.path.join(out_dir, "convergence_filters.csv"))
    if filters:
        md += ["## Filters (%s spp)" % filters[0]["samples"], "",
               "Energy balance: the Combined pass's RGB sum over the Noisy Image pass's, minus 1.", "",
               table(filters, ["scene", "integrator", "filter", "target", lambda r: g(num(r, "relative_mse")),
                               lambda r: g(num(r, "vs_unfiltered")), lambda r: g(num(r, "surface_mse")),
                               lambda r: g(num(r, "energy_balance"), "%.2e"),
                               lambda r: g(1e3 * num(r, "filter_seconds"), "%.1f"),
                               lambda r: g(num(r, "seconds"), "%.1f")],
                     ["scene", "integrator", "filter", "target", "relative MSE", "/ unfiltered", "away from lamps",
                      "energy balance", "filter (ms)", "render (s)"]), ""]
    for npz in sorted(glob.glob(os.path.join(out_dir, "convergence_strip_*.npz"))):
        path = plot_filter_strip(npz, out_dir)
        md += ["![%s](%s)" % (os.path.basename(path)[:-4], os.path.basename(path)), ""]
    return md


def table(rows, cols, heads):
    lines = ["| " + " | ".join(heads) + " |", "|" + "---|" * len(heads)]
    for r in rows:
        lines.append("| " + " | ".join(c(r) if callable(c) else str(r.get(c, "")) for c in cols) + " |")
    return "\n".join(lines)


def g(x, fmt="%.3g"):
    return fmt % x if x == x else ""


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join("out", "bench")
    scenes = []
    for path in sorted(glob.glob(os.path.join(out_dir, "bench_*.csv"))):
        scene = os.path.basename(path)[len("bench_"):-len(".csv")]
        rows = read_csv(path)
        # Budgets measured again on their own (quality.py bench --parts
        # budgets) replace those of the full run.
        budgets = read_csv(os.path.join(out_dir, "budgets_%s.csv" % scene))
        if budgets:
            rows = [r for r in rows if r.get("kind") != "budget"] + budgets
        scenes.append((scene, rows))
    md = ["# Phos benchmark", ""]
    if scenes and scenes[0][1]:
        r0 = scenes[0][1][0]
        md += ["Machine: %s, %s cores; Blender %s; %s." % (r0.get("cpu"), r0.get("cores"), r0.get("blender"),
                                                           r0.get("date")), ""]
    if scenes:
        md += ["## Equal time at the defaults", "",
               table([r for _, rows in scenes for r in rows if r.get("kind") == "equal_time"
                      and r["engine"] == "PHOS"],
                     ["scene", "integrator", lambda r: g(num(r, "seconds"), "%.1f"),
                      lambda r: g(num(r, "relative_mse")), lambda r: g(num(r, "vs_cycles"))],
                     ["scene", "Phos", "seconds", "relative MSE", "Phos / Cycles at equal time"]), ""]
        md += ["## Fixed budgets", "",
               table([r for _, rows in scenes for r in rows if r.get("kind") == "budget"],
                     ["scene", "budget", lambda r: r["integrator"] or "Cycles", "samples",
                      lambda r: g(num(r, "seconds"), "%.1f"), lambda r: g(num(r, "relative_mse"))],
                     ["scene", "budget (s)", "engine", "samples", "seconds", "relative MSE"]), ""]
        md += ["## Path tracers at equal samples", "",
               table([r for _, rows in scenes for r in rows if r.get("kind") == "path_speed"],
                     ["scene", "engine", "samples", lambda r: g(1e3 * num(r, "seconds_per_sample"), "%.2f"),
                      lambda r: g(num(r, "variance_per_sample"))],
                     ["scene", "engine", "samples", "ms per sample", "relative MSE × samples"]), ""]
        md += ["![quality against time](%s)" % os.path.basename(plot_quality(scenes, out_dir)), ""]
        for scene, rows in scenes:
            npz = os.path.join(out_dir, "bench_%s.npz" % scene)
            if os.path.exists(npz):
                engine = rows[0].get("reference_engine", "CYCLES") if rows else "CYCLES"
                md += ["![%s](%s)" % (scene, os.path.basename(plot_strip(scene, npz, out_dir, engine))), ""]
    official_rows = [r for path in sorted(glob.glob(os.path.join(out_dir, "official_*.csv")))
                     for r in read_csv(path)]
    official = [r for r in official_rows if r.get("kind") == "official"]
    official_equal = [r for r in official_rows if r.get("kind") == "equal_time" and r["engine"] == "PHOS"]
    if official_equal:
        md += ["## Equal time against Cycles as artists run it (Blender %s)" % official_equal[0].get("blender"), "",
               "Phos at its defaults and this Cycles given the same time (issue 24's scenes).", "",
               table(official_equal, ["scene", "integrator", lambda r: g(num(r, "seconds"), "%.1f"),
                                      lambda r: g(num(r, "relative_mse")), lambda r: g(num(r, "vs_cycles"))],
                     ["scene", "Phos", "seconds", "relative MSE", "Phos / Cycles at equal time"]), ""]
    if official:
        def config(r):
            return ("Phos " + r["integrator"]) if r["engine"] == "PHOS" else {
                "cycles": "Cycles", "cycles_guiding": "Cycles, path guiding",
                "cycles_oidn": "Cycles, OpenImageDenoise"}.get(r["integrator"], r["integrator"])
        phos_error = {r["scene"]: num(r, "relative_mse") for r in official
                      if r["engine"] == "PHOS" and r["integrator"] == "PHOTON"}
        md += ["## Against Cycles as artists run it (Blender %s)" % official[0].get("blender"), "",
               "At the time Phos PHOTON takes at its defaults; the error of each, and Phos PHOTON's "
               "(raw) divided by it.", "",
               table(official, ["scene", config, lambda r: g(num(r, "seconds"), "%.1f"),
                                lambda r: g(num(r, "relative_mse")),
                                lambda r: g(phos_error.get(r["scene"], float("nan")) / num(r, "relative_mse"))],
                     ["scene", "configuration", "seconds", "relative MSE", "Phos PHOTON / this"]), ""]
    rays = read_csv(os.path.join(out_dir, "rays.csv"))
    if rays:
        md += ["## Ray throughput", "", table(rays, ["threads", "phos_mrays_s", "raw_mrays_s", "ratio"],
                                              ["threads", "Phos PATH (M rays/s)", "raw Embree (M rays/s)",
                                               "Phos / raw"]), ""]
    threads = read_csv(os.path.join(out_dir, "threads.csv"))
    if threads:
        md += ["## Thread scaling", "", table(threads, ["stage", "seconds_1", "seconds_all", "speedup", "a_second_or_more"],
                                              ["stage", "1 thread (s)", "all (s)", "speed-up",
                                               "a second or more on 1 thread (the target's stages)"]), ""]
    photons = read_csv(os.path.join(out_dir, "photons.csv"))
    if photons:
        md += ["## Photon maps", "", table(photons, ["photons", "trace_seconds", "build_seconds",
                                                     "build_ns_per_nlog2n", "bytes_per_photon",
                                                     "queries_per_second"],
                                           ["photons", "trace (s)", "build (s)", "build ns / (n log₂ n)",
                                            "bytes per photon", "k = 50 queries/s"]), ""]
    kd = read_csv(os.path.join(out_dir, "kdtree.csv"))
    if kd:
        md += ["## kd-tree against nanoflann", "", table(kd, list(kd[0].keys()), list(kd[0].keys())), ""]
    viewport = read_csv(os.path.join(out_dir, "viewport.csv"))
    if viewport:
        md += ["## Viewport latency against Cycles' viewport", "",
               "From switching to Rendered, and from each edit, to the first image on the screen "
               "(bench/viewport.py); the ratio is this engine's time over Cycles'.", "",
               table(viewport, ["engine", "what", "seconds", "ratio_to_cycles"],
                     ["engine", "", "seconds", "/ Cycles"]), ""]
    scaling = read_csv(os.path.join(out_dir, "scaling.csv"))
    if scaling:
        md += ["## Cost against triangles", "", table(scaling, list(scaling[0].keys()), list(scaling[0].keys())), ""]
    path = plot_scaling(scaling, photons, out_dir)
    if path:
        md += ["![scaling](%s)" % os.path.basename(path), ""]
    md += convergence_section(out_dir)
    with open(os.path.join(out_dir, "summary.md"), "w") as f:
        f.write("\n".join(md))
    print("wrote %s" % os.path.join(out_dir, "summary.md"))


if __name__ == "__main__":
    main()
