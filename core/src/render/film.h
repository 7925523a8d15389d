/*
 * film.h — the image being rendered: one float plane per enabled pass over
 * the render region, and the pixel filter used to place samples.
 */
#ifndef PHOS_FILM_H
#define PHOS_FILM_H

#include "phos.h"

#define PIXEL_FILTER_TABLE_SIZE 1024

typedef struct film {
    uint32_t x0, y0, width, height;   /* region in full-frame pixels */
    uint32_t pass_mask;
    float *planes[PHOS_PASS_COUNT];   /* width*height*channels each, or NULL if disabled */
    /* Progressive refinement: the running sums of the samples so far, in
     * double, of each enabled pass that is a mean over samples, so that a
     * pixel rendered in several passes sums exactly what one pass sums
     * (NULL: one pass, the sums stay on the stack). */
    double *sums[PHOS_PASS_COUNT];
    /* Samples each pixel has so far, PIXEL_CONVERGED set once adaptive
     * sampling stopped it (differing counts: adaptive sampling, the time
     * limit). */
    uint32_t *sample_counts;
    /* Per pixel, the sum of its samples' luminance and of its square, for
     * adaptive sampling's error and the noise filters' variance (NULL when
     * neither is on). */
    double *moments;
    /* Per pixel, the sum of its first samples' caustic-map estimates
     * (integrator_settings.caustic_reads), kept between passes (NULL when
     * the render does not read the caustic map on a share of samples, or
     * renders in one pass). */
    double *caustic_reads;
} film;

#define PIXEL_CONVERGED 0x80000000u

/* What a film keeps besides its pass planes. */
enum film_extras {
    FILM_KEEP_SUMS = 1,  /* the sums of mean passes, for progressive refinement */
    FILM_MOMENTS = 2,    /* film.moments */
    FILM_CAUSTIC_READS = 4 /* film.caustic_reads (with FILM_KEEP_SUMS) */
};

/* Whether a pass is the mean of a pixel's samples (the photon and record
 * dots are drawn once instead; the sample count and the noisy image are
 * written by the render loop and the filter). */
static inline int film_pass_is_sample_mean(uint32_t pass)
{
    return pass != PHOS_PASS_PHOTONS && pass != PHOS_PASS_IRRADIANCE_CACHE && pass != PHOS_PASS_SAMPLE_COUNT &&
           pass != PHOS_PASS_NOISY_IMAGE;
}

/* Bytes film_create allocates for these passes and extras (enum film_extras). */
uint64_t film_memory_bytes(uint32_t width, uint32_t height, uint32_t pass_mask, uint32_t extras);
/* Returns 0 when memory is exhausted. */
int film_create(film *f, uint32_t x0, uint32_t y0, uint32_t width, uint32_t height, uint32_t pass_mask,
                uint32_t extras);
void film_free(film *f);

/* The channels of pixel (x, y) (full-frame coordinates) of a pass. */
static inline float *film_pixel(const film *f, uint32_t pass, uint32_t x, uint32_t y)
{
    return f->planes[pass] + ((size_t)(y - f->y0) * f->width + (x - f->x0)) * phos_pass_channels(pass);
}

/* Index of pixel (x, y) (full-frame coordinates) in the film's per-pixel arrays. */
static inline size_t film_index(const film *f, uint32_t x, uint32_t y)
{
    return (size_t)(y - f->y0) * f->width + (x - f->x0);
}

/* The running sums of pixel (x, y) of a pass (film.sums[pass] not NULL). */
static inline double *film_sums(const film *f, uint32_t pass, uint32_t x, uint32_t y)
{
    return f->sums[pass] + ((size_t)(y - f->y0) * f->width + (x - f->x0)) * phos_pass_channels(pass);
}

/* Importance sampling of a separable pixel filter (Cycles' approach: every
 * sample weighs the same and lands where the filter puts it, so a pixel is
 * the plain mean of its samples and tiles never share pixels). */
typedef struct pixel_filter {
    float width;                         /* Blackman-Harris support is ±width pixels */
    float table[PIXEL_FILTER_TABLE_SIZE];/* inverse CDF: u → offset in pixels */
} pixel_filter;

void pixel_filter_init(pixel_filter *pf, float width);
/* Offset from the pixel centre, in pixels, for u in [0,1). */
float pixel_filter_sample(const pixel_filter *pf, float u);

#endif /* PHOS_FILM_H */
