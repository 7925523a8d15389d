/*
 * camera.c — camera rays. The add-on gives the frame on the image plane in
 * camera space (Blender's view_frame with sensor fit and shift applied),
 * so the camera model only interpolates it. Clipping follows Cycles: the
 * clip distances are depths along the view axis, not ray lengths.
 */
#include "scene/camera.h"

#include "sampling/warp.h"

camera_ray camera_generate_ray(const phos_camera_desc *c, float fx, float fy, float2 lens)
{
    float x = c->frame_min[0] + fx * (c->frame_max[0] - c->frame_min[0]);
    float y = c->frame_min[1] + fy * (c->frame_max[1] - c->frame_min[1]);
    /* Origin and direction in camera space; the direction need not be
     * unit, its depth along the view axis (−Z) is `depth`. */
    vec3 o_cam = v3s(0.0f), dir = v3(x, y, -1.0f);
    float depth = 1.0f;
    if (c->type == PHOS_CAMERA_ORTHOGRAPHIC) {
        o_cam = v3(x, y, 0.0f);
        dir = v3(0.0f, 0.0f, -1.0f);
    } else if (camera_has_lens(c)) {
        /* Thin lens: aim from a point on the aperture at the point of the
         * primary ray that lies on the focal plane. */
        vec3 focus = v3_scale(dir, c->focus_distance);
        float2 dk = warp_disk_concentric(lens);
        o_cam = v3(dk.x * c->aperture_radius, dk.y * c->aperture_radius, 0.0f);
        dir = v3_sub(focus, o_cam);
        depth = c->focus_distance;
    }
    camera_ray r;
    r.o = xform_point(c->transform, o_cam);
    /* The transform may scale: the world length of `dir` over its depth is
     * the ray length per unit of depth, which turns the clip depths into
     * distances along the unit direction. */
    vec3 d_world = xform_vector(c->transform, dir);
    float length = v3_length(d_world);
    r.d = v3_scale(d_world, 1.0f / length);
    float length_per_depth = length / depth;
    r.tmin = c->clip_start * length_per_depth;
    r.tmax = c->clip_end * length_per_depth;
    r.spread_origin = 0.0f;
    r.spread_per_distance = 0.0f;
    return r;
}

/* How far the unit world direction d0 (through the image-plane point
 * `through`, camera space) moves when that point moves by `step`. */
static float direction_change(const phos_camera_desc *c, vec3 d0, vec3 through, vec3 step)
{
    vec3 d1 = v3_normalize(xform_vector(c->transform, v3_add(through, step)));
    return v3_length(v3_sub(d1, d0));
}

void camera_ray_set_footprint(const phos_camera_desc *c, float fx, float fy, uint32_t width, uint32_t height,
                              camera_ray *r)
{
    float pixel_x = (c->frame_max[0] - c->frame_min[0]) / (float)(width ? width : 1);
    float pixel_y = (c->frame_max[1] - c->frame_min[1]) / (float)(height ? height : 1);
    if (c->type == PHOS_CAMERA_ORTHOGRAPHIC) {
        /* Cycles measures the orthographic footprint by a pixel's width
         * along x alone (kernel camera_sample_orthographic, 3.4 to 4.5). */
        r->spread_origin = v3_length(xform_vector(c->transform, v3(pixel_x, 0.0f, 0.0f)));
        r->spread_per_distance = 0.0f;
        return;
    }
    /* The change of the unit direction to the next pixel along x and along
     * y, averaged: the cone's half-angle rate (Cycles'
     * differential_make_compact). The ray's length is measured from the
     * camera's centre, so clipping needs no correction. */
    vec3 through = v3(c->frame_min[0] + fx * (c->frame_max[0] - c->frame_min[0]),
                      c->frame_min[1] + fy * (c->frame_max[1] - c->frame_min[1]), -1.0f);
    vec3 d0 = v3_normalize(xform_vector(c->transform, through));
    float dx = direction_change(c, d0, through, v3(pixel_x, 0.0f, 0.0f));
    float dy = direction_change(c, d0, through, v3(0.0f, pixel_y, 0.0f));
    r->spread_origin = 0.0f;
    r->spread_per_distance = 0.5f * (dx + dy);
}

int camera_project(const phos_camera_desc *c, vec3 p, float *fx, float *fy, vec3 *p_cam)
{
    const float *m = c->transform;
    /* Invert the affine camera transform: p_cam = A⁻¹ (p − t). */
    vec3 q = v3(p.x - m[3], p.y - m[7], p.z - m[11]);
    vec3 c0 = v3(m[0], m[4], m[8]), c1 = v3(m[1], m[5], m[9]), c2 = v3(m[2], m[6], m[10]);
    vec3 r0 = v3_cross(c1, c2), r1 = v3_cross(c2, c0), r2 = v3_cross(c0, c1);
    float det = v3_dot(c0, r0);
    vec3 pc = v3_scale(v3(v3_dot(r0, q), v3_dot(r1, q), v3_dot(r2, q)), 1.0f / det);
    *p_cam = pc;
    float x = pc.x, y = pc.y;
    if (c->type != PHOS_CAMERA_ORTHOGRAPHIC) {
        if (pc.z >= 0.0f)
            return 0;
        x = pc.x / -pc.z;
        y = pc.y / -pc.z;
    }
    *fx = (x - c->frame_min[0]) / (c->frame_max[0] - c->frame_min[0]);
    *fy = (y - c->frame_min[1]) / (c->frame_max[1] - c->frame_min[1]);
    return 1;
}

/* The transform's columns are the camera axes in world space (scaled, if
 * the camera object is): project on each, then normalise. Cycles' camera
 * space looks down +z, Blender's down −z. */
vec3 camera_direction_to_camera_space(const phos_camera_desc *c, vec3 d)
{
    const float *m = c->transform;
    vec3 x = v3_normalize(v3(m[0], m[4], m[8])), y = v3_normalize(v3(m[1], m[5], m[9]));
    vec3 back = v3_normalize(v3(m[2], m[6], m[10]));
    return v3_normalize(v3(v3_dot(d, x), v3_dot(d, y), -v3_dot(d, back)));
}
