/*
 * photon_maps_file.c — the photon maps saved as they leave photon tracing
 * (the global and caustic photons, the radiance photons' sites, the paths
 * emitted) and read back in its place; the kd-trees and radiance photons
 * are then built from them as after tracing, so a render that reads the
 * file renders the same image (photon_maps_file.h; docs/cache_files.md).
 */
#include "cache/photon_maps_file.h"

#include <stdlib.h>
#include <string.h>

#include "cache/file_io.h"

#define PM_FILE_MAGIC "PHOSPMF\n"
#define PM_FILE_VERSION 3u /* 2: caustic_roughness; 3: sampler */
#define WHAT "photon map"
#define SITE_WORDS 9u   /* a radiance photon's site: position, normal, reflectance */

/* A photon as 5 words: position (3 floats), RGBE power (4 bytes, in
 * order), direction bytes and flags (theta | phi << 8 | flags << 16). */
static int write_photons(FILE *f, const photon_map *m)
{
    int ok = file_write_u32(f, m->count);
    for (uint32_t i = 0; ok && i < m->count; i++) {
        const photon *p = &m->photons[i];
        const uint8_t *e = p->power;
        ok = file_write_u32(f, file_float_bits(p->position[0])) && file_write_u32(f, file_float_bits(p->position[1])) &&
             file_write_u32(f, file_float_bits(p->position[2])) &&
             file_write_u32(f, (uint32_t)e[0] | (uint32_t)e[1] << 8 | (uint32_t)e[2] << 16 | (uint32_t)e[3] << 24) &&
             file_write_u32(f, (uint32_t)p->theta | (uint32_t)p->phi << 8 | (uint32_t)p->flags << 16);
    }
    return ok;
}

static const char *read_photons(FILE *f, photon_map *m)
{
    uint32_t count;
    if (!file_read_u32(f, &count) || count > PHOTON_MAP_MAX_PHOTONS)
        return "it ends before its photons";
    if (!photon_map_reserve(m, count))
        return "out of memory for its photons";
    for (uint32_t i = 0; i < count; i++) {
        uint32_t w[5];
        for (int k = 0; k < 5; k++)
            if (!file_read_u32(f, &w[k]))
                return "it ends before its last photon";
        photon p;
        for (int k = 0; k < 3; k++)
            p.position[k] = file_bits_float(w[k]);
        for (int k = 0; k < 4; k++)
            p.power[k] = (uint8_t)(w[3] >> (8 * k));
        p.theta = (uint8_t)w[4];
        p.phi = (uint8_t)(w[4] >> 8);
        p.flags = (uint16_t)(w[4] >> 16);
        if (!photon_map_append(m, &p, 1))
            return "it holds a photon that is not finite";
    }
    return NULL;
}

phos_status photon_maps_save(const photon_maps *maps, const scene *s, const photon_trace_settings *ps,
                             const char *path, char *msg, size_t msg_size)
{
    FILE *f = file_open(path, "wb", WHAT, msg, msg_size);
    if (!f)
        return PHOS_ERROR_INVALID_ARGUMENT;
    uint32_t settings[PHOTON_TRACE_SETTING_WORDS];
    photon_trace_settings_words(ps, settings);
    int ok = file_write_header(f, PM_FILE_MAGIC, PM_FILE_VERSION, s, settings, PHOTON_TRACE_SETTING_WORDS) &&
             file_write_u64(f, maps->global_emitted) && file_write_u64(f, maps->caustic_emitted) &&
             file_write_u32(f, maps->caustic_reused) && write_photons(f, &maps->global) &&
             write_photons(f, &maps->caustic) && file_write_u32(f, SITE_WORDS) &&
             file_write_u32(f, maps->radiance_site_count);
    for (uint64_t i = 0; ok && i < (uint64_t)SITE_WORDS * maps->radiance_site_count; i++)
        ok = file_write_u32(f, file_float_bits(maps->radiance_sites[i]));
    return file_finish_write(f, ok, path, WHAT, msg, msg_size);
}

phos_status photon_maps_load(photon_maps *maps, const scene *s, const photon_trace_settings *ps, const char *path,
                             char *msg, size_t msg_size)
{
    FILE *f = file_open(path, "rb", WHAT, msg, msg_size);
    if (!f)
        return PHOS_ERROR_INVALID_ARGUMENT;
    char detail[160];
    uint32_t settings[PHOTON_TRACE_SETTING_WORDS], words = 0, sites = 0;
    photon_trace_settings_words(ps, settings);
    const char *why = file_check_header(f, PM_FILE_MAGIC, PM_FILE_VERSION, WHAT, s, settings, photon_trace_setting_names,
                                        PHOTON_TRACE_SETTING_WORDS, detail, sizeof(detail));
    if (!why && (!file_read_u64(f, &maps->global_emitted) || !file_read_u64(f, &maps->caustic_emitted) ||
                 !file_read_u32(f, &maps->caustic_reused)))
        why = "it ends in its header";
    if (!why)
        why = read_photons(f, &maps->global);
    if (!why)
        why = read_photons(f, &maps->caustic);
    if (!why && (!file_read_u32(f, &words) || words != SITE_WORDS || !file_read_u32(f, &sites)))
        why = "its radiance sites do not match this version";
    if (!why && sites) {
        maps->radiance_sites = malloc(sizeof(float) * SITE_WORDS * sites);
        if (!maps->radiance_sites)
            why = "out of memory for its radiance sites";
        for (uint64_t i = 0; !why && i < (uint64_t)SITE_WORDS * sites; i++) {
            uint32_t w;
            if (!file_read_u32(f, &w))
                why = "it ends before its last radiance site";
            else
                maps->radiance_sites[i] = file_bits_float(w);
        }
        maps->radiance_site_count = why ? 0 : sites;
    }
    /* Whether they were aimed at a view is not saved: assume so, so that
     * maps kept from this render are not taken as view-independent. */
    maps->aimed_at_view = 1;
    photon_maps_note_short(maps, s, ps);
    return file_finish_read(f, why, path, WHAT, msg, msg_size);
}
