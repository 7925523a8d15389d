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
PHOS_SHADER_NO_REGISTER = 4294967295
PHOS_SHADER_MAX_INPUTS = 12
PHOS_SHADER_MAX_OUTPUTS = 5
PHOS_SHADER_MAX_REGISTERS = 2048
PHOS_SHADER_MAX_INSTRUCTIONS = 4096
PHOS_SHADER_MAX_TABLE = 65536
PHOS_SKY_DATA_FLOATS = 32
PHOS_SKY_DATA_IMAGE = 11
PHOS_MAX_CLOSURES = 16
PHOS_MAX_MESH_ATTRIBUTES = 64
PHOS_WORLD_NO_MATERIAL = 4294967295
PHOS_MAX_VIEWS = 16384

# enum phos_status
PHOS_OK = 0
PHOS_ERROR_INVALID_ARGUMENT = 1
PHOS_ERROR_INVALID_STATE = 2
PHOS_ERROR_OUT_OF_MEMORY = 3
PHOS_ERROR_EMBREE = 4
PHOS_ERROR_CANCELLED = 5
PHOS_ERROR_TIMEOUT = 6
PHOS_ERROR_INTERNAL = 7

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
PHOS_CLOSURE_TRANSLUCENT = 11
PHOS_CLOSURE_HOLDOUT = 12
PHOS_CLOSURE_TYPE_COUNT = 13

# enum phos_glass_fresnel
PHOS_GLASS_FRESNEL_MACRO = 0
PHOS_GLASS_FRESNEL_MICROFACET = 1

# enum phos_microfacet
PHOS_MICROFACET_GGX_SEPARABLE = 0
PHOS_MICROFACET_GGX = 1
PHOS_MICROFACET_GGX_MULTISCATTER = 2
PHOS_MICROFACET_BECKMANN_SEPARABLE = 3
PHOS_MICROFACET_BECKMANN = 4
PHOS_MICROFACET_ASHIKHMIN_SHIRLEY = 5

# enum phos_normal_correction
PHOS_NORMAL_CORRECTION_NONE = 0
PHOS_NORMAL_CORRECTION_BOTH_ROOTS = 1
PHOS_NORMAL_CORRECTION_ONE_ROOT = 2

# enum phos_shader_op
PHOS_OP_MATH = 0
PHOS_OP_VECTOR_MATH = 1
PHOS_OP_MIX_FLOAT = 2
PHOS_OP_MIX_VECTOR = 3
PHOS_OP_MIX_COLOR = 4
PHOS_OP_MAP_RANGE = 5
PHOS_OP_MAP_RANGE_VECTOR = 6
PHOS_OP_CLAMP = 7
PHOS_OP_RAMP = 8
PHOS_OP_CURVES_RGB = 9
PHOS_OP_CURVES_VECTOR = 10
PHOS_OP_CURVE_FLOAT = 11
PHOS_OP_HUE_SATURATION = 12
PHOS_OP_BRIGHT_CONTRAST = 13
PHOS_OP_GAMMA = 14
PHOS_OP_INVERT = 15
PHOS_OP_SEPARATE_COLOR = 16
PHOS_OP_COMBINE_COLOR = 17
PHOS_OP_COMBINE_XYZ = 18
PHOS_OP_RGB_TO_BW = 19
PHOS_OP_BLACKBODY = 20
PHOS_OP_WAVELENGTH = 21
PHOS_OP_TEX_IMAGE = 22
PHOS_OP_TEX_NOISE = 23
PHOS_OP_TEX_MUSGRAVE = 24
PHOS_OP_TEX_WHITE_NOISE = 25
PHOS_OP_TEX_VORONOI = 26
PHOS_OP_TEX_WAVE = 27
PHOS_OP_TEX_BRICK = 28
PHOS_OP_TEX_CHECKER = 29
PHOS_OP_TEX_MAGIC = 30
PHOS_OP_TEX_GRADIENT = 31
PHOS_OP_TEXTURE_COORDINATE = 32
PHOS_OP_GEOMETRY = 33
PHOS_OP_OBJECT_INFO = 34
PHOS_OP_FRESNEL = 35
PHOS_OP_LAYER_WEIGHT = 36
PHOS_OP_LIGHT_PATH = 37
PHOS_OP_MAPPING = 38
PHOS_OP_NORMAL_MAP = 39
PHOS_OP_BUMP = 40
PHOS_OP_BUMP_OFFSET = 41
PHOS_OP_VECTOR_ROTATE = 42
PHOS_OP_VECTOR_TRANSFORM = 43
PHOS_OP_NORMAL = 44
PHOS_OP_ATTRIBUTE = 45
PHOS_OP_TANGENT = 46
PHOS_OP_TEX_SKY = 47
PHOS_OP_COUNT = 48

# enum phos_math
PHOS_MATH_ADD = 0
PHOS_MATH_SUBTRACT = 1
PHOS_MATH_MULTIPLY = 2
PHOS_MATH_DIVIDE = 3
PHOS_MATH_MULTIPLY_ADD = 4
PHOS_MATH_POWER = 5
PHOS_MATH_LOGARITHM = 6
PHOS_MATH_SQRT = 7
PHOS_MATH_INVERSE_SQRT = 8
PHOS_MATH_ABSOLUTE = 9
PHOS_MATH_EXPONENT = 10
PHOS_MATH_MINIMUM = 11
PHOS_MATH_MAXIMUM = 12
PHOS_MATH_LESS_THAN = 13
PHOS_MATH_GREATER_THAN = 14
PHOS_MATH_SIGN = 15
PHOS_MATH_COMPARE = 16
PHOS_MATH_SMOOTH_MIN = 17
PHOS_MATH_SMOOTH_MAX = 18
PHOS_MATH_ROUND = 19
PHOS_MATH_FLOOR = 20
PHOS_MATH_CEIL = 21
PHOS_MATH_TRUNC = 22
PHOS_MATH_FRACT = 23
PHOS_MATH_MODULO = 24
PHOS_MATH_FLOORED_MODULO = 25
PHOS_MATH_WRAP = 26
PHOS_MATH_SNAP = 27
PHOS_MATH_PINGPONG = 28
PHOS_MATH_SINE = 29
PHOS_MATH_COSINE = 30
PHOS_MATH_TANGENT = 31
PHOS_MATH_ARCSINE = 32
PHOS_MATH_ARCCOSINE = 33
PHOS_MATH_ARCTANGENT = 34
PHOS_MATH_ARCTAN2 = 35
PHOS_MATH_SINH = 36
PHOS_MATH_COSH = 37
PHOS_MATH_TANH = 38
PHOS_MATH_RADIANS = 39
PHOS_MATH_DEGREES = 40
PHOS_MATH_COUNT = 41

# enum phos_vector_math
PHOS_VECTOR_MATH_ADD = 0
PHOS_VECTOR_MATH_SUBTRACT = 1
PHOS_VECTOR_MATH_MULTIPLY = 2
PHOS_VECTOR_MATH_DIVIDE = 3
PHOS_VECTOR_MATH_MULTIPLY_ADD = 4
PHOS_VECTOR_MATH_CROSS_PRODUCT = 5
PHOS_VECTOR_MATH_PROJECT = 6
PHOS_VECTOR_MATH_REFLECT = 7
PHOS_VECTOR_MATH_REFRACT = 8
PHOS_VECTOR_MATH_FACEFORWARD = 9
PHOS_VECTOR_MATH_DOT_PRODUCT = 10
PHOS_VECTOR_MATH_DISTANCE = 11
PHOS_VECTOR_MATH_LENGTH = 12
PHOS_VECTOR_MATH_SCALE = 13
PHOS_VECTOR_MATH_NORMALIZE = 14
PHOS_VECTOR_MATH_ABSOLUTE = 15
PHOS_VECTOR_MATH_POWER = 16
PHOS_VECTOR_MATH_SIGN = 17
PHOS_VECTOR_MATH_MINIMUM = 18
PHOS_VECTOR_MATH_MAXIMUM = 19
PHOS_VECTOR_MATH_FLOOR = 20
PHOS_VECTOR_MATH_CEIL = 21
PHOS_VECTOR_MATH_FRACTION = 22
PHOS_VECTOR_MATH_MODULO = 23
PHOS_VECTOR_MATH_WRAP = 24
PHOS_VECTOR_MATH_SNAP = 25
PHOS_VECTOR_MATH_SINE = 26
PHOS_VECTOR_MATH_COSINE = 27
PHOS_VECTOR_MATH_TANGENT = 28
PHOS_VECTOR_MATH_COUNT = 29

# enum phos_blend
PHOS_BLEND_MIX = 0
PHOS_BLEND_DARKEN = 1
PHOS_BLEND_MULTIPLY = 2
PHOS_BLEND_BURN = 3
PHOS_BLEND_LIGHTEN = 4
PHOS_BLEND_SCREEN = 5
PHOS_BLEND_DODGE = 6
PHOS_BLEND_ADD = 7
PHOS_BLEND_OVERLAY = 8
PHOS_BLEND_SOFT_LIGHT = 9
PHOS_BLEND_LINEAR_LIGHT = 10
PHOS_BLEND_DIFFERENCE = 11
PHOS_BLEND_EXCLUSION = 12
PHOS_BLEND_SUBTRACT = 13
PHOS_BLEND_DIVIDE = 14
PHOS_BLEND_HUE = 15
PHOS_BLEND_SATURATION = 16
PHOS_BLEND_VALUE = 17
PHOS_BLEND_COLOR = 18
PHOS_BLEND_COUNT = 19

# enum phos_map_range
PHOS_MAP_RANGE_LINEAR = 0
PHOS_MAP_RANGE_STEPPED = 1
PHOS_MAP_RANGE_SMOOTHSTEP = 2
PHOS_MAP_RANGE_SMOOTHERSTEP = 3
PHOS_MAP_RANGE_COUNT = 4

# enum phos_clamp
PHOS_CLAMP_MINMAX = 0
PHOS_CLAMP_RANGE = 1
PHOS_CLAMP_COUNT = 2

# enum phos_color_model
PHOS_COLOR_MODEL_RGB = 0
PHOS_COLOR_MODEL_HSV = 1
PHOS_COLOR_MODEL_HSL = 2
PHOS_COLOR_MODEL_COUNT = 3

# enum phos_image_projection
PHOS_PROJECTION_FLAT = 0
PHOS_PROJECTION_BOX = 1
PHOS_PROJECTION_SPHERE = 2
PHOS_PROJECTION_TUBE = 3
PHOS_PROJECTION_EQUIRECTANGULAR = 4
PHOS_PROJECTION_MIRROR_BALL = 5
PHOS_PROJECTION_COUNT = 6

# enum phos_image_flags
PHOS_IMAGE_LINEAR = 0
PHOS_IMAGE_CLOSEST = 1
PHOS_IMAGE_CUBIC = 2
PHOS_IMAGE_REPEAT = 0
PHOS_IMAGE_EXTEND = 4
PHOS_IMAGE_CLIP = 8
PHOS_IMAGE_MIRROR = 12
PHOS_IMAGE_UNASSOCIATE = 16

# enum phos_noise_type
PHOS_NOISE_FBM = 0
PHOS_NOISE_MULTIFRACTAL = 1
PHOS_NOISE_HYBRID_MULTIFRACTAL = 2
PHOS_NOISE_RIDGED_MULTIFRACTAL = 3
PHOS_NOISE_HETERO_TERRAIN = 4
PHOS_NOISE_COUNT = 5

# enum phos_voronoi_feature
PHOS_VORONOI_F1 = 0
PHOS_VORONOI_F2 = 1
PHOS_VORONOI_SMOOTH_F1 = 2
PHOS_VORONOI_DISTANCE_TO_EDGE = 3
PHOS_VORONOI_N_SPHERE_RADIUS = 4
PHOS_VORONOI_FEATURE_COUNT = 5

# enum phos_voronoi_metric
PHOS_VORONOI_EUCLIDEAN = 0
PHOS_VORONOI_MANHATTAN = 1
PHOS_VORONOI_CHEBYCHEV = 2
PHOS_VORONOI_MINKOWSKI = 3

# enum phos_wave_type
PHOS_WAVE_BANDS = 0
PHOS_WAVE_RINGS = 1
PHOS_WAVE_TYPE_COUNT = 2

# enum phos_wave_direction
PHOS_WAVE_X = 0
PHOS_WAVE_Y = 1
PHOS_WAVE_Z = 2
PHOS_WAVE_DIAGONAL = 3
PHOS_WAVE_SPHERICAL = 3

# enum phos_wave_profile
PHOS_WAVE_SIN = 0
PHOS_WAVE_SAW = 1
PHOS_WAVE_TRI = 2

# enum phos_gradient
PHOS_GRADIENT_LINEAR = 0
PHOS_GRADIENT_QUADRATIC = 1
PHOS_GRADIENT_EASING = 2
PHOS_GRADIENT_DIAGONAL = 3
PHOS_GRADIENT_SPHERICAL = 4
PHOS_GRADIENT_QUADRATIC_SPHERE = 5
PHOS_GRADIENT_RADIAL = 6
PHOS_GRADIENT_COUNT = 7

# enum phos_mapping
PHOS_MAPPING_POINT = 0
PHOS_MAPPING_TEXTURE = 1
PHOS_MAPPING_VECTOR = 2
PHOS_MAPPING_NORMAL = 3
PHOS_MAPPING_COUNT = 4

# enum phos_tangent
PHOS_TANGENT_RADIAL_X = 0
PHOS_TANGENT_RADIAL_Y = 1
PHOS_TANGENT_RADIAL_Z = 2
PHOS_TANGENT_UV_MAP = 3
PHOS_TANGENT_COUNT = 4

# enum phos_normal_map_space
PHOS_NORMAL_MAP_TANGENT = 0
PHOS_NORMAL_MAP_OBJECT = 1
PHOS_NORMAL_MAP_WORLD = 2
PHOS_NORMAL_MAP_COUNT = 3

# enum phos_vector_rotate
PHOS_VECTOR_ROTATE_AXIS_ANGLE = 0
PHOS_VECTOR_ROTATE_X_AXIS = 1
PHOS_VECTOR_ROTATE_Y_AXIS = 2
PHOS_VECTOR_ROTATE_Z_AXIS = 3
PHOS_VECTOR_ROTATE_EULER_XYZ = 4
PHOS_VECTOR_ROTATE_COUNT = 5

# enum phos_vector_transform_type
PHOS_VECTOR_TRANSFORM_POINT = 0
PHOS_VECTOR_TRANSFORM_VECTOR = 1
PHOS_VECTOR_TRANSFORM_NORMAL = 2
PHOS_VECTOR_TRANSFORM_COUNT = 3

# enum phos_space
PHOS_SPACE_WORLD = 0
PHOS_SPACE_OBJECT = 1
PHOS_SPACE_CAMERA = 2
PHOS_SPACE_COUNT = 3

# enum phos_sky_model
PHOS_SKY_SINGLE_SCATTERING = 0
PHOS_SKY_MULTIPLE_SCATTERING = 1
PHOS_SKY_PREETHAM = 2
PHOS_SKY_HOSEK_WILKIE = 3
PHOS_SKY_MODEL_COUNT = 4

# enum phos_sky_layout
PHOS_SKY_LAYOUT_HEMISPHERE = 0
PHOS_SKY_LAYOUT_SPHERE = 1
PHOS_SKY_LAYOUT_COUNT = 2

# enum phos_closure_field
PHOS_FIELD_WEIGHT = 0
PHOS_FIELD_ROUGHNESS = 1
PHOS_FIELD_IOR = 2
PHOS_FIELD_SPECULAR_COLOR = 3
PHOS_FIELD_TRANSMISSION_TINT = 4
PHOS_FIELD_TRANSMISSION_ROUGHNESS = 5
PHOS_FIELD_MULTISCATTER_FRESNEL = 6
PHOS_FIELD_SPECULAR_TINT = 7
PHOS_FIELD_THIN_FILM_THICKNESS = 8
PHOS_FIELD_THIN_FILM_IOR = 9
PHOS_FIELD_LAYER_WEIGHT = 10
PHOS_FIELD_LAYER_TINT = 11
PHOS_FIELD_LAYER_TINT_WEIGHT = 12
PHOS_FIELD_NORMAL = 13
PHOS_FIELD_ROUGHNESS_Y = 14
PHOS_FIELD_TANGENT_ROTATION = 15
PHOS_FIELD_TANGENT = 16
PHOS_FIELD_COUNT = 17

# enum phos_attribute_type
PHOS_ATTRIBUTE_FLOAT = 0
PHOS_ATTRIBUTE_FLOAT2 = 1
PHOS_ATTRIBUTE_VECTOR = 2
PHOS_ATTRIBUTE_COLOR = 3
PHOS_ATTRIBUTE_TYPE_COUNT = 4

# enum phos_light_type
PHOS_LIGHT_POINT = 0
PHOS_LIGHT_SPOT = 1
PHOS_LIGHT_AREA = 2
PHOS_LIGHT_SUN = 3
PHOS_LIGHT_PORTAL = 4

# enum phos_area_shape
PHOS_AREA_RECTANGLE = 0
PHOS_AREA_ELLIPSE = 1

# enum phos_point_shape
PHOS_POINT_DISK = 0
PHOS_POINT_SPHERE = 1

# enum phos_camera_type
PHOS_CAMERA_PERSPECTIVE = 0
PHOS_CAMERA_ORTHOGRAPHIC = 1

# enum phos_scene_change
PHOS_CHANGE_GEOMETRY = 1
PHOS_CHANGE_MATERIALS = 2
PHOS_CHANGE_LIGHTS = 4
PHOS_CHANGE_CAMERA = 8

# enum phos_integrator
PHOS_INTEGRATOR_PATH = 0
PHOS_INTEGRATOR_PHOTON = 1

# enum phos_sampler
PHOS_SAMPLER_SOBOL = 0
PHOS_SAMPLER_RANDOM = 1
PHOS_SAMPLER_STRATIFIED = 2
PHOS_SAMPLER_HALTON = 3

# enum phos_noise_filter
PHOS_NOISE_FILTER_NONE = 0
PHOS_NOISE_FILTER_LOWPASS = 1
PHOS_NOISE_FILTER_MEDIAN = 2
PHOS_NOISE_FILTER_ADAPTIVE_WIDTH = 3
PHOS_NOISE_FILTER_DIFFUSION = 4
PHOS_NOISE_FILTER_SPLATTING = 5

# enum phos_filter_target
PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE = 0
PHOS_FILTER_TARGET_INDIRECT = 1
PHOS_FILTER_TARGET_ALL = 2

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
PHOS_PASS_GROUP_NOISE = 5

# enum phos_pass_kind
PHOS_PASS_KIND_COLOR = 0
PHOS_PASS_KIND_VECTOR = 1
PHOS_PASS_KIND_VALUE = 2

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
PHOS_PASS_SAMPLE_COUNT = 12
PHOS_PASS_NOISY_IMAGE = 13
PHOS_PASS_COUNT = 14

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
PHOS_STAGE_FILTERING = 6
PHOS_STAGE_FINISHED = 7
PHOS_STAGE_COUNT = 8

# enum phos_photon_map
PHOS_MAP_GLOBAL = 0
PHOS_MAP_CAUSTIC = 1

ENUMS = {
    'phos_status': {'PHOS_OK': 0, 'PHOS_ERROR_INVALID_ARGUMENT': 1, 'PHOS_ERROR_INVALID_STATE': 2, 'PHOS_ERROR_OUT_OF_MEMORY': 3, 'PHOS_ERROR_EMBREE': 4, 'PHOS_ERROR_CANCELLED': 5, 'PHOS_ERROR_TIMEOUT': 6, 'PHOS_ERROR_INTERNAL': 7},
    'phos_closure_type': {'PHOS_CLOSURE_DIFFUSE': 0, 'PHOS_CLOSURE_PRINCIPLED_DIFFUSE': 1, 'PHOS_CLOSURE_REFLECTION': 2, 'PHOS_CLOSURE_REFLECTION_FRESNEL': 3, 'PHOS_CLOSURE_REFRACTION': 4, 'PHOS_CLOSURE_GLASS': 5, 'PHOS_CLOSURE_TRANSPARENT': 6, 'PHOS_CLOSURE_EMISSION': 7, 'PHOS_CLOSURE_METAL': 8, 'PHOS_CLOSURE_OREN_NAYAR': 9, 'PHOS_CLOSURE_SHEEN': 10, 'PHOS_CLOSURE_TRANSLUCENT': 11, 'PHOS_CLOSURE_HOLDOUT': 12, 'PHOS_CLOSURE_TYPE_COUNT': 13},
    'phos_glass_fresnel': {'PHOS_GLASS_FRESNEL_MACRO': 0, 'PHOS_GLASS_FRESNEL_MICROFACET': 1},
    'phos_microfacet': {'PHOS_MICROFACET_GGX_SEPARABLE': 0, 'PHOS_MICROFACET_GGX': 1, 'PHOS_MICROFACET_GGX_MULTISCATTER': 2, 'PHOS_MICROFACET_BECKMANN_SEPARABLE': 3, 'PHOS_MICROFACET_BECKMANN': 4, 'PHOS_MICROFACET_ASHIKHMIN_SHIRLEY': 5},
    'phos_normal_correction': {'PHOS_NORMAL_CORRECTION_NONE': 0, 'PHOS_NORMAL_CORRECTION_BOTH_ROOTS': 1, 'PHOS_NORMAL_CORRECTION_ONE_ROOT': 2},
    'phos_shader_op': {'PHOS_OP_MATH': 0, 'PHOS_OP_VECTOR_MATH': 1, 'PHOS_OP_MIX_FLOAT': 2, 'PHOS_OP_MIX_VECTOR': 3, 'PHOS_OP_MIX_COLOR': 4, 'PHOS_OP_MAP_RANGE': 5, 'PHOS_OP_MAP_RANGE_VECTOR': 6, 'PHOS_OP_CLAMP': 7, 'PHOS_OP_RAMP': 8, 'PHOS_OP_CURVES_RGB': 9, 'PHOS_OP_CURVES_VECTOR': 10, 'PHOS_OP_CURVE_FLOAT': 11, 'PHOS_OP_HUE_SATURATION': 12, 'PHOS_OP_BRIGHT_CONTRAST': 13, 'PHOS_OP_GAMMA': 14, 'PHOS_OP_INVERT': 15, 'PHOS_OP_SEPARATE_COLOR': 16, 'PHOS_OP_COMBINE_COLOR': 17, 'PHOS_OP_COMBINE_XYZ': 18, 'PHOS_OP_RGB_TO_BW': 19, 'PHOS_OP_BLACKBODY': 20, 'PHOS_OP_WAVELENGTH': 21, 'PHOS_OP_TEX_IMAGE': 22, 'PHOS_OP_TEX_NOISE': 23, 'PHOS_OP_TEX_MUSGRAVE': 24, 'PHOS_OP_TEX_WHITE_NOISE': 25, 'PHOS_OP_TEX_VORONOI': 26, 'PHOS_OP_TEX_WAVE': 27, 'PHOS_OP_TEX_BRICK': 28, 'PHOS_OP_TEX_CHECKER': 29, 'PHOS_OP_TEX_MAGIC': 30, 'PHOS_OP_TEX_GRADIENT': 31, 'PHOS_OP_TEXTURE_COORDINATE': 32, 'PHOS_OP_GEOMETRY': 33, 'PHOS_OP_OBJECT_INFO': 34, 'PHOS_OP_FRESNEL': 35, 'PHOS_OP_LAYER_WEIGHT': 36, 'PHOS_OP_LIGHT_PATH': 37, 'PHOS_OP_MAPPING': 38, 'PHOS_OP_NORMAL_MAP': 39, 'PHOS_OP_BUMP': 40, 'PHOS_OP_BUMP_OFFSET': 41, 'PHOS_OP_VECTOR_ROTATE': 42, 'PHOS_OP_VECTOR_TRANSFORM': 43, 'PHOS_OP_NORMAL': 44, 'PHOS_OP_ATTRIBUTE': 45, 'PHOS_OP_TANGENT': 46, 'PHOS_OP_TEX_SKY': 47, 'PHOS_OP_COUNT': 48},
    'phos_math': {'PHOS_MATH_ADD': 0, 'PHOS_MATH_SUBTRACT': 1, 'PHOS_MATH_MULTIPLY': 2, 'PHOS_MATH_DIVIDE': 3, 'PHOS_MATH_MULTIPLY_ADD': 4, 'PHOS_MATH_POWER': 5, 'PHOS_MATH_LOGARITHM': 6, 'PHOS_MATH_SQRT': 7, 'PHOS_MATH_INVERSE_SQRT': 8, 'PHOS_MATH_ABSOLUTE': 9, 'PHOS_MATH_EXPONENT': 10, 'PHOS_MATH_MINIMUM': 11, 'PHOS_MATH_MAXIMUM': 12, 'PHOS_MATH_LESS_THAN': 13, 'PHOS_MATH_GREATER_THAN': 14, 'PHOS_MATH_SIGN': 15, 'PHOS_MATH_COMPARE': 16, 'PHOS_MATH_SMOOTH_MIN': 17, 'PHOS_MATH_SMOOTH_MAX': 18, 'PHOS_MATH_ROUND': 19, 'PHOS_MATH_FLOOR': 20, 'PHOS_MATH_CEIL': 21, 'PHOS_MATH_TRUNC': 22, 'PHOS_MATH_FRACT': 23, 'PHOS_MATH_MODULO': 24, 'PHOS_MATH_FLOORED_MODULO': 25, 'PHOS_MATH_WRAP': 26, 'PHOS_MATH_SNAP': 27, 'PHOS_MATH_PINGPONG': 28, 'PHOS_MATH_SINE': 29, 'PHOS_MATH_COSINE': 30, 'PHOS_MATH_TANGENT': 31, 'PHOS_MATH_ARCSINE': 32, 'PHOS_MATH_ARCCOSINE': 33, 'PHOS_MATH_ARCTANGENT': 34, 'PHOS_MATH_ARCTAN2': 35, 'PHOS_MATH_SINH': 36, 'PHOS_MATH_COSH': 37, 'PHOS_MATH_TANH': 38, 'PHOS_MATH_RADIANS': 39, 'PHOS_MATH_DEGREES': 40, 'PHOS_MATH_COUNT': 41},
    'phos_vector_math': {'PHOS_VECTOR_MATH_ADD': 0, 'PHOS_VECTOR_MATH_SUBTRACT': 1, 'PHOS_VECTOR_MATH_MULTIPLY': 2, 'PHOS_VECTOR_MATH_DIVIDE': 3, 'PHOS_VECTOR_MATH_MULTIPLY_ADD': 4, 'PHOS_VECTOR_MATH_CROSS_PRODUCT': 5, 'PHOS_VECTOR_MATH_PROJECT': 6, 'PHOS_VECTOR_MATH_REFLECT': 7, 'PHOS_VECTOR_MATH_REFRACT': 8, 'PHOS_VECTOR_MATH_FACEFORWARD': 9, 'PHOS_VECTOR_MATH_DOT_PRODUCT': 10, 'PHOS_VECTOR_MATH_DISTANCE': 11, 'PHOS_VECTOR_MATH_LENGTH': 12, 'PHOS_VECTOR_MATH_SCALE': 13, 'PHOS_VECTOR_MATH_NORMALIZE': 14, 'PHOS_VECTOR_MATH_ABSOLUTE': 15, 'PHOS_VECTOR_MATH_POWER': 16, 'PHOS_VECTOR_MATH_SIGN': 17, 'PHOS_VECTOR_MATH_MINIMUM': 18, 'PHOS_VECTOR_MATH_MAXIMUM': 19, 'PHOS_VECTOR_MATH_FLOOR': 20, 'PHOS_VECTOR_MATH_CEIL': 21, 'PHOS_VECTOR_MATH_FRACTION': 22, 'PHOS_VECTOR_MATH_MODULO': 23, 'PHOS_VECTOR_MATH_WRAP': 24, 'PHOS_VECTOR_MATH_SNAP': 25, 'PHOS_VECTOR_MATH_SINE': 26, 'PHOS_VECTOR_MATH_COSINE': 27, 'PHOS_VECTOR_MATH_TANGENT': 28, 'PHOS_VECTOR_MATH_COUNT': 29},
    'phos_blend': {'PHOS_BLEND_MIX': 0, 'PHOS_BLEND_DARKEN': 1, 'PHOS_BLEND_MULTIPLY': 2, 'PHOS_BLEND_BURN': 3, 'PHOS_BLEND_LIGHTEN': 4, 'PHOS_BLEND_SCREEN': 5, 'PHOS_BLEND_DODGE': 6, 'PHOS_BLEND_ADD': 7, 'PHOS_BLEND_OVERLAY': 8, 'PHOS_BLEND_SOFT_LIGHT': 9, 'PHOS_BLEND_LINEAR_LIGHT': 10, 'PHOS_BLEND_DIFFERENCE': 11, 'PHOS_BLEND_EXCLUSION': 12, 'PHOS_BLEND_SUBTRACT': 13, 'PHOS_BLEND_DIVIDE': 14, 'PHOS_BLEND_HUE': 15, 'PHOS_BLEND_SATURATION': 16, 'PHOS_BLEND_VALUE': 17, 'PHOS_BLEND_COLOR': 18, 'PHOS_BLEND_COUNT': 19},
    'phos_map_range': {'PHOS_MAP_RANGE_LINEAR': 0, 'PHOS_MAP_RANGE_STEPPED': 1, 'PHOS_MAP_RANGE_SMOOTHSTEP': 2, 'PHOS_MAP_RANGE_SMOOTHERSTEP': 3, 'PHOS_MAP_RANGE_COUNT': 4},
    'phos_clamp': {'PHOS_CLAMP_MINMAX': 0, 'PHOS_CLAMP_RANGE': 1, 'PHOS_CLAMP_COUNT': 2},
    'phos_color_model': {'PHOS_COLOR_MODEL_RGB': 0, 'PHOS_COLOR_MODEL_HSV': 1, 'PHOS_COLOR_MODEL_HSL': 2, 'PHOS_COLOR_MODEL_COUNT': 3},
    'phos_image_projection': {'PHOS_PROJECTION_FLAT': 0, 'PHOS_PROJECTION_BOX': 1, 'PHOS_PROJECTION_SPHERE': 2, 'PHOS_PROJECTION_TUBE': 3, 'PHOS_PROJECTION_EQUIRECTANGULAR': 4, 'PHOS_PROJECTION_MIRROR_BALL': 5, 'PHOS_PROJECTION_COUNT': 6},
    'phos_image_flags': {'PHOS_IMAGE_LINEAR': 0, 'PHOS_IMAGE_CLOSEST': 1, 'PHOS_IMAGE_CUBIC': 2, 'PHOS_IMAGE_REPEAT': 0, 'PHOS_IMAGE_EXTEND': 4, 'PHOS_IMAGE_CLIP': 8, 'PHOS_IMAGE_MIRROR': 12, 'PHOS_IMAGE_UNASSOCIATE': 16},
    'phos_noise_type': {'PHOS_NOISE_FBM': 0, 'PHOS_NOISE_MULTIFRACTAL': 1, 'PHOS_NOISE_HYBRID_MULTIFRACTAL': 2, 'PHOS_NOISE_RIDGED_MULTIFRACTAL': 3, 'PHOS_NOISE_HETERO_TERRAIN': 4, 'PHOS_NOISE_COUNT': 5},
    'phos_voronoi_feature': {'PHOS_VORONOI_F1': 0, 'PHOS_VORONOI_F2': 1, 'PHOS_VORONOI_SMOOTH_F1': 2, 'PHOS_VORONOI_DISTANCE_TO_EDGE': 3, 'PHOS_VORONOI_N_SPHERE_RADIUS': 4, 'PHOS_VORONOI_FEATURE_COUNT': 5},
    'phos_voronoi_metric': {'PHOS_VORONOI_EUCLIDEAN': 0, 'PHOS_VORONOI_MANHATTAN': 1, 'PHOS_VORONOI_CHEBYCHEV': 2, 'PHOS_VORONOI_MINKOWSKI': 3},
    'phos_wave_type': {'PHOS_WAVE_BANDS': 0, 'PHOS_WAVE_RINGS': 1, 'PHOS_WAVE_TYPE_COUNT': 2},
    'phos_wave_direction': {'PHOS_WAVE_X': 0, 'PHOS_WAVE_Y': 1, 'PHOS_WAVE_Z': 2, 'PHOS_WAVE_DIAGONAL': 3, 'PHOS_WAVE_SPHERICAL': 3},
    'phos_wave_profile': {'PHOS_WAVE_SIN': 0, 'PHOS_WAVE_SAW': 1, 'PHOS_WAVE_TRI': 2},
    'phos_gradient': {'PHOS_GRADIENT_LINEAR': 0, 'PHOS_GRADIENT_QUADRATIC': 1, 'PHOS_GRADIENT_EASING': 2, 'PHOS_GRADIENT_DIAGONAL': 3, 'PHOS_GRADIENT_SPHERICAL': 4, 'PHOS_GRADIENT_QUADRATIC_SPHERE': 5, 'PHOS_GRADIENT_RADIAL': 6, 'PHOS_GRADIENT_COUNT': 7},
    'phos_mapping': {'PHOS_MAPPING_POINT': 0, 'PHOS_MAPPING_TEXTURE': 1, 'PHOS_MAPPING_VECTOR': 2, 'PHOS_MAPPING_NORMAL': 3, 'PHOS_MAPPING_COUNT': 4},
    'phos_tangent': {'PHOS_TANGENT_RADIAL_X': 0, 'PHOS_TANGENT_RADIAL_Y': 1, 'PHOS_TANGENT_RADIAL_Z': 2, 'PHOS_TANGENT_UV_MAP': 3, 'PHOS_TANGENT_COUNT': 4},
    'phos_normal_map_space': {'PHOS_NORMAL_MAP_TANGENT': 0, 'PHOS_NORMAL_MAP_OBJECT': 1, 'PHOS_NORMAL_MAP_WORLD': 2, 'PHOS_NORMAL_MAP_COUNT': 3},
    'phos_vector_rotate': {'PHOS_VECTOR_ROTATE_AXIS_ANGLE': 0, 'PHOS_VECTOR_ROTATE_X_AXIS': 1, 'PHOS_VECTOR_ROTATE_Y_AXIS': 2, 'PHOS_VECTOR_ROTATE_Z_AXIS': 3, 'PHOS_VECTOR_ROTATE_EULER_XYZ': 4, 'PHOS_VECTOR_ROTATE_COUNT': 5},
    'phos_vector_transform_type': {'PHOS_VECTOR_TRANSFORM_POINT': 0, 'PHOS_VECTOR_TRANSFORM_VECTOR': 1, 'PHOS_VECTOR_TRANSFORM_NORMAL': 2, 'PHOS_VECTOR_TRANSFORM_COUNT': 3},
    'phos_space': {'PHOS_SPACE_WORLD': 0, 'PHOS_SPACE_OBJECT': 1, 'PHOS_SPACE_CAMERA': 2, 'PHOS_SPACE_COUNT': 3},
    'phos_sky_model': {'PHOS_SKY_SINGLE_SCATTERING': 0, 'PHOS_SKY_MULTIPLE_SCATTERING': 1, 'PHOS_SKY_PREETHAM': 2, 'PHOS_SKY_HOSEK_WILKIE': 3, 'PHOS_SKY_MODEL_COUNT': 4},
    'phos_sky_layout': {'PHOS_SKY_LAYOUT_HEMISPHERE': 0, 'PHOS_SKY_LAYOUT_SPHERE': 1, 'PHOS_SKY_LAYOUT_COUNT': 2},
    'phos_closure_field': {'PHOS_FIELD_WEIGHT': 0, 'PHOS_FIELD_ROUGHNESS': 1, 'PHOS_FIELD_IOR': 2, 'PHOS_FIELD_SPECULAR_COLOR': 3, 'PHOS_FIELD_TRANSMISSION_TINT': 4, 'PHOS_FIELD_TRANSMISSION_ROUGHNESS': 5, 'PHOS_FIELD_MULTISCATTER_FRESNEL': 6, 'PHOS_FIELD_SPECULAR_TINT': 7, 'PHOS_FIELD_THIN_FILM_THICKNESS': 8, 'PHOS_FIELD_THIN_FILM_IOR': 9, 'PHOS_FIELD_LAYER_WEIGHT': 10, 'PHOS_FIELD_LAYER_TINT': 11, 'PHOS_FIELD_LAYER_TINT_WEIGHT': 12, 'PHOS_FIELD_NORMAL': 13, 'PHOS_FIELD_ROUGHNESS_Y': 14, 'PHOS_FIELD_TANGENT_ROTATION': 15, 'PHOS_FIELD_TANGENT': 16, 'PHOS_FIELD_COUNT': 17},
    'phos_attribute_type': {'PHOS_ATTRIBUTE_FLOAT': 0, 'PHOS_ATTRIBUTE_FLOAT2': 1, 'PHOS_ATTRIBUTE_VECTOR': 2, 'PHOS_ATTRIBUTE_COLOR': 3, 'PHOS_ATTRIBUTE_TYPE_COUNT': 4},
    'phos_light_type': {'PHOS_LIGHT_POINT': 0, 'PHOS_LIGHT_SPOT': 1, 'PHOS_LIGHT_AREA': 2, 'PHOS_LIGHT_SUN': 3, 'PHOS_LIGHT_PORTAL': 4},
    'phos_area_shape': {'PHOS_AREA_RECTANGLE': 0, 'PHOS_AREA_ELLIPSE': 1},
    'phos_point_shape': {'PHOS_POINT_DISK': 0, 'PHOS_POINT_SPHERE': 1},
    'phos_camera_type': {'PHOS_CAMERA_PERSPECTIVE': 0, 'PHOS_CAMERA_ORTHOGRAPHIC': 1},
    'phos_scene_change': {'PHOS_CHANGE_GEOMETRY': 1, 'PHOS_CHANGE_MATERIALS': 2, 'PHOS_CHANGE_LIGHTS': 4, 'PHOS_CHANGE_CAMERA': 8},
    'phos_integrator': {'PHOS_INTEGRATOR_PATH': 0, 'PHOS_INTEGRATOR_PHOTON': 1},
    'phos_sampler': {'PHOS_SAMPLER_SOBOL': 0, 'PHOS_SAMPLER_RANDOM': 1, 'PHOS_SAMPLER_STRATIFIED': 2, 'PHOS_SAMPLER_HALTON': 3},
    'phos_noise_filter': {'PHOS_NOISE_FILTER_NONE': 0, 'PHOS_NOISE_FILTER_LOWPASS': 1, 'PHOS_NOISE_FILTER_MEDIAN': 2, 'PHOS_NOISE_FILTER_ADAPTIVE_WIDTH': 3, 'PHOS_NOISE_FILTER_DIFFUSION': 4, 'PHOS_NOISE_FILTER_SPLATTING': 5},
    'phos_filter_target': {'PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE': 0, 'PHOS_FILTER_TARGET_INDIRECT': 1, 'PHOS_FILTER_TARGET_ALL': 2},
    'phos_irradiance_cache': {'PHOS_IRRADIANCE_CACHE_OFF': 0, 'PHOS_IRRADIANCE_CACHE_PHOTON': 1, 'PHOS_IRRADIANCE_CACHE_ALWAYS': 2},
    'phos_photon_view': {'PHOS_PHOTON_VIEW_FINAL_GATHER': 0, 'PHOS_PHOTON_VIEW_FAST': 1, 'PHOS_PHOTON_VIEW_PATH_TRACED': 2},
    'phos_pass_group': {'PHOS_PASS_GROUP_COMBINED': 0, 'PHOS_PASS_GROUP_LIGHT': 1, 'PHOS_PASS_GROUP_DENOISING': 2, 'PHOS_PASS_GROUP_PHOTONS': 3, 'PHOS_PASS_GROUP_CACHE': 4, 'PHOS_PASS_GROUP_NOISE': 5},
    'phos_pass_kind': {'PHOS_PASS_KIND_COLOR': 0, 'PHOS_PASS_KIND_VECTOR': 1, 'PHOS_PASS_KIND_VALUE': 2},
    'phos_pass': {'PHOS_PASS_COMBINED': 0, 'PHOS_PASS_EMISSION': 1, 'PHOS_PASS_DIRECT': 2, 'PHOS_PASS_SPECULAR': 3, 'PHOS_PASS_CAUSTICS': 4, 'PHOS_PASS_INDIRECT': 5, 'PHOS_PASS_PHOTON_MAP': 6, 'PHOS_PASS_CAUSTIC_MAP': 7, 'PHOS_PASS_PHOTONS': 8, 'PHOS_PASS_IRRADIANCE_CACHE': 9, 'PHOS_PASS_DENOISING_ALBEDO': 10, 'PHOS_PASS_DENOISING_NORMAL': 11, 'PHOS_PASS_SAMPLE_COUNT': 12, 'PHOS_PASS_NOISY_IMAGE': 13, 'PHOS_PASS_COUNT': 14},
    'phos_cache_kind': {'PHOS_CACHE_IRRADIANCE': 0, 'PHOS_CACHE_PHOTON_MAPS': 1, 'PHOS_CACHE_KIND_COUNT': 2},
    'phos_cache_file_mode': {'PHOS_CACHE_FILE_NONE': 0, 'PHOS_CACHE_FILE_SAVE': 1, 'PHOS_CACHE_FILE_LOAD': 2},
    'phos_render_state': {'PHOS_STATE_IDLE': 0, 'PHOS_STATE_RUNNING': 1, 'PHOS_STATE_DONE': 2, 'PHOS_STATE_CANCELLED': 3, 'PHOS_STATE_FAILED': 4},
    'phos_stage': {'PHOS_STAGE_WAITING': 0, 'PHOS_STAGE_TRACING_PHOTONS': 1, 'PHOS_STAGE_BUILDING_KDTREES': 2, 'PHOS_STAGE_PRECOMPUTING_RADIANCE': 3, 'PHOS_STAGE_FILLING_IRRADIANCE_CACHE': 4, 'PHOS_STAGE_RENDERING': 5, 'PHOS_STAGE_FILTERING': 6, 'PHOS_STAGE_FINISHED': 7, 'PHOS_STAGE_COUNT': 8},
    'phos_photon_map': {'PHOS_MAP_GLOBAL': 0, 'PHOS_MAP_CAUSTIC': 1},
}

# Opaque handles, passed as c_void_p.
HANDLES = ('phos_scene', 'phos_render', 'phos_photon_maps')


class phos_image_desc(ctypes.Structure):
    _fields_ = [
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
        ("pixels", ctypes.POINTER(ctypes.c_float)),
    ]


class phos_closure_desc(ctypes.Structure):
    _fields_ = [
        ("type", ctypes.c_uint32),
        ("weight", ctypes.c_float * 3),
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
        ("roughness_y", ctypes.c_float),
        ("tangent_rotation", ctypes.c_float),
        ("normal_correction", ctypes.c_uint32),
    ]


class phos_sky_desc(ctypes.Structure):
    _fields_ = [
        ("model", ctypes.c_uint32),
        ("layout", ctypes.c_uint32),
        ("sun_elevation", ctypes.c_float),
        ("sun_rotation", ctypes.c_float),
        ("sun_size", ctypes.c_float),
        ("sun_intensity", ctypes.c_float),
        ("sun_disc", ctypes.c_uint32),
        ("altitude", ctypes.c_float),
        ("air_density", ctypes.c_float),
        ("aerosol_density", ctypes.c_float),
        ("ozone_density", ctypes.c_float),
        ("turbidity", ctypes.c_float),
        ("ground_albedo", ctypes.c_float),
        ("sun_direction", ctypes.c_float * 3),
    ]


class phos_shader_instruction(ctypes.Structure):
    _fields_ = [
        ("op", ctypes.c_uint32),
        ("mode", ctypes.c_uint32),
        ("flags", ctypes.c_uint32),
        ("table", ctypes.c_uint32),
        ("param", ctypes.c_float * 4),
        ("inputs", ctypes.c_uint32 * 12),
        ("outputs", ctypes.c_uint32 * 5),
    ]


class phos_shader_binding(ctypes.Structure):
    _fields_ = [
        ("closure", ctypes.c_uint32),
        ("field", ctypes.c_uint32),
        ("reg", ctypes.c_uint32),
    ]


class phos_shader_program_desc(ctypes.Structure):
    _fields_ = [
        ("register_count", ctypes.c_uint32),
        ("constant_count", ctypes.c_uint32),
        ("constants", ctypes.POINTER(ctypes.c_float)),
        ("instruction_count", ctypes.c_uint32),
        ("instructions", ctypes.POINTER(phos_shader_instruction)),
        ("table_size", ctypes.c_uint32),
        ("table", ctypes.POINTER(ctypes.c_float)),
        ("binding_count", ctypes.c_uint32),
        ("bindings", ctypes.POINTER(phos_shader_binding)),
    ]


class phos_material_desc(ctypes.Structure):
    _fields_ = [
        ("closure_count", ctypes.c_uint32),
        ("closures", ctypes.POINTER(phos_closure_desc)),
        ("program", ctypes.POINTER(phos_shader_program_desc)),
    ]


class phos_mesh_attribute(ctypes.Structure):
    _fields_ = [
        ("id", ctypes.c_uint32),
        ("type", ctypes.c_uint32),
        ("values", ctypes.POINTER(ctypes.c_float)),
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
        ("tangents", ctypes.POINTER(ctypes.c_float)),
        ("texspace_location", ctypes.c_float * 3),
        ("texspace_size", ctypes.c_float * 3),
        ("attribute_count", ctypes.c_uint32),
        ("attributes", ctypes.POINTER(phos_mesh_attribute)),
    ]


class phos_instance_desc(ctypes.Structure):
    _fields_ = [
        ("mesh_id", ctypes.c_uint32),
        ("transform", ctypes.c_float * 12),
        ("material_count", ctypes.c_uint32),
        ("materials", ctypes.POINTER(ctypes.c_uint32)),
        ("random", ctypes.c_float),
        ("pass_index", ctypes.c_float),
    ]


class phos_instances_desc(ctypes.Structure):
    _fields_ = [
        ("count", ctypes.c_uint32),
        ("mesh_ids", ctypes.POINTER(ctypes.c_uint32)),
        ("transforms", ctypes.POINTER(ctypes.c_float)),
        ("material_offsets", ctypes.POINTER(ctypes.c_uint32)),
        ("materials", ctypes.POINTER(ctypes.c_uint32)),
        ("randoms", ctypes.POINTER(ctypes.c_float)),
        ("pass_indices", ctypes.POINTER(ctypes.c_float)),
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
        ("material", ctypes.c_uint32),
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
        ("sampler", ctypes.c_uint32),
        ("max_bounces", ctypes.c_uint32),
        ("threads", ctypes.c_uint32),
        ("tile_size", ctypes.c_uint32),
        ("progressive", ctypes.c_uint32),
        ("adaptive_sampling", ctypes.c_uint32),
        ("adaptive_threshold", ctypes.c_float),
        ("adaptive_min_samples", ctypes.c_uint32),
        ("time_limit", ctypes.c_float),
        ("noise_filter", ctypes.c_uint32),
        ("filter_target", ctypes.c_uint32),
        ("filter_width", ctypes.c_float),
        ("transparent_background", ctypes.c_uint32),
        ("caches_only", ctypes.c_uint32),
        ("pass_mask", ctypes.c_uint32),
        ("global_photons", ctypes.c_uint32),
        ("caustic_photons", ctypes.c_uint32),
        ("caustic_roughness", ctypes.c_float),
        ("global_estimate_photons", ctypes.c_uint32),
        ("caustic_estimate_photons", ctypes.c_uint32),
        ("caustic_sample_share", ctypes.c_float),
        ("progressive_caustics", ctypes.c_uint32),
        ("progressive_caustic_photons", ctypes.c_uint32),
        ("progressive_first_photons", ctypes.c_uint32),
        ("progressive_alpha", ctypes.c_float),
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
        ("samples_done", ctypes.c_uint32),
        ("stage", ctypes.c_char * 64),
        ("stage_id", ctypes.c_uint32),
        ("stage_index", ctypes.c_uint32),
        ("photons_stored", ctypes.c_uint32),
        ("photons_emitted", ctypes.c_uint64),
        ("global_photons", ctypes.c_uint32),
        ("caustic_photons", ctypes.c_uint32),
        ("photon_map", ctypes.c_uint32),
        ("photon_maps_short", ctypes.c_uint32),
        ("stage_seconds", ctypes.c_double * 8),
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
    phos_sky_desc,
    phos_shader_instruction,
    phos_shader_binding,
    phos_shader_program_desc,
    phos_material_desc,
    phos_mesh_attribute,
    phos_mesh_desc,
    phos_instance_desc,
    phos_instances_desc,
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
    "phos_sky_desc_init": (None, [ctypes.POINTER(phos_sky_desc)]),
    "phos_sky_texture_size": (ctypes.c_int, [ctypes.POINTER(phos_sky_desc), ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_sky_bake": (ctypes.c_int, [ctypes.POINTER(phos_sky_desc), ctypes.POINTER(ctypes.c_float), ctypes.POINTER(ctypes.c_float)]),
    "phos_material_desc_init": (None, [ctypes.POINTER(phos_material_desc)]),
    "phos_scene_add_material": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_material_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_mesh_desc_init": (None, [ctypes.POINTER(phos_mesh_desc)]),
    "phos_scene_add_mesh": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_mesh_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_vertex_normals": (ctypes.c_int, [ctypes.c_uint32, ctypes.POINTER(ctypes.c_float), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_float), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32), ctypes.POINTER(ctypes.c_float)]),
    "phos_instance_desc_init": (None, [ctypes.POINTER(phos_instance_desc)]),
    "phos_scene_add_instance": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_instance_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_scene_add_instances": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_instances_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_light_desc_init": (None, [ctypes.POINTER(phos_light_desc)]),
    "phos_scene_add_light": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_light_desc), ctypes.POINTER(ctypes.c_uint32)]),
    "phos_world_desc_init": (None, [ctypes.POINTER(phos_world_desc)]),
    "phos_scene_set_world": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_world_desc)]),
    "phos_camera_desc_init": (None, [ctypes.POINTER(phos_camera_desc)]),
    "phos_scene_set_camera": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_camera_desc)]),
    "phos_scene_commit": (ctypes.c_int, [ctypes.c_void_p]),
    "phos_scene_update_mesh": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.POINTER(phos_mesh_desc)]),
    "phos_scene_update_instance": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.POINTER(phos_instance_desc)]),
    "phos_scene_update_material": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.POINTER(phos_material_desc)]),
    "phos_scene_update_light": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.POINTER(phos_light_desc)]),
    "phos_scene_changes": (ctypes.c_uint32, [ctypes.c_void_p]),
    "phos_scene_cancel": (None, [ctypes.c_void_p]),
    "phos_pass_channels": (ctypes.c_uint32, [ctypes.c_uint32]),
    "phos_render_settings_init": (None, [ctypes.POINTER(phos_render_settings)]),
    "phos_render_create": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_render_settings), ctypes.POINTER(ctypes.c_void_p)]),
    "phos_render_destroy": (None, [ctypes.c_void_p]),
    "phos_render_error": (ctypes.c_char_p, [ctypes.c_void_p]),
    "phos_render_set_cache_file": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_char_p, ctypes.c_uint32]),
    "phos_render_add_view": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_camera_desc)]),
    "phos_render_keep_photon_maps": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p)]),
    "phos_render_use_photon_maps": (ctypes.c_int, [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint32]),
    "phos_photon_maps_release": (None, [ctypes.c_void_p]),
    "phos_render_start": (ctypes.c_int, [ctypes.c_void_p]),
    "phos_render_stages": (ctypes.c_int, [ctypes.c_void_p, ctypes.POINTER(phos_stage_info), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32)]),
    "phos_settings_stages": (ctypes.c_int, [ctypes.POINTER(phos_render_settings), ctypes.POINTER(ctypes.c_uint32), ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32)]),
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
        name='sampler', ctype='uint32_t', default=0, min=0, max=3,
        user=True, prop='sampler', kind='ENUM', enum='phos_sampler', soft_max=0,
        label='Sampler',
        description='How the random numbers of paths, photons and gathers are drawn'),
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
        description='Edge of the square tiles the image is rendered and delivered in (halved, down to 8, until each thread has 16 tiles to choose from)'),
    RenderSetting(
        name='progressive', ctype='uint32_t', default=1, min=0, max=1,
        user=True, prop='use_progressive_refine', kind='BOOLEAN', enum=None, soft_max=0,
        label='Progressive Refine',
        description='Show the whole frame after one sample a pixel, then refine it in passes of doubling sample counts; the final image is the same (costs 8 bytes a pixel per channel of the enabled passes)'),
    RenderSetting(
        name='adaptive_sampling', ctype='uint32_t', default=0, min=0, max=1,
        user=True, prop='use_adaptive_sampling', kind='BOOLEAN', enum=None, soft_max=0,
        label='Adaptive Sampling',
        description='Stop sampling each pixel once its estimated noise is below the threshold (its count of samples depends only on its own samples)'),
    RenderSetting(
        name='adaptive_threshold', ctype='float', default=0.01, min=0.0001, max=1.0,
        user=True, prop='adaptive_threshold', kind='NUMBER', enum=None, soft_max=0.1,
        label='Noise Threshold',
        description='Error at which a pixel stops: the standard error of its mean over the square root of its value (over its value above 1)'),
    RenderSetting(
        name='adaptive_min_samples', ctype='uint32_t', default=16, min=2, max=16777216,
        user=True, prop='adaptive_min_samples', kind='NUMBER', enum=None, soft_max=4096,
        label='Min Samples',
        description='Samples every pixel takes before its noise is first estimated'),
    RenderSetting(
        name='time_limit', ctype='float', default=0.0, min=0.0, max=10000000.0,
        user=True, prop='time_limit', kind='SECONDS', enum=None, soft_max=3600.0,
        label='Time Limit',
        description="Stop sampling after this many seconds of rendering (after the photon and cache stages; 0: none); every pixel gets at least one sample, and the image then depends on the machine's speed"),
    RenderSetting(
        name='noise_filter', ctype='uint32_t', default=0, min=0, max=5,
        user=True, prop='filter', kind='ENUM', enum='phos_noise_filter', soft_max=0,
        label='Noise Filter',
        description='Filter run over the rendered image'),
    RenderSetting(
        name='filter_target', ctype='uint32_t', default=0, min=0, max=2,
        user=True, prop='filter_target', kind='ENUM', enum='phos_filter_target', soft_max=0,
        label='Filter',
        description='What the noise filter is applied to; the rest is added back unfiltered'),
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
        name='caches_only', ctype='uint32_t', default=0, min=0, max=1,
        user=False, prop=None, kind=None, enum=None, soft_max=None,
        label=None,
        description="1: trace the photon maps and fill the irradiance cache, render no pixel (a render farm's cache job, with phos_render_set_cache_file saving them)"),
    RenderSetting(
        name='pass_mask', ctype='uint32_t', default=1, min=0, max=16383,
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
        description='Photons stored in the caustic photon map (light focused by mirrors and glass); tracing stops after ten light paths per photon asked for, so a faint caustic stores fewer (still right, only sparser)'),
    RenderSetting(
        name='caustic_roughness', ctype='float', default=0.3, min=0.0, max=1.0,
        user=True, prop='caustic_roughness', kind='FACTOR', enum=None, soft_max=0.0,
        label='Caustic Roughness',
        description='Glossy reflection and refraction smoother than this focus light into caustics like mirrors and glass (photons pass them); rougher ones are lit by the caustic map like diffuse surfaces (0: only sharp mirrors and glass make caustics)'),
    RenderSetting(
        name='global_estimate_photons', ctype='uint32_t', default=50, min=1, max=10000,
        user=True, prop='global_estimate_photons', kind='NUMBER', enum=None, soft_max=1000,
        label='Global Estimate',
        description='Nearest photons used in a radiance estimate of the global map'),
    RenderSetting(
        name='caustic_estimate_photons', ctype='uint32_t', default=20, min=1, max=10000,
        user=True, prop='caustic_estimate_photons', kind='NUMBER', enum=None, soft_max=1000,
        label='Caustic Estimate',
        description='Nearest photons used in a (cone-filtered) radiance estimate of the caustic map'),
    RenderSetting(
        name='caustic_sample_share', ctype='float', default=0.25, min=0.0, max=1.0,
        user=True, prop='caustic_sample_share', kind='FACTOR', enum=None, soft_max=0.0,
        label='Caustic Sample Share',
        description="Share of a pixel's samples that read the caustic map, its first ones (at least one); the caustics are the mean over those alone and the other samples skip the estimate (1: every sample)"),
    RenderSetting(
        name='progressive_caustics', ctype='uint32_t', default=0, min=0, max=1,
        user=True, prop='use_progressive_caustics', kind='BOOLEAN', enum=None, soft_max=0,
        label='Progressive',
        description='A new caustic map for every sample, read within a radius that shrinks from sample to sample, so caustics converge to the exact image as samples grow instead of staying blurred by a fixed number of nearest photons'),
    RenderSetting(
        name='progressive_caustic_photons', ctype='uint32_t', default=10000, min=1, max=67108864,
        user=True, prop='progressive_caustic_photons', kind='NUMBER', enum=None, soft_max=1000000,
        label='Photons per Sample',
        description='Caustic photons stored for each sample when caustics are progressive'),
    RenderSetting(
        name='progressive_first_photons', ctype='uint32_t', default=4, min=1, max=10000,
        user=True, prop='progressive_first_photons', kind='NUMBER', enum=None, soft_max=100,
        label='First Radius Photons',
        description="Photons within a point's first progressive radius (from the map of the sample before); the radius then shrinks with every sample"),
    RenderSetting(
        name='progressive_alpha', ctype='float', default=0.5, min=0.01, max=0.99,
        user=True, prop='progressive_alpha', kind='FACTOR', enum=None, soft_max=0.0,
        label='Alpha',
        description='How fast the progressive radius shrinks: the squared radius falls as samples^(alpha-1); lower shrinks faster, leaving less blur and more noise'),
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
    Pass(id=12, ident='SAMPLE_COUNT', name='Sample Count', channels=1, group=5, kind=2,
         description='Samples each pixel received, as a share of the Samples setting (adaptive sampling and the time limit make them differ)'),
    Pass(id=13, ident='NOISY_IMAGE', name='Noisy Image', channels=4, group=5, kind=0,
         description='The image before the noise filter (the Combined pass holds it filtered)'),
)

__all__ = (
    'PHOS_VERSION_MAJOR',
    'PHOS_VERSION_MINOR',
    'PHOS_VERSION_PATCH',
    'PHOS_VERSION',
    'PHOS_SHADER_NO_REGISTER',
    'PHOS_SHADER_MAX_INPUTS',
    'PHOS_SHADER_MAX_OUTPUTS',
    'PHOS_SHADER_MAX_REGISTERS',
    'PHOS_SHADER_MAX_INSTRUCTIONS',
    'PHOS_SHADER_MAX_TABLE',
    'PHOS_SKY_DATA_FLOATS',
    'PHOS_SKY_DATA_IMAGE',
    'PHOS_MAX_CLOSURES',
    'PHOS_MAX_MESH_ATTRIBUTES',
    'PHOS_WORLD_NO_MATERIAL',
    'PHOS_MAX_VIEWS',
    'PHOS_OK',
    'PHOS_ERROR_INVALID_ARGUMENT',
    'PHOS_ERROR_INVALID_STATE',
    'PHOS_ERROR_OUT_OF_MEMORY',
    'PHOS_ERROR_EMBREE',
    'PHOS_ERROR_CANCELLED',
    'PHOS_ERROR_TIMEOUT',
    'PHOS_ERROR_INTERNAL',
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
    'PHOS_CLOSURE_TRANSLUCENT',
    'PHOS_CLOSURE_HOLDOUT',
    'PHOS_CLOSURE_TYPE_COUNT',
    'PHOS_GLASS_FRESNEL_MACRO',
    'PHOS_GLASS_FRESNEL_MICROFACET',
    'PHOS_MICROFACET_GGX_SEPARABLE',
    'PHOS_MICROFACET_GGX',
    'PHOS_MICROFACET_GGX_MULTISCATTER',
    'PHOS_MICROFACET_BECKMANN_SEPARABLE',
    'PHOS_MICROFACET_BECKMANN',
    'PHOS_MICROFACET_ASHIKHMIN_SHIRLEY',
    'PHOS_NORMAL_CORRECTION_NONE',
    'PHOS_NORMAL_CORRECTION_BOTH_ROOTS',
    'PHOS_NORMAL_CORRECTION_ONE_ROOT',
    'PHOS_OP_MATH',
    'PHOS_OP_VECTOR_MATH',
    'PHOS_OP_MIX_FLOAT',
    'PHOS_OP_MIX_VECTOR',
    'PHOS_OP_MIX_COLOR',
    'PHOS_OP_MAP_RANGE',
    'PHOS_OP_MAP_RANGE_VECTOR',
    'PHOS_OP_CLAMP',
    'PHOS_OP_RAMP',
    'PHOS_OP_CURVES_RGB',
    'PHOS_OP_CURVES_VECTOR',
    'PHOS_OP_CURVE_FLOAT',
    'PHOS_OP_HUE_SATURATION',
    'PHOS_OP_BRIGHT_CONTRAST',
    'PHOS_OP_GAMMA',
    'PHOS_OP_INVERT',
    'PHOS_OP_SEPARATE_COLOR',
    'PHOS_OP_COMBINE_COLOR',
    'PHOS_OP_COMBINE_XYZ',
    'PHOS_OP_RGB_TO_BW',
    'PHOS_OP_BLACKBODY',
    'PHOS_OP_WAVELENGTH',
    'PHOS_OP_TEX_IMAGE',
    'PHOS_OP_TEX_NOISE',
    'PHOS_OP_TEX_MUSGRAVE',
    'PHOS_OP_TEX_WHITE_NOISE',
    'PHOS_OP_TEX_VORONOI',
    'PHOS_OP_TEX_WAVE',
    'PHOS_OP_TEX_BRICK',
    'PHOS_OP_TEX_CHECKER',
    'PHOS_OP_TEX_MAGIC',
    'PHOS_OP_TEX_GRADIENT',
    'PHOS_OP_TEXTURE_COORDINATE',
    'PHOS_OP_GEOMETRY',
    'PHOS_OP_OBJECT_INFO',
    'PHOS_OP_FRESNEL',
    'PHOS_OP_LAYER_WEIGHT',
    'PHOS_OP_LIGHT_PATH',
    'PHOS_OP_MAPPING',
    'PHOS_OP_NORMAL_MAP',
    'PHOS_OP_BUMP',
    'PHOS_OP_BUMP_OFFSET',
    'PHOS_OP_VECTOR_ROTATE',
    'PHOS_OP_VECTOR_TRANSFORM',
    'PHOS_OP_NORMAL',
    'PHOS_OP_ATTRIBUTE',
    'PHOS_OP_TANGENT',
    'PHOS_OP_TEX_SKY',
    'PHOS_OP_COUNT',
    'PHOS_MATH_ADD',
    'PHOS_MATH_SUBTRACT',
    'PHOS_MATH_MULTIPLY',
    'PHOS_MATH_DIVIDE',
    'PHOS_MATH_MULTIPLY_ADD',
    'PHOS_MATH_POWER',
    'PHOS_MATH_LOGARITHM',
    'PHOS_MATH_SQRT',
    'PHOS_MATH_INVERSE_SQRT',
    'PHOS_MATH_ABSOLUTE',
    'PHOS_MATH_EXPONENT',
    'PHOS_MATH_MINIMUM',
    'PHOS_MATH_MAXIMUM',
    'PHOS_MATH_LESS_THAN',
    'PHOS_MATH_GREATER_THAN',
    'PHOS_MATH_SIGN',
    'PHOS_MATH_COMPARE',
    'PHOS_MATH_SMOOTH_MIN',
    'PHOS_MATH_SMOOTH_MAX',
    'PHOS_MATH_ROUND',
    'PHOS_MATH_FLOOR',
    'PHOS_MATH_CEIL',
    'PHOS_MATH_TRUNC',
    'PHOS_MATH_FRACT',
    'PHOS_MATH_MODULO',
    'PHOS_MATH_FLOORED_MODULO',
    'PHOS_MATH_WRAP',
    'PHOS_MATH_SNAP',
    'PHOS_MATH_PINGPONG',
    'PHOS_MATH_SINE',
    'PHOS_MATH_COSINE',
    'PHOS_MATH_TANGENT',
    'PHOS_MATH_ARCSINE',
    'PHOS_MATH_ARCCOSINE',
    'PHOS_MATH_ARCTANGENT',
    'PHOS_MATH_ARCTAN2',
    'PHOS_MATH_SINH',
    'PHOS_MATH_COSH',
    'PHOS_MATH_TANH',
    'PHOS_MATH_RADIANS',
    'PHOS_MATH_DEGREES',
    'PHOS_MATH_COUNT',
    'PHOS_VECTOR_MATH_ADD',
    'PHOS_VECTOR_MATH_SUBTRACT',
    'PHOS_VECTOR_MATH_MULTIPLY',
    'PHOS_VECTOR_MATH_DIVIDE',
    'PHOS_VECTOR_MATH_MULTIPLY_ADD',
    'PHOS_VECTOR_MATH_CROSS_PRODUCT',
    'PHOS_VECTOR_MATH_PROJECT',
    'PHOS_VECTOR_MATH_REFLECT',
    'PHOS_VECTOR_MATH_REFRACT',
    'PHOS_VECTOR_MATH_FACEFORWARD',
    'PHOS_VECTOR_MATH_DOT_PRODUCT',
    'PHOS_VECTOR_MATH_DISTANCE',
    'PHOS_VECTOR_MATH_LENGTH',
    'PHOS_VECTOR_MATH_SCALE',
    'PHOS_VECTOR_MATH_NORMALIZE',
    'PHOS_VECTOR_MATH_ABSOLUTE',
    'PHOS_VECTOR_MATH_POWER',
    'PHOS_VECTOR_MATH_SIGN',
    'PHOS_VECTOR_MATH_MINIMUM',
    'PHOS_VECTOR_MATH_MAXIMUM',
    'PHOS_VECTOR_MATH_FLOOR',
    'PHOS_VECTOR_MATH_CEIL',
    'PHOS_VECTOR_MATH_FRACTION',
    'PHOS_VECTOR_MATH_MODULO',
    'PHOS_VECTOR_MATH_WRAP',
    'PHOS_VECTOR_MATH_SNAP',
    'PHOS_VECTOR_MATH_SINE',
    'PHOS_VECTOR_MATH_COSINE',
    'PHOS_VECTOR_MATH_TANGENT',
    'PHOS_VECTOR_MATH_COUNT',
    'PHOS_BLEND_MIX',
    'PHOS_BLEND_DARKEN',
    'PHOS_BLEND_MULTIPLY',
    'PHOS_BLEND_BURN',
    'PHOS_BLEND_LIGHTEN',
    'PHOS_BLEND_SCREEN',
    'PHOS_BLEND_DODGE',
    'PHOS_BLEND_ADD',
    'PHOS_BLEND_OVERLAY',
    'PHOS_BLEND_SOFT_LIGHT',
    'PHOS_BLEND_LINEAR_LIGHT',
    'PHOS_BLEND_DIFFERENCE',
    'PHOS_BLEND_EXCLUSION',
    'PHOS_BLEND_SUBTRACT',
    'PHOS_BLEND_DIVIDE',
    'PHOS_BLEND_HUE',
    'PHOS_BLEND_SATURATION',
    'PHOS_BLEND_VALUE',
    'PHOS_BLEND_COLOR',
    'PHOS_BLEND_COUNT',
    'PHOS_MAP_RANGE_LINEAR',
    'PHOS_MAP_RANGE_STEPPED',
    'PHOS_MAP_RANGE_SMOOTHSTEP',
    'PHOS_MAP_RANGE_SMOOTHERSTEP',
    'PHOS_MAP_RANGE_COUNT',
    'PHOS_CLAMP_MINMAX',
    'PHOS_CLAMP_RANGE',
    'PHOS_CLAMP_COUNT',
    'PHOS_COLOR_MODEL_RGB',
    'PHOS_COLOR_MODEL_HSV',
    'PHOS_COLOR_MODEL_HSL',
    'PHOS_COLOR_MODEL_COUNT',
    'PHOS_PROJECTION_FLAT',
    'PHOS_PROJECTION_BOX',
    'PHOS_PROJECTION_SPHERE',
    'PHOS_PROJECTION_TUBE',
    'PHOS_PROJECTION_EQUIRECTANGULAR',
    'PHOS_PROJECTION_MIRROR_BALL',
    'PHOS_PROJECTION_COUNT',
    'PHOS_IMAGE_LINEAR',
    'PHOS_IMAGE_CLOSEST',
    'PHOS_IMAGE_CUBIC',
    'PHOS_IMAGE_REPEAT',
    'PHOS_IMAGE_EXTEND',
    'PHOS_IMAGE_CLIP',
    'PHOS_IMAGE_MIRROR',
    'PHOS_IMAGE_UNASSOCIATE',
    'PHOS_NOISE_FBM',
    'PHOS_NOISE_MULTIFRACTAL',
    'PHOS_NOISE_HYBRID_MULTIFRACTAL',
    'PHOS_NOISE_RIDGED_MULTIFRACTAL',
    'PHOS_NOISE_HETERO_TERRAIN',
    'PHOS_NOISE_COUNT',
    'PHOS_VORONOI_F1',
    'PHOS_VORONOI_F2',
    'PHOS_VORONOI_SMOOTH_F1',
    'PHOS_VORONOI_DISTANCE_TO_EDGE',
    'PHOS_VORONOI_N_SPHERE_RADIUS',
    'PHOS_VORONOI_FEATURE_COUNT',
    'PHOS_VORONOI_EUCLIDEAN',
    'PHOS_VORONOI_MANHATTAN',
    'PHOS_VORONOI_CHEBYCHEV',
    'PHOS_VORONOI_MINKOWSKI',
    'PHOS_WAVE_BANDS',
    'PHOS_WAVE_RINGS',
    'PHOS_WAVE_TYPE_COUNT',
    'PHOS_WAVE_X',
    'PHOS_WAVE_Y',
    'PHOS_WAVE_Z',
    'PHOS_WAVE_DIAGONAL',
    'PHOS_WAVE_SPHERICAL',
    'PHOS_WAVE_SIN',
    'PHOS_WAVE_SAW',
    'PHOS_WAVE_TRI',
    'PHOS_GRADIENT_LINEAR',
    'PHOS_GRADIENT_QUADRATIC',
    'PHOS_GRADIENT_EASING',
    'PHOS_GRADIENT_DIAGONAL',
    'PHOS_GRADIENT_SPHERICAL',
    'PHOS_GRADIENT_QUADRATIC_SPHERE',
    'PHOS_GRADIENT_RADIAL',
    'PHOS_GRADIENT_COUNT',
    'PHOS_MAPPING_POINT',
    'PHOS_MAPPING_TEXTURE',
    'PHOS_MAPPING_VECTOR',
    'PHOS_MAPPING_NORMAL',
    'PHOS_MAPPING_COUNT',
    'PHOS_TANGENT_RADIAL_X',
    'PHOS_TANGENT_RADIAL_Y',
    'PHOS_TANGENT_RADIAL_Z',
    'PHOS_TANGENT_UV_MAP',
    'PHOS_TANGENT_COUNT',
    'PHOS_NORMAL_MAP_TANGENT',
    'PHOS_NORMAL_MAP_OBJECT',
    'PHOS_NORMAL_MAP_WORLD',
    'PHOS_NORMAL_MAP_COUNT',
    'PHOS_VECTOR_ROTATE_AXIS_ANGLE',
    'PHOS_VECTOR_ROTATE_X_AXIS',
    'PHOS_VECTOR_ROTATE_Y_AXIS',
    'PHOS_VECTOR_ROTATE_Z_AXIS',
    'PHOS_VECTOR_ROTATE_EULER_XYZ',
    'PHOS_VECTOR_ROTATE_COUNT',
    'PHOS_VECTOR_TRANSFORM_POINT',
    'PHOS_VECTOR_TRANSFORM_VECTOR',
    'PHOS_VECTOR_TRANSFORM_NORMAL',
    'PHOS_VECTOR_TRANSFORM_COUNT',
    'PHOS_SPACE_WORLD',
    'PHOS_SPACE_OBJECT',
    'PHOS_SPACE_CAMERA',
    'PHOS_SPACE_COUNT',
    'PHOS_SKY_SINGLE_SCATTERING',
    'PHOS_SKY_MULTIPLE_SCATTERING',
    'PHOS_SKY_PREETHAM',
    'PHOS_SKY_HOSEK_WILKIE',
    'PHOS_SKY_MODEL_COUNT',
    'PHOS_SKY_LAYOUT_HEMISPHERE',
    'PHOS_SKY_LAYOUT_SPHERE',
    'PHOS_SKY_LAYOUT_COUNT',
    'PHOS_FIELD_WEIGHT',
    'PHOS_FIELD_ROUGHNESS',
    'PHOS_FIELD_IOR',
    'PHOS_FIELD_SPECULAR_COLOR',
    'PHOS_FIELD_TRANSMISSION_TINT',
    'PHOS_FIELD_TRANSMISSION_ROUGHNESS',
    'PHOS_FIELD_MULTISCATTER_FRESNEL',
    'PHOS_FIELD_SPECULAR_TINT',
    'PHOS_FIELD_THIN_FILM_THICKNESS',
    'PHOS_FIELD_THIN_FILM_IOR',
    'PHOS_FIELD_LAYER_WEIGHT',
    'PHOS_FIELD_LAYER_TINT',
    'PHOS_FIELD_LAYER_TINT_WEIGHT',
    'PHOS_FIELD_NORMAL',
    'PHOS_FIELD_ROUGHNESS_Y',
    'PHOS_FIELD_TANGENT_ROTATION',
    'PHOS_FIELD_TANGENT',
    'PHOS_FIELD_COUNT',
    'PHOS_ATTRIBUTE_FLOAT',
    'PHOS_ATTRIBUTE_FLOAT2',
    'PHOS_ATTRIBUTE_VECTOR',
    'PHOS_ATTRIBUTE_COLOR',
    'PHOS_ATTRIBUTE_TYPE_COUNT',
    'PHOS_LIGHT_POINT',
    'PHOS_LIGHT_SPOT',
    'PHOS_LIGHT_AREA',
    'PHOS_LIGHT_SUN',
    'PHOS_LIGHT_PORTAL',
    'PHOS_AREA_RECTANGLE',
    'PHOS_AREA_ELLIPSE',
    'PHOS_POINT_DISK',
    'PHOS_POINT_SPHERE',
    'PHOS_CAMERA_PERSPECTIVE',
    'PHOS_CAMERA_ORTHOGRAPHIC',
    'PHOS_CHANGE_GEOMETRY',
    'PHOS_CHANGE_MATERIALS',
    'PHOS_CHANGE_LIGHTS',
    'PHOS_CHANGE_CAMERA',
    'PHOS_INTEGRATOR_PATH',
    'PHOS_INTEGRATOR_PHOTON',
    'PHOS_SAMPLER_SOBOL',
    'PHOS_SAMPLER_RANDOM',
    'PHOS_SAMPLER_STRATIFIED',
    'PHOS_SAMPLER_HALTON',
    'PHOS_NOISE_FILTER_NONE',
    'PHOS_NOISE_FILTER_LOWPASS',
    'PHOS_NOISE_FILTER_MEDIAN',
    'PHOS_NOISE_FILTER_ADAPTIVE_WIDTH',
    'PHOS_NOISE_FILTER_DIFFUSION',
    'PHOS_NOISE_FILTER_SPLATTING',
    'PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE',
    'PHOS_FILTER_TARGET_INDIRECT',
    'PHOS_FILTER_TARGET_ALL',
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
    'PHOS_PASS_GROUP_NOISE',
    'PHOS_PASS_KIND_COLOR',
    'PHOS_PASS_KIND_VECTOR',
    'PHOS_PASS_KIND_VALUE',
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
    'PHOS_PASS_SAMPLE_COUNT',
    'PHOS_PASS_NOISY_IMAGE',
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
    'PHOS_STAGE_FILTERING',
    'PHOS_STAGE_FINISHED',
    'PHOS_STAGE_COUNT',
    'PHOS_MAP_GLOBAL',
    'PHOS_MAP_CAUSTIC',
    'phos_image_desc',
    'phos_closure_desc',
    'phos_sky_desc',
    'phos_shader_instruction',
    'phos_shader_binding',
    'phos_shader_program_desc',
    'phos_material_desc',
    'phos_mesh_attribute',
    'phos_mesh_desc',
    'phos_instance_desc',
    'phos_instances_desc',
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
