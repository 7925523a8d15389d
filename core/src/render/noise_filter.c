/*
 * noise_filter.c — the FILTERING stage (noise_filter.h).
 *
 * The course's "Problems With Filtering" slide: a filter over the whole
 * image blurs textures, highlights and caustics with the noise. Most of
 * the noise of a photon-mapped or path-traced image is in the indirect
 * light, and the indirect irradiance of a diffuse surface is smooth where
 * the surface's texture is not; so the default target is that irradiance:
 * the Indirect component over the surface's albedo (the Denoising Albedo
 * pass), filtered, then multiplied by the albedo again. Everything else
 * (emitters, direct light, mirrors, caustics) is added back unfiltered.
 */
#include "render/noise_filter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "filters/image_filter.h"

/* Albedo channels below this are taken as this when the indirect light is
 * divided by them (black surfaces reflect no indirect light, so their
 * irradiance is read as 0/ε = 0 and multiplied back exactly). */
#define ALBEDO_FLOOR 1e-3f

/* The albedo the indirect light is divided by and multiplied back with:
 * the Denoising Albedo pass, floored, and at most 1, since that pass also
 * holds the emitters seen (as Cycles' does), whose "albedo" of 3–12 at a
 * lamp's edge made the filtered irradiance come back brighter there. */
static float divisor_albedo(float albedo) { return fminf(fmaxf(albedo, ALBEDO_FLOOR), 1.0f); }

/* The variance of each pixel's mean luminance, from its samples' moments
 * (film.moments): s²/n with s² the samples' variance; 0 with one sample. */
static void mean_variances(const film *f, float *variance)
{
    size_t pixels = (size_t)f->width * f->height;
    for (size_t i = 0; i < pixels; i++) {
        uint32_t n = f->sample_counts[i] & ~PIXEL_CONVERGED;
        const double *m = f->moments + 2 * i;
        double v = 0.0;
        if (n > 1) {
            double mean = m[0] / n;
            v = fmax((m[1] - m[0] * mean) / (n - 1), 0.0) / n;
        }
        variance[i] = (float)v;
    }
}

/* The RGB the filter reads, by target. */
static void filter_source(const render *r, float *rgb)
{
    const film *f = &r->film;
    size_t pixels = (size_t)f->width * f->height;
    const float *combined = f->planes[PHOS_PASS_COMBINED];
    const float *indirect = f->planes[PHOS_PASS_INDIRECT];
    const float *albedo = f->planes[PHOS_PASS_DENOISING_ALBEDO];
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            switch (r->settings.filter_target) {
            case PHOS_FILTER_TARGET_ALL: rgb[3 * i + c] = combined[4 * i + c]; break;
            case PHOS_FILTER_TARGET_INDIRECT: rgb[3 * i + c] = indirect[3 * i + c]; break;
            default: rgb[3 * i + c] = indirect[3 * i + c] / divisor_albedo(albedo[3 * i + c]); break;
            }
        }
}

/* Combined with the filtered target in place of the unfiltered one. */
static void compose(render *r, const float *filtered)
{
    film *f = &r->film;
    size_t pixels = (size_t)f->width * f->height;
    float *combined = f->planes[PHOS_PASS_COMBINED];
    const float *indirect = f->planes[PHOS_PASS_INDIRECT];
    const float *albedo = f->planes[PHOS_PASS_DENOISING_ALBEDO];
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            float *out = &combined[4 * i + c], v = filtered[3 * i + c];
            switch (r->settings.filter_target) {
            case PHOS_FILTER_TARGET_ALL: *out = v; break;
            case PHOS_FILTER_TARGET_INDIRECT: *out += v - indirect[3 * i + c]; break;
            default: *out += v * divisor_albedo(albedo[3 * i + c]) - indirect[3 * i + c]; break;
            }
            *out = fmaxf(*out, 0.0f); /* rounding of the difference, never light taken away */
        }
}

/* Every tile again: its Combined pixels changed. */
static void deliver_all_tiles(render *r)
{
    pthread_mutex_lock(&r->lock);
    for (uint32_t t = 0; t < r->tile_count; t++)
        r->finished[r->finished_count++] = t;
    pthread_cond_broadcast(&r->finished_cond);
    pthread_mutex_unlock(&r->lock);
}

phos_status render_filter(render *r)
{
    film *f = &r->film;
    size_t pixels = (size_t)f->width * f->height;
    int whole_image = r->settings.filter_target == PHOS_FILTER_TARGET_ALL;
    float *source = malloc(sizeof(float) * 3 * pixels), *filtered = malloc(sizeof(float) * 3 * pixels);
    float *variance = whole_image ? malloc(sizeof(float) * pixels) : NULL;
    uint32_t *samples = malloc(sizeof(uint32_t) * pixels);
    phos_status st = PHOS_ERROR_OUT_OF_MEMORY;
    if (source && filtered && samples && (!whole_image || variance)) {
        filter_source(r, source);
        /* Only the whole image has its own variance: the moments are the
         * Combined pass's, and the filter estimates a component's from its
         * neighbourhood. */
        if (variance)
            mean_variances(f, variance);
        for (size_t i = 0; i < pixels; i++)
            samples[i] = f->sample_counts[i] & ~PIXEL_CONVERGED;
        image_filter_input in = {f->width, f->height, source, variance, samples,
                                 f->planes[PHOS_PASS_DENOISING_NORMAL], f->planes[PHOS_PASS_DENOISING_ALBEDO]};
        st = image_filter_apply(r->settings.noise_filter, &in, filtered, &r->cancel);
        if (st == PHOS_OK) {
            compose(r, filtered);
            deliver_all_tiles(r);
        }
    }
    free(source);
    free(filtered);
    free(variance);
    free(samples);
    return st;
}
