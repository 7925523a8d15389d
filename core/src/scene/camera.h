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
} camera_ray;

/* Ray through film position (fx, fy) in [0,1]² of the full frame (0,0 =
 * bottom-left corner), lens sample in [0,1)². */
camera_ray camera_generate_ray(const phos_camera_desc *c, float fx, float fy, float2 lens);

/* Where a world point lies on the camera's full frame: (fx, fy) in [0,1]²
 * (0,0 = bottom-left, as camera_generate_ray takes them) and the point in
 * camera space. Returns 0 for a point behind a perspective camera. */
int camera_project(const phos_camera_desc *c, vec3 p, float *fx, float *fy, vec3 *p_cam);

/* A world direction in Cycles' camera space (x right, y up, z along the
 * view), unit length: what the Denoising Normal pass holds, as in Cycles. */
vec3 camera_direction_to_camera_space(const phos_camera_desc *c, vec3 d);

#endif /* PHOS_CAMERA_H */
