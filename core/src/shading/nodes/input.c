/*
 * input.c — the nodes that read the shading point: Texture Coordinate,
 * Geometry, Object Info, Tangent, Fresnel, Layer Weight and Light Path, with
 * Cycles' definitions (Blender manual, "Input" nodes).
 */
#include "shading/fresnel.h"
#include "shading/shader_program.h"

/* Cycles' camera space looks down +z; Blender's camera down −z. The
 * background's P is a direction, seen from the camera's position. */
static vec3 camera_space_point(const shader_globals *g, vec3 p)
{
    if (!g->world_to_camera)
        return p;
    vec3 c = g->background ? xform_vector(g->world_to_camera, p) : xform_point(g->world_to_camera, p);
    return v3(c.x, c.y, -c.z);
}

/* Mode 0: Generated, Normal (object space), UV, Object, Camera.
 * Mode 1: Window, Reflection (the view direction mirrored about N). */
void shader_op_texture_coordinate(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    if (ins->mode == 0) {
        SHADER_OUT3(0, g->generated);
        SHADER_OUT3(1, shader_normal_to_object(g, g->N));
        SHADER_OUT3(2, v3(g->u, g->v, 0.0f));
        SHADER_OUT3(3, g->object_P);
        SHADER_OUT3(4, camera_space_point(g, g->P));
    } else {
        SHADER_OUT3(0, g->window);
        /* R = 2 (N·I) N − I */
        SHADER_OUT3(1, v3_sub(v3_scale(g->N, 2.0f * v3_dot(g->N, g->I)), g->I));
    }
}

/* Position, Normal, True Normal, Incoming, Backfacing. */
void shader_op_geometry(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    SHADER_OUT3(0, g->P);
    SHADER_OUT3(1, g->N);
    SHADER_OUT3(2, g->Ng);
    SHADER_OUT3(3, g->I);
    SHADER_OUT(4, g->backfacing ? 1.0f : 0.0f);
}

/* Location, Random, Object Index. */
void shader_op_object_info(const phos_shader_instruction *ins, shader_context *ctx)
{
    SHADER_OUT3(0, ctx->g->object_location);
    SHADER_OUT(1, ctx->g->object_random);
    SHADER_OUT(2, ctx->g->object_index);
}

/* The Tangent node (and Geometry's Tangent, radial about Z), as Cycles
 * defines it: radial about an object axis through the centre of the
 * texture space, c = generated − ½ turned a quarter about the axis (about
 * Z: (−c.y, c.x, 0)), to world space as a normal is; or the UV map's
 * MikkTSpace tangent (0 without one); then made perpendicular to the
 * shading normal, N × normalize(T × N). */
void shader_op_tangent(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    vec3 t;
    if (ins->mode == PHOS_TANGENT_UV_MAP) {
        t = g->tangent;
    } else {
        vec3 c = v3_sub(g->generated, v3s(0.5f));
        t = ins->mode == PHOS_TANGENT_RADIAL_X ? v3(0.0f, -c.z, c.y)
            : ins->mode == PHOS_TANGENT_RADIAL_Y ? v3(-c.z, 0.0f, c.x)
                                                 : v3(-c.y, c.x, 0.0f);
        const float *m = g->normal_to_world;
        if (m)
            t = v3(m[0] * t.x + m[1] * t.y + m[2] * t.z, m[3] * t.x + m[4] * t.y + m[5] * t.z,
                   m[6] * t.x + m[7] * t.y + m[8] * t.z);
    }
    vec3 across = v3_cross(t, g->N);
    SHADER_OUT3(0, v3_length2(across) > 0.0f ? v3_cross(g->N, v3_normalize(across)) : v3s(0.0f));
}

/* The dielectric Fresnel reflectance of IOR η for the view direction about
 * the normal; seen from the back the interface is inverted (1/η). */
void shader_op_fresnel(const phos_shader_instruction *ins, shader_context *ctx)
{
    float eta = fmaxf(SHADER_IN(0), 1e-5f);
    if (ctx->g->backfacing)
        eta = 1.0f / eta;
    SHADER_OUT(0, fresnel_dielectric(v3_dot(ctx->g->I, SHADER_IN3(1)), eta));
}

/* Fresnel: the Fresnel reflectance of η = 1/(1 − blend);
 * Facing: 1 − |N·I|^b with b = 2·blend below ½ and ½/(1 − blend) above. */
void shader_op_layer_weight(const phos_shader_instruction *ins, shader_context *ctx)
{
    float blend = SHADER_IN(0);
    vec3 n = SHADER_IN3(1);
    float cosi = v3_dot(ctx->g->I, n);
    float eta = fmaxf(1.0f - blend, 1e-5f);
    if (!ctx->g->backfacing)
        eta = 1.0f / eta;
    SHADER_OUT(0, fresnel_dielectric(cosi, eta));
    float f = fabsf(cosi);
    if (blend != 0.5f) {
        float b = clampf(blend, 0.0f, 1.0f - 1e-5f);
        b = b < 0.5f ? 2.0f * b : 0.5f / (1.0f - b);
        f = powf(f, b);
    }
    SHADER_OUT(1, 1.0f - f);
}

/* Mode 0: Is Camera, Is Shadow, Is Diffuse, Is Glossy, Is Singular Ray.
 * Mode 1: Is Reflection, Is Transmission Ray, Ray Length, Ray Depth,
 * Transparent Depth. Mode 2: Diffuse, Glossy, Transmission Depth. What
 * each integrator sets: README, "Light Path". */
void shader_op_light_path(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    uint32_t f = g->ray_flags;
    if (ins->mode == 0) {
        SHADER_OUT(0, (f & SHADER_RAY_CAMERA) ? 1.0f : 0.0f);
        SHADER_OUT(1, (f & SHADER_RAY_SHADOW) ? 1.0f : 0.0f);
        SHADER_OUT(2, (f & SHADER_RAY_DIFFUSE) ? 1.0f : 0.0f);
        SHADER_OUT(3, (f & SHADER_RAY_GLOSSY) ? 1.0f : 0.0f);
        SHADER_OUT(4, (f & SHADER_RAY_SINGULAR) ? 1.0f : 0.0f);
    } else if (ins->mode == 1) {
        SHADER_OUT(0, (f & SHADER_RAY_REFLECT) ? 1.0f : 0.0f);
        SHADER_OUT(1, (f & SHADER_RAY_TRANSMIT) ? 1.0f : 0.0f);
        SHADER_OUT(2, g->ray_length);
        SHADER_OUT(3, (float)g->ray_depth);
        SHADER_OUT(4, (float)g->transparent_depth);
    } else {
        SHADER_OUT(0, (float)g->diffuse_depth);
        SHADER_OUT(1, (float)g->glossy_depth);
        SHADER_OUT(2, (float)g->transmission_depth);
    }
}
