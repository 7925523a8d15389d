/*
 * texture_image.c — the Image Texture node: flat, box, sphere and tube
 * projections of an image (Blender manual, "Image Texture Node"), and the
 * Environment Texture's equirectangular and mirror-ball projections of a
 * direction, with Cycles' conventions for each.
 */
#include "scene/scene.h"
#include "shading/shader_program.h"
#include "shading/texture.h"

/* RGBA at (u, v) with the node's interpolation, extension and alpha. The
 * core keeps straight colours; Cycles interpolates associated ones (colour
 * × alpha) and gives them so, unless the node unassociates the result
 * again (its Alpha output is used, or the alpha is channel-packed). */
static void lookup(const shader_context *ctx, const phos_shader_instruction *ins, float u, float v, float out[4])
{
    const image *img = &ctx->scene->images[ins->table];
    image_lookup_rgba(img, u, v, ins->flags & 3u, (ins->flags >> 2) & 3u, 1, out);
    float a = out[3];
    if ((ins->flags & PHOS_IMAGE_UNASSOCIATE) && a != 1.0f && a != 0.0f)
        for (int c = 0; c < 3; c++)
            out[c] /= a;
}

/* The [0,1]³ box coordinates mapped to [−1,1]³ first. Sphere: longitude
 * u = (1 − atan2(x, y)/π)/2, latitude v = 1 − acos(z/|p|)/π; tube: the same
 * longitude and v = (z + 1)/2. */
static vec3 remap_square(vec3 co)
{
    return v3((co.x - 0.5f) * 2.0f, (co.y - 0.5f) * 2.0f, (co.z - 0.5f) * 2.0f);
}

static void map_to_sphere(vec3 p, float *u, float *v)
{
    float len = v3_length(p);
    *u = *v = 0.0f;
    if (len > 0.0f) {
        *u = (p.x == 0.0f && p.y == 0.0f) ? 0.0f : (1.0f - atan2f(p.x, p.y) * PHOS_INV_PI) * 0.5f;
        *v = 1.0f - acosf(clampf(p.z / len, -1.0f, 1.0f)) * PHOS_INV_PI;
    }
}

static void map_to_tube(vec3 p, float *u, float *v)
{
    float len = sqrtf(p.x * p.x + p.y * p.y);
    *u = *v = 0.0f;
    if (len > 0.0f) {
        *u = (1.0f - atan2f(p.x / len, p.y / len) * PHOS_INV_PI) * 0.5f;
        *v = (p.z + 1.0f) * 0.5f;
    }
}

/* Equirectangular: longitude u = ½ − atan2(y, x)/(2π), so +x is the
 * image's centre column and u grows toward −y (clockwise seen from +z);
 * latitude v = ½ + atan2(z, √(x² + y²))/π, the top row straight up. */
static void map_to_equirectangular(vec3 d, float *u, float *v)
{
    *u = 0.5f - atan2f(d.y, d.x) * (0.5f * PHOS_INV_PI);
    *v = 0.5f + atan2f(d.z, sqrtf(d.x * d.x + d.y * d.y)) * PHOS_INV_PI;
}

static vec3 unit_or_zero(vec3 d)
{
    float l = v3_length(d);
    return l > 0.0f ? v3_scale(d, 1.0f / l) : d;
}

/* Mirror ball: the image of a mirrored sphere photographed from −y with
 * an orthographic lens. A direction d is reflected toward the camera by
 * the sphere's normal along d − (0, 1, 0), normalised; that normal's x and
 * z are the image's coordinates in [−1, 1]. */
static void map_to_mirror_ball(vec3 d, float *u, float *v)
{
    d.y -= 1.0f;
    float div = 2.0f * safe_sqrtf(-0.5f * d.y);
    if (div > 0.0f)
        d = v3_scale(d, 1.0f / div);
    *u = 0.5f * (d.x + 1.0f);
    *v = 0.5f * (d.z + 1.0f);
}

/* Box: three planar projections along the object-space axes, blended by
 * the normal's direction cosines (zones of a barycentric triangle whose
 * corners are the three faces; blend widens the zones that mix). */
static vec3 box_weights(vec3 n, float blend)
{
    n = v3(fabsf(n.x), fabsf(n.y), fabsf(n.z));
    float sum = n.x + n.y + n.z;
    if (sum > 0.0f)
        n = v3_scale(n, 1.0f / sum);
    float limit = 0.5f * (1.0f + blend);
    if (n.x > limit * (n.x + n.y) && n.x > limit * (n.x + n.z))
        return v3(1.0f, 0.0f, 0.0f);
    if (n.y > limit * (n.x + n.y) && n.y > limit * (n.y + n.z))
        return v3(0.0f, 1.0f, 0.0f);
    if (n.z > limit * (n.x + n.z) && n.z > limit * (n.y + n.z))
        return v3(0.0f, 0.0f, 1.0f);
    if (!(blend > 0.0f))
        return v3(1.0f, 0.0f, 0.0f);
    float lo = 0.5f * (1.0f - blend);
    if (n.z < (1.0f - limit) * (n.y + n.x)) {
        float w = clampf((n.x / (n.x + n.y) - lo) / blend, 0.0f, 1.0f);
        return v3(w, 1.0f - w, 0.0f);
    }
    if (n.x < (1.0f - limit) * (n.y + n.z)) {
        float w = clampf((n.y / (n.y + n.z) - lo) / blend, 0.0f, 1.0f);
        return v3(0.0f, w, 1.0f - w);
    }
    if (n.y < (1.0f - limit) * (n.x + n.z)) {
        float w = clampf((n.x / (n.x + n.z) - lo) / blend, 0.0f, 1.0f);
        return v3(w, 0.0f, 1.0f - w);
    }
    float d = 2.0f * limit - 1.0f;
    return v3(((2.0f - limit) * n.x + (limit - 1.0f)) / d, ((2.0f - limit) * n.y + (limit - 1.0f)) / d,
              ((2.0f - limit) * n.z + (limit - 1.0f)) / d);
}

static void box_lookup(const shader_context *ctx, const phos_shader_instruction *ins, vec3 co, float out[4])
{
    const shader_globals *g = ctx->g;
    vec3 n = shader_normal_to_object(g, g->N);
    vec3 w = box_weights(n, ins->param[0]);
    float t[4];
    out[0] = out[1] = out[2] = out[3] = 0.0f;
    /* Oriented so that no face is mirrored. */
    float uv[3][2] = {{n.x < 0.0f ? 1.0f - co.y : co.y, co.z},
                      {n.y > 0.0f ? 1.0f - co.x : co.x, co.z},
                      {n.z > 0.0f ? 1.0f - co.y : co.y, co.x}};
    float wk[3] = {w.x, w.y, w.z};
    for (int k = 0; k < 3; k++) {
        if (!(wk[k] > 0.0f))
            continue;
        lookup(ctx, ins, uv[k][0], uv[k][1], t);
        for (int c = 0; c < 4; c++)
            out[c] += wk[k] * t[c];
    }
}

void shader_op_tex_image(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 co = SHADER_IN3(0);
    float rgba[4], u = co.x, v = co.y;
    switch (ins->mode) {
    case PHOS_PROJECTION_BOX:
        box_lookup(ctx, ins, co, rgba);
        break;
    case PHOS_PROJECTION_SPHERE:
        map_to_sphere(remap_square(co), &u, &v);
        lookup(ctx, ins, u, v, rgba);
        break;
    case PHOS_PROJECTION_TUBE:
        map_to_tube(remap_square(co), &u, &v);
        lookup(ctx, ins, u, v, rgba);
        break;
    case PHOS_PROJECTION_EQUIRECTANGULAR:
        map_to_equirectangular(co, &u, &v);
        lookup(ctx, ins, u, v, rgba);
        break;
    case PHOS_PROJECTION_MIRROR_BALL:
        map_to_mirror_ball(unit_or_zero(co), &u, &v);
        lookup(ctx, ins, u, v, rgba);
        break;
    default:
        lookup(ctx, ins, u, v, rgba);
        break;
    }
    SHADER_OUT3(0, v3(rgba[0], rgba[1], rgba[2]));
    SHADER_OUT(1, rgba[3]);
}
