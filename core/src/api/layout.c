/*
 * layout.c — the layout of the public structs as this library was compiled:
 * each struct's size and each field's offset and size, so that a binding
 * (the add-on's, generated from phos.h) can refuse a library built from
 * another phos.h instead of corrupting memory (docs/architecture.md,
 * "Layout checks").
 */
#include <string.h>

#include "phos.h"

typedef struct layout_field {
    const char *struct_name, *field_name;
    uint32_t offset, size;
} layout_field;

#define FIELD(T, f) {#T, #f, (uint32_t)offsetof(T, f), (uint32_t)sizeof(((T *)0)->f)},
#define SETTING_FIELD(type, name, ...) FIELD(phos_render_settings, name)

/* Every field of every struct of phos.h, struct by struct in header order. */
static const layout_field fields[] = {
    FIELD(phos_image_desc, width) FIELD(phos_image_desc, height) FIELD(phos_image_desc, pixels)


    FIELD(phos_closure_desc, type) FIELD(phos_closure_desc, weight) 
    FIELD(phos_closure_desc, roughness) FIELD(phos_closure_desc, ior) FIELD(phos_closure_desc, specular_color)
    FIELD(phos_closure_desc, glass_fresnel) FIELD(phos_closure_desc, transmission_tint)
    FIELD(phos_closure_desc, transmission_roughness) FIELD(phos_closure_desc, microfacet)
    FIELD(phos_closure_desc, multiscatter_fresnel) FIELD(phos_closure_desc, specular_tint)
    FIELD(phos_closure_desc, thin_film_thickness) FIELD(phos_closure_desc, thin_film_ior)
    FIELD(phos_closure_desc, layer_span) FIELD(phos_closure_desc, layer_weight)
    FIELD(phos_closure_desc, layer_tint) FIELD(phos_closure_desc, layer_tint_weight)
    FIELD(phos_closure_desc, roughness_y) FIELD(phos_closure_desc, tangent_rotation)
    FIELD(phos_closure_desc, normal_correction)

    FIELD(phos_material_desc, closure_count) FIELD(phos_material_desc, closures) FIELD(phos_material_desc, program)

    FIELD(phos_shader_instruction, op) FIELD(phos_shader_instruction, mode) FIELD(phos_shader_instruction, flags)
    FIELD(phos_shader_instruction, table) FIELD(phos_shader_instruction, param)
    FIELD(phos_shader_instruction, inputs) FIELD(phos_shader_instruction, outputs)
    FIELD(phos_shader_binding, closure) FIELD(phos_shader_binding, field) FIELD(phos_shader_binding, reg)
    FIELD(phos_shader_program_desc, register_count) FIELD(phos_shader_program_desc, constant_count)
    FIELD(phos_shader_program_desc, constants) FIELD(phos_shader_program_desc, instruction_count)
    FIELD(phos_shader_program_desc, instructions) FIELD(phos_shader_program_desc, table_size)
    FIELD(phos_shader_program_desc, table) FIELD(phos_shader_program_desc, binding_count)
    FIELD(phos_shader_program_desc, bindings)

    FIELD(phos_mesh_attribute, id) FIELD(phos_mesh_attribute, type) FIELD(phos_mesh_attribute, values)
    FIELD(phos_mesh_desc, vertex_count) FIELD(phos_mesh_desc, positions) FIELD(phos_mesh_desc, triangle_count)
    FIELD(phos_mesh_desc, indices) FIELD(phos_mesh_desc, normals) FIELD(phos_mesh_desc, uvs)
    FIELD(phos_mesh_desc, material_slots) FIELD(phos_mesh_desc, tangents) FIELD(phos_mesh_desc, texspace_location)
    FIELD(phos_mesh_desc, texspace_size) FIELD(phos_mesh_desc, attribute_count) FIELD(phos_mesh_desc, attributes)

    FIELD(phos_instance_desc, mesh_id) FIELD(phos_instance_desc, transform)
    FIELD(phos_instance_desc, material_count) FIELD(phos_instance_desc, materials)
    FIELD(phos_instance_desc, random) FIELD(phos_instance_desc, pass_index)
    FIELD(phos_instances_desc, count) FIELD(phos_instances_desc, mesh_ids) FIELD(phos_instances_desc, transforms)
    FIELD(phos_instances_desc, material_offsets) FIELD(phos_instances_desc, materials)
    FIELD(phos_instances_desc, randoms) FIELD(phos_instances_desc, pass_indices)

    FIELD(phos_light_desc, type) FIELD(phos_light_desc, color) FIELD(phos_light_desc, position)
    FIELD(phos_light_desc, direction) FIELD(phos_light_desc, axis_u) FIELD(phos_light_desc, axis_v)
    FIELD(phos_light_desc, area_shape) FIELD(phos_light_desc, radius) FIELD(phos_light_desc, point_shape)
    FIELD(phos_light_desc, spot_angle) FIELD(phos_light_desc, spot_blend) FIELD(phos_light_desc, spot_cosine)
    FIELD(phos_light_desc, sun_angle) FIELD(phos_light_desc, camera_visible)

    FIELD(phos_sky_desc, model) FIELD(phos_sky_desc, layout) FIELD(phos_sky_desc, sun_elevation) FIELD(phos_sky_desc, sun_rotation)
    FIELD(phos_sky_desc, sun_size) FIELD(phos_sky_desc, sun_intensity) FIELD(phos_sky_desc, sun_disc)
    FIELD(phos_sky_desc, altitude) FIELD(phos_sky_desc, air_density) FIELD(phos_sky_desc, aerosol_density)
    FIELD(phos_sky_desc, ozone_density) FIELD(phos_sky_desc, turbidity)
    FIELD(phos_sky_desc, ground_albedo) FIELD(phos_sky_desc, sun_direction)

    FIELD(phos_world_desc, color)
    FIELD(phos_world_desc, material)

    FIELD(phos_camera_desc, type) FIELD(phos_camera_desc, transform) FIELD(phos_camera_desc, frame_min)
    FIELD(phos_camera_desc, frame_max) FIELD(phos_camera_desc, aperture_radius)
    FIELD(phos_camera_desc, focus_distance) FIELD(phos_camera_desc, clip_start) FIELD(phos_camera_desc, clip_end)

    PHOS_RENDER_SETTINGS(SETTING_FIELD, SETTING_FIELD)

    FIELD(phos_stage_info, id) FIELD(phos_stage_info, name)

    FIELD(phos_progress, state) FIELD(phos_progress, fraction) FIELD(phos_progress, tiles_done)
    FIELD(phos_progress, tiles_total) FIELD(phos_progress, samples) FIELD(phos_progress, samples_done) FIELD(phos_progress, stage)
    FIELD(phos_progress, stage_id) FIELD(phos_progress, stage_index) FIELD(phos_progress, photons_stored)
    FIELD(phos_progress, photons_emitted) FIELD(phos_progress, global_photons)
    FIELD(phos_progress, caustic_photons) FIELD(phos_progress, photon_map) FIELD(phos_progress, photon_maps_short)
    FIELD(phos_progress, stage_seconds)
    FIELD(phos_progress, rays_traced) FIELD(phos_progress, cache_records)
    FIELD(phos_progress, cache_rays_traced) FIELD(phos_progress, cache_lookups)
    FIELD(phos_progress, cache_interpolated) FIELD(phos_progress, gather_rays)

    FIELD(phos_tile, x) FIELD(phos_tile, y) FIELD(phos_tile, width) FIELD(phos_tile, height)
};

static const struct {
    const char *name;
    uint32_t size;
} structs[] = {
    {"phos_image_desc", sizeof(phos_image_desc)},
    {"phos_closure_desc", sizeof(phos_closure_desc)},
    {"phos_material_desc", sizeof(phos_material_desc)},
    {"phos_shader_instruction", sizeof(phos_shader_instruction)},
    {"phos_shader_binding", sizeof(phos_shader_binding)},
    {"phos_shader_program_desc", sizeof(phos_shader_program_desc)},
    {"phos_mesh_attribute", sizeof(phos_mesh_attribute)},
    {"phos_mesh_desc", sizeof(phos_mesh_desc)},
    {"phos_instance_desc", sizeof(phos_instance_desc)},
    {"phos_instances_desc", sizeof(phos_instances_desc)},
    {"phos_light_desc", sizeof(phos_light_desc)},
    {"phos_sky_desc", sizeof(phos_sky_desc)},
    {"phos_world_desc", sizeof(phos_world_desc)},
    {"phos_camera_desc", sizeof(phos_camera_desc)},
    {"phos_render_settings", sizeof(phos_render_settings)},
    {"phos_stage_info", sizeof(phos_stage_info)},
    {"phos_progress", sizeof(phos_progress)},
    {"phos_tile", sizeof(phos_tile)},
};

uint32_t phos_struct_size(const char *name)
{
    if (!name)
        return 0;
    for (size_t i = 0; i < sizeof(structs) / sizeof(structs[0]); i++)
        if (strcmp(structs[i].name, name) == 0)
            return structs[i].size;
    return 0;
}

phos_status phos_struct_field(const char *struct_name, const char *field_name, uint32_t *out_offset,
                              uint32_t *out_size)
{
    if (!struct_name || !field_name)
        return PHOS_ERROR_INVALID_ARGUMENT;
    for (size_t i = 0; i < sizeof(fields) / sizeof(fields[0]); i++) {
        const layout_field *f = &fields[i];
        if (strcmp(f->struct_name, struct_name) == 0 && strcmp(f->field_name, field_name) == 0) {
            if (out_offset)
                *out_offset = f->offset;
            if (out_size)
                *out_size = f->size;
            return PHOS_OK;
        }
    }
    return PHOS_ERROR_INVALID_ARGUMENT;
}
