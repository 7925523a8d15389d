# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of libphos, core/include/phos.h.

This is the lowest module of the add-on; it imports nothing from bpy, so it
can be tested in a plain Python with numpy. The header's constants, structs,
function signatures and render settings table come from phos_h.py, which
tools/gen_binding.py generates from phos.h (`make binding`); this module
adds loading, checking and the handle owners.

The library is found beside this file (``lib/libphos.so``) or at the path in
the environment variable ``PHOS_LIBRARY``. Loading checks the library's
version, the size of every public struct and the offset and size of every
field against phos_h.py, so a stale or mismatched build is refused with a
readable message naming the struct and field instead of corrupting memory.
A failed load never raises at import: the message is kept (``load_error()``)
for the preferences panel and the render report.

On top of the raw functions sit two small owners, :class:`Scene` and
:class:`Render`, that raise :class:`PhosError` with the core's own message on
a failed call and free their handle deterministically (``close()`` or a
``with`` block), because a render engine must not rely on garbage collection
to release gigabytes of BVH and film.
"""

import ctypes
import os
import threading

import numpy as np

# The constants, enums and structs of phos.h (core.PHOS_*, core.phos_*),
# the functions' signatures (FUNCTIONS) and the render settings table
# (RENDER_SETTINGS), generated from the header by tools/gen_binding.py.
from .phos_h import *  # noqa: F401,F403
from .phos_h import FUNCTIONS, STRUCTS

# How often a commit running on its worker thread asks whether to stop (s).
COMMIT_POLL_SECONDS = 0.05

# The library version this add-on was written against: major and minor must
# match exactly (phos.h: "The add-on refuses a library whose major or minor
# differs from its own").
EXPECTED_VERSION = (PHOS_VERSION_MAJOR, PHOS_VERSION_MINOR)

_u32 = ctypes.c_uint32
_vp = ctypes.c_void_p

# ------------------------------------------------------------------ loading

LIBRARY_ENV = "PHOS_LIBRARY"
LIBRARY_NAME = "libphos.so"

_lock = threading.Lock()
_lib = None
_load_error = ""
_loaded_path = ""


class PhosError(RuntimeError):
    """A libphos call failed; the message is the core's own explanation."""

    def __init__(self, message, status=None):
        super().__init__(message)
        self.status = status


def library_path():
    """Where the library is looked for: $PHOS_LIBRARY, else lib/ beside this file."""
    override = os.environ.get(LIBRARY_ENV, "").strip()
    if override:
        return override
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib", LIBRARY_NAME)


def _bind(lib):
    """Declare argtypes/restype of every function; a missing symbol is an error."""
    for name, (restype, argtypes) in FUNCTIONS.items():
        try:
            fn = getattr(lib, name)
        except AttributeError:
            raise PhosError("the library has no function %s() (built from an older phos.h?)" % name)
        fn.restype = restype
        fn.argtypes = argtypes


def _check_version(lib):
    """Refuse a library of another major.minor version. Asked before the
    functions are bound: another version may lack some, and its version
    is the clearer message."""
    try:
        version = lib.phos_version
    except AttributeError:
        raise PhosError("the library has no function phos_version() (not a Phos library?)")
    version.restype, version.argtypes = ctypes.c_uint32, []
    v = version()
    major, minor, patch = (v >> 16) & 0xFFFF, (v >> 8) & 0xFF, v & 0xFF
    if (major, minor) != EXPECTED_VERSION:
        raise PhosError("library version %d.%d.%d, but this add-on needs %d.%d.x"
                        % (major, minor, patch, EXPECTED_VERSION[0], EXPECTED_VERSION[1]))


def _check(lib):
    """Refuse a library whose struct layouts differ from this binding:
    the size of every struct, and the offset and size of every field."""
    stale = "the library was built from a different phos.h"
    for struct in STRUCTS:
        name = struct.__name__
        size = lib.phos_struct_size(name.encode("ascii"))
        if size != ctypes.sizeof(struct):
            raise PhosError("struct %s is %d bytes in the library but %d in the add-on: %s"
                            % (name, size, ctypes.sizeof(struct), stale))
        for field, _type in struct._fields_:
            offset, fsize = _u32(), _u32()
            if lib.phos_struct_field(name.encode("ascii"), field.encode("ascii"),
                                     ctypes.byref(offset), ctypes.byref(fsize)) != PHOS_OK:
                raise PhosError("struct %s has no field %s in the library: %s" % (name, field, stale))
            mine = getattr(struct, field)
            if (offset.value, fsize.value) != (mine.offset, mine.size):
                raise PhosError("field %s.%s is at offset %d (%d bytes) in the library but at %d "
                                "(%d bytes) in the add-on: %s" % (name, field, offset.value, fsize.value,
                                                                  mine.offset, mine.size, stale))


def load():
    """Load and check the library once; return it, or None after a failure.

    A failed attempt is retried on the next call (the library may have been
    built since); a successful one is kept for the life of the process, since
    a shared library cannot be safely unloaded while Blender runs.
    """
    global _lib, _load_error, _loaded_path
    with _lock:
        if _lib is not None:
            return _lib
        path = library_path()
        try:
            if not os.path.isfile(path):
                raise PhosError("%s not found (build the core with CMake, or set %s)"
                                % (path, LIBRARY_ENV))
            try:
                lib = ctypes.CDLL(path)
            except OSError as ex:
                raise PhosError("cannot load %s: %s" % (path, ex))
            _check_version(lib)
            _bind(lib)
            _check(lib)
        except PhosError as ex:
            _load_error = "Phos core library: %s" % ex
            return None
        except Exception as ex:  # never let a broken library take the add-on down
            _load_error = "Phos core library: unexpected error loading %s: %r" % (path, ex)
            return None
        _lib, _load_error, _loaded_path = lib, "", path
        return _lib


def load_error():
    """The message of the last failed load, "" if the library is loaded or untried."""
    return _load_error


def loaded_path():
    """Path of the loaded library, "" if none is loaded."""
    return _loaded_path


def lib():
    """The loaded library, loading it if needed; raises PhosError if unavailable."""
    l = load()
    if l is None:
        raise PhosError(_load_error)
    return l


def version_string():
    """"major.minor.patch" of the loaded library, "" if none."""
    if _lib is None:
        return ""
    v = _lib.phos_version()
    return "%d.%d.%d" % ((v >> 16) & 0xFFFF, (v >> 8) & 0xFF, v & 0xFF)


# ------------------------------------------------------------------ helpers

def _decode(b):
    return b.decode("utf-8", "replace") if b else ""


def status_string(status):
    l = lib()
    return _decode(l.phos_status_string(status))


def _as_array(a, dtype, count, what):
    """A C-contiguous numpy array of dtype with exactly `count` elements."""
    arr = np.ascontiguousarray(a, dtype=dtype).reshape(-1)
    if arr.size != count:
        raise PhosError("%s has %d values, expected %d" % (what, arr.size, count))
    return arr


def _ptr(arr, ctype):
    return arr.ctypes.data_as(ctypes.POINTER(ctype)) if arr is not None else None


def matrix_to_3x4(matrix):
    """Row-major 3x4 (the top three rows) of a 4x4 matrix as 12 floats."""
    m = np.asarray(matrix, dtype=np.float64).reshape(4, 4)
    return tuple(float(x) for x in m[:3, :4].reshape(-1))


def new_closure():
    """A phos_closure_desc with the library's defaults."""
    d = phos_closure_desc()
    lib().phos_closure_desc_init(ctypes.byref(d))
    return d


def new_light():
    d = phos_light_desc()
    lib().phos_light_desc_init(ctypes.byref(d))
    return d


def new_camera():
    d = phos_camera_desc()
    lib().phos_camera_desc_init(ctypes.byref(d))
    return d


def new_world():
    d = phos_world_desc()
    lib().phos_world_desc_init(ctypes.byref(d))
    return d


def sky_bake(fields, texture=True):
    """The Sky Texture computed once (phos.h, phos_sky_bake): (pixels,
    width, height, data) for a phos_sky_desc with `fields` set over the
    library's defaults; pixels (float32 RGBA) None for the analytic models,
    or without `texture`."""
    l = lib()
    d = phos_sky_desc()
    l.phos_sky_desc_init(ctypes.byref(d))
    for name, value in fields.items():
        if name == "sun_direction":
            d.sun_direction[:] = [float(v) for v in value]
        else:
            setattr(d, name, value)
    w, h = _u32(), _u32()
    status = l.phos_sky_texture_size(ctypes.byref(d), ctypes.byref(w), ctypes.byref(h))
    pixels = None
    if status == PHOS_OK and texture and w.value:
        pixels = np.empty(w.value * h.value * 4, dtype=np.float32)
    data = np.zeros(PHOS_SKY_DATA_FLOATS, dtype=np.float32)
    if status == PHOS_OK:
        status = l.phos_sky_bake(ctypes.byref(d), _ptr(pixels, ctypes.c_float), _ptr(data, ctypes.c_float))
    if status != PHOS_OK:
        raise PhosError("the sky's settings are out of range: %s" % status_string(status), status)
    return pixels, w.value, h.value, data


def new_render_settings():
    d = phos_render_settings()
    lib().phos_render_settings_init(ctypes.byref(d))
    return d


def settings_stages(settings):
    """The stages (enum phos_stage) a render with these settings runs, in
    order: the core's plan, without making a render."""
    ids = (ctypes.c_uint32 * PHOS_STAGE_COUNT)()
    n = _u32()
    if lib().phos_settings_stages(ctypes.byref(settings), ids, PHOS_STAGE_COUNT, ctypes.byref(n)) != PHOS_OK:
        raise PhosError("reading the plan of the settings")
    return list(ids[:min(n.value, PHOS_STAGE_COUNT)])


# -------------------------------------------------------------------- scene

class _Handle:
    """What both handle owners share: close() frees the handle once (also on
    leaving a `with` block, and as a last resort when garbage collected), and
    a failed call raises PhosError with the message the core left on it."""

    _kind = "handle"
    _handle = None

    @property
    def handle(self):
        if not self._handle:
            raise PhosError("the %s was already closed" % self._kind, PHOS_ERROR_INVALID_STATE)
        return self._handle

    def close(self):
        if self._handle:
            handle, self._handle = self._handle, None
            self._destroy(handle)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        # Safety net only; owners call close() deterministically.
        try:
            self.close()
        except Exception:
            pass

    def _raise_on(self, status, what):
        if status != PHOS_OK:
            msg = self._error_text(self._handle) or _decode(self._lib.phos_status_string(status))
            raise PhosError("%s: %s" % (what, msg), status)

    def error(self):
        return self._error_text(self.handle)


class Scene(_Handle):
    """Owner of a phos_scene handle.

    Use as a context manager or call close(); every add_* returns the new
    id and raises PhosError with phos_scene_error() on failure. Array
    arguments are converted to C-contiguous float32/uint32 and only need to
    live during the call (the core copies them).
    """

    _kind = "scene"

    def __init__(self):
        self._lib = lib()
        self._handle = self._lib.phos_scene_create()
        if not self._handle:
            raise PhosError("out of memory creating a scene", PHOS_ERROR_OUT_OF_MEMORY)

    def _destroy(self, handle):
        self._lib.phos_scene_destroy(handle)

    def _error_text(self, handle):
        return _decode(self._lib.phos_scene_error(handle))

    def add_image(self, pixels, width, height):
        """Add linear RGBA float pixels (rows bottom-up, straight alpha);
        returns the image id."""
        px = _as_array(pixels, np.float32, width * height * 4, "image pixels")
        d = phos_image_desc()
        self._lib.phos_image_desc_init(ctypes.byref(d))
        d.width, d.height = width, height
        d.pixels = _ptr(px, ctypes.c_float)
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_image(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding an image")
        return out.value

    def add_material(self, closures, program=None):
        """Add a material from a sequence of phos_closure_desc and, when its
        closures vary over the surface, the shader program that sets them
        (a phos_shader_program_desc whose arrays the caller keeps alive);
        returns its id."""
        d, arr = self._material_desc(closures, program)
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_material(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding a material")
        return out.value

    def update_material(self, material_id, closures, program=None):
        """Replace material `material_id` (phos_scene_update_material): the
        scene must be committed with no render holding it, or still open."""
        d, arr = self._material_desc(closures, program)
        self._raise_on(self._lib.phos_scene_update_material(self.handle, material_id, ctypes.byref(d)),
                       "changing a material")

    def _material_desc(self, closures, program):
        """(phos_material_desc, the closure array it points into)."""
        n = len(closures)
        arr = (phos_closure_desc * max(n, 1))(*closures)
        d = phos_material_desc()
        self._lib.phos_material_desc_init(ctypes.byref(d))
        d.closure_count = n
        d.closures = ctypes.cast(arr, ctypes.POINTER(phos_closure_desc)) if n else None
        d.program = ctypes.pointer(program) if program is not None else None
        return d, arr

    def _mesh_desc(self, positions, indices, normals=None, uvs=None, material_slots=None, tangents=None,
                   texspace=None, attributes=()):
        """A phos_mesh_desc of the arrays, and what keeps its arrays alive."""
        pos = np.ascontiguousarray(positions, dtype=np.float32).reshape(-1)
        idx = np.ascontiguousarray(indices, dtype=np.uint32).reshape(-1)
        if pos.size % 3 or idx.size % 3:
            raise PhosError("mesh arrays must hold whole vertices and triangles")
        v, t = pos.size // 3, idx.size // 3
        nrm = _as_array(normals, np.float32, t * 9, "normals") if normals is not None else None
        uv = _as_array(uvs, np.float32, t * 6, "uvs") if uvs is not None else None
        slots = _as_array(material_slots, np.uint32, t, "material slots") \
            if material_slots is not None else None
        tan = _as_array(tangents, np.float32, t * 12, "tangents") if tangents is not None else None
        d = phos_mesh_desc()
        self._lib.phos_mesh_desc_init(ctypes.byref(d))
        d.vertex_count, d.positions = v, _ptr(pos, ctypes.c_float)
        d.triangle_count, d.indices = t, _ptr(idx, ctypes.c_uint32)
        d.normals = _ptr(nrm, ctypes.c_float)
        d.uvs = _ptr(uv, ctypes.c_float)
        d.material_slots = _ptr(slots, ctypes.c_uint32)
        d.tangents = _ptr(tan, ctypes.c_float)
        attr_values = [_as_array(values, np.float32, t * 12, "attribute values") for _, _, values in attributes]
        attrs = (phos_mesh_attribute * max(len(attr_values), 1))()
        for k, ((attr_id, kind, _), values) in enumerate(zip(attributes, attr_values)):
            attrs[k].id, attrs[k].type, attrs[k].values = attr_id, kind, _ptr(values, ctypes.c_float)
        d.attribute_count = len(attr_values)
        d.attributes = ctypes.cast(attrs, ctypes.POINTER(phos_mesh_attribute)) if attr_values else None
        if texspace is not None:
            d.texspace_location[:] = [float(x) for x in texspace[0]]
            d.texspace_size[:] = [float(x) for x in texspace[1]]
        return d, (pos, idx, nrm, uv, slots, tan, attr_values, attrs)

    def add_mesh(self, *arrays, **named):
        """Add a triangle mesh in object space; returns the mesh id.

        positions (V*3), indices (T*3), per-corner normals (T*9) and UVs (T*6),
        per-triangle slots (T), tangents (T*12), texspace ((location, size));
        the optional ones may be None. attributes: (id, enum
        phos_attribute_type, T*12 per-corner values) each.
        """
        d, _keep = self._mesh_desc(*arrays, **named)
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_mesh(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding a mesh")
        return out.value

    def update_mesh(self, mesh_id, *arrays, **named):
        """Replace mesh `mesh_id` (phos_scene_update_mesh) by the arrays, as add_mesh takes them."""
        d, _keep = self._mesh_desc(*arrays, **named)
        self._raise_on(self._lib.phos_scene_update_mesh(self.handle, mesh_id, ctypes.byref(d)),
                       "replacing a mesh")

    def _instance_desc(self, mesh_id, transform, materials, random, pass_index):
        mats = np.ascontiguousarray(materials, dtype=np.uint32).reshape(-1)
        d = phos_instance_desc()
        self._lib.phos_instance_desc_init(ctypes.byref(d))
        d.mesh_id = mesh_id
        d.transform[:] = [float(x) for x in transform]
        d.material_count = mats.size
        d.materials = _ptr(mats, ctypes.c_uint32) if mats.size else None
        d.random, d.pass_index = float(random), float(pass_index)
        return d, mats

    def add_instance(self, mesh_id, transform, materials, random=0.0, pass_index=0.0):
        """Place a mesh with a row-major 3x4 transform and per-slot material ids
        (random and pass_index: what Object Info reads)."""
        d, _keep = self._instance_desc(mesh_id, transform, materials, random, pass_index)
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_instance(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding an instance")
        return out.value

    def update_instance(self, instance_id, mesh_id, transform, materials, random=0.0, pass_index=0.0):
        """Replace instance `instance_id` (phos_scene_update_instance), as add_instance takes it."""
        d, _keep = self._instance_desc(mesh_id, transform, materials, random, pass_index)
        self._raise_on(self._lib.phos_scene_update_instance(self.handle, instance_id, ctypes.byref(d)),
                       "replacing an instance")

    def add_instances(self, mesh_ids, transforms, material_lists, randoms, pass_indices):
        """Add many instances in one call (phos_scene_add_instances): mesh ids,
        row-major 3x4 transforms as an (n, 12) array, a sequence of material
        id lists, and Object Info's random and pass index per instance.
        Returns the first instance's id. A refusal adds none, and its message
        names the instance by its index ("instance 7 of 1000: ...")."""
        n = len(mesh_ids)
        ids = np.ascontiguousarray(mesh_ids, dtype=np.uint32)
        xf = np.ascontiguousarray(transforms, dtype=np.float32).reshape(n, 12)
        counts = np.fromiter((len(m) for m in material_lists), dtype=np.uint32, count=n)
        offsets = np.zeros(n + 1, dtype=np.uint32)
        np.cumsum(counts, out=offsets[1:])
        mats = np.fromiter((m for ms in material_lists for m in ms), dtype=np.uint32, count=int(offsets[-1]))
        rnd = np.ascontiguousarray(randoms, dtype=np.float32)
        idx = np.ascontiguousarray(pass_indices, dtype=np.float32)
        d = phos_instances_desc()
        d.count = n
        d.mesh_ids = _ptr(ids, ctypes.c_uint32)
        d.transforms = _ptr(xf, ctypes.c_float)
        d.material_offsets = _ptr(offsets, ctypes.c_uint32)
        d.materials = _ptr(mats, ctypes.c_uint32) if mats.size else None
        d.randoms = _ptr(rnd, ctypes.c_float)
        d.pass_indices = _ptr(idx, ctypes.c_float)
        first = _u32()
        self._raise_on(self._lib.phos_scene_add_instances(self.handle, ctypes.byref(d), ctypes.byref(first)),
                       "adding instances")
        return first.value

    def add_light(self, desc):
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_light(self.handle, ctypes.byref(desc), ctypes.byref(out)),
                       "adding a light")
        return out.value

    def update_light(self, light_id, desc):
        self._raise_on(self._lib.phos_scene_update_light(self.handle, light_id, ctypes.byref(desc)),
                       "changing a light")

    def set_world(self, desc):
        self._raise_on(self._lib.phos_scene_set_world(self.handle, ctypes.byref(desc)),
                       "setting the world")

    def set_camera(self, desc):
        self._raise_on(self._lib.phos_scene_set_camera(self.handle, ctypes.byref(desc)),
                       "setting the camera")

    def commit(self, cancelled=None):
        """Build the BVH and light tables; False if `cancelled` stopped it.

        A large scene's BVH takes seconds. With `cancelled` (a callable,
        the engine's test_break), the build runs on a worker thread (ctypes
        releases the GIL for the call) while this thread asks `cancelled`
        every COMMIT_POLL_SECONDS and, when it says so, calls
        phos_scene_cancel: the core then returns within a fraction of a
        second (tests/c/test_cancel.c measures it), which bounds the join.
        """
        if cancelled is None:
            self._raise_on(self._lib.phos_scene_commit(self.handle), "building the scene")
            return True
        result = {}

        def build():
            result["status"] = self._lib.phos_scene_commit(self.handle)

        worker = threading.Thread(target=build, name="phos-commit", daemon=True)
        worker.start()
        asked = False
        while worker.is_alive():
            worker.join(COMMIT_POLL_SECONDS)
            if worker.is_alive() and not asked and cancelled():
                self._lib.phos_scene_cancel(self.handle)
                asked = True
        status = result.get("status", PHOS_ERROR_INTERNAL)
        if status == PHOS_ERROR_CANCELLED:
            return False
        self._raise_on(status, "building the scene")
        return True

    def cancel(self):
        """Stop a commit running on another thread (phos_scene_cancel)."""
        self._lib.phos_scene_cancel(self.handle)


def vertex_normals(positions, loop_starts, loop_totals, polygon_normals, loop_vertices):
    """Angle-weighted vertex normals (V*3 float32) of a polygon mesh, the
    same for the same input (phos_vertex_normals): positions V*3, per
    polygon its first loop, corner count and unit normal (P*3), and each
    loop's vertex. Raises PhosError for an invalid mesh."""
    pos = np.ascontiguousarray(positions, dtype=np.float32).reshape(-1)
    starts = np.ascontiguousarray(loop_starts, dtype=np.uint32).reshape(-1)
    totals = np.ascontiguousarray(loop_totals, dtype=np.uint32).reshape(-1)
    normals = np.ascontiguousarray(polygon_normals, dtype=np.float32).reshape(-1)
    loops = np.ascontiguousarray(loop_vertices, dtype=np.uint32).reshape(-1)
    if pos.size % 3 or starts.size != totals.size or normals.size != 3 * starts.size:
        raise PhosError("vertex normals: arrays of mismatched sizes", PHOS_ERROR_INVALID_ARGUMENT)
    out = np.empty(pos.size, dtype=np.float32)
    status = lib().phos_vertex_normals(pos.size // 3, _ptr(pos, ctypes.c_float), starts.size,
                                       _ptr(starts, ctypes.c_uint32), _ptr(totals, ctypes.c_uint32),
                                       _ptr(normals, ctypes.c_float), loops.size,
                                       _ptr(loops, ctypes.c_uint32), _ptr(out, ctypes.c_float))
    if status != PHOS_OK:
        raise PhosError("vertex normals: %s" % _decode(lib().phos_status_string(status)), status)
    return out


# ------------------------------------------------------------------- render

class PhotonMaps(_Handle):
    """A reference to photon maps kept between renders of one scene
    (Render.keep_photon_maps, Render.use_photon_maps); close() releases it,
    and the maps go with their last holder."""

    _kind = "photon maps"

    def __init__(self, library, handle):
        self._lib = library
        self._handle = handle

    def _destroy(self, handle):
        self._lib.phos_photon_maps_release(handle)

    def _error_text(self, handle):
        return ""


class Render(_Handle):
    """Owner of a phos_render handle created from a committed Scene.

    The core runs its own threads; every method here returns quickly except
    wait(). cancel() is safe from any thread.
    """

    _kind = "render"

    def __init__(self, scene, settings):
        self._lib = lib()
        self._handle = None
        out = _vp()
        status = self._lib.phos_render_create(scene.handle, ctypes.byref(settings), ctypes.byref(out))
        if status != PHOS_OK:
            # The message of a failed create is put on the scene.
            msg = _decode(self._lib.phos_scene_error(scene.handle)) or \
                _decode(self._lib.phos_status_string(status))
            raise PhosError("creating the render: %s" % msg, status)
        self._handle = out.value
        self.settings = settings
        self._channels = {}

    def _destroy(self, handle):
        # A running render is cancelled and joined before it is freed.
        self._lib.phos_render_cancel(handle)
        self._lib.phos_render_wait(handle, -1.0)
        self._lib.phos_render_destroy(handle)

    def _error_text(self, handle):
        return _decode(self._lib.phos_render_error(handle))

    def set_cache_file(self, kind, path, mode):
        """Save the cache to `path` after computing it, or read it from there
        (enum phos_cache_kind, enum phos_cache_file_mode); before start()."""
        self._raise_on(self._lib.phos_render_set_cache_file(self.handle, kind, os.fsencode(path), mode),
                       "setting the cache file")

    def add_view(self, camera):
        """Before start(): a further view (a core camera, new_camera()) the
        photon maps are aimed at and the irradiance cache is filled from,
        after the scene's camera (a farm's cache job, docs/farm.md)."""
        self._raise_on(self._lib.phos_render_add_view(self.handle, ctypes.byref(camera)), "adding a view")

    def keep_photon_maps(self):
        """The photon maps of this render as a PhotonMaps that outlives it,
        once its photon stages have finished; None before that, or for a
        render that uses no maps."""
        out = _vp()
        status = self._lib.phos_render_keep_photon_maps(self.handle, ctypes.byref(out))
        if status == PHOS_ERROR_INVALID_STATE:
            return None
        self._raise_on(status, "keeping the photon maps")
        return PhotonMaps(self._lib, out.value)

    def use_photon_maps(self, maps, any_view=False):
        """Before start(): read `maps` (kept from an earlier render) instead
        of tracing. Returns False, with the reason in error(), when the core
        refuses them: another scene or version of it, other settings, or
        (unless any_view) photons aimed at another view."""
        status = self._lib.phos_render_use_photon_maps(self.handle, maps.handle, 1 if any_view else 0)
        if status == PHOS_ERROR_INVALID_ARGUMENT:
            return False
        self._raise_on(status, "using kept photon maps")
        return True

    def start(self):
        self._raise_on(self._lib.phos_render_start(self.handle), "starting the render")

    def stages(self):
        """The plan of this render, fixed at create: (enum phos_stage, name) per
        stage in running order, WAITING first and FINISHED last."""
        infos = (phos_stage_info * PHOS_STAGE_COUNT)()
        n = _u32()
        self._raise_on(self._lib.phos_render_stages(self.handle, infos, PHOS_STAGE_COUNT, ctypes.byref(n)),
                       "reading the stages")
        return [(info.id, _decode(info.name)) for info in infos[:min(n.value, PHOS_STAGE_COUNT)]]

    def progress(self):
        p = phos_progress()
        self._raise_on(self._lib.phos_render_progress(self.handle, ctypes.byref(p)),
                       "reading progress")
        return p

    def next_tile(self):
        """The next finished tile (full-frame coordinates), or None."""
        t = phos_tile()
        n = _u32()
        self._raise_on(self._lib.phos_render_next_tile(self.handle, ctypes.byref(t), ctypes.byref(n)),
                       "reading finished tiles")
        return t if n.value else None

    def channels(self, pass_id):
        c = self._channels.get(pass_id)
        if c is None:
            c = self._channels[pass_id] = int(self._lib.phos_pass_channels(pass_id))
        return c

    def read(self, pass_id, x, y, width, height, out=None):
        """Pixels of a pass as a float32 array shaped (width*height, channels).

        Rows bottom-up, as Blender's render result wants them; `out` may be a
        preallocated C-contiguous float32 array of that shape.
        """
        ch = self.channels(pass_id)
        if ch == 0:
            raise PhosError("unknown pass %d" % pass_id, PHOS_ERROR_INVALID_ARGUMENT)
        shape = (width * height, ch)
        if out is None or out.shape != shape or out.dtype != np.float32 or not out.flags.c_contiguous:
            out = np.empty(shape, dtype=np.float32)
        self._raise_on(self._lib.phos_render_read(self.handle, pass_id, x, y, width, height,
                                                  _ptr(out, ctypes.c_float), out.size),
                       "reading pixels")
        return out

    def cancel(self):
        if self._handle:
            self._lib.phos_render_cancel(self._handle)

    def wait(self, timeout_seconds=-1.0):
        """Returns the status: PHOS_OK, PHOS_ERROR_CANCELLED or PHOS_ERROR_TIMEOUT.

        Any other status (a failed render) raises PhosError.
        """
        status = self._lib.phos_render_wait(self.handle, float(timeout_seconds))
        if status not in (PHOS_OK, PHOS_ERROR_CANCELLED, PHOS_ERROR_TIMEOUT):
            self._raise_on(status, "rendering")
        return status
