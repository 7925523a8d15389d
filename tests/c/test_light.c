/*
 * test_light.c — light sampling against its own pdf.
 *
 * For each light type, directions sampled from a shading point are binned
 * in (cos θ, φ) around the direction to the light; the expected count per
 * bin integrates the pdf that the intersection routines report for rays
 * hitting the light (the pdf MIS uses), so a chi-square test checks both
 * that sampling follows its pdf and that the two agree. Each sample is also
 * traced back: the ray must hit the light with the same pdf and radiance.
 * A uniform world is sampled apart from the picked lights (light_pick.c),
 * so its own sample is checked on its own.
 */
#include <stdio.h>
#include <string.h>

#include "chi2.h"
#include "scene/embree.h"
#include "lights/environment.h"
#include "lights/light.h"
#include "lights/light_kind.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "test_util.h"

#define NZ 12
#define NPHI 16
#define SAMPLES 200000

typedef struct light_query {
    const scene *s;
    light_context c;            /* the receiver: a point in space, or on a surface */
    int world_sample;           /* 1: the uniform world's own sample; 0: the picked lights' */
} light_query;

/* pdf of the scene's light sampling toward direction w, as MIS sees it. */
static double pdf_toward(const light_query *q, vec3 w)
{
    const scene *s = q->s;
    ray_hit h;
    float tmax = INFINITY;
    int hit = embree_intersect(s->bvh, q->c.p, w, 1e-4f, INFINITY, 0, &h);
    if (q->world_sample)
        return hit ? 0.0 : light_escape_pdf(s, &q->c, (uint32_t)s->lights.world, w);
    if (hit)
        tmax = h.t;
    /* Lamps do not block rays: a ray past one goes on to what lies behind
     * it, as the walk does (camera_path.c). */
    light_hit lh;
    double lamp = lights_intersect(s, &q->c, q->c.p, w, 0.0f, tmax, 0, &lh) ? lh.pdf : 0.0;
    if (hit) {
        const instance *inst = &s->instances[h.instance];
        if (!inst->emitter_of_triangle)
            return lamp;
        vec3 v[3];
        scene_triangle_vertices(s, inst, h.prim, v);
        vec3 ng = v3_normalize(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])));
        return lamp + light_pdf_triangle(s, inst->emitter_of_triangle[h.prim], &q->c, v3_madd(q->c.p, w, h.t), ng);
    }
    /* Escaped: the distant lights' pdfs, recovered from the MIS weights is
     * awkward, so compute them directly from the table. */
    double pdf = lamp;
    for (uint32_t i = 0; i < s->lights.count; i++) {
        const light *l = &s->lights.lights[i];
        double pick = light_pick_pdf(&s->lights, &q->c, i);
        if ((int32_t)i == s->lights.world && light_world_apart(&s->lights, &q->c))
            continue; /* not among the picked lights */
        if (light_is_distant(l))
            pdf += pick * light_escape_pdf(s, &q->c, i, w);
    }
    return pdf;
}

static double bin_integral(const light_query *q, const frame *f, double z0, double z1, double p0, double p1)
{
    enum { SUB = 160 }; /* fine enough for the sharp rims of small lights */
    double sum = 0.0;
    for (int i = 0; i < SUB; i++) {
        for (int j = 0; j < SUB; j++) {
            double z = z0 + (z1 - z0) * (i + 0.5) / SUB;
            double phi = p0 + (p1 - p0) * (j + 0.5) / SUB;
            double r = sqrt(fmax(0.0, 1.0 - z * z));
            vec3 w = frame_to_world(f, v3((float)(r * cos(phi)), (float)(r * sin(phi)), (float)z));
            sum += pdf_toward(q, w);
        }
    }
    return sum * (z1 - z0) * (p1 - p0) / (SUB * SUB);
}

static light_context point_in_space(vec3 p)
{
    light_context c = {p, v3s(0.0f), v3s(0.0f), 0, 1};
    return c;
}

/* Samples lights from receiver c, binned about axis down to cos θ = z_min
 * (samples below it are errors). `overlapping`: the lights overlap in
 * direction (a lamp in front of the world), so a sample's traced-back pdf
 * is the sum of theirs, not its own; the chi-square test still holds. */
static void check_receiver(const char *name, phos_scene *s, light_context c, vec3 axis, double z_min,
                           int overlapping, int world_sample)
{
    CHECK_MSG(phos_scene_commit(s) == PHOS_OK, "%s: %s", name, phos_scene_error(s));
    light_query q = {s, c, world_sample};
    frame f = frame_from_normal(v3_normalize(axis));
    static double observed[NZ * NPHI], expected[NZ * NPHI];
    memset(observed, 0, sizeof(observed));
    int outside = 0, mismatched = 0, produced = 0;
    for (uint32_t i = 0; i < SAMPLES; i++) {
        sampler smp = sampler_independent(1234, 0, i);
        light_sample ls;
        if (world_sample ? !light_sample_world(s, &c, sampler_2d(&smp, 1), &ls)
                         : !light_sample_pick(s, &c, sampler_1d(&smp, 0), sampler_2d(&smp, 1), &ls))
            continue;
        produced++;
        vec3 lw = frame_to_local(&f, ls.wi);
        if (lw.z < z_min) {
            outside++;
            continue;
        }
        int zi = (int)((lw.z - z_min) / (1.0 - z_min) * NZ);
        double phi = atan2(lw.y, lw.x);
        if (phi < 0.0)
            phi += 2.0 * M_PI;
        int pi = (int)(phi / (2.0 * M_PI) * NPHI);
        zi = zi < 0 ? 0 : (zi >= NZ ? NZ - 1 : zi);
        pi = pi < 0 ? 0 : (pi >= NPHI ? NPHI - 1 : pi);
        observed[zi * NPHI + pi] += 1.0;
        double back = pdf_toward(&q, ls.wi);
        if (!overlapping && fabs(back - ls.pdf) > 2e-3 * ls.pdf)
            mismatched++;
    }
    for (int zi = 0; zi < NZ; zi++)
        for (int pi = 0; pi < NPHI; pi++) {
            double z0 = z_min + (1.0 - z_min) * zi / NZ, z1 = z_min + (1.0 - z_min) * (zi + 1) / NZ;
            double p0 = 2.0 * M_PI * pi / NPHI, p1 = 2.0 * M_PI * (pi + 1) / NPHI;
            expected[zi * NPHI + pi] = SAMPLES * bin_integral(&q, &f, z0, z1, p0, p1);
        }
    if (getenv("PHOS_TEST_VERBOSE")) {
        double so = 0.0, se = 0.0;
        for (int i = 0; i < NZ * NPHI; i++) {
            so += observed[i];
            se += expected[i];
            if (fabs(observed[i] - expected[i]) > 4.0 * sqrt(expected[i] + 1.0))
                printf("    bin z%d phi%d: observed %.0f expected %.1f\n", i / NPHI, i % NPHI, observed[i], expected[i]);
        }
        printf("    total observed %.0f expected %.1f\n", so, se);
    }
    int dof;
    double pvalue = chi2_test(observed, expected, NZ * NPHI, &dof);
    printf("  %-24s samples %d, chi-square p = %.4f (dof %d), pdf mismatches %d\n", name, produced, pvalue, dof,
           mismatched);
    CHECK_MSG(pvalue > 0.01 / 8.0, "%s: sampling does not follow its pdf (p = %g)", name, pvalue);
    CHECK_MSG(outside == 0, "%s: %d samples outside the light's cone", name, outside);
    CHECK_MSG(mismatched <= produced / 1000, "%s: %d samples whose traced-back pdf differs", name, mismatched);
    CHECK_MSG(produced > SAMPLES / 2, "%s: only %d of %d samples produced", name, produced, SAMPLES);
    phos_scene_destroy(s);
}

static void check_light(const char *name, phos_scene *s, vec3 p, vec3 axis, double z_min)
{
    check_receiver(name, s, point_in_space(p), axis, z_min, 0, 0);
}

static phos_scene *scene_with_light(const phos_light_desc *l)
{
    phos_scene *s = phos_scene_create();
    if (l)
        phos_scene_add_light(s, l, NULL);
    test_set_camera(s, 0, 0, 5, 0.5f);
    return s;
}

/* Every kind of light at once, seen from a point on a floor facing +z:
 * an area light above, a point lamp below the floor, a spot aimed away
 * from the point, a sun below the horizon, and the world. Picking follows
 * each light's bound at the point, so the lamp below, the spot and the sun
 * get probability 0 (the world, sampled apart, the whole sphere), and the
 * sampled directions follow the pdf that MIS reads for rays that hit the
 * lights. On a surface that transmits, the lamp below is picked again. */
static phos_scene *mixed_lights_scene(void)
{
    phos_scene *s = scene_with_light(NULL);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = 1.0f;
    l.axis_u[0] = 1.0f;
    l.axis_v[1] = 0.6f;
    l.color[0] = l.color[1] = l.color[2] = 2.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_POINT;
    l.position[2] = -0.5f;
    l.radius = 0.1f;
    l.color[0] = l.color[1] = l.color[2] = 50.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SPOT;
    l.position[0] = 2.0f;
    l.position[2] = 1.0f;
    l.direction[0] = 1.0f;
    l.direction[2] = 0.0f;
    l.spot_angle = 1.0f;
    l.spot_blend = 0.3f;
    l.color[0] = l.color[1] = l.color[2] = 50.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SUN;
    l.direction[0] = 1.0f;
    l.direction[2] = 0.2f; /* shining slightly upward: from 11° below the floor's horizon */
    l.sun_angle = 0.2f;
    l.color[0] = l.color[1] = l.color[2] = 3.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = 0.3f;
    phos_scene_set_world(s, &w);
    return s;
}

/* The same lights under a sky that varies with direction (a 32 × 16 map,
 * brighter toward the zenith and toward +x), sampled from its map: unlike
 * a uniform world it is picked with the other lights. */
static phos_scene *mixed_lights_under_sky(void)
{
    static float px[32 * 16 * 4];
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 32; x++) {
            float *q = px + 4 * (y * 32 + x);
            float g = 0.05f + 0.4f * (float)y / 15.0f + 0.3f * (float)(x > 12 && x < 20);
            q[0] = g, q[1] = g * 0.9f, q[2] = g * 1.2f, q[3] = 1.0f;
        }
    phos_scene *s = mixed_lights_scene();
    test_set_environment(s, px, 32, 16, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
    return s;
}

/* A uniform world seen from a floor point through two portals above it
 * (a square window and a round skylight, facing down into the room):
 * half the world's samples go through them, and the draws follow the
 * mixture's pdf. */
static phos_scene *world_with_portals(void)
{
    phos_scene *s = scene_with_light(NULL);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_PORTAL;
    l.position[0] = 0.8f, l.position[2] = 1.5f;
    l.direction[0] = 0.0f, l.direction[2] = -1.0f;
    l.axis_u[0] = 0.8f, l.axis_v[1] = 0.5f;
    phos_scene_add_light(s, &l, NULL);
    l.position[0] = -1.0f, l.position[1] = 0.5f, l.position[2] = 2.0f;
    l.area_shape = PHOS_AREA_ELLIPSE;
    l.axis_u[0] = 0.6f, l.axis_v[1] = 0.6f;
    phos_scene_add_light(s, &l, NULL);
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = 0.5f;
    phos_scene_set_world(s, &w);
    return s;
}

static void check_lights_picked_for_a_surface(void)
{
    vec3 p = v3(0.3f, -0.2f, 0.0f), up = v3(0.0f, 0.0f, 1.0f);
    light_context floor = {p, up, up, 0, 0};
    check_receiver("mixed lights, on a floor", mixed_lights_scene(), floor, up, -1.0, 1, 0);

    /* Shading normal tilted 30° toward the sun: it may reach the point
     * through the shading normal, so it is picked again. */
    phos_scene *s = mixed_lights_scene();
    CHECK(phos_scene_commit(s) == PHOS_OK);
    light_context tilted = {p, up, v3(-0.5f, 0.0f, 0.8660254f), 0, 0};
    light_context glass = {p, up, up, 1, 0};
    check_receiver("mixed lights, tilted", mixed_lights_scene(), tilted, up, -1.0, 1, 0);
    check_receiver("mixed lights, on glass", mixed_lights_scene(), glass, up, -1.0, 1, 0);
    const light_table *t = &s->lights;
    uint32_t below = 1, spot = 2, sun = 3;
    CHECK_MSG(light_pick_pdf(t, &floor, below) == 0.0f && light_pick_pdf(t, &floor, spot) == 0.0f &&
                  light_pick_pdf(t, &floor, sun) == 0.0f,
              "a light that cannot reach the floor is still picked");
    CHECK_MSG(light_pick_pdf(t, &glass, below) > 0.0f && light_pick_pdf(t, &glass, sun) > 0.0f,
              "a transmitting surface must pick the lights behind it");
    CHECK_MSG(light_pick_pdf(t, &tilted, sun) > 0.0f && light_pick_pdf(t, &tilted, below) == 0.0f,
              "the shading normal decides which lights can reach the point");
    /* A uniform world is sampled apart (light_pick.c): pick probability 1,
     * and no share of the others' pick. */
    uint32_t world = t->count - 1;
    CHECK_MSG(t->lights[world].kind == LIGHT_WORLD && light_world_apart(t, &floor) &&
                  light_pick_pdf(t, &floor, world) == 1.0f,
              "a uniform world is sampled apart, with pick probability 1");
    double sum_floor = 0.0, sum_tilted = 0.0;
    for (uint32_t i = 0; i < world; i++) {
        sum_floor += light_pick_pdf(t, &floor, i);
        sum_tilted += light_pick_pdf(t, &tilted, i);
    }
    CHECK_MSG(fabs(sum_floor - 1.0) < 1e-5 && fabs(sum_tilted - 1.0) < 1e-5, "pick probabilities sum to %g and %g",
              sum_floor, sum_tilted);
    phos_scene_destroy(s);

    check_receiver("world's own sample, floor", mixed_lights_scene(), floor, up, -1.0, 0, 1);
    check_receiver("world's own sample, glass", mixed_lights_scene(), glass, up, -1.0, 0, 1);
    check_receiver("world through portals, floor", world_with_portals(), floor, up, -1.0, 0, 1);
    check_receiver("mixed lights under a sky, on a floor", mixed_lights_under_sky(), floor, up, -1.0, 1, 0);
    check_receiver("mixed lights under a sky, on glass", mixed_lights_under_sky(), glass, up, -1.0, 1, 0);
    s = mixed_lights_under_sky();
    CHECK(phos_scene_commit(s) == PHOS_OK);
    world = s->lights.count - 1;
    CHECK_MSG(s->lights.lights[world].kind == LIGHT_ENVIRONMENT && light_pick_pdf(&s->lights, &floor, world) > 0.0f,
              "a world that varies is picked with the other lights");
    phos_scene_destroy(s);
}

/* A spot with a radius, at points across the edge of its cone: the pick's
 * bound on its light (light_pick.c) is never below the irradiance it
 * gives. Each point of the lamp sends its own ray, and rays within β of
 * the centre's direction can carry more of the beam than the centre's (in
 * the blend, and just outside the cone); a spot picked for less than it
 * gives makes fireflies (Blender's lamp_kinds scene showed one pixel at
 * 6.4× its value, one sample in 128 weighing 300× the pixel, before the
 * bound took the widest ray). The bound is read off the pick against a
 * point lamp whose bound is known: I·cos θ/d². The irradiance is the
 * spot's own light samples' mean on a stratified grid. */
static void check_spot_bound_at_its_edge(void)
{
    phos_scene *s = scene_with_light(NULL);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SPOT;
    l.position[2] = 2.0f;
    l.direction[2] = -1.0f;
    l.spot_angle = 0.8f; /* half angle 0.4 rad: the edge at x = 0.85 m, the blend from 0.69 m */
    l.spot_blend = 0.3f;
    l.radius = 0.1f;
    l.color[0] = l.color[1] = l.color[2] = 100.0f;
    phos_scene_add_light(s, &l, NULL);
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_POINT;
    l.position[0] = 3.0f;
    l.position[2] = 1.0f;
    l.color[0] = l.color[1] = l.color[2] = 10.0f;
    phos_scene_add_light(s, &l, NULL);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    const light_table *t = &s->lights;
    const light *spot = &t->lights[0];
    vec3 up = v3(0.0f, 0.0f, 1.0f);
    int checked = 0, violations = 0;
    double worst = INFINITY;
    for (int k = 0; k <= 24; k++) {
        vec3 p = v3(0.6f + 0.02f * (float)k, 0.0f, 0.0f);
        light_context c = {p, up, up, 0, 0};
        vec3 to_point = v3_sub(v3(3.0f, 0.0f, 1.0f), p); /* the point lamp */
        double d2 = v3_length2(to_point), cos_point = to_point.z / sqrt(d2);
        double w_point = 10.0 * cos_point / d2;
        double p_spot = light_pick_pdf(t, &c, 0), p_point = light_pick_pdf(t, &c, 1);
        double bound = p_point > 0.0 ? p_spot / p_point * w_point : 0.0;
        const int n = 128;
        double e = 0.0;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                light_sample ls;
                float2 u = {((float)i + 0.5f) / (float)n, ((float)j + 0.5f) / (float)n};
                if (light_ops(spot)->sample(s, spot, &c, u, &ls) && ls.wi.z > 0.0f)
                    e += v3_average(ls.radiance) * ls.wi.z / ls.pdf;
            }
        e /= (double)(n * n);
        if (e <= 0.0)
            continue;
        checked++;
        worst = fmin(worst, bound / e);
        violations += bound < 0.99 * e;
    }
    printf("  spot across its edge: %d points lit, bound / irradiance at least %.3f\n", checked, worst);
    CHECK_MSG(checked >= 10, "only %d points across the edge are lit", checked);
    CHECK_MSG(violations == 0, "the pick's bound on a spot is below its irradiance at %d points (worst ratio %.3f)",
              violations, worst);
    phos_scene_destroy(s);
}

int main(void)
{
    vec3 p = v3(0.3f, -0.2f, 0.0f);
    phos_light_desc l;

    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = 1.0f;
    l.axis_u[0] = 1.5f;
    l.axis_v[1] = 0.7f;
    check_light("area rectangle", scene_with_light(&l), p, v3_sub(v3(0, 0, 1), p), 0.5);
    l.area_shape = PHOS_AREA_ELLIPSE;
    check_light("area ellipse", scene_with_light(&l), p, v3_sub(v3(0, 0, 1), p), 0.5);

    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_POINT;
    l.position[2] = 1.0f;
    l.radius = 0.3f;
    check_light("point, disk", scene_with_light(&l), p, v3_sub(v3(0, 0, 1), p), 0.85);
    l.point_shape = PHOS_POINT_SPHERE;
    check_light("point, sphere", scene_with_light(&l), p, v3_sub(v3(0, 0, 1), p), 0.85);

    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SUN;
    l.direction[0] = 0.3f;
    l.sun_angle = 0.4f;
    check_light("sun, angle 0.4", scene_with_light(&l), p, v3(-0.3f, 0.0f, 1.0f), 0.95);

    /* Two emissive quads of different strength: picking by power too. */
    phos_scene *s = scene_with_light(NULL);
    uint32_t quad = test_add_quad_mesh(s, 0.5f);
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_EMISSION;
    c.weight[0] = c.weight[1] = c.weight[2] = 3.0f;
    phos_material_desc m;
    phos_material_desc_init(&m);
    m.closure_count = 1;
    m.closures = &c;
    uint32_t bright, dim;
    phos_scene_add_material(s, &m, &bright);
    c.weight[0] = c.weight[1] = c.weight[2] = 1.0f;
    phos_scene_add_material(s, &m, &dim);
    test_add_instance(s, quad, bright, 0.0f, 0.0f, 1.0f);
    test_add_instance(s, quad, dim, 1.2f, 0.0f, 1.5f);
    check_light("emissive triangles", s, p, v3_sub(v3(0.6f, 0, 1.2f), p), 0.2);

    s = scene_with_light(NULL);
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = 1.0f;
    phos_scene_set_world(s, &w);
    check_receiver("world", s, point_in_space(p), v3(0, 0, 1), -1.0, 0, 1);

    check_lights_picked_for_a_surface();
    check_spot_bound_at_its_edge();

    return test_summary("test_light");
}
