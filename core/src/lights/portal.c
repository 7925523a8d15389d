/*
 * portal.c — Cycles' light portals: area-shaped openings (a window, a
 * door) marked by the artist, through which the world's light reaches an
 * interior. They emit nothing and block nothing; they only guide where the
 * world's light samples go. From a point on the inner side of a portal
 * (the side its direction points to) a sample of the world is drawn, with
 * probability ½, toward a uniform point of a portal picked uniformly, and
 * otherwise by the world's own sampling; its pdf is the mixture's
 *
 *   p(ω) = ½ · (1/n) Σ_k [ω crosses portal k] d_k² / (A_k |cos θ_k|)
 *        + ½ · p_own(ω),
 *
 * one-sample MIS of the two strategies (Veach 1997, §9.2.4), so every
 * direction the world's own sampling reaches is still reached and the
 * estimate stays unbiased whatever the portals cover. Elsewhere (outside,
 * or no portals) the world samples as it would without them.
 */
#include "lights/light_kind.h"

float portal_share(const light_table *t, const light_context *c)
{
    for (uint32_t k = 0; k < t->portal_count; k++) {
        const light *p = &t->portals[k];
        if (v3_dot(v3_sub(c->p, p->position), p->direction) > 0.0f)
            return 0.5f;
    }
    return 0.0f;
}

/* (1/n) Σ_k of the portals that the ray from c along wi crosses, of the
 * solid-angle pdf of drawing it through that portal. */
static float portals_pdf(const light_table *t, const light_context *c, vec3 wi)
{
    float sum = 0.0f;
    for (uint32_t k = 0; k < t->portal_count; k++) {
        float hit_t, pdf;
        /* A ray leaving through the portal crosses it against its direction. */
        if (light_area_crossing(&t->portals[k], c->p, wi, INFINITY, &hit_t, &pdf))
            sum += pdf;
    }
    return sum / (float)t->portal_count;
}

static int sample_portals(const light_table *t, const light_context *c, float2 u, vec3 *wi)
{
    uint32_t k = (uint32_t)(u.x * (float)t->portal_count);
    k = k < t->portal_count ? k : t->portal_count - 1;
    u.x = u.x * (float)t->portal_count - (float)k;
    float d, d2;
    const light *p = &t->portals[k];
    if (!light_direction_to(c->p, light_area_point(p, u), wi, &d, &d2))
        return 0;
    return v3_dot(*wi, p->direction) < 0.0f; /* out through the portal, from its inner side */
}

int portal_mix_sample(const scene *s, const light_context *c, const world_sampling *own, float2 u, vec3 *wi,
                      float *pdf)
{
    const light_table *t = &s->lights;
    float share = c ? portal_share(t, c) : 0.0f;
    if (share > 0.0f && u.x < share) {
        u.x = minf(u.x / share, 0x1.fffffep-1f);
        if (!sample_portals(t, c, u, wi))
            return 0;
    } else {
        u.x = share > 0.0f ? minf((u.x - share) / (1.0f - share), 0x1.fffffep-1f) : u.x;
        float own_pdf;
        *wi = own->sample(s, c, u, &own_pdf);
        if (!(own_pdf > 0.0f))
            return 0;
    }
    *pdf = portal_mix_pdf(s, c, own, *wi);
    return *pdf > 0.0f;
}

float portal_mix_pdf(const scene *s, const light_context *c, const world_sampling *own, vec3 wi)
{
    const light_table *t = &s->lights;
    float share = c ? portal_share(t, c) : 0.0f;
    float own_pdf = own->pdf(s, c, wi);
    return share > 0.0f ? share * portals_pdf(t, c, wi) + (1.0f - share) * own_pdf : own_pdf;
}
