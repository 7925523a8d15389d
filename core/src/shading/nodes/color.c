/*
 * color.c — the Color nodes of a shader program, and the colour Converter
 * nodes: Mix (float, vector, colour, and the legacy MixRGB), Hue/Saturation/
 * Value, Bright/Contrast, Gamma, Invert, Separate/Combine Color, RGB to BW,
 * Blackbody, Wavelength, ColorRamp, RGB Curves, Vector Curves and Float
 * Curve, evaluated as Cycles evaluates them (the Blender manual, "Shader
 * Nodes > Color" and "> Converter"). Colours are scene-linear Rec. 709.
 *
 * Blender 4.3 changed Hue/Saturation/Value's hue wrap; the add-on sets
 * PHOS_NODE_PRE_4_3 (node_util.h) on HUE_SATURATION for older versions.
 */
#include "shading/color_space.h"
#include "shading/nodes/node_util.h"
#include "shading/shader_program.h"

#define MIX_CLAMP_RESULT 1u
#define MIX_CLAMP_FACTOR 2u
#define MIX_FACTOR_VECTOR 4u
#define RAMP_CONSTANT 8u
#define CURVES_EXTRAPOLATE 1u

/* ------------------------------------------------------------ HSV and HSL */

/* Hue, saturation and value of linear RGB, each in [0,1] for colours in
 * [0,1] (Smith 1978, "Color gamut transform pairs"): v = max, s = (max −
 * min)/max, h by the sextant of the largest component; h = s = 0 for greys
 * and black. */
static vec3 rgb_to_hsv(vec3 c)
{
    float hi = fmaxf(c.x, fmaxf(c.y, c.z));
    float lo = node_min(c.x, node_min(c.y, c.z));
    float delta = hi - lo;
    float s = hi != 0.0f ? delta / hi : 0.0f;
    float h = 0.0f;
    if (s != 0.0f) {
        /* Distances of each component below the maximum, in units of delta. */
        float dr = (hi - c.x) / delta, dg = (hi - c.y) / delta, db = (hi - c.z) / delta;
        if (c.x == hi)
            h = db - dg;
        else if (c.y == hi)
            h = 2.0f + dr - db;
        else
            h = 4.0f + dg - dr;
        h /= 6.0f;
        if (h < 0.0f)
            h += 1.0f;
    }
    return v3(h, s, hi);
}

/* The inverse: h = 1 is h = 0; sextant i = ⌊6h⌋ and f = 6h − i pick two of
 * p = v(1 − s), q = v(1 − sf), t = v(1 − s(1 − f)) and v. A hue outside
 * [0,1) falls in the last sextant. */
static vec3 hsv_to_rgb(vec3 hsv)
{
    float h = hsv.x, s = hsv.y, v = hsv.z;
    if (s == 0.0f)
        return v3s(v);
    if (h == 1.0f)
        h = 0.0f;
    h *= 6.0f;
    float i = floorf(h);
    float f = h - i;
    float p = v * (1.0f - s);
    float q = v * (1.0f - s * f);
    float t = v * (1.0f - s * (1.0f - f));
    if (i == 0.0f)
        return v3(v, t, p);
    if (i == 1.0f)
        return v3(q, v, p);
    if (i == 2.0f)
        return v3(p, v, t);
    if (i == 3.0f)
        return v3(p, q, v);
    if (i == 4.0f)
        return v3(t, p, v);
    return v3(v, p, q);
}

/* Hue, saturation and lightness: l = min(1, (max + min)/2); s = Δ/(max + min)
 * for l <= 1/2, else Δ/(2 − max − min); h as for HSV. */
static vec3 rgb_to_hsl(vec3 c)
{
    float hi = fmaxf(c.x, fmaxf(c.y, c.z));
    float lo = node_min(c.x, node_min(c.y, c.z));
    float l = node_min(1.0f, (hi + lo) / 2.0f);
    float h = 0.0f, s = 0.0f;
    if (hi != lo) {
        float delta = hi - lo;
        s = l > 0.5f ? delta / (2.0f - hi - lo) : delta / (hi + lo);
        if (hi == c.x)
            h = (c.y - c.z) / delta + (c.y < c.z ? 6.0f : 0.0f);
        else if (hi == c.y)
            h = (c.z - c.x) / delta + 2.0f;
        else
            h = (c.x - c.y) / delta + 4.0f;
    }
    return v3(h / 6.0f, s, l);
}

/* The inverse through the hue's piecewise-linear RGB ramps, each clamped to
 * [0,1]: component = (ramp − 1/2)·chroma + l, chroma = (1 − |2l − 1|)·s. */
static vec3 hsl_to_rgb(vec3 hsl)
{
    float h = hsl.x, s = hsl.y, l = hsl.z;
    float r = node_clamp(fabsf(h * 6.0f - 3.0f) - 1.0f, 0.0f, 1.0f);
    float g = node_clamp(2.0f - fabsf(h * 6.0f - 2.0f), 0.0f, 1.0f);
    float b = node_clamp(2.0f - fabsf(h * 6.0f - 4.0f), 0.0f, 1.0f);
    float chroma = (1.0f - fabsf(2.0f * l - 1.0f)) * s;
    return v3((r - 0.5f) * chroma + l, (g - 0.5f) * chroma + l, (b - 0.5f) * chroma + l);
}

/* ------------------------------------------------------------------- Mix */

/* a + t(b − a). */
static inline vec3 lerp3(vec3 a, vec3 b, float t) { return v3_add(a, v3_scale(v3_sub(b, a), t)); }
static inline vec3 min3(vec3 a, vec3 b) { return v3(node_min(a.x, b.x), node_min(a.y, b.y), node_min(a.z, b.z)); }
static inline vec3 max3(vec3 a, vec3 b) { return v3(node_max(a.x, b.x), node_max(a.y, b.y), node_max(a.z, b.z)); }
static inline vec3 abs3(vec3 a) { return v3(fabsf(a.x), fabsf(a.y), fabsf(a.z)); }

/* Screen: 1 − ((1 − t) + t(1 − b))(1 − a). */
static vec3 blend_screen(float t, vec3 a, vec3 b)
{
    float tm = 1.0f - t;
    return v3(1.0f - (tm + t * (1.0f - b.x)) * (1.0f - a.x), 1.0f - (tm + t * (1.0f - b.y)) * (1.0f - a.y),
              1.0f - (tm + t * (1.0f - b.z)) * (1.0f - a.z));
}

/* Overlay, per component: a < 1/2: a((1 − t) + 2tb); else 1 − ((1 − t) + 2t(1 − b))(1 − a). */
static float overlay1(float t, float a, float b)
{
    float tm = 1.0f - t;
    if (a < 0.5f)
        return a * (tm + 2.0f * t * b);
    return 1.0f - (tm + 2.0f * t * (1.0f - b)) * (1.0f - a);
}

/* Divide, per component: (1 − t)a + ta/b, a unchanged where b = 0. */
static float divide1(float t, float a, float b)
{
    return b != 0.0f ? (1.0f - t) * a + t * a / b : a;
}

/* Dodge, per component: a/(1 − tb) capped at 1 (1 when 1 − tb <= 0); a = 0 stays 0. */
static float dodge1(float t, float a, float b)
{
    if (a == 0.0f)
        return a;
    float d = 1.0f - t * b;
    if (d <= 0.0f)
        return 1.0f;
    float x = a / d;
    return x > 1.0f ? 1.0f : x;
}

/* Burn, per component: 1 − (1 − a)/((1 − t) + tb) clamped to [0,1] (0 when the divisor <= 0). */
static float burn1(float t, float a, float b)
{
    float d = (1.0f - t) + t * b;
    if (d <= 0.0f)
        return 0.0f;
    float x = 1.0f - (1.0f - a) / d;
    return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
}

/* Hue: a with b's hue, unless b is grey; mixed by t. */
static vec3 blend_hue(float t, vec3 a, vec3 b)
{
    vec3 hb = rgb_to_hsv(b);
    if (hb.y == 0.0f)
        return a;
    vec3 ha = rgb_to_hsv(a);
    ha.x = hb.x;
    return lerp3(a, hsv_to_rgb(ha), t);
}

/* Saturation: a's saturation moved toward b's by t, unless a is grey. */
static vec3 blend_saturation(float t, vec3 a, vec3 b)
{
    vec3 ha = rgb_to_hsv(a);
    if (ha.y == 0.0f)
        return a;
    vec3 hb = rgb_to_hsv(b);
    ha.y = (1.0f - t) * ha.y + t * hb.y;
    return hsv_to_rgb(ha);
}

/* Value: a's value moved toward b's by t. */
static vec3 blend_value(float t, vec3 a, vec3 b)
{
    vec3 ha = rgb_to_hsv(a), hb = rgb_to_hsv(b);
    ha.z = (1.0f - t) * ha.z + t * hb.z;
    return hsv_to_rgb(ha);
}

/* Color: a with b's hue and saturation, unless b is grey; mixed by t. */
static vec3 blend_color(float t, vec3 a, vec3 b)
{
    vec3 hb = rgb_to_hsv(b);
    if (hb.y == 0.0f)
        return a;
    vec3 ha = rgb_to_hsv(a);
    ha.x = hb.x;
    ha.y = hb.y;
    return lerp3(a, hsv_to_rgb(ha), t);
}

/* Soft Light: (1 − t)a + t((1 − a)ba + a·screen), screen = 1 − (1 − b)(1 − a). */
static float soft_light1(float t, float a, float b)
{
    float screen = 1.0f - (1.0f - b) * (1.0f - a);
    return (1.0f - t) * a + t * ((1.0f - a) * b * a + a * screen);
}

#define PER_COMPONENT(f, t, a, b) v3(f((t), (a).x, (b).x), f((t), (a).y, (b).y), f((t), (a).z, (b).z))

/* One blend mode at factor t (Cycles' definitions as of Blender 3.4–5.1). */
static vec3 blend(uint32_t mode, float t, vec3 a, vec3 b)
{
    switch (mode) {
    case PHOS_BLEND_MIX: return lerp3(a, b, t);
    case PHOS_BLEND_DARKEN: return lerp3(a, min3(a, b), t);
    case PHOS_BLEND_MULTIPLY: return lerp3(a, v3_mul(a, b), t);
    case PHOS_BLEND_BURN: return PER_COMPONENT(burn1, t, a, b);
    case PHOS_BLEND_LIGHTEN: return lerp3(a, max3(a, b), t);
    case PHOS_BLEND_SCREEN: return blend_screen(t, a, b);
    case PHOS_BLEND_DODGE: return PER_COMPONENT(dodge1, t, a, b);
    case PHOS_BLEND_ADD: return lerp3(a, v3_add(a, b), t);
    case PHOS_BLEND_OVERLAY: return PER_COMPONENT(overlay1, t, a, b);
    case PHOS_BLEND_SOFT_LIGHT: return PER_COMPONENT(soft_light1, t, a, b);
    /* a + t(2b − 1). */
    case PHOS_BLEND_LINEAR_LIGHT: return v3_add(a, v3_scale(v3_add(v3_scale(b, 2.0f), v3s(-1.0f)), t));
    case PHOS_BLEND_DIFFERENCE: return lerp3(a, abs3(v3_sub(a, b)), t);
    /* max(0, lerp(a, a + b − 2ab, t)). */
    case PHOS_BLEND_EXCLUSION:
        return max3(lerp3(a, v3_sub(v3_add(a, b), v3_scale(v3_mul(a, b), 2.0f)), t), v3s(0.0f));
    case PHOS_BLEND_SUBTRACT: return lerp3(a, v3_sub(a, b), t);
    case PHOS_BLEND_DIVIDE: return PER_COMPONENT(divide1, t, a, b);
    case PHOS_BLEND_HUE: return blend_hue(t, a, b);
    case PHOS_BLEND_SATURATION: return blend_saturation(t, a, b);
    case PHOS_BLEND_VALUE: return blend_value(t, a, b);
    case PHOS_BLEND_COLOR: return blend_color(t, a, b);
    default: return v3s(0.0f);
    }
}

/* in fac, a, b; out value: a(1 − t) + bt, t clamped to [0,1] with flags 2. */
void shader_op_mix_float(const phos_shader_instruction *ins, shader_context *ctx)
{
    float t = SHADER_IN(0);
    if (ins->flags & MIX_CLAMP_FACTOR)
        t = node_clamp(t, 0.0f, 1.0f);
    SHADER_OUT(0, SHADER_IN(1) * (1.0f - t) + SHADER_IN(2) * t);
}

/* in fac(1 or 3: flags 4), a(3), b(3); out (3): a(1 − t) + bt per component. */
void shader_op_mix_vector(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 t = (ins->flags & MIX_FACTOR_VECTOR) ? SHADER_IN3(0) : v3s(SHADER_IN(0));
    if (ins->flags & MIX_CLAMP_FACTOR)
        t = node_saturate3(t);
    vec3 a = SHADER_IN3(1), b = SHADER_IN3(2);
    SHADER_OUT3(0, v3(a.x * (1.0f - t.x) + b.x * t.x, a.y * (1.0f - t.y) + b.y * t.y,
                      a.z * (1.0f - t.z) + b.z * t.z));
}

/* in fac, a(3), b(3); out (3). The Mix node (3.4+) maps Clamp Factor to
 * flags 2 and Clamp Result to flags 1; the legacy MixRGB node always clamps
 * its factor (flags 2) and maps its Clamp to flags 1. */
void shader_op_mix_color(const phos_shader_instruction *ins, shader_context *ctx)
{
    float t = SHADER_IN(0);
    if (ins->flags & MIX_CLAMP_FACTOR)
        t = node_clamp(t, 0.0f, 1.0f);
    vec3 r = blend(ins->mode, t, SHADER_IN3(1), SHADER_IN3(2));
    if (ins->flags & MIX_CLAMP_RESULT)
        r = node_saturate3(r);
    SHADER_OUT3(0, r);
}

/* ------------------------------------------------------ colour adjustment */

/* in hue, saturation, value, fac, color(3); out color(3). In HSV: h + hue +
 * 1/2 wrapped to [0,1) (before 4.3 with fmod, which leaves a negative sum
 * negative), s·saturation clamped to [0,1], v·value; then mixed with the
 * input by fac and clamped below at 0. */
void shader_op_hue_saturation(const phos_shader_instruction *ins, shader_context *ctx)
{
    float hue = SHADER_IN(0), sat = SHADER_IN(1), val = SHADER_IN(2), fac = SHADER_IN(3);
    vec3 in = SHADER_IN3(4);
    vec3 hsv = rgb_to_hsv(in);
    float h = hsv.x + hue + 0.5f;
    hsv.x = (ins->flags & PHOS_NODE_PRE_4_3) ? fmodf(h, 1.0f) : h - floorf(h);
    hsv.y = node_clamp(hsv.y * sat, 0.0f, 1.0f);
    hsv.z *= val;
    vec3 c = hsv_to_rgb(hsv);
    c = v3(fac * c.x + (1.0f - fac) * in.x, fac * c.y + (1.0f - fac) * in.y, fac * c.z + (1.0f - fac) * in.z);
    SHADER_OUT3(0, max3(c, v3s(0.0f)));
}

/* in color(3), bright, contrast; out color(3): max(0, (1 + contrast)c +
 * bright − contrast/2). */
void shader_op_bright_contrast(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 c = SHADER_IN3(0);
    float bright = SHADER_IN(1), contrast = SHADER_IN(2);
    float a = 1.0f + contrast, b = bright - contrast * 0.5f;
    SHADER_OUT3(0, v3(node_max(a * c.x + b, 0.0f), node_max(a * c.y + b, 0.0f), node_max(a * c.z + b, 0.0f)));
}

/* c^gamma for c > 0 (other components unchanged); gamma 0 gives white. */
static inline float gamma1(float c, float g) { return c > 0.0f ? powf(c, g) : c; }

/* in color(3), gamma; out color(3). */
void shader_op_gamma(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 c = SHADER_IN3(0);
    float g = SHADER_IN(1);
    SHADER_OUT3(0, g == 0.0f ? v3s(1.0f) : v3(gamma1(c.x, g), gamma1(c.y, g), gamma1(c.z, g)));
}

/* fac(1 − c) + (1 − fac)c. */
static inline float invert1(float c, float fac) { return fac * (1.0f - c) + (1.0f - fac) * c; }

/* in fac, color(3); out color(3). */
void shader_op_invert(const phos_shader_instruction *ins, shader_context *ctx)
{
    float fac = SHADER_IN(0);
    vec3 c = SHADER_IN3(1);
    SHADER_OUT3(0, v3(invert1(c.x, fac), invert1(c.y, fac), invert1(c.z, fac)));
}

/* in color(3); out (3): the components in the model (RGB unchanged). */
void shader_op_separate_color(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 c = SHADER_IN3(0);
    if (ins->mode == PHOS_COLOR_MODEL_HSV)
        c = rgb_to_hsv(c);
    else if (ins->mode == PHOS_COLOR_MODEL_HSL)
        c = rgb_to_hsl(c);
    SHADER_OUT3(0, c);
}

/* in r, g, b (or h, s, v / h, s, l); out color(3). */
void shader_op_combine_color(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 c = v3(SHADER_IN(0), SHADER_IN(1), SHADER_IN(2));
    if (ins->mode == PHOS_COLOR_MODEL_HSV)
        c = hsv_to_rgb(c);
    else if (ins->mode == PHOS_COLOR_MODEL_HSL)
        c = hsl_to_rgb(c);
    SHADER_OUT3(0, c);
}

/* --------------------------------------------------- physical colour data */

/* Relative luminance Y of linear Rec. 709 / sRGB primaries with a D65 white
 * (IEC 61966-2-1; Lindbloom's RGB → XYZ matrix, middle row). Cycles takes
 * the row of the OpenColorIO config's RGB → XYZ; for Blender's configs (3.4
 * to 5.x, scene linear = Linear Rec. 709) that is this row up to the
 * configs' rounding (≈1e-6). */
static const vec3 REC709_TO_Y = {0.2126729f, 0.7151522f, 0.0721750f};

/* in color(3); out value: the luminance of the colour. */
void shader_op_rgb_to_bw(const phos_shader_instruction *ins, shader_context *ctx)
{
    SHADER_OUT(0, v3_dot(SHADER_IN3(0), REC709_TO_Y));
}

/* Cycles' piecewise fit of the linear Rec. 709 colour of a Planckian
 * radiator (normalised in luminance) over 800–12000 K, in 7 segments:
 * r, g = a/T + bT + c; b = ((aT + b)T + c)T + d. Coefficients from Cycles'
 * kernel/tables.h (Blender 3.4 to 5.1, Apache-2.0), unchanged across those
 * versions. The fit goes below 0 where the colour is outside Rec. 709. */
static const float BLACKBODY_SPLIT[6] = {965.0f, 1167.0f, 1449.0f, 1902.0f, 3315.0f, 6365.0f};
static const float BLACKBODY_R[7][3] = {
    {1.61919106e+03f, -2.05010916e-03f, 5.02995757e+00f},
    {2.48845471e+03f, -1.11330907e-03f, 3.22621544e+00f},
    {3.34143193e+03f, -4.86551192e-04f, 1.76486769e+00f},
    {4.09461742e+03f, -1.27446582e-04f, 7.25731635e-01f},
    {4.67028036e+03f, 2.91258199e-05f, 1.26703442e-01f},
    {4.59509185e+03f, 2.87495649e-05f, 1.50345020e-01f},
    {3.78717450e+03f, 9.35907826e-06f, 3.99075871e-01f},
};
static const float BLACKBODY_G[7][3] = {
    {-4.88999748e+02f, 6.04330754e-04f, -7.55807526e-02f},
    {-7.55994277e+02f, 3.16730098e-04f, 4.78306139e-01f},
    {-1.02363977e+03f, 1.20223470e-04f, 9.36662319e-01f},
    {-1.26571316e+03f, 4.87340896e-06f, 1.27054498e+00f},
    {-1.42529332e+03f, -4.01150431e-05f, 1.43972784e+00f},
    {-1.17554822e+03f, -2.16378048e-05f, 1.30408023e+00f},
    {-5.00799571e+02f, -4.59832026e-06f, 1.09098763e+00f},
};
static const float BLACKBODY_B[7][4] = {
    {5.96945309e-11f, -4.85742887e-08f, -9.70622247e-05f, -4.07936148e-03f},
    {2.40430366e-11f, 5.55021075e-08f, -1.98503712e-04f, 2.89312858e-02f},
    {-1.40949732e-11f, 1.89878968e-07f, -3.56632824e-04f, 9.10767778e-02f},
    {-3.61460868e-11f, 2.84822009e-07f, -4.93211319e-04f, 1.56723440e-01f},
    {-1.97075738e-11f, 1.75359352e-07f, -2.50542825e-04f, -2.22783266e-02f},
    {-1.61997957e-13f, -1.64216008e-08f, 3.86216271e-04f, -7.38077418e-01f},
    {6.72650283e-13f, -2.73078809e-08f, 4.24098264e-04f, -7.52335691e-01f},
};

/* The fit at T kelvin; the ends are held constant above 12000 K and below
 * 800 K (where the light is very dim). */
static vec3 blackbody_rec709(float t)
{
    if (t >= 12000.0f)
        return v3(0.8262954810464208f, 0.9945080501520986f, 1.566307710274283f);
    if (t < 800.0f)
        return v3(5.413294490189271f, -0.20319390035873933f, -0.0822535242887164f);
    int i = 0;
    while (i < 6 && t >= BLACKBODY_SPLIT[i])
        i++;
    const float *r = BLACKBODY_R[i], *g = BLACKBODY_G[i], *b = BLACKBODY_B[i];
    float inv = 1.0f / t;
    return v3(r[0] * inv + r[1] * t + r[2], g[0] * inv + g[1] * t + g[2], ((b[0] * t + b[1]) * t + b[2]) * t + b[3]);
}

/* in temperature (K); out color(3): the fit, clamped below at 0 (a NaN gives 0). */
void shader_op_blackbody(const phos_shader_instruction *ins, shader_context *ctx)
{
    SHADER_OUT3(0, max3(blackbody_rec709(SHADER_IN(0)), v3s(0.0f)));
}

/* The CIE 1931 2° standard observer's colour matching functions x̄, ȳ, z̄
 * (CIE 15:2004, table T.4) at 5 nm from 380 to 780 nm, to 4 decimals as in
 * J. Walker's specrend.c, the table Cycles uses. */
static const float CIE_1931[81][3] = {
    {0.0014f, 0.0000f, 0.0065f}, /* 380 nm */
    {0.0022f, 0.0001f, 0.0105f}, /* 385 nm */
    {0.0042f, 0.0001f, 0.0201f}, /* 390 nm */
    {0.0076f, 0.0002f, 0.0362f}, /* 395 nm */
    {0.0143f, 0.0004f, 0.0679f}, /* 400 nm */
    {0.0232f, 0.0006f, 0.1102f}, /* 405 nm */
    {0.0435f, 0.0012f, 0.2074f}, /* 410 nm */
    {0.0776f, 0.0022f, 0.3713f}, /* 415 nm */
    {0.1344f, 0.0040f, 0.6456f}, /* 420 nm */
    {0.2148f, 0.0073f, 1.0391f}, /* 425 nm */
    {0.2839f, 0.0116f, 1.3856f}, /* 430 nm */
    {0.3285f, 0.0168f, 1.6230f}, /* 435 nm */
    {0.3483f, 0.0230f, 1.7471f}, /* 440 nm */
    {0.3481f, 0.0298f, 1.7826f}, /* 445 nm */
    {0.3362f, 0.0380f, 1.7721f}, /* 450 nm */
    {0.3187f, 0.0480f, 1.7441f}, /* 455 nm */
    {0.2908f, 0.0600f, 1.6692f}, /* 460 nm */
    {0.2511f, 0.0739f, 1.5281f}, /* 465 nm */
    {0.1954f, 0.0910f, 1.2876f}, /* 470 nm */
    {0.1421f, 0.1126f, 1.0419f}, /* 475 nm */
    {0.0956f, 0.1390f, 0.8130f}, /* 480 nm */
    {0.0580f, 0.1693f, 0.6162f}, /* 485 nm */
    {0.0320f, 0.2080f, 0.4652f}, /* 490 nm */
    {0.0147f, 0.2586f, 0.3533f}, /* 495 nm */
    {0.0049f, 0.3230f, 0.2720f}, /* 500 nm */
    {0.0024f, 0.4073f, 0.2123f}, /* 505 nm */
    {0.0093f, 0.5030f, 0.1582f}, /* 510 nm */
    {0.0291f, 0.6082f, 0.1117f}, /* 515 nm */
    {0.0633f, 0.7100f, 0.0782f}, /* 520 nm */
    {0.1096f, 0.7932f, 0.0573f}, /* 525 nm */
    {0.1655f, 0.8620f, 0.0422f}, /* 530 nm */
    {0.2257f, 0.9149f, 0.0298f}, /* 535 nm */
    {0.2904f, 0.9540f, 0.0203f}, /* 540 nm */
    {0.3597f, 0.9803f, 0.0134f}, /* 545 nm */
    {0.4334f, 0.9950f, 0.0087f}, /* 550 nm */
    {0.5121f, 1.0000f, 0.0057f}, /* 555 nm */
    {0.5945f, 0.9950f, 0.0039f}, /* 560 nm */
    {0.6784f, 0.9786f, 0.0027f}, /* 565 nm */
    {0.7621f, 0.9520f, 0.0021f}, /* 570 nm */
    {0.8425f, 0.9154f, 0.0018f}, /* 575 nm */
    {0.9163f, 0.8700f, 0.0017f}, /* 580 nm */
    {0.9786f, 0.8163f, 0.0014f}, /* 585 nm */
    {1.0263f, 0.7570f, 0.0011f}, /* 590 nm */
    {1.0567f, 0.6949f, 0.0010f}, /* 595 nm */
    {1.0622f, 0.6310f, 0.0008f}, /* 600 nm */
    {1.0456f, 0.5668f, 0.0006f}, /* 605 nm */
    {1.0026f, 0.5030f, 0.0003f}, /* 610 nm */
    {0.9384f, 0.4412f, 0.0002f}, /* 615 nm */
    {0.8544f, 0.3810f, 0.0002f}, /* 620 nm */
    {0.7514f, 0.3210f, 0.0001f}, /* 625 nm */
    {0.6424f, 0.2650f, 0.0000f}, /* 630 nm */
    {0.5419f, 0.2170f, 0.0000f}, /* 635 nm */
    {0.4479f, 0.1750f, 0.0000f}, /* 640 nm */
    {0.3608f, 0.1382f, 0.0000f}, /* 645 nm */
    {0.2835f, 0.1070f, 0.0000f}, /* 650 nm */
    {0.2187f, 0.0816f, 0.0000f}, /* 655 nm */
    {0.1649f, 0.0610f, 0.0000f}, /* 660 nm */
    {0.1212f, 0.0446f, 0.0000f}, /* 665 nm */
    {0.0874f, 0.0320f, 0.0000f}, /* 670 nm */
    {0.0636f, 0.0232f, 0.0000f}, /* 675 nm */
    {0.0468f, 0.0170f, 0.0000f}, /* 680 nm */
    {0.0329f, 0.0119f, 0.0000f}, /* 685 nm */
    {0.0227f, 0.0082f, 0.0000f}, /* 690 nm */
    {0.0158f, 0.0057f, 0.0000f}, /* 695 nm */
    {0.0114f, 0.0041f, 0.0000f}, /* 700 nm */
    {0.0081f, 0.0029f, 0.0000f}, /* 705 nm */
    {0.0058f, 0.0021f, 0.0000f}, /* 710 nm */
    {0.0041f, 0.0015f, 0.0000f}, /* 715 nm */
    {0.0029f, 0.0010f, 0.0000f}, /* 720 nm */
    {0.0020f, 0.0007f, 0.0000f}, /* 725 nm */
    {0.0014f, 0.0005f, 0.0000f}, /* 730 nm */
    {0.0010f, 0.0004f, 0.0000f}, /* 735 nm */
    {0.0007f, 0.0002f, 0.0000f}, /* 740 nm */
    {0.0005f, 0.0002f, 0.0000f}, /* 745 nm */
    {0.0003f, 0.0001f, 0.0000f}, /* 750 nm */
    {0.0002f, 0.0001f, 0.0000f}, /* 755 nm */
    {0.0002f, 0.0001f, 0.0000f}, /* 760 nm */
    {0.0001f, 0.0000f, 0.0000f}, /* 765 nm */
    {0.0001f, 0.0000f, 0.0000f}, /* 770 nm */
    {0.0001f, 0.0000f, 0.0000f}, /* 775 nm */
    {0.0000f, 0.0000f, 0.0000f}, /* 780 nm */
};

/* in wavelength (nm); out color(3). The matching functions interpolated
 * linearly at λ (index (λ − 380)/5 truncated toward zero, so 375–380 nm
 * extrapolates the first interval; 0 outside), to linear Rec. 709, scaled
 * by 1/2.52 (Cycles' empirical factor keeping the components <= 1) and
 * clamped below at 0. */
void shader_op_wavelength(const phos_shader_instruction *ins, shader_context *ctx)
{
    float x = (SHADER_IN(0) - 380.0f) * (1.0f / 5.0f);
    int i = node_float_to_int(x);
    vec3 xyz = v3s(0.0f);
    if (i >= 0 && i < 80) {
        x -= (float)i;
        xyz = lerp3(v3_load(CIE_1931[i]), v3_load(CIE_1931[i + 1]), x);
    }
    vec3 rgb = v3_scale(xyz_to_rec709(xyz), 1.0f / 2.52f);
    SHADER_OUT3(0, max3(rgb, v3s(0.0f)));
}

/* --------------------------------------------------- ramps and curves */

/*
 * Baked tables, in ctx->program->table from offset ins->table, `mode`
 * entries of 4 floats each (mode >= 2 for curves; an empty table gives 0):
 *   RAMP           entry i = the ColorRamp's RGBA at position i/(n − 1).
 *   CURVES_RGB     entry i at x_i = lo + i(hi − lo)/(n − 1), lo = param[0],
 *                  hi = param[1] (the curves' common x range): R(C(x_i)),
 *                  G(C(x_i)), B(C(x_i)) with C the Combined curve, as Cycles
 *                  bakes them; the 4th float is not read (C(x_i) or 0).
 *   CURVES_VECTOR  entry i: X(x_i), Y(x_i), Z(x_i), 0.
 *   CURVE_FLOAT    entry i: F(x_i), 0, 0, 0.
 * flags 1 on the curves = the mapping's Extend is Extrapolated.
 */

/* Component k of a table at f in [0,1] (Cycles' ramp lookup): outside
 * [0,1] either extrapolated along the end segment or clamped (a NaN f
 * reads entry 0); inside, entry ⌊f(n − 1)⌋ blended linearly with the next
 * unless constant. */
static float table_lookup(const float *tab, int n, int k, float f, int interpolate, int extrapolate)
{
    if ((f < 0.0f || f > 1.0f) && extrapolate && n >= 2) {
        float t0, dy;
        if (f < 0.0f) {
            t0 = tab[k];
            dy = t0 - tab[4 + k];
            f = -f;
        } else {
            t0 = tab[4 * (n - 1) + k];
            dy = t0 - tab[4 * (n - 2) + k];
            f = f - 1.0f;
        }
        return t0 + dy * f * (float)(n - 1);
    }
    f = node_clamp(f, 0.0f, 1.0f) * (float)(n - 1);
    int i = node_float_to_int(f);
    i = i < 0 ? 0 : (i > n - 1 ? n - 1 : i);
    float t = f - (float)i;
    float a = tab[4 * i + k];
    if (interpolate && t > 0.0f)
        a = (1.0f - t) * a + t * tab[4 * (i + 1) + k];
    return a;
}

static const float *op_table(const phos_shader_instruction *ins, const shader_context *ctx)
{
    return ins->mode > 0 ? ctx->program->table + ins->table : NULL;
}

/* in fac; out color(3), alpha. */
void shader_op_ramp(const phos_shader_instruction *ins, shader_context *ctx)
{
    const float *tab = op_table(ins, ctx);
    float c[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    if (tab) {
        float f = SHADER_IN(0);
        int interpolate = !(ins->flags & RAMP_CONSTANT);
        for (int k = 0; k < 4; k++)
            c[k] = table_lookup(tab, (int)ins->mode, k, f, interpolate, 0);
    }
    SHADER_OUT3(0, v3(c[0], c[1], c[2]));
    SHADER_OUT(1, c[3]);
}

/* RGB and Vector Curves: component k of the input at (v − lo)/(hi − lo)
 * through column k, then mixed with the input by fac. */
static void curves3(const phos_shader_instruction *ins, shader_context *ctx)
{
    const float *tab = op_table(ins, ctx);
    float fac = SHADER_IN(0);
    vec3 v = SHADER_IN3(1);
    if (!tab) {
        SHADER_OUT3(0, v3s(0.0f));
        return;
    }
    float lo = ins->param[0], range = ins->param[1] - ins->param[0];
    int n = (int)ins->mode, ex = (ins->flags & CURVES_EXTRAPOLATE) != 0;
    vec3 c = v3(table_lookup(tab, n, 0, (v.x - lo) / range, 1, ex), table_lookup(tab, n, 1, (v.y - lo) / range, 1, ex),
                table_lookup(tab, n, 2, (v.z - lo) / range, 1, ex));
    SHADER_OUT3(0, v3_add(v3_scale(v, 1.0f - fac), v3_scale(c, fac)));
}

/* in fac, color(3); out color(3). */
void shader_op_curves_rgb(const phos_shader_instruction *ins, shader_context *ctx) { curves3(ins, ctx); }

/* in fac, vector(3); out vector(3). */
void shader_op_curves_vector(const phos_shader_instruction *ins, shader_context *ctx) { curves3(ins, ctx); }

/* in fac, value; out value. */
void shader_op_curve_float(const phos_shader_instruction *ins, shader_context *ctx)
{
    const float *tab = op_table(ins, ctx);
    float fac = SHADER_IN(0), x = SHADER_IN(1);
    if (!tab) {
        SHADER_OUT(0, 0.0f);
        return;
    }
    float lo = ins->param[0], range = ins->param[1] - ins->param[0];
    float y = table_lookup(tab, (int)ins->mode, 0, (x - lo) / range, 1, (ins->flags & CURVES_EXTRAPOLATE) != 0);
    SHADER_OUT(0, (1.0f - fac) * x + fac * y);
}
