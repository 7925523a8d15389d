#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Which PHOTON settings give the lowest error per second: the sweeps'
CSV files (bench/quality.py sweep) ranked by efficiency.

    python3 bench/defaults_report.py out/bench/sweep_*.csv [--top N]

Efficiency is 1 / (relative MSE x render time), Monte Carlo's figure of
merit (Veach 1997 §2.6; pbrt-v4 §2.1.2): an unbiased renderer's relative
MSE falls as 1 / time, so the product is what a setting buys per second, and
its ratio between two renderers is their ratio of relative MSE at equal
time. The time is full_hd_seconds: the measured render with its tiles
scaled to 1920 x 1080, Blender's default output, so the photon maps' fixed
cost weighs as it does on a user's F12.

Timing on a shared machine only ever errs upward (another process, a
lower clock), so the time of a setting is modelled from the fastest
measurement of the same work: its fixed part (export, photon maps) is the
fastest fixed part measured with the same photon settings, its tiles the
fastest per-sample tile time measured with the same per-sample settings
(everything but `samples`) times the sample count. Pass --measured to use
each render's own time instead.

A setting's score is the geometric mean over the scenes of its efficiency
divided by the best efficiency found on that scene (1 = best everywhere).
Only settings measured on every scene are scored.
"""

import argparse
import collections
import csv
import math

# What a row measured, as against the settings it was measured at: every
# other column is a setting (bench/quality.py phos_measurement).
KEYS_NOT_SETTINGS = {"scene", "engine", "integrator", "seconds", "fixed_seconds", "full_hd_seconds",
                     "relative_mse", "reference_share", "mean_ratio", "vs_cycles",
                     "tracing_seconds", "tracing_share", "photon_yield"}


def read_rows(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as f:
            rows += list(csv.DictReader(f))
    return rows


def setting_key(row):
    return tuple(sorted((k, v) for k, v in row.items() if k not in KEYS_NOT_SETTINGS and v != ""))


PHOTON_MAP_SETTINGS = ("global_photons", "caustic_photons", "global_estimate_photons", "max_radius")


def modelled_seconds(rows):
    """Full HD time of each row from the fastest measurements of the same work."""
    def fixed_key(r):
        return (r["scene"],) + tuple(r.get(k, "") for k in PHOTON_MAP_SETTINGS)

    def sample_key(r):
        return (r["scene"],) + tuple(kv for kv in setting_key(r) if kv[0] != "samples")

    fixed, per_sample = {}, {}
    for r in rows:
        f = float(r["fixed_seconds"])
        tiles = (float(r["full_hd_seconds"]) - f) / int(r["samples"])
        fixed[fixed_key(r)] = min(fixed.get(fixed_key(r), f), f)
        per_sample[sample_key(r)] = min(per_sample.get(sample_key(r), tiles), tiles)
    return [fixed[fixed_key(r)] + int(r["samples"]) * per_sample[sample_key(r)] for r in rows]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("csv", nargs="+")
    p.add_argument("--top", type=int, default=12)
    p.add_argument("--measured", action="store_true", help="each render's own time, not the model")
    p.add_argument("--max-seconds", type=float, default=0.0,
                   help="only settings whose Full HD time on every scene is at most this")
    args = p.parse_args()
    rows = [r for r in read_rows(args.csv) if r["engine"] == "PHOS"]
    times = [float(r["full_hd_seconds"]) for r in rows] if args.measured else modelled_seconds(rows)
    by_scene = collections.defaultdict(dict)
    for r, t in zip(rows, times):
        mse = float(r["relative_mse"])
        if mse > 0.0 and t > 0.0:
            by_scene[r["scene"]][setting_key(r)] = (1.0 / (mse * t), mse, t)
    scenes = sorted(by_scene)
    best = {s: max(v[0] for v in by_scene[s].values()) for s in scenes}
    common = set.intersection(*(set(by_scene[s]) for s in scenes)) if scenes else set()
    if args.max_seconds > 0.0:
        common = {k for k in common if all(by_scene[s][k][2] <= args.max_seconds for s in scenes)}
    scored = []
    for key in common:
        logs = [math.log(by_scene[s][key][0] / best[s]) for s in scenes]
        scored.append((math.exp(sum(logs) / len(logs)), key))
    scored.sort(reverse=True)

    print("scenes: %s; %d settings measured on all of them" % (", ".join(scenes), len(common)))
    header = "score  " + "  ".join("%-28s" % ("%s: relMSE, s (Full HD)" % s[:12]) for s in scenes) + "  setting"
    print(header)
    for score, key in scored[:args.top]:
        cells = ["%.3g, %.0f (%.2f)" % (by_scene[s][key][1], by_scene[s][key][2], by_scene[s][key][0] / best[s])
                 for s in scenes]
        print("%.3f  " % score + "  ".join("%-28s" % c for c in cells) + "  " +
              " ".join("%s=%s" % kv for kv in key))


if __name__ == "__main__":
    main()
