/*
 * camera.h — primary rays for Blender's perspective and orthographic
 * cameras, with a thin-lens aperture for depth of field.
 */
#ifndef PHOS_CAMERA_H
#define PHOS_CAMERA_H

#include "phos.h"
#include "sampling/sampler.h"
#include "util/vec.h"

typedef struct camera_ray {
    vec3 o, d;               /* world origin, unit direction */
    float tmin, tmax;        /* clipping along d */
    /* The pixel's footprint as a cone (Cycles' compact ray differentials,
     * after Igehy 1999, "Tracing Ray Differentials"): its radius at the
     * origin (scene units) and its growth per unit of distance along d.
     * Both 0 when the ray stands for no pixel. */
    float spread_origin, spread_per_distance;
} camera_ray;

/* Ray through film position (fx, fy) in [0,1]² of the full frame (0,0 =
 * bottom-left corner), lens sample in [0,1)². */
camera_ray camera_generate_ray(const phos_camera_desc *c, float fx, float fy, float2 lens);

/* Whether camera_generate_ray reads its lens sample: a perspective camera
 * with an aperture. Without one, a render draws no lens dimensions. */
static inline int camera_has_lens(const phos_camera_desc *c)
{
    return c->type != PHOS_CAMERA_ORTHOGRAPHIC && c->aperture_radius > 0.0f;
}

/* Sets the ray's footprint for a film of width × height pixels, as Cycles
 * does for its camera rays: a perspective ray starts as a point and
 * spreads by the angle between neighbouring pixels' directions; an
 * orthographic one keeps a pixel's width. Depth of field is left out of it,
 * as in Cycles. */
void camera_ray_set_footprint(const phos_camera_desc *c, float fx, float fy, uint32_t width, uint32_t height,
                              camera_ray *r);

/* Where a world point lies on the camera's full frame: (fx, fy) in [0,1]²
 * (0,0 = bottom-left, as camera_generate_ray takes them) and the point in
 * camera space. Returns 0 for a point behind a perspective camera. */
int camera_project(const phos_camera_desc *c, vec3 p, float *fx, float *fy, vec3 *p_cam);

/* A world direction in Cycles' camera space (x right, y up, z along the
 * view), unit length: what the Denoising Normal pass holds, as in Cycles. */
vec3 camera_direction_to_camera_space(const phos_camera_desc *c, vec3 d);

#endif /* PHOS_CAMERA_H */
