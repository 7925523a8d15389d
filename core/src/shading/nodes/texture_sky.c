/*
 * texture_sky.c — the Sky Texture node: the radiance of the daylight
 * models of shading/sky/ in a direction, as Cycles draws them
 * (docs/algorithms.md §11.4).
 */
#include "scene/scene.h"
#include "shading/shader_program.h"
#include "shading/sky/sky.h"
#include "shading/texture.h"

/* The sun's disc at d: the radiance of its lowest and highest points
 * blended by elevation, darkened toward the limb as
 * 1 − 0.6 (1 − √(1 − (r/R)²)) (r the angle from the centre, R the
 * disc's), and hidden below the horizon's dip (the single-scattering
 * sky, which has no ground, below the horizon itself). */
static vec3 sun_disc(const float *data, vec3 d, float elevation, int multiple)
{
    float diameter = data[SKY_SUN_DIAMETER], half = 0.5f * diameter;
    if (!(diameter > 0.0f) || elevation <= data[SKY_EARTH_ANGLE] || (!multiple && d.z < 0.0f))
        return v3s(0.0f);
    float r = sky_angle_between(d, sky_sun_direction(data[SKY_SUN_ELEVATION], data[SKY_SUN_ROTATION]));
    if (r >= half)
        return v3s(0.0f);
    float y = (elevation - data[SKY_SUN_ELEVATION]) / diameter + 0.5f;
    vec3 bottom = v3_load(data + SKY_SUN_BOTTOM), top = v3_load(data + SKY_SUN_TOP);
    vec3 at = v3_add(v3_scale(bottom, 1.0f - y), v3_scale(top, y));
    float limb = 1.0f - 0.6f * (1.0f - safe_sqrtf(1.0f - sqr(r / half)));
    return v3_scale(at, data[SKY_SUN_INTENSITY] * limb);
}

/* The scattering models: the texture at d's elevation and azimuth from
 * the sun (which lies at azimuth π/2 − rotation from +x), plus the disc
 * unless the core renders it as a light (SHADER_RAY_SKY_SUN_AS_LIGHT). */
static vec3 scattering_sky(const shader_context *ctx, const phos_shader_instruction *ins, const float *data, vec3 d)
{
    float elevation = atan2f(d.z, sqrtf(d.x * d.x + d.y * d.y));
    float azimuth = atan2f(d.y, d.x) - (0.5f * PHOS_PI - data[SKY_SUN_ROTATION]);
    const image *img = &ctx->scene->images[(uint32_t)data[SKY_IMAGE]];
    float u, v, rgba[4];
    sky_texture_coordinates(elevation, azimuth, img->width, img->height, &u, &v);
    image_lookup_rgba(img, u, v, PHOS_IMAGE_LINEAR, PHOS_IMAGE_EXTEND >> 2, 0, rgba);
    vec3 sky = v3(rgba[0], rgba[1], rgba[2]);
    if (ctx->g->ray_flags & SHADER_RAY_SKY_SUN_AS_LIGHT)
        return sky;
    return v3_add(sky, sun_disc(data, d, elevation, ins->mode == PHOS_SKY_MULTIPLE_SCATTERING));
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
        rgb = scattering_sky(ctx, ins, data, d);
    SHADER_OUT3(0, v3_max(rgb, v3s(0.0f)));
}
