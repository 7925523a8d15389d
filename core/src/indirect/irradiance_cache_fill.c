/*
 * irradiance_cache_fill.c — the irradiance cache's pre-pass: coarse to fine
 * over the image (Tabellion & Lamorlette 2004), so that the tiles that
 * render afterwards only read the cache and the image is the same for any
 * thread count, tile order or border region.
 *
 * The passes visit pixels on ever finer grids: first every S-th
 * pixel in x and y (S, a power of two, about the largest spacing), then
 * for each s = S/2 … 1 the three cosets of the 2s grid that are new at
 * step s, (s, 0), (0, s) and (s, s), so that within a pass candidates lie
 * 2s pixels apart and rarely fall within one another's reach. In a pass,
 * each candidate follows a camera ray through a point of its pixel (drawn
 * from the pixel's own numbers) through specular surfaces (always
 * the lobe at u = 0.5, so the floor seen in a mirror gets records too) to
 * the first surface with a diffuse part, and looks the cache up there; the
 * candidates no record covers get one, computed in parallel, and the new
 * records are inserted in candidate order when the pass ends. Every random
 * number a record draws depends only on the seed and its pixel.
 *
 * A render farm's cache job fills one cache for a whole camera path: the
 * passes run again from each further view (phos_render_add_view), in
 * order, and add records only where those before left a gap. A view's
 * candidates draw from streams split by the view's index, so that a
 * pixel's record in one view does not repeat its numbers in another.
 *
 * The passes cover the full frame even when a border is rendered: a
 * region's pixels then read the same cache as in the full frame, which is
 * what makes a border, or a render farm's split of a frame, identical to
 * the same pixels of the whole.
 */
#include "indirect/irradiance_cache_fill.h"

#include <stdlib.h>

#include "indirect/irradiance_record.h"
#include "scene/camera.h"
#include "scene/embree.h"
#include "transport/specular_chain.h"
#include "util/parallel.h"

#define FILL_CHAIN_STEPS 16        /* specular surfaces a candidate's ray passes */
#define FILL_RECORD_STREAM 0x1cac0000u /* the candidates' sampler, split off the pixel's */
#define FILL_DIM_FILM 0u           /* 2: the candidate's point in its pixel, the sampler's only own
                                      dimensions (a record's rays draw from streams split off it) */
#define FILL_BLOCK 64              /* candidates per work item of the lookup phase */

static uint32_t passes_per_view(const irradiance_cache_fill_settings *fs)
{
    uint32_t S = 1, levels = 0, edge = fs->width > fs->height ? fs->width : fs->height;
    while (2 * S <= fs->max_spacing && 2 * S <= edge) {
        S *= 2;
        levels++;
    }
    return 1 + 3 * levels;
}

uint32_t irradiance_cache_fill_passes(const irradiance_cache_fill_settings *fs)
{
    return passes_per_view(fs) * (1u + fs->view_count);
}

/* Pass i's grid: pixels (x, y) with x ≡ ox and y ≡ oy modulo step. */
static void pass_grid(uint32_t passes, uint32_t i, uint32_t *step, uint32_t *ox, uint32_t *oy)
{
    uint32_t S = 1u << ((passes - 1) / 3);
    if (i == 0) {
        *step = S;
        *ox = *oy = 0;
        return;
    }
    uint32_t level = (i - 1) / 3 + 1, coset = (i - 1) % 3;
    uint32_t s = S >> level;
    *step = 2 * s;
    *ox = coset == 1 ? 0 : s;
    *oy = coset == 0 ? 0 : s;
}

typedef struct fill_job {
    irradiance_cache *c;
    const scene *s;
    const integrator_settings *is;
    const irradiance_cache_fill_settings *fs;
    integrator_scratch *scratch;
    const phos_camera_desc *camera; /* the view being filled from */
    uint32_t view;                  /* its index: 0 the scene's camera, then fs->views */
    uint32_t step, ox, oy, nx, ny; /* the pass's grid */
    uint32_t candidates;
    uint8_t *uncovered;            /* per candidate */
    uint32_t *todo;                /* the uncovered candidates, in order */
    irradiance_record *made;       /* their records */
    uint8_t *ok;
    atomic_uint_fast64_t *rays;    /* cast by the fill, counted per work item */
} fill_job;

static void candidate_pixel(const fill_job *job, uint32_t i, uint32_t *x, uint32_t *y)
{
    *x = job->ox + (i % job->nx) * job->step;
    *y = job->oy + (i / job->nx) * job->step;
}

/* The sampler of pixel (x, y)'s candidate: where in the pixel its ray
 * goes, and its record's rays. */
static sampler candidate_sampler(const fill_job *job, uint32_t x, uint32_t y)
{
    sampler pixel = sampler_for_pixel(job->fs->sampler, job->fs->seed, x, y, 0, 1);
    return sampler_split(&pixel, FILL_RECORD_STREAM + job->view);
}

/* The first surface with a diffuse part along pixel (x, y)'s candidate
 * ray: through a point of the pixel drawn from its own sampler, not its
 * centre, since a ray through the exact centre of a symmetric view can
 * meet a triangle's edge exactly, where which of the two triangles the
 * kernel reports depends on how its BVH was built. */
static int candidate_point(const fill_job *job, uint32_t x, uint32_t y, specular_chain_end *end, bsdf *diffuse)
{
    const irradiance_cache_fill_settings *fs = job->fs;
    sampler smp = candidate_sampler(job, x, y);
    float2 u = sampler_2d(&smp, FILL_DIM_FILM);
    float2 lens = {0.5f, 0.5f}; /* the lens centre */
    camera_ray ray = camera_generate_ray(job->camera, ((float)x + u.x) / (float)fs->width,
                                         ((float)y + u.y) / (float)fs->height, lens);
    specular_chain chain = {STOP_AT_DIFFUSE, FILL_CHAIN_STEPS, 1, NULL, 0, 0.0f, NULL, 0.0f};
    if (!specular_chain_follow(job->s, &chain, ray.o, ray.d, ray.tmin, ray.tmax, end))
        return 0;
    bsdf rest;
    bsdf_split(&end->b, diffuse, &rest);
    return diffuse->count > 0;
}

static void lookup_block(void *ctx, uint32_t item, uint32_t thread)
{
    fill_job *job = ctx;
    uint64_t rays_before = embree_thread_rays();
    uint32_t end_i = (item + 1) * FILL_BLOCK < job->candidates ? (item + 1) * FILL_BLOCK : job->candidates;
    for (uint32_t i = item * FILL_BLOCK; i < end_i; i++) {
        uint32_t x, y;
        candidate_pixel(job, i, &x, &y);
        specular_chain_end end;
        bsdf diffuse;
        irradiance_estimate e;
        job->uncovered[i] = candidate_point(job, x, y, &end, &diffuse) &&
                            !irradiance_cache_lookup(job->c, end.sf.p, end.sf.ns, &e);
    }
    atomic_fetch_add(job->rays, embree_thread_rays() - rays_before);
}

/* World size of a pixel at p (scene units): the spacing clamps are in
 * pixels so that records neither crowd nor thin out on screen. */
static float pixel_footprint(const phos_camera_desc *c, const irradiance_cache_fill_settings *fs, vec3 p)
{
    float per_unit = (c->frame_max[0] - c->frame_min[0]) / (float)fs->width;
    if (c->type == PHOS_CAMERA_ORTHOGRAPHIC)
        return per_unit;
    vec3 eye = v3(c->transform[3], c->transform[7], c->transform[11]);
    return per_unit * v3_length(v3_sub(p, eye));
}

static void record_one(void *ctx, uint32_t item, uint32_t thread)
{
    fill_job *job = ctx;
    uint32_t x, y;
    candidate_pixel(job, job->todo[item], &x, &y);
    specular_chain_end end;
    bsdf diffuse;
    job->ok[item] = 0;
    uint64_t rays_before = embree_thread_rays();
    if (!candidate_point(job, x, y, &end, &diffuse))
        return;
    sampler smp = candidate_sampler(job, x, y);
    light_context light = light_context_at(&end.sf);
    indirect_query q = {job->s, job->is, &end.sf, &light, &diffuse, end.wo, &smp, 0, 0, &job->scratch[thread]};
    float fp = pixel_footprint(job->camera, job->fs, end.sf.p), acc = job->c->accuracy;
    job->ok[item] = (uint8_t)irradiance_record_compute(&q, job->is->cache_inner->incoming, job->fs->rays,
                                                       acc * job->fs->min_spacing * fp,
                                                       acc * job->fs->max_spacing * fp, &job->made[item]);
    atomic_fetch_add(job->rays, embree_thread_rays() - rays_before);
}

/* One pass: look up every candidate, make records for the uncovered ones
 * in parallel, insert them in candidate order. */
static phos_status fill_pass(fill_job *job, atomic_int *cancel)
{
    const irradiance_cache_fill_settings *fs = job->fs;
    job->nx = fs->width > job->ox ? (fs->width - job->ox + job->step - 1) / job->step : 0;
    job->ny = fs->height > job->oy ? (fs->height - job->oy + job->step - 1) / job->step : 0;
    job->candidates = job->nx * job->ny;
    if (!job->candidates)
        return PHOS_OK;
    job->uncovered = malloc(job->candidates);
    job->todo = malloc(sizeof(uint32_t) * job->candidates);
    phos_status st = PHOS_ERROR_OUT_OF_MEMORY;
    if (!job->uncovered || !job->todo)
        goto done;
    st = PHOS_ERROR_CANCELLED;
    if (!parallel_for((job->candidates + FILL_BLOCK - 1) / FILL_BLOCK, fs->threads, lookup_block, job, cancel))
        goto done;
    uint32_t n = 0;
    for (uint32_t i = 0; i < job->candidates; i++)
        if (job->uncovered[i])
            job->todo[n++] = i;
    st = PHOS_ERROR_OUT_OF_MEMORY;
    job->made = malloc(sizeof(irradiance_record) * (n ? n : 1));
    job->ok = malloc(n ? n : 1);
    if (!job->made || !job->ok)
        goto done;
    st = PHOS_ERROR_CANCELLED;
    if (!parallel_for(n, fs->threads, record_one, job, cancel))
        goto done;
    st = PHOS_OK;
    for (uint32_t i = 0; i < n && st == PHOS_OK; i++)
        if (job->ok[i] && !irradiance_cache_insert(job->c, &job->made[i]))
            st = PHOS_ERROR_OUT_OF_MEMORY;
done:
    free(job->uncovered);
    free(job->todo);
    free(job->made);
    free(job->ok);
    job->uncovered = job->ok = NULL;
    job->todo = NULL;
    job->made = NULL;
    return st;
}

phos_status irradiance_cache_fill(irradiance_cache *c, const scene *s, const integrator_settings *is,
                                  const irradiance_cache_fill_settings *fs, integrator_scratch *scratch,
                                  atomic_int *cancel, atomic_uint *passes_done, atomic_uint_fast64_t *rays_traced)
{
    uint32_t passes = passes_per_view(fs);
    fill_job job = {c, s, is, fs, scratch, &s->camera, 0, 0, 0, 0, 0, 0, 0, NULL, NULL, NULL, NULL, rays_traced};
    for (uint32_t view = 0; view <= fs->view_count; view++) {
        job.view = view;
        job.camera = view == 0 ? &s->camera : &fs->views[view - 1];
        for (uint32_t i = 0; i < passes; i++) {
            if (atomic_load(cancel))
                return PHOS_ERROR_CANCELLED;
            pass_grid(passes, i, &job.step, &job.ox, &job.oy);
            phos_status st = fill_pass(&job, cancel);
            if (st != PHOS_OK)
                return st;
            atomic_fetch_add(passes_done, 1u);
        }
    }
    /* Neighbour clamping has shrunk radii since their records were
     * placed: the final tree, as a saved cache gets it. */
    return irradiance_cache_rebuild(c) ? PHOS_OK : PHOS_ERROR_OUT_OF_MEMORY;
}
