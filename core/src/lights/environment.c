/*
 * environment.c — the varying world's radiance and its sampling
 * distribution over equal-area cells (environment.h).
 */
#include "lights/environment.h"

#include <stdlib.h>
#include <string.h>

#include "lights/light_kind.h"
#include "sampling/warp.h"
#include "shading/material.h"
#include "shading/shader_program.h"
#include "util/parallel.h"

#define BIN_COUNT (ENVIRONMENT_BINS * ENVIRONMENT_BINS)
#define MIN_ROWS 64
#define MIN_COLUMNS 128
/* A cell darker than this share of the mean keeps this much probability:
 * every direction that sends light can still be drawn, so photons, which
 * leave only by the distribution, stay unbiased where a cell's four
 * points missed a small bright feature (docs/algorithms.md §11). */
#define FLOOR_SHARE 1e-3f

static uint32_t round_up_bins(uint32_t n) { return (n + ENVIRONMENT_BINS - 1) / ENVIRONMENT_BINS * ENVIRONMENT_BINS; }

static uint32_t clamp_u32(uint32_t x, uint32_t lo, uint32_t hi) { return x < lo ? lo : x > hi ? hi : x; }

void environment_resolution(const scene *s, const material *m, uint32_t *rows, uint32_t *columns)
{
    uint32_t width = 0, height = 0;
    for (uint32_t k = 0; m->has_program && k < m->program.instruction_count; k++) {
        const phos_shader_instruction *ins = &m->program.instructions[k];
        if (ins->op == PHOS_OP_TEX_IMAGE && ins->table < s->image_count) {
            const image *img = &s->images[ins->table];
            width = img->width > width ? img->width : width;
            height = img->height > height ? img->height : height;
        }
    }
    /* An equirectangular map's pixel at the horizon spans 2π/W by π/H; a
     * cell 2π/columns by 2/rows. Matching the widths and keeping the
     * count near the pixels': columns ≈ W, rows ≈ 2H/π. */
    *columns = clamp_u32(round_up_bins(width), MIN_COLUMNS, ENVIRONMENT_MAX_COLUMNS);
    *rows = clamp_u32(round_up_bins((uint32_t)(0.6366f * (float)height)), MIN_ROWS, ENVIRONMENT_MAX_ROWS);
}

size_t environment_bytes(uint32_t rows, uint32_t columns)
{
    size_t cells = (size_t)rows * columns;
    /* The cumulative tables (one float per cell and bin, plus one per
     * table), and the build's two floats per cell. */
    return sizeof(float) * (cells + 2 * BIN_COUNT + 1) + 2 * sizeof(float) * cells;
}

/* --------------------------------------------------------------- cells */

typedef struct cell_index {
    uint32_t bin, local;
} cell_index;

static uint32_t bin_rows(const environment *e) { return e->rows / ENVIRONMENT_BINS; }
static uint32_t bin_columns(const environment *e) { return e->columns / ENVIRONMENT_BINS; }

static cell_index index_of_cell(const environment *e, uint32_t row, uint32_t column)
{
    uint32_t br = bin_rows(e), bc = bin_columns(e);
    cell_index c = {(row / br) * ENVIRONMENT_BINS + column / bc, (row % br) * bc + column % bc};
    return c;
}

static void cell_of_index(const environment *e, cell_index c, uint32_t *row, uint32_t *column)
{
    uint32_t br = bin_rows(e), bc = bin_columns(e);
    *row = (c.bin / ENVIRONMENT_BINS) * br + c.local / bc;
    *column = (c.bin % ENVIRONMENT_BINS) * bc + c.local % bc;
}

/* The point (u along z, v along φ) of warp_uniform_sphere's square a
 * direction maps to. */
static float2 square_of_direction(vec3 d)
{
    float phi = atan2f(d.y, d.x);
    if (phi < 0.0f)
        phi += 2.0f * PHOS_PI;
    float2 u = {clampf(0.5f * (1.0f - d.z), 0.0f, 0x1.fffffep-1f),
                clampf(phi * (0.5f * PHOS_INV_PI), 0.0f, 0x1.fffffep-1f)};
    return u;
}

uint32_t environment_bin_of(vec3 d)
{
    float2 u = square_of_direction(d);
    return (uint32_t)(u.x * ENVIRONMENT_BINS) * ENVIRONMENT_BINS + (uint32_t)(u.y * ENVIRONMENT_BINS);
}

float2 environment_bin_corner(uint32_t bin)
{
    float2 u = {(float)(bin / ENVIRONMENT_BINS) / ENVIRONMENT_BINS, (float)(bin % ENVIRONMENT_BINS) / ENVIRONMENT_BINS};
    return u;
}

/* Direction at (s, t) ∈ [0,1)² within a cell. */
static vec3 cell_direction(const environment *e, uint32_t row, uint32_t column, float s, float t)
{
    float2 u = {((float)row + s) / (float)e->rows, ((float)column + t) / (float)e->columns};
    return warp_uniform_sphere(u);
}

/* Density in solid angle of a cell drawn with probability p: its area is
 * 4π / (rows · columns). */
static float cell_density(const environment *e, float p)
{
    return p * (float)e->rows * (float)e->columns * PHOS_INV_4PI;
}

vec3 environment_radiance(const scene *s, const environment *e, vec3 d, uint32_t ray_flags)
{
    return material_background(s, e->mat, d, ray_flags);
}

/* ---------------------------------------------------------------- build */

typedef struct build_job {
    const scene *s;
    const environment *e;
    float *luminance, *mean;    /* per cell, bin-major (bin · cells per bin + local) */
} build_job;

/* One row of cells: the luminance (Rec. 709 Y) and the channel mean of
 * the radiance, each the average of a 2 × 2 grid of points in the cell. */
static void build_row(void *ctx, uint32_t row, uint32_t thread)
{
    (void)thread;
    const build_job *job = ctx;
    const environment *e = job->e;
    uint32_t per_bin = bin_rows(e) * bin_columns(e);
    for (uint32_t column = 0; column < e->columns; column++) {
        vec3 sum = v3s(0.0f);
        for (int k = 0; k < 4; k++) {
            vec3 d = cell_direction(e, row, column, 0.25f + 0.5f * (float)(k & 1), 0.25f + 0.5f * (float)(k >> 1));
            sum = v3_add(sum, environment_radiance(job->s, e, d, 0));
        }
        vec3 L = v3_scale(sum, 0.25f);
        cell_index c = index_of_cell(e, row, column);
        size_t at = (size_t)c.bin * per_bin + c.local;
        job->luminance[at] = 0.2126f * L.x + 0.7152f * L.y + 0.0722f * L.z;
        job->mean[at] = v3_average(L);
    }
}

void environment_free(environment *e)
{
    if (e->cells)
        for (uint32_t b = 0; b < BIN_COUNT; b++)
            distribution_free(&e->cells[b]);
    free(e->cells);
    distribution_free(&e->bins);
    memset(e, 0, sizeof(*e));
}

/* The bins' and cells' distributions from the cells' luminance, each cell
 * kept at FLOOR_SHARE of the mean at least. */
static int build_distributions(environment *e, float *luminance)
{
    uint32_t per_bin = bin_rows(e) * bin_columns(e);
    size_t n = (size_t)per_bin * BIN_COUNT;
    double total = 0.0;
    for (size_t i = 0; i < n; i++) {
        luminance[i] = isfinite(luminance[i]) ? fmaxf(luminance[i], 0.0f) : 0.0f;
        total += luminance[i];
    }
    float floor = FLOOR_SHARE * (float)(total / (double)n);
    float bin_weight[BIN_COUNT];
    e->cells = calloc(BIN_COUNT, sizeof(distribution));
    if (!e->cells)
        return 0;
    for (uint32_t b = 0; b < BIN_COUNT; b++) {
        float *w = luminance + (size_t)b * per_bin;
        double sum = 0.0;
        for (uint32_t k = 0; k < per_bin; k++) {
            w[k] = fmaxf(w[k], floor);
            sum += w[k];
        }
        bin_weight[b] = (float)sum;
        if (!distribution_build(&e->cells[b], w, per_bin))
            return 0;
    }
    return distribution_build(&e->bins, bin_weight, BIN_COUNT);
}

phos_status environment_build(environment *e, const scene *s, const material *m, uint32_t threads, int *zero)
{
    memset(e, 0, sizeof(*e));
    *zero = 1;
    e->mat = m;
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
    uint32_t per_bin = bin_rows(e) * bin_columns(e);
    float cell_omega = 4.0f * PHOS_PI / (float)n;
    for (uint32_t b = 0; b < BIN_COUNT; b++) {
        double sum = 0.0;
        for (uint32_t k = 0; k < per_bin; k++) {
            float x = mean[(size_t)b * per_bin + k];
            sum += isfinite(x) && x > 0.0f ? (double)x : 0.0;
        }
        e->bin_integral[b] = (float)(sum * cell_omega);
        e->integral += sum * cell_omega;
    }
    *zero = !(e->integral > 0.0);
    if (!*zero && !build_distributions(e, luminance))
        st = PHOS_ERROR_OUT_OF_MEMORY;
done:
    free(luminance);
    free(mean);
    if (st != PHOS_OK || *zero) {
        environment_free(e);
        e->mat = m;
    }
    return st;
}

/* ------------------------------------------------------------- sampling */

static vec3 sample_cell(const environment *e, uint32_t bin, float2 u, float *p_in_bin)
{
    float ux;
    cell_index c = {bin, distribution_sample(&e->cells[bin], u.x, p_in_bin, &ux)};
    uint32_t row, column;
    cell_of_index(e, c, &row, &column);
    return cell_direction(e, row, column, ux, u.y);
}

vec3 environment_sample(const environment *e, float2 u, float *pdf)
{
    float p_bin, p_cell;
    uint32_t bin = distribution_sample(&e->bins, u.x, &p_bin, &u.x);
    vec3 d = sample_cell(e, bin, u, &p_cell);
    *pdf = cell_density(e, p_bin * p_cell);
    return d;
}

vec3 environment_sample_in_bin(const environment *e, uint32_t bin, float2 u, float *pdf)
{
    float p_cell;
    vec3 d = sample_cell(e, bin, u, &p_cell);
    *pdf = cell_density(e, p_cell);
    return d;
}

float environment_pdf(const environment *e, vec3 d)
{
    if (!e->cells)
        return 0.0f;
    float2 u = square_of_direction(d);
    uint32_t row = (uint32_t)(u.x * (float)e->rows), column = (uint32_t)(u.y * (float)e->columns);
    row = row < e->rows ? row : e->rows - 1;
    column = column < e->columns ? column : e->columns - 1;
    cell_index c = index_of_cell(e, row, column);
    return cell_density(e, distribution_pdf(&e->bins, c.bin) * distribution_pdf(&e->cells[c.bin], c.local));
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
    int zero = 0;
    phos_status st = environment_build(e, s, world, 0, &zero);
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

static int environment_light_sample(const scene *s, const light *l, const light_context *c, float2 u,
                                    light_sample *out)
{
    (void)l, (void)c;
    const environment *e = env_of(s);
    if (!e->cells)
        return 0;
    out->wi = environment_sample(e, u, &out->pdf);
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
    *pdf = from ? environment_pdf(e, d) : 0.0f;
    return 1;
}

/* A photon from a direction drawn from the map, starting on the disk that
 * faces it: Φ = L(ω)·πR² / p(ω). */
static int environment_emit(const scene *s, const light *l, float2 u_origin, float2 u_direction, vec3 *origin,
                            vec3 *direction, vec3 *flux)
{
    (void)l;
    const environment *e = env_of(s);
    if (!e->cells)
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
