/*
 * sky_sun.c — the Sky Texture's sun as a light of its own
 * (docs/algorithms.md §11.1).
 *
 * The scattering skies draw the sun as a disc of 0.5° or so whose
 * radiance is some 10⁵ times the sky's. The environment map's cells are
 * 0.7° (Blender 4's texture) or 0.35° (Blender 5's) and each is read at
 * its centre, so drawn from the map the disc would be found by chance:
 * the direct light of a sunlit scene would be noise. When the world's
 * program has one Sky Texture with a disc, looked up by the world's
 * direction, the disc becomes a sun light (sun.c: a cone sampled
 * uniformly, hit by rays, emitting photons) and the program leaves the
 * disc out (SHADER_RAY_SKY_SUN_AS_LIGHT) for every ray but the camera's,
 * so the map holds the sky alone. Camera rays still see the disc as the
 * program draws it (lights/environment.c), and the light is hidden from
 * them.
 *
 * The light's radiance is what the disc adds to the world's radiance, as
 * the whole program gives it (after Strength, mixes and any colour
 * node): the difference between the world evaluated with and without the
 * disc, averaged over SUN_SIDE² points of the disc. Within the disc the
 * light is uniform, where the texture darkens it toward the limb and
 * shades it from bottom to top; the light it sends is the same.
 */
#include "lights/light_kind.h"

#include <string.h>

#include "sampling/warp.h"
#include "shading/material.h"
#include "shading/shader_program.h"
#include "shading/sky/sky.h"

#define SUN_SIDE 64 /* SUN_SIDE² points of the disc, on a stratified grid: the mean within 10⁻⁴ */

/* The one Sky Texture whose disc may be a light, or NULL: looked up by the
 * world's direction (flags 1), with a disc, and the only one with a disc
 * (the flag hides every disc, and only one becomes a light). */
static const float *sky_with_sun(const material *world)
{
    const shader_program *p = &world->program;
    const float *found = NULL;
    for (uint32_t k = 0; k < p->instruction_count; k++) {
        const phos_shader_instruction *ins = &p->instructions[k];
        if (ins->op != PHOS_OP_TEX_SKY || !sky_model_textured(ins->mode))
            continue;
        const float *data = p->table + ins->table;
        if (!(data[SKY_SUN_DIAMETER] > 0.0f && data[SKY_SUN_INTENSITY] > 0.0f))
            continue;
        if (found || !(ins->flags & 1u))
            return NULL;
        found = data;
    }
    return found;
}

/* The mean over the disc of what the disc adds to the world's radiance,
 * for the rays that are not the camera's. */
static vec3 disc_radiance(const scene *s, const material *world, vec3 to_sun, float cos_half)
{
    vec3 sum = v3s(0.0f);
    for (int i = 0; i < SUN_SIDE * SUN_SIDE; i++) {
        float2 u = {((float)(i % SUN_SIDE) + 0.5f) / SUN_SIDE, ((float)(i / SUN_SIDE) + 0.5f) / SUN_SIDE};
        vec3 d = warp_cone(to_sun, cos_half, u);
        vec3 with = material_background(s, world, d, 0);
        vec3 without = material_background(s, world, d, SHADER_RAY_SKY_SUN_AS_LIGHT);
        sum = v3_add(sum, v3_sub(with, without));
    }
    return v3_scale(sum, 1.0f / (SUN_SIDE * SUN_SIDE));
}

phos_status light_sky_sun_add(const scene *s, light_table *t, uint32_t *capacity, const material *world,
                              int *added)
{
    *added = 0;
    const float *data = sky_with_sun(world);
    if (!data)
        return PHOS_OK;
    /* The whole disc above the horizon (and above its dip), where the
     * texture draws all of it. */
    float half = 0.5f * data[SKY_SUN_DIAMETER];
    if (!(data[SKY_SUN_ELEVATION] - half > maxf(data[SKY_EARTH_ANGLE], 0.0f)))
        return PHOS_OK;
    vec3 to_sun = sky_sun_direction(data[SKY_SUN_ELEVATION], data[SKY_SUN_ROTATION]);
    float cos_half = cosf(half);
    /* A channel can come out below 0 where the disc replaces the sky
     * (Blender 4) and the program clamps the disc's colour, outside Rec.
     * 709, to the gamut: a light gives no negative light. */
    vec3 lit = v3_max(disc_radiance(s, world, to_sun, cos_half), v3s(0.0f));
    if (!(v3_average(lit) > 0.0f) || !v3_is_finite(lit))
        return PHOS_OK;
    light l;
    memset(&l, 0, sizeof(l));
    l.kind = LIGHT_SUN;
    l.direction = v3_neg(to_sun);
    l.sun_cos_half = cos_half;
    l.sun_radiance = lit;
    float sin_half = sinf(half);
    l.color = v3_scale(lit, PHOS_PI * sin_half * sin_half); /* irradiance at normal incidence (sun.c) */
    l.camera_visible = 0; /* the program draws it for them */
    if (!light_table_append(t, capacity, &l))
        return PHOS_ERROR_OUT_OF_MEMORY;
    *added = 1;
    return PHOS_OK;
}
