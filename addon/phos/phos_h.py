# SPDX-License-Identifier: GPL-3.0-or-later
# Generated from core/include/phos.h by tools/gen_binding.py: do not edit. Change phos.h,
# then run `make binding` (`make test` fails while this file is stale).
"""The constants, enums, structs, function signatures and render settings
of phos.h, for core.py: see core/include/phos.h for what each one means.
"""

import collections
import ctypes

# #define
PHOS_VERSION_MAJOR = 0
PHOS_VERSION_MINOR = 2
PHOS_VERSION_PATCH = 0
PHOS_VERSION = 512
PHOS_MAX_CLOSURES = 16

# enum phos_status
PHOS_OK = 0
PHOS_ERROR_INVALID_ARGUMENT = 1
PHOS_ERROR_INVALID_STATE = 2
PHOS_ERROR_OUT_OF_MEMORY = 3
PHOS_ERROR_EMBREE = 4
PHOS_ERROR_CANCELLED = 5
PHOS_ERROR_TIMEOUT = 6
PHOS_ERROR_INTERNAL = 7

# enum phos_image_interpolation
PHOS_INTERP_LINEAR = 0
PHOS_INTERP_CLOSEST = 1

# enum phos_image_extension
PHOS_EXTEND_REPEAT = 0
PHOS_EXTEND_EXTEND = 1
PHOS_EXTEND_CLIP = 2

# enum phos_closure_type
PHOS_CLOSURE_DIFFUSE = 0
PHOS_CLOSURE_PRINCIPLED_DIFFUSE = 1
PHOS_CLOSURE_REFLECTION = 2
PHOS_CLOSURE_REFLECTION_FRESNEL = 3
PHOS_CLOSURE_REFRACTION = 4
PHOS_CLOSURE_GLASS = 5
PHOS_CLOSURE_TRANSPARENT = 6
PHOS_CLOSURE_EMISSION = 7
PHOS_CLOSURE_METAL = 8
PHOS_CLOSURE_OREN_NAYAR = 9
PHOS_CLOSURE_SHEEN = 10
PHOS_CLOSURE_TYPE_COUNT = 11

# enum phos_glass_fresnel
PHOS_GLASS_FRESNEL_MACRO = 0
PHOS_GLASS_FRESNEL_MICROFACET = 1

# enum phos_microfacet
PHOS_MICROFACET_GGX_SEPARABLE = 0
PHOS_MICROFACET_GGX = 1
PHOS_MICROFACET_GGX_MULTISCATTER = 2

# enum phos_light_type
PHOS_LIGHT_POINT = 0
PHOS_LIGHT_SPOT = 1
PHOS_LIGHT_AREA = 2
PHOS_LIGHT_SUN = 3

# enum phos_area_shape
PHOS_AREA_RECTANGLE = 0
PHOS_AREA_ELLIPSE = 1

# enum phos_point_shape
PHOS_POINT_DISK = 0
PHOS_POINT_SPHERE = 1

# enum phos_camera_type
PHOS_CAMERA_PERSPECTIVE = 0
PHOS_CAMERA_ORTHOGRAPHIC = 1

# enum phos_integrator
PHOS_INTEGRATOR_PATH = 0
PHOS_INTEGRATOR_PHOTON = 1

# enum phos_irradiance_cache
PHOS_IRRADIANCE_CACHE_OFF = 0
PHOS_IRRADIANCE_CACHE_PHOTON = 1
PHOS_IRRADIANCE_CACHE_ALWAYS = 2

# enum phos_photon_view
PHOS_PHOTON_VIEW_FINAL_GATHER = 0
PHOS_PHOTON_VIEW_FAST = 1
PHOS_PHOTON_VIEW_PATH_TRACED = 2

# enum phos_pass_group
PHOS_PASS_GROUP_COMBINED = 0
PHOS_PASS_GROUP_LIGHT = 1
PHOS_PASS_GROUP_DENOISING = 2
PHOS_PASS_GROUP_PHOTONS = 3
PHOS_PASS_GROUP_CACHE = 4

# enum phos_pass_kind
PHOS_PASS_KIND_COLOR = 0
PHOS_PASS_KIND_VECTOR = 1

# enum phos_pass
PHOS_PASS_COMBINED = 0
PHOS_PASS_EMISSION = 1
PHOS_PASS_DIRECT = 2
PHOS_PASS_SPECULAR = 3
PHOS_PASS_CAUSTICS = 4
PHOS_PASS_INDIRECT = 5
PHOS_PASS_PHOTON_MAP = 6
PHOS_PASS_CAUSTIC_MAP = 7
PHOS_PASS_PHOTONS = 8
PHOS_PASS_IRRADIANCE_CACHE = 9
PHOS_PASS_DENOISING_ALBEDO = 10
PHOS_PASS_DENOISING_NORMAL = 11
PHOS_PASS_COUNT = 12

# enum phos_cache_kind
PHOS_CACHE_IRRADIANCE = 0
PHOS_CACHE_PHOTON_MAPS = 1
PHOS_CACHE_KIND_COUNT = 2

# enum phos_cache_file_mode
PHOS_CACHE_FILE_NONE = 0
PHOS_CACHE_FILE_SAVE = 1
PHOS_CACHE_FILE_LOAD = 2

# enum phos_render_state
PHOS_STATE_IDLE = 0
PHOS_STATE_RUNNING = 1
PHOS_STATE_DONE = 2
PHOS_STATE_CANCELLED = 3
PHOS_STATE_FAILED = 4

# enum phos_stage
PHOS_STAGE_WAITING = 0
PHOS_STAGE_TRACING_PHOTONS = 1
PHOS_STAGE_BUILDING_KDTREES = 2
PHOS_STAGE_PRECOMPUTING_RADIANCE = 3
PHOS_STAGE_FILLING_IRRADIANCE_CACHE = 4
PHOS_STAGE_RENDERING = 5
PHOS_STAGE_FINISHED = 6
PHOS_STAGE_COUNT = 7

# enum phos_photon_map
PHOS_MAP_GLOBAL = 0
PHOS_MAP_CAUSTIC = 1

ENUMS = {
    'phos_status': {'PHOS_OK': 0, 'PHOS_ERROR_INVALID_ARGUMENT': 1, 'PHOS_ERROR_INVALID_STATE': 2, 'PHOS_ERROR_OUT_OF_MEMORY': 3, 'PHOS_ERROR_EMBREE': 4, 'PHOS_ERROR_CANCELLED': 5, 'PHOS_ERROR_TIMEOUT': 6, 'PHOS_ERROR_INTERNAL': 7},
    'phos_image_interpolation': {'PHOS_INTERP_LINEAR': 0, 'PHOS_INTERP_CLOSEST': 1},
    'phos_image_extension': {'PHOS_EXTEND_REPEAT': 0, 'PHOS_EXTEND_EXTEND': 1, 'PHOS_EXTEND_CLIP': 2},
    'phos_closure_type': {'PHOS_CLOSURE_DIFFUSE': 0, 'PHOS_CLOSURE_PRINCIPLED_DIFFUSE': 1, 'PHOS_CLOSURE_REFLECTION': 2, 'PHOS_CLOSURE_REFLECTION_FRESNEL': 3, 'PHOS_CLOSURE_REFRACTION': 4, 'PHOS_CLOSURE_GLASS': 5, 'PHOS_CLOSURE_TRANSPARENT': 6, 'PHOS_CLOSURE_EMISSION': 7, 'PHOS_CLOSURE_METAL': 8, 'PHOS_CLOSURE_OREN_NAYAR': 9, 'PHOS_CLOSURE_SHEEN': 10, 'PHOS_CLOSURE_TYPE_COUNT': 11},
    'phos_glass_fresnel': {'PHOS_GLASS_FRESNEL_MACRO': 0, 'PHOS_GLASS_FRESNEL_MICROFACET': 1},
    'phos_microfacet': {'PHOS_MICROFACET_GGX_SEPARABLE': 0, 'PHOS_MICROFACET_GGX': 1, 'PHOS_MICROFACET_GGX_MULTISCATTER': 2},
    'phos_light_type': {'PHOS_LIGHT_POINT': 0, 'PHOS_LIGHT_SPOT': 1, 'PHOS_LIGHT_AREA': 2, 'PHOS_LIGHT_SUN': 3},
    'phos_area_shape': {'PHOS_AREA_RECTANGLE': 0, 'PHOS_AREA_ELLIPSE': 1},
    'phos_point_shape': {'PHOS_POINT_DISK': 0, 'PHOS_POINT_SPHERE': 1},
    'phos_camera_type': {'PHOS_CAMERA_PERSPECTIVE': 0, 'PHOS_CAMERA_ORTHOGRAPHIC': 1},
    'phos_integrator': {'PHOS_INTEGRATOR_PATH': 0, 'PHOS_INTEGRATOR_PHOTON': 1},
    'phos_irradiance_cache': {'PHOS_IRRADIANCE_CACHE_OFF': 0, 'PHOS_IRRADIANCE_CACHE_PHOTON': 1, 'PHOS_IRRADIANCE_CACHE_ALWAYS': 2},
    'phos_photon_view': {'PHOS_PHOTON_VIEW_FINAL_GATHER': 0, 'PHOS_PHOTON_VIEW_FAST': 1, 'PHOS_PHOTON_VIEW_PATH_TRACED': 2},
    'phos_pass_group': {'PHOS_PASS_GROUP_COMBINED': 0, 'PHOS_PASS_GROUP_LIGHT': 1, 'PHOS_PASS_GROUP_DENOISING': 2, 'PHOS_PASS_GROUP_PHOTONS': 3, 'PHOS_PASS_GROUP_CACHE': 4},
    'phos_pass_kind': {'PHOS_PASS_KIND_COLOR': 0, 'PHOS_PASS_KIND_VECTOR': 1},
    'phos_pass': {'PHOS_PASS_COMBINED': 0, 'PHOS_PASS_EMISSION': 1, 'PHOS_PASS_DIRECT': 2, 'PHOS_PASS_SPECULAR': 3, 'PHOS_PASS_CAUSTICS': 4, 'PHOS_PASS_INDIRECT': 5, 'PHOS_PASS_PHOTON_MAP': 6, 'PHOS_PASS_CAUSTIC_MAP': 7, 'PHOS_PASS_PHOTONS': 8, 'PHOS_PASS_IRRADIANCE_CACHE': 9, 'PHOS_PASS_DENOISING_ALBEDO': 10, 'PHOS_PASS_DENOISING_NORMAL': 11, 'PHOS_PASS_COUNT': 12},
    'phos_cache_kind': {'PHOS_CACHE_IRRADIANCE': 0, 'PHOS_CACHE_PHOTON_MAPS': 1, 'PHOS_CACHE_KIND_COUNT': 2},
    'phos_cache_file_mode': {'PHOS_CACHE_FILE_NONE': 0, 'PHOS_CACHE_FILE_SAVE': 1, 'PHOS_CACHE_FILE_LOAD': 2},
    'phos_render_state': {'PHOS_STATE_IDLE': 0, 'PHOS_STATE_RUNNING': 1, 'PHOS_STATE_DONE': 2, 'PHOS_STATE_CANCELLED': 3, 'PHOS_STATE_FAILED': 4},
    'phos_stage': {'PHOS_STAGE_WAITING': 0, 'PHOS_STAGE_TRACING_PHOTONS': 1, 'PHOS_STAGE_BUILDING_KDTREES': 2, 'PHOS_STAGE_PRECOMPUTING_RADIANCE': 3, 'PHOS_STAGE_FILLING_IRRADIANCE_CACHE': 4, 'PHOS_STAGE_RENDERING': 5, 'PHOS_STAGE_FINISHED': 6, 'PHOS_STAGE_COUNT': 7},
    'phos_photon_map': {'PHOS_MAP_GLOBAL': 0, 'PHOS_MAP_CAUSTIC': 1},
}

# Opaque handles, passed as c_void_p.
HANDLES = ('phos_scene', 'phos_render')


class phos_image_desc(ctypes.Structure):
    _fields_ = [
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
        ("pixels", ctypes.POINTER(ctypes.c_float)),
        ("interpolation", ctypes.c_uint32),
        ("extension", ctypes.c_uint32),
    ]


class phos_closure_desc(ctypes.Structure):
    _fields_ = [
        ("type", ctypes.c_uint32),
        ("weight", ctypes.c_float * 3),
        ("weight_image", ctypes.c_int32),
        ("roughness", ctypes.c_float),
        ("ior", ctypes.c_float),
        ("specular_color", ctypes.c_float * 3),
        ("glass_fresnel", ctypes.c_uint32),
        ("transmission_tint", ctypes.c_float * 3),
        ("transmission_roughness", ctypes.c_float),
        ("microfacet", ctypes.c_uint32),
        ("multiscatter_fresnel", ctypes.c_float * 3),
        ("specular_tint", ctypes.c_float * 3),
        ("thin_film_thickness", ctypes.c_float),
        ("thin_film_ior", ctypes.c_float),
        ("layer_span", ctypes.c_uint32),
        ("layer_weight", ctypes.c_float * 3),
        ("layer_tint", ctypes.c_float * 3),
        ("layer_tint_weight", ctypes.c_float),
    ]


class phos_material_desc(ctypes.Structure):
    _fields_ = [
        ("closure_count", ctypes.c_uint32),
        ("closures", ctypes.POINTER(phos_closure_desc)),
    ]


class phos_mesh_desc(ctypes.Structure):
    _fields_ = [
        ("vertex_count", ctypes.c_uint32),
        ("positions", ctypes.POINTER(ctypes.c_float)),
        ("triangle_count", ctypes.c_uint32),
        ("indices", ctypes.POINTER(ctypes.c_uint32)),
        ("normals", ctypes.POINTER(ctypes.c_float)),
        ("uvs", ctypes.POINTER(ctypes.c_float)),
        ("material_slots", ctypes.POINTER(ctypes.c_uint32)),
    ]


class phos_instance_desc(ctypes.Structure):
    _fields_ = [
        ("mesh_id", ctypes.c_uint32),
        ("transform", ctypes.c_float * 12),
        ("material_count", ctypes.c_uint32),
        ("materials", ctypes.POINTER(ctypes.c_uint32)),
    ]


class phos_light_desc(ctypes.Structure):
    _fields_ = [
        ("type", ctypes.c_uint32),
        ("color", ctypes.c_float * 3),
        ("position", ctypes.c_float * 3),
        ("direction", ctypes.c_float * 3),
        ("axis_u", ctypes.c_float * 3),
        ("axis_v", ctypes.c_float * 3),
        ("area_shape", ctypes.c_uint32),
        ("radius", ctypes.c_float),
        ("point_shape", ctypes.c_uint32),
        ("spot_angle", ctypes.c_float),
        ("spot_blend", ctypes.c_float),
        ("spot_cosine", ctypes.c_uint32),
        ("sun_angle", ctypes.c_float),
        ("camera_visible", ctypes.c_uint32),
    ]


class phos_world_desc(ctypes.Structure):
    _fields_ = [
        ("color", ctypes.c_float * 3),
    ]


class phos_camera_desc(ctypes.Structure):
    _fields_ = [
        ("type", ctypes.c_uint32),
        ("transform", ctypes.c_float * 12),
        ("frame_min", ctypes.c_float * 2),
        ("frame_max", ctypes.c_float * 2),
        ("aperture_radius", ctypes.c_float),
        ("focus_distance", ctypes.c_float),
        ("clip_start", ctypes.c_float),
        ("clip_end", ctypes.c_float),
    ]


class phos_render_settings(ctypes.Structure):
    _fields_ = [
        ("integrator", ctypes.c_uint32),
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
        ("region_x", ctypes.c_uint32),
        ("region_y", ctypes.c_uint32),
        ("region_width", ctypes.c_uint32),
        ("region_height", ctypes.c_uint32),
        ("samples", ctypes.c_uint32),
        ("seed", ctypes.c_uint32),
        ("max_bounces", ctypes.c_uint32),
        ("threads", ctypes.c_uint32),
        ("tile_size", ctypes.c_uint32),
        ("filter_width", ctypes.c_float),
        ("transparent_background", ctypes.c_uint32),
        ("pass_mask", ctypes.c_uint32),
        ("global_photons", ctypes.c_uint32),
        ("caustic_photons", ctypes.c_uint32),
        ("global_estimate_photons", ctypes.c_uint32),
        ("caustic_estimate_photons", ctypes.c_uint32),
        ("max_radius", ctypes.c_float),
        ("final_gather_rays", ctypes.c_uint32),
        ("photon_view", ctypes.c_uint32),
        ("max_photons_emitted_millions", ctypes.c_uint32),
        ("irradiance_cache", ctypes.c_uint32),
        ("ic_accuracy", ctypes.c_float),
        ("ic_rays", ctypes.c_uint32),
        ("ic_min_spacing", ctypes.c_float),
        ("ic_max_spacing", ctypes.c_float),
    ]


class phos_stage_info(ctypes.Structure):
    _fields_ = [
        ("id", ctypes.c_uint32),
        ("name", ctypes.c_char * 64),
    ]


class phos_progress(ctypes.Structure):
    _fields_ = [
        ("state", ctypes.c_uint32),
        ("fraction", ctypes.c_float),
        ("tiles_done", ctypes.c_uint32),
        ("tiles_total", ctypes.c_uint32),
        ("samples", ctypes.c_uint32),
        ("stage", ctypes.c_char * 64),
        ("stage_id", ctypes.c_uint32),
        ("stage_index", ctypes.c_uint32),
        ("photons_stored", ctypes.c_uint32),
        ("photons_emitted", ctypes.c_uint64),
        ("global_photons", ctypes.c_uint32),
        ("caustic_photons", ctypes.c_uint32),
        ("photon_map", ctypes.c_uint32),
        ("stage_seconds", ctypes.c_double * 7),
        ("rays_traced", ctypes.c_uint64),
        ("cache_records", ctypes.c_uint32),
        ("cache_rays_traced", ctypes.c_uint64),
        ("cache_lookups", ctypes.c_uint64),
        ("cache_interpolated", ctypes.c_uint64),
        ("gather_rays", ctypes.c_uint64),
    ]


class phos_tile(ctypes.Structure):
    _fields_ = [
        ("x", ctypes.c_uint32),
        ("y", ctypes.c_uint32),
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
    ]


STRUCTS = (
    phos_image_desc,
    phos_closure_desc,
    phos_material_desc,
    phos_mesh_desc,
    phos_instance_desc,
    phos_light_desc,
    phos_world_desc,
    phos_camera_desc,
    phos_render_settings,
    phos_stage_info,
    phos_progress,
    phos_tile,
)

# name: (restype, argtypes)
FUNCTIONS = {
    "phos_version": (ctypes.c_uint32, []),
    "phos_struct_size": (ctypes.c_uint32, [ctypes.c_char_p]),
    "phos_status_string": (ctypes.c_char_p, [ctypes.c_int]),
    "phos_struct_field": (ctypes.c_int, [ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_scene_create": (ctypes.c_void_p, []),
    "phos_scene_destroy": (None, [ctypes.c_void_p]),
    "phos_scene_error": (ctypes.c_char_p, [ctypes.c_void_p]),
    "phos_image_desc_init": (None, [ctypes.POINTER(phos_image_desc)]),
    "phos_scene_add_image": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_image_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_closure_desc_init": (None, [ctypes.POINTER(phos_closure_desc)]),
    "phos_material_desc_init": (None, [ctypes.POINTER(phos_material_desc)]),
    "phos_scene_add_material": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_material_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_mesh_desc_init": (None, [ctypes.POINTER(phos_mesh_desc)]),
    "phos_scene_add_mesh": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_mesh_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_vertex_normals": (ctypes.c_int, [ctypes.c_uint32, ctypes.POINTER(ctypes.c_float), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_float), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_float)]),
    "phos_instance_desc_init": (None, [ctypes.POINTER(phos_instance_desc)]),
    "phos_scene_add_instance": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_instance_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_light_desc_init": (None, [ctypes.POINTER(phos_light_desc)]),
    "phos_scene_add_light": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_light_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_world_desc_init": (None, [ctypes.POINTER(phos_world_desc)]),
    "phos_scene_set_world": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_world_desc)]),
    "phos_camera_desc_init": (None, [ctypes.POINTER(phos_camera_desc)]),
    "phos_scene_set_camera": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_camera_desc)]),
    "phos_scene_commit": (ctypes.c_int, [ctypes.c_void_p]),
    "phos_scene_cancel": (None, [ctypes.c_void_p]),
    "phos_pass_channels": (ctypes.c_uint32, [ctypes.c_uint32]),
    "phos_render_settings_init": (None, [ctypes.POINTER(phos_render_settings)]),
    "phos_render_create": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_render_settings), ctypes.POINTER(ctypes.c_void_p)]),
    "phos_render_destroy": (None, [ctypes.c_void_p]),
    "phos_render_error": (ctypes.c_char_p, [ctypes.c_void_p]),
    "phos_render_set_cache_file": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_char_p, ctypes.c_uint32]),
    "phos_render_start": (ctypes.c_int, [ctypes.c_void_p]),
    "phos_render_stages": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_stage_info), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32)]),
    "phos_render_progress": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_progress)]),
    "phos_render_next_tile": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_tile), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_render_read": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32, ctypes.c_uint32, ctypes.c_uint32, ctypes.c_uint32, ctypes.POINTER(ctypes.c_float), ctypes.c_size_t]),
    "phos_render_cancel": (None, [ctypes.c_void_p]),
    "phos_render_wait": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_double]),
}

# PHOS_RENDER_SETTINGS: user (scene.phos.<prop>) or host-derived (prop None).
RenderSetting = collections.namedtuple("RenderSetting", "name ctype default min max user prop kind enum soft_max label description")
RENDER_SETTINGS = (
    RenderSetting(
        name='integrator', ctype='uint32_t', default=0, min=0, max=1,
        user=True, prop='integrator', kind='ENUM', enum='phos_integrator', soft_max=0,
        label='Integrator',
        description='Method used to compute the light transport'),
    RenderSetting(
        name='width', ctype='uint32_t', default=640, min=1, max=65536,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Full frame width in pixels'),
    RenderSetting(
        name='height', ctype='uint32_t', default=480, min=1, max=65536,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Full frame height in pixels'),
    RenderSetting(
        name='region_x', ctype='uint32_t', default=0, min=0, max=65535,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Left column of the rendered region'),
    RenderSetting(
        name='region_y', ctype='uint32_t', default=0, min=0, max=65535,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Bottom row of the rendered region'),
    RenderSetting(
        name='region_width', ctype='uint32_t', default=0, min=0, max=65536,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Width of the rendered region, 0: the full frame'),
    RenderSetting(
        name='region_height', ctype='uint32_t', default=0, min=0, max=65536,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Height of the rendered region, 0: the full frame'),
    RenderSetting(
        name='samples', ctype='uint32_t', default=128, min=1, max=16777216,
        user=True, prop='samples', kind='NUMBER', enum=None, soft_max=4096,
        label='Samples',
        description='Samples per pixel of a final render'),
    RenderSetting(
        name='seed', ctype='uint32_t', default=0, min=0, max=4294967295,
        user=True, prop='seed', kind='NUMBER', enum=None, soft_max=0,
        label='Seed',
        description='Seed of the random numbers: the same seed renders the same image, whatever the thread count, tile order or border'),
    RenderSetting(
        name='max_bounces', ctype='uint32_t', default=12, min=0, max=1024,
        user=True, prop='max_bounces', kind='NUMBER', enum=None, soft_max=0,
        label='Max Bounces',
        description='Scattering events a path may have after the camera ray'),
    RenderSetting(
        name='threads', ctype='uint32_t', default=0, min=0, max=1024,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Render threads, 0: one per core'),
    RenderSetting(
        name='tile_size', ctype='uint32_t', default=64, min=8, max=8192,
        user=True, prop='tile_size', kind='PIXELS', enum=None, soft_max=1024,
        label='Tile Size',
        description='Edge of the square tiles the image is rendered and delivered in'),
    RenderSetting(
        name='filter_width', ctype='float', default=1.5, min=0.0, max=10.0,
        user=True, prop='filter_width', kind='PIXELS', enum=None, soft_max=0.0,
        label='Filter Width',
        description='Width of the Blackman-Harris pixel filter (0 is a box of one pixel)'),
    RenderSetting(
        name='transparent_background', ctype='uint32_t', default=0, min=0, max=1,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='1: the world is not seen by camera rays, alpha = coverage'),
    RenderSetting(
        name='pass_mask', ctype='uint32_t', default=1, min=0, max=4095,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description='Bit (1 << pass) per enabled pass; COMBINED is always on'),
    RenderSetting(
        name='global_photons', ctype='uint32_t', default=200000, min=0, max=268435456,
        user=True, prop='global_photons', kind='NUMBER', enum=None, soft_max=10000000,
        label='Global Photons',
        description='Photons stored in the global photon map (indirect light); photons are emitted until this many are stored'),
    RenderSetting(
        name='caustic_photons', ctype='uint32_t', default=800000, min=0, max=268435456,
        user=True, prop='caustic_photons', kind='NUMBER', enum=None, soft_max=10000000,
        label='Caustic Photons',
        description='Photons stored in the caustic photon map (light focused by mirrors and glass)'),
    RenderSetting(
        name='global_estimate_photons', ctype='uint32_t', default=50, min=1, max=10000,
        user=True, prop='global_estimate_photons', kind='NUMBER', enum=None, soft_max=1000,
        label='Global Estimate',
        description='Nearest photons used in a radiance estimate of the global map'),
    RenderSetting(
        name='caustic_estimate_photons', ctype='uint32_t', default=80, min=1, max=10000,
        user=True, prop='caustic_estimate_photons', kind='NUMBER', enum=None, soft_max=1000,
        label='Caustic Estimate',
        description='Nearest photons used in a (cone-filtered) radiance estimate of the caustic map'),
    RenderSetting(
        name='max_radius', ctype='float', default=0.0, min=0.0, max=3.4028234663852886e+38,
        user=True, prop='max_radius', kind='LENGTH', enum=None, soft_max=10.0,
        label='Max Radius',
        description="Largest search radius of a radiance estimate; 0 chooses it from the scene's size (its diagonal / 40)"),
    RenderSetting(
        name='final_gather_rays', ctype='uint32_t', default=4, min=1, max=65536,
        user=True, prop='final_gather_rays', kind='NUMBER', enum=None, soft_max=1024,
        label='Final Gather Rays',
        description='Gather rays per camera sample at the first diffuse surface (final gathering and the path-traced gather)'),
    RenderSetting(
        name='photon_view', ctype='uint32_t', default=0, min=0, max=2,
        user=True, prop='photon_view', kind='ENUM', enum='phos_photon_view', soft_max=0,
        label='Indirect Light',
        description='Where the indirect light of diffuse surfaces comes from'),
    RenderSetting(
        name='max_photons_emitted_millions', ctype='uint32_t', default=50, min=1, max=100000,
        user=True, prop='max_photons_emitted', kind='NUMBER', enum=None, soft_max=1000,
        label='Max Emitted (Millions)',
        description='Stop filling the photon maps after this many million emitted photon paths (for scenes where most photons escape)'),
    RenderSetting(
        name='irradiance_cache', ctype='uint32_t', default=1, min=0, max=2,
        user=True, prop='irradiance_cache', kind='ENUM', enum='phos_irradiance_cache', soft_max=0,
        label='Irradiance Cache',
        description="Compute the indirect light of diffuse surfaces at a few points and interpolate between them (Ward's irradiance cache)"),
    RenderSetting(
        name='ic_accuracy', ctype='float', default=5.0, min=1.0, max=1000.0,
        user=True, prop='ic_accuracy', kind='NUMBER', enum=None, soft_max=50.0,
        label='Accuracy',
        description='A record is used where its weight exceeds this (q in w > q): higher places records closer together'),
    RenderSetting(
        name='ic_rays', ctype='uint32_t', default=1024, min=4, max=65536,
        user=True, prop='ic_rays', kind='NUMBER', enum=None, soft_max=4096,
        label='Rays per Record',
        description='Stratified hemisphere rays that compute one record'),
    RenderSetting(
        name='ic_min_spacing', ctype='float', default=4.0, min=0.0, max=1000.0,
        user=True, prop='ic_min_spacing', kind='PIXELS', enum=None, soft_max=20.0,
        label='Min Spacing',
        description='Smallest reach of a record, in pixels: records never crowd closer'),
    RenderSetting(
        name='ic_max_spacing', ctype='float', default=32.0, min=1.0, max=4096.0,
        user=True, prop='ic_max_spacing', kind='PIXELS', enum=None, soft_max=128.0,
        label='Max Spacing',
        description='Largest reach of a record, in pixels: records never spread further'),
)

# PHOS_PASSES, in enum phos_pass order.
Pass = collections.namedtuple("Pass", "id ident name channels group kind description")
PASSES = (
    Pass(id=0, ident='COMBINED', name='Combined', channels=4, group=0, kind=0,
         description='The image: every light component, and alpha'),
    Pass(id=1, ident='EMISSION', name='Emission', channels=3, group=1, kind=0,
         description='Emitters seen directly (lights, emissive surfaces, the world)'),
    Pass(id=2, ident='DIRECT', name='Direct', channels=3, group=1, kind=0,
         description='Light from the emitters after one diffuse scattering'),
    Pass(id=3, ident='SPECULAR', name='Specular', channels=3, group=1, kind=0,
         description='Light seen through a specular or glossy first bounce (mirrors, glass)'),
    Pass(id=4, ident='CAUSTICS', name='Caustics', channels=3, group=1, kind=0,
         description='Light focused onto diffuse surfaces by specular bounces (L S+ D E)'),
    Pass(id=5, ident='INDIRECT', name='Indirect', channels=3, group=1, kind=0,
         description='Diffuse interreflection: light after further non-specular bounces'),
    Pass(id=6, ident='PHOTON_MAP', name='Photon Map', channels=3, group=3, kind=0,
         description="Debug: the global photon map's radiance estimate at the first diffuse surface seen"),
    Pass(id=7, ident='CAUSTIC_MAP', name='Caustic Map', channels=3, group=3, kind=0,
         description="Debug: the caustic photon map's radiance estimate at the first diffuse surface seen"),
    Pass(id=8, ident='PHOTONS', name='Photons', channels=3, group=3, kind=0,
         description='Debug: every stored photon drawn as a dot where it lies in the image'),
    Pass(id=9, ident='IRRADIANCE_CACHE', name='Irradiance Cache', channels=3, group=4, kind=0,
         description='Debug: every irradiance-cache record drawn as a dot where it lies in the image (needs the cache on)'),
    Pass(id=10, ident='DENOISING_ALBEDO', name='Denoising Albedo', channels=3, group=2, kind=0,
         description='Albedo of the first surface that is not mostly specular, for the Denoise node'),
    Pass(id=11, ident='DENOISING_NORMAL', name='Denoising Normal', channels=3, group=2, kind=1,
         description='Normal (camera space) of the first surface that is not mostly specular, for the Denoise node'),
)

__all__ = (
    'PHOS_VERSION_MAJOR',
    'PHOS_VERSION_MINOR',
    'PHOS_VERSION_PATCH',
    'PHOS_VERSION',
    'PHOS_MAX_CLOSURES',
    'PHOS_OK',
    'PHOS_ERROR_INVALID_ARGUMENT',
    'PHOS_ERROR_INVALID_STATE',
    'PHOS_ERROR_OUT_OF_MEMORY',
    'PHOS_ERROR_EMBREE',
    'PHOS_ERROR_CANCELLED',
    'PHOS_ERROR_TIMEOUT',
    'PHOS_ERROR_INTERNAL',
    'PHOS_INTERP_LINEAR',
    'PHOS_INTERP_CLOSEST',
    'PHOS_EXTEND_REPEAT',
    'PHOS_EXTEND_EXTEND',
    'PHOS_EXTEND_CLIP',
    'PHOS_CLOSURE_DIFFUSE',
    'PHOS_CLOSURE_PRINCIPLED_DIFFUSE',
    'PHOS_CLOSURE_REFLECTION',
    'PHOS_CLOSURE_REFLECTION_FRESNEL',
    'PHOS_CLOSURE_REFRACTION',
    'PHOS_CLOSURE_GLASS',
    'PHOS_CLOSURE_TRANSPARENT',
    'PHOS_CLOSURE_EMISSION',
    'PHOS_CLOSURE_METAL',
    'PHOS_CLOSURE_OREN_NAYAR',
    'PHOS_CLOSURE_SHEEN',
    'PHOS_CLOSURE_TYPE_COUNT',
    'PHOS_GLASS_FRESNEL_MACRO',
    'PHOS_GLASS_FRESNEL_MICROFACET',
    'PHOS_MICROFACET_GGX_SEPARABLE',
    'PHOS_MICROFACET_GGX',
    'PHOS_MICROFACET_GGX_MULTISCATTER',
    'PHOS_LIGHT_POINT',
    'PHOS_LIGHT_SPOT',
    'PHOS_LIGHT_AREA',
    'PHOS_LIGHT_SUN',
    'PHOS_AREA_RECTANGLE',
    'PHOS_AREA_ELLIPSE',
    'PHOS_POINT_DISK',
    'PHOS_POINT_SPHERE',
    'PHOS_CAMERA_PERSPECTIVE',
    'PHOS_CAMERA_ORTHOGRAPHIC',
    'PHOS_INTEGRATOR_PATH',
    'PHOS_INTEGRATOR_PHOTON',
    'PHOS_IRRADIANCE_CACHE_OFF',
    'PHOS_IRRADIANCE_CACHE_PHOTON',
    'PHOS_IRRADIANCE_CACHE_ALWAYS',
    'PHOS_PHOTON_VIEW_FINAL_GATHER',
    'PHOS_PHOTON_VIEW_FAST',
    'PHOS_PHOTON_VIEW_PATH_TRACED',
    'PHOS_PASS_GROUP_COMBINED',
    'PHOS_PASS_GROUP_LIGHT',
    'PHOS_PASS_GROUP_DENOISING',
    'PHOS_PASS_GROUP_PHOTONS',
    'PHOS_PASS_GROUP_CACHE',
    'PHOS_PASS_KIND_COLOR',
    'PHOS_PASS_KIND_VECTOR',
    'PHOS_PASS_COMBINED',
    'PHOS_PASS_EMISSION',
    'PHOS_PASS_DIRECT',
    'PHOS_PASS_SPECULAR',
    'PHOS_PASS_CAUSTICS',
    'PHOS_PASS_INDIRECT',
    'PHOS_PASS_PHOTON_MAP',
    'PHOS_PASS_CAUSTIC_MAP',
    'PHOS_PASS_PHOTONS',
    'PHOS_PASS_IRRADIANCE_CACHE',
    'PHOS_PASS_DENOISING_ALBEDO',
    'PHOS_PASS_DENOISING_NORMAL',
    'PHOS_PASS_COUNT',
    'PHOS_CACHE_IRRADIANCE',
    'PHOS_CACHE_PHOTON_MAPS',
    'PHOS_CACHE_KIND_COUNT',
    'PHOS_CACHE_FILE_NONE',
    'PHOS_CACHE_FILE_SAVE',
    'PHOS_CACHE_FILE_LOAD',
    'PHOS_STATE_IDLE',
    'PHOS_STATE_RUNNING',
    'PHOS_STATE_DONE',
    'PHOS_STATE_CANCELLED',
    'PHOS_STATE_FAILED',
    'PHOS_STAGE_WAITING',
    'PHOS_STAGE_TRACING_PHOTONS',
    'PHOS_STAGE_BUILDING_KDTREES',
    'PHOS_STAGE_PRECOMPUTING_RADIANCE',
    'PHOS_STAGE_FILLING_IRRADIANCE_CACHE',
    'PHOS_STAGE_RENDERING',
    'PHOS_STAGE_FINISHED',
    'PHOS_STAGE_COUNT',
    'PHOS_MAP_GLOBAL',
    'PHOS_MAP_CAUSTIC',
    'phos_image_desc',
    'phos_closure_desc',
    'phos_material_desc',
    'phos_mesh_desc',
    'phos_instance_desc',
    'phos_light_desc',
    'phos_world_desc',
    'phos_camera_desc',
    'phos_render_settings',
    'phos_stage_info',
    'phos_progress',
    'phos_tile',
    'ENUMS',
    'HANDLES',
    'STRUCTS',
    'FUNCTIONS',
    'RenderSetting',
    'RENDER_SETTINGS',
    'Pass',
    'PASSES',
)
