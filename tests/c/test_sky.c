/*
 * test_sky.c — the Sky Texture's models (shading/sky/) and its sun as a
 * light (lights/sky_sun.c). Cycles is the reference for each model's
 * values (tests/blender/test_sky.py); here, what has a closed form:
 *
 *  - Single scattering in the optically thin limit: with the sun at the
 *    zenith, the radiance seen along a view is ε σ p(μ) E ∫ ρ(h(s)) ds,
 *    so the ratio of the horizon's radiance to the zenith's is
 *    p(0)/p(1) times the ratio of the density's integrals along the two
 *    rays, whatever the spectrum: ½ for molecules (Rayleigh), the
 *    Cornette-Shanks ratio for aerosols. The integrals come from a fine
 *    quadrature here, the model's from its own 32 segments.
 *  - The sun's disc: its radiance × its solid angle (the irradiance it
 *    gives) does not depend on its size.
 *  - A sky without air is black.
 *  - The sun as a light: its irradiance equals the disc's radiance, as the
 *    program draws it (limb darkening and all), integrated over the disc;
 *    the world's map no longer holds the disc.
 *  - Bad settings and bad programs are refused.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lights/environment.h"
#include "lights/light.h"
#include "sampling/warp.h"
#include "scene/scene.h"
#include "shading/material.h"
#include "shading/shader_program.h"
#include "shading/sky/sky.h"
#include "test_scenes.h"
#include "test_util.h"

#define W SKY_TEXTURE_WIDTH

static const double PI = 3.14159265358979323846;

static float *bake(const phos_sky_desc *d, float *data)
{
    uint32_t w = 0, h = 0;
    CHECK(phos_sky_texture_size(d, &w, &h) == PHOS_OK && w == W && h == sky_texture_height(d->layout));
    float *px = malloc(sizeof(float) * 4 * w * h);
    CHECK(phos_sky_bake(d, px, data) == PHOS_OK);
    return px;
}

static const float *texel(const float *px, uint32_t column, uint32_t row) { return px + 4 * ((size_t)row * W + column); }

/* ∫ exp(−h(s)/scale) ds along a ray from height a (m) above a sphere of
 * radius r at elevation e, to the sphere of radius top: a fine midpoint
 * sum. */
static double density_integral(double r, double top, double a, double e, double scale)
{
    double o = r + a, b = o * sin(e), c = o * o - top * top;
    double length = -b + sqrt(b * b - c);
    const int n = 200000;
    double ds = length / n, sum = 0.0;
    for (int i = 0; i < n; i++) {
        double s = (i + 0.5) * ds;
        double x = s * cos(e), z = o + s * sin(e);
        sum += exp(-(sqrt(x * x + z * z) - r) / scale);
    }
    return sum * ds;
}

static phos_sky_desc thin_air(float air, float aerosol)
{
    phos_sky_desc d;
    phos_sky_desc_init(&d);
    d.sun_elevation = (float)(PI / 2);
    d.sun_disc = 0;
    d.altitude = 1.0f;
    d.air_density = air;
    d.aerosol_density = aerosol;
    d.ozone_density = 0.0f;
    return d;
}

static void test_thin_limit(void)
{
    const double r = 6360e3, top = 6420e3;
    float data[PHOS_SKY_DATA_FLOATS];
    /* Molecules: phase (1 + μ²) gives ½ at the horizon (μ = 0) against
     * (1 + μ²)/2 at the top row, μ = sin e; in both layouts. */
    for (uint32_t layout = 0; layout < PHOS_SKY_LAYOUT_COUNT; layout++) {
        phos_sky_desc d = thin_air(1e-4f, 0.0f);
        d.layout = layout;
        float *px = bake(&d, data);
        uint32_t h = sky_texture_height(layout), horizon = layout == PHOS_SKY_LAYOUT_SPHERE ? h / 2 : 0;
        float e_top;
        sky_texel_direction(layout, 0, 10, h - 1, &e_top);
        double mu = sin(e_top);
        double expected = 0.5 / (0.5 * (1.0 + mu * mu)) * density_integral(r, top, 1.0, 0.0, 8e3) /
                          density_integral(r, top, 1.0, e_top, 8e3);
        for (int c = 0; c < 3; c++)
            CHECK_REL(texel(px, 10, horizon)[c] / texel(px, 10, h - 1)[c], expected, 0.01);
        /* Symmetric about the sun: mirrored halves. */
        CHECK(texel(px, 3, horizon)[1] == texel(px, W - 4, horizon)[1]);
        free(px);
    }
    /* Aerosols (scale height 1.2 km, which the model's 32 segments of the
     * zenith ray do not resolve, so not against the integral): the top row
     * of the sphere layout (88.6° up, column 0, away from the sun's
     * azimuth) lit by a sun on the horizon over a sun at the zenith, along
     * the same ray, is the ratio of the phase functions at the two angles,
     * Cornette-Shanks with g = 0.76 (and Rayleigh's for molecules). */
    float e_top;
    vec3 view = sky_texel_direction(PHOS_SKY_LAYOUT_SPHERE, 0, 0, 255, &e_top);
    double mu[2] = {view.z, view.x}; /* the sun along +z, then along +x */
    for (int kind = 0; kind < 2; kind++) {
        float zenith[2];
        double phase[2];
        for (int k = 0; k < 2; k++) {
            phos_sky_desc d = thin_air(kind ? 0.0f : 1e-4f, kind ? 1e-4f : 0.0f);
            d.layout = PHOS_SKY_LAYOUT_SPHERE;
            d.sun_elevation = k ? 0.0f : (float)(PI / 2);
            float *px = bake(&d, data);
            zenith[k] = texel(px, 0, 255)[1];
            free(px);
            const double g = 0.76, m = mu[k];
            phase[k] = kind ? (1.0 + m * m) / pow(1.0 + g * g - 2.0 * g * m, 1.5) : 1.0 + m * m;
        }
        CHECK_REL(zenith[1] / zenith[0], phase[1] / phase[0], 0.01);
    }
}

static void test_airless_sky_is_black(void)
{
    for (uint32_t model = PHOS_SKY_SINGLE_SCATTERING; model <= PHOS_SKY_MULTIPLE_SCATTERING; model++) {
        phos_sky_desc d = thin_air(0.0f, 0.0f);
        d.model = model;
        d.layout = PHOS_SKY_LAYOUT_SPHERE;
        d.sun_elevation = 0.4f;
        float data[PHOS_SKY_DATA_FLOATS];
        float *px = bake(&d, data);
        double sum = 0.0;
        for (size_t i = 0; i < (size_t)W * sky_texture_height(d.layout); i++)
            sum += fabs(px[4 * i]) + fabs(px[4 * i + 1]) + fabs(px[4 * i + 2]);
        CHECK_MSG(sum == 0.0, "model %u: a sky without air sums to %g", model, sum);
        free(px);
    }
}

/* Without air the disc gives the sun's whole irradiance: its radiance ×
 * its solid angle has the luminance ∫ ȳ(λ) E(λ) dλ of a black body of
 * 5778 K seen at 1 AU, E = πB(λ, T)(R☉/d)², summed here at the model's 21
 * wavelengths (CIE 1931 ȳ, CIE 15:2004 Table T.4). */
static void test_sun_irradiance(void)
{
    static const double ybar[21] = {0.000039, 0.000396, 0.004,  0.023,    0.06,     0.13902,  0.323,
                                     0.71,     0.954,    0.995,  0.87,     0.631,    0.381,    0.175,
                                     0.061,    0.017,    0.004102, 0.001047, 0.0002492, 0.00006, 0.00001499};
    const double h = 6.62607015e-34, c = 2.99792458e8, k = 1.380649e-23, t = 5778.0, ratio = 6.957e8 / 1.495978707e11;
    double luminance = 0.0;
    for (int i = 0; i < 21; i++) {
        double l = (380.0 + 20.0 * i) * 1e-9;
        double b = 2.0 * h * c * c / pow(l, 5.0) / expm1(h * c / (l * k * t));
        luminance += ybar[i] * PI * b * ratio * ratio * 1e-9 * 20.0;
    }
    for (uint32_t layout = 0; layout < PHOS_SKY_LAYOUT_COUNT; layout++) {
        phos_sky_desc d = thin_air(0.0f, 0.0f);
        d.layout = layout;
        d.sun_elevation = 0.6f;
        d.sun_disc = 1;
        d.sun_size = 0.02f;
        float data[PHOS_SKY_DATA_FLOATS];
        CHECK(phos_sky_bake(&d, NULL, data) == PHOS_OK);
        float omega = sky_disc_solid_angle(d.sun_size);
        CHECK_REL(rgb_luminance(v3_load(data + SKY_SUN_BOTTOM)) * omega, luminance, 1e-3);
        CHECK_REL(rgb_luminance(v3_load(data + SKY_SUN_TOP)) * omega, luminance, 1e-3);
        CHECK(data[SKY_SUN_DIAMETER] == d.sun_size);
    }
}

/* --------------------------------------------------------- the sun as a light */

/* A world: Generated (the direction) → Sky Texture → Background. */
static void set_sky_world(phos_scene *s, const phos_sky_desc *d, uint32_t flags)
{
    static float data[PHOS_SKY_DATA_FLOATS];
    float *px = bake(d, data);
    phos_image_desc im;
    phos_image_desc_init(&im);
    im.width = W, im.height = sky_texture_height(d->layout), im.pixels = px;
    uint32_t image = 0;
    CHECK(phos_scene_add_image(s, &im, &image) == PHOS_OK);
    free(px);
    data[PHOS_SKY_DATA_IMAGE] = (float)image;
    phos_shader_instruction sky;
    memset(&sky, 0, sizeof(sky));
    sky.op = PHOS_OP_TEX_SKY;
    sky.mode = d->model;
    sky.flags = flags;
    CHECK(test_set_world_texture(s, sky, data, PHOS_SKY_DATA_FLOATS) == PHOS_OK);
}

static const light *find_sun(const phos_scene *s)
{
    for (uint32_t i = 0; i < s->lights.count; i++)
        if (s->lights.lights[i].kind == LIGHT_SUN)
            return &s->lights.lights[i];
    return NULL;
}

/* The disc's mean radiance as the texture defines it: the limb darkening
 * 1 − 0.6(1 − √(1 − x²)) averages 0.8 over a disc (x² uniform), the
 * bottom-to-top blend averages the two; times the intensity. */
static vec3 disc_mean(const float *data)
{
    vec3 mid = v3_scale(v3_add(v3_load(data + SKY_SUN_BOTTOM), v3_load(data + SKY_SUN_TOP)), 0.5f);
    return v3_scale(mid, 0.8f * data[SKY_SUN_INTENSITY]);
}

static void test_sun_becomes_a_light(void)
{
    for (uint32_t layout = 0; layout < PHOS_SKY_LAYOUT_COUNT; layout++) {
        phos_sky_desc d;
        phos_sky_desc_init(&d);
        d.layout = layout;
        d.sun_elevation = 0.5f;
        d.sun_rotation = 0.7f;
        d.sun_size = 0.03f;
        d.sun_intensity = 0.7f;
        phos_scene *s = phos_scene_create();
        test_add_instance(s, test_add_quad_mesh(s, 1.0f), test_add_diffuse(s, 0.5f, 0.5f, 0.5f), 0, 0, 0);
        set_sky_world(s, &d, 1);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        const light *sun = find_sun(s);
        CHECK(sun != NULL);
        if (!sun) {
            phos_scene_destroy(s);
            continue;
        }
        const float *data = s->materials[s->world.material].program.table;
        vec3 to_sun = sky_sun_direction(d.sun_elevation, d.sun_rotation);
        CHECK(fabsf(v3_dot(sun->direction, to_sun) + 1.0f) < 1e-5f);
        /* Its radiance is the disc's mean (Blender 4's disc replaces the
         * sky behind it, 5's adds to it), its irradiance at normal
         * incidence that × π sin²(size/2). */
        vec3 sky = environment_radiance(s, s->lights.env, to_sun, 0);
        vec3 expected = disc_mean(data);
        if (layout == PHOS_SKY_LAYOUT_HEMISPHERE)
            expected = v3_sub(expected, sky);
        float s2 = sqr(sinf(0.5f * d.sun_size));
        for (int c = 0; c < 3; c++) {
            CHECK_REL(v3_component(sun->sun_radiance, c), v3_component(expected, c), 1e-3);
            CHECK_REL(v3_component(sun->color, c), v3_component(expected, c) * (float)PI * s2, 1e-3);
        }
        /* Hidden from the camera, which sees the disc the program draws:
         * at its centre (limb 1, the blend half way) the mean of bottom
         * and top, and in Blender 5 the sky behind it too. */
        CHECK(!sun->camera_visible);
        vec3 centre = v3_scale(v3_add(v3_load(data + SKY_SUN_BOTTOM), v3_load(data + SKY_SUN_TOP)),
                               0.5f * data[SKY_SUN_INTENSITY]);
        if (layout == PHOS_SKY_LAYOUT_SPHERE)
            centre = v3_add(centre, sky);
        vec3 seen = environment_radiance(s, s->lights.env, to_sun, SHADER_RAY_CAMERA);
        for (int c = 0; c < 3; c++)
            CHECK_REL(v3_component(seen, c), v3_component(centre, c), 1e-3);
        /* Every other ray finds the sky alone: far darker than the disc. */
        CHECK_MSG(v3_average(sky) < 1e-3f * v3_average(sun->sun_radiance), "the map still holds the disc: %g vs %g",
                  v3_average(sky), v3_average(sun->sun_radiance));
        phos_scene_destroy(s);

        /* A sky looked up by another vector (flags 0), or a sun at the
         * horizon, keeps its disc in the program. */
        for (int k = 0; k < 2; k++) {
            s = phos_scene_create();
            test_add_instance(s, test_add_quad_mesh(s, 1.0f), test_add_diffuse(s, 0.5f, 0.5f, 0.5f), 0, 0, 0);
            phos_sky_desc h = d;
            if (k)
                h.sun_elevation = 0.01f;
            set_sky_world(s, &h, k ? 1u : 0u);
            CHECK(phos_scene_commit(s) == PHOS_OK);
            CHECK(find_sun(s) == NULL);
            phos_scene_destroy(s);
        }
    }
}

/* ------------------------------------------------------------ bad input */

static void test_bad_settings_refused(void)
{
    float data[PHOS_SKY_DATA_FLOATS];
    uint32_t w, h;
    phos_sky_desc d;
    phos_sky_desc_init(&d);
    CHECK(phos_sky_bake(NULL, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_sky_bake(&d, NULL, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_sky_texture_size(NULL, &w, &h) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_sky_desc bad = d;
    bad.layout = PHOS_SKY_LAYOUT_COUNT;
    CHECK(phos_sky_bake(&bad, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    bad = d; /* Blender 5's model has no hemisphere layout */
    bad.model = PHOS_SKY_MULTIPLE_SCATTERING;
    CHECK(phos_sky_texture_size(&bad, &w, &h) == PHOS_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.sun_elevation = NAN;
    CHECK(phos_sky_bake(&bad, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.air_density = -1.0f;
    CHECK(phos_sky_bake(&bad, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.model = PHOS_SKY_MODEL_COUNT;
    CHECK(phos_sky_bake(&bad, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.model = PHOS_SKY_HOSEK_WILKIE;
    bad.sun_direction[0] = bad.sun_direction[1] = bad.sun_direction[2] = 0.0f;
    CHECK(phos_sky_bake(&bad, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.model = PHOS_SKY_PREETHAM;
    bad.turbidity = 0.5f;
    CHECK(phos_sky_bake(&bad, NULL, data) == PHOS_ERROR_INVALID_ARGUMENT);
    /* Preetham's zenith normalisation crosses 0 near turbidity 1.643: the
     * sky stays finite and bounded there. */
    for (int k = 0; k < 3; k++) {
        phos_sky_desc p = d;
        p.model = PHOS_SKY_PREETHAM;
        p.turbidity = 1.642f + 0.001f * (float)k;
        p.sun_direction[0] = 0.3f;
        CHECK(phos_sky_bake(&p, NULL, data) == PHOS_OK);
        vec3 L = sky_preetham_radiance(data, v3(0.0f, 0.6f, 0.8f));
        CHECK_MSG(v3_is_finite(L) && v3_max_component(L) < 1e4f, "turbidity %g: %g", (double)p.turbidity,
                  (double)v3_max_component(L));
    }
    /* The analytic models below the horizon: finite everywhere. */
    for (uint32_t model = PHOS_SKY_PREETHAM; model <= PHOS_SKY_HOSEK_WILKIE; model++) {
        phos_sky_desc a = d;
        a.model = model;
        a.sun_direction[0] = 1.0f, a.sun_direction[2] = -0.2f;
        CHECK(phos_sky_bake(&a, NULL, data) == PHOS_OK);
        for (int i = 0; i < 64; i++) {
            float t = (float)PI * (float)i / 63.0f;
            vec3 v = v3(sinf(t), 0.0f, cosf(t));
            vec3 L = model == PHOS_SKY_PREETHAM ? sky_preetham_radiance(data, v) : sky_hosek_wilkie_radiance(data, v);
            CHECK(v3_is_finite(L));
        }
    }
}

static void test_bad_program_refused(void)
{
    phos_scene *s = phos_scene_create();
    phos_sky_desc d;
    phos_sky_desc_init(&d);
    set_sky_world(s, &d, 1); /* image 0 */
    float data[PHOS_SKY_DATA_FLOATS];
    CHECK(phos_sky_bake(&d, NULL, data) == PHOS_OK);
    phos_shader_instruction sky;
    memset(&sky, 0, sizeof(sky));
    sky.op = PHOS_OP_TEX_SKY;
    /* The data does not fit in the table. */
    CHECK(test_set_world_texture(s, sky, data, PHOS_SKY_DATA_FLOATS - 1) == PHOS_ERROR_INVALID_ARGUMENT);
    data[PHOS_SKY_DATA_IMAGE] = 7.0f; /* no such image */
    CHECK(test_set_world_texture(s, sky, data, PHOS_SKY_DATA_FLOATS) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(phos_scene_error(s), "not an image") != NULL);
    data[PHOS_SKY_DATA_IMAGE] = 0.0f;
    data[SKY_LAYOUT] = 5.0f; /* no such layout */
    CHECK(test_set_world_texture(s, sky, data, PHOS_SKY_DATA_FLOATS) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(phos_scene_error(s), "no texture layout") != NULL);
    data[SKY_LAYOUT] = (float)d.layout;
    CHECK(test_set_world_texture(s, sky, data, PHOS_SKY_DATA_FLOATS) == PHOS_OK);
    sky.mode = PHOS_SKY_MODEL_COUNT;
    CHECK(test_set_world_texture(s, sky, data, PHOS_SKY_DATA_FLOATS) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_scene_destroy(s);
}

int main(void)
{
    test_thin_limit();
    test_airless_sky_is_black();
    test_sun_irradiance();
    test_sun_becomes_a_light();
    test_bad_settings_refused();
    test_bad_program_refused();
    return test_summary("test_sky");
}
