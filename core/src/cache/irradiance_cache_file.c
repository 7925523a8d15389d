/*
 * irradiance_cache_file.c — reading and writing the irradiance cache
 * (irradiance_cache_file.h; the layout is in docs/cache_files.md).
 */
#include "cache/irradiance_cache_file.h"

#include <stdio.h>
#include <string.h>

#include "cache/file_io.h"

#define IC_FILE_MAGIC "PHOSIRC\n"
#define IC_FILE_VERSION 4u /* 2: caustic_roughness; 3: sampler; 4: records from estimates clipped at walls */
#define WHAT "irradiance cache"
#define RECORD_WORDS 37u /* p, n, E, E_caustic, w_mean (3 each), grad_r, grad_t (9 each), R, R_free, R_lo, R_hi */

/* The settings a cache's records depend on, in file order. The camera and
 * the image size are not among them: records are world-space, and another
 * view reads them (where it sees what no record covers, it gathers). */
#define CACHE_SETTINGS(U, F)                                                                      \
    U(integrator) U(photon_view) U(seed) U(sampler) U(max_bounces) U(ic_rays) U(global_photons)              \
    U(caustic_photons) U(global_estimate_photons) U(max_photons_emitted_millions)                 \
    F(ic_accuracy) F(ic_min_spacing) F(ic_max_spacing) F(max_radius) F(caustic_roughness)
#define COUNT_SETTING(name) +1
#define CACHE_SETTING_COUNT (0 CACHE_SETTINGS(COUNT_SETTING, COUNT_SETTING))

/* ------------------------------------------------------------ settings */

static void settings_words(const phos_render_settings *rs, uint32_t *w)
{
    uint32_t n = 0;
#define SETTING_U(name) w[n++] = rs->name;
#define SETTING_F(name) w[n++] = file_float_bits(rs->name);
    CACHE_SETTINGS(SETTING_U, SETTING_F)
#undef SETTING_U
#undef SETTING_F
}

static const char *const setting_names[CACHE_SETTING_COUNT] = {
#define SETTING_NAME(name) #name,
    CACHE_SETTINGS(SETTING_NAME, SETTING_NAME)
#undef SETTING_NAME
};

/* -------------------------------------------------------------- records */

static void record_words(const irradiance_record *r, uint32_t *w)
{
    const float *v[] = {&r->p.x, &r->n.x, &r->E.x, &r->E_caustic.x, &r->w_mean.x};
    uint32_t n = 0;
    for (int k = 0; k < 5; k++)
        for (int c = 0; c < 3; c++)
            w[n++] = file_float_bits(v[k][c]);
    for (int g = 0; g < 2; g++)
        for (int ch = 0; ch < 3; ch++) {
            const vec3 *d = g ? &r->grad_t[ch] : &r->grad_r[ch];
            w[n++] = file_float_bits(d->x);
            w[n++] = file_float_bits(d->y);
            w[n++] = file_float_bits(d->z);
        }
    w[n++] = file_float_bits(r->R);
    w[n++] = file_float_bits(r->R_free);
    w[n++] = file_float_bits(r->R_lo);
    w[n++] = file_float_bits(r->R_hi);
}

static void words_record(const uint32_t *w, irradiance_record *r)
{
    memset(r, 0, sizeof(*r));
    float *v[] = {&r->p.x, &r->n.x, &r->E.x, &r->E_caustic.x, &r->w_mean.x};
    uint32_t n = 0;
    for (int k = 0; k < 5; k++)
        for (int c = 0; c < 3; c++)
            v[k][c] = file_bits_float(w[n++]);
    for (int g = 0; g < 2; g++)
        for (int ch = 0; ch < 3; ch++) {
            vec3 *d = g ? &r->grad_t[ch] : &r->grad_r[ch];
            d->x = file_bits_float(w[n++]);
            d->y = file_bits_float(w[n++]);
            d->z = file_bits_float(w[n++]);
        }
    r->R = file_bits_float(w[n++]);
    r->R_free = file_bits_float(w[n++]);
    r->R_lo = file_bits_float(w[n++]);
    r->R_hi = file_bits_float(w[n++]);
}

_Static_assert(RECORD_WORDS == 5 * 3 + 2 * 9 + 4, "the record layout of docs/cache_files.md");

/* ---------------------------------------------------------- save, load */

phos_status irradiance_cache_save(const irradiance_cache *c, const scene *s, const phos_render_settings *rs,
                                  const char *path, char *msg, size_t msg_size)
{
    FILE *f = file_open(path, "wb", WHAT, msg, msg_size);
    if (!f)
        return PHOS_ERROR_INVALID_ARGUMENT;
    uint32_t settings[CACHE_SETTING_COUNT];
    settings_words(rs, settings);
    int ok = file_write_header(f, IC_FILE_MAGIC, IC_FILE_VERSION, s, settings, CACHE_SETTING_COUNT);
    ok = ok && file_write_u32(f, RECORD_WORDS) && file_write_u32(f, c->count);
    for (uint32_t i = 0; ok && i < c->count; i++) {
        uint32_t w[RECORD_WORDS];
        record_words(&c->records[i], w);
        for (uint32_t k = 0; ok && k < RECORD_WORDS; k++)
            ok = file_write_u32(f, w[k]);
    }
    return file_finish_write(f, ok, path, WHAT, msg, msg_size);
}

phos_status irradiance_cache_load(irradiance_cache *c, const scene *s, const phos_render_settings *rs,
                                  const char *path, char *msg, size_t msg_size)
{
    FILE *f = file_open(path, "rb", WHAT, msg, msg_size);
    if (!f)
        return PHOS_ERROR_INVALID_ARGUMENT;
    char detail[160];
    uint32_t settings[CACHE_SETTING_COUNT];
    settings_words(rs, settings);
    const char *why = file_check_header(f, IC_FILE_MAGIC, IC_FILE_VERSION, WHAT, s, settings,
                                        setting_names, CACHE_SETTING_COUNT, detail, sizeof(detail));
    uint32_t words = 0, count = 0;
    if (!why && (!file_read_u32(f, &words) || words != RECORD_WORDS || !file_read_u32(f, &count)))
        why = "its record block does not match this version";
    phos_status st = PHOS_OK;
    for (uint32_t i = 0; !why && i < count; i++) {
        uint32_t w[RECORD_WORDS];
        for (uint32_t k = 0; !why && k < RECORD_WORDS; k++)
            if (!file_read_u32(f, &w[k]))
                why = "it ends before its last record";
        irradiance_record r;
        if (!why) {
            words_record(w, &r);
            if (!irradiance_cache_place(c, &r)) {
                st = PHOS_ERROR_OUT_OF_MEMORY;
                why = "out of memory";
            }
        }
    }
    phos_status read = file_finish_read(f, why, path, WHAT, msg, msg_size);
    return st != PHOS_OK ? st : read;
}
