/*
 * lamp_shape.h — the shape point and spot lamps share, implemented once in
 * point.c: a delta light of intensity I (radius 0), or of radius r a disk
 * facing the receiver (Cycles < 4.0) or a sphere (Cycles 4.0+), either of
 * radiance I/(πr²) so that it has intensity I seen from afar.
 *
 * A lamp's beam is shaped by an attenuation a(ω) of the direction ω from
 * the lamp (unit vector): 1 for a point lamp (lamp_unattenuated), the
 * spot's cone for a spot (light_spot_attenuation, spot.c).
 */
#ifndef PHOS_LAMP_SHAPE_H
#define PHOS_LAMP_SHAPE_H

#include "lights/light.h"

typedef float (*lamp_attenuation)(const light *l, vec3 dir_from_light);

float lamp_unattenuated(const light *l, vec3 dir_from_light);

/* Rays can hit a lamp of nonzero radius. */
int lamp_hittable(const light *l);

/* A direction from p toward the lamp (light_kind_ops.sample). */
int lamp_sample(const light *l, vec3 p, float2 u, lamp_attenuation attenuation, light_sample *out);

/* The lamp's disk or sphere along a ray (light_kind_ops.intersect). */
int lamp_intersect(const light *l, vec3 o, vec3 d, float tmax, lamp_attenuation attenuation, light_hit *out);

/* Origin and intensity I·a(d) (W/sr) of a photon leaving along d
 * (light_kind_ops.emit_toward). */
int lamp_emit_toward(const light *l, vec3 d, lamp_attenuation attenuation, vec3 *origin, vec3 *intensity);

#endif /* PHOS_LAMP_SHAPE_H */
