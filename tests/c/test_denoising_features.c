/*
 * test_denoising_features.c — the Denoising Albedo and Denoising Normal
 * passes against their definition (Cycles' denoising features): the albedo
 * and camera-space normal of the first surface that is not mostly
 * specular, seen through the specular surfaces before it (their albedo
 * applied), with emitters seen on the way adding to the albedo.
 *
 * The camera at the origin looks down −Z; every scene fills the view with
 * one surface (or none), so each pixel must hold the same values.
 */
#include <stdlib.h>
#include <string.h>

#include "phos.h"
#include "test_scenes.h"
#include "test_util.h"

#define SIZE 8

typedef struct passes {
    float combined[SIZE * SIZE * 4], albedo[SIZE * SIZE * 3], normal[SIZE * SIZE * 3];
} passes;

static int render_passes(phos_scene *s, uint32_t integrator, passes *out)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = SIZE;
    rs.samples = 16;
    rs.integrator = integrator;
    rs.global_photons = 2000;
    rs.caustic_photons = 0;
    rs.max_photons_emitted_millions = 1; /* an open scene stores few: do not chase them */
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF;
    rs.pass_mask = (1u << PHOS_PASS_DENOISING_ALBEDO) | (1u << PHOS_PASS_DENOISING_NORMAL);
    phos_render *r = NULL;
    int ok = phos_render_create(s, &rs, &r) == PHOS_OK &&
             phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK &&
             phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, SIZE, SIZE, out->combined, SIZE * SIZE * 4) == PHOS_OK &&
             phos_render_read(r, PHOS_PASS_DENOISING_ALBEDO, 0, 0, SIZE, SIZE, out->albedo, SIZE * SIZE * 3) ==
                 PHOS_OK &&
             phos_render_read(r, PHOS_PASS_DENOISING_NORMAL, 0, 0, SIZE, SIZE, out->normal, SIZE * SIZE * 3) ==
                 PHOS_OK;
    phos_render_destroy(r);
    return ok;
}

/* Every pixel's value of a 3-channel pass equals v within tol. */
static int all_equal(const float *p, const float v[3], float tol)
{
    for (int i = 0; i < SIZE * SIZE; i++)
        for (int c = 0; c < 3; c++)
            if (!(fabsf(p[3 * i + c] - v[c]) <= tol))
                return 0;
    return 1;
}

static void set_world(phos_scene *s, float radiance)
{
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = radiance;
    phos_scene_set_world(s, &w);
}

static uint32_t add_glossy(phos_scene *s, float weight, float roughness)
{
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_REFLECTION;
    c.weight[0] = c.weight[1] = c.weight[2] = weight;
    c.roughness = roughness;
    return test_add_closure_material(s, &c);
}

static void check_scene(const char *name, phos_scene *s, const float albedo[3], const float normal[3])
{
    CHECK_MSG(phos_scene_commit(s) == PHOS_OK, "%s: commit failed", name);
    for (uint32_t integrator = 0; integrator < 2; integrator++) {
        passes p;
        CHECK_MSG(render_passes(s, integrator, &p), "%s: the render failed", name);
        CHECK_MSG(all_equal(p.albedo, albedo, 1e-4f), "%s (integrator %u): albedo (%.4f %.4f %.4f), expected (%.4f %.4f %.4f)",
                  name, integrator, p.albedo[0], p.albedo[1], p.albedo[2], albedo[0], albedo[1], albedo[2]);
        CHECK_MSG(all_equal(p.normal, normal, 1e-4f), "%s (integrator %u): normal (%.4f %.4f %.4f), expected (%.4f %.4f %.4f)",
                  name, integrator, p.normal[0], p.normal[1], p.normal[2], normal[0], normal[1], normal[2]);
    }
}

int main(void)
{
    /* Camera space as Cycles': x right, y up, z along the view. */
    const float toward_camera[3] = {0.0f, 0.0f, -1.0f}, away[3] = {0.0f, 0.0f, 1.0f}, none[3] = {0, 0, 0};

    /* A diffuse wall facing the camera: its colour, its normal. */
    {
        phos_scene *s = phos_scene_create();
        set_world(s, 0.5f);
        test_add_instance(s, test_add_quad_mesh(s, 50.0f), test_add_diffuse(s, 0.6f, 0.3f, 0.1f), 0, 0, -5);
        test_set_camera(s, 0, 0, 0, 0.2f);
        const float albedo[3] = {0.6f, 0.3f, 0.1f};
        check_scene("diffuse wall", s, albedo, toward_camera);
        phos_scene_destroy(s);
    }
    /* A rough glossy wall (α = 0.64 > 0.075) is where the features stop. */
    {
        phos_scene *s = phos_scene_create();
        set_world(s, 0.5f);
        test_add_instance(s, test_add_quad_mesh(s, 50.0f), add_glossy(s, 0.9f, 0.8f), 0, 0, -5);
        test_set_camera(s, 0, 0, 0, 0.2f);
        const float albedo[3] = {0.9f, 0.9f, 0.9f};
        check_scene("rough glossy wall", s, albedo, toward_camera);
        phos_scene_destroy(s);
    }
    /* A sharp mirror facing the camera, a diffuse wall behind the camera
     * facing it: the wall's albedo times the mirror's, the wall's normal. */
    {
        phos_scene *s = phos_scene_create();
        set_world(s, 0.0f);
        test_add_instance(s, test_add_quad_mesh(s, 50.0f), add_glossy(s, 0.8f, 0.0f), 0, 0, -5);
        test_add_ceiling(s, 50.0f, 5.0f, test_add_diffuse(s, 0.5f, 0.25f, 0.125f)); /* faces −Z, at z = 5 */
        test_set_camera(s, 0, 0, 0, 0.2f);
        const float albedo[3] = {0.4f, 0.2f, 0.1f};
        check_scene("mirror, then a wall", s, albedo, away);
        phos_scene_destroy(s);
    }
    /* The world alone: its radiance is the albedo, there is no normal; and
     * through a mirror, the radiance arriving (the path's throughput times
     * it) times the mirror's albedo, as Cycles counts emitters seen on the
     * way: 0.5 · 0.5 · 0.7. */
    {
        phos_scene *s = phos_scene_create();
        set_world(s, 0.7f);
        test_set_camera(s, 0, 0, 0, 0.2f);
        const float albedo[3] = {0.7f, 0.7f, 0.7f};
        check_scene("the world", s, albedo, none);
        phos_scene_destroy(s);
    }
    {
        phos_scene *s = phos_scene_create();
        set_world(s, 0.7f);
        test_add_instance(s, test_add_quad_mesh(s, 50.0f), add_glossy(s, 0.5f, 0.0f), 0, 0, -5);
        test_set_camera(s, 0, 0, 0, 0.2f);
        const float albedo[3] = {0.175f, 0.175f, 0.175f};
        check_scene("the world in a mirror", s, albedo, none);
        phos_scene_destroy(s);
    }
    return test_summary("test_denoising_features");
}
