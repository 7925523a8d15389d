/*
 * test_analytic.c — the path tracer against closed-form answers.
 *
 *  - pbrt's test: a Kd = 0.5 sphere around a point light of intensity π.
 *    Direct irradiance is π/r² = π, so L_direct = (0.5/π)·π = 0.5, and in a
 *    sphere every bounce adds the same fraction: L = 0.5/(1 − 0.5) = 1.
 *  - White furnace: a convex diffuse sphere of albedo ρ under a uniform
 *    world of radiance 1 reflects exactly ρ.
 *  - Every light type over a diffuse plane: the irradiance at the point
 *    below the light has a closed form; the plane's radiance is ρE/π.
 *    Direct light only (max_bounces 0), so this checks light sampling, the
 *    units of each light, and the MIS weights of BSDF-sampled hits.
 *
 * Tolerance: the pixel means are independent estimates, so their standard
 * error bounds the noise (4σ); 0.5 % more covers tessellation and the
 * camera footprint.
 */
#include <stdio.h>

#include "test_scenes.h"
#include "test_util.h"

static void check_mean(const char *what, const float *img, size_t pixels, double expected)
{
    for (int c = 0; c < 3; c++) {
        double mean, se;
        test_image_stats(img, pixels, c, &mean, &se);
        double tol = 4.0 * se + 0.005 * expected;
        CHECK_MSG(fabs(mean - expected) <= tol, "%s: channel %d mean %.5f, expected %.5f ± %.5f", what, c, mean,
                  expected, tol);
        if (c == 0)
            printf("  %-28s mean %.5f expected %.5f (±%.5f)\n", what, mean, expected, tol);
    }
}

static void test_sphere_around_point_light(void)
{
    phos_scene *s = phos_scene_create();
    uint32_t mesh = test_add_sphere_mesh(s, 1.0f, 96, 48, 1);
    uint32_t mat = test_add_diffuse(s, 0.5f, 0.5f, 0.5f);
    test_add_instance(s, mesh, mat, 0, 0, 0);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_POINT;
    l.color[0] = l.color[1] = l.color[2] = (float)M_PI; /* intensity W/sr */
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0, 0, 0, 1.0f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 256;
    rs.max_bounces = 200;
    rs.filter_width = 0.0f;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img)
        check_mean("sphere around point light", img, 16 * 16, 1.0);
    free(img);
    phos_scene_destroy(s);
}

static void test_white_furnace(void)
{
    phos_scene *s = phos_scene_create();
    uint32_t mesh = test_add_sphere_mesh(s, 1.0f, 96, 48, 0);
    uint32_t mat = test_add_diffuse(s, 0.8f, 0.8f, 0.8f);
    test_add_instance(s, mesh, mat, 0, 0, 0);
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = 1.0f;
    phos_scene_set_world(s, &w);
    test_set_camera(s, 0, 0, 4, 0.05f); /* sees only the sphere's front */
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 256;
    rs.max_bounces = 16;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img)
        check_mean("white furnace sphere", img, 16 * 16, 0.8);
    free(img);
    phos_scene_destroy(s);
}

/* A camera-visible area lamp in front of a fully transparent plane, black
 * world: every pixel sees the lamp's radiance once. A ray that passes the
 * plane keeps its origin, and the lamp before the plane must not be found
 * again on the way on (it was, and the image read 2 L). Both integrators. */
static void test_lamp_before_transparent_plane(void)
{
    phos_scene *s = phos_scene_create();
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_TRANSPARENT;
    c.weight[0] = c.weight[1] = c.weight[2] = 1.0f;
    test_add_instance(s, test_add_quad_mesh(s, 5.0f), test_add_closure_material(s, &c), 0, 0, 0);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = 1.0f;
    l.direction[2] = 1.0f; /* emits toward the camera */
    l.axis_u[0] = l.axis_v[1] = 4.0f;
    l.color[0] = l.color[1] = l.color[2] = 0.5f;
    l.camera_visible = 1;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0, 0, 3, 0.1f); /* sees only the lamp */
    CHECK(phos_scene_commit(s) == PHOS_OK);
    for (uint32_t integrator = PHOS_INTEGRATOR_PATH; integrator <= PHOS_INTEGRATOR_PHOTON; integrator++) {
        phos_render_settings rs;
        phos_render_settings_init(&rs);
        rs.width = rs.height = 8;
        rs.samples = 4;
        rs.integrator = integrator;
        rs.global_photons = rs.caustic_photons = 1000;
        float *img = test_render(s, &rs);
        CHECK(img != NULL);
        if (img)
            check_mean(integrator == PHOS_INTEGRATOR_PATH ? "PATH: lamp before a transparent plane"
                                                          : "PHOTON: lamp before a transparent plane",
                       img, 8 * 8, 0.5);
        free(img);
    }
    phos_scene_destroy(s);
}

/* Irradiance at a point below the corner of a w×l rectangle at height h,
 * per unit radiance (the form factor times π). */
static double rect_corner_irradiance(double w, double l, double h)
{
    double X = w / h, Y = l / h;
    double a = sqrt(1.0 + X * X), b = sqrt(1.0 + Y * Y);
    double F = (X / a * atan(Y / a) + Y / b * atan(X / b)) / (2.0 * M_PI);
    return M_PI * F;
}

typedef struct light_case {
    const char *name;
    phos_light_desc light;
    int emissive_quad;     /* use a two-sided emissive quad instead of a lamp */
    float world;           /* world radiance, W/(m²·sr) */
    double irradiance;     /* expected at the origin, W/m² */
} light_case;

static void run_light_case(const light_case *lc)
{
    const float rho = 0.5f;
    phos_scene *s = phos_scene_create();
    uint32_t plane = test_add_quad_mesh(s, 1000.0f);
    uint32_t mat = test_add_diffuse(s, rho, rho, rho);
    test_add_instance(s, plane, mat, 0, 0, 0);
    if (lc->emissive_quad) {
        uint32_t quad = test_add_quad_mesh(s, 0.5f);
        phos_closure_desc c;
        phos_closure_desc_init(&c);
        c.type = PHOS_CLOSURE_EMISSION;
        c.weight[0] = c.weight[1] = c.weight[2] = 2.0f;
        phos_material_desc m;
        phos_material_desc_init(&m);
        m.closure_count = 1;
        m.closures = &c;
        uint32_t em;
        phos_scene_add_material(s, &m, &em);
        test_add_instance(s, quad, em, 0, 0, 1.0f);
    } else if (lc->world <= 0.0f) {
        CHECK(phos_scene_add_light(s, &lc->light, NULL) == PHOS_OK);
    }
    if (lc->world > 0.0f) {
        phos_world_desc w;
        phos_world_desc_init(&w);
        w.color[0] = w.color[1] = w.color[2] = lc->world;
        phos_scene_set_world(s, &w);
    }
    /* Looking at the origin from the side, so lamps above it stay out of view. */
    test_set_camera_pitched(s, 0.0f, -3.0f, 3.0f, (float)(M_PI / 4.0), 0.004f);
    CHECK_MSG(phos_scene_commit(s) == PHOS_OK, "%s: %s", lc->name, phos_scene_error(s));
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 8;
    rs.samples = 1024;
    rs.max_bounces = 0;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img)
        check_mean(lc->name, img, 64, rho / M_PI * lc->irradiance);
    free(img);
    phos_scene_destroy(s);
}

static phos_light_desc base_light(uint32_t type, float h)
{
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = type;
    l.position[2] = h;
    l.direction[0] = 0.0f;
    l.direction[1] = 0.0f;
    l.direction[2] = -1.0f;
    return l;
}

static void test_lights_over_plane(void)
{
    const float I = 3.0f, h = 1.0f, r = 0.2f, L = 2.0f, E = 1.5f;
    light_case cases[10];
    int n = 0;

    cases[n] = (light_case){"point light", base_light(PHOS_LIGHT_POINT, h), 0, 0, I / (h * h)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = I;
    n++;
    cases[n] = (light_case){"point light, disk r=0.2", base_light(PHOS_LIGHT_POINT, h), 0, 0, I / (h * h + r * r)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = I;
    cases[n].light.radius = r;
    n++;
    cases[n] = (light_case){"point light, sphere r=0.2", base_light(PHOS_LIGHT_POINT, h), 0, 0, I / (h * h)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = I;
    cases[n].light.radius = r;
    cases[n].light.point_shape = PHOS_POINT_SPHERE;
    n++;
    cases[n] = (light_case){"spot light", base_light(PHOS_LIGHT_SPOT, h), 0, 0, I / (h * h)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = I;
    cases[n].light.spot_cosine = 1; /* cos = 1 on the axis */
    n++;
    cases[n] = (light_case){"area square", base_light(PHOS_LIGHT_AREA, h), 0, 0,
                            4.0 * L * rect_corner_irradiance(0.5, 0.5, h)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = L;
    n++;
    cases[n] = (light_case){"area rectangle 2x0.5", base_light(PHOS_LIGHT_AREA, h), 0, 0,
                            4.0 * L * rect_corner_irradiance(1.0, 0.25, h)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = L;
    cases[n].light.axis_u[0] = 2.0f;
    cases[n].light.axis_v[1] = 0.5f;
    n++;
    /* A disk of radius R on axis: E = πL·R²/(R² + h²). */
    cases[n] = (light_case){"area disk", base_light(PHOS_LIGHT_AREA, h), 0, 0, M_PI * L * 0.25 / (0.25 + h * h)};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = L;
    cases[n].light.area_shape = PHOS_AREA_ELLIPSE;
    n++;
    cases[n] = (light_case){"sun", base_light(PHOS_LIGHT_SUN, h), 0, 0, E};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = E;
    n++;
    cases[n] = (light_case){"sun, angle 10 degrees", base_light(PHOS_LIGHT_SUN, h), 0, 0, E};
    cases[n].light.color[0] = cases[n].light.color[1] = cases[n].light.color[2] = E;
    cases[n].light.sun_angle = (float)(10.0 * M_PI / 180.0);
    n++;
    cases[n] = (light_case){"emissive quad", base_light(PHOS_LIGHT_POINT, h), 1, 0,
                            4.0 * 2.0 * rect_corner_irradiance(0.5, 0.5, h)};
    n++;
    for (int i = 0; i < n; i++)
        run_light_case(&cases[i]);

    light_case world = {"world", base_light(PHOS_LIGHT_POINT, h), 0, 0.7f, M_PI * 0.7};
    run_light_case(&world);
}

int main(void)
{
    test_lamp_before_transparent_plane();
    test_sphere_around_point_light();
    test_white_furnace();
    test_lights_over_plane();
    return test_summary("test_analytic");
}
