# SPDX-License-Identifier: GPL-3.0-or-later
"""The status line of a render, as F12 (engine.py) and the viewport
(viewport.py) show it: the core's name of the running stage and what it
has counted so far."""

from . import core


def stage_text(progress, stage_id, name, samples):
    """The status line's stage part: the core's name of the stage and what it
    has counted so far, e.g. "Tracing photons | 123,456 stored"."""
    if stage_id == core.PHOS_STAGE_TRACING_PHOTONS:
        which = "caustic map" if progress.photon_map == core.PHOS_MAP_CAUSTIC else "global map"
        return "{} | {} | {:,} stored | {:,} emitted".format(
            name, which, progress.photons_stored, progress.photons_emitted)
    if stage_id == core.PHOS_STAGE_BUILDING_KDTREES:
        return "{} | {:,} photons".format(name, progress.photons_stored)
    if stage_id in (core.PHOS_STAGE_RENDERING, core.PHOS_STAGE_FINISHED):
        if stage_id == core.PHOS_STAGE_FINISHED:
            # What stays on the status line when the render is done: its
            # time (the stages', export aside), then samples, photons, records.
            name = "%s in %.2f s" % (name, sum(progress.stage_seconds))
        total = progress.samples or samples
        if progress.tiles_total > 0 and progress.samples_done < total:
            # Progressive refinement: the pass running is the one after
            # the samples every pixel has.
            text = "%s | Sample %d/%d | Tile %d/%d" % (
                name, progress.samples_done, total, progress.tiles_done, progress.tiles_total)
        else:
            text = "%s | Tile %d/%d | %d samples" % (name, progress.tiles_done, progress.tiles_total, total)
        if progress.global_photons or progress.caustic_photons:
            text += " | photons {:,} global, {:,} caustic".format(
                progress.global_photons, progress.caustic_photons)
        return text + cache_text(progress)
    return name


def cache_text(progress):
    """" | irradiance cache 1,234 records, 97.5 % interpolated", or "" without a cache."""
    if not progress.cache_records:
        return ""
    text = " | irradiance cache {:,} records".format(progress.cache_records)
    if progress.cache_lookups:
        text += ", %.1f %% interpolated" % (100.0 * progress.cache_interpolated / progress.cache_lookups)
    return text


def short_map_warnings(progress, rs):
    """A warning per photon map that ended short of its count, saying why
    the core stopped it and what to do about it. The core stops the global
    pass at its emission cap, or at its probe when that stores almost
    nothing; the caustic pass also at ten paths a photon asked for, which
    a faint caustic (a dark mirror, a coat over a diffuse base) reaches
    first (docs/algorithms.md §3.2)."""
    maps = ((core.PHOS_MAP_GLOBAL, "global", progress.global_photons, rs.global_photons,
             "its lights' photons mostly leave the scene or are absorbed", ""),
            (core.PHOS_MAP_CAUSTIC, "caustic", progress.caustic_photons, rs.caustic_photons,
             "few of its lights' paths reach a diffuse surface by way of a mirror or glass (a faint caustic)",
             "; raising Caustic Photons traces more paths"))
    out = []
    for bit, name, got, want, reason, advice in maps:
        if progress.photon_maps_short & (1 << bit):
            out.append("Phos: the %s photon map holds %s of %s photons: %s, so tracing stopped early "
                       "(the map is right, only sparser)%s"
                       % (name, "{:,}".format(got), "{:,}".format(want), reason, advice))
    return out
