/*
 * stages.c — the stage names and a render's plan (stages.h).
 */
#include "render/stages.h"

#include <math.h>

#include "render/film.h"

/* The passes that need the photon maps whatever the integrator. */
#define PHOTON_DEBUG_PASSES ((1u << PHOS_PASS_PHOTON_MAP) | (1u << PHOS_PASS_CAUSTIC_MAP) | (1u << PHOS_PASS_PHOTONS))
/* Those of them that read the global map itself, not through gathers. */
#define GLOBAL_MAP_DEBUG_PASSES ((1u << PHOS_PASS_PHOTON_MAP) | (1u << PHOS_PASS_PHOTONS))

int stage_plan_uses_cache(const phos_render_settings *rs)
{
    int photon = rs->integrator == PHOS_INTEGRATOR_PHOTON;
    /* The fast estimate sends no gather rays: there is nothing to cache. */
    if (photon && rs->photon_view == PHOS_PHOTON_VIEW_FAST)
        return 0;
    return rs->irradiance_cache == PHOS_IRRADIANCE_CACHE_ALWAYS ||
           (rs->irradiance_cache == PHOS_IRRADIANCE_CACHE_PHOTON && photon);
}

void stage_plan_make(const phos_render_settings *rs, stage_plan *plan)
{
    int photon = rs->integrator == PHOS_INTEGRATOR_PHOTON;
    uint32_t n = 0;
    plan->stages[n++] = PHOS_STAGE_WAITING;
    if (photon || (rs->pass_mask & PHOTON_DEBUG_PASSES)) {
        plan->stages[n++] = PHOS_STAGE_TRACING_PHOTONS;
        plan->stages[n++] = PHOS_STAGE_BUILDING_KDTREES;
        /* Final gathering reads radiance precomputed at the photons
         * (Christensen 1999, "Faster photon map global illumination"). */
        if (photon && rs->photon_view == PHOS_PHOTON_VIEW_FINAL_GATHER)
            plan->stages[n++] = PHOS_STAGE_PRECOMPUTING_RADIANCE;
    }
    if (stage_plan_uses_cache(rs))
        plan->stages[n++] = PHOS_STAGE_FILLING_IRRADIANCE_CACHE;
    if (!rs->caches_only) {
        plan->stages[n++] = PHOS_STAGE_RENDERING;
        if (rs->noise_filter != PHOS_NOISE_FILTER_NONE)
            plan->stages[n++] = PHOS_STAGE_FILTERING;
    }
    plan->stages[n++] = PHOS_STAGE_FINISHED;
    plan->count = n;
}

/* Each stage's share of a progress bar, relative to the others a plan
 * runs: a render with photon maps and the cache spends about a fifth of
 * its time on each before the tiles (docs/benchmarks.md's stage times). */
static const float stage_weight[PHOS_STAGE_COUNT] = {
    [PHOS_STAGE_WAITING] = 0.0f,
    [PHOS_STAGE_TRACING_PHOTONS] = 15.0f,
    [PHOS_STAGE_BUILDING_KDTREES] = 2.0f,
    [PHOS_STAGE_PRECOMPUTING_RADIANCE] = 3.0f,
    [PHOS_STAGE_FILLING_IRRADIANCE_CACHE] = 20.0f,
    [PHOS_STAGE_RENDERING] = 60.0f,
    [PHOS_STAGE_FILTERING] = 1.0f,
    [PHOS_STAGE_FINISHED] = 0.0f,
};

float stage_plan_fraction(const stage_plan *plan, uint32_t index, float within)
{
    float total = 0.0f, done = 0.0f;
    for (uint32_t i = 0; i < plan->count; i++) {
        float w = stage_weight[plan->stages[i]];
        total += w;
        if (i < index)
            done += w;
        else if (i == index)
            done += w * (within > 0.0f ? (within < 1.0f ? within : 1.0f) : 0.0f);
    }
    if (index >= plan->count || plan->stages[index] == PHOS_STAGE_FINISHED)
        return 1.0f;
    return total > 0.0f ? done / total : 0.0f;
}

int stage_plan_has(const stage_plan *plan, uint32_t stage)
{
    for (uint32_t i = 0; i < plan->count; i++)
        if (plan->stages[i] == stage)
            return 1;
    return 0;
}

int stage_is_photon_stage(uint32_t stage)
{
    return stage == PHOS_STAGE_TRACING_PHOTONS || stage == PHOS_STAGE_BUILDING_KDTREES ||
           stage == PHOS_STAGE_PRECOMPUTING_RADIANCE;
}

void stage_plan_drop_photon_stages(stage_plan *plan)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < plan->count; i++)
        if (!stage_is_photon_stage(plan->stages[i]))
            plan->stages[n++] = plan->stages[i];
    plan->count = n;
}

const char *stage_name(uint32_t stage, uint32_t integrator)
{
    switch (stage) {
    case PHOS_STAGE_WAITING: return "Waiting";
    case PHOS_STAGE_TRACING_PHOTONS: return "Tracing photons";
    case PHOS_STAGE_BUILDING_KDTREES: return "Building kd-trees";
    case PHOS_STAGE_PRECOMPUTING_RADIANCE: return "Precomputing radiance";
    case PHOS_STAGE_FILLING_IRRADIANCE_CACHE: return "Filling irradiance cache";
    case PHOS_STAGE_RENDERING:
        return integrator == PHOS_INTEGRATOR_PHOTON ? "Rendering with photon maps" : "Path tracing";
    case PHOS_STAGE_FILTERING: return "Filtering";
    case PHOS_STAGE_FINISHED: return "Finished";
    }
    return "Unknown stage";
}

uint32_t render_sample_passes(const phos_render_settings *rs, uint32_t ends[RENDER_MAX_SAMPLE_PASSES])
{
    uint32_t count = 0;
    /* A time limit needs passes: when it strikes, every pixel keeps what
     * the passes before gave it. */
    if (rs->progressive || rs->time_limit > 0.0f)
        for (uint32_t end = 1; end < rs->samples && count + 1 < RENDER_MAX_SAMPLE_PASSES; end *= 2)
            ends[count++] = end;
    ends[count++] = rs->samples;
    return count;
}

int render_progressive_caustics(const phos_render_settings *rs)
{
    return rs->integrator == PHOS_INTEGRATOR_PHOTON && rs->progressive_caustics && rs->samples > 1;
}

uint32_t render_global_photons(const phos_render_settings *rs)
{
    int read = !(rs->integrator == PHOS_INTEGRATOR_PHOTON && rs->photon_view == PHOS_PHOTON_VIEW_PATH_TRACED) ||
               (rs->pass_mask & GLOBAL_MAP_DEBUG_PASSES);
    return read ? rs->global_photons : 0;
}

int render_global_read_by_gathers(const phos_render_settings *rs)
{
    return rs->integrator == PHOS_INTEGRATOR_PHOTON && rs->photon_view == PHOS_PHOTON_VIEW_FINAL_GATHER &&
           !(rs->pass_mask & GLOBAL_MAP_DEBUG_PASSES);
}

int render_keeps_sums(const phos_render_settings *rs)
{
    uint32_t ends[RENDER_MAX_SAMPLE_PASSES];
    /* Progressive caustics render one sample at a time over the frame. */
    return render_sample_passes(rs, ends) > 1 || render_progressive_caustics(rs);
}

/* What the noise filter reads besides the user's passes: the Indirect
 * component, and the albedo its irradiance is taken over. */
static uint32_t filter_input_passes(const phos_render_settings *rs)
{
    if (rs->noise_filter == PHOS_NOISE_FILTER_NONE)
        return 0;
    switch (rs->filter_target) {
    case PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE:
        return (1u << PHOS_PASS_INDIRECT) | (1u << PHOS_PASS_DENOISING_ALBEDO);
    case PHOS_FILTER_TARGET_INDIRECT: return 1u << PHOS_PASS_INDIRECT;
    default: return 0;
    }
}

uint32_t render_film_passes(const phos_render_settings *rs)
{
    return rs->pass_mask | (1u << PHOS_PASS_COMBINED) | filter_input_passes(rs);
}

uint32_t render_caustic_reads(const phos_render_settings *rs)
{
    if (rs->integrator != PHOS_INTEGRATOR_PHOTON || render_progressive_caustics(rs))
        return 0;
    double reads = ceil((double)rs->caustic_sample_share * (double)rs->samples);
    uint32_t k = reads < 1.0 ? 1u : (uint32_t)reads; /* NaN: 1 */
    return k < rs->samples ? k : 0;
}

uint32_t render_film_extras(const phos_render_settings *rs)
{
    uint32_t extras = render_keeps_sums(rs) ? FILM_KEEP_SUMS : 0u;
    if (render_caustic_reads(rs))
        extras |= FILM_CAUSTIC_READS;
    if (rs->adaptive_sampling || rs->noise_filter != PHOS_NOISE_FILTER_NONE)
        extras |= FILM_MOMENTS;
    return extras;
}
