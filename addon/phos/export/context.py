# SPDX-License-Identifier: GPL-3.0-or-later
"""State shared by the exporters of one frame.

An ExportContext lives for one render() call: it holds the core scene being
filled, the caches that make each Blender datablock exported once (meshes,
materials, images), and the warnings to show in Blender's report. It is
the only thing the export modules pass around, so none of them needs
bpy.context (which must not be touched from a final render).
"""

import bpy


class ExportContext:
    def __init__(self, scene, core_scene, is_preview=False):
        self.scene = scene                  # evaluated bpy.types.Scene
        self.core = core_scene              # core.Scene being filled
        self.is_preview = is_preview
        self.cancelled = False              # set when the export was stopped early
        self.version = tuple(bpy.app.version)
        self._warnings = {}                 # message → None, ordered and deduplicated
        # Caches: Blender datablock → core id, so each is added once per frame.
        self.meshes = {}                    # geometry key → mesh id, or None for no triangles
        self.materials = {}                 # material pointer → material id
        self.light_ids = {}                 # light object pointer → core light ids (None: instanced, or none)
        self.object_shading = {}            # object pointer → instances.object_shading when exported
        # What lets an edit of an object be applied in place (instances.py,
        # move_object, reshape_objects): the core instances of each object
        # placed as itself (None: not placed), the objects that are
        # instanced or instance others, the core meshes instances use, each
        # core mesh's objects, and the objects a material reads the place of.
        self.object_instances = {}          # object pointer → [instances._Placed] or None
        self.instanced = set()
        self.instanced_meshes = set()
        self.mesh_users = {}                # mesh id → {object pointer}
        self.referenced_objects = set()
        self.images = {}                    # image pointer → image id or None
        self.tangents_wanted = False        # a material reads tangents (a Normal Map in tangent space)
        self.view_layer = None              # the view layer rendered (its properties: Attribute nodes)
        self.attribute_ids = {}             # attribute key → the number programs read it by (mesh_attributes.py)
        self.material_attributes = {}       # material id → the attribute keys its program reads
        self.image_pixels = {}              # image pointer → (pixels, width, height) or None
        self.default_material = None        # id of the grey default, added on first use
        self.world_emits = False            # the world's colour is not black
        self.world_material = None          # core material id of the world's node tree, once added
        self.stats = {"objects": 0, "instances": 0, "meshes": 0, "triangles": 0,
                      "lights": 0, "portals": 0, "materials": 0, "images": 0, "emissive_materials": 0}

    def at_least(self, major, minor=0):
        """True when the running Blender is version major.minor or later."""
        return self.version[:2] >= (major, minor)

    def warn(self, message):
        """Queue a warning for Blender's report; duplicates are dropped."""
        self._warnings.setdefault(message, None)

    @property
    def warnings(self):
        return list(self._warnings)
