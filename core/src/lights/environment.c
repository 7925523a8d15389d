/*
 * environment.c — the varying world's radiance and its sampling
 * distribution over a latitude-longitude grid of cells (environment.h).
 */
#include "lights/environment.h"

#include <stdlib.h>
#include <string.h>

#include "lights/light_kind.h"
#include "sampling/warp.h"
#include "shading/material.h"
#include "shading/shader_program.h"
#include "shading/sky/sky.h"
#include "util/parallel.h"

#define BIN_COUNT (ENVIRONMENT_BINS * ENVIRONMENT_BINS)
#define MIN_ROWS 64
#define MIN_COLUMNS 128
/* A cell darker than this share of the mean keeps this much probability:
 * every direction that sends light can still be drawn, so photons, which
 * leave only by the distribution, stay unbiased where a cell's centre
 * missed a small bright feature (docs/algorithms.md §11). */
#define FLOOR_SHARE 1e-3f

static uint32_t round_up_bins(uint32_t n) { return (n + ENVIRONMENT_BINS - 1) / ENVIRONMENT_BINS * ENVIRONMENT_BINS; }

static uint32_t clamp_u32(uint32_t x, uint32_t lo, uint32_t hi) { return x < lo ? lo : x > hi ? hi : x; }

/* Cells for a world: a quarter of a pixel of the largest image its
 * program reads (an equirectangular map's rows then fall on its rows, and
 * its columns on its columns whatever a Mapping turns it by about Z), at
 * most ENVIRONMENT_MAX_ROWS × ENVIRONMENT_MAX_COLUMNS; 256 × 512 without an
 * image. Each cell is evaluated at its centre, a quarter pixel from the
 * pixel's: the bilinear lookup there already holds a quarter of the
 * neighbours' radiance, so a dark cell beside a bright pixel keeps a share
 * of it (cells one per pixel, read at pixel centres, left such cells a
 * thousandth of the radiance at their edge: fireflies). Measured on
 * Blender's studio HDRs, Phos's pixel variance over Cycles': 2.4 with a
 * cell per pixel and 2 × 2 points, 1.5 with these, 3.3 with cells of equal
 * solid angle that straddle pixels (docs/algorithms.md §11). */
void environment_resolution(const scene *s, const material *m, uint32_t *rows, uint32_t *columns)
{
    uint32_t width = 0, height = 0;
    for (uint32_t k = 0; m->has_program && k < m->program.instruction_count; k++) {
        const phos_shader_instruction *ins = &m->program.instructions[k];
        uint32_t id = ins->op == PHOS_OP_TEX_IMAGE ? ins->table : PHOS_SHADER_NO_REGISTER;
        if (ins->op == PHOS_OP_TEX_SKY && sky_model_textured(ins->mode))
            id = (uint32_t)m->program.table[ins->table + PHOS_SKY_DATA_IMAGE];
        if (id < s->image_count) {
            const image *img = &s->images[id];
            width = img->width > width ? img->width : width;
            height = img->height > height ? img->height : height;
        }
    }
    if (width == 0 || height == 0)
        width = 256, height = 128;
    *columns = clamp_u32(round_up_bins(2 * width), MIN_COLUMNS, ENVIRONMENT_MAX_COLUMNS);
    *rows = clamp_u32(round_up_bins(2 * height), MIN_ROWS, ENVIRONMENT_MAX_ROWS);
}

size_t environment_bytes(uint32_t rows, uint32_t columns)
{
    size_t cells = (size_t)rows * columns;
    /* The weights and the rows' cumulative shares (a float per cell each,
     * and one more per row), the marginal and the bins' rows (a float per
     * row each, and one more per table), and the build's radiance means
     * (a float per cell). */
    return sizeof(float) * (3 * cells + 3 * (size_t)rows + BIN_COUNT + 1);
}

/* --------------------------------------------------------------- cells */

static uint32_t bin_rows(const environment *e) { return e->rows / ENVIRONMENT_BINS; }
static uint32_t bin_columns(const environment *e) { return e->columns / ENVIRONMENT_BINS; }

/* Polar angle θ from +z and azimuth φ ∈ [0, 2π) from +x toward +y: the
 * grid's coordinates, (θ/π, φ/2π) in [0,1)². */
static float2 grid_of_direction(vec3 d)
{
    float phi = atan2f(d.y, d.x);
    if (phi < 0.0f)
        phi += 2.0f * PHOS_PI;
    float2 u = {clampf(acosf(clampf(d.z, -1.0f, 1.0f)) * PHOS_INV_PI, 0.0f, 0x1.fffffep-1f),
                clampf(phi * (0.5f * PHOS_INV_PI), 0.0f, 0x1.fffffep-1f)};
    return u;
}

static vec3 direction_of_grid(float2 u)
{
    float theta = PHOS_PI * u.x, phi = 2.0f * PHOS_PI * u.y;
    float st = sinf(theta);
    return v3(st * cosf(phi), st * sinf(phi), cosf(theta));
}

uint32_t environment_bin_of(vec3 d)
{
    float2 u = grid_of_direction(d);
    return (uint32_t)(u.x * ENVIRONMENT_BINS) * ENVIRONMENT_BINS + (uint32_t)(u.y * ENVIRONMENT_BINS);
}

vec3 environment_bin_direction(uint32_t bin, float2 at)
{
    float2 u = {((float)(bin / ENVIRONMENT_BINS) + at.x) / ENVIRONMENT_BINS,
                ((float)(bin % ENVIRONMENT_BINS) + at.y) / ENVIRONMENT_BINS};
    return direction_of_grid(u);
}

float environment_bin_solid_angle(uint32_t bin)
{
    float t0 = PHOS_PI * (float)(bin / ENVIRONMENT_BINS) / ENVIRONMENT_BINS, t1 = t0 + PHOS_PI / ENVIRONMENT_BINS;
    return 2.0f * PHOS_PI / ENVIRONMENT_BINS * (cosf(t0) - cosf(t1));
}

/* Direction at (s, t) ∈ [0,1)² within a cell: uniform in θ and φ. */
static vec3 cell_direction(const environment *e, uint32_t row, uint32_t column, float s, float t)
{
    float2 u = {((float)row + s) / (float)e->rows, ((float)column + t) / (float)e->columns};
    return direction_of_grid(u);
}

/* A cell's solid angle: Δφ (cos θ₀ − cos θ₁), sr. */
static float cell_solid_angle(const environment *e, uint32_t row)
{
    float t0 = PHOS_PI * (float)row / (float)e->rows, t1 = PHOS_PI * (float)(row + 1) / (float)e->rows;
    return 2.0f * PHOS_PI / (float)e->columns * (cosf(t0) - cosf(t1));
}

/* Density in solid angle at d of a cell of weight w drawn among cells of
 * total weight `total`, d uniform in θ and φ over the cell: the cell's
 * probability over its extent Δθ Δφ = 2π²/(rows · columns) times sin θ
 * (pbrt-v4's p(u, v) / (2π² sin θ)). */
static float cell_density(const environment *e, float w, double total, vec3 d)
{
    float sin_theta = safe_sqrtf(1.0f - d.z * d.z);
    if (!(sin_theta > 0.0f))
        return 0.0f;
    return (float)((double)w / total * (double)e->rows * (double)e->columns) /
           (2.0f * PHOS_PI * PHOS_PI * sin_theta);
}

/* Camera rays see the world as its program draws it: the sky's disc
 * too, which is a light of its own for every other ray (sky_sun.c). */
vec3 environment_radiance(const scene *s, const environment *e, vec3 d, uint32_t ray_flags)
{
    return material_background(s, e->mat, d, ray_flags | (ray_flags & SHADER_RAY_CAMERA ? 0u : e->ray_flags));
}

/* ---------------------------------------------------------------- build */

typedef struct build_job {
    const scene *s;
    const environment *e;
    float *luminance, *mean;    /* per cell, row-major */
} build_job;

/* One row of cells: the luminance (Rec. 709 Y) times the cell's solid
 * angle (the sampling weight: pbrt-v4's luminance × sin θ) and the
 * channel mean of the radiance times it, read at the cell's centre
 * (environment_resolution says why one point). */
static void build_row(void *ctx, uint32_t row, uint32_t thread)
{
    (void)thread;
    const build_job *job = ctx;
    const environment *e = job->e;
    float omega = cell_solid_angle(e, row);
    for (uint32_t column = 0; column < e->columns; column++) {
        vec3 L = environment_radiance(job->s, e, cell_direction(e, row, column, 0.5f, 0.5f), 0);
        size_t at = (size_t)row * e->columns + column;
        job->luminance[at] = (0.2126f * L.x + 0.7152f * L.y + 0.0722f * L.z) * omega;
        job->mean[at] = v3_average(L) * omega;
    }
}

void environment_free(environment *e)
{
    if (e->bin_rows)
        for (uint32_t b = 0; b < BIN_COUNT; b++)
            distribution_free(&e->bin_rows[b]);
    free(e->bin_rows);
    free(e->weight);
    free(e->row_cdf);
    distribution_free(&e->marginal);
    memset(e, 0, sizeof(*e));
}

/* Each row's cumulative shares, and the row weights (*row_weight, rows of
 * them). */
static void build_rows(environment *e, double *row_weight)
{
    for (uint32_t r = 0; r < e->rows; r++) {
        const float *w = e->weight + (size_t)r * e->columns;
        float *cdf = e->row_cdf + (size_t)r * (e->columns + 1);
        double sum = 0.0;
        for (uint32_t c = 0; c < e->columns; c++)
            sum += w[c];
        double below = 0.0;
        cdf[0] = 0.0f;
        for (uint32_t c = 0; c < e->columns; c++) {
            below += w[c];
            cdf[c + 1] = (float)(below / sum);
        }
        cdf[e->columns] = 1.0f;
        row_weight[r] = sum;
    }
}

/* The distributions from the cells' luminance, each cell kept at
 * FLOOR_SHARE of the mean at least (luminance becomes e->weight). */
static int build_distributions(environment *e, float *luminance)
{
    size_t n = (size_t)e->rows * e->columns;
    double total = 0.0;
    for (size_t i = 0; i < n; i++) {
        luminance[i] = isfinite(luminance[i]) ? fmaxf(luminance[i], 0.0f) : 0.0f;
        total += luminance[i];
    }
    /* The floor is per steradian, so a polar cell keeps a share of it
     * in proportion to its solid angle, as the luminance itself does. */
    float floor_per_sr = FLOOR_SHARE * (float)(total / (4.0 * PHOS_PI));
    e->total = 0.0;
    for (uint32_t r = 0; r < e->rows; r++) {
        float floor = floor_per_sr * cell_solid_angle(e, r);
        for (uint32_t c = 0; c < e->columns; c++) {
            float *w = &luminance[(size_t)r * e->columns + c];
            *w = fmaxf(*w, floor);
            e->total += *w;
        }
    }
    e->weight = luminance;
    e->row_cdf = malloc(sizeof(float) * e->rows * (e->columns + 1));
    double *row_weight = malloc(sizeof(double) * e->rows);
    float *in_bin = malloc(sizeof(float) * bin_rows(e));
    e->bin_rows = calloc(BIN_COUNT, sizeof(distribution));
    int ok = e->row_cdf && row_weight && in_bin && e->bin_rows;
    if (ok)
        build_rows(e, row_weight);
    float *marginal = ok ? malloc(sizeof(float) * e->rows) : NULL;
    ok = ok && marginal;
    for (uint32_t r = 0; ok && r < e->rows; r++)
        marginal[r] = (float)row_weight[r];
    ok = ok && distribution_build(&e->marginal, marginal, e->rows);
    /* A bin's rows weigh the bin's columns of each row. */
    uint32_t rb = bin_rows(e), cb = bin_columns(e);
    for (uint32_t b = 0; ok && b < BIN_COUNT; b++) {
        uint32_t r0 = (b / ENVIRONMENT_BINS) * rb, c0 = (b % ENVIRONMENT_BINS) * cb;
        double sum = 0.0;
        for (uint32_t k = 0; k < rb; k++) {
            const float *w = e->weight + (size_t)(r0 + k) * e->columns + c0;
            double row = 0.0;
            for (uint32_t c = 0; c < cb; c++)
                row += w[c];
            in_bin[k] = (float)row;
            sum += row;
        }
        e->bin_total[b] = sum;
        ok = distribution_build(&e->bin_rows[b], in_bin, rb);
    }
    free(marginal);
    free(row_weight);
    free(in_bin);
    return ok;
}

phos_status environment_build(environment *e, const scene *s, const material *m, uint32_t ray_flags,
                              uint32_t threads, int *zero)
{
    memset(e, 0, sizeof(*e));
    *zero = 1;
    e->mat = m;
    e->ray_flags = ray_flags;
    environment_resolution(s, m, &e->rows, &e->columns);
    size_t n = (size_t)e->rows * e->columns;
    float *luminance = malloc(sizeof(float) * n), *mean = malloc(sizeof(float) * n);
    phos_status st = PHOS_OK;
    if (!luminance || !mean) {
        st = PHOS_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    build_job job = {s, e, luminance, mean};
    if (!parallel_for(e->rows, parallel_thread_count(threads), build_row, &job, (atomic_int *)&s->cancel)) {
        st = atomic_load(&s->cancel) ? PHOS_ERROR_CANCELLED : PHOS_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    /* Bin by bin, in order: the sums do not depend on the threads. */
    uint32_t rb = bin_rows(e), cb = bin_columns(e);
    for (uint32_t b = 0; b < BIN_COUNT; b++) {
        uint32_t r0 = (b / ENVIRONMENT_BINS) * rb, c0 = (b % ENVIRONMENT_BINS) * cb;
        double sum = 0.0;
        for (uint32_t r = r0; r < r0 + rb; r++)
            for (uint32_t c = c0; c < c0 + cb; c++) {
                float x = mean[(size_t)r * e->columns + c];
                sum += isfinite(x) && x > 0.0f ? (double)x : 0.0;
            }
        e->bin_integral[b] = (float)sum; /* the means were weighted by solid angle */
        e->integral += sum;
    }
    *zero = !(e->integral > 0.0);
    if (!*zero) {
        if (build_distributions(e, luminance))
            luminance = NULL; /* e->weight now */
        else
            st = PHOS_ERROR_OUT_OF_MEMORY;
    }
done:
    free(luminance);
    free(mean);
    if (st != PHOS_OK || *zero) {
        double integral = e->integral;
        environment_free(e);
        e->mat = m;
        e->ray_flags = ray_flags;
        e->integral = integral;
    }
    return st;
}

/* ------------------------------------------------------------- sampling */

/* The column of row `row` whose cumulative share interval holds x, among
 * columns [c0, c1); *rest: where x falls within it, in [0, 1). */
static uint32_t row_column(const environment *e, uint32_t row, uint32_t c0, uint32_t c1, float x, float *rest)
{
    const float *cdf = e->row_cdf + (size_t)row * (e->columns + 1);
    uint32_t lo = c0, hi = c1; /* the last c with cdf[c] <= x */
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (cdf[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    while (lo + 1 < c1 && cdf[lo + 1] - cdf[lo] <= 0.0f)
        lo++;
    float width = cdf[lo + 1] - cdf[lo];
    *rest = width > 0.0f ? clampf((x - cdf[lo]) / width, 0.0f, 0x1.fffffep-1f) : 0.5f;
    return lo;
}

static float cell_weight(const environment *e, uint32_t row, uint32_t column)
{
    return e->weight[(size_t)row * e->columns + column];
}

vec3 environment_sample(const environment *e, float2 u, float *pdf)
{
    if (!e->weight) { /* a world of no power: nothing to draw (pilot photons still ask) */
        *pdf = 0.0f;
        return v3(0.0f, 0.0f, 1.0f);
    }
    float s, t;
    uint32_t row = distribution_sample(&e->marginal, u.x, NULL, &s);
    uint32_t column = row_column(e, row, 0, e->columns, u.y, &t);
    vec3 d = cell_direction(e, row, column, s, t);
    *pdf = cell_density(e, cell_weight(e, row, column), e->total, d);
    return d;
}

vec3 environment_sample_in_bin(const environment *e, uint32_t bin, float2 u, float *pdf)
{
    if (!e->weight) {
        float2 centre = {0.5f, 0.5f};
        *pdf = 0.0f;
        return environment_bin_direction(bin, centre);
    }
    uint32_t rb = bin_rows(e), cb = bin_columns(e);
    uint32_t r0 = (bin / ENVIRONMENT_BINS) * rb, c0 = (bin % ENVIRONMENT_BINS) * cb;
    float s, t;
    uint32_t row = r0 + distribution_sample(&e->bin_rows[bin], u.x, NULL, &s);
    const float *cdf = e->row_cdf + (size_t)row * (e->columns + 1);
    float x = cdf[c0] + u.y * (cdf[c0 + cb] - cdf[c0]);
    uint32_t column = row_column(e, row, c0, c0 + cb, x, &t);
    vec3 d = cell_direction(e, row, column, s, t);
    *pdf = cell_density(e, cell_weight(e, row, column), e->bin_total[bin], d);
    return d;
}

float environment_pdf(const environment *e, vec3 d)
{
    if (!e->weight)
        return 0.0f;
    float2 u = grid_of_direction(d);
    uint32_t row = (uint32_t)(u.x * (float)e->rows), column = (uint32_t)(u.y * (float)e->columns);
    row = row < e->rows ? row : e->rows - 1;
    column = column < e->columns ? column : e->columns - 1;
    return cell_density(e, cell_weight(e, row, column), e->total, d);
}

/* ------------------------------------------------------- the light kind */

void environment_destroy(environment *e)
{
    if (!e)
        return;
    environment_free(e);
    free(e);
}

phos_status light_environment_add(const scene *s, light_table *t, uint32_t *capacity, const material *world)
{
    environment *e = calloc(1, sizeof(environment));
    if (!e)
        return PHOS_ERROR_OUT_OF_MEMORY;
    int zero = 0, sun = 0;
    phos_status st = light_sky_sun_add(s, t, capacity, world, &sun);
    if (st == PHOS_OK)
        st = environment_build(e, s, world, sun ? SHADER_RAY_SKY_SUN_AS_LIGHT : 0, 0, &zero);
    if (st != PHOS_OK) {
        environment_destroy(e);
        return st;
    }
    /* A world that sends no light is still seen by camera rays (Light
     * Path's Is Camera Ray can show a background that lights nothing):
     * it stays in the table with no power, and is never picked. */
    t->env = e;
    light l;
    memset(&l, 0, sizeof(l));
    l.kind = LIGHT_ENVIRONMENT;
    l.color = v3s((float)(e->integral * PHOS_INV_4PI)); /* the mean radiance */
    t->world = (int32_t)t->count;
    return light_table_append(t, capacity, &l) ? PHOS_OK : PHOS_ERROR_OUT_OF_MEMORY;
}

static const environment *env_of(const scene *s) { return s->lights.env; }

/* ∫ L dω · πR²: each direction's radiance through the disk facing it. */
static float environment_power(const light *l, float scene_radius)
{
    return 4.0f * PHOS_PI * light_mean_color(l) * distant_disk_area(scene_radius);
}

static int environment_hittable(const light *l) { return (void)l, 1; }

static vec3 own_sample(const scene *s, const light_context *c, float2 u, float *pdf)
{
    (void)c;
    return environment_sample(env_of(s), u, pdf);
}

static float own_pdf(const scene *s, const light_context *c, vec3 wi)
{
    (void)c;
    return environment_pdf(env_of(s), wi);
}

static const world_sampling map_sampling = {own_sample, own_pdf};

static int environment_light_sample(const scene *s, const light *l, const light_context *c, float2 u,
                                    light_sample *out)
{
    (void)l;
    const environment *e = env_of(s);
    if (!e->weight || !portal_mix_sample(s, c, &map_sampling, u, &out->wi, &out->pdf))
        return 0;
    out->distance = INFINITY;
    out->radiance = environment_radiance(s, e, out->wi, 0);
    out->delta = 0;
    return out->pdf > 0.0f && !v3_is_zero(out->radiance);
}

/* Camera rays see the background as Light Path's Is Camera Ray says;
 * every other ray, and the light samples and photons, as a non-camera
 * ray: so the light sample and the rays it is weighted against agree. */
static int environment_escape(const scene *s, const light *l, const light_context *from, vec3 d, int camera_ray,
                              vec3 *radiance, float *pdf)
{
    (void)l;
    const environment *e = env_of(s);
    *radiance = environment_radiance(s, e, d, camera_ray ? SHADER_RAY_CAMERA : 0);
    *pdf = from && e->weight ? portal_mix_pdf(s, from, &map_sampling, d) : 0.0f;
    return 1;
}

/* A photon from a direction drawn from the map, starting on the disk that
 * faces it: Φ = L(ω)·πR² / p(ω). */
static int environment_emit(const scene *s, const light *l, float2 u_origin, float2 u_direction, vec3 *origin,
                            vec3 *direction, vec3 *flux)
{
    (void)l;
    const environment *e = env_of(s);
    if (!e->weight)
        return 0;
    float pdf;
    vec3 from = environment_sample(e, u_direction, &pdf);
    *direction = v3_neg(from);
    float area = distant_origin(&s->lights, *direction, u_origin, origin);
    *flux = v3_scale(environment_radiance(s, e, from, 0), area / pdf);
    return pdf > 0.0f;
}

const light_kind_ops light_environment_ops = {
    .name = "environment",
    .desc_type = -1,
    .power = environment_power,
    .hittable = environment_hittable,
    .sample = environment_light_sample,
    .escape = environment_escape,
    .emit = environment_emit,
};
