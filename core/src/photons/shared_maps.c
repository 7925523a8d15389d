/*
 * shared_maps.c — photon maps shared between renders (shared_maps.h).
 */
#include "photons/shared_maps.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

shared_maps *shared_maps_create(void)
{
    shared_maps *m = calloc(1, sizeof(shared_maps));
    if (!m)
        return NULL;
    atomic_init(&m->refcount, 1);
    photon_maps_init(&m->maps);
    return m;
}

void shared_maps_retain(shared_maps *m) { atomic_fetch_add(&m->refcount, 1); }

void shared_maps_release(shared_maps *m)
{
    if (!m || atomic_fetch_sub(&m->refcount, 1) != 1)
        return;
    photon_maps_free(&m->maps);
    free(m);
}

void shared_maps_seal(shared_maps *m, const scene *s, const photon_trace_settings *ps, int has_radiance)
{
    m->scene_id = s->id;
    m->scene_version = s->version;
    photon_trace_settings_words(ps, m->settings);
    m->has_radiance = has_radiance;
    m->camera = s->camera;
}

const char *shared_maps_mismatch(const shared_maps *m, const scene *s, const photon_trace_settings *ps,
                                 int needs_radiance, int any_view, char *detail, size_t detail_size)
{
    if (m->scene_id != s->id)
        return "they were made for another scene";
    if (m->scene_version != s->version)
        return "the scene has changed since they were made (geometry, materials or lights)";
    uint32_t words[PHOTON_TRACE_SETTING_WORDS];
    photon_trace_settings_words(ps, words);
    for (uint32_t i = 0; i < PHOTON_TRACE_SETTING_WORDS; i++)
        if (words[i] != m->settings[i]) {
            snprintf(detail, detail_size, "they were made with another %s", photon_trace_setting_names[i]);
            return detail;
        }
    if (needs_radiance && !m->has_radiance)
        return "they hold no radiance photons (made for another Indirect Light than final gathering)";
    /* Byte equality: the same description puts every pilot ray where it was. */
    if (!any_view && m->maps.aimed_at_view && memcmp(&m->camera, &s->camera, sizeof(s->camera)) != 0)
        return "their photons were aimed at, or left out for, another view";
    return NULL;
}
