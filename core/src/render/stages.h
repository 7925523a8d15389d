/*
 * stages.h — the stages of a render, written once: their names, and which
 * of them a render with given settings runs, in order (its plan). The
 * controller (render.c) runs the plan; phos_render_stages and
 * phos_render_progress report it.
 */
#ifndef PHOS_STAGES_H
#define PHOS_STAGES_H

#include "phos.h"

typedef struct stage_plan {
    uint32_t count;
    uint32_t stages[PHOS_STAGE_COUNT]; /* enum phos_stage, in running order: WAITING first, FINISHED last */
} stage_plan;

/* The plan of a render with these (validated) settings: WAITING; the photon
 * stages if it uses photon maps (the PHOTON integrator, or a photon debug
 * pass with either integrator), with the radiance precomputation only for
 * final gathering; the irradiance cache's pre-pass if the cache is on;
 * RENDERING; FINISHED. */
void stage_plan_make(const phos_render_settings *rs, stage_plan *plan);

/* 1 if the settings turn the irradiance cache on for their integrator. */
int stage_plan_uses_cache(const phos_render_settings *rs);

/* How far along a progress bar a render is, 0..1, running the plan's
 * stage at `index`, `within` (0..1) of the way through it: each stage of
 * the plan has its share (stages.c), FINISHED is 1. */
float stage_plan_fraction(const stage_plan *plan, uint32_t index, float within);

/* 1 if the plan runs the stage. */
int stage_plan_has(const stage_plan *plan, uint32_t stage);

/* 1 for the stages that make the photon maps (tracing, kd-trees, radiance). */
int stage_is_photon_stage(uint32_t stage);

/* Leaves the photon stages out of the plan: a render given complete maps
 * (phos_render_use_photon_maps). */
void stage_plan_drop_photon_stages(stage_plan *plan);

/* The rendering stage's passes over the whole frame: with progressive
 * refinement and more than one sample, pass k ends at sample 2^k (1, 2,
 * 4 …) and the last at `samples`, so the first look at the whole frame
 * costs one sample a pixel; else one pass of every sample. Writes the
 * passes' ends (at most RENDER_MAX_SAMPLE_PASSES) and returns their count.
 * A time limit makes passes as progressive refinement does. */
#define RENDER_MAX_SAMPLE_PASSES 32
uint32_t render_sample_passes(const phos_render_settings *rs, uint32_t ends[RENDER_MAX_SAMPLE_PASSES]);

/* Whether the caustics are progressive (progressive_caustics.h): PHOTON
 * with the setting on and more than one sample; the rendering stage then
 * sweeps the frame one sample at a time, each with its own caustic map. */
int render_progressive_caustics(const phos_render_settings *rs);

/* The photons the global map stores: none when nothing reads it, which
 * is PHOTON's path-traced gather without the debug passes that show the
 * map. The tracing (render.c) and the memory estimate (memory.c) both
 * ask here. */
uint32_t render_global_photons(const phos_render_settings *rs);
/* Whether the render reads the global map only where gathers from surfaces
 * land (final gathering, and the irradiance cache's records made by it):
 * no fast view, no debug pass of the map (photon_trace_settings.gathers_only). */
int render_global_read_by_gathers(const phos_render_settings *rs);

/* The samples per pixel that read the caustic map at their first vertex
 * when only a share of them do: ⌈caustic_sample_share × samples⌉, at
 * least 1, for PHOTON with the fixed caustic map; 0 when every sample
 * reads it. */
uint32_t render_caustic_reads(const phos_render_settings *rs);

/* Whether a render keeps its pixels' sums between passes (film.h). */
int render_keeps_sums(const phos_render_settings *rs);

/* The passes a render's film holds: the user's (pass_mask), Combined, and
 * those the noise filter reads. */
uint32_t render_film_passes(const phos_render_settings *rs);
/* What else it keeps (enum film_extras). */
uint32_t render_film_extras(const phos_render_settings *rs);

/* The name of a stage as a status line shows it ("Tracing photons"); the
 * rendering stage is named after the integrator. Never NULL. */
const char *stage_name(uint32_t stage, uint32_t integrator);

#endif /* PHOS_STAGES_H */
