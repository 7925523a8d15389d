/*
 * material.h — from a ray hit to what the integrators need: the surface
 * geometry (position, normals, texture coordinates) and the material's
 * BSDF, emission and transparency there.
 */
#ifndef PHOS_MATERIAL_H
#define PHOS_MATERIAL_H

#include "shading/bsdf.h"
#include "scene/scene.h"

typedef struct surface {
    vec3 p;                 /* world position */
    vec3 ng;                /* geometric normal, facing the ray origin */
    vec3 ns;                /* shading normal, facing the ray origin */
    vec3 wo;                /* toward the ray origin */
    float u, v;             /* texture coordinates */
    float b1, b2;           /* barycentrics of the hit in the triangle */
    int backfacing;         /* the ray arrived from behind the triangle's winding normal */
    uint32_t ray_flags;     /* enum shader_ray_flags of the ray (Light Path node); 0 unless the caller sets it */
    float ray_length;       /* scene units from the ray origin */
    uint32_t ray_depth;
    float footprint;        /* radius (scene units) of the camera pixel's footprint here, carried along
                               the path (Cycles' sd->dP); 0 where no pixel's ray found the point */
    /* Scattering events before the ray by kind, as Cycles counts them
     * (path_state_next): diffuse and glossy (also sharp) reflections,
     * transmissions (refraction, translucency), transparent pass-throughs
     * (which ray_depth does not count). 0 unless the caller sets them. */
    uint32_t diffuse_depth, glossy_depth, transmission_depth, transparent_depth;
    uint32_t instance, prim;
    const material *mat;
} surface;

/* Fills the surface at barycentrics (b1, b2) of a triangle hit by a ray of
 * direction d (unit). */
void surface_from_hit(const scene *s, uint32_t instance, uint32_t prim, float b1, float b2, vec3 d,
                      surface *out);

/* Gives a material its shader program (api.c, after validation): folds
 * it, writes the bindings that became constant into the closures, and
 * keeps the program only if something still varies over the surface. */
void material_set_program(const scene *s, material *m, shader_program *p);

/* The BSDF at the surface, textures applied; wo = −d. */
void material_bsdf(const scene *s, const surface *sf, bsdf *out);

/* Emitted radiance W/(m²·sr) (both faces emit, as in Cycles). */
vec3 material_emission(const scene *s, const surface *sf);
vec3 material_emission_at(const scene *s, uint32_t instance, uint32_t prim, float b1, float b2);

/* The radiance W/(m²·sr) a world material sends back along a ray of unit
 * direction d that left the scene (its EMISSION closures, the program run
 * as Cycles runs a background shader), for a ray of kind ray_flags (enum
 * shader_ray_flags: the Light Path node). Never negative or NaN. */
vec3 material_background(const scene *s, const material *m, vec3 d, uint32_t ray_flags);

/* Mean emitted radiance of a material, for light power estimates. */
vec3 material_emission_estimate(const scene *s, const material *m);
/* The same for one triangle of an instance, where a program may vary it. */
vec3 material_emission_estimate_triangle(const scene *s, uint32_t instance, uint32_t prim);

/* What a shader program reads at the surface; needs: enum shader_needs,
 * the costlier parts to fill. */
void material_shader_globals(const scene *s, const surface *sf, uint32_t needs, shader_globals *g);

/* Whether some closure of the material can scatter into a delta lobe
 * (sharp mirror or glass, index-matched refraction), or glossily with a
 * roughness below max_roughness (bsdf.h, closure_scatters_caustic): only
 * such a surface can start a caustic path (L S+ D). Transparent
 * pass-through is not a scattering event and does not count. */
int material_can_scatter_caustic(const material *m, float max_roughness);

/* Whether any material of the scene can (the caustic map can fill). */
int scene_can_scatter_caustic(const scene *s, float max_roughness);

/* How much light passes straight through (transparent closures). */
vec3 material_transparency(const scene *s, const surface *sf);

/* The sum of the holdout closures' weights (0 without any): how much of
 * the surface cuts a hole in the film where a camera ray meets it. */
vec3 material_holdout(const scene *s, const surface *sf);

#endif /* PHOS_MATERIAL_H */
