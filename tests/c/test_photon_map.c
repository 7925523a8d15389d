/*
 * test_photon_map.c — photon tracing and the radiance estimate against
 * closed forms, and the PHOTON integrator against PATH.
 *
 *  - Irradiance: a point light of intensity I at height h over a large
 *    diffuse plane gives E = I cos θ / d² = Φ cos θ / (4π d²). The estimate
 *    at 40 points must match within 4 standard errors (1/√k relative, box
 *    kernel with the k−1 rule) plus 1 %, and their mean within 2 %.
 *  - Power: every photon from a point light inside a closed sphere lands on
 *    it, so the direct photons carry Φ = 4πI in all; with albedo ρ the
 *    stored power (all bounces) is Φ/(1 − ρ) in expectation (Russian
 *    roulette keeps it unbiased).
 *  - Determinism: the maps are identical for 1 and 3 threads.
 *  - PHOTON vs PATH: each light component pass agrees on the glass-sphere
 *    scene, where the two integrators split the light alike (README, "What
 *    the passes mean"), and Combined is the sum of the components.
 *  - PHOTON with the path-traced gather vs PATH: Direct, Specular and
 *    Indirect agree within the noise alone, also in a closed room.
 *  - Consistency where the bias lives: the fast view's edges, corners and
 *    middle in a white room converge to PATH as photons grow, over
 *    several photon seeds.
 */
#include <stdio.h>
#include <string.h>

#include "photons/kdtree.h"
#include "photons/photon_trace.h"
#include "photons/radiance_estimate.h"
#include "shading/material.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "test_util.h"

static photon_trace_settings trace_settings(uint32_t global, uint32_t caustic, uint32_t threads)
{
    photon_trace_settings ps;
    memset(&ps, 0, sizeof(ps));
    ps.global_photons = global;
    ps.caustic_photons = caustic;
    ps.max_emitted = 50000000;
    ps.max_bounces = 16;
    ps.seed = 3;
    ps.threads = threads;
    ps.radiance_k = 50;
    ps.max_radius = 1.0f;
    return ps;
}

static phos_scene *plane_under_point_light(float I, float h, float rho)
{
    phos_scene *s = phos_scene_create();
    uint32_t plane = test_add_quad_mesh(s, 1000.0f);
    uint32_t mat = test_add_diffuse(s, rho, rho, rho);
    test_add_instance(s, plane, mat, 0, 0, 0);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[2] = h;
    l.color[0] = l.color[1] = l.color[2] = I;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0, 0, 5, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static void test_point_light_irradiance(void)
{
    const float I = 2.0f, h = 1.0f;
    phos_scene *s = plane_under_point_light(I, h, 0.5f);
    photon_trace_settings ps = trace_settings(1000000, 0, 0);
    photon_maps maps;
    photon_maps_init(&maps);
    atomic_int cancel = 0;
    CHECK(photon_maps_trace(s, &ps, &maps, &cancel, NULL) == PHOS_OK);
    CHECK(photon_maps_build(&maps, 0, NULL) == PHOS_OK);
    /* Half the lamp's directions go up and escape; aimed at the plane
     * (test_photon_aiming.c), the paths are emitted downward alone: about
     * one emitted per stored. */
    CHECK_MSG(maps.global.count >= 1000000 && maps.global_emitted > 950000 && maps.global_emitted < 1050000,
              "stored %u, emitted %llu", maps.global.count, (unsigned long long)maps.global_emitted);
    const uint32_t k = 2000;
    kdtree_query q;
    CHECK(kdtree_query_init(&q, k));
    estimate_params ep = {k, 0.5f, ESTIMATE_BOX, 0};
    double sum_ratio = 0.0;
    int n = 0, bad = 0;
    for (int i = 0; i < 40; i++) {
        /* Points out to 0.8 m, where the density is still high. */
        float r = 0.8f * sqrtf((float)(i + 0.5f) / 40.0f), a = 2.4f * (float)i;
        vec3 x = v3(r * cosf(a), r * sinf(a), 0.0f);
        vec3 E = photon_irradiance(&maps.global, x, v3(0, 0, 1), &ep, &q);
        float d2 = r * r + h * h;
        double expected = I * (h / sqrtf(d2)) / d2;
        double ratio = E.x / expected;
        double tol = 4.0 / sqrt((double)k) + 0.01;
        if (fabs(ratio - 1.0) > tol) {
            bad++;
            fprintf(stderr, "  irradiance at r=%.2f: %.4f, expected %.4f\n", r, E.x, expected);
        }
        sum_ratio += ratio;
        n++;
    }
    double mean = sum_ratio / n;
    printf("  point light over a plane: mean estimate / exact = %.4f over %d points\n", mean, n);
    CHECK_MSG(bad == 0, "%d of %d irradiance estimates outside 4σ + 1%%", bad, n);
    CHECK_MSG(fabs(mean - 1.0) < 0.02, "mean ratio %.4f", mean);
    kdtree_query_free(&q);
    photon_maps_free(&maps);
    phos_scene_destroy(s);
}

/* A point light of intensity I (W/sr) at the centre of a closed diffuse
 * sphere of radius 1 m and albedo rho, seen from the centre. */
static phos_scene *light_in_closed_sphere(float I, float rho, int segments, int rings, int smooth)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_sphere_mesh_shaded(s, 1.0f, segments, rings, 1, smooth),
                      test_add_diffuse(s, rho, rho, rho), 0, 0, 0);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.color[0] = l.color[1] = l.color[2] = I;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0, 0, 0, 1.0f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

/* Area of test_add_sphere_mesh's polyhedron (m²). */
static double sphere_mesh_area(double radius, int segments, int rings)
{
    double area = 0.0;
    for (int r = 0; r < rings; r++)
        for (int sg = 0; sg < segments; sg++) {
            double v[4][3];
            for (int k = 0; k < 4; k++) {
                double th = M_PI * (r + (k >> 1)) / rings, ph = 2.0 * M_PI * (sg + (k & 1)) / segments;
                v[k][0] = radius * sin(th) * cos(ph);
                v[k][1] = radius * sin(th) * sin(ph);
                v[k][2] = radius * cos(th);
            }
            static const int tri[2][3] = {{0, 2, 1}, {1, 2, 3}};
            for (int t = 0; t < 2; t++) {
                const double *p0 = v[tri[t][0]], *p1 = v[tri[t][1]], *p2 = v[tri[t][2]];
                double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
                double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
                double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                               e1[0] * e2[1] - e1[1] * e2[0]};
                area += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            }
        }
    return area;
}

/* Christensen's radiance photons against the closed form. They hold the
 * exitance of light that scattered at least once before (final gathering
 * takes direct light at its hits from a light sample). Inside a closed
 * diffuse sphere of albedo ρ with a point light of intensity I at its
 * centre, every bounce spreads its flux uniformly, so the indirect
 * irradiance is E = ρ/(1 − ρ) · 4πI / A everywhere, and every site holds
 * L = ρ/π · E. The ratio's standard error is measured from the sites
 * themselves (neighbouring estimates share photons: the spread is
 * computed over blocks of 64 sites in map order, which are spatially
 * scattered). The sites come from photon paths of their own: taken from
 * the global map's photons, they would sit where its photons cluster, and
 * the lookups below read dark (docs/algorithms.md §5.3). */
static void test_radiance_photons_unbiased(void)
{
    const float I = 2.0f, rho = 0.5f;
    const int segments = 96, rings = 48;
    /* Flat normals: the faces' own. */
    phos_scene *s = light_in_closed_sphere(I, rho, segments, rings, 0);
    /* Few photons an estimate (k = 5) and many photons: on a curved surface
     * the estimate reads dark in proportion to r², so to k/N (measured
     * here at 800 k photons: −0.24 % at k = 5, −0.43 % at k = 20, −0.89 %
     * at k = 80; docs/algorithms.md §5.3). The k − 1 rule, which k = 5
     * tests hardest (counting the k-th photon would read 25 % bright),
     * holds within the noise. */
    photon_trace_settings ps = trace_settings(800000, 0, 0);
    ps.max_radius = 0.5f;
    ps.max_bounces = 64;
    ps.radiance_k = 5;
    photon_maps maps;
    photon_maps_init(&maps);
    atomic_int cancel = 0;
    CHECK(photon_maps_trace(s, &ps, &maps, &cancel, NULL) == PHOS_OK);
    CHECK(photon_maps_build(&maps, 0, NULL) == PHOS_OK);
    CHECK(photon_maps_precompute_radiance(s, &ps, &maps, &cancel) == PHOS_OK);
    double expected = rho / M_PI * rho / (1.0 - rho) * 4.0 * M_PI * I / sphere_mesh_area(1.0, segments, rings);
    double sum = 0.0, block_sum = 0.0, sum_blocks2 = 0.0;
    uint32_t n = 0, blocks = 0, in_block = 0;
    for (uint32_t i = 0; i < maps.radiance.count; i++) {
        double ratio = photon_power(&maps.radiance.photons[i]).x / expected;
        sum += ratio;
        n++;
        block_sum += ratio;
        if (++in_block == 64) {
            sum_blocks2 += (block_sum / 64.0) * (block_sum / 64.0);
            blocks++;
            block_sum = 0.0;
            in_block = 0;
        }
    }
    double mean = sum / n;
    double block_var = sum_blocks2 / blocks - mean * mean;
    double stderr_mean = sqrt(fmax(block_var, 0.0) / blocks);
    printf("  radiance photons in a closed sphere: mean estimate / exact = %.4f ± %.4f over %u sites\n", mean,
           stderr_mean, n);
    CHECK(n > 100000);
    CHECK_MSG(fabs(mean - 1.0) < 4.0 * stderr_mean, "radiance photons: mean ratio %.4f (± %.4f)", mean,
              stderr_mean);
    photon_maps_free(&maps);
    phos_scene_destroy(s);
}

/* A glass bead of 1 cm radius 3 m from a point light, over a floor.
 * Emitted over the whole sphere, a photon hits it about 3 times in a
 * million (50 000 caustic photons would take 17 billion paths); aimed at
 * it by the projection map, about one in five does. With a diffuse board
 * between the lamp and the bead no aimed photon can reach it, and the
 * caustic pass gives up at the first checkpoint (1 M paths) instead of
 * running to its cap (10 paths a photon of its target: 2 M for 200 000;
 * before that cap, the 50 M of the emission limit), keeps the photons it
 * has, and does so at the same path whatever the thread count. */
static void bead_maps(int blocked, uint32_t caustic, photon_maps *a, photon_maps *b)
{
    phos_scene *s = phos_scene_create();
    uint32_t grey = test_add_diffuse(s, 0.5f, 0.5f, 0.5f);
    test_add_instance(s, test_add_quad_mesh(s, 5.0f), grey, 0, 0, 0);
    test_add_instance(s, test_add_sphere_mesh(s, 0.01f, 16, 8, 0), test_add_glass(s, 1.5f), 0, 0, 0.5f);
    if (blocked)
        test_add_ceiling(s, 0.5f, 2.0f, grey);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[2] = 3.5f;
    l.color[0] = l.color[1] = l.color[2] = 10.0f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0, 0, 3.0f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    for (int t = 0; t < 2; t++) {
        photon_trace_settings ps = trace_settings(1000, caustic, t ? 2u : 1u);
        photon_maps *m = t ? b : a;
        photon_maps_init(m);
        atomic_int cancel = 0;
        CHECK(photon_maps_trace(s, &ps, m, &cancel, NULL) == PHOS_OK);
        CHECK(photon_maps_build(m, 0, NULL) == PHOS_OK);
    }
    CHECK(a->caustic_emitted == b->caustic_emitted && a->caustic.count == b->caustic.count);
    CHECK(a->caustic.count == 0 ||
          memcmp(a->caustic.photons, b->caustic.photons, sizeof(photon) * a->caustic.count) == 0);
    phos_scene_destroy(s);
}

static void test_caustic_photons_aimed_at_a_bead(void)
{
    photon_maps a, b;
    bead_maps(0, 50000, &a, &b);
    printf("  glass bead: %u caustic photons from %llu paths (cap 500 k)\n", a.caustic.count,
           (unsigned long long)a.caustic_emitted);
    CHECK_MSG(a.caustic.count >= 50000 && a.caustic_emitted < 1000000,
              "aimed at the bead, 50 000 caustic photons took %llu paths (%u stored)",
              (unsigned long long)a.caustic_emitted, a.caustic.count);
    photon_maps_free(&a);
    photon_maps_free(&b);
    bead_maps(1, 200000, &a, &b);
    printf("  glass bead behind a board: %u caustic photons from %llu paths\n", a.caustic.count,
           (unsigned long long)a.caustic_emitted);
    CHECK_MSG(a.caustic_emitted == 1000000, "the caustic pass emitted %llu paths, not 1 M",
              (unsigned long long)a.caustic_emitted);
    CHECK(a.caustic.count < 5000);
    photon_maps_free(&a);
    photon_maps_free(&b);
}

/* Projection maps change where caustic photons are emitted, not what the
 * map holds in expectation: the caustic map's total power must equal that
 * of the caustic-flagged photons of the global map, which is emitted over
 * every direction. Glass and mirror balls over a floor, lit by a point
 * lamp, a spot with a blend, an area light, a sun with an angle and a
 * uniform world (the sun and the world aim through plane cells, the
 * others through cones). Within 4 standard errors of the two sums (each
 * photon's power taken as an independent draw). Three traces: the global
 * map alone, the caustic map alone (all its photons aimed), and both,
 * where the caustic map reuses the global pass's caustic photons and the
 * caustic pass traces only the rest (another seed, so independent of the
 * first). */
static double caustic_power(const photon_map *pm, int only_flagged, double *sum2, uint32_t *n)
{
    double sum = 0.0;
    *sum2 = 0.0;
    *n = 0;
    for (uint32_t i = 0; i < pm->count; i++) {
        if (only_flagged && !photon_is_caustic(&pm->photons[i]))
            continue;
        double p = v3_average(photon_power(&pm->photons[i]));
        sum += p;
        *sum2 += p * p;
        (*n)++;
    }
    return sum;
}

static void test_caustic_projection_unbiased(int sky)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 3.0f), test_add_diffuse(s, 0.6f, 0.6f, 0.6f), 0, 0, 0);
    test_add_instance(s, test_add_sphere_mesh(s, 0.3f, 32, 16, 0), test_add_glass(s, 1.5f), -0.5f, 0, 0.5f);
    test_add_instance(s, test_add_sphere_mesh(s, 0.25f, 32, 16, 0), test_add_mirror(s), 0.7f, 0.3f, 0.4f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[0] = 1.0f;
    l.position[2] = 2.5f;
    l.color[0] = l.color[1] = l.color[2] = 5.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SPOT;
    l.position[0] = -1.5f;
    l.position[2] = 2.0f;
    l.direction[0] = 0.5f;
    l.direction[2] = -1.0f;
    l.spot_angle = 0.8f;
    l.spot_blend = 0.4f;
    l.radius = 0.1f;
    l.color[0] = l.color[1] = l.color[2] = 8.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[1] = -1.5f;
    l.position[2] = 2.0f;
    l.direction[1] = 0.6f;
    l.direction[2] = -0.8f;
    l.axis_u[0] = 0.8f;
    l.axis_v[1] = 0.48f;
    l.axis_v[2] = 0.36f;
    l.color[0] = l.color[1] = l.color[2] = 3.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SUN;
    l.direction[0] = 0.3f;
    l.direction[2] = -1.0f;
    l.sun_angle = 0.2f;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    phos_scene_add_light(s, &l, NULL);
    if (sky) {
        /* A sky with a bright patch: the world's caustic photons are drawn
         * from its map and aimed at the spheres' discs. */
        test_set_sky_with_patch(s, 0.05f, 3.0f, 11, 4, 8);
    } else {
        phos_world_desc w;
        phos_world_desc_init(&w);
        w.color[0] = w.color[1] = w.color[2] = 0.1f;
        phos_scene_set_world(s, &w);
    }
    test_set_camera(s, 0, 0, 3.0f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    const uint32_t global[3] = {400000, 0, 400000}, caustic[3] = {0, 100000, 100000};
    double sum[3], sum2[3];
    uint32_t n[3], reused = 0, own = 0;
    for (int k = 0; k < 3; k++) {
        photon_trace_settings ps = trace_settings(global[k], caustic[k], 0);
        ps.seed = k == 2 ? 11u : 3u;
        photon_maps m;
        photon_maps_init(&m);
        atomic_int cancel = 0;
        CHECK(photon_maps_trace(s, &ps, &m, &cancel, NULL) == PHOS_OK);
        sum[k] = caustic_power(k ? &m.caustic : &m.global, k == 0, &sum2[k], &n[k]);
        if (k == 2) {
            reused = m.caustic_reused;
            own = m.caustic.count - reused;
        }
        printf("  caustic power%s, %s: %.5f W (%u photons%s)\n", sky ? " under a sky" : "",
               k == 0 ? "global map's caustic photons" : k == 1 ? "caustic map alone" : "caustic map with reuse",
               sum[k], n[k], k == 2 ? ", some reused" : "");
        photon_maps_free(&m);
    }
    printf("  caustic map with reuse: %u reused from the global pass, %u traced\n", reused, own);
    CHECK(n[0] > 1000 && n[1] >= 100000 && n[2] >= 100000);
    CHECK_MSG(reused > 1000 && own >= 100000 - reused && own < 100000 - reused + 100,
              "the caustic pass traced %u photons beside %u reused", own, reused);
    for (int k = 1; k < 3; k++) {
        double se = sqrt(sum2[0] + sum2[k]);
        CHECK_MSG(fabs(sum[k] - sum[0]) < 4.0 * se, "%s caustic photons carry %.5f W, unaimed ones %.5f W (± %.5f)",
                  k == 1 ? "aimed" : "aimed and reused", sum[k], sum[0], 4.0 * se);
    }
    phos_scene_destroy(s);
}

/* The caustic pass aimed at the view (photon_trace.c, aim_caustic): a sun
 * over a glass sphere, whose caustic the camera sees, and a mirror sphere
 * out of view. The pilots weigh the sun's cells by the share of their
 * paths that store a caustic photon in view, so more of the emitted paths
 * end there, and the caustic power in view is the same as unweighted
 * (within 4 standard errors). */
static void test_caustic_aimed_at_view(void)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 4.0f), test_add_diffuse(s, 0.6f, 0.6f, 0.6f), 0, 0, 0);
    test_add_instance(s, test_add_sphere_mesh(s, 0.3f, 32, 16, 0), test_add_glass(s, 1.5f), 0, 0, 0.3f);
    test_add_instance(s, test_add_sphere_mesh(s, 0.3f, 32, 16, 0), test_add_mirror(s), -2.0f, 0, 0.3f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SUN;
    l.direction[0] = 0.6f;
    l.direction[2] = -0.8f;
    l.sun_angle = 0.01f;
    l.color[0] = l.color[1] = l.color[2] = 3.0f;
    phos_scene_add_light(s, &l, NULL);
    /* Looking straight down at x in [0.1, 1.3], y in [−0.6, 0.6]: the glass
     * sphere's caustic, which the sun throws toward +x. */
    test_set_camera(s, 0.7f, 0.0f, 2.0f, 0.3f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    double power[2], se2[2], yield[2];
    for (int aimed = 0; aimed < 2; aimed++) {
        photon_trace_settings ps = trace_settings(0, 40000, 0);
        ps.unaimed = aimed ? 0 : 1;
        ps.seed = 5u + (uint32_t)aimed;
        photon_maps m;
        photon_maps_init(&m);
        atomic_int cancel = 0;
        CHECK(photon_maps_trace(s, &ps, &m, &cancel, NULL) == PHOS_OK);
        uint32_t in_view = 0;
        power[aimed] = se2[aimed] = 0.0;
        for (uint32_t i = 0; i < m.caustic.count; i++) {
            const photon *p = &m.caustic.photons[i];
            if (fabsf(p->position[0] - 0.7f) > 0.6f || fabsf(p->position[1]) > 0.6f)
                continue;
            double w = v3_average(photon_power(p));
            power[aimed] += w;
            se2[aimed] += w * w;
            in_view++;
        }
        yield[aimed] = (double)in_view / (double)m.caustic_emitted;
        printf("  caustic photons in view, %s: %u of %llu paths (%.4f a path), %.5f W\n",
               aimed ? "cells weighed by the view" : "cells unweighed", in_view,
               (unsigned long long)m.caustic_emitted, yield[aimed], power[aimed]);
        CHECK(m.aimed_at_view == aimed);
        photon_maps_free(&m);
    }
    CHECK_MSG(yield[1] > 2.0 * yield[0], "the view's pilots raised the yield in view only from %.4f to %.4f",
              yield[0], yield[1]);
    double se = sqrt(se2[0] + se2[1]);
    CHECK_MSG(fabs(power[1] - power[0]) < 4.0 * se, "caustic power in view %.5f W aimed, %.5f W unaimed (± %.5f)",
              power[1], power[0], 4.0 * se);
    phos_scene_destroy(s);
}

/* Radiance-photon lookups in a corner: a floor (normal +z, L = 1) with a
 * record every 5 cm meets a wall (normal +y, L = 2) with a record every
 * 5 mm. Just in front of the wall the 8 records nearest to a floor point
 * are all wall records, which face the other way; the lookup must still
 * find a floor record, and only floor records. */
static void test_radiance_lookup_in_a_corner(void)
{
    photon_map m;
    photon_map_init(&m);
    int ok = 1;
    for (int i = -20; i <= 20; i++)
        for (int j = 1; j <= 20; j++) {
            photon p = photon_make(v3(0.05f * i, 0.05f * j, 0.0f), v3s(1.0f), v3(0, 0, 1), v3(0, 0, 1), 0);
            ok &= photon_map_append(&m, &p, 1);
        }
    for (int i = -200; i <= 200; i++)
        for (int j = 0; j <= 100; j++) {
            photon p = photon_make(v3(0.005f * i, 0.0f, 0.005f * j), v3s(2.0f), v3(0, 1, 0), v3(0, 1, 0), 0);
            ok &= photon_map_append(&m, &p, 1);
        }
    CHECK(ok && photon_map_build(&m, NULL));
    kdtree_query q, q8;
    CHECK(kdtree_query_init(&q, 1) && kdtree_query_init(&q8, 8));
    int crowded = 0, wrong = 0;
    for (int i = 0; i < 20; i++) {
        vec3 x = v3(-0.5f + 0.05f * i + 0.013f, 0.004f, 0.0f);
        /* The situation: all 8 Euclidean nearest records are on the wall. */
        photon_map_knn(&m, x, 1.0f, &q8);
        int floor_records = 0;
        for (uint32_t j = 0; j < q8.found; j++)
            floor_records += photon_direction(kdtree_result(m.photons, &q8, j)).z > 0.5f;
        crowded += floor_records == 0;
        vec3 L;
        int found = radiance_photon_lookup(&m, x, v3(0, 0, 1), 0.5f, &q, &L);
        wrong += !found || fabsf(L.x - 1.0f) > 0.01f;
    }
    CHECK_MSG(crowded == 20, "only %d of 20 corner points have no floor record among the 8 nearest", crowded);
    CHECK_MSG(wrong == 0, "%d of 20 corner lookups did not return the floor's radiance", wrong);
    /* Nothing facing the query's way within the radius: not found. */
    vec3 L;
    CHECK(!radiance_photon_lookup(&m, v3(0.0f, 0.01f, 0.3f), v3(0, -1, 0), 0.1f, &q, &L));
    kdtree_query_free(&q);
    kdtree_query_free(&q8);
    photon_map_free(&m);
}

/* The caustic pass traces nothing where no surface has a delta lobe (it
 * could never store a photon), and does where one has. */
static void test_caustic_pass_needs_a_delta_lobe(void)
{
    struct {
        uint32_t type;
        float roughness, ior;
        int delta;
    } cases[] = {
        {PHOS_CLOSURE_DIFFUSE, 0.0f, 1.5f, 0},
        {PHOS_CLOSURE_REFLECTION, 0.3f, 1.5f, 0},          /* rough metal */
        {PHOS_CLOSURE_REFLECTION, 0.0f, 1.5f, 1},          /* mirror */
        {PHOS_CLOSURE_REFLECTION_FRESNEL, 0.005f, 1.5f, 1}, /* sharp coat: α = 2.5e-5 */
        {PHOS_CLOSURE_GLASS, 0.2f, 1.5f, 0},               /* frosted glass */
        {PHOS_CLOSURE_GLASS, 0.2f, 1.0f, 1},               /* index-matched: a straight pass */
        {PHOS_CLOSURE_REFRACTION, 0.0f, 1.45f, 1},
        {PHOS_CLOSURE_TRANSPARENT, 0.0f, 1.5f, 0},         /* pass-through is no scattering */
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        phos_scene *s = phos_scene_create();
        phos_closure_desc c;
        phos_closure_desc_init(&c);
        c.type = cases[i].type;
        c.roughness = cases[i].roughness;
        c.ior = cases[i].ior;
        uint32_t floor_mesh = test_add_quad_mesh(s, 3.0f);
        test_add_instance(s, floor_mesh, test_add_diffuse(s, 0.5f, 0.5f, 0.5f), 0, 0, 0);
        /* The material under test on a small panel above the floor. */
        test_add_instance(s, test_add_quad_mesh(s, 0.5f), test_add_closure_material(s, &c), 0, 0, 0.5f);
        phos_light_desc l;
        phos_light_desc_init(&l);
        l.position[2] = 2.0f;
        l.color[0] = l.color[1] = l.color[2] = 2.0f;
        phos_scene_add_light(s, &l, NULL);
        test_set_camera(s, 0, 0, 5, 0.5f);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        CHECK_MSG(scene_can_scatter_caustic(s, 0.0f) == cases[i].delta, "case %zu: closure %u, roughness %.3f, ior %.2f",
                  i, cases[i].type, cases[i].roughness, cases[i].ior);
        photon_trace_settings ps = trace_settings(2000, 2000, 0);
        ps.max_emitted = 2000000;
        photon_maps maps;
        photon_maps_init(&maps);
        atomic_int cancel = 0;
        CHECK(photon_maps_trace(s, &ps, &maps, &cancel, NULL) == PHOS_OK);
        if (cases[i].delta)
            CHECK_MSG(maps.caustic_emitted > 0, "case %zu: no caustic paths traced", i);
        else
            CHECK_MSG(maps.caustic_emitted == 0 && maps.caustic.count == 0,
                      "case %zu: %llu caustic paths traced where none can be stored", i,
                      (unsigned long long)maps.caustic_emitted);
        photon_maps_free(&maps);
        phos_scene_destroy(s);
    }
}

/* Flux of the direct photons a light leaves on an almost black receiver
 * (albedo 10⁻³, so photons are stored at their first hit and then die),
 * against the light's power in closed form. Inside a closed sphere every
 * photon lands and the sum is exact up to RGBE rounding of each photon's
 * power (< 1/256, mostly cancelling: 0.5 % is allowed for it); on a plane
 * under a distant light the number that lands is binomial, and 4 of its
 * standard errors are added. */
static double direct_flux(phos_scene *s, uint32_t photons, int from_above_only, double *hit_fraction)
{
    photon_trace_settings ps = trace_settings(photons, 0, 0);
    photon_maps maps;
    photon_maps_init(&maps);
    atomic_int cancel = 0;
    CHECK(photon_maps_trace(s, &ps, &maps, &cancel, NULL) == PHOS_OK);
    double flux = 0.0;
    for (uint32_t i = 0; i < maps.global.count; i++) {
        const photon *p = &maps.global.photons[i];
        if (photon_is_direct(p) && (!from_above_only || photon_direction(p).z < 0.0f))
            flux += photon_power(p).x;
    }
    *hit_fraction = maps.global_emitted ? (double)maps.global.count / (double)maps.global_emitted : 0.0;
    photon_maps_free(&maps);
    return flux;
}

static phos_scene *light_in_black_sphere(const phos_light_desc *l)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_sphere_mesh(s, 3.0f, 48, 24, 1), test_add_diffuse(s, 1e-3f, 1e-3f, 1e-3f), 0, 0,
                      0);
    phos_scene_add_light(s, l, NULL);
    test_set_camera(s, 0, 0, 0, 1.0f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static void test_emitted_flux_per_light_type(void)
{
    const double L = 1.5;
    /* Lamps and an emissive mesh inside a closed sphere. */
    struct {
        const char *name;
        phos_light_desc d;
        double flux;
    } lamps[4];
    for (int i = 0; i < 4; i++)
        phos_light_desc_init(&lamps[i].d);
    lamps[0].name = "area rectangle";
    lamps[0].d.type = PHOS_LIGHT_AREA;
    lamps[0].d.axis_u[0] = 0.5f;
    lamps[0].d.axis_v[1] = 0.3f;
    lamps[0].flux = M_PI * 0.15 * L; /* πAL */
    lamps[1].name = "area ellipse";
    lamps[1].d = lamps[0].d;
    lamps[1].d.area_shape = PHOS_AREA_ELLIPSE;
    lamps[1].flux = M_PI * (M_PI * 0.25 * 0.15) * L;
    const float cos_half = cosf(0.5f * 0.9f);
    lamps[2].name = "spot, hard edge";
    lamps[2].d.type = PHOS_LIGHT_SPOT;
    lamps[2].d.spot_angle = 0.9f;
    lamps[2].d.spot_blend = 0.0f;
    lamps[2].flux = 2.0 * M_PI * L * (1.0 - cos_half); /* ∫ I dω over the cone */
    lamps[3].name = "spot, blend 0.4";
    lamps[3].d = lamps[2].d;
    lamps[3].d.spot_blend = 0.4f;
    /* smoothstep over the outer w = (1 − cos_half)·blend of cos θ integrates to w/2 */
    lamps[3].flux = 2.0 * M_PI * L * (1.0 - cos_half - 0.5 * (1.0 - cos_half) * 0.4);
    for (int i = 0; i < 4; i++) {
        lamps[i].d.direction[2] = 1.0f;
        lamps[i].d.color[0] = lamps[i].d.color[1] = lamps[i].d.color[2] = (float)L;
        phos_scene *s = light_in_black_sphere(&lamps[i].d);
        double hit;
        double flux = direct_flux(s, 200000, 0, &hit);
        printf("  emitted flux, %-16s %.5f W, closed form %.5f W\n", lamps[i].name, flux, lamps[i].flux);
        CHECK_MSG(fabs(flux / lamps[i].flux - 1.0) < 0.005, "%s: flux %.5f W, expected %.5f W", lamps[i].name, flux,
                  lamps[i].flux);
        phos_scene_destroy(s);
    }
    /* An emissive quad (two triangles, both faces emit): 2πAL. */
    {
        phos_scene *s = phos_scene_create();
        test_add_instance(s, test_add_sphere_mesh(s, 3.0f, 48, 24, 1), test_add_diffuse(s, 1e-3f, 1e-3f, 1e-3f), 0,
                          0, 0);
        phos_closure_desc e;
        phos_closure_desc_init(&e);
        e.type = PHOS_CLOSURE_EMISSION;
        e.weight[0] = e.weight[1] = e.weight[2] = (float)L;
        test_add_instance(s, test_add_quad_mesh(s, 0.3f), test_add_closure_material(s, &e), 0, 0, 0);
        test_set_camera(s, 0, 0, -1.0f, 1.0f);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        double hit, expected = 2.0 * M_PI * 0.36 * L;
        double flux = direct_flux(s, 200000, 0, &hit);
        printf("  emitted flux, %-16s %.5f W, closed form %.5f W\n", "emissive mesh", flux, expected);
        CHECK_MSG(fabs(flux / expected - 1.0) < 0.005, "emissive mesh: flux %.5f W, expected %.5f W", flux, expected);
        phos_scene_destroy(s);
    }
    /* Distant lights over a 4 m × 4 m absorbing plane: the sun's irradiance
     * at normal incidence E (its whole disc, angle or not), the world's πL
     * on the side facing up. */
    struct {
        const char *name;
        int world;
        float angle;
        double flux;
    } distant[] = {
        {"sun, angle 0", 0, 0.0f, 16.0 * L},
        {"sun, angle 30°", 0, (float)(M_PI / 6.0), 16.0 * L},
        {"world", 1, 0.0f, 16.0 * M_PI * L},
    };
    for (size_t i = 0; i < sizeof(distant) / sizeof(distant[0]); i++) {
        phos_scene *s = phos_scene_create();
        test_add_instance(s, test_add_quad_mesh(s, 2.0f), test_add_diffuse(s, 1e-3f, 1e-3f, 1e-3f), 0, 0, 0);
        if (distant[i].world) {
            phos_world_desc w;
            phos_world_desc_init(&w);
            w.color[0] = w.color[1] = w.color[2] = (float)L;
            phos_scene_set_world(s, &w);
        } else {
            phos_light_desc l;
            phos_light_desc_init(&l);
            l.type = PHOS_LIGHT_SUN;
            l.direction[2] = -1.0f;
            l.sun_angle = distant[i].angle;
            l.color[0] = l.color[1] = l.color[2] = (float)L;
            phos_scene_add_light(s, &l, NULL);
        }
        test_set_camera(s, 0, 0, 5, 0.5f);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        double p;
        double flux = direct_flux(s, 200000, 1, &p);
        /* Landed photons: binomial out of ~200000/p emitted. */
        double rel_se = sqrt((1.0 - p) / 200000.0);
        double tol = 4.0 * rel_se + 0.005;
        printf("  emitted flux, %-16s %.5f W, closed form %.5f W (±%.2f %%)\n", distant[i].name, flux,
               distant[i].flux, 100.0 * tol);
        CHECK_MSG(fabs(flux / distant[i].flux - 1.0) < tol, "%s: flux %.5f W, expected %.5f W", distant[i].name, flux,
                  distant[i].flux);
        phos_scene_destroy(s);
    }
}

static void test_power_in_closed_sphere(void)
{
    const float I = 1.5f, rho = 0.6f;
    phos_scene *s = light_in_closed_sphere(I, rho, 48, 24, 1);
    photon_trace_settings ps = trace_settings(200000, 0, 0);
    ps.max_bounces = 200;
    photon_maps maps;
    photon_maps_init(&maps);
    atomic_int cancel = 0;
    CHECK(photon_maps_trace(s, &ps, &maps, &cancel, NULL) == PHOS_OK);
    double direct = 0.0, all = 0.0;
    for (uint32_t i = 0; i < maps.global.count; i++) {
        vec3 p = photon_power(&maps.global.photons[i]);
        all += p.x;
        if (photon_is_direct(&maps.global.photons[i]))
            direct += p.x;
    }
    double phi = 4.0 * M_PI * I;
    printf("  closed sphere: direct power %.4f W, all %.4f W (Φ = %.4f, Φ/(1-ρ) = %.4f)\n", direct, all, phi,
           phi / (1.0 - rho));
    /* Direct: exact up to the RGBE rounding of each photon (< 1/256) and the
     * photons of the last, partial path. */
    CHECK_REL(direct, phi, 0.005);
    /* All bounces: a random number of photons per path; 2 % is many σ. */
    CHECK_REL(all, phi / (1.0 - rho), 0.02);
    photon_maps_free(&maps);
    phos_scene_destroy(s);
}

static phos_scene *glass_sphere_scene(void)
{
    phos_scene *s = phos_scene_create();
    uint32_t plane = test_add_quad_mesh(s, 3.0f);
    uint32_t white = test_add_diffuse(s, 0.7f, 0.7f, 0.7f);
    test_add_instance(s, plane, white, 0, 0, 0);
    uint32_t glass = test_add_glass(s, 1.5f);
    uint32_t sphere = test_add_sphere_mesh(s, 0.4f, 48, 24, 0);
    test_add_instance(s, sphere, glass, 0, 0, 0.6f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = 2.5f;
    l.axis_u[0] = 0.5f;
    l.axis_v[1] = 0.5f;
    l.color[0] = l.color[1] = l.color[2] = 60.0f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera_pitched(s, 0.0f, -3.5f, 3.0f, 0.9f, 0.6f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static void test_maps_deterministic(void)
{
    phos_scene *s = glass_sphere_scene();
    photon_maps a, b;
    photon_maps_init(&a);
    photon_maps_init(&b);
    atomic_int cancel = 0;
    photon_trace_settings p1 = trace_settings(30000, 10000, 1), p3 = trace_settings(30000, 10000, 3);
    CHECK(photon_maps_trace(s, &p1, &a, &cancel, NULL) == PHOS_OK && photon_maps_build(&a, p1.threads, NULL) == PHOS_OK);
    CHECK(photon_maps_trace(s, &p3, &b, &cancel, NULL) == PHOS_OK && photon_maps_build(&b, p3.threads, NULL) == PHOS_OK);
    CHECK(a.global.count == b.global.count && a.caustic.count == b.caustic.count);
    CHECK(a.global_emitted == b.global_emitted && a.caustic_emitted == b.caustic_emitted);
    CHECK(a.global.count && memcmp(a.global.photons, b.global.photons, sizeof(photon) * a.global.count) == 0);
    CHECK(a.caustic.count && memcmp(a.caustic.photons, b.caustic.photons, sizeof(photon) * a.caustic.count) == 0);
    /* Caustic photons are flagged, came through at least one bounce (are not
     * direct), and
     * most lie in the focus under the sphere (the rest are reflections off
     * its surface, which land anywhere). */
    uint32_t unflagged = 0, focused = 0;
    for (uint32_t i = 0; i < a.caustic.count; i++) {
        const photon *p = &a.caustic.photons[i];
        vec3 x = photon_position(p);
        unflagged += !photon_is_caustic(p) || photon_is_direct(p);
        focused += x.x * x.x + x.y * x.y < 0.5f * 0.5f;
    }
    CHECK_MSG(unflagged == 0, "%u caustic photons unflagged or without a bounce", unflagged);
    CHECK_MSG(focused > a.caustic.count / 2, "only %u of %u caustic photons under the sphere", focused, a.caustic.count);
    photon_maps_free(&a);
    photon_maps_free(&b);
    phos_scene_destroy(s);
}

/* Renders with rs and reads the passes of rs.pass_mask (the others stay
 * zero); progress (may be NULL) gets the final progress. */
static float *render_settings_passes(phos_scene *s, const phos_render_settings *rs, float *passes[PHOS_PASS_COUNT],
                                     phos_progress *progress)
{
    uint32_t w = rs->width;
    phos_render *r = NULL;
    CHECK(phos_render_create(s, rs, &r) == PHOS_OK);
    if (!r)
        return NULL;
    CHECK(phos_render_start(r) == PHOS_OK);
    CHECK(phos_render_wait(r, -1.0) == PHOS_OK);
    if (progress)
        CHECK(phos_render_progress(r, progress) == PHOS_OK);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        uint32_t ch = phos_pass_channels(p);
        passes[p] = calloc((size_t)ch * w * w, sizeof(float));
        if (rs->pass_mask & (1u << p))
            CHECK(phos_render_read(r, p, 0, 0, w, w, passes[p], (size_t)ch * w * w) == PHOS_OK);
    }
    phos_render_destroy(r);
    return passes[0];
}

/* Square test renders of w² pixels, 8 bounces, 16 gather rays, no
 * irradiance cache. */
static phos_render_settings test_settings(uint32_t integrator, uint32_t mask, uint32_t samples, uint32_t seed,
                                          uint32_t w)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.seed = seed;
    rs.width = rs.height = w;
    rs.samples = samples;
    rs.integrator = integrator;
    rs.max_bounces = 8;
    rs.pass_mask = mask ? mask : (1u << PHOS_PASS_COUNT) - 1u;
    rs.final_gather_rays = 16;
    /* These tests are of the photon maps and the gather; the irradiance
     * cache over them is test_irradiance_cache.c's. */
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF;
    return rs;
}

/* Every pass of mask (0: all); view is the photon view, 100 k photons in
 * each map. */
static float *render_view(phos_scene *s, uint32_t integrator, uint32_t view, uint32_t mask, uint32_t samples,
                          uint32_t seed, float *passes[PHOS_PASS_COUNT], uint32_t w, phos_progress *progress)
{
    phos_render_settings rs = test_settings(integrator, mask, samples, seed, w);
    rs.photon_view = view;
    rs.global_photons = rs.caustic_photons = 100000;
    return render_settings_passes(s, &rs, passes, progress);
}

/* PHOTON with final gathering and `photons` in the global map (a quarter as
 * many caustic photons). */
static float *render_photons(phos_scene *s, uint32_t photons, uint32_t mask, uint32_t samples, uint32_t seed,
                             float *passes[PHOS_PASS_COUNT], uint32_t w)
{
    phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON, mask, samples, seed, w);
    rs.global_photons = photons;
    rs.caustic_photons = photons / 4;
    return render_settings_passes(s, &rs, passes, NULL);
}

static float *render_passes(phos_scene *s, uint32_t integrator, uint32_t samples, uint32_t seed,
                            float *passes[PHOS_PASS_COUNT], uint32_t w)
{
    return render_view(s, integrator, PHOS_PHOTON_VIEW_FINAL_GATHER, 0, samples, seed, passes, w, NULL);
}

/* Frees four renders' passes (render_view). */
static void free_pass_sets(float *a[PHOS_PASS_COUNT], float *b[PHOS_PASS_COUNT], float *c[PHOS_PASS_COUNT],
                           float *d[PHOS_PASS_COUNT])
{
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(a[p]);
        free(b[p]);
        free(c[p]);
        free(d[p]);
    }
}

/* Standard error of the mean of two renders a and b with different seeds:
 * per pixel, Var(a − b) = 2σ², and the mean of (a + b)/2 over n pixels has
 * variance σ²/(2n) = Var(a − b)/(4n). */
static double pair_stderr(const float *a, const float *b, uint32_t channels, uint32_t n)
{
    double m = 0.0, v = 0.0;
    for (uint32_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            m += a[i * channels + c] - b[i * channels + c];
    m /= 3.0 * n;
    for (uint32_t i = 0; i < n; i++) {
        double d = 0.0;
        for (int c = 0; c < 3; c++)
            d += (a[i * channels + c] - b[i * channels + c]) / 3.0;
        v += (d - m) * (d - m);
    }
    return sqrt(v / (n - 1) / (4.0 * n));
}

/* One pass of two renders of rs, with seeds rs.seed and rs.seed + 1: the
 * mean over both and the standard error of that mean from their
 * difference. */
static void pass_mean_of_pair(phos_scene *s, phos_render_settings rs, uint32_t pass, double *mean, double *se)
{
    const uint32_t n = rs.width * rs.height, ch = phos_pass_channels(pass);
    float *a[PHOS_PASS_COUNT], *b[PHOS_PASS_COUNT];
    CHECK(render_settings_passes(s, &rs, a, NULL) != NULL);
    rs.seed++;
    CHECK(render_settings_passes(s, &rs, b, NULL) != NULL);
    *mean = 0.5 * (test_mean_rgb(a[pass], ch, n) + test_mean_rgb(b[pass], ch, n));
    *se = pair_stderr(a[pass], b[pass], ch, n);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(a[p]);
        free(b[p]);
    }
}

static void test_photon_vs_path(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = glass_sphere_scene();
    const uint32_t w = 32, n = w * w;
    float *path[PHOS_PASS_COUNT], *path2[PHOS_PASS_COUNT], *pm[PHOS_PASS_COUNT], *pm2[PHOS_PASS_COUNT];
    CHECK(render_passes(s, PHOS_INTEGRATOR_PATH, 1024, 1, path, w) != NULL);
    CHECK(render_passes(s, PHOS_INTEGRATOR_PATH, 1024, 2, path2, w) != NULL);
    CHECK(render_passes(s, PHOS_INTEGRATOR_PHOTON, 64, 1, pm, w) != NULL);
    CHECK(render_passes(s, PHOS_INTEGRATOR_PHOTON, 64, 2, pm2, w) != NULL);
    static const char *names[] = {"combined", "emission", "direct", "specular", "caustics", "indirect"};
    /* Tolerance: 4 standard errors of the difference of the two means (each
     * from a pair of renders with different seeds; the caustic focus is a
     * small part of a pixel, so camera sampling is the main noise of both),
     * and nothing else: no allowance for the photon maps' bias, which at
     * 100 k photons is below the noise of every pass (it once had 10 % for
     * Caustics and Indirect, and 2–3 % for the rest). Emission too: the
     * camera sees no emitter here, so both must read exactly 0. */
    for (uint32_t p = 0; p <= PHOS_PASS_INDIRECT; p++) {
        uint32_t ch = phos_pass_channels(p);
        double a = 0.5 * (test_mean_rgb(path[p], ch, n) + test_mean_rgb(path2[p], ch, n));
        double b = 0.5 * (test_mean_rgb(pm[p], ch, n) + test_mean_rgb(pm2[p], ch, n));
        double se_a = pair_stderr(path[p], path2[p], ch, n), se_b = pair_stderr(pm[p], pm2[p], ch, n);
        double limit = 4.0 * sqrt(se_a * se_a + se_b * se_b);
        printf("  %-9s PATH %.5f  PHOTON %.5f  (limit ±%.5f)\n", names[p], a, b, limit);
        CHECK_MSG(fabs(b - a) <= limit, "%s: PHOTON %.5f vs PATH %.5f", names[p], b, a);
    }
    /* Combined is the sum of the light components, pixel by pixel. */
    int mismatches = 0;
    for (int k = 0; k < 2; k++) {
        float **img = k ? pm : path;
        for (uint32_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                double sum = 0.0;
                for (uint32_t p = PHOS_PASS_EMISSION; p <= PHOS_PASS_INDIRECT; p++)
                    sum += img[p][3 * i + c];
                mismatches += fabs(sum - img[0][4 * i + c]) > 1e-5 * fabs(sum) + 1e-7;
            }
    }
    CHECK_MSG(mismatches == 0, "%d pixels where Combined is not the sum of the components", mismatches);
    /* The debug passes see the maps: the photon map's estimate is close to
     * Combined (the scene is diffuse where the camera looks), and photons
     * are drawn. */
    double photon_map = test_mean_rgb(pm[PHOS_PASS_PHOTON_MAP], 3, n), combined = test_mean_rgb(pm[0], 4, n);
    CHECK_MSG(fabs(photon_map - combined) < 0.1 * combined, "photon map pass %.4f vs combined %.4f", photon_map, combined);
    CHECK(test_mean_rgb(pm[PHOS_PASS_PHOTONS], 3, n) > 0.0);
    CHECK(test_mean_rgb(pm[PHOS_PASS_CAUSTIC_MAP], 3, n) > 0.0);
    free_pass_sets(path, path2, pm, pm2);
    phos_scene_destroy(s);
}

/* PHOTON's split with the path-traced hemisphere as its indirect provider:
 * every term but the caustic map's is unbiased, so Direct, Specular and
 * Indirect must agree with PATH within the noise alone (4 standard errors,
 * no allowance), and no global map is traced for it. This checks the
 * walker's decomposition (indirect_diffuse.h) apart from the maps' bias. */
/* Inside a closed diffuse sphere (ρ = 0.6) with a glass ball and a point
 * light: most of the light is indirect, and every wall meets the light of
 * every other. */
static phos_scene *closed_room_scene(void)
{
    phos_scene *s = phos_scene_create();
    uint32_t room = test_add_sphere_mesh(s, 2.0f, 48, 24, 1);
    test_add_instance(s, room, test_add_diffuse(s, 0.6f, 0.6f, 0.6f), 0, 0, 0);
    uint32_t glass = test_add_glass(s, 1.5f);
    test_add_instance(s, test_add_sphere_mesh(s, 0.4f, 32, 16, 0), glass, 0.3f, 0.2f, -1.0f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[0] = 0.8f;
    l.position[1] = 0.8f;
    l.position[2] = 0.8f;
    l.color[0] = l.color[1] = l.color[2] = 1.5f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0, 0, 1.0f, 1.0f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static void path_traced_gather_vs_path(const char *name, phos_scene *s)
{
    const uint32_t w = 24, n = w * w;
    printf("  %s:\n", name);
    const uint32_t light_passes = (1u << (PHOS_PASS_INDIRECT + 1)) - 1u;
    float *path[PHOS_PASS_COUNT], *path2[PHOS_PASS_COUNT], *pt[PHOS_PASS_COUNT], *pt2[PHOS_PASS_COUNT];
    phos_progress progress;
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, light_passes, 1024, 3, path, w, NULL) != NULL);
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, light_passes, 1024, 4, path2, w, NULL) != NULL);
    CHECK(render_view(s, PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_PATH_TRACED, light_passes, 64, 3, pt, w,
                      &progress) != NULL);
    printf("    photons: %u global, %u caustic\n", progress.global_photons, progress.caustic_photons);
    CHECK_MSG(progress.global_photons == 0, "path-traced gather: %u global photons traced, none are read",
              progress.global_photons);
    CHECK(render_view(s, PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_PATH_TRACED, light_passes, 64, 4, pt2, w, NULL) !=
          NULL);
    static const char *names[] = {"combined", "emission", "direct", "specular", "caustics", "indirect"};
    for (uint32_t p = PHOS_PASS_DIRECT; p <= PHOS_PASS_INDIRECT; p++) {
        if (p == PHOS_PASS_CAUSTICS)
            continue; /* the caustic map's estimate: test_photon_vs_path */
        uint32_t ch = phos_pass_channels(p);
        double a = 0.5 * (test_mean_rgb(path[p], ch, n) + test_mean_rgb(path2[p], ch, n));
        double b = 0.5 * (test_mean_rgb(pt[p], ch, n) + test_mean_rgb(pt2[p], ch, n));
        double se_a = pair_stderr(path[p], path2[p], ch, n), se_b = pair_stderr(pt[p], pt2[p], ch, n);
        double limit = 4.0 * sqrt(se_a * se_a + se_b * se_b);
        printf("    %-9s PATH %.5f  PHOTON, path-traced gather %.5f  (limit ±%.5f)\n", names[p], a, b, limit);
        CHECK_MSG(fabs(b - a) <= limit, "%s: path-traced gather %.5f vs PATH %.5f", names[p], b, a);
    }
    free_pass_sets(path, path2, pt, pt2);
    phos_scene_destroy(s);
}

static void test_path_traced_gather_vs_path(void)
{
    path_traced_gather_vs_path("glass sphere on a floor", glass_sphere_scene());
    path_traced_gather_vs_path("closed room", closed_room_scene());
}

/* Blender's default scene in small: a diffuse ball on a floor, a strong
 * point lamp and a dim uniform world. Where the lamp does not reach, the
 * world lights the ball; a light sample seldom picks the world there, so
 * the gather rays that escape must count it (under MIS) or the face is
 * covered in speckles. PHOTON's noise per pixel at equal samples must stay
 * within a small factor of PATH's, and the means agree. Noise is measured
 * from two seeds of each: Var = mean (a − b)² / 2. */
static phos_scene *default_cube_scene(void)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 4.0f), test_add_diffuse(s, 0.8f, 0.8f, 0.8f), 0, 0, 0);
    test_add_instance(s, test_add_sphere_mesh(s, 0.8f, 32, 16, 0), test_add_diffuse(s, 0.8f, 0.8f, 0.8f), 0, 0,
                      0.8f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[0] = 4.0f;
    l.position[1] = 1.0f;
    l.position[2] = 5.0f;
    l.color[0] = l.color[1] = l.color[2] = 1000.0f / (4.0f * (float)M_PI); /* 1000 W */
    phos_scene_add_light(s, &l, NULL);
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = 0.05f;
    phos_scene_set_world(s, &w);
    /* From the side the lamp does not reach. */
    test_set_camera_pitched(s, -1.0f, -4.5f, 1.6f, 0.15f, 0.35f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static double pair_variance(const float *a, const float *b, uint32_t channels, uint32_t n)
{
    double v = 0.0;
    for (uint32_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double d = a[i * channels + c] - b[i * channels + c];
            v += d * d / 2.0;
        }
    return v / (3.0 * n);
}

static void test_world_light_noise(void)
{
    phos_scene *s = default_cube_scene();
    const uint32_t w = 32, n = w * w;
    const uint32_t combined = 1u << PHOS_PASS_COMBINED;
    float *path[PHOS_PASS_COUNT], *path2[PHOS_PASS_COUNT], *pm[PHOS_PASS_COUNT], *pm2[PHOS_PASS_COUNT];
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, combined, 16, 5, path, w, NULL) != NULL);
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, combined, 16, 6, path2, w, NULL) != NULL);
    /* 32 gather rays: the gather makes 3 × 10 = 30 strata of them, and the
     * MIS weights must count those 30 (the default, 4, makes 1 × 4). */
    for (int k = 0; k < 2; k++) {
        phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON, combined, 16, 5 + (uint32_t)k, w);
        rs.global_photons = rs.caustic_photons = 100000;
        rs.final_gather_rays = 32;
        CHECK(render_settings_passes(s, &rs, k ? pm2 : pm, NULL) != NULL);
    }
    double v_path = pair_variance(path[0], path2[0], 4, n), v_pm = pair_variance(pm[0], pm2[0], 4, n);
    double a = 0.5 * (test_mean_rgb(path[0], 4, n) + test_mean_rgb(path2[0], 4, n));
    double b = 0.5 * (test_mean_rgb(pm[0], 4, n) + test_mean_rgb(pm2[0], 4, n));
    double se = sqrt(pow(pair_stderr(path[0], path2[0], 4, n), 2) + pow(pair_stderr(pm[0], pm2[0], 4, n), 2));
    printf("  world-lit ball: mean PATH %.5f PHOTON %.5f (±%.5f); pixel variance PATH %.3g PHOTON %.3g (%.2fx)\n", a,
           b, 4.0 * se, v_path, v_pm, v_pm / v_path);
    CHECK_MSG(v_pm <= 2.0 * v_path, "PHOTON's pixel variance %.3g is %.1fx PATH's %.3g", v_pm, v_pm / v_path, v_path);
    CHECK_MSG(fabs(b - a) <= 4.0 * se, "world-lit ball: PHOTON mean %.5f vs PATH %.5f", b, a);
    free_pass_sets(path, path2, pm, pm2);
    phos_scene_destroy(s);
}

/* A diffuse floor lit only by a lamp's reflection in a rough metal ceiling
 * (a spot pointing up): the light reaches the floor along E D G L, which
 * final gathering reads where its rays land on the metal. Against a PATH
 * render of the same scene, PHOTON's Indirect must agree within 4 standard
 * errors of the two renders' noise at 25 k photons and at 400 k. The
 * error fell from 1.56 % to 0.62 % while gather hits read direct light
 * from the global map; since they take it from a light sample it is
 * 0.55 % and 0.58 %, at the noise floor (1.6 %) at both counts, so a fall
 * cannot be measured here (the sunlit room shows one). */
static phos_scene *metal_ceiling_scene_of(float roughness)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 3.0f), test_add_diffuse(s, 0.7f, 0.7f, 0.7f), 0, 0, 0);
    phos_closure_desc metal;
    phos_closure_desc_init(&metal);
    metal.type = PHOS_CLOSURE_REFLECTION;
    metal.weight[0] = metal.weight[1] = metal.weight[2] = 0.9f;
    metal.roughness = roughness;
    test_add_ceiling(s, 3.0f, 2.0f, test_add_closure_material(s, &metal));
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SPOT;
    l.position[2] = 1.0f;
    l.direction[2] = 1.0f;
    l.spot_angle = 1.6f;
    l.spot_blend = 0.0f;
    l.color[0] = l.color[1] = l.color[2] = 20.0f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera_pitched(s, 0.0f, -2.5f, 1.2f, 0.5f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static phos_scene *metal_ceiling_scene(void) { return metal_ceiling_scene_of(0.5f); }

static void test_glossy_gather_hits(void)
{
    phos_scene *s = metal_ceiling_scene();
    const uint32_t w = 24, indirect = 1u << PHOS_PASS_INDIRECT;
    double ref, se_ref;
    pass_mean_of_pair(s, test_settings(PHOS_INTEGRATOR_PATH, indirect, 512, 7, w), PHOS_PASS_INDIRECT, &ref, &se_ref);
    printf("  metal ceiling: PATH indirect %.5f (± %.5f)\n", ref, se_ref);
    CHECK(ref > 0.01);
    const uint32_t photons[] = {25000, 400000};
    double err[2], limit[2];
    for (int i = 0; i < 2; i++) {
        phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON, indirect, 16, 7, w);
        rs.global_photons = photons[i];
        rs.caustic_photons = photons[i] / 4;
        double m, se;
        pass_mean_of_pair(s, rs, PHOS_PASS_INDIRECT, &m, &se);
        err[i] = fabs(m / ref - 1.0);
        limit[i] = 4.0 * sqrt(se * se + se_ref * se_ref) / ref;
        printf("    PHOTON, %6u photons: indirect %.5f (± %.5f), error %.2f %% (noise limit %.2f %%)\n", photons[i], m,
               se, 100.0 * err[i], 100.0 * limit[i]);
    }
    for (int i = 0; i < 2; i++)
        CHECK_MSG(err[i] < limit[i], "PHOTON misses light a rough metal ceiling reflects onto the floor: error %.2f %% > %.2f %%",
                  100.0 * err[i], 100.0 * limit[i]);
    phos_scene_destroy(s);
}

/* Glossy caustics (docs/algorithms.md §12): the same floor under a
 * smoother ceiling (roughness 0.15), whose reflection of the spot is now a
 * caustic (L G D) that photons carry to the floor's caustic map, and gather
 * rays pass on through. Against a PATH render of 8192 samples, PHOTON's
 * mean within 4 standard errors of both renders' noise, and its per-pixel
 * RMS error falling as caustic photons grow (the reference's own noise,
 * measured from a second seed, is subtracted in quadrature). */
static void test_glossy_caustic_on_a_floor(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = metal_ceiling_scene_of(0.25f);
    const uint32_t w = 16, n = w * w, combined = 1u;
    float *ref[PHOS_PASS_COUNT], *ref2[PHOS_PASS_COUNT], *pm[PHOS_PASS_COUNT];
    phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PATH, combined, 16384, 7, w);
    CHECK(render_settings_passes(s, &rs, ref, NULL) != NULL);
    rs.seed++;
    CHECK(render_settings_passes(s, &rs, ref2, NULL) != NULL);
    double mean_ref = 0.5 * (test_mean_rgb(ref[0], 4, n) + test_mean_rgb(ref2[0], 4, n));
    double se_ref = pair_stderr(ref[0], ref2[0], 4, n);
    double ref_noise = test_rms_difference(ref[0], ref2[0], 4, n) / sqrt(2.0); /* one render's noise per pixel */
    printf("  glossy caustic: PATH %.5f (± %.5f), per-pixel noise %.4f\n", mean_ref, se_ref, ref_noise);
    const uint32_t photons[] = {5000, 40000, 320000};
    double rmse[3];
    for (int i = 0; i < 3; i++) {
        phos_render_settings pr = test_settings(PHOS_INTEGRATOR_PHOTON, combined, 16, 7, w);
        pr.global_photons = 20000;
        pr.caustic_photons = photons[i];
        /* Every sample reads the caustic map: the error's fall with photons
         * is the estimate's, not hidden under the noise of 4 reads. */
        pr.caustic_sample_share = 1.0f;
        double m, se;
        pass_mean_of_pair(s, pr, PHOS_PASS_COMBINED, &m, &se);
        CHECK(render_settings_passes(s, &pr, pm, NULL) != NULL);
        double d = test_rms_difference(pm[0], ref[0], 4, n);
        rmse[i] = sqrt(fmax(d * d - ref_noise * ref_noise, 0.0));
        double limit = 4.0 * sqrt(se * se + se_ref * se_ref);
        printf("    PHOTON, %6u caustic photons: %.5f (± %.5f), mean error %.2f %% (noise limit %.2f %%), "
               "per-pixel RMS error %.4f\n", photons[i], m, se, 100.0 * fabs(m / mean_ref - 1.0),
               100.0 * limit / mean_ref, rmse[i]);
        CHECK_MSG(fabs(m - mean_ref) < limit, "glossy caustic: PHOTON %.5f, PATH %.5f (limit %.5f)", m, mean_ref,
                  limit);
        for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++)
            free(pm[p]);
    }
    CHECK_MSG(rmse[2] < 0.7 * rmse[0], "glossy caustic: the per-pixel error did not fall with photons (%.4f → %.4f)",
              rmse[0], rmse[2]);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(ref[p]);
        free(ref2[p]);
    }
    phos_scene_destroy(s);
}

/* Glossy receivers (docs/algorithms.md §12; the course's "caustics on
 * glossy surfaces"): a rough metal floor (roughness 0.5) under a sharp
 * mirror ceiling 2 m up, lit only by the reflection of a spot 1 m up that
 * points at the ceiling. `mirrored`: the same floor with no ceiling and the
 * spot's mirror image instead (3 m up, pointing down), whose light on the
 * floor is direct light, which PATH samples well: the reference for the
 * caustic, by another method. */
static phos_scene *glossy_receiver_scene(int mirrored, float lamp_radius)
{
    phos_scene *s = phos_scene_create();
    phos_closure_desc metal;
    phos_closure_desc_init(&metal);
    metal.type = PHOS_CLOSURE_REFLECTION;
    metal.weight[0] = metal.weight[1] = metal.weight[2] = 0.8f;
    metal.roughness = 0.5f;
    test_add_instance(s, test_add_quad_mesh(s, 3.0f), test_add_closure_material(s, &metal), 0, 0, 0);
    if (!mirrored) {
        phos_closure_desc mirror;
        phos_closure_desc_init(&mirror);
        mirror.type = PHOS_CLOSURE_REFLECTION;
        mirror.weight[0] = mirror.weight[1] = mirror.weight[2] = 1.0f; /* the image is the lamp itself */
        mirror.roughness = 0.0f;
        test_add_ceiling(s, 3.0f, 2.0f, test_add_closure_material(s, &mirror));
    }
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SPOT;
    l.position[2] = mirrored ? 3.0f : 1.0f;
    l.direction[2] = mirrored ? -1.0f : 1.0f;
    l.spot_angle = 1.6f;
    l.spot_blend = 0.0f;
    /* A sphere (Blender 4's point shape): the older disk (Cycles 3's)
     * faces each ray's origin, which seen in a mirror is not the point it
     * lights; here PATH sees it 6 % dimmer through the mirror than it
     * samples it directly, whatever the caustics do. */
    l.radius = lamp_radius;
    l.point_shape = PHOS_POINT_SPHERE;
    l.color[0] = l.color[1] = l.color[2] = 20.0f;
    phos_scene_add_light(s, &l, NULL);
    /* Looking down at the floor, below the ceiling's reflection in it. */
    test_set_camera_pitched(s, 0.0f, -1.5f, 1.0f, 0.7f, 0.45f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

/* Under a point spot no path can find the caustic: the floor's Caustics
 * pass under PHOTON must match the mirrored scene's Direct pass under PATH
 * (mean within 4 standard errors of both renders' noise at every count),
 * with the per-pixel RMS error falling as caustic photons grow. Under a
 * sphere spot the path that goes on through the metal finds the lamp in
 * the mirror too: PHOTON's whole image must still match PATH's of the same
 * scene, so that light is not counted twice. */
static void test_glossy_receivers(void)
{
    const uint32_t w = 16, n = w * w;
    const uint32_t direct = 1u << PHOS_PASS_DIRECT, caustics = 1u << PHOS_PASS_CAUSTICS;
    phos_scene *virt = glossy_receiver_scene(1, 0.0f);
    float *ref[PHOS_PASS_COUNT], *ref2[PHOS_PASS_COUNT], *pm[PHOS_PASS_COUNT], *pm2[PHOS_PASS_COUNT];
    phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PATH, direct, 1024, 7, w);
    CHECK(render_settings_passes(virt, &rs, ref, NULL) != NULL);
    rs.seed++;
    CHECK(render_settings_passes(virt, &rs, ref2, NULL) != NULL);
    const uint32_t ch = phos_pass_channels(PHOS_PASS_DIRECT), cc = phos_pass_channels(PHOS_PASS_CAUSTICS);
    double mean_ref = 0.5 * (test_mean_rgb(ref[PHOS_PASS_DIRECT], ch, n) + test_mean_rgb(ref2[PHOS_PASS_DIRECT], ch, n));
    double se_ref = pair_stderr(ref[PHOS_PASS_DIRECT], ref2[PHOS_PASS_DIRECT], ch, n);
    printf("  glossy receiver: mirrored lamp's direct light (PATH) %.5f (± %.5f)\n", mean_ref, se_ref);
    CHECK(mean_ref > 0.01);
    phos_scene *s = glossy_receiver_scene(0, 0.0f);
    const uint32_t photons[] = {5000, 80000, 1280000};
    double rmse[3];
    for (int i = 0; i < 3; i++) {
        phos_render_settings pr = test_settings(PHOS_INTEGRATOR_PHOTON, caustics, 16, 7, w);
        pr.global_photons = 20000;
        pr.caustic_photons = photons[i];
        CHECK(render_settings_passes(s, &pr, pm, NULL) != NULL);
        pr.seed++;
        CHECK(render_settings_passes(s, &pr, pm2, NULL) != NULL);
        const float *a = pm[PHOS_PASS_CAUSTICS], *b = pm2[PHOS_PASS_CAUSTICS];
        double m = 0.5 * (test_mean_rgb(a, cc, n) + test_mean_rgb(b, cc, n)), se = pair_stderr(a, b, cc, n);
        double limit = 4.0 * sqrt(se * se + se_ref * se_ref);
        rmse[i] = test_rms_difference(a, ref[PHOS_PASS_DIRECT], cc, n);
        printf("    PHOTON, %6u caustic photons: caustics %.5f (± %.5f), mean error %.2f %% (noise limit %.2f %%), "
               "per-pixel RMS error %.4f\n", photons[i], m, se, 100.0 * fabs(m / mean_ref - 1.0),
               100.0 * limit / mean_ref, rmse[i]);
        CHECK_MSG(fabs(m - mean_ref) < limit, "caustic on a glossy floor: PHOTON %.5f, reference %.5f (limit %.5f)",
                  m, mean_ref, limit);
        for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
            free(pm[p]);
            free(pm2[p]);
        }
    }
    CHECK_MSG(rmse[2] < 0.7 * rmse[0], "caustic on a glossy floor: the per-pixel error did not fall (%.4f → %.4f)",
              rmse[0], rmse[2]);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(ref[p]);
        free(ref2[p]);
    }
    phos_scene_destroy(virt);
    phos_scene_destroy(s);

    /* A sphere spot: counted once. */
    s = glossy_receiver_scene(0, 0.25f);
    double path_mean, path_se, photon_mean, photon_se;
    pass_mean_of_pair(s, test_settings(PHOS_INTEGRATOR_PATH, 1u, 4096, 7, w), PHOS_PASS_COMBINED, &path_mean,
                      &path_se);
    phos_render_settings pr = test_settings(PHOS_INTEGRATOR_PHOTON, 1u, 64, 7, w);
    pr.global_photons = 20000;
    pr.caustic_photons = 320000;
    pass_mean_of_pair(s, pr, PHOS_PASS_COMBINED, &photon_mean, &photon_se);
    double limit = 4.0 * sqrt(path_se * path_se + photon_se * photon_se);
    printf("    sphere spot: PATH %.5f (± %.5f), PHOTON %.5f (± %.5f), error %.2f %% (noise limit %.2f %%)\n",
           path_mean, path_se, photon_mean, photon_se, 100.0 * (photon_mean / path_mean - 1.0),
           100.0 * limit / path_mean);
    CHECK_MSG(fabs(photon_mean - path_mean) < limit, "sphere spot over a glossy floor: PHOTON %.5f, PATH %.5f",
              photon_mean, path_mean);
    phos_scene_destroy(s);
}

/* PHOTON's passes against PATH's on one scene (those in `asserted`), each
 * within 4 standard errors of the two pairs of renders' noise (no
 * allowance), at `photons` global and caustic photons. */
static void photon_vs_path_passes(const char *name, phos_scene *s, uint32_t photons, uint32_t path_samples,
                                  uint32_t photon_samples, uint32_t w, uint32_t asserted)
{
    static const char *names[] = {"combined", "emission", "direct", "specular", "caustics", "indirect"};
    const uint32_t n = w * w, light_passes = (1u << (PHOS_PASS_INDIRECT + 1)) - 1u;
    float *path[PHOS_PASS_COUNT], *path2[PHOS_PASS_COUNT], *pm[PHOS_PASS_COUNT], *pm2[PHOS_PASS_COUNT];
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, light_passes, path_samples, 11, path, w, NULL) != NULL);
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, light_passes, path_samples, 12, path2, w, NULL) != NULL);
    for (int k = 0; k < 2; k++) {
        phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON, light_passes, photon_samples, 11 + (uint32_t)k, w);
        rs.global_photons = rs.caustic_photons = photons;
        CHECK(render_settings_passes(s, &rs, k ? pm2 : pm, NULL) != NULL);
    }
    printf("  %s:\n", name);
    for (uint32_t p = 0; p <= PHOS_PASS_INDIRECT; p++) {
        if (!(asserted & (1u << p)))
            continue;
        uint32_t ch = phos_pass_channels(p);
        double a = 0.5 * (test_mean_rgb(path[p], ch, n) + test_mean_rgb(path2[p], ch, n));
        double b = 0.5 * (test_mean_rgb(pm[p], ch, n) + test_mean_rgb(pm2[p], ch, n));
        double se = sqrt(pow(pair_stderr(path[p], path2[p], ch, n), 2) + pow(pair_stderr(pm[p], pm2[p], ch, n), 2));
        printf("    %-9s PATH %.5f PHOTON %.5f (error %+.2f %%, noise limit %.2f %%)\n", names[p], a, b,
               100.0 * (b / a - 1.0), 400.0 * se / a);
        CHECK(a > 0.0);
        CHECK_MSG(fabs(b - a) <= 4.0 * se, "%s, %s: PHOTON %.5f vs PATH %.5f (limit %.5f)", name, names[p], b, a,
                  4.0 * se);
    }
    free_pass_sets(path, path2, pm, pm2);
}

/* A square area light facing up at a panel 1 m above it that is half sharp
 * mirror, half diffuse (a mix shader): the mirror half throws the light's
 * image onto the floor around it, a caustic (L S D) that leaves the panel
 * by its delta lobe. Caustic paths used to stop at the panel's diffuse
 * half and the image was missing. */
static phos_scene *mirror_mix_scene(float mirror, float diffuse)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 3.0f), test_add_diffuse(s, 0.7f, 0.7f, 0.7f), 0, 0, 0);
    phos_closure_desc c[2];
    phos_closure_desc_init(&c[0]);
    phos_closure_desc_init(&c[1]);
    c[0].type = PHOS_CLOSURE_REFLECTION;
    c[0].roughness = 0.0f;
    c[1].type = PHOS_CLOSURE_DIFFUSE;
    for (int k = 0; k < 3; k++) {
        c[0].weight[k] = mirror;
        c[1].weight[k] = diffuse;
    }
    test_add_ceiling(s, 1.0f, 1.5f, test_add_mix_material(s, c, 2));
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[0] = 0.8f;
    l.position[2] = 0.5f;
    l.direction[2] = 1.0f;
    l.axis_u[0] = 0.3f;
    l.axis_v[1] = 0.3f;
    l.color[0] = l.color[1] = l.color[2] = 40.0f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera_pitched(s, 0.0f, -2.2f, 0.6f, 1.1f, 0.4f); /* the floor under the panel */
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

/* A mirror mixed with a diffuse coat: the caustic pass stores its photons
 * past the panel (before, none: it ran to its cap of emitted paths), and
 * PHOTON's Caustics and Indirect match PATH's. */
static void test_mirror_mix_caustic(void)
{
    phos_scene *s = mirror_mix_scene(0.45f, 0.45f);
    phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON, 1u << PHOS_PASS_CAUSTICS, 1, 1, 8);
    rs.global_photons = rs.caustic_photons = 20000;
    float *passes[PHOS_PASS_COUNT];
    phos_progress progress;
    CHECK(render_settings_passes(s, &rs, passes, &progress) != NULL);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++)
        free(passes[p]);
    printf("  mirror mix: %u caustic photons stored\n", progress.caustic_photons);
    CHECK_MSG(progress.caustic_photons == 20000, "mirror mix: %u caustic photons stored of 20000",
              progress.caustic_photons);
    photon_vs_path_passes("mirror mix", s, 200000, 2048, 64, 16,
                          (1u << PHOS_PASS_CAUSTICS) | (1u << PHOS_PASS_INDIRECT));
    phos_scene_destroy(s);
}

/* A clear coat's reflection: the panel a 4 % mirror over a 90 % diffuse
 * base. Most aimed caustic paths leave the panel by its diffuse part and
 * store nothing (about one path in 60 stores a photon), so the caustic pass
 * stops at 10 paths a photon of what it was to trace (photon_trace.c,
 * CAUSTIC_PATHS_PER_PHOTON), the map reported short, instead of tracing
 * on until it holds its target (some 3 M paths here; a fainter caustic
 * ran to the 50 M-path emission cap). Its photons
 * still carry the caustic's whole power: that of the global pass's
 * caustic photons, emitted everywhere and capped by nothing (within 4
 * standard errors). */
static void test_faint_caustic_path_budget(void)
{
    phos_scene *s = mirror_mix_scene(0.04f, 0.9f);
    const uint32_t target = 50000;
    double sum[2], sum2[2];
    uint32_t n[2];
    uint64_t emitted = 0;
    uint32_t own = 0, short_maps = 0;
    for (int k = 0; k < 2; k++) {
        photon_trace_settings ps = trace_settings(k ? 0 : 2000000, k ? target : 0, 0);
        photon_maps m;
        photon_maps_init(&m);
        atomic_int cancel = 0;
        CHECK(photon_maps_trace(s, &ps, &m, &cancel, NULL) == PHOS_OK);
        sum[k] = caustic_power(k ? &m.caustic : &m.global, k == 0, &sum2[k], &n[k]);
        if (k) {
            emitted = m.caustic_emitted;
            own = m.caustic.count - m.caustic_reused;
            short_maps = m.short_maps;
        }
        photon_maps_free(&m);
    }
    printf("  faint caustic: %u photons from %llu caustic paths (target %u), %.5f W; global pass's caustic "
           "photons %.5f W (%u)\n", own, (unsigned long long)emitted, target, sum[1], sum[0], n[0]);
    CHECK_MSG(emitted <= 10ull * target && own < target,
              "the caustic pass traced %llu paths for %u photons of %u", (unsigned long long)emitted, own, target);
    CHECK(short_maps == (1u << PHOS_MAP_CAUSTIC));
    CHECK(n[0] > 1000 && own > 1000);
    double se = sqrt(sum2[0] + sum2[1]);
    CHECK_MSG(fabs(sum[1] - sum[0]) < 4.0 * se, "faint caustic: the caustic map carries %.5f W, the global "
              "pass's caustic photons %.5f W (± %.5f)", sum[1], sum[0], 4.0 * se);
    phos_scene_destroy(s);
}

/* A point lamp inside a frosted glass shade (a very rough glass sphere of
 * radius 0.3 m, Cycles 3.x's MACRO glass, 1 m above a diffuse floor). No
 * shadow ray reaches the lamp through the shade, so all the floor's light
 * is Indirect: diffuse, then the shade's rough refraction. The camera sees
 * only the floor under the shade. */
static phos_scene *frosted_shade_scene(void)
{
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 3.0f), test_add_diffuse(s, 0.7f, 0.7f, 0.7f), 0, 0, 0);
    phos_closure_desc glass;
    phos_closure_desc_init(&glass);
    glass.type = PHOS_CLOSURE_GLASS;
    glass.weight[0] = glass.weight[1] = glass.weight[2] = 1.0f;
    glass.roughness = 0.8f;
    glass.ior = 1.5f;
    test_add_instance(s, test_add_sphere_mesh(s, 0.3f, 48, 24, 0), test_add_closure_material(s, &glass), 0, 0, 1.0f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_POINT;
    l.position[2] = 1.0f;
    l.color[0] = l.color[1] = l.color[2] = 5.0f; /* W/sr */
    phos_scene_add_light(s, &l, NULL);
    test_set_camera_pitched(s, 0.0f, -2.5f, 1.2f, 0.8f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

/* The floor under the frosted shade, PHOTON's final gather and fast
 * estimate against PATH, within 4 standard errors of the noise. Both read
 * photons that left the lamp through the shade's rough refraction, so
 * both need the adjoint BSDF there (bsdf_adjoint_weight): this glass
 * picks its lobes by Fresnel at the side the light arrives from, so it is
 * not symmetric, and photons weighted by the BSDF as camera paths see it
 * came out 14 % (final gather) and 62 % (fast estimate) dark. With the
 * adjoint but sampled as camera paths sample it, the fast estimate was
 * still 15 % dark: from inside, beyond the critical angle, that sampler
 * never refracts, yet light from outside can refract into those
 * directions through tilted microfacets (bsdf_set_adjoint). */
static void test_frosted_shade(void)
{
    phos_scene *s = frosted_shade_scene();
    const uint32_t w = 16, indirect = 1u << PHOS_PASS_INDIRECT;
    double ref, se_ref;
    pass_mean_of_pair(s, test_settings(PHOS_INTEGRATOR_PATH, indirect, 2048, 11, w), PHOS_PASS_INDIRECT, &ref, &se_ref);
    printf("  frosted shade: PATH indirect %.5f (± %.5f)\n", ref, se_ref);
    CHECK(ref > 0.1);
    static const char *views[] = {"final gather", "fast estimate"};
    for (uint32_t v = 0; v < 2; v++) {
        phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON, indirect, 64, 11, w);
        rs.photon_view = v;
        rs.global_photons = rs.caustic_photons = 100000;
        double m, se;
        pass_mean_of_pair(s, rs, PHOS_PASS_INDIRECT, &m, &se);
        double limit = 4.0 * sqrt(se * se + se_ref * se_ref);
        printf("    PHOTON, %s: %.5f (± %.5f), error %+.2f %% (noise limit %.2f %%)\n", views[v], m, se,
               100.0 * (m / ref - 1.0), 100.0 * limit / ref);
        CHECK_MSG(fabs(m - ref) <= limit, "frosted shade, %s: PHOTON %.5f vs PATH %.5f (limit %.5f)", views[v], m,
                  ref, limit);
    }
    phos_scene_destroy(s);
}

/* A pool: a diffuse floor under 0.5 m of water (a closed box of sharp
 * glass, IOR 1.33), an area light above, the camera looking straight down
 * through the surface. Light reaches the floor only through the water's
 * surface, a caustic (L S D S E; the Specular pass, as the camera sees the
 * floor through a refraction). Camera paths carry
 * radiance without 1/η² across a refraction (as Cycles), so photons must
 * carry T/η² into the water (bsdf_photon_weight); with T alone the
 * caustics came out η² = 1.77 × too bright. */
static phos_scene *pool_scene(void)
{
    const float a = 1.5f, b = -0.1f, t = 0.5f; /* the water box: |x|, |y| < a, b < z < t */
    float box[6][4][3] = {
        {{-a, -a, t}, {a, -a, t}, {a, a, t}, {-a, a, t}},   /* surface, +z */
        {{-a, -a, b}, {-a, a, b}, {a, a, b}, {a, -a, b}},   /* bottom, −z */
        {{-a, -a, b}, {a, -a, b}, {a, -a, t}, {-a, -a, t}}, /* y = −a, −y */
        {{-a, a, b}, {-a, a, t}, {a, a, t}, {a, a, b}},     /* y = +a, +y */
        {{-a, -a, b}, {-a, -a, t}, {-a, a, t}, {-a, a, b}}, /* x = −a, −x */
        {{a, -a, b}, {a, a, b}, {a, a, t}, {a, -a, t}},     /* x = +a, +x */
    };
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])box, 6), test_add_glass(s, 1.33f), 0, 0, 0);
    test_add_instance(s, test_add_quad_mesh(s, 1.4f), test_add_diffuse(s, 0.7f, 0.7f, 0.7f), 0, 0, 0);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = 2.0f;
    l.direction[2] = -1.0f;
    l.axis_u[0] = 0.8f;
    l.axis_v[1] = 0.8f;
    l.color[0] = l.color[1] = l.color[2] = 5.0f; /* W/(m²·sr) */
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0.0f, 0.0f, 2.5f, 0.25f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static void test_pool_caustic(void)
{
    phos_scene *s = pool_scene();
    photon_vs_path_passes("pool", s, 100000, 1024, 16, 16, (1u << PHOS_PASS_COMBINED) | (1u << PHOS_PASS_SPECULAR));
    phos_scene_destroy(s);
}

/* A closed diffuse room (4 × 4 × 2.5 m, ρ = 0.6) lit only by the sun
 * through a small window (0.8 × 0.8 m) in its +y wall, with a diffuse ball
 * on the floor: almost all the light the camera sees is indirect, and it
 * sees every kind of edge and corner. The camera stands inside, looking
 * at the window wall. */
#define ROOM_HALF 2.0f
#define ROOM_HEIGHT 2.5f
#define ROOM_CAMERA_PITCH 1.42f
#define ROOM_TAN_HALF 0.8f
static const float room_camera[3] = {0.0f, -1.8f, 1.3f};
static const float room_ball[4] = {-1.0f, 0.6f, 0.5f, 0.5f}; /* centre, radius */

/* The rectangle x ∈ [x0, x1], z ∈ [z0, z1] of the wall y = ROOM_HALF,
 * facing −y (into the room). */
static void window_wall_quad(float q[4][3], float x0, float x1, float z0, float z1)
{
    const float y = ROOM_HALF;
    float c[4][3] = {{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}};
    memcpy(q, c, sizeof(c));
}

/* The room lit by the sun, or (sky) by a uniform world of radiance
 * 30/π W/(m²·sr) instead, whose light enters through the same window. */
static phos_scene *room_scene(int sky)
{
    const float a = ROOM_HALF, h = ROOM_HEIGHT;
    const float wx = 0.4f, wz0 = 1.0f, wz1 = 1.8f; /* the window */
    float quads[9][4][3] = {
        {{-a, -a, 0}, {a, -a, 0}, {a, a, 0}, {-a, a, 0}},  /* floor, +z */
        {{-a, -a, h}, {-a, a, h}, {a, a, h}, {a, -a, h}},  /* ceiling, −z */
        {{-a, -a, 0}, {-a, a, 0}, {-a, a, h}, {-a, -a, h}}, /* x = −a, +x */
        {{a, -a, 0}, {a, -a, h}, {a, a, h}, {a, a, 0}},    /* x = +a, −x */
        {{-a, -a, 0}, {-a, -a, h}, {a, -a, h}, {a, -a, 0}}, /* y = −a, +y */
    };
    window_wall_quad(quads[5], -a, a, 0.0f, wz0);
    window_wall_quad(quads[6], -a, a, wz1, h);
    window_wall_quad(quads[7], -a, -wx, wz0, wz1);
    window_wall_quad(quads[8], wx, a, wz0, wz1);
    phos_scene *s = phos_scene_create();
    uint32_t walls = test_add_diffuse(s, 0.6f, 0.6f, 0.6f);
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])quads, 9), walls, 0, 0, 0);
    test_add_instance(s, test_add_sphere_mesh(s, room_ball[3], 48, 24, 0), walls, room_ball[0], room_ball[1],
                      room_ball[2]);
    if (sky) {
        phos_world_desc w;
        phos_world_desc_init(&w);
        w.color[0] = w.color[1] = w.color[2] = 30.0f / (float)M_PI;
        phos_scene_set_world(s, &w);
    } else {
        phos_light_desc l;
        phos_light_desc_init(&l);
        l.type = PHOS_LIGHT_SUN;
        float d[3] = {0.35f, -1.0f, -0.9f}, len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; k++)
            l.direction[k] = d[k] / len;
        l.color[0] = l.color[1] = l.color[2] = 30.0f; /* W/m² */
        phos_scene_add_light(s, &l, NULL);
    }
    test_set_camera_pitched(s, room_camera[0], room_camera[1], room_camera[2], ROOM_CAMERA_PITCH, ROOM_TAN_HALF);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

/* Distance (m) from where pixel (i, j)'s central ray meets the room's walls
 * to the nearest edge between two of them, or −1 where the ray meets the
 * ball or leaves through the window. Rows count from the bottom. */
static double room_pixel_edge_distance(uint32_t i, uint32_t j, uint32_t w)
{
    double x = ROOM_TAN_HALF * (2.0 * (i + 0.5) / w - 1.0), y = ROOM_TAN_HALF * (2.0 * (j + 0.5) / w - 1.0);
    double cp = cos(ROOM_CAMERA_PITCH), sp = sin(ROOM_CAMERA_PITCH);
    double d[3] = {x, cp * y + sp, sp * y - cp}; /* R·(x, y, −1) */
    double o[3] = {room_camera[0], room_camera[1], room_camera[2]};
    /* The ball. */
    double oc[3] = {o[0] - room_ball[0], o[1] - room_ball[1], o[2] - room_ball[2]};
    double A = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], B = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double C = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - room_ball[3] * room_ball[3];
    if (B * B - A * C > 0.0 && -B - sqrt(B * B - A * C) > 0.0)
        return -1.0;
    double lo[3] = {-ROOM_HALF, -ROOM_HALF, 0.0}, hi[3] = {ROOM_HALF, ROOM_HALF, ROOM_HEIGHT};
    double t = INFINITY;
    for (int k = 0; k < 3; k++)
        if (d[k] != 0.0)
            t = fmin(t, ((d[k] > 0.0 ? hi[k] : lo[k]) - o[k]) / d[k]);
    double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    if (fabs(p[1] - ROOM_HALF) < 1e-6 && fabs(p[0]) < 0.4 && p[2] > 1.0 && p[2] < 1.8)
        return -1.0; /* through the window */
    double e = INFINITY;
    for (int k = 0; k < 3; k++) {
        double dk = fmin(p[k] - lo[k], hi[k] - p[k]);
        if (dk > 1e-6) /* not the face the point lies on */
            e = fmin(e, dk);
    }
    return e;
}

/* Mean of a 3-channel pass over the pixels where mask[i] is set, and the
 * standard error of the mean of two renders' (pair_stderr over the mask). */
static double masked_mean(const float *p, const unsigned char *mask, uint32_t n)
{
    double m = 0.0;
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++)
        if (mask[i]) {
            m += p[3 * i] + p[3 * i + 1] + p[3 * i + 2];
            count++;
        }
    return m / (3.0 * count);
}

static double masked_pair_stderr(const float *a, const float *b, const unsigned char *mask, uint32_t n)
{
    double m = 0.0, v = 0.0;
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++)
        if (mask[i]) {
            m += (a[3 * i] + a[3 * i + 1] + a[3 * i + 2] - b[3 * i] - b[3 * i + 1] - b[3 * i + 2]) / 3.0;
            count++;
        }
    m /= count;
    for (uint32_t i = 0; i < n; i++)
        if (mask[i]) {
            double d = (a[3 * i] + a[3 * i + 1] + a[3 * i + 2] - b[3 * i] - b[3 * i + 1] - b[3 * i + 2]) / 3.0;
            v += (d - m) * (d - m);
        }
    return sqrt(v / (count - 1) / (4.0 * count));
}

/* Power of the global map's photons on the room's inner faces (normal
 * toward the room's centre), indirect (0) and direct (1), with the
 * standard error of each sum (photons as independent draws). */
static void room_inside_power(const photon_map *m, double sum[2], double se[2], uint32_t n[2])
{
    double sum2[2] = {0.0, 0.0};
    sum[0] = sum[1] = 0.0;
    n[0] = n[1] = 0;
    vec3 centre = v3(0.0f, 0.0f, 0.5f * ROOM_HEIGHT);
    for (uint32_t k = 0; k < m->count; k++) {
        const photon *ph = &m->photons[k];
        vec3 p = photon_position(ph);
        if (v3_dot(photon_normal(ph), v3_sub(centre, p)) <= 0.0f || fabsf(p.x) > ROOM_HALF + 1e-3f ||
            fabsf(p.y) > ROOM_HALF + 1e-3f || p.z < -1e-3f || p.z > ROOM_HEIGHT + 1e-3f)
            continue;
        int d = photon_is_direct(ph);
        double w = v3_average(photon_power(ph));
        sum[d] += w;
        sum2[d] += w * w;
        n[d]++;
    }
    se[0] = sqrt(sum2[0]);
    se[1] = sqrt(sum2[1]);
}

/* The sun's global photons are aimed at what the camera reads (pilot
 * photons weight the cells of its emission plane); photons that miss stay
 * possible, with a floor weight, so the map is unchanged in expectation.
 * In the sunlit room the power stored on the inner faces must equal that
 * of an unaimed map (the same scene without a camera, where nothing is
 * aimed) within 4 standard errors, direct and indirect, while 8 times as
 * large a share of the stored photons lands inside. Measured: indirect
 * 19.759 W aimed at 1.6 M photons against 19.743 W unaimed at 6.4 M
 * (± 0.024 and ± 0.044 W); 71 % of the aimed photons lie inside, 5.4 % of
 * the unaimed ones. */
static void global_photons_aimed_at_the_room(int sky, uint32_t aimed_photons, uint32_t unaimed_photons,
                                             double min_gain)
{
    const char *name = sky ? "sky-lit room" : "sunlit room";
    double sum[2][2], se[2][2];
    uint32_t n[2][2], stored[2];
    for (int aimed = 0; aimed < 2; aimed++) {
        phos_scene *s = room_scene(sky);
        if (!aimed)
            ((scene *)s)->has_camera = 0;
        photon_trace_settings ps = trace_settings(aimed ? aimed_photons : unaimed_photons, 0, 0);
        photon_maps m;
        photon_maps_init(&m);
        atomic_int cancel = 0;
        CHECK(photon_maps_trace(s, &ps, &m, &cancel, NULL) == PHOS_OK);
        room_inside_power(&m.global, sum[aimed], se[aimed], n[aimed]);
        stored[aimed] = m.global.count;
        printf("  %s, %s: inside indirect %.4f W (± %.4f, %u photons), direct %.4f W (± %.4f, %u), of %u "
               "stored from %llu paths\n",
               name, aimed ? "aimed" : "unaimed", sum[aimed][0], se[aimed][0], n[aimed][0], sum[aimed][1],
               se[aimed][1], n[aimed][1], m.global.count, (unsigned long long)m.global_emitted);
        photon_maps_free(&m);
        phos_scene_destroy(s);
    }
    for (int d = 0; d < 2; d++) {
        double tol = 4.0 * sqrt(se[0][d] * se[0][d] + se[1][d] * se[1][d]);
        CHECK_MSG(fabs(sum[1][d] - sum[0][d]) < tol, "%s: aimed global photons carry %.4f W inside, unaimed %.4f W (± %.4f)",
                  name, sum[1][d], sum[0][d], tol);
    }
    /* No wasted work: the indirect power inside is known better per stored
     * photon (variance × photons), not only from more of them. */
    double cost_aimed = se[1][0] * se[1][0] * stored[1], cost = se[0][0] * se[0][0] * stored[0];
    CHECK_MSG(cost_aimed * min_gain < cost, "%s: variance × stored photons %.0f aimed, %.0f unaimed", name, cost_aimed,
              cost);
    double share_aimed = (double)(n[1][0] + n[1][1]) / stored[1], share = (double)(n[0][0] + n[0][1]) / stored[0];
    CHECK_MSG(share_aimed > min_gain * share, "%s: aimed, %.1f %% of the photons land inside; unaimed %.1f %%", name,
              100.0 * share_aimed, 100.0 * share);
}

static void test_global_photons_aimed_at_the_room(void)
{
    global_photons_aimed_at_the_room(0, 1600000, 6400000, 8.0);
    global_photons_aimed_at_the_room(1, 400000, 3200000, 8.0);
}

/* Indirect light in the sunlit room, PHOTON (final gathering) against
 * PATH: over the whole image and over the strip of pixels that see a wall
 * within 0.3 m of an edge or corner, where the density estimates' bias
 * lives. Measured on this scene before issue 8's fixes: +11 % over the
 * image and +25 % in the strip at 400 k photons, growing with photons
 * (light from the sunlit outside walls counted inside, radiance photons
 * 30 % dark). Since the sun's global photons are aimed at what the camera
 * reads (16 times as many land inside), the error over the image falls
 * from +2.8 % at 1 k photons and +1.2 % at 3 k to the noise by 10 k
 * (+0.3 %); the test asserts that it falls from 2 k to 100 k (or is
 * within the noise at 2 k already), and that at 100 k and 1.6 M photons
 * both errors are within 4 standard errors of the two renders' noise.
 * Measured at 1.6 M over three seed pairs: +0.5 % to +0.8 % (limit about
 * 1.05 %), in the strip 0.0 % to +0.4 % (2.9 %). With the discs clipped at
 * walls (radiance_estimate.h), seeds 9 and 10: -0.09 %, +0.45 %, +0.98 % at
 * 2 k, 100 k and 1.6 M (strip +0.49 %, +0.44 %, +0.39 %), against -1.23 %,
 * -0.51 %, +0.70 % (strip -1.16 %, -0.91 %, -0.07 %) with whole discs. */
static void test_sunlit_room(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = room_scene(0);
    const uint32_t w = 32, n = w * w;
    unsigned char strip[32 * 32], all[32 * 32];
    uint32_t strip_pixels = 0;
    for (uint32_t j = 0; j < w; j++)
        for (uint32_t i = 0; i < w; i++) {
            double e = room_pixel_edge_distance(i, j, w);
            all[j * w + i] = 1;
            strip[j * w + i] = e >= 0.0 && e < 0.3;
            strip_pixels += strip[j * w + i];
        }
    CHECK(strip_pixels > 100);
    const uint32_t light_passes = (1u << (PHOS_PASS_INDIRECT + 1)) - 1u;
    float *path[PHOS_PASS_COUNT], *path2[PHOS_PASS_COUNT];
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, light_passes, 4096, 9, path, w, NULL) != NULL);
    CHECK(render_view(s, PHOS_INTEGRATOR_PATH, 0, light_passes, 4096, 10, path2, w, NULL) != NULL);
    const float *ref_a = path[PHOS_PASS_INDIRECT], *ref_b = path2[PHOS_PASS_INDIRECT];
    double ref = 0.5 * (masked_mean(ref_a, all, n) + masked_mean(ref_b, all, n));
    double ref_strip = 0.5 * (masked_mean(ref_a, strip, n) + masked_mean(ref_b, strip, n));
    double se_ref = masked_pair_stderr(ref_a, ref_b, all, n), se_ref_strip = masked_pair_stderr(ref_a, ref_b, strip, n);
    printf("  sunlit room: PATH indirect %.5f (± %.5f), in the strip (%u px) %.5f (± %.5f)\n", ref, se_ref,
           strip_pixels, ref_strip, se_ref_strip);
    const uint32_t photons[] = {2000, 100000, 1600000};
    double err[3], err_strip[3], limit[3], limit_strip[3];
    for (int i = 0; i < 3; i++) {
        float *pm[PHOS_PASS_COUNT], *pm2[PHOS_PASS_COUNT];
        CHECK(render_photons(s, photons[i], light_passes, 64, 9, pm, w) != NULL);
        CHECK(render_photons(s, photons[i], light_passes, 64, 10, pm2, w) != NULL);
        const float *a = pm[PHOS_PASS_INDIRECT], *b = pm2[PHOS_PASS_INDIRECT];
        double m = 0.5 * (masked_mean(a, all, n) + masked_mean(b, all, n));
        double ms = 0.5 * (masked_mean(a, strip, n) + masked_mean(b, strip, n));
        double se = masked_pair_stderr(a, b, all, n), se_strip = masked_pair_stderr(a, b, strip, n);
        err[i] = m / ref - 1.0;
        err_strip[i] = ms / ref_strip - 1.0;
        limit[i] = 4.0 * sqrt(se * se + se_ref * se_ref) / ref;
        limit_strip[i] = 4.0 * sqrt(se_strip * se_strip + se_ref_strip * se_ref_strip) / ref_strip;
        printf("    PHOTON %7u photons: indirect error %+.2f %% (noise limit %.2f %%), in the strip %+.2f %% (%.2f %%)\n",
               photons[i], 100.0 * err[i], 100.0 * limit[i], 100.0 * err_strip[i], 100.0 * limit_strip[i]);
        for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
            free(pm[p]);
            free(pm2[p]);
        }
    }
    /* Falling, unless already within the noise at 2 k (since the discs
     * are clipped at walls: -0.09 %, where the whole disc read -1.23 %). */
    CHECK_MSG(fabs(err[1]) < fmax(fabs(err[0]), limit[0]),
              "sunlit room: the error does not fall as photons grow: %+.4f then %+.4f", err[0], err[1]);
    for (int i = 1; i < 3; i++) {
        CHECK_MSG(fabs(err[i]) < limit[i], "sunlit room, %u photons: indirect %+.2f %% off PATH (noise limit %.2f %%)",
                  photons[i], 100.0 * err[i], 100.0 * limit[i]);
        CHECK_MSG(fabs(err_strip[i]) < limit_strip[i],
                  "sunlit room, %u photons, edges and corners: indirect %+.2f %% off PATH (%.2f %%)", photons[i],
                  100.0 * err_strip[i], 100.0 * limit_strip[i]);
    }
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(path[p]);
        free(path2[p]);
    }
    phos_scene_destroy(s);
}

/* A closed white room (the cube [−1, 1]³ m, ρ = 0.73 inside) lit by a
 * 0.5 m square area light 5 cm under the ceiling, facing down, seen from
 * 10 cm under the light straight down: the image is the floor, its border
 * the floor's edge along the walls (docs/benchmarks.md, "Discs cut by
 * walls"). */
static phos_scene *white_cube_room_scene(void)
{
    phos_scene *s = phos_scene_create();
    const float faces[6][4][3] = {
        {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}}, /* floor, normal +z */
        {{-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}},     /* ceiling, −z */
        {{-1, -1, -1}, {-1, 1, -1}, {-1, 1, 1}, {-1, -1, 1}}, /* +x */
        {{1, -1, -1}, {1, -1, 1}, {1, 1, 1}, {1, 1, -1}},     /* −x */
        {{-1, -1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}}, /* +y */
        {{-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}},     /* −y */
    };
    test_add_instance(s, test_add_quads(s, faces, 6), test_add_diffuse(s, 0.73f, 0.73f, 0.73f), 0.0f, 0.0f, 0.0f);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.color[0] = l.color[1] = l.color[2] = 10.0f; /* W/(m²·sr) */
    l.position[2] = 0.95f;
    l.direction[2] = -1.0f;
    l.axis_u[0] = l.axis_v[1] = 0.5f;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_OK);
    test_set_camera(s, 0.0f, 0.0f, 0.9f, 1.0f / 1.9f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

enum { ROOM_STRIP, ROOM_CORNERS, ROOM_MIDDLE, ROOM_REGIONS };
static const char *const room_region_names[ROOM_REGIONS] = {"edge strip", "corners", "middle"};

/* Masks of w² pixels: the outer ring of pixels without the corners (the
 * floor within 6 cm of one wall), each corner's 2 × 2 pixels, and the
 * middle half of the image. */
static void white_cube_room_regions(unsigned char masks[ROOM_REGIONS][32 * 32], uint32_t w)
{
    for (uint32_t j = 0; j < w; j++)
        for (uint32_t i = 0; i < w; i++) {
            int edge_i = i < 2 || i >= w - 2, edge_j = j < 2 || j >= w - 2;
            int corner = edge_i && edge_j;
            masks[ROOM_CORNERS][j * w + i] = (unsigned char)corner;
            masks[ROOM_STRIP][j * w + i] = !corner && (i == 0 || j == 0 || i == w - 1 || j == w - 1);
            masks[ROOM_MIDDLE][j * w + i] = i >= w / 4 && i < 3 * w / 4 && j >= w / 4 && j < 3 * w / 4;
        }
}

/* PHOTON's fast view (the global map's estimate read at the camera, no
 * final gathering to hide its bias) in the white cube room, against PATH, on
 * the Indirect pass: over the edge strip and the corners, where the
 * density estimate's disc is cut by walls, and the middle. Each photon
 * count renders several photon seeds; the noise of a region's mean is
 * taken from their spread (a photon map's error is blotchy, correlated
 * across pixels, so one image's pixels cannot give it), PATH's from its
 * two seeds' pixels. Asserted: at 1.28 M photons every region is within
 * 4 standard errors of PATH, and the regions' largest error has fallen
 * from 20 k photons (or was within its noise there already).
 * Measured (eight seeds, ratio to PATH, strip / corners / middle): 20 k
 * 1.000 / 0.949 / 1.006, 1.28 M 0.998 / 0.989 / 1.003 (noise limits at
 * 1.28 M 0.013 / 0.060 / 0.008). With whole discs (no clipping at walls)
 * the strip read 0.741 and 0.933 and the corners 0.692 and 0.921:
 * falling, but at 1.28 M still 18 and 4.5 standard errors off, and the
 * test fails. */
static void test_fast_view_in_a_white_cube_room(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = white_cube_room_scene();
    const uint32_t w = 32, n = w * w, seeds = 8;
    unsigned char masks[ROOM_REGIONS][32 * 32];
    white_cube_room_regions(masks, w);
    phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PATH, 1u << PHOS_PASS_INDIRECT, 4096, 100, w);
    rs.max_bounces = 64;
    float *path[PHOS_PASS_COUNT], *path2[PHOS_PASS_COUNT];
    CHECK(render_settings_passes(s, &rs, path, NULL) != NULL);
    rs.seed++;
    CHECK(render_settings_passes(s, &rs, path2, NULL) != NULL);
    double ref[ROOM_REGIONS], se_ref[ROOM_REGIONS];
    for (int g = 0; g < ROOM_REGIONS; g++) {
        ref[g] = 0.5 * (masked_mean(path[PHOS_PASS_INDIRECT], masks[g], n) +
                        masked_mean(path2[PHOS_PASS_INDIRECT], masks[g], n));
        se_ref[g] = masked_pair_stderr(path[PHOS_PASS_INDIRECT], path2[PHOS_PASS_INDIRECT], masks[g], n) / ref[g];
    }
    const uint32_t photons[2] = {20000, 1280000};
    double worst[2] = {0.0, 0.0}, worst_limit[2] = {0.0, 0.0};
    for (int c = 0; c < 2; c++) {
        double sum[ROOM_REGIONS] = {0}, sum2[ROOM_REGIONS] = {0};
        for (uint32_t seed = 1; seed <= seeds; seed++) {
            phos_render_settings ps = test_settings(PHOS_INTEGRATOR_PHOTON, 1u << PHOS_PASS_INDIRECT, 4, seed, w);
            ps.max_bounces = 64;
            ps.photon_view = PHOS_PHOTON_VIEW_FAST;
            ps.global_photons = photons[c];
            ps.caustic_photons = 1000;
            float *pm[PHOS_PASS_COUNT];
            CHECK(render_settings_passes(s, &ps, pm, NULL) != NULL);
            for (int g = 0; g < ROOM_REGIONS; g++) {
                double ratio = masked_mean(pm[PHOS_PASS_INDIRECT], masks[g], n) / ref[g];
                sum[g] += ratio;
                sum2[g] += ratio * ratio;
            }
            for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++)
                free(pm[p]);
        }
        printf("    fast view, %7u photons:", photons[c]);
        for (int g = 0; g < ROOM_REGIONS; g++) {
            double mean = sum[g] / seeds, var = (sum2[g] - seeds * mean * mean) / (seeds - 1);
            double limit = 4.0 * sqrt(fmax(var, 0.0) / seeds + se_ref[g] * se_ref[g]);
            printf(" %s %.4f (noise limit %.4f)", room_region_names[g], mean, limit);
            if (fabs(mean - 1.0) > worst[c]) {
                worst[c] = fabs(mean - 1.0);
                worst_limit[c] = limit;
            }
            if (c == 1)
                CHECK_MSG(fabs(mean - 1.0) < limit,
                          "white cube room, fast view at %u photons, %s: %.4f of PATH (noise limit %.4f)",
                          photons[c], room_region_names[g], mean, limit);
        }
        printf("\n");
    }
    CHECK_MSG(worst[1] < fmax(worst[0], worst_limit[0]),
              "white cube room, fast view: the largest region error does not fall with photons (%.4f, then %.4f)",
              worst[0], worst[1]);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(path[p]);
        free(path2[p]);
    }
    phos_scene_destroy(s);
}

/* The sharp edge of a mirror's caustic, where a fixed number of nearest
 * photons blurs and progressive photon mapping converges (issue 25,
 * docs/algorithms.md §4.6). A point lamp 0.5 m over a white floor under a
 * horizontal mirror (z = 1, facing down, x from −0.5 to 0.2): the mirror's
 * image of the lamp, 1.5 m up, lights the floor through the mirror only
 * for x < 0.6, so the caustic steps to zero there. Its exact value per
 * pixel follows from the Direct pass (next-event estimation, unbiased) of
 * the same render: E_caustic / E_direct = (z_v / d_v³) / (z_l / d_l³),
 * with d_l, d_v the distances to the lamp and its image, times the
 * mirror's reflectance (a closure's default weight, 0.8). The camera looks
 * straight down at x in [0.2, 1.0], the edge in the middle. The relative
 * error of the Caustics pass over the image: progressive, it falls from 4
 * to 64 samples (measured: 0.244, then 0.116; ideally by 16^(α/2) = 2).
 * Not asserted, because it is not so here: the fixed estimate, its 80
 * nearest among as many photons as the progressive render traced in all
 * (1.3 M), measured 0.068 at 64 samples (docs/benchmarks.md). */
#define MIRROR_WEIGHT 0.8 /* phos_closure_desc_init's weight */

static double mirror_edge_error(phos_scene *s, uint32_t progressive, uint32_t samples, uint32_t caustic_photons)
{
    const uint32_t w = 32;
    phos_render_settings rs = test_settings(PHOS_INTEGRATOR_PHOTON,
                                            (1u << PHOS_PASS_COMBINED) | (1u << PHOS_PASS_DIRECT) |
                                                (1u << PHOS_PASS_CAUSTICS),
                                            samples, 3, w);
    rs.global_photons = 1000;
    rs.caustic_photons = caustic_photons;
    rs.progressive_caustics = progressive;
    rs.progressive_caustic_photons = 20000;
    float *passes[PHOS_PASS_COUNT];
    CHECK(render_settings_passes(s, &rs, passes, NULL) != NULL);
    double err2 = 0.0, ref2 = 0.0;
    for (uint32_t j = 0; j < w; j++)
        for (uint32_t i = 0; i < w; i++) {
            /* Pixel centre on the floor: x = 0.6 + 0.4·u, y = 0.4·v (rows
             * from the top, the camera's up being +y). */
            double u = (i + 0.5) / w * 2.0 - 1.0, v = 1.0 - (j + 0.5) / w * 2.0;
            double x = 0.6 + 0.4 * u, y = 0.4 * v;
            double dl = sqrt(x * x + y * y + 0.25), dv = sqrt(x * x + y * y + 2.25);
            /* Through the mirror: the ray from the image (0, 0, 1.5) to
             * (x, y, 0) crosses z = 1 at a third of the way. */
            double mx = x / 3.0, my = y / 3.0;
            int lit = mx > -0.5 && mx < 0.2 && my > -0.5 && my < 0.5;
            size_t k = 3 * ((size_t)j * w + i);
            double direct = passes[PHOS_PASS_DIRECT][k];
            double want = lit ? MIRROR_WEIGHT * direct * (1.5 / (dv * dv * dv)) / (0.5 / (dl * dl * dl)) : 0.0;
            double got = passes[PHOS_PASS_CAUSTICS][k];
            err2 += (got - want) * (got - want);
            ref2 += want * want;
        }
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++)
        free(passes[p]);
    return sqrt(err2 / ref2);
}

static void test_progressive_caustic_edge(void)
{
    phos_scene *s = phos_scene_create();
    float floor_quad[1][4][3] = {{{-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0}}};
    float mirror_quad[1][4][3] = {{{-0.5f, -0.5f, 1}, {-0.5f, 0.5f, 1}, {0.2f, 0.5f, 1}, {0.2f, -0.5f, 1}}};
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])floor_quad, 1), test_add_diffuse(s, 0.5f, 0.5f, 0.5f),
                      0, 0, 0);
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])mirror_quad, 1), test_add_mirror(s), 0, 0, 0);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_POINT;
    l.position[2] = 0.5f;
    l.color[0] = l.color[1] = l.color[2] = 5.0f; /* W/sr */
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0.6f, 0.0f, 0.9f, 0.4f / 0.9f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    double p4 = mirror_edge_error(s, 1, 4, 20000), p64 = mirror_edge_error(s, 1, 64, 20000);
    printf("  mirror caustic's edge: relative error, progressive %.4f at 4 samples, %.4f at 64\n", p4, p64);
    CHECK_MSG(p64 < 0.7 * p4, "progressive caustics: the error does not fall with samples (%.4f, then %.4f)", p4, p64);
    phos_scene_destroy(s);
}

int main(void)
{
    test_progressive_caustic_edge();
    test_point_light_irradiance();
    test_radiance_photons_unbiased();
    test_emitted_flux_per_light_type();
    test_caustic_pass_needs_a_delta_lobe();
    test_caustic_photons_aimed_at_a_bead();
    test_caustic_projection_unbiased(0);
    test_caustic_projection_unbiased(1);
    test_caustic_aimed_at_view();
    test_radiance_lookup_in_a_corner();
    test_power_in_closed_sphere();
    test_maps_deterministic();
    test_photon_vs_path();
    test_path_traced_gather_vs_path();
    test_world_light_noise();
    test_glossy_gather_hits();
    test_glossy_caustic_on_a_floor();
    test_glossy_receivers();
    test_mirror_mix_caustic();
    test_faint_caustic_path_budget();
    test_frosted_shade();
    test_pool_caustic();
    test_global_photons_aimed_at_the_room();
    test_sunlit_room();
    test_fast_view_in_a_white_cube_room();
    return test_summary("test_photon_map");
}
