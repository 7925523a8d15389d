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
 * photon tilted by the sun's half angle.
 */
#include "photons/projection_map.h"

#include <stdlib.h>
#include <string.h>

#include "lights/light.h"
#include "sampling/warp.h"
#include "shading/material.h"

#define PLANE_CELLS 64
#define MAX_CONES 64        /* per light; more instances share one sphere */
#define MARGIN 1e-3f        /* rad or m: rounding never unmarks a cell that can see a target */

typedef struct sphere {
    vec3 c;
    float r;
} sphere;

/* ------------------------------------------------------------- targets */

static int instance_scatters_delta(const scene *s, const instance *inst)
{
    if (inst->material_count == 0)
        return material_can_scatter_delta(&scene_default_material);
    for (uint32_t k = 0; k < inst->material_count; k++)
        if (material_can_scatter_delta(scene_instance_material(s, inst, k)))
            return 1;
    return 0;
}

static sphere instance_sphere(const scene *s, const instance *inst)
{
    const mesh *m = &s->meshes[inst->mesh_id];
    vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        vec3 p = xform_point(inst->transform, v3_load(m->positions + 3 * (size_t)v));
        lo = v3_min(lo, p);
        hi = v3_max(hi, p);
    }
    sphere sp = {v3_scale(v3_add(lo, hi), 0.5f), 0.5f * v3_length(v3_sub(hi, lo))};
    return sp;
}

/* The bounding spheres of the instances that can scatter delta; one
 * sphere around all of them past MAX_CONES (each photon tests every cone
 * for its density). Returns the count (−1: out of memory). */
static int collect_targets(const scene *s, sphere **out)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++)
        n += s->meshes[s->instances[i].mesh_id].triangle_count > 0 && instance_scatters_delta(s, &s->instances[i]);
    *out = NULL;
    if (n == 0)
        return 0;
    sphere *t = malloc(sizeof(sphere) * n);
    if (!t)
        return -1;
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const instance *inst = &s->instances[i];
        if (s->meshes[inst->mesh_id].triangle_count > 0 && instance_scatters_delta(s, inst))
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
        spread = 2.0f * PHOS_PI * (1.0f - l->spot_cos_half);
    } else if (l->kind == LIGHT_AREA) {
        spread = 2.0f * PHOS_PI;
    }
    return omega / spread;
}

/* ---------------------------------------------------------- plane cells */

typedef struct sun_plane {
    frame f;                /* f.n = the sun's direction of travel */
    vec3 corner;            /* of the square, on the plane */
    float half;             /* m: half the square's side */
} sun_plane;

/* The plane a sun's photons start on: perpendicular to its axis, R before
 * the scene's centre, a square of half side R plus the sideways drift of a
 * photon tilted by the sun's half angle over the 2R it crosses. */
static sun_plane plane_of(const light_table *t, const light *l)
{
    sun_plane p;
    p.f = frame_from_normal(l->direction);
    float tan_a = l->sun_cos_half < 1.0f ? safe_sqrtf(1.0f - l->sun_cos_half * l->sun_cos_half) / l->sun_cos_half
                                         : 0.0f;
    p.half = t->radius * (1.0f + 2.0f * tan_a);
    vec3 centre = v3_madd(t->center, l->direction, -t->radius);
    p.corner = v3_sub(centre, v3_add(v3_scale(p.f.t, p.half), v3_scale(p.f.b, p.half)));
    return p;
}

static int plane_cell_marked(const light_table *tab, const light *l, const sun_plane *p, const sphere *t, int nt,
                             uint32_t cell)
{
    float side = 2.0f * p->half / PLANE_CELLS;
    float x0 = (float)(cell % PLANE_CELLS) * side, y0 = (float)(cell / PLANE_CELLS) * side;
    float tan_a = l->sun_cos_half < 1.0f ? safe_sqrtf(1.0f - l->sun_cos_half * l->sun_cos_half) / l->sun_cos_half
                                         : 0.0f;
    for (int k = 0; k < nt; k++) {
        vec3 v = v3_sub(t[k].c, p->corner);
        float cx = v3_dot(v, p->f.t), cy = v3_dot(v, p->f.b), depth = v3_dot(v, p->f.n);
        float reach = t[k].r + fmaxf(depth + t[k].r, 0.0f) * tan_a + MARGIN * tab->radius;
        float dx = fmaxf(fmaxf(x0 - cx, cx - (x0 + side)), 0.0f), dy = fmaxf(fmaxf(y0 - cy, cy - (y0 + side)), 0.0f);
        if (dx * dx + dy * dy <= reach * reach)
            return 1;
    }
    return 0;
}

/* ---------------------------------------------------------------- build */

void projection_map_free(projection_map *pm)
{
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
        uint16_t *n = realloc(pm->cells, sizeof(uint16_t) * cap);
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
    pm->cells[g->first + g->count++] = (uint16_t)cell;
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

/* The sun's marked cells; returns the power sent into them (W). */
static float mark_sun(projection_map *pm, uint32_t *capacity, const light_table *tab, const light *l,
                      const sphere *t, int nt, int *ok)
{
    projection_group *pg = &pm->groups[pm->group_count];
    sun_plane p = plane_of(tab, l);
    for (uint32_t cell = 0; cell < PLANE_CELLS * PLANE_CELLS; cell++)
        if (plane_cell_marked(tab, l, &p, t, nt, cell) && !(*ok = append_cell(pm, capacity, cell)))
            return 0.0f;
    float side = 2.0f * p.half / PLANE_CELLS;
    return fmaxf(v3_average(l->color), 0.0f) * (float)pg->count * side * side; /* E·A_marked */
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
        c.omega = 2.0f * PHOS_PI * (1.0f - c.cos_max);
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
    if (l->kind == LIGHT_WORLD) {
        pg->all = 1;
        return g->power;
    }
    /* Each kind of group keeps its own list, in group order. */
    for (const projection_group *q = prev; q; q = q > pm->groups ? q - 1 : NULL)
        if (!q->all && q->sun == (l->kind == LIGHT_SUN)) {
            pg->first = q->first + q->count;
            break;
        }
    pg->sun = l->kind == LIGHT_SUN;
    if (pg->sun)
        return mark_sun(pm, cells_capacity, tab, l, t, nt, ok);
    return mark_cones(pm, cones_capacity, tab, g, t, nt, ok);
}

int projection_map_build(projection_map *pm, const scene *s)
{
    memset(pm, 0, sizeof(*pm));
    const light_table *tab = &s->lights;
    if (tab->group_count == 0)
        return 1;
    sphere *t;
    int nt = collect_targets(s, &t);
    if (nt < 0)
        return 0;
    pm->groups = calloc(tab->group_count, sizeof(projection_group));
    float *weight = malloc(sizeof(float) * tab->group_count);
    int ok = pm->groups && weight;
    uint32_t cells_capacity = 0, cones_capacity = 0;
    double sent = 0.0, total = 0.0;
    for (uint32_t g = 0; ok && g < tab->group_count; g++) {
        if (nt) {
            weight[g] = mark_group(pm, &cells_capacity, &cones_capacity, s, &tab->groups[g], t, nt, &ok);
        } else {
            weight[g] = tab->groups[g].power;
            pm->groups[g].all = 1;
        }
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

/* The power a sun group sends through its cells as weighted: E·Σ w·A. */
static float sun_weight(const light_table *tab, const projection_map *pm, uint32_t g)
{
    const light *l = &tab->lights[tab->groups[g].first];
    const projection_group *pg = &pm->groups[g];
    sun_plane p = plane_of(tab, l);
    float side = 2.0f * p.half / PLANE_CELLS;
    return fmaxf(v3_average(l->color), 0.0f) * side * side * pm->cell_cum[pg->first + pg->count - 1];
}

static int rebuild_pick(projection_map *pm, const scene *s)
{
    const light_table *tab = &s->lights;
    float *weight = malloc(sizeof(float) * tab->group_count);
    if (!weight)
        return 0;
    for (uint32_t g = 0; g < tab->group_count; g++) {
        const projection_group *pg = &pm->groups[g];
        weight[g] = pg->all || !pg->sun ? tab->groups[g].power : (pg->count ? sun_weight(tab, pm, g) : 0.0f);
    }
    distribution_free(&pm->pick);
    int ok = distribution_build(&pm->pick, weight, tab->group_count);
    free(weight);
    return ok;
}

int projection_map_build_suns(projection_map *pm, const scene *s)
{
    memset(pm, 0, sizeof(*pm));
    const light_table *tab = &s->lights;
    if (tab->group_count == 0)
        return 1;
    pm->groups = calloc(tab->group_count, sizeof(projection_group));
    if (!pm->groups)
        return 0;
    /* One target, the scene's bounding sphere: every cell a photon can
     * reach the scene from. */
    sphere scene_sphere = {tab->center, tab->radius};
    uint32_t capacity = 0, first = 0;
    int ok = 1;
    for (uint32_t g = 0; ok && g < tab->group_count; g++) {
        const light *l = &tab->lights[tab->groups[g].first];
        projection_group *pg = &pm->groups[g];
        pg->first = first;
        if (l->kind != LIGHT_SUN) {
            pg->all = 1;
        } else {
            pg->sun = 1;
            mark_sun(pm, &capacity, tab, l, &scene_sphere, 1, &ok);
            first += pg->count;
        }
        pm->group_count++;
    }
    if (ok)
        ok = rebuild_pick(pm, s);
    if (!ok)
        projection_map_free(pm);
    return ok;
}

/* Each cell takes the largest weight of its 3 × 3 neighbourhood: a cell
 * only partly over an opening, which the pilots may all have missed, lies
 * beside one they found, and keeps its full share. Otherwise its photons
 * that do pass would carry 1/PILOT_FLOOR times the power of the others and
 * blotch the map. */
int projection_map_set_weights(projection_map *pm, const scene *s, const float *weights)
{
    float *grid = malloc(sizeof(float) * PLANE_CELLS * PLANE_CELLS);
    if (!grid)
        return 0;
    for (uint32_t g = 0; g < pm->group_count; g++) {
        const projection_group *pg = &pm->groups[g];
        if (pg->all || !pg->sun)
            continue;
        memset(grid, 0, sizeof(float) * PLANE_CELLS * PLANE_CELLS);
        for (uint32_t k = 0; k < pg->count; k++)
            grid[pm->cells[pg->first + k]] = weights[pg->first + k];
        float cum = 0.0f;
        for (uint32_t k = 0; k < pg->count; k++) {
            int cx = pm->cells[pg->first + k] % PLANE_CELLS, cy = pm->cells[pg->first + k] / PLANE_CELLS;
            float w = 0.0f;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int x = cx + dx, y = cy + dy;
                    if (x >= 0 && y >= 0 && x < PLANE_CELLS && y < PLANE_CELLS)
                        w = fmaxf(w, grid[y * PLANE_CELLS + x]);
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

/* Origin on the sun's plane in `cell` and direction, from u and ud. */
static void sun_cell_ray(const light *l, const sun_plane *p, uint32_t cell, float2 u, float2 ud, vec3 *origin,
                         vec3 *direction)
{
    float side = 2.0f * p->half / PLANE_CELLS;
    float px = ((float)(cell % PLANE_CELLS) + u.x) * side, py = ((float)(cell / PLANE_CELLS) + u.y) * side;
    *origin = v3_add(p->corner, v3_add(v3_scale(p->f.t, px), v3_scale(p->f.b, py)));
    *direction = l->sun_cos_half < 1.0f ? warp_cone(l->direction, l->sun_cos_half, ud) : l->direction;
}

void projection_map_cell_ray(const scene *s, const projection_map *pm, uint32_t g, uint32_t k, float2 u, float2 ud,
                             vec3 *origin, vec3 *direction)
{
    const light *l = &s->lights.lights[s->lights.groups[g].first];
    sun_plane p = plane_of(&s->lights, l);
    sun_cell_ray(l, &p, pm->cells[pm->groups[g].first + k], u, ud, origin, direction);
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
    } else if (pg->count == 0) {
        return 0;
    } else if (l->kind == LIGHT_SUN) {
        sun_plane p = plane_of(tab, l);
        float side = 2.0f * p.half / PLANE_CELLS, share;
        float2 uc = {u[1], u[2]}, ud = {u[3], u[4]};
        uint32_t cell = pick_cell(pm, pg, &uc.x, &share);
        sun_cell_ray(l, &p, cell, uc, ud, origin, direction);
        float area = side * side / share; /* 1/p_A: the cell's area over its probability */
        if (l->sun_cos_half < 1.0f) {
            /* Through a plane across the axis, radiance L from direction d
             * brings L·cos θ per unit area and solid angle. */
            float omega = 2.0f * PHOS_PI * (1.0f - l->sun_cos_half);
            flux = v3_scale(l->sun_radiance, v3_dot(*direction, l->direction) * omega * area);
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
