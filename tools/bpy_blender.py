# SPDX-License-Identifier: GPL-3.0-or-later
"""`blender` for Blender as a Python module (the official `bpy` builds).

The `bpy` package on PyPI is Blender built as a Python module by the
Blender project, with the same Cycles (OpenImageDenoise, path guiding) as
the blender.org releases. It has no `blender` executable and does not
parse Blender's command line. This script does, for the options Phos's
tests, scenes, tools and benchmarks use, so that every one of them runs
unchanged against a `bpy` release through a wrapper (tools/bpy-env.sh
writes it as build/bpy/<version>/blender):

    python bpy_blender.py [options] [file.blend] [options] [-- script args]

Options are handled in the order given, as Blender does (a .blend is
loaded where it appears; -E, -o, -F, -x apply to the scene loaded then;
-f renders):

    -b, --background            (always: the module has no window)
    --factory-startup           factory settings and preferences, not the user's
                                (without it, the user's preferences are read first)
    --addons A[,B]              enable add-ons (by module name)
    FILE.blend                  open it
    -E ENGINE, -o PATH, -F FMT, -x 0|1, -t N
    -f N                        render frame N to the -o path, as `blender -b -f` does
    --python FILE, --python-expr CODE, --python-exit-code N
    --command extension ARGS    Blender's own extension command (install-file, validate)
    --version, -v
    --                          the rest is for the scripts (sys.argv keeps it all)

What differs from Blender's own parser is said here, since tests run
through it: an engine's ERROR report during -f makes the frame fail and
the process exit 1 (Blender prints the same report and exits 1 as well);
options not listed above are refused (exit 2), never ignored.
"""

import os
import sys
import traceback


class Usage(Exception):
    pass


def _take(argv, i, option):
    if i + 1 >= len(argv):
        raise Usage("option %s needs a value" % option)
    return argv[i + 1]


def _scene():
    import bpy
    return bpy.context.scene


def _run_python(code, filename, exit_code):
    """Run a script as Blender's --python does: __name__ '__main__', errors printed."""
    namespace = {"__name__": "__main__", "__file__": filename, "__builtins__": __builtins__}
    try:
        exec(compile(code, filename, "exec"), namespace)
    except SystemExit:
        raise
    except BaseException:
        traceback.print_exc()
        if exit_code:
            sys.stdout.flush()
            sys.exit(exit_code)


def _render_frame(frame):
    """`-f N`: render frame N and save it to the output path (frame number
    substituted for the #s, extension added when use_file_extension)."""
    import bpy
    scene = _scene()
    scene.frame_set(frame)
    path = bpy.path.abspath(scene.render.frame_path(frame=frame))
    scene.render.filepath = path
    scene.render.use_file_extension = False
    try:
        bpy.ops.render.render(write_still=True, scene=scene.name)
    except RuntimeError as ex:
        # Blender has printed the reports ("Error: ..."); say it as blender -b does.
        message = str(ex).strip()
        if not any(line.startswith("Error:") for line in message.splitlines()):
            message = "Error: " + message
        print(message, flush=True)
        return False
    print("Saved: '%s'" % path, flush=True)
    return True


def _set_file_format(image_settings, name):
    """-F: Blender 5 chooses a multilayer EXR by media type, and single-layer
    formats only when the media type is an image."""
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = 'MULTI_LAYER_IMAGE' if name == 'OPEN_EXR_MULTILAYER' else 'IMAGE'
        if name == 'OPEN_EXR_MULTILAYER':
            return
    image_settings.file_format = name


def _enable_addons(names):
    import addon_utils
    for name in names.split(","):
        name = name.strip()
        if name and addon_utils.enable(name, default_set=True) is None:
            print("Error: add-on '%s' could not be enabled" % name, flush=True)


def _extension_command(args):
    """Blender's `--command extension ...`, through the handler Blender registers."""
    import addon_utils
    module = sys.modules.get("bl_pkg") or addon_utils.enable("bl_pkg", default_set=False)
    if module is None:
        print("Error: Blender's extension add-on (bl_pkg) is not available", flush=True)
        return 1
    return int(module.cli_extension(args) or 0)


def main(argv):
    if "--" in argv:
        cut = argv.index("--")
        own, script_args = argv[:cut], argv[cut:]
    else:
        own, script_args = argv, []
    if "--version" in own or "-v" in own:
        import bpy
        print("Blender %s" % bpy.app.version_string)
        return 0
    if own[:1] == ["--command"] or own[1:2] == ["--command"]:
        i = own.index("--command")
        if own[i + 1:i + 2] != ["extension"]:
            raise Usage("only '--command extension' is supported")
        import bpy  # noqa: F401  (loads Blender)
        return _extension_command(own[i + 2:])

    # Blender's own sys.argv holds the whole command line: scripts look for '--'.
    sys.argv = [sys.argv[0]] + argv
    import bpy
    if "--factory-startup" not in own:
        # Blender starts with the user's preferences (and the add-ons and
        # extensions they enable); the module starts with the factory ones.
        bpy.ops.wm.read_userpref()
    exit_code = 0
    status = 0
    i = 0
    while i < len(own):
        a = own[i]
        if a in ("-b", "--background", "--python-use-system-env", "--disable-autoexec",
                 "--enable-autoexec", "-noaudio"):
            pass
        elif a == "--factory-startup":
            pass  # the module's own start: factory settings, no user preferences
        elif a == "--addons":
            _enable_addons(_take(own, i, a))
            i += 1
        elif a == "--python-exit-code":
            exit_code = int(_take(own, i, a))
            i += 1
        elif a in ("--python", "-P"):
            path = _take(own, i, a)
            with open(path, encoding="utf-8") as f:
                _run_python(f.read(), path, exit_code)
            i += 1
        elif a == "--python-expr":
            _run_python(_take(own, i, a), "<string>", exit_code)
            i += 1
        elif a == "-E":
            _scene().render.engine = _take(own, i, a)
            i += 1
        elif a == "-o":
            _scene().render.filepath = _take(own, i, a)
            i += 1
        elif a == "-F":
            _set_file_format(_scene().render.image_settings, _take(own, i, a))
            i += 1
        elif a == "-x":
            _scene().render.use_file_extension = bool(int(_take(own, i, a)))
            i += 1
        elif a == "-t":
            threads = int(_take(own, i, a))
            r = _scene().render
            r.threads_mode = "AUTO" if threads == 0 else "FIXED"
            if threads:
                r.threads = threads
            i += 1
        elif a == "-f":
            if not _render_frame(int(_take(own, i, a))):
                status = 1
            i += 1
        elif a.endswith(".blend") and not a.startswith("-"):
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(a))
        else:
            raise Usage("option %r is not supported by this bpy launcher" % a)
        i += 1
    return status


if __name__ == "__main__":
    try:
        code = main(sys.argv[1:])
    except SystemExit as ex:  # a script's sys.exit(code), e.g. run_tests.py's
        code = ex.code if isinstance(ex.code, int) else (0 if ex.code is None else 1)
    except Usage as ex:
        print("bpy_blender: %s" % ex, file=sys.stderr, flush=True)
        code = 2
    sys.stdout.flush()
    sys.stderr.flush()
    # Leave at once, as Blender does after its last option: the module's
    # interpreter teardown with the C threads of an add-on still loaded is
    # not what is being tested.
    os._exit(code)
