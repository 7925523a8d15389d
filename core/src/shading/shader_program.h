/*
 * shader_program.h — the compiled form of a Cycles node tree and its
 * evaluator (docs/architecture.md, "Shader programs").
 *
 * A program is a flat list of instructions over a register file of floats
 * (phos.h, phos_shader_instruction). The evaluator runs them in order at a
 * shading point described by shader_globals; each node family implements
 * its ops in shading/nodes/ with the signature shader_op_fn, reading its
 * inputs with SHADER_IN/SHADER_IN3 and writing with SHADER_OUT/SHADER_OUT3
 * (an output nobody reads is PHOS_SHADER_NO_REGISTER and is skipped).
 */
#ifndef PHOS_SHADER_PROGRAM_H
#define PHOS_SHADER_PROGRAM_H

#include "phos.h"
#include "util/vec.h"

struct phos_scene;
struct mesh;

/* What the inputs of a node tree read at a shading point. Vectors are in
 * world space unless named otherwise; N faces the viewer (Cycles). */
typedef struct shader_globals {
    vec3 P;                  /* position */
    vec3 N;                  /* shading normal */
    vec3 Ng;                 /* geometric normal */
    vec3 I;                  /* toward the viewer (−ray direction) */
    vec3 dPdu, dPdv;         /* surface tangents along the UV map's u and v (scene units per UV unit) */
    float u, v;              /* the active UV map */
    vec3 generated;          /* object-space position in the mesh's texture space, [0,1]³ */
    vec3 generated_scale;    /* d generated / d object_P per axis: ½ / texture-space size */
    vec3 tangent;            /* the UV map's MikkTSpace tangent, world space, or 0 without one */
    float tangent_sign;      /* ±1: the bitangent is sign · N × tangent */
    vec3 object_P;           /* object-space position */
    const float *object_to_world;   /* row-major 3x4, NULL for the world */
    const float *world_to_object;   /* row-major 3x4 */
    const float *normal_to_world;   /* 3x3 inverse transpose of object_to_world */
    const float *camera_to_world;   /* row-major 3x4 */
    const float *world_to_camera;   /* row-major 3x4 */
    vec3 window;             /* the point's position in the camera's frame, [0,1]² and 0 */
    vec3 object_location;    /* the instance's origin */
    float object_random;     /* Object Info's Random, in [0,1) */
    float object_index;      /* Object Info's Object Index (pass index) */
    int backfacing;
    int background;          /* the world's shader: P is a direction, not a point */
    uint32_t ray_flags;      /* enum shader_ray_flags of the ray that found the point */
    float ray_length;        /* scene units */
    uint32_t ray_depth, transparent_depth;
    vec3 dPdx, dPdy;         /* position differentials: the pixel's footprint along two orthogonal axes
                                of the plane ⊥ Ng (scene units), the steps of Bump (Cycles' sd->dP) */
    const struct mesh *mesh; /* the mesh hit and where on it (attributes), or NULL */
    uint32_t prim;           /* triangle */
    float b1, b2;            /* barycentric weights of corners 1 and 2 */
    uint32_t diffuse_depth, glossy_depth, transmission_depth; /* surface.h: by kind of event */
} shader_globals;

enum shader_ray_flags {
    SHADER_RAY_CAMERA = 1 << 0,
    SHADER_RAY_SHADOW = 1 << 1,
    SHADER_RAY_DIFFUSE = 1 << 2,
    SHADER_RAY_GLOSSY = 1 << 3,
    SHADER_RAY_SINGULAR = 1 << 4,
    SHADER_RAY_REFLECT = 1 << 5,
    SHADER_RAY_TRANSMIT = 1 << 6,
    /* Not a kind of ray: the world's sky sun is a light of its own
     * (lights/environment.c), so the Sky Texture leaves its disc out. */
    SHADER_RAY_SKY_SUN_AS_LIGHT = 1 << 7
};

/* A program as the core keeps it: validated, folded, owned. */
typedef struct shader_program {
    uint32_t register_count;
    uint32_t constant_count;
    float *constants;
    uint32_t instruction_count;
    phos_shader_instruction *instructions;
    uint32_t table_size;
    float *table;
    uint32_t binding_count;
    phos_shader_binding *bindings;
    uint32_t needs;                 /* enum shader_needs: what the globals must hold */
} shader_program;

/* The costlier parts of shader_globals, filled only for a program that
 * reads them. */
enum shader_needs {
    SHADER_NEEDS_UV_TANGENTS = 1 << 0, /* dPdu, dPdv and the position differentials (Bump) */
    SHADER_NEEDS_TANGENT = 1 << 1,     /* the MikkTSpace tangent (Normal Map) */
    SHADER_NEEDS_WINDOW = 1 << 2,      /* window coordinates (Texture Coordinate's Window) */
    SHADER_NEEDS_ATTRIBUTES = 1 << 3   /* the mesh and the point on it (Attribute) */
};

/* The state one op sees. */
typedef struct shader_context {
    float *r;                       /* the register file */
    const shader_globals *g;
    const shader_program *program;
    const struct phos_scene *scene;      /* images */
} shader_context;

typedef void (*shader_op_fn)(const phos_shader_instruction *ins, shader_context *ctx);

static inline float shader_in(const shader_context *c, const phos_shader_instruction *ins, int k)
{
    return c->r[ins->inputs[k]];
}
static inline vec3 shader_in3(const shader_context *c, const phos_shader_instruction *ins, int k)
{
    return v3_load(c->r + ins->inputs[k]);
}
static inline void shader_out(shader_context *c, const phos_shader_instruction *ins, int k, float x)
{
    if (ins->outputs[k] != PHOS_SHADER_NO_REGISTER)
        c->r[ins->outputs[k]] = x;
}
static inline void shader_out3(shader_context *c, const phos_shader_instruction *ins, int k, vec3 x)
{
    if (ins->outputs[k] != PHOS_SHADER_NO_REGISTER) {
        float *o = c->r + ins->outputs[k];
        o[0] = x.x;
        o[1] = x.y;
        o[2] = x.z;
    }
}
/* A world-space normal in object space, normalised: normals map to world
 * by the inverse transpose of the object's matrix M, so back by Mᵀ. */
static inline vec3 shader_normal_to_object(const shader_globals *g, vec3 n)
{
    const float *m = g->object_to_world;
    if (!m)
        return n;
    vec3 o = v3(m[0] * n.x + m[4] * n.y + m[8] * n.z, m[1] * n.x + m[5] * n.y + m[9] * n.z,
                m[2] * n.x + m[6] * n.y + m[10] * n.z);
    float l = v3_length(o);
    return l > 0.0f ? v3_scale(o, 1.0f / l) : o;
}

#define SHADER_IN(k) shader_in(ctx, ins, (k))
#define SHADER_IN3(k) shader_in3(ctx, ins, (k))
#define SHADER_OUT(k, x) shader_out(ctx, ins, (k), (x))
#define SHADER_OUT3(k, x) shader_out3(ctx, ins, (k), (x))

/* One op's description: how wide each socket is (0 = absent), whether it
 * reads the shading point (otherwise it is a pure function of its inputs
 * and folds when they are constant), and how many enum values `mode` has. */
typedef struct shader_op_info {
    const char *name;
    shader_op_fn fn;
    uint8_t in_width[PHOS_SHADER_MAX_INPUTS];
    uint8_t out_width[PHOS_SHADER_MAX_OUTPUTS];
    uint8_t reads_globals;
    uint32_t mode_count;     /* mode < mode_count; 0 = mode unchecked (op validates it) */
} shader_op_info;

extern const shader_op_info shader_ops[PHOS_OP_COUNT];

/* Validates a program desc against a scene's images and a material's
 * closure count, copies and folds it into *out. Returns NULL on success or
 * a message naming what is wrong (written into msg, of size n). */
const char *shader_program_create(const phos_shader_program_desc *d, uint32_t closure_count, uint32_t image_count,
                                  shader_program *out, char *msg, size_t n);
void shader_program_free(shader_program *p);

/* Folds what does not depend on the shading point (s: the scene's images,
 * for an image looked up at a constant vector). Bindings that became
 * constant are moved to baked[] (*baked_count of them) with their values
 * in values[] (indexed by register; register_count floats), for the
 * caller to write into the closures. */
void shader_program_fold(shader_program *p, const struct phos_scene *s, float *values, phos_shader_binding *baked,
                         uint32_t *baked_count);

/* Width of an enum phos_closure_field (0 for an unknown one). */
uint32_t shader_field_width(uint32_t field);

/* Runs the program at a shading point. r holds register_count floats. */
void shader_program_eval(const shader_program *p, const struct phos_scene *s, const shader_globals *g, float *r);

/* The node families' ops (shading/nodes/). */
void shader_op_math(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_vector_math(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_mix_float(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_mix_vector(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_mix_color(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_map_range(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_map_range_vector(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_clamp(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_ramp(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_curves_rgb(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_curves_vector(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_curve_float(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_hue_saturation(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_bright_contrast(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_gamma(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_invert(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_separate_color(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_combine_color(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_combine_xyz(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_rgb_to_bw(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_blackbody(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_wavelength(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_image(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_sky(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_noise(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_musgrave(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_white_noise(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_voronoi(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_wave(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_brick(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_checker(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_magic(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tex_gradient(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_texture_coordinate(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_geometry(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_object_info(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_tangent(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_fresnel(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_layer_weight(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_light_path(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_mapping(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_normal_map(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_bump(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_bump_offset(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_vector_rotate(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_vector_transform(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_normal(const phos_shader_instruction *ins, shader_context *ctx);
void shader_op_attribute(const phos_shader_instruction *ins, shader_context *ctx);

/* The two steps a Bump evaluates its height at (world space, in the
 * plane ⊥ Ng): the position differentials times the filter width, the
 * fraction of the pixel's footprint the Blender version steps
 * (shading/nodes/vector.c). */
void shader_bump_steps(float filter_width, const shader_globals *g, vec3 *dx, vec3 *dy);

/* The MikkTSpace tangent of a UV map other than the render one, from the
 * mesh attribute `id` (object-space x, y, z and the bitangent sign per
 * corner): in world space, perpendicular to the shading normal and unit,
 * as material_shader_globals makes the render map's. 0 when the mesh has
 * no such attribute. */

int shader_attribute_tangent(const shader_globals *g, uint32_t id, vec3 *tangent, float *sign);

#endif /* PHOS_SHADER_PROGRAM_H */
