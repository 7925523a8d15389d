/*
 * irradiance_cache_file.c — reading and writing the irradiance cache
 * (irradiance_cache_file.h; the layout is in docs/cache_files.md).
 */
#include "cache/irradiance_cache_file.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cache/fingerprint.h"

#define IC_FILE_MAGIC "PHOSIRC\n"
#define IC_FILE_VERSION 1u
#define RECORD_WORDS 37u /* p, n, E, E_caustic, w_mean (3 each), grad_r, grad_t (9 each), R, R_free, R_lo, R_hi */

/* The settings a cache's records depend on, in file order. The camera and
 * the image size are not among them: records are world-space, and another
 * view reads them (where it sees what no record covers, it gathers). */
#define CACHE_SETTINGS(U, F)                                                                      \
    U(integrator) U(photon_view) U(seed) U(max_bounces) U(ic_rays) U(global_photons)              \
    U(caustic_photons) U(global_estimate_photons) U(max_photons_emitted_millions)                 \
    F(ic_accuracy) F(ic_min_spacing) F(ic_max_spacing) F(max_radius)
#define COUNT_SETTING(name) +1
#define CACHE_SETTING_COUNT (0 CACHE_SETTINGS(COUNT_SETTING, COUNT_SETTING))

/* ------------------------------------------------------ little-endian words */

static void put_u32(unsigned char *b, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        b[i] = (unsigned char)(v >> (8 * i));
}

static uint32_t get_u32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static uint32_t float_bits(float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    return v;
}

static float bits_float(uint32_t v)
{
    float f;
    memcpy(&f, &v, 4);
    return f;
}

static int write_u32(FILE *f, uint32_t v)
{
    unsigned char b[4];
    put_u32(b, v);
    return fwrite(b, 1, 4, f) == 4;
}

static int read_u32(FILE *f, uint32_t *v)
{
    unsigned char b[4];
    if (fread(b, 1, 4, f) != 4)
        return 0;
    *v = get_u32(b);
    return 1;
}

static int write_u64(FILE *f, uint64_t v) { return write_u32(f, (uint32_t)v) && write_u32(f, (uint32_t)(v >> 32)); }

static int read_u64(FILE *f, uint64_t *v)
{
    uint32_t lo, hi;
    if (!read_u32(f, &lo) || !read_u32(f, &hi))
        return 0;
    *v = (uint64_t)hi << 32 | lo;
    return 1;
}

/* ------------------------------------------------------------ settings */

static void settings_words(const phos_render_settings *rs, uint32_t *w)
{
    uint32_t n = 0;
#define SETTING_U(name) w[n++] = rs->name;
#define SETTING_F(name) w[n++] = float_bits(rs->name);
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
            w[n++] = float_bits(v[k][c]);
    for (int g = 0; g < 2; g++)
        for (int ch = 0; ch < 3; ch++) {
            const vec3 *d = g ? &r->grad_t[ch] : &r->grad_r[ch];
            w[n++] = float_bits(d->x);
            w[n++] = float_bits(d->y);
            w[n++] = float_bits(d->z);
        }
    w[n++] = float_bits(r->R);
    w[n++] = float_bits(r->R_free);
    w[n++] = float_bits(r->R_lo);
    w[n++] = float_bits(r->R_hi);
}

static void words_record(const uint32_t *w, irradiance_record *r)
{
    memset(r, 0, sizeof(*r));
    float *v[] = {&r->p.x, &r->n.x, &r->E.x, &r->E_caustic.x, &r->w_mean.x};
    uint32_t n = 0;
    for (int k = 0; k < 5; k++)
        for (int c = 0; c < 3; c++)
            v[k][c] = bits_float(w[n++]);
    for (int g = 0; g < 2; g++)
        for (int ch = 0; ch < 3; ch++) {
            vec3 *d = g ? &r->grad_t[ch] : &r->grad_r[ch];
            d->x = bits_float(w[n++]);
            d->y = bits_float(w[n++]);
            d->z = bits_float(w[n++]);
        }
    r->R = bits_float(w[n++]);
    r->R_free = bits_float(w[n++]);
    r->R_lo = bits_float(w[n++]);
    r->R_hi = bits_float(w[n++]);
}

_Static_assert(RECORD_WORDS == 5 * 3 + 2 * 9 + 4, "the record layout of docs/cache_files.md");

/* ---------------------------------------------------------- save, load */

phos_status irradiance_cache_save(const irradiance_cache *c, const scene *s, const phos_render_settings *rs,
                                  const char *path, char *msg, size_t msg_size)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        snprintf(msg, msg_size, "cannot write the irradiance cache file %s: %s", path, strerror(errno));
        return PHOS_ERROR_INVALID_ARGUMENT;
    }
    scene_fingerprint fp = scene_fingerprint_of(s);
    uint32_t settings[CACHE_SETTING_COUNT];
    settings_words(rs, settings);
    int ok = fwrite(IC_FILE_MAGIC, 1, 8, f) == 8 && write_u32(f, IC_FILE_VERSION) && write_u64(f, fp.geometry) &&
             write_u64(f, fp.materials) && write_u64(f, fp.lights) && write_u32(f, CACHE_SETTING_COUNT);
    for (uint32_t i = 0; ok && i < CACHE_SETTING_COUNT; i++)
        ok = write_u32(f, settings[i]);
    ok = ok && write_u32(f, RECORD_WORDS) && write_u32(f, c->count);
    for (uint32_t i = 0; ok && i < c->count; i++) {
        uint32_t w[RECORD_WORDS];
        record_words(&c->records[i], w);
        for (uint32_t k = 0; ok && k < RECORD_WORDS; k++)
            ok = write_u32(f, w[k]);
    }
    if (fclose(f) != 0)
        ok = 0;
    if (!ok) {
        snprintf(msg, msg_size, "could not write all of the irradiance cache file %s", path);
        return PHOS_ERROR_INVALID_ARGUMENT;
    }
    return PHOS_OK;
}

/* What differs between the file's header and this render, or NULL. */
static const char *header_mismatch(FILE *f, const scene *s, const phos_render_settings *rs, char *detail,
                                   size_t detail_size)
{
    char magic[8];
    uint32_t version = 0, count;
    if (fread(magic, 1, 8, f) != 8 || memcmp(magic, IC_FILE_MAGIC, 8) != 0)
        return "it is not a Phos irradiance cache file";
    if (!read_u32(f, &version) || version != IC_FILE_VERSION) {
        snprintf(detail, detail_size, "it is of format version %u, this Phos reads version %u", version,
                 IC_FILE_VERSION);
        return detail;
    }
    scene_fingerprint fp = scene_fingerprint_of(s), file;
    if (!read_u64(f, &file.geometry) || !read_u64(f, &file.materials) || !read_u64(f, &file.lights))
        return "it ends in its header";
    if (file.geometry != fp.geometry)
        return "it was made for other geometry (meshes or their placement differ)";
    if (file.materials != fp.materials)
        return "it was made for other materials (closures or images differ)";
    if (file.lights != fp.lights)
        return "it was made for other lights (lamps or the world differ)";
    if (!read_u32(f, &count) || count != CACHE_SETTING_COUNT)
        return "its settings block does not match this version";
    uint32_t mine[CACHE_SETTING_COUNT];
    settings_words(rs, mine);
    for (uint32_t i = 0; i < CACHE_SETTING_COUNT; i++) {
        uint32_t v;
        if (!read_u32(f, &v))
            return "it ends in its header";
        if (v != mine[i]) {
            snprintf(detail, detail_size, "it was made with another %s", setting_names[i]);
            return detail;
        }
    }
    return NULL;
}

phos_status irradiance_cache_load(irradiance_cache *c, const scene *s, const phos_render_settings *rs,
                                  const char *path, char *msg, size_t msg_size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(msg, msg_size, "cannot read the irradiance cache file %s: %s", path, strerror(errno));
        return PHOS_ERROR_INVALID_ARGUMENT;
    }
    char detail[160];
    const char *why = header_mismatch(f, s, rs, detail, sizeof(detail));
    uint32_t words = 0, count = 0;
    if (!why && (!read_u32(f, &words) || words != RECORD_WORDS || !read_u32(f, &count)))
        why = "its record block does not match this version";
    phos_status st = PHOS_OK;
    for (uint32_t i = 0; !why && i < count; i++) {
        uint32_t w[RECORD_WORDS];
        for (uint32_t k = 0; !why && k < RECORD_WORDS; k++)
            if (!read_u32(f, &w[k]))
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
    fclose(f);
    if (why) {
        snprintf(msg, msg_size, "the irradiance cache file %s is not used: %s", path, why);
        return st != PHOS_OK ? st : PHOS_ERROR_INVALID_ARGUMENT;
    }
    return PHOS_OK;
}
