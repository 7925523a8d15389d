/*
 * attribute.c — the Attribute node: a named per-corner attribute of the
 * mesh (phos.h, phos_mesh_attribute), interpolated barycentrically at the
 * hit and converted to the node's outputs by its type, as Cycles' Attribute
 * node converts them (Blender manual, "Attribute Node"; docs/architecture.md,
 * "Shader programs"): Color and Vector are the value as three numbers, Fac
 * their mean, Alpha a colour's fourth number and 1 otherwise.
 */
#include "scene/geometry.h"
#include "shading/shader_program.h"

/* The attribute's 4 floats at barycentrics (b1, b2): b0·corner0 + b1·corner1 + b2·corner2. */
static void attribute_at(const shader_globals *g, const mesh_attribute *a, float b1, float b2, float out[4])
{
    const float *c = a->values + 12 * (size_t)g->prim;
    float b0 = 1.0f - b1 - b2;
    for (int k = 0; k < 4; k++)
        out[k] = b0 * c[k] + b1 * c[4 + k] + b2 * c[8 + k];
}

/* The barycentrics of the point moved by a Bump's step (mode 1: dx, 2:
 * dy): the object-space step d = e1·δb1 + e2·δb2 over the triangle's edges
 * e1, e2, solved in the least-squares sense (d lies in the plane), so the
 * attribute changes along the step as its linear interpolation does (Cycles
 * adds the attribute's derivative along the ray footprint instead). */
static void moved_barycentrics(const phos_shader_instruction *ins, const shader_globals *g, float *b1, float *b2)
{
    *b1 = g->b1, *b2 = g->b2;
    if (ins->mode == 0)
        return;
    vec3 dx, dy;
    shader_bump_steps(ins->param[0], g, &dx, &dy); /* the Bump's filter width, as BUMP_OFFSET's */
    vec3 d = ins->mode == 1 ? dx : dy;
    if (g->world_to_object)
        d = xform_vector(g->world_to_object, d);
    const uint32_t *tri = g->mesh->indices + 3 * (size_t)g->prim;
    vec3 v0 = v3_load(g->mesh->positions + 3 * (size_t)tri[0]);
    vec3 e1 = v3_sub(v3_load(g->mesh->positions + 3 * (size_t)tri[1]), v0);
    vec3 e2 = v3_sub(v3_load(g->mesh->positions + 3 * (size_t)tri[2]), v0);
    float aa = v3_dot(e1, e1), ab = v3_dot(e1, e2), bb = v3_dot(e2, e2);
    float det = aa * bb - ab * ab;
    if (!(fabsf(det) > 1e-30f))
        return;
    float ad = v3_dot(e1, d), bd = v3_dot(e2, d);
    *b1 += (bb * ad - ab * bd) / det;
    *b2 += (aa * bd - ab * ad) / det;
}

int shader_attribute_tangent(const shader_globals *g, uint32_t id, vec3 *tangent, float *sign)
{
    const mesh_attribute *a = g->mesh ? mesh_find_attribute(g->mesh, id) : NULL;
    if (!a)
        return 0;
    float t[4];
    attribute_at(g, a, g->b1, g->b2, t);
    vec3 tw = v3(t[0], t[1], t[2]);
    if (g->object_to_world)
        tw = xform_vector(g->object_to_world, tw);
    /* Orthogonal to the shading normal (seen from the front), which
     * interpolation breaks. */
    vec3 n = g->backfacing ? v3_neg(g->N) : g->N;
    tw = v3_sub(tw, v3_scale(n, v3_dot(tw, n)));
    if (!(v3_length2(tw) > 0.0f))
        return 0;
    *tangent = v3_normalize(tw);
    *sign = t[3] < 0.0f ? -1.0f : 1.0f;
    return 1;
}

/* Out color(3), vector(3), fac, alpha. A point with no such attribute
 * (another mesh, the world) reads 0 with alpha 1, as Cycles' Attribute node
 * reads an attribute it does not find; flags 1: alpha 0, as its Color
 * Attribute node does. */
void shader_op_attribute(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    const mesh_attribute *a = g->mesh ? mesh_find_attribute(g->mesh, ins->table) : NULL;
    float v[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    if (a) {
        float b1, b2;
        moved_barycentrics(ins, g, &b1, &b2);
        attribute_at(g, a, b1, b2, v);
    }
    vec3 value;
    float fac, alpha = (!a && (ins->flags & 1)) ? 0.0f : 1.0f;
    switch (a ? a->type : PHOS_ATTRIBUTE_VECTOR) {
    case PHOS_ATTRIBUTE_FLOAT:
        value = v3s(v[0]);
        fac = v[0];
        break;
    case PHOS_ATTRIBUTE_FLOAT2:
        value = v3(v[0], v[1], 0.0f);
        fac = v[0]; /* Cycles: a 2D attribute's Fac is its first number */
        break;
    case PHOS_ATTRIBUTE_COLOR:
        value = v3(v[0], v[1], v[2]);
        fac = (v[0] + v[1] + v[2]) / 3.0f;
        alpha = v[3];
        break;
    default: /* VECTOR, and the missing attribute's zeros */
        value = v3(v[0], v[1], v[2]);
        fac = (v[0] + v[1] + v[2]) / 3.0f;
        break;
    }
    SHADER_OUT3(0, value);
    SHADER_OUT3(1, value);
    SHADER_OUT(2, fac);
    SHADER_OUT(3, alpha);
}
