/*
 * texture_sky.c — the Sky Texture node: the radiance of the daylight
 * models of shading/sky/ in a direction, as Cycles draws them
 * (docs/algorithms.md §11.1).
 */
#include "scene/scene.h"
#include "shading/shader_program.h"
#include "shading/sky/sky.h"
#include "shading/texture.h"

/* The sun's disc at d, or −1 outside it: the radiance of its lowest and
 * highest points blended by elevation, darkened toward the limb as
 * 1 − 0.6 (1 − √(1 − (r/R)²)) (r the angle from the centre, R the
 * disc's), and hidden below the horizon's dip. */
static int sun_disc(const float *data, vec3 d, float elevation, vec3 *out)
{
    float diameter = data[SKY_SUN_DIAMETER], half = 0.5f * diameter;
    if (!(diameter > 0.0f) || elevation <= data[SKY_EARTH_ANGLE])
        return 0;
    float r = sky_angle_between(d, sky_sun_direction(data[SKY_SUN_ELEVATION], data[SKY_SUN_ROTATION]));
    if (r >= half)
        return 0;
    float y = (elevation - data[SKY_SUN_ELEVATION]) / diameter + 0.5f;
    vec3 bottom = v3_load(data + SKY_SUN_BOTTOM), top = v3_load(data + SKY_SUN_TOP);
    vec3 at = v3_add(v3_scale(bottom, 1.0f - y), v3_scale(top, y));
    float limb = 1.0f - 0.6f * (1.0f - safe_sqrtf(1.0f - sqr(r / half)));
    *out = v3_scale(at, data[SKY_SUN_INTENSITY] * limb);
    return 1;
}

/* The scattering models, as each Blender's Cycles draws them: the
 * texture at d's elevation and azimuth from the sun (which lies at
 * azimuth π/2 − rotation from +x), and the disc unless the core renders
 * it as a light (SHADER_RAY_SKY_SUN_AS_LIGHT). Blender 2.90 to 4.x draw
 * the disc instead of the sky behind it and, below the horizon, the
 * horizon's colour fading to black (sky_ground_fade, of the ray's own
 * elevation); 5.x adds the disc to the sky, whose texture holds the
 * ground. */
static vec3 scattering_sky(const shader_context *ctx, const float *data, vec3 d)
{
    uint32_t layout = (uint32_t)data[SKY_LAYOUT];
    float elevation = atan2f(d.z, sqrtf(d.x * d.x + d.y * d.y));
    float azimuth = atan2f(d.y, d.x) - (0.5f * PHOS_PI - data[SKY_SUN_ROTATION]);
    vec3 disc = v3s(0.0f);
    int in_disc = !(ctx->g->ray_flags & SHADER_RAY_SKY_SUN_AS_LIGHT) && sun_disc(data, d, elevation, &disc);
    int hemisphere = layout == PHOS_SKY_LAYOUT_HEMISPHERE;
    if (hemisphere && elevation >= 0.0f && in_disc)
        return disc;
    const image *img = &ctx->scene->images[(uint32_t)data[SKY_IMAGE]];
    float u, v, rgba[4];
    sky_texture_coordinates(layout, elevation, azimuth, &u, &v);
    image_lookup_rgba(img, u, v, PHOS_IMAGE_LINEAR, PHOS_IMAGE_EXTEND >> 2, 0, rgba);
    vec3 sky = v3(rgba[0], rgba[1], rgba[2]);
    if (hemisphere)
        return elevation >= 0.0f ? sky : v3_scale(sky, sky_ground_fade(elevation));
    return v3_add(sky, disc);
}

/* in vector(3); out color(3), never negative (Cycles clamps the colours
 * outside Rec. 709's gamut to it). */
void shader_op_tex_sky(const phos_shader_instruction *ins, shader_context *ctx)
{
    const float *data = ctx->program->table + ins->table;
    vec3 d = SHADER_IN3(0);
    float l = v3_length(d);
    d = l > 0.0f ? v3_scale(d, 1.0f / l) : v3(0.0f, 0.0f, 1.0f);
    vec3 rgb;
    if (ins->mode == PHOS_SKY_PREETHAM)
        rgb = sky_preetham_radiance(data, d);
    else if (ins->mode == PHOS_SKY_HOSEK_WILKIE)
        rgb = sky_hosek_wilkie_radiance(data, d);
    else
        rgb = scattering_sky(ctx, data, d);
    SHADER_OUT3(0, v3_max(rgb, v3s(0.0f)));
}
