/*
 * vector.c — the vector nodes: Mapping, Vector Rotate, Vector Transform,
 * Normal, Normal Map and Bump, with Cycles' definitions (Blender manual,
 * "Vector" nodes).
 */
#include "shading/shader_program.h"
#include "shading/valid_reflection.h"

static vec3 safe_divide3(vec3 a, vec3 b)
{
    return v3(b.x != 0.0f ? a.x / b.x : 0.0f, b.y != 0.0f ? a.y / b.y : 0.0f, b.z != 0.0f ? a.z / b.z : 0.0f);
}

static vec3 safe_normalize3(vec3 a)
{
    float l = v3_length(a);
    return l > 0.0f ? v3_scale(a, 1.0f / l) : a;
}

/* The rotation of Euler angles (radians) applied X first, then Y, then Z:
 * R = Rz Ry Rx, row-major. */
static void euler_xyz_matrix(vec3 e, float m[9])
{
    float cx = cosf(e.x), cy = cosf(e.y), cz = cosf(e.z);
    float sx = sinf(e.x), sy = sinf(e.y), sz = sinf(e.z);
    m[0] = cy * cz, m[1] = sy * sx * cz - cx * sz, m[2] = sy * cx * cz + sx * sz;
    m[3] = cy * sz, m[4] = sy * sx * sz + cx * cz, m[5] = sy * cx * sz - sx * cz;
    m[6] = -sy, m[7] = cy * sx, m[8] = cy * cx;
}

static vec3 mat3_mul(const float m[9], vec3 v)
{
    return v3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
              m[6] * v.x + m[7] * v.y + m[8] * v.z);
}

static vec3 mat3_mul_transposed(const float m[9], vec3 v)
{
    return v3(m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z,
              m[2] * v.x + m[5] * v.y + m[8] * v.z);
}

/* Point: R(v·s) + t; Texture: the inverse, Rᵀ(v − t)/s; Vector: R(v·s);
 * Normal: normalize(R(v/s)). */
void shader_op_mapping(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 v = SHADER_IN3(0), loc = SHADER_IN3(1), rot = SHADER_IN3(2), scale = SHADER_IN3(3);
    float m[9];
    euler_xyz_matrix(rot, m);
    vec3 r;
    switch (ins->mode) {
    case PHOS_MAPPING_POINT:
        r = v3_add(mat3_mul(m, v3_mul(v, scale)), loc);
        break;
    case PHOS_MAPPING_TEXTURE:
        r = safe_divide3(mat3_mul_transposed(m, v3_sub(v, loc)), scale);
        break;
    case PHOS_MAPPING_VECTOR:
        r = mat3_mul(m, v3_mul(v, scale));
        break;
    default:
        r = safe_normalize3(mat3_mul(m, safe_divide3(v, scale)));
        break;
    }
    SHADER_OUT3(0, r);
}

/* Rodrigues' rotation of p about the unit axis a by angle θ. */
static vec3 rotate_around_axis(vec3 p, vec3 a, float angle)
{
    float c = cosf(angle), s = sinf(angle), t = 1.0f - c;
    float m[9] = {c + t * a.x * a.x,       t * a.x * a.y - a.z * s, t * a.x * a.z + a.y * s,
                  t * a.x * a.y + a.z * s, c + t * a.y * a.y,       t * a.y * a.z - a.x * s,
                  t * a.x * a.z - a.y * s, t * a.y * a.z + a.x * s, c + t * a.z * a.z};
    return mat3_mul(m, p);
}

void shader_op_vector_rotate(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 v = SHADER_IN3(0), center = SHADER_IN3(1), axis = SHADER_IN3(2), euler = SHADER_IN3(4);
    float angle = (ins->flags & 1) ? -SHADER_IN(3) : SHADER_IN(3);
    vec3 p = v3_sub(v, center), r;
    switch (ins->mode) {
    case PHOS_VECTOR_ROTATE_EULER_XYZ: {
        float m[9];
        euler_xyz_matrix(euler, m);
        r = v3_add((ins->flags & 1) ? mat3_mul_transposed(m, p) : mat3_mul(m, p), center);
        break;
    }
    case PHOS_VECTOR_ROTATE_X_AXIS:
        r = v3_add(rotate_around_axis(p, v3(1.0f, 0.0f, 0.0f), angle), center);
        break;
    case PHOS_VECTOR_ROTATE_Y_AXIS:
        r = v3_add(rotate_around_axis(p, v3(0.0f, 1.0f, 0.0f), angle), center);
        break;
    case PHOS_VECTOR_ROTATE_Z_AXIS:
        r = v3_add(rotate_around_axis(p, v3(0.0f, 0.0f, 1.0f), angle), center);
        break;
    default: {
        float l = v3_length(axis);
        r = l != 0.0f ? v3_add(rotate_around_axis(p, v3_scale(axis, 1.0f / l), angle), center) : v;
        break;
    }
    }
    SHADER_OUT3(0, r);
}

/* A point, direction or normal from one space to world space and back. */
static vec3 to_world(const shader_globals *g, uint32_t space, uint32_t type, vec3 v)
{
    const float *m = space == PHOS_SPACE_OBJECT ? g->object_to_world : space == PHOS_SPACE_CAMERA ? g->camera_to_world
                                                                                                : NULL;
    if (!m)
        return v;
    if (space == PHOS_SPACE_CAMERA)
        v.z = -v.z; /* Cycles' camera space looks down +z */
    if (type == PHOS_VECTOR_TRANSFORM_POINT)
        return xform_point(m, v);
    if (type == PHOS_VECTOR_TRANSFORM_VECTOR || space == PHOS_SPACE_CAMERA)
        return xform_vector(m, v);
    return g->normal_to_world ? mat3_mul(g->normal_to_world, v) : v;
}

static vec3 from_world(const shader_globals *g, uint32_t space, uint32_t type, vec3 v)
{
    const float *m = space == PHOS_SPACE_OBJECT ? g->world_to_object : space == PHOS_SPACE_CAMERA ? g->world_to_camera
                                                                                                : NULL;
    if (!m)
        return v;
    vec3 r;
    if (type == PHOS_VECTOR_TRANSFORM_POINT)
        r = xform_point(m, v);
    else if (type == PHOS_VECTOR_TRANSFORM_VECTOR || space == PHOS_SPACE_CAMERA)
        r = xform_vector(m, v);
    else
        r = shader_normal_to_object(g, v);
    if (space == PHOS_SPACE_CAMERA)
        r.z = -r.z;
    return r;
}

void shader_op_vector_transform(const phos_shader_instruction *ins, shader_context *ctx)
{
    uint32_t from = ins->flags & 15u, to = (ins->flags >> 4) & 15u;
    vec3 v = from_world(ctx->g, to, ins->mode, to_world(ctx->g, from, ins->mode, SHADER_IN3(0)));
    if (ins->mode == PHOS_VECTOR_TRANSFORM_NORMAL)
        v = safe_normalize3(v);
    SHADER_OUT3(0, v);
}

/* Normal: the node's own direction (param), and its dot product with the
 * input normalised. */
void shader_op_normal(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 d = v3_normalize(v3(ins->param[0], ins->param[1], ins->param[2]));
    SHADER_OUT3(0, d);
    SHADER_OUT(1, v3_dot(d, safe_normalize3(SHADER_IN3(0))));
}

/* Colour → normal: tangent space uses the UV map's MikkTSpace tangent
 * frame (T, ±N×T, N) about the interpolated normal; object and world
 * space take the colour as the normal itself. Strength blends from the
 * shading normal, normalize(N + s·(N' − N)), except in tangent space from
 * Blender 4 (flags 1), where it scales the map's tilt. */
void shader_op_normal_map(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    float strength = SHADER_IN(0);
    vec3 c = SHADER_IN3(1);
    c = v3(2.0f * (c.x - 0.5f), 2.0f * (c.y - 0.5f), 2.0f * (c.z - 0.5f));
    vec3 n;
    int blend_strength = 1;
    if (ins->mode == PHOS_NORMAL_MAP_TANGENT) {
        vec3 tangent = g->tangent;
        float sign = g->tangent_sign;
        if ((ins->flags & 2) && !shader_attribute_tangent(g, ins->table, &tangent, &sign))
            tangent = v3s(0.0f);
        if (v3_is_zero(tangent)) {
            SHADER_OUT3(0, g->N); /* no tangents: the unperturbed normal */
            return;
        }
        if (ins->flags & 1) {
            /* Strength in tangent space (Cycles of Blender 4+): the map's
             * tilt scales by it, its z goes toward 1. */
            c.x *= strength;
            c.y *= strength;
            c.z = 1.0f + (c.z - 1.0f) * clampf(strength, 0.0f, 1.0f);
            blend_strength = 0;
        }
        /* The frame is the one the map was baked in, seen from the front. */
        vec3 normal = g->backfacing ? v3_neg(g->N) : g->N;
        vec3 b = v3_scale(v3_cross(normal, tangent), sign);
        n = safe_normalize3(v3_add(v3_add(v3_scale(tangent, c.x), v3_scale(b, c.y)), v3_scale(normal, c.z)));
    } else if (ins->mode == PHOS_NORMAL_MAP_OBJECT) {
        n = safe_normalize3(g->normal_to_world ? mat3_mul(g->normal_to_world, c) : c);
    } else {
        n = safe_normalize3(c);
    }
    if (g->backfacing)
        n = v3_neg(n);
    if (blend_strength && strength != 1.0f) {
        strength = fmaxf(strength, 0.0f);
        n = safe_normalize3(v3_add(g->N, v3_scale(v3_sub(n, g->N), strength)));
    }
    SHADER_OUT3(0, v3_is_zero(n) ? g->N : n);
}

/* The two offsets a bump evaluates its height at: the position
 * differentials (the pixel's footprint, Cycles' dPdx and dPdy) times the
 * filter width (the instruction's param[0]), the fraction of the footprint the
 * Blender version steps (the whole footprint before 4.4, then the node's
 * Filter Width, 0.1 by default; 0 reads as 1). A forward difference over that step is the
 * height's derivative half a step away, which is why the step must be
 * Cycles' where heights vary within a pixel. */
void shader_bump_steps(float filter_width, const shader_globals *g, vec3 *dx, vec3 *dy)
{
    float width = filter_width > 0.0f ? filter_width : 1.0f;
    *dx = v3_scale(g->dPdx, width);
    *dy = v3_scale(g->dPdy, width);
}

/* Mode 1 (dx) or 2 (dy): the position moved by that step, and the texture
 * coordinates there (generated, UV, object); mode 0 the point itself. */
void shader_op_bump_offset(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    vec3 dx, dy, d = v3s(0.0f);
    shader_bump_steps(ins->param[0], g, &dx, &dy);
    if (ins->mode == 1)
        d = dx;
    else if (ins->mode == 2)
        d = dy;
    vec3 d_obj = g->world_to_object ? xform_vector(g->world_to_object, d) : d;
    /* UV step: the least-squares (du, dv) with dPdu du + dPdv dv = d. */
    float aa = v3_dot(g->dPdu, g->dPdu), ab = v3_dot(g->dPdu, g->dPdv), bb = v3_dot(g->dPdv, g->dPdv);
    float det = aa * bb - ab * ab, du = 0.0f, dv = 0.0f;
    if (fabsf(det) > 1e-30f) {
        float ad = v3_dot(g->dPdu, d), bd = v3_dot(g->dPdv, d);
        du = (bb * ad - ab * bd) / det;
        dv = (aa * bd - ab * ad) / det;
    }
    SHADER_OUT3(0, v3_add(g->P, d));
    SHADER_OUT3(1, v3_add(g->generated, v3_mul(d_obj, g->generated_scale)));
    SHADER_OUT3(2, v3(g->u + du, g->v + dv, 0.0f));
    SHADER_OUT3(3, v3_add(g->object_P, d_obj));
    SHADER_OUT3(4, v3_add(g->P, d));
}

/* The surface gradient of the height h from its values at the point and
 * at the two steps (Mikkelsen 2010, "Bump Mapping Unparametrized
 * Surfaces on the GPU"): with R1 = dy × N, R2 = N × dx and det = dx·R1,
 * N' = normalize(|det| N − distance · sign(det) · ((h_x − h)R1 + (h_y − h)R2)),
 * blended toward N by 1 − strength. flags 1 inverts; flags 2 keeps the
 * viewer's reflection above the surface as Cycles before 4.0 does
 * (valid_reflection.h). */
void shader_op_bump(const phos_shader_instruction *ins, shader_context *ctx)
{
    const shader_globals *g = ctx->g;
    float strength = fmaxf(SHADER_IN(0), 0.0f), distance = SHADER_IN(1);
    float h = SHADER_IN(2), hx = SHADER_IN(3), hy = SHADER_IN(4);
    vec3 n = SHADER_IN3(5);
    if (ins->flags & 1)
        distance = -distance;
    vec3 dx, dy;
    shader_bump_steps(ins->param[0], g, &dx, &dy);
    vec3 rx = v3_cross(dy, n), ry = v3_cross(n, dx);
    float det = v3_dot(dx, rx);
    vec3 grad = v3_add(v3_scale(rx, hx - h), v3_scale(ry, hy - h));
    float sign = det < 0.0f ? -1.0f : 1.0f;
    vec3 out = safe_normalize3(v3_sub(v3_scale(n, fabsf(det)), v3_scale(grad, distance * sign)));
    if (v3_is_zero(out))
        out = n;
    else
        out = v3_normalize(v3_add(v3_scale(out, strength), v3_scale(n, 1.0f - strength)));
    if (ins->flags & 2)
        out = valid_reflection_normal(g->Ng, g->I, out, PHOS_NORMAL_CORRECTION_BOTH_ROOTS);
    SHADER_OUT3(0, out);
}
