/*
 * projection_map.c — caustic emission aimed at specular objects
 * (projection_map.h).
 *
 * Local lights (points, spots, area lights, the emissive triangles of an
 * instance) aim at cones: one per instance that has a delta-scattering
 * material, about the direction from the light's bounding sphere to the
 * instance's, of half angle asin((r + r_light)/d), so that every direction
 * from any point of the light to any point of the instance lies in it. A
 * photon picks a cone in proportion to its solid angle Ω_k and a uniform
 * direction in it; its density is the mixture's, Σ_j p_j [ω ∈ cone j]/Ω_j,
 * since cones may overlap. Suns aim at cells of a PLANE_CELLS² grid over a
 * square of the plane their photons start on: a cell is marked when it can
 * meet the shadow of an instance's sphere, widened by the drift of a
 * photon tilted by the sun's half angle. The world is a sun per bin of
 * directions: each of its WORLD_BINS² bins of equal solid angle has a
 * plane of its own, and a photon from it takes a uniform direction in the
 * bin (distant_plane below).
 *
 * For the global map every visible instance is a target, as its
 * axis-aligned bounding box rather than its sphere: a lamp over a floor
 * lies inside the floor's sphere but outside its box, and the box's cone
 * (box_cone) is about a hemisphere, half the directions a point lamp
 * sends photons into.
 */
#include "photons/projection_map.h"

#include <stdlib.h>
#include <string.h>

#include "lights/environment.h"
#include "lights/light.h"
#include "sampling/warp.h"
#include "shading/material.h"

#define PLANE_CELLS 64       /* per side of a sun's plane */
#define WORLD_BINS ENVIRONMENT_BINS /* per side of the world's grid of directions: 64 bins of π/16 sr */
#define WORLD_PLANE_CELLS 32 /* per side of the plane of each of the world's bins */
#define MAX_CONES 64        /* per light; more instances share one sphere */
#define MARGIN 1e-3f        /* rad or m: rounding never unmarks a cell that can see a target */

typedef struct sphere {
    vec3 c;
    float r;
} sphere;

/* ------------------------------------------------------------- targets */

static int instance_scatters_caustic(const scene *s, const instance *inst, float max_roughness)
{
    if (inst->material_count == 0)
        return material_can_scatter_caustic(&scene_default_material, max_roughness);
    for (uint32_t k = 0; k < inst->material_count; k++)
        if (material_can_scatter_caustic(scene_instance_material(s, inst, k), max_roughness))
            return 1;
    return 0;
}

typedef struct box {
    vec3 lo, hi;
    uint32_t instance;   /* the instance bounded (UINT32_MAX: several) */
    int planar;          /* all its triangles in one plane: its own emission never lands on it */
} box;

/* World-space bounds of an instance's vertices. */
static box instance_box(const scene *s, const instance *inst)
{
    const mesh *m = &s->meshes[inst->mesh_id];
    box b = {v3s(INFINITY), v3s(-INFINITY), UINT32_MAX, 0};
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        vec3 p = xform_point(inst->transform, v3_load(m->positions + 3 * (size_t)v));
        b.lo = v3_min(b.lo, p);
        b.hi = v3_max(b.hi, p);
    }
    return b;
}

static sphere instance_sphere(const scene *s, const instance *inst)
{
    box b = instance_box(s, inst);
    sphere sp = {v3_scale(v3_add(b.lo, b.hi), 0.5f), 0.5f * v3_length(v3_sub(b.hi, b.lo))};
    return sp;
}

static int instance_receives(const scene *s, const instance *inst)
{
    return s->meshes[inst->mesh_id].triangle_count > 0 && !inst->hidden;
}

/* Whether every vertex of the instance lies in the plane of its first
 * triangle (within a millionth of its size): an emissive plane's photons
 * leave that plane and can never come back to it. */
static int instance_is_planar(const scene *s, const instance *inst, const box *b)
{
    const mesh *m = &s->meshes[inst->mesh_id];
    vec3 v[3];
    scene_triangle_vertices(s, inst, 0, v);
    vec3 n = v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0]));
    float len = v3_length(n), size = v3_length(v3_sub(b->hi, b->lo));
    if (!(len > 0.0f))
        return 0;
    n = v3_scale(n, 1.0f / len);
    for (uint32_t k = 0; k < m->vertex_count; k++) {
        vec3 p = xform_point(inst->transform, v3_load(m->positions + 3 * (size_t)k));
        if (!(fabsf(v3_dot(v3_sub(p, v[0]), n)) <= 1e-6f * size + 1e-7f))
            return 0;
    }
    return 1;
}

/* The bounding boxes of the instances a photon can land on; one box
 * around all of them past MAX_CONES. Returns the count (−1: out of
 * memory). */
static int collect_boxes(const scene *s, box **out)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++)
        n += instance_receives(s, &s->instances[i]);
    *out = NULL;
    if (n == 0)
        return 0;
    box *t = malloc(sizeof(box) * (n > MAX_CONES ? 1 : n));
    if (!t)
        return -1;
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!instance_receives(s, &s->instances[i]))
            continue;
        box b = instance_box(s, &s->instances[i]);
        b.instance = i;
        b.planar = n <= MAX_CONES && instance_is_planar(s, &s->instances[i], &b);
        if (n <= MAX_CONES) {
            t[k++] = b;
        } else if (k == 0) {
            t[k++] = b;
            t[0].instance = UINT32_MAX;
        } else {
            t[0].lo = v3_min(t[0].lo, b.lo);
            t[0].hi = v3_max(t[0].hi, b.hi);
        }
    }
    *out = t;
    return (int)k;
}

/* The bounding spheres of the instances that can scatter delta; one
 * sphere around all of them past MAX_CONES (each photon tests every cone
 * for its density). Returns the count (−1: out of memory). */
static int collect_targets(const scene *s, float max_roughness, sphere **out)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++)
        n += s->meshes[s->instances[i].mesh_id].triangle_count > 0 && !s->instances[i].hidden &&
             instance_scatters_caustic(s, &s->instances[i], max_roughness);
    *out = NULL;
    if (n == 0)
        return 0;
    sphere *t = malloc(sizeof(sphere) * n);
    if (!t)
        return -1;
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const instance *inst = &s->instances[i];
        if (s->meshes[inst->mesh_id].triangle_count > 0 && !inst->hidden &&
            instance_scatters_caustic(s, inst, max_roughness))
            t[k++] = instance_sphere(s, inst);
    }
    if (n > MAX_CONES) {
        vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
        for (uint32_t i = 0; i < n; i++) {
            lo = v3_min(lo, v3_sub(t[i].c, v3s(t[i].r)));
            hi = v3_max(hi, v3_add(t[i].c, v3s(t[i].r)));
        }
        t[0].c = v3_scale(v3_add(lo, hi), 0.5f);
        t[0].r = 0.5f * v3_length(v3_sub(hi, lo));
        n = 1;
    }
    *out = t;
    return (int)n;
}

/* ---------------------------------------------------------------- cones */

static float angle_between(vec3 a, vec3 b) { return acosf(clampf(v3_dot(a, b), -1.0f, 1.0f)); }

/* Share of a local light's emission a cone about `axis` of solid angle
 * omega receives, roughly: for weighing the lights against each other
 * only (any positive weight keeps the photons unbiased). */
static float cone_share(const light *l, vec3 axis, float omega)
{
    float spread = 4.0f * PHOS_PI; /* sr the light emits into */
    if (l->kind == LIGHT_SPOT) {
        if (angle_between(axis, l->direction) > acosf(l->spot_cos_half) + asinf(fminf(1.0f, safe_sqrtf(omega / PHOS_PI))))
            return 0.0f;
        spread = cone_solid_angle(l->spot_cos_half);
    } else if (l->kind == LIGHT_AREA) {
        spread = 2.0f * PHOS_PI;
    }
    return omega / spread;
}

/* Steps of the search for a box's narrowest cone (box_cone). */
#define CONE_AXIS_STEPS 24

/* The cosine of the widest angle between axis and the unit directions d[8]. */
static float widest_cos(vec3 axis, const vec3 d[8], int *widest)
{
    float lowest = 2.0f;
    for (int k = 0; k < 8; k++) {
        float c = v3_dot(axis, d[k]);
        if (c < lowest) {
            lowest = c;
            *widest = k;
        }
    }
    return lowest;
}

/* The cone of every direction from a point of the sphere (c, r) (a light
 * group's bounds) to a point of box b, into *out; 0 when there is none
 * narrower than the whole sphere of directions worth having (the light
 * touches or sits in the box, or the box spans more than a hemisphere
 * around it). The directions from c to the box form the convex cone over
 * its corners; a cone of half angle θ ≤ 90° is convex too, so holding
 * every corner it holds the whole box. Its axis starts at the corners'
 * mean direction and steps toward the widest corner by shrinking amounts
 * (Bădoiu & Clarkson's iteration for the smallest enclosing ball), which
 * for a floor under a lamp turns it from the floor's centre to straight
 * down. Another point of the light, within r of c, sees any point of the
 * box at most asin(r/near) away, near the box's distance from c. */
static int box_cone(vec3 c, float r, const box *b, projection_cone *out)
{
    vec3 nearest = v3_min(v3_max(c, b->lo), b->hi);
    float near = v3_length(v3_sub(nearest, c)), reach = r * (1.0f + MARGIN) + MARGIN * near;
    if (!(near > reach))
        return 0;
    vec3 d[8], axis = v3s(0.0f);
    for (int k = 0; k < 8; k++) {
        vec3 corner = v3((k & 1) ? b->hi.x : b->lo.x, (k & 2) ? b->hi.y : b->lo.y, (k & 4) ? b->hi.z : b->lo.z);
        d[k] = v3_normalize(v3_sub(corner, c)); /* corners are at least `near` > 0 away */
        axis = v3_add(axis, d[k]);
    }
    if (!(v3_length(axis) > 0.0f))
        return 0;
    axis = v3_normalize(axis);
    int widest = 0;
    float cos_corner = widest_cos(axis, d, &widest);
    for (int step = 0; step < CONE_AXIS_STEPS; step++) {
        vec3 next = v3_add(axis, v3_scale(d[widest], 1.0f / (float)(step + 2)));
        if (!(v3_length(next) > 0.0f))
            break;
        next = v3_normalize(next);
        int w = 0;
        float cw = widest_cos(next, d, &w);
        if (cw > cos_corner) { /* else the next, shorter step from the same axis */
            axis = next;
            cos_corner = cw;
            widest = w;
        }
    }
    if (!(cos_corner >= 0.0f))
        return 0;
    float half = acosf(clampf(cos_corner, -1.0f, 1.0f)) + asinf(clampf(reach / near, 0.0f, 1.0f)) + MARGIN;
    if (!(half < PHOS_PI))
        return 0;
    out->axis = axis;
    out->cos_max = cosf(half);
    out->omega = cone_solid_angle(out->cos_max);
    return out->omega > 0.0f;
}

/* ---------------------------------------------------------- plane cells */

/* A distant light's photons start on a plane across their direction of
 * travel. A sun has one plane. The world has one per bin of a grid of
 * WORLD_BINS × WORLD_BINS equal solid angles (the cells of
 * warp_uniform_sphere's square): its photons from a bin start on the
 * plane across the bin's centre direction. A cell's index is
 * bin · grid² + (its place in the bin's grid). */
typedef struct distant_plane {
    frame f;                /* f.n = the direction of travel through the plane's centre */
    vec3 corner;            /* of the square, on the plane */
    float half;             /* m: half the square's side */
    float back;             /* m: how far before the plane a photon starts */
    float tan_a;            /* tan of the largest angle between f.n and a photon's direction */
    uint32_t grid;          /* cells per side */
    float omega;            /* sr of the directions the plane's photons take (0: one direction) */
} distant_plane;

/* The world's bin `bin` as a rectangle of warp_uniform_sphere's square. */
static float2 world_bin_u(uint32_t bin, float2 ud)
{
    float2 u = {((float)(bin / WORLD_BINS) + ud.x) / WORLD_BINS, ((float)(bin % WORLD_BINS) + ud.y) / WORLD_BINS};
    return u;
}

/* Direction of travel of a world photon from bin `bin` (ud: where in it):
 * a uniform world's bins are rectangles of warp_uniform_sphere's square,
 * of equal solid angle; an environment's are those of its latitude-
 * longitude grid (environment.h). */
static vec3 world_bin_direction(const light *l, uint32_t bin, float2 ud)
{
    if (l->kind == LIGHT_ENVIRONMENT)
        return v3_neg(environment_bin_direction(bin, ud));
    return v3_neg(warp_uniform_sphere(world_bin_u(bin, ud)));
}

/* The plane of a sun (bin 0) or of the world's bin `bin`: perpendicular
 * to its axis through the scene's centre, a square of half side R / cos a
 * (a the largest angle between a photon's direction and the axis), so
 * that every photon with one of the plane's directions that crosses the
 * scene's sphere crosses the square: a point of the sphere lies at most
 * R sin φ sideways and R cos φ along the axis from the centre, and its ray
 * drifts R cos φ · tan a more sideways on its way to the plane. A photon
 * is parametrized by where it crosses the plane, not where it starts: the
 * drift of an opening's shadow over a bin's directions grows with its
 * distance from the plane, and the centre keeps that distance small. */
static distant_plane plane_of(const light_table *t, const light *l, uint32_t bin)
{
    distant_plane p;
    vec3 axis;
    if (light_is_world(l)) {
        float2 c = {0.5f, 0.5f};
        axis = world_bin_direction(l, bin, c);
        /* The angle from the centre is largest at a corner of the bin: along
         * an edge of constant z it grows with the azimuth difference, and
         * along a meridian arc shorter than π it has no interior maximum. */
        float cos_min = 1.0f;
        for (int k = 0; k < 4; k++) {
            float2 corner = {(float)(k & 1), (float)(k >> 1)};
            cos_min = fminf(cos_min, v3_dot(axis, world_bin_direction(l, bin, corner)));
        }
        cos_min = clampf(cos_min - MARGIN, 0.1f, 1.0f);
        p.tan_a = safe_sqrtf(1.0f - cos_min * cos_min) / cos_min;
        p.grid = WORLD_PLANE_CELLS;
        p.omega = l->kind == LIGHT_ENVIRONMENT ? environment_bin_solid_angle(bin)
                                               : 4.0f * PHOS_PI / (WORLD_BINS * WORLD_BINS);
    } else {
        axis = l->direction;
        p.tan_a = l->sun_cos_half < 1.0f ? safe_sqrtf(1.0f - l->sun_cos_half * l->sun_cos_half) / l->sun_cos_half
                                         : 0.0f;
        p.grid = PLANE_CELLS;
        p.omega = l->sun_cos_half < 1.0f ? cone_solid_angle(l->sun_cos_half) : 0.0f;
    }
    p.f = frame_from_normal(axis);
    p.half = t->radius * safe_sqrtf(1.0f + p.tan_a * p.tan_a) * (1.0f + MARGIN);
    p.back = t->radius + 1.5f * p.half; /* > R + √2·half: every start lies outside the sphere */
    p.corner = v3_sub(t->center, v3_add(v3_scale(p.f.t, p.half), v3_scale(p.f.b, p.half)));
    return p;
}

static uint32_t distant_bins(const light *l) { return light_is_world(l) ? WORLD_BINS * WORLD_BINS : 1u; }

/* Cells in each of the light's planes. */
static uint32_t cell_grid_size(const light *l)
{
    return light_is_world(l) ? WORLD_PLANE_CELLS * WORLD_PLANE_CELLS : PLANE_CELLS * PLANE_CELLS;
}

/* m²: the area of one of the plane's cells. */
static float plane_cell_area(const distant_plane *p)
{
    float side = 2.0f * p->half / (float)p->grid;
    return side * side;
}

/* Whether a photon through cell `cell` of the plane (its place in the
 * plane's grid) can reach one of the target spheres. */
static int plane_cell_marked(const light_table *tab, const distant_plane *p, const sphere *t, int nt, uint32_t cell)
{
    float side = 2.0f * p->half / (float)p->grid;
    float x0 = (float)(cell % p->grid) * side, y0 = (float)(cell / p->grid) * side;
    for (int k = 0; k < nt; k++) {
        vec3 v = v3_sub(t[k].c, p->corner);
        float cx = v3_dot(v, p->f.t), cy = v3_dot(v, p->f.b), depth = v3_dot(v, p->f.n);
        float reach = t[k].r + (fabsf(depth) + t[k].r) * p->tan_a + MARGIN * tab->radius;
        float dx = fmaxf(fmaxf(x0 - cx, cx - (x0 + side)), 0.0f), dy = fmaxf(fmaxf(y0 - cy, cy - (y0 + side)), 0.0f);
        if (dx * dx + dy * dy <= reach * reach)
            return 1;
    }
    return 0;
}

/* W/m² a cell's photons carry per unit of its area: the sun's irradiance
 * across its axis, or the world's radiance integrated over the bin's
 * directions (a uniform world's radiance times the bin's solid angle). */
static float distant_flux_density(const light_table *tab, const light *l, const distant_plane *p, uint32_t bin)
{
    if (l->kind == LIGHT_ENVIRONMENT)
        return tab->env->bin_integral[bin];
    float c = fmaxf(v3_average(l->color), 0.0f);
    return l->kind == LIGHT_WORLD ? c * p->omega : c;
}

/* ---------------------------------------------------------------- build */

void projection_map_free(projection_map *pm)
{
    free(pm->targets);
    free(pm->target_cdf);
    free(pm->groups);
    free(pm->cells);
    free(pm->cell_cum);
    free(pm->cones);
    distribution_free(&pm->pick);
    memset(pm, 0, sizeof(*pm));
}

static int append_cell(projection_map *pm, uint32_t *capacity, uint32_t cell)
{
    if (pm->groups[pm->group_count].first + pm->groups[pm->group_count].count == *capacity) {
        uint32_t cap = *capacity ? *capacity * 2 : 1024;
        uint32_t *n = realloc(pm->cells, sizeof(uint32_t) * cap);
        if (n)
            pm->cells = n;
        float *c = realloc(pm->cell_cum, sizeof(float) * cap);
        if (c)
            pm->cell_cum = c;
        if (!n || !c)
            return 0;
        *capacity = cap;
    }
    projection_group *g = &pm->groups[pm->group_count];
    pm->cell_cum[g->first + g->count] = (float)(g->count + 1); /* weight 1 each */
    pm->cells[g->first + g->count++] = cell;
    return 1;
}

static int append_cone(projection_map *pm, uint32_t *capacity, const projection_cone *c)
{
    projection_group *g = &pm->groups[pm->group_count];
    if (g->first + g->count == *capacity) {
        uint32_t cap = *capacity ? *capacity * 2 : 64;
        projection_cone *n = realloc(pm->cones, sizeof(projection_cone) * cap);
        if (!n)
            return 0;
        pm->cones = n;
        *capacity = cap;
    }
    pm->cones[g->first + g->count++] = *c;
    return 1;
}

/* A distant light's marked cells, over all its planes; returns the power
 * sent into them (W). */
static float mark_distant(projection_map *pm, uint32_t *capacity, const light_table *tab, const light *l,
                          const sphere *t, int nt, int *ok)
{
    float power = 0.0f;
    for (uint32_t bin = 0; bin < distant_bins(l); bin++) {
        distant_plane p = plane_of(tab, l, bin);
        uint32_t cells = p.grid * p.grid, before = pm->groups[pm->group_count].count;
        for (uint32_t cell = 0; cell < cells; cell++)
            if (plane_cell_marked(tab, &p, t, nt, cell) && !(*ok = append_cell(pm, capacity, bin * cells + cell)))
                return 0.0f;
        power += distant_flux_density(tab, l, &p, bin) * plane_cell_area(&p) *
                 (float)(pm->groups[pm->group_count].count - before); /* E·A_marked */
    }
    return power;
}

/* A local light group's cones; returns the power sent into them (W),
 * roughly (cone_share). */
static float mark_cones(projection_map *pm, uint32_t *capacity, const light_table *tab, const light_group *g,
                        const sphere *t, int nt, int *ok)
{
    const light *l = &tab->lights[g->first];
    projection_group *pg = &pm->groups[pm->group_count];
    float share = 0.0f, total_omega = 0.0f;
    for (int k = 0; k < nt; k++) {
        vec3 v = v3_sub(t[k].c, g->center);
        float d = v3_length(v), reach = t[k].r + g->radius * (1.0f + MARGIN) + MARGIN * d;
        if (!(d > reach)) { /* the light sits among the targets */
            pg->all = 1;
            pg->count = 0;
            return g->power;
        }
        float sin_b = reach / d;
        projection_cone c;
        c.axis = v3_scale(v, 1.0f / d);
        c.cos_max = safe_sqrtf(1.0f - sin_b * sin_b);
        c.omega = cone_solid_angle(c.cos_max);
        if (!(c.omega > 0.0f))
            continue;
        total_omega += c.omega;
        c.cdf_end = total_omega;
        share += cone_share(l, c.axis, c.omega);
        if (!(*ok = append_cone(pm, capacity, &c)))
            return 0.0f;
    }
    for (uint32_t k = 0; k < pg->count; k++)
        pm->cones[pg->first + k].cdf_end /= total_omega;
    if (total_omega >= 4.0f * PHOS_PI) { /* cones covering the sphere gain nothing */
        pg->all = 1;
        pg->count = 0;
        return g->power;
    }
    /* Never zero: a cone the estimate misses still carries flux. */
    return g->power * clampf(share, 1e-4f, 1.0f);
}

/* sr a local light emits into: a spot its cone, an area lamp its
 * hemisphere, a point lamp the sphere. */
static float emission_solid_angle(const light *l)
{
    if (l->kind == LIGHT_SPOT)
        return cone_solid_angle(l->spot_cos_half);
    return l->kind == LIGHT_AREA ? 2.0f * PHOS_PI : 4.0f * PHOS_PI;
}

/* A local light group's cones toward the global map's boxes (box_cone),
 * leaving out those the light sends nothing into (a spot's back); every
 * direction when one box has no cone, or when the cones span as much as
 * the light emits into: photons drawn uniformly in them would then be
 * spread thinner than the light's own sampling spreads them (a spot
 * under a ceiling: its cone lies inside the ceiling's). Returns the power
 * sent into them (W), roughly (cone_share). */
static float mark_box_cones(projection_map *pm, uint32_t *capacity, const light_table *tab, const light_group *g,
                            const box *t, int nt, int *ok)
{
    const light *l = &tab->lights[g->first];
    projection_group *pg = &pm->groups[pm->group_count];
    float share = 0.0f, total_omega = 0.0f, emitted_into = g->count == 1 ? emission_solid_angle(l) : 4.0f * PHOS_PI;
    for (int k = 0; k < nt; k++) {
        /* An emissive plane's own instance: its photons never land on it. */
        if (l->kind == LIGHT_TRIANGLE && t[k].planar && t[k].instance == l->instance)
            continue;
        projection_cone c;
        int has_cone = box_cone(g->center, g->radius, &t[k], &c);
        float cone_power = has_cone ? cone_share(l, c.axis, c.omega) : 0.0f;
        if (has_cone && g->count == 1 && !(cone_power > 0.0f))
            continue;
        if (!has_cone || total_omega + c.omega >= emitted_into) {
            pg->all = 1;
            pg->count = 0;
            return g->power;
        }
        total_omega += c.omega;
        c.cdf_end = total_omega;
        share += cone_power;
        if (!(*ok = append_cone(pm, capacity, &c)))
            return 0.0f;
    }
    if (pg->count == 0) { /* nothing it can land on: no photon is ever stored */
        pg->all = 1;
        return g->power;
    }
    for (uint32_t k = 0; k < pg->count; k++)
        pm->cones[pg->first + k].cdf_end /= total_omega;
    return g->power * clampf(share, 1e-4f, 1.0f);
}

/* ------------------------------------------------------- world discs */

/* The world's caustic photons (Jensen's projection maps for a light at
 * infinity): a direction ω from the world's own distribution p(ω), a
 * target sphere k picked by its cross-section (q_k = r_k² / Σ r²), and a
 * uniform point of the disc of radius r_k about its centre across ω, from
 * which the photon starts back outside the scene. Every line from the
 * world that can reach a target crosses its disc, so nothing that makes a
 * caustic is missed; a line that crosses n of the discs has the density
 * p(ω) · n / (π Σ r²) per unit area across ω, and carries
 *
 *     Φ = L(ω) · π Σ r² / (p(ω) · n).
 */
static int store_targets(projection_map *pm, const sphere *t, int nt)
{
    pm->targets = malloc(sizeof(float) * 4 * (size_t)nt);
    pm->target_cdf = malloc(sizeof(float) * (size_t)nt);
    if (!pm->targets || !pm->target_cdf)
        return 0;
    double sum = 0.0;
    for (int k = 0; k < nt; k++) {
        pm->targets[4 * k] = t[k].c.x, pm->targets[4 * k + 1] = t[k].c.y, pm->targets[4 * k + 2] = t[k].c.z;
        pm->targets[4 * k + 3] = t[k].r;
        sum += (double)t[k].r * t[k].r;
        pm->target_cdf[k] = (float)sum;
    }
    for (int k = 0; k < nt; k++)
        pm->target_cdf[k] = sum > 0.0 ? (float)(pm->target_cdf[k] / sum) : (float)(k + 1) / (float)nt;
    pm->target_cdf[nt - 1] = 1.0f;
    pm->target_count = (uint32_t)nt;
    return 1;
}

/* π Σ r² (m²): the discs' total area. */
static float discs_area(const projection_map *pm)
{
    double sum = 0.0;
    for (uint32_t k = 0; k < pm->target_count; k++)
        sum += (double)pm->targets[4 * k + 3] * pm->targets[4 * k + 3];
    return (float)(PHOS_PI * sum);
}

/* The power the world sends through the discs (W, counting overlaps
 * twice: a weight among the lights only): ∫ L dω · π Σ r². */
static float world_disc_power(const light_table *tab, const light *l, const projection_map *pm)
{
    float radiance_integral = l->kind == LIGHT_ENVIRONMENT ? (float)tab->env->integral
                                                           : 4.0f * PHOS_PI * fmaxf(v3_average(l->color), 0.0f);
    return radiance_integral * discs_area(pm);
}

/* How many discs across d the line through x along d crosses. */
static uint32_t discs_crossed(const projection_map *pm, vec3 x, vec3 d)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < pm->target_count; k++) {
        vec3 v = v3_sub(v3_load(pm->targets + 4 * k), x);
        vec3 across = v3_sub(v, v3_scale(d, v3_dot(v, d)));
        float r = pm->targets[4 * k + 3];
        n += v3_length2(across) <= r * r;
    }
    return n;
}

static int world_disc_emit(const scene *s, const projection_map *pm, const light *l, const float u[4],
                           vec3 *origin, vec3 *direction, vec3 *flux)
{
    const light_table *tab = &s->lights;
    float2 ud = {u[2], u[3]};
    float pdf;
    vec3 from = l->kind == LIGHT_ENVIRONMENT ? environment_sample(tab->env, ud, &pdf) : warp_uniform_sphere(ud);
    if (l->kind != LIGHT_ENVIRONMENT)
        pdf = PHOS_INV_4PI;
    if (!(pdf > 0.0f))
        return 0;
    vec3 d = v3_neg(from);
    /* A target by its cross-section; u[0] is rescaled to the disc. */
    float x = u[0];
    uint32_t k = 0;
    while (k + 1 < pm->target_count && x >= pm->target_cdf[k])
        k++;
    float below = k ? pm->target_cdf[k - 1] : 0.0f;
    float2 uo = {fminf((x - below) / (pm->target_cdf[k] - below), 0x1.fffffep-1f), u[1]};
    vec3 c = v3_load(pm->targets + 4 * k);
    float r = pm->targets[4 * k + 3];
    frame f = frame_from_normal(d);
    float2 dk = warp_disk_concentric(uo);
    vec3 on_disc = v3_add(c, v3_add(v3_scale(f.t, dk.x * r), v3_scale(f.b, dk.y * r)));
    uint32_t n = discs_crossed(pm, on_disc, d);
    if (n == 0)
        return 0;
    /* Back outside the scene's bounding sphere, so that whatever lies
     * between the world and the target can block the photon. */
    float back = v3_length(v3_sub(c, tab->center)) + tab->radius + r;
    *origin = v3_madd(on_disc, d, -back);
    *direction = d;
    vec3 L = l->kind == LIGHT_ENVIRONMENT ? environment_radiance(s, tab->env, from, 0) : l->color;
    *flux = v3_scale(L, discs_area(pm) / (pdf * (float)n));
    return 1;
}

/* Marks group g's cells or cones; returns the power it sends into them. */
static float mark_group(projection_map *pm, uint32_t *cells_capacity, uint32_t *cones_capacity, const scene *s,
                        const light_group *g, const sphere *t, int nt, int *ok)
{
    const light_table *tab = &s->lights;
    const light *l = &tab->lights[g->first];
    projection_group *pg = &pm->groups[pm->group_count];
    const projection_group *prev = pm->group_count ? pg - 1 : NULL;
    *ok = 1;
    pg->all = 0;
    pg->count = 0;
    pg->first = 0;
    /* Each kind of group keeps its own list, in group order. */
    int distant = light_is_distant(l);
    for (const projection_group *q = prev; q; q = q > pm->groups ? q - 1 : NULL)
        if (!q->all && (int)q->distant == distant) {
            pg->first = q->first + q->count;
            break;
        }
    pg->distant = (uint32_t)distant;
    if (light_is_world(l)) {
        /* Bins of directions as wide as π/8 drift a photon so far across
         * the scene that a plane cell reaching a 10 cm glass is mostly
         * aimed past it (2 % of the paths stored under an HDR); a disc
         * across each direction hits what it aims at. */
        pg->distant = 0;
        pg->discs = 1;
        return world_disc_power(tab, l, pm);
    }
    if (pg->distant)
        return mark_distant(pm, cells_capacity, tab, l, t, nt, ok);
    return mark_cones(pm, cones_capacity, tab, g, t, nt, ok);
}

int projection_map_build(projection_map *pm, const scene *s, float max_roughness)
{
    memset(pm, 0, sizeof(*pm));
    const light_table *tab = &s->lights;
    if (tab->group_count == 0)
        return 1;
    sphere *t;
    int nt = collect_targets(s, max_roughness, &t);
    if (nt < 0)
        return 0;
    pm->groups = calloc(tab->group_count, sizeof(projection_group));
    float *weight = malloc(sizeof(float) * tab->group_count);
    int ok = pm->groups && weight && (nt == 0 || store_targets(pm, t, nt));
    uint32_t cells_capacity = 0, cones_capacity = 0;
    double sent = 0.0, total = 0.0;
    for (uint32_t g = 0; ok && g < tab->group_count; g++) {
        if (nt) {
            weight[g] = mark_group(pm, &cells_capacity, &cones_capacity, s, &tab->groups[g], t, nt, &ok);
        } else {
            weight[g] = tab->groups[g].power;
            pm->groups[g].all = 1;
        }
        /* A local group's pick weight, kept for when pilots reweigh the
         * cells (rebuild_pick). */
        pm->groups[g].power = weight[g];
        pm->group_count++;
        sent += weight[g];
        total += tab->groups[g].power;
    }
    if (ok)
        ok = distribution_build(&pm->pick, weight, tab->group_count);
    pm->marked_fraction = total > 0.0 ? (float)(sent / total) : 1.0f;
    free(weight);
    free(t);
    if (!ok)
        projection_map_free(pm);
    return ok;
}

/* The power a distant group sends through its cells as weighted: Σ E·w·A
 * (E the flux density of the cell's plane). */
static float distant_weight(const light_table *tab, const projection_map *pm, uint32_t g)
{
    const light *l = &tab->lights[tab->groups[g].first];
    const projection_group *pg = &pm->groups[g];
    double sum = 0.0, below = 0.0;
    uint32_t bin = UINT32_MAX;
    float per_weight = 0.0f;
    for (uint32_t k = 0; k < pg->count; k++) {
        if (pm->cells[pg->first + k] / cell_grid_size(l) != bin) {
            bin = pm->cells[pg->first + k] / cell_grid_size(l);
            distant_plane p = plane_of(tab, l, bin);
            per_weight = distant_flux_density(tab, l, &p, bin) * plane_cell_area(&p);
        }
        double cum = pm->cell_cum[pg->first + k];
        sum += (cum - below) * per_weight;
        below = cum;
    }
    return (float)sum;
}

static int rebuild_pick(projection_map *pm, const scene *s)
{
    const light_table *tab = &s->lights;
    float *weight = malloc(sizeof(float) * tab->group_count);
    if (!weight)
        return 0;
    for (uint32_t g = 0; g < tab->group_count; g++) {
        const projection_group *pg = &pm->groups[g];
        weight[g] = pg->all ? tab->groups[g].power
                    : pg->distant ? (pg->count ? distant_weight(tab, pm, g) : 0.0f)
                                  : pg->power;
    }
    distribution_free(&pm->pick);
    int ok = distribution_build(&pm->pick, weight, tab->group_count);
    free(weight);
    return ok;
}

int projection_map_build_global(projection_map *pm, const scene *s)
{
    memset(pm, 0, sizeof(*pm));
    const light_table *tab = &s->lights;
    if (tab->group_count == 0)
        return 1;
    box *boxes;
    int nb = collect_boxes(s, &boxes);
    pm->groups = calloc(tab->group_count, sizeof(projection_group));
    if (nb < 0 || !pm->groups) {
        free(boxes);
        free(pm->groups);
        pm->groups = NULL;
        return 0;
    }
    /* One target for the distant lights, the scene's bounding sphere:
     * every cell a photon can reach the scene from. */
    sphere scene_sphere = {tab->center, tab->radius};
    uint32_t cells_capacity = 0, cones_capacity = 0, first_cell = 0, first_cone = 0;
    int ok = 1;
    for (uint32_t g = 0; ok && g < tab->group_count; g++) {
        const light *l = &tab->lights[tab->groups[g].first];
        projection_group *pg = &pm->groups[g];
        if (light_is_distant(l)) {
            pg->first = first_cell;
            pg->distant = 1;
            mark_distant(pm, &cells_capacity, tab, l, &scene_sphere, 1, &ok);
            first_cell += pg->count;
        } else {
            pg->first = first_cone;
            pg->power = mark_box_cones(pm, &cones_capacity, tab, &tab->groups[g], boxes, nb, &ok);
            first_cone += pg->count;
        }
        pm->group_count++;
    }
    free(boxes);
    if (ok)
        ok = rebuild_pick(pm, s);
    if (!ok)
        projection_map_free(pm);
    return ok;
}

/* Each cell takes the largest weight of its 3 × 3 neighbourhood in its
 * plane: a cell only partly over an opening, which the pilots may all have
 * missed, lies beside one they found, and keeps its full share. Otherwise
 * its photons that do pass would carry 1/PILOT_FLOOR times the power of
 * the others and blotch the map. */
int projection_map_set_weights(projection_map *pm, const scene *s, const float *weights)
{
    const uint32_t most = WORLD_BINS * WORLD_BINS * WORLD_PLANE_CELLS * WORLD_PLANE_CELLS > PLANE_CELLS * PLANE_CELLS
                              ? WORLD_BINS * WORLD_BINS * WORLD_PLANE_CELLS * WORLD_PLANE_CELLS
                              : PLANE_CELLS * PLANE_CELLS;
    float *grid = malloc(sizeof(float) * most);
    if (!grid)
        return 0;
    for (uint32_t g = 0; g < pm->group_count; g++) {
        const projection_group *pg = &pm->groups[g];
        if (pg->all || !pg->distant)
            continue;
        const light *l = &s->lights.lights[s->lights.groups[g].first];
        int side = (int)(light_is_world(l) ? WORLD_PLANE_CELLS : PLANE_CELLS);
        memset(grid, 0, sizeof(float) * most);
        for (uint32_t k = 0; k < pg->count; k++)
            grid[pm->cells[pg->first + k]] = weights[pg->first + k];
        float cum = 0.0f;
        for (uint32_t k = 0; k < pg->count; k++) {
            uint32_t cell = pm->cells[pg->first + k], bin_first = cell - cell % (uint32_t)(side * side);
            int cx = (int)(cell % (uint32_t)(side * side)) % side, cy = (int)(cell % (uint32_t)(side * side)) / side;
            float w = 0.0f;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int x = cx + dx, y = cy + dy;
                    if (x >= 0 && y >= 0 && x < side && y < side)
                        w = fmaxf(w, grid[bin_first + (uint32_t)(y * side + x)]);
                }
            cum += w;
            pm->cell_cum[pg->first + k] = cum;
        }
    }
    free(grid);
    return rebuild_pick(pm, s);
}

/* ------------------------------------------------------------- emission */

/* A cell of the group by weight, from u (rescaled to the position within
 * it); *share receives the cell's weight over the group's total. */
static uint32_t pick_cell(const projection_map *pm, const projection_group *g, float *u, float *share)
{
    const float *cum = pm->cell_cum + g->first;
    float total = cum[g->count - 1], x = *u * total;
    uint32_t lo = 0, hi = g->count - 1; /* the first k with cum[k] > x */
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (cum[mid] > x)
            hi = mid;
        else
            lo = mid + 1;
    }
    float below = lo ? cum[lo - 1] : 0.0f, w = cum[lo] - below;
    *u = fminf(fmaxf((x - below) / w, 0.0f), 0x1.fffffep-1f);
    *share = w / total;
    return pm->cells[g->first + lo];
}

/* Origin in cell `cell` of the light's planes and direction, from u and
 * ud; returns the cell's plane, and in *solid_angle the reciprocal of the
 * direction's density among the plane's directions (sr: the plane's Ω
 * where they are uniform; 0 for a delta sun). An environment draws its
 * direction from its map within the plane's bin (environment.h). */
static distant_plane distant_cell_ray(const light_table *tab, const light *l, uint32_t cell, float2 u, float2 ud,
                                      vec3 *origin, vec3 *direction, float *solid_angle)
{
    uint32_t cells = cell_grid_size(l), bin = cell / cells, local = cell % cells;
    distant_plane p = plane_of(tab, l, bin);
    float side = 2.0f * p.half / (float)p.grid;
    float px = ((float)(local % p.grid) + u.x) * side, py = ((float)(local / p.grid) + u.y) * side;
    vec3 crossing = v3_add(p.corner, v3_add(v3_scale(p.f.t, px), v3_scale(p.f.b, py)));
    *solid_angle = p.omega;
    if (l->kind == LIGHT_ENVIRONMENT) {
        float pdf;
        *direction = v3_neg(environment_sample_in_bin(tab->env, bin, ud, &pdf));
        *solid_angle = pdf > 0.0f ? 1.0f / pdf : 0.0f;
    } else if (l->kind == LIGHT_WORLD) {
        *direction = world_bin_direction(l, bin, ud);
    } else {
        *direction = l->sun_cos_half < 1.0f ? warp_cone(l->direction, l->sun_cos_half, ud) : l->direction;
    }
    *origin = v3_madd(crossing, *direction, -p.back);
    return p;
}

void projection_map_cell_ray(const scene *s, const projection_map *pm, uint32_t g, uint32_t k, float2 u, float2 ud,
                             vec3 *origin, vec3 *direction)
{
    const light *l = &s->lights.lights[s->lights.groups[g].first];
    float solid_angle;
    distant_cell_ray(&s->lights, l, pm->cells[pm->groups[g].first + k], u, ud, origin, direction, &solid_angle);
}

int projection_map_cone_ray(const scene *s, const projection_map *pm, uint32_t g, uint32_t k, float u_light,
                            float2 uo, float2 ud, vec3 *origin, vec3 *direction)
{
    const light_group *lg = &s->lights.groups[g];
    const projection_cone *c = &pm->cones[pm->groups[g].first + k];
    float p_light = 1.0f;
    uint32_t li = lg->first + (lg->count > 1 ? distribution_sample(&lg->within, u_light, &p_light, NULL) : 0);
    vec3 intensity;
    *direction = warp_cone(c->axis, c->cos_max, ud);
    return light_emit_toward(s, li, *direction, uo, origin, &intensity) && !v3_is_zero(intensity);
}

int projection_map_set_cone_weights(projection_map *pm, const float *weights)
{
    for (uint32_t g = 0; g < pm->group_count; g++) {
        projection_group *pg = &pm->groups[g];
        if (pg->all || pg->distant || pg->count == 0)
            continue;
        double total = 0.0;
        for (uint32_t k = 0; k < pg->count; k++)
            total += (double)weights[pg->first + k] * pm->cones[pg->first + k].omega;
        if (!(total > 0.0))
            return 0;
        double cum = 0.0;
        for (uint32_t k = 0; k < pg->count; k++) {
            cum += (double)weights[pg->first + k] * pm->cones[pg->first + k].omega;
            pm->cones[pg->first + k].cdf_end = (float)(cum / total);
        }
        pm->cones[pg->first + pg->count - 1].cdf_end = 1.0f;
    }
    return 1;
}

int projection_map_emit(const scene *s, const projection_map *pm, const float u[5], vec3 *origin, vec3 *direction,
                        vec3 *power)
{
    const light_table *tab = &s->lights;
    if (pm->group_count == 0)
        return light_sample_emission(s, u, origin, direction, power);
    float p_group, uw;
    uint32_t gi = distribution_sample(&pm->pick, u[0], &p_group, &uw);
    const light_group *g = &tab->groups[gi];
    const projection_group *pg = &pm->groups[gi];
    float p_light = 1.0f;
    uint32_t li = g->first + (g->count > 1 ? distribution_sample(&g->within, uw, &p_light, NULL) : 0);
    if (!(p_group > 0.0f) || !(p_light > 0.0f))
        return 0;
    const light *l = &tab->lights[li];
    vec3 flux;
    if (pg->all) {
        if (!light_emit(s, li, u + 1, origin, direction, &flux))
            return 0;
    } else if (pg->discs) {
        if (!world_disc_emit(s, pm, l, u + 1, origin, direction, &flux))
            return 0;
    } else if (pg->count == 0) {
        return 0;
    } else if (pg->distant) {
        float share;
        float2 uc = {u[1], u[2]}, ud = {u[3], u[4]};
        uint32_t cell = pick_cell(pm, pg, &uc.x, &share);
        float solid_angle;
        distant_plane p = distant_cell_ray(tab, l, cell, uc, ud, origin, direction, &solid_angle);
        float area = plane_cell_area(&p) / share; /* 1/p_A: the cell's area over its probability */
        if (p.omega > 0.0f) {
            /* Through a plane across the axis, radiance L from direction d
             * brings L·cos θ per unit area and solid angle; d has density
             * 1/solid_angle among the plane's directions. */
            vec3 L = l->kind == LIGHT_ENVIRONMENT ? environment_radiance(s, tab->env, v3_neg(*direction), 0)
                     : l->kind == LIGHT_WORLD     ? l->color
                                                  : l->sun_radiance;
            flux = v3_scale(L, v3_dot(*direction, p.f.n) * solid_angle * area);
        } else {
            flux = v3_scale(l->color, area); /* E / p_A */
        }
    } else {
        /* A cone by its solid angle, a uniform direction in it, and the
         * mixture's density over every cone that holds that direction. */
        const projection_cone *cones = pm->cones + pg->first;
        uint32_t k = 0;
        while (k + 1 < pg->count && u[3] >= cones[k].cdf_end)
            k++;
        float below = k ? cones[k - 1].cdf_end : 0.0f;
        float2 ud = {fminf((u[3] - below) / (cones[k].cdf_end - below), 0x1.fffffep-1f), u[4]};
        vec3 d = warp_cone(cones[k].axis, cones[k].cos_max, ud);
        float pdf = 0.0f;
        for (uint32_t j = 0; j < pg->count; j++)
            if (v3_dot(d, cones[j].axis) >= cones[j].cos_max)
                pdf += (cones[j].cdf_end - (j ? cones[j - 1].cdf_end : 0.0f)) / cones[j].omega;
        float2 uo = {u[1], u[2]};
        vec3 intensity;
        if (!(pdf > 0.0f) || !light_emit_toward(s, li, d, uo, origin, &intensity))
            return 0;
        *direction = d;
        flux = v3_scale(intensity, 1.0f / pdf);
    }
    *power = v3_scale(flux, 1.0f / (p_group * p_light));
    return !v3_is_zero(*power) && v3_is_finite(*power);
}
