/*
 * shader_program.c — validation, constant folding and evaluation of the
 * compiled node programs (docs/architecture.md, "Shader programs").
 *
 * The op table below is the one place that says how wide each socket of
 * each op is and whether the op reads the shading point; validation and
 * folding both follow it, and the node families in shading/nodes/
 * implement the ops.
 */
#include "shading/shader_program.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shading/sky/sky.h"

#define W1 1
#define W3 3

/* Socket widths in the order of phos.h's comments. */
const shader_op_info shader_ops[PHOS_OP_COUNT] = {
    [PHOS_OP_MATH] = {"Math", shader_op_math, {W1, W1, W1}, {W1}, 0, PHOS_MATH_COUNT},
    [PHOS_OP_VECTOR_MATH] = {"Vector Math", shader_op_vector_math, {W3, W3, W3, W1}, {W3, W1}, 0,
                             PHOS_VECTOR_MATH_COUNT},
    [PHOS_OP_MIX_FLOAT] = {"Mix (float)", shader_op_mix_float, {W1, W1, W1}, {W1}, 0, 0},
    [PHOS_OP_MIX_VECTOR] = {"Mix (vector)", shader_op_mix_vector, {W3, W3, W3}, {W3}, 0, 0},
    [PHOS_OP_MIX_COLOR] = {"Mix (colour)", shader_op_mix_color, {W1, W3, W3}, {W3}, 0, PHOS_BLEND_COUNT},
    [PHOS_OP_MAP_RANGE] = {"Map Range", shader_op_map_range, {W1, W1, W1, W1, W1, W1}, {W1}, 0,
                           PHOS_MAP_RANGE_COUNT},
    [PHOS_OP_MAP_RANGE_VECTOR] = {"Map Range (vector)", shader_op_map_range_vector, {W3, W3, W3, W3, W3, W3},
                                  {W3}, 0, PHOS_MAP_RANGE_COUNT},
    [PHOS_OP_CLAMP] = {"Clamp", shader_op_clamp, {W1, W1, W1}, {W1}, 0, PHOS_CLAMP_COUNT},
    [PHOS_OP_RAMP] = {"Color Ramp", shader_op_ramp, {W1}, {W3, W1}, 0, 0},
    [PHOS_OP_CURVES_RGB] = {"RGB Curves", shader_op_curves_rgb, {W1, W3}, {W3}, 0, 0},
    [PHOS_OP_CURVES_VECTOR] = {"Vector Curves", shader_op_curves_vector, {W1, W3}, {W3}, 0, 0},
    [PHOS_OP_CURVE_FLOAT] = {"Float Curve", shader_op_curve_float, {W1, W1}, {W1}, 0, 0},
    [PHOS_OP_HUE_SATURATION] = {"Hue/Saturation/Value", shader_op_hue_saturation, {W1, W1, W1, W1, W3}, {W3}, 0,
                                0},
    [PHOS_OP_BRIGHT_CONTRAST] = {"Brightness/Contrast", shader_op_bright_contrast, {W3, W1, W1}, {W3}, 0, 0},
    [PHOS_OP_GAMMA] = {"Gamma", shader_op_gamma, {W3, W1}, {W3}, 0, 0},
    [PHOS_OP_INVERT] = {"Invert Color", shader_op_invert, {W1, W3}, {W3}, 0, 0},
    [PHOS_OP_SEPARATE_COLOR] = {"Separate Color", shader_op_separate_color, {W3}, {W3}, 0, PHOS_COLOR_MODEL_COUNT},
    [PHOS_OP_COMBINE_COLOR] = {"Combine Color", shader_op_combine_color, {W1, W1, W1}, {W3}, 0,
                               PHOS_COLOR_MODEL_COUNT},
    [PHOS_OP_COMBINE_XYZ] = {"Combine XYZ", shader_op_combine_xyz, {W1, W1, W1}, {W3}, 0, 0},
    [PHOS_OP_RGB_TO_BW] = {"RGB to BW", shader_op_rgb_to_bw, {W3}, {W1}, 0, 0},
    [PHOS_OP_BLACKBODY] = {"Blackbody", shader_op_blackbody, {W1}, {W3}, 0, 0},
    [PHOS_OP_WAVELENGTH] = {"Wavelength", shader_op_wavelength, {W1}, {W3}, 0, 0},
    [PHOS_OP_TEX_IMAGE] = {"Image Texture", shader_op_tex_image, {W3}, {W3, W1}, 0, PHOS_PROJECTION_COUNT},
    [PHOS_OP_TEX_NOISE] = {"Noise Texture", shader_op_tex_noise, {W3, W1, W1, W1, W1, W1, W1, W1, W1}, {W1, W3},
                           0, PHOS_NOISE_COUNT},
    [PHOS_OP_TEX_MUSGRAVE] = {"Musgrave Texture", shader_op_tex_musgrave, {W3, W1, W1, W1, W1, W1, W1, W1}, {W1},
                              0, PHOS_NOISE_COUNT},
    [PHOS_OP_TEX_WHITE_NOISE] = {"White Noise Texture", shader_op_tex_white_noise, {W3, W1}, {W1, W3}, 0, 0},
    [PHOS_OP_TEX_VORONOI] = {"Voronoi Texture", shader_op_tex_voronoi, {W3, W1, W1, W1, W1, W1, W1, W1, W1},
                             {W1, W3, W3, W1, W1}, 0, PHOS_VORONOI_FEATURE_COUNT},
    [PHOS_OP_TEX_WAVE] = {"Wave Texture", shader_op_tex_wave, {W3, W1, W1, W1, W1, W1, W1}, {W3, W1}, 0,
                          PHOS_WAVE_TYPE_COUNT},
    [PHOS_OP_TEX_BRICK] = {"Brick Texture", shader_op_tex_brick, {W3, W3, W3, W3, W1, W1, W1, W1, W1, W1},
                           {W3, W1}, 0, 0},
    [PHOS_OP_TEX_CHECKER] = {"Checker Texture", shader_op_tex_checker, {W3, W3, W3, W1}, {W3, W1}, 0, 0},
    [PHOS_OP_TEX_MAGIC] = {"Magic Texture", shader_op_tex_magic, {W3, W1, W1}, {W3, W1}, 0, 11},
    [PHOS_OP_TEX_GRADIENT] = {"Gradient Texture", shader_op_tex_gradient, {W3}, {W3, W1}, 0, PHOS_GRADIENT_COUNT},
    [PHOS_OP_TEXTURE_COORDINATE] = {"Texture Coordinate", shader_op_texture_coordinate, {0},
                                    {W3, W3, W3, W3, W3}, 1, 2},
    [PHOS_OP_GEOMETRY] = {"Geometry", shader_op_geometry, {0}, {W3, W3, W3, W3, W1}, 1, 0},
    [PHOS_OP_OBJECT_INFO] = {"Object Info", shader_op_object_info, {0}, {W3, W1, W1}, 1, 0},
    [PHOS_OP_FRESNEL] = {"Fresnel", shader_op_fresnel, {W1, W3}, {W1}, 1, 0},
    [PHOS_OP_LAYER_WEIGHT] = {"Layer Weight", shader_op_layer_weight, {W1, W3}, {W1, W1}, 1, 0},
    [PHOS_OP_LIGHT_PATH] = {"Light Path", shader_op_light_path, {0}, {W1, W1, W1, W1, W1}, 1, 3},
    [PHOS_OP_MAPPING] = {"Mapping", shader_op_mapping, {W3, W3, W3, W3}, {W3}, 0, PHOS_MAPPING_COUNT},
    [PHOS_OP_NORMAL_MAP] = {"Normal Map", shader_op_normal_map, {W1, W3}, {W3}, 1, PHOS_NORMAL_MAP_COUNT},
    [PHOS_OP_BUMP] = {"Bump", shader_op_bump, {W1, W1, W1, W1, W1, W3}, {W3}, 1, 0},
    [PHOS_OP_BUMP_OFFSET] = {"Bump offset", shader_op_bump_offset, {0}, {W3, W3, W3, W3, W3}, 1, 3},
    [PHOS_OP_VECTOR_ROTATE] = {"Vector Rotate", shader_op_vector_rotate, {W3, W3, W3, W1, W3}, {W3}, 0,
                               PHOS_VECTOR_ROTATE_COUNT},
    [PHOS_OP_VECTOR_TRANSFORM] = {"Vector Transform", shader_op_vector_transform, {W3}, {W3}, 1,
                                  PHOS_VECTOR_TRANSFORM_COUNT},
    [PHOS_OP_NORMAL] = {"Normal", shader_op_normal, {W3}, {W3, W1}, 0, 0},
    [PHOS_OP_ATTRIBUTE] = {"Attribute", shader_op_attribute, {0}, {W3, W3, W1, W1}, 1, 3},
    [PHOS_OP_TANGENT] = {"Tangent", shader_op_tangent, {0}, {W3}, 1, PHOS_TANGENT_COUNT},
    /* Reads the ray's flags: the sun's disc is left out when it is a light. */
    [PHOS_OP_TEX_SKY] = {"Sky Texture", shader_op_tex_sky, {W3}, {W3}, 1, PHOS_SKY_MODEL_COUNT},
};

/* Width of each closure field (phos.h, enum phos_closure_field). */
static const uint8_t field_width[PHOS_FIELD_COUNT] = {
    [PHOS_FIELD_WEIGHT] = 3, [PHOS_FIELD_ROUGHNESS] = 1, [PHOS_FIELD_IOR] = 1, [PHOS_FIELD_SPECULAR_COLOR] = 3,
    [PHOS_FIELD_TRANSMISSION_TINT] = 3, [PHOS_FIELD_TRANSMISSION_ROUGHNESS] = 1,
    [PHOS_FIELD_MULTISCATTER_FRESNEL] = 3, [PHOS_FIELD_SPECULAR_TINT] = 3, [PHOS_FIELD_THIN_FILM_THICKNESS] = 1,
    [PHOS_FIELD_THIN_FILM_IOR] = 1, [PHOS_FIELD_LAYER_WEIGHT] = 3, [PHOS_FIELD_LAYER_TINT] = 3,
    [PHOS_FIELD_LAYER_TINT_WEIGHT] = 1, [PHOS_FIELD_NORMAL] = 3, [PHOS_FIELD_ROUGHNESS_Y] = 1,
    [PHOS_FIELD_TANGENT_ROTATION] = 1, [PHOS_FIELD_TANGENT] = 3,
};

uint32_t shader_field_width(uint32_t field) { return field < PHOS_FIELD_COUNT ? field_width[field] : 0; }

/* Width of input k of an instruction (MIX_VECTOR's factor is 1 or 3 wide). */
static uint32_t in_width(const phos_shader_instruction *ins, int k)
{
    if (ins->op == PHOS_OP_MIX_VECTOR && k == 0)
        return (ins->flags & 4) ? 3 : 1;
    return shader_ops[ins->op].in_width[k];
}

/* ------------------------------------------------------------ validation */

#define BAD(...) (snprintf(msg, n, __VA_ARGS__), msg)

static int in_range(uint32_t reg, uint32_t width, uint32_t count)
{
    return reg < count && width <= count - reg;
}

/* Whether registers [reg, reg+width) are all set (bit per register). */
static int all_set(const uint8_t *set, uint32_t reg, uint32_t width)
{
    for (uint32_t k = 0; k < width; k++)
        if (!set[reg + k])
            return 0;
    return 1;
}

/* A Sky Texture's data lies within the table, and the scattering models'
 * data names a texture layout and an image of the scene. */
static const char *validate_sky(const phos_shader_program_desc *d, const phos_shader_instruction *ins,
                                uint32_t image_count)
{
    if (ins->table > d->table_size || d->table_size - ins->table < PHOS_SKY_DATA_FLOATS)
        return "reads its data beyond the program's table";
    if (!sky_model_textured(ins->mode))
        return NULL;
    float layout = d->table[ins->table + SKY_LAYOUT];
    if (!(layout == (float)PHOS_SKY_LAYOUT_HEMISPHERE || layout == (float)PHOS_SKY_LAYOUT_SPHERE))
        return "names no texture layout";
    float id = d->table[ins->table + PHOS_SKY_DATA_IMAGE];
    if (!(id >= 0.0f && id < (float)image_count && id == floorf(id)))
        return "refers to a texture that is not an image of the scene";
    return NULL;
}

static const char *validate_instruction(const phos_shader_program_desc *d, uint32_t i, uint32_t image_count,
                                        uint8_t *set, char *msg, size_t n)
{
    const phos_shader_instruction *ins = &d->instructions[i];
    if (ins->op >= PHOS_OP_COUNT)
        return BAD("instruction %u has unknown op %u", i, ins->op);
    const shader_op_info *op = &shader_ops[ins->op];
    if (op->mode_count && ins->mode >= op->mode_count)
        return BAD("instruction %u (%s) has unknown mode %u", i, op->name, ins->mode);
    for (int k = 0; k < 4; k++)
        if (!isfinite(ins->param[k]))
            return BAD("instruction %u (%s) has a non-finite parameter", i, op->name);
    if ((ins->op == PHOS_OP_BUMP || ins->op == PHOS_OP_BUMP_OFFSET) && ins->param[0] < 0.0f)
        return BAD("instruction %u (%s) has a negative filter width %g", i, op->name, (double)ins->param[0]);
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++) {
        uint32_t w = in_width(ins, k);
        if (!w)
            continue;
        if (!in_range(ins->inputs[k], w, d->register_count))
            return BAD("instruction %u (%s) reads register %u, beyond the %u registers", i, op->name, ins->inputs[k],
                       d->register_count);
        if (!all_set(set, ins->inputs[k], w))
            return BAD("instruction %u (%s) reads register %u before any instruction writes it", i, op->name,
                       ins->inputs[k]);
    }
    if (ins->op == PHOS_OP_TEX_IMAGE && ins->table >= image_count)
        return BAD("instruction %u (%s) refers to image %u, but the scene has %u images", i, op->name, ins->table,
                   image_count);
    if ((ins->op == PHOS_OP_RAMP || ins->op == PHOS_OP_CURVES_RGB || ins->op == PHOS_OP_CURVES_VECTOR ||
         ins->op == PHOS_OP_CURVE_FLOAT)) {
        uint32_t floats = 4; /* RGBA, or a curve's (r, g, b, ·) / (x, y, z, ·) / (value, ·, ·, ·) */
        if (ins->mode < 2 || ins->mode > PHOS_SHADER_MAX_TABLE / floats || ins->table > d->table_size ||
            ins->mode * floats > d->table_size - ins->table)
            return BAD("instruction %u (%s) reads %u table entries at %u, beyond the table of %u floats", i,
                       op->name, ins->mode, ins->table, d->table_size);
    }
    if (ins->op == PHOS_OP_TEX_SKY) {
        const char *bad = validate_sky(d, ins, image_count);
        if (bad)
            return BAD("instruction %u (%s) %s", i, op->name, bad);
    }
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++) {
        uint32_t w = op->out_width[k];
        if (!w || ins->outputs[k] == PHOS_SHADER_NO_REGISTER)
            continue;
        if (!in_range(ins->outputs[k], w, d->register_count) || ins->outputs[k] < d->constant_count)
            return BAD("instruction %u (%s) writes register %u, outside [%u, %u)", i, op->name, ins->outputs[k],
                       d->constant_count, d->register_count);
    }
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        if (op->out_width[k] && ins->outputs[k] != PHOS_SHADER_NO_REGISTER)
            memset(set + ins->outputs[k], 1, op->out_width[k]);
    return NULL;
}

static const char *validate(const phos_shader_program_desc *d, uint32_t closure_count, uint32_t image_count,
                            uint8_t *set, char *msg, size_t n)
{
    if (d->register_count > PHOS_SHADER_MAX_REGISTERS || d->constant_count > d->register_count)
        return BAD("%u registers and %u constants; at most %d registers, constants among them", d->register_count,
                   d->constant_count, PHOS_SHADER_MAX_REGISTERS);
    if (d->instruction_count > PHOS_SHADER_MAX_INSTRUCTIONS)
        return BAD("%u instructions, at most %d", d->instruction_count, PHOS_SHADER_MAX_INSTRUCTIONS);
    if (d->table_size > PHOS_SHADER_MAX_TABLE)
        return BAD("a table of %u floats, at most %d", d->table_size, PHOS_SHADER_MAX_TABLE);
    if ((d->constant_count && !d->constants) || (d->instruction_count && !d->instructions) ||
        (d->table_size && !d->table) || (d->binding_count && !d->bindings))
        return "an array is NULL";
    for (uint32_t k = 0; k < d->constant_count; k++)
        if (!isfinite(d->constants[k]))
            return BAD("constant %u is not finite", k);
    for (uint32_t k = 0; k < d->table_size; k++)
        if (!isfinite(d->table[k]))
            return BAD("table entry %u is not finite", k);
    memset(set, 0, d->register_count);
    memset(set, 1, d->constant_count);
    for (uint32_t i = 0; i < d->instruction_count; i++) {
        const char *bad = validate_instruction(d, i, image_count, set, msg, n);
        if (bad)
            return bad;
    }
    for (uint32_t b = 0; b < d->binding_count; b++) {
        const phos_shader_binding *bd = &d->bindings[b];
        if (bd->closure >= closure_count)
            return BAD("binding %u sets closure %u of %u", b, bd->closure, closure_count);
        if (bd->field >= PHOS_FIELD_COUNT)
            return BAD("binding %u has unknown field %u", b, bd->field);
        if (!in_range(bd->reg, field_width[bd->field], d->register_count) ||
            !all_set(set, bd->reg, field_width[bd->field]))
            return BAD("binding %u reads register %u, which no instruction writes", b, bd->reg);
    }
    return NULL;
}

/* --------------------------------------------------------------- folding */

/* Whether every input of an instruction is known when the material is added. */
static int inputs_known(const phos_shader_instruction *ins, const uint8_t *known)
{
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++) {
        uint32_t w = in_width(ins, k);
        if (w && !all_set(known, ins->inputs[k], w))
            return 0;
    }
    return 1;
}

/*
 * Constant folding: an op that does not read the shading point and whose
 * inputs are all known runs once here, on a register file that holds the
 * constants and every folded result; the instruction is then dropped and
 * its outputs become constants. Registers keep their numbers, so the
 * constants of a folded program are the whole known prefix of values.
 */
static void fold(shader_program *p, const struct phos_scene *s, float *r, uint8_t *known)
{
    uint32_t kept = 0;
    shader_globals none;
    memset(&none, 0, sizeof(none));
    shader_context ctx = {r, &none, p, s};
    for (uint32_t i = 0; i < p->instruction_count; i++) {
        phos_shader_instruction *ins = &p->instructions[i];
        const shader_op_info *op = &shader_ops[ins->op];
        if (!op->reads_globals && inputs_known(ins, known)) {
            op->fn(ins, &ctx);
            for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
                if (op->out_width[k] && ins->outputs[k] != PHOS_SHADER_NO_REGISTER)
                    memset(known + ins->outputs[k], 1, op->out_width[k]);
            continue;
        }
        p->instructions[kept++] = *ins;
    }
    p->instruction_count = kept;
}

/* A binding whose value is known can be written into its closure once;
 * a normal or tangent sets the closure's frame, not a field, and stays a
 * binding. */
static int bakeable(const phos_shader_binding *bd, const uint8_t *known)
{
    return bd->field != PHOS_FIELD_NORMAL && bd->field != PHOS_FIELD_TANGENT &&
           all_set(known, bd->reg, field_width[bd->field]);
}

/* Bindings whose registers are all known: their values, for the caller to
 * bake into the closures; the rest stay. Returns how many were baked. */
static uint32_t split_constant_bindings(shader_program *p, const uint8_t *known)
{
    uint32_t kept = 0, baked = 0;
    for (uint32_t b = 0; b < p->binding_count; b++) {
        phos_shader_binding bd = p->bindings[b];
        if (bakeable(&bd, known)) {
            baked++;
            continue;
        }
        p->bindings[kept++] = bd;
    }
    p->binding_count = kept;
    return baked;
}

/* Which costlier globals the program's instructions read. */
static void shader_program_needs(shader_program *p)
{
    p->needs = 0;
    for (uint32_t i = 0; i < p->instruction_count; i++) {
        const phos_shader_instruction *ins = &p->instructions[i];
        if (ins->op == PHOS_OP_BUMP || ins->op == PHOS_OP_BUMP_OFFSET)
            p->needs |= SHADER_NEEDS_UV_TANGENTS;
        else if (ins->op == PHOS_OP_NORMAL_MAP)
            p->needs |= (ins->flags & 2) ? SHADER_NEEDS_ATTRIBUTES : SHADER_NEEDS_TANGENT;
        else if (ins->op == PHOS_OP_TANGENT && ins->mode == PHOS_TANGENT_UV_MAP)
            p->needs |= SHADER_NEEDS_TANGENT;
        else if (ins->op == PHOS_OP_TEXTURE_COORDINATE && ins->mode == 1)
            p->needs |= SHADER_NEEDS_WINDOW;
        else if (ins->op == PHOS_OP_ATTRIBUTE)
            p->needs |= SHADER_NEEDS_ATTRIBUTES;
    }
}

const char *shader_program_create(const phos_shader_program_desc *d, uint32_t closure_count, uint32_t image_count,
                                  shader_program *out, char *msg, size_t n)
{
    memset(out, 0, sizeof(*out));
    uint8_t *set = malloc(d->register_count ? d->register_count : 1);
    if (!set)
        return "out of memory";
    const char *bad = validate(d, closure_count, image_count, set, msg, n);
    free(set);
    if (bad)
        return bad;
    out->register_count = d->register_count;
    out->constant_count = d->constant_count;
    out->instruction_count = d->instruction_count;
    out->table_size = d->table_size;
    out->binding_count = d->binding_count;
    out->constants = malloc(sizeof(float) * (d->register_count ? d->register_count : 1));
    out->instructions = malloc(sizeof(phos_shader_instruction) * (d->instruction_count ? d->instruction_count : 1));
    out->table = malloc(sizeof(float) * (d->table_size ? d->table_size : 1));
    out->bindings = malloc(sizeof(phos_shader_binding) * (d->binding_count ? d->binding_count : 1));
    if (!out->constants || !out->instructions || !out->table || !out->bindings) {
        shader_program_free(out);
        return "out of memory";
    }
    memset(out->constants, 0, sizeof(float) * d->register_count);
    if (d->constant_count)
        memcpy(out->constants, d->constants, sizeof(float) * d->constant_count);
    if (d->instruction_count)
        memcpy(out->instructions, d->instructions, sizeof(phos_shader_instruction) * d->instruction_count);
    if (d->table_size)
        memcpy(out->table, d->table, sizeof(float) * d->table_size);
    if (d->binding_count)
        memcpy(out->bindings, d->bindings, sizeof(phos_shader_binding) * d->binding_count);
    shader_program_needs(out);
    return NULL;
}

void shader_program_fold(shader_program *p, const struct phos_scene *s, float *baked_registers, phos_shader_binding *baked,
                         uint32_t *baked_count)
{
    uint8_t *known = calloc(p->register_count ? p->register_count : 1, 1);
    if (!known) {
        *baked_count = 0;
        return; /* nothing folds: the program runs unfolded, with the same result */
    }
    memset(known, 1, p->constant_count);
    memcpy(baked_registers, p->constants, sizeof(float) * p->register_count);
    fold(p, s, baked_registers, known);
    /* The folded values become the constants every evaluation starts from. */
    memcpy(p->constants, baked_registers, sizeof(float) * p->register_count);
    uint32_t count = 0;
    for (uint32_t b = 0; b < p->binding_count; b++)
        if (bakeable(&p->bindings[b], known))
            baked[count++] = p->bindings[b];
    split_constant_bindings(p, known);
    *baked_count = count;
    /* Registers that are known are now constants: the evaluation copies
     * the whole prefix up to the highest known register. */
    uint32_t prefix = 0;
    for (uint32_t k = 0; k < p->register_count; k++)
        if (known[k])
            prefix = k + 1;
    p->constant_count = prefix;
    free(known);
}

void shader_program_free(shader_program *p)
{
    free(p->constants);
    free(p->instructions);
    free(p->table);
    free(p->bindings);
    memset(p, 0, sizeof(*p));
}

/* ------------------------------------------------------------ evaluation */

void shader_program_eval(const shader_program *p, const struct phos_scene *s, const shader_globals *g, float *r)
{
    if (p->constant_count) /* a program without constants may have no array (memcpy's NULL is undefined) */
        memcpy(r, p->constants, sizeof(float) * p->constant_count);
    shader_context ctx = {r, g, p, s};
    for (uint32_t i = 0; i < p->instruction_count; i++) {
        const phos_shader_instruction *ins = &p->instructions[i];
        shader_ops[ins->op].fn(ins, &ctx);
    }
}
