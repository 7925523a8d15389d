/*
 * irradiance_record.h — one record of the irradiance cache, computed by a
 * stratified hemisphere of gather rays (irradiance_record.c).
 */
#ifndef PHOS_IRRADIANCE_RECORD_H
#define PHOS_IRRADIANCE_RECORD_H

#include "indirect/indirect_diffuse.h"
#include "indirect/irradiance_cache.h"

/* The record at the query's surface point from `rays` cosine-stratified
 * rays (M×N strata, hemisphere_strata), each bringing the radiance
 * `incoming` finds along it with the emitters its first segment reaches
 * left out (the light sample counts them). Its radius is clamped to
 * [R_lo, R_hi] (scene units). 0 when memory is exhausted. */
int irradiance_record_compute(const indirect_query *q, hemisphere_incoming incoming, uint32_t rays, float R_lo,
                              float R_hi, irradiance_record *out);

#endif /* PHOS_IRRADIANCE_RECORD_H */
