#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Write the add-on's binding of libphos from the public header.

    tools/gen_binding.py [--header core/include/phos.h] [--output addon/phos/phos_h.py]

(`make binding`; `make test` regenerates into a temporary file and fails if
it differs from the committed one). The output holds what ctypes needs to
know of phos.h: the #define and enum constants, the structs as
ctypes.Structure classes, the functions' (restype, argtypes), and the render
settings table PHOS_RENDER_SETTINGS and the pass table PHOS_PASSES as plain
data, from which the add-on declares its Blender properties (docs/architecture.md,
"One table of render settings", "One table of passes").

This parses phos.h's own style, not C at large: declarations at file scope,
no nested structs, and among function-like macros only X-macro tables (a
body of one call of a parameter per row) are read; helpers with `...` are
skipped. A declaration it cannot read is an error, not a silent omission.
"""

import argparse
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADER = "core/include/phos.h"
OUTPUT = "addon/phos/phos_h.py"

# Limits the header may use in the table, from <stdint.h> and <float.h>.
BUILTIN_CONSTANTS = {"UINT32_MAX": 0xFFFFFFFF, "INT32_MAX": 0x7FFFFFFF, "FLT_MAX": 3.4028234663852886e38}

CTYPES = {
    "uint32_t": "ctypes.c_uint32", "int32_t": "ctypes.c_int32", "uint64_t": "ctypes.c_uint64",
    "int64_t": "ctypes.c_int64", "float": "ctypes.c_float", "double": "ctypes.c_double",
    "char": "ctypes.c_char", "size_t": "ctypes.c_size_t", "int": "ctypes.c_int",
}

# What a USER row's kind may be besides `enum <name>`.
SETTING_KINDS = ("NUMBER", "PIXELS", "LENGTH", "FACTOR", "SECONDS", "BOOLEAN")
SETTING_FIELDS = ("name", "ctype", "default", "min", "max", "user", "prop", "kind", "enum",
                  "soft_max", "label", "description")
PASS_FIELDS = ("id", "ident", "name", "channels", "group", "kind", "description")


class HeaderError(Exception):
    pass


# ------------------------------------------------------------------ lexing

def strip_comments(text):
    """Splice continued lines, then drop comments (string literals kept)."""
    text = re.sub(r"\\\n", " ", text)
    return re.sub(r'"(?:\\.|[^"\\])*"|/\*.*?\*/|//[^\n]*',
                  lambda m: m.group(0) if m.group(0).startswith('"') else " ", text, flags=re.S)


def split_args(text):
    """Split at the commas outside parentheses and string literals."""
    args, depth, current, i = [], 0, [], 0
    while i < len(text):
        c = text[i]
        if c == '"':
            m = re.match(r'"(?:\\.|[^"\\])*"', text[i:])
            current.append(m.group(0))
            i += len(m.group(0))
            continue
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
        elif c == "," and depth == 0:
            args.append("".join(current).strip())
            current = []
            i += 1
            continue
        current.append(c)
        i += 1
    args.append("".join(current).strip())
    return args


def calls(text, names):
    """(name, argument text) of each call NAME(...) in text, which must hold nothing else."""
    out, pos = [], 0
    pattern = re.compile(r"\s*(%s)\s*\(" % "|".join(map(re.escape, names)))
    while text[pos:].strip():
        m = pattern.match(text, pos)
        if not m:
            raise HeaderError("expected one of %s at: %.60s" % (", ".join(names), text[pos:].strip()))
        depth, i = 1, m.end()
        while depth:
            if i >= len(text):
                raise HeaderError("unbalanced parentheses in %s(...)" % m.group(1))
            if text[i] == '"':
                i += len(re.match(r'"(?:\\.|[^"\\])*"', text[i:]).group(0))
                continue
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            i += 1
        out.append((m.group(1), text[m.end():i - 1]))
        pos = i
    return out


def string_literal(text):
    """The value of adjacent C string literals ("a " "b")."""
    parts = re.findall(r'"((?:\\.|[^"\\])*)"', text)
    if not parts or re.sub(r'"(?:\\.|[^"\\])*"', "", text).strip():
        raise HeaderError("expected a string literal: %s" % text)
    escapes = {"n": "\n", "t": "\t"}
    return "".join(re.sub(r"\\(.)", lambda m: escapes.get(m.group(1), m.group(1)), p) for p in parts)


def evaluate(expr, constants):
    """Value of a constant expression: literals, known names, ( ) + - * << >> | &."""
    def literal(m):
        tok = m.group(0)
        if tok in constants:
            return repr(constants[tok])
        if re.fullmatch(r"[A-Za-z_]\w*", tok):
            raise HeaderError("unknown name %s in %r" % (tok, expr))
        if re.fullmatch(r"0[xX][0-9a-fA-F]+[uUlL]*|\d+[uUlL]*", tok):
            return str(int(tok.rstrip("uUlL"), 0))
        return repr(float(tok.rstrip("fF")))
    py = re.sub(r"[A-Za-z_]\w*|\d+\.\d*(?:[eE][+-]?\d+)?[fF]?|\d+[eE][+-]?\d+[fF]?|"
                r"0[xX][0-9a-fA-F]+[uUlL]*|\d+[uUlL]*", literal, expr)
    if not re.fullmatch(r"[\d\s.eE+\-*()<>|&]*", py):
        raise HeaderError("cannot evaluate %r" % expr)
    return eval(py, {"__builtins__": {}})  # only digits and the operators above remain


# ----------------------------------------------------------------- parsing

class Header:
    """What phos.h declares, read from its text."""

    def __init__(self, text):
        self.constants = dict(BUILTIN_CONSTANTS)
        self.defines = []          # (name, value) of the object-like #defines with a value
        self.enums = []            # (name, [(member, value)])
        self.enum_typedefs = set()
        self.handles = []          # opaque struct typedefs
        self.structs = []          # (name, [(field, ctypes expression)])
        self.functions = []        # (name, restype, [argtypes])
        self.tables = {}           # X-macro name -> (row macros, [(row macro, arguments)])
        code = self._preprocessor(strip_comments(text))
        self._enums(code)
        self.passes = self._passes_table()
        self.settings = self._settings_table()
        self._types(code)
        self._functions(code)

    def _preprocessor(self, text):
        lines = []
        for line in text.split("\n"):
            m = re.match(r"\s*#\s*(\w+)\s*(.*)", line)
            if not m:
                lines.append(line)
                continue
            if m.group(1) != "define":
                continue
            d = re.match(r"(\w+)(\(([^)]*)\))?\s*(.*)", m.group(2))
            name, params, body = d.group(1), d.group(3), d.group(4).strip()
            if params is not None:
                params = [p.strip() for p in params.split(",")]
                if "..." in params or not re.search(r"\b(%s)\s*\(" % "|".join(params), body):
                    continue  # a helper such as PHOS_SETTING_FIELD_, not a table
                self.tables[name] = (params, [(macro, split_args(args)) for macro, args in calls(body, params)])
            elif body and name not in ("PHOS_API",):
                self.constants[name] = evaluate(body, self.constants)
                self.defines.append((name, self.constants[name]))
        return "\n".join(lines)

    def _enums(self, code):
        for m in re.finditer(r"(typedef\s+)?enum\s+(\w+)\s*\{(.*?)\}\s*(\w*)\s*;", code, re.S):
            members, value = [], -1
            # enum phos_pass is the pass table's ids: PHOS_PASSES(PHOS_PASS_ENUM_).
            body = re.sub(r"\bPHOS_PASSES\s*\(\s*\w+\s*\)",
                          lambda _m: "".join("PHOS_PASS_%s," % args[0] for _mac, args in self._pass_rows()),
                          m.group(3))
            for item in filter(None, (s.strip() for s in body.split(","))):
                e = re.fullmatch(r"(\w+)(?:\s*=\s*(.+))?", item, re.S)
                if not e:
                    raise HeaderError("enum %s: cannot read %r" % (m.group(2), item))
                value = evaluate(e.group(2), self.constants) if e.group(2) else value + 1
                self.constants[e.group(1)] = value
                members.append((e.group(1), value))
            self.enums.append((m.group(2), members))
            if m.group(1):
                self.enum_typedefs.add(m.group(4) or m.group(2))

    def _pass_rows(self):
        if len(self.tables.get("PHOS_PASSES", ((),))[0]) != 1:
            raise HeaderError("no PHOS_PASSES(PASS) table")
        return self.tables["PHOS_PASSES"][1]

    def _passes_table(self):
        out = []
        for index, (_macro, args) in enumerate(self._pass_rows()):
            if len(args) != 6:
                raise HeaderError("PASS(%s): wrong number of columns" % ", ".join(args))
            out.append(dict(id=index, ident=args[0], name=string_literal(args[1]),
                            channels=evaluate(args[2], self.constants), group=evaluate(args[3], self.constants),
                            kind=evaluate(args[4], self.constants), description=string_literal(args[5])))
            if self.constants.get("PHOS_PASS_" + args[0]) != index:
                raise HeaderError("pass %s is not enum value %d" % (args[0], index))
        return out

    def _settings_table(self):
        if len(self.tables.get("PHOS_RENDER_SETTINGS", ((),))[0]) != 2:
            raise HeaderError("no PHOS_RENDER_SETTINGS(USER, HOST) table")
        (user_macro, _host_macro), rows = self.tables["PHOS_RENDER_SETTINGS"]
        enum_names = dict(self.enums)
        out = []
        for macro, args in rows:
            user = macro == user_macro
            if len(args) != (10 if user else 6):
                raise HeaderError("%s(%s): wrong number of columns" % (macro, ", ".join(args)))
            ctype, name = args[0], args[1]
            number = float if ctype == "float" else int
            s = dict(name=name, ctype=ctype, user=user, prop=None, kind=None, enum=None,
                     soft_max=None, label=None)
            s["default"], s["min"], s["max"] = (number(evaluate(a, self.constants)) for a in args[2:5])
            if user:
                s["prop"], kind = args[5], args[6]
                s["soft_max"] = number(evaluate(args[7], self.constants))
                s["label"], s["description"] = string_literal(args[8]), string_literal(args[9])
                e = re.fullmatch(r"enum\s+(\w+)", kind)
                if e and e.group(1) in enum_names:
                    s["kind"], s["enum"] = "ENUM", e.group(1)
                    values = [v for m, v in enum_names[e.group(1)] if not m.endswith("_COUNT")]
                    if (s["min"], s["max"]) != (min(values), max(values)):
                        raise HeaderError("setting %s: range [%r, %r] is not that of enum %s [%r, %r]"
                                          % (name, s["min"], s["max"], e.group(1), min(values), max(values)))
                elif kind in SETTING_KINDS:
                    s["kind"] = kind
                else:
                    raise HeaderError("setting %s: unknown kind %r" % (name, kind))
            else:
                s["description"] = string_literal(args[5])
            if not s["min"] <= s["default"] <= s["max"] or (s["soft_max"] or 0) > s["max"]:
                raise HeaderError("setting %s: default %r or soft max %r outside [%r, %r]"
                                  % (name, s["default"], s["soft_max"], s["min"], s["max"]))
            out.append(s)
        return out

    def _ctype(self, base, pointers, dims=()):
        if base in self.handles:
            if pointers not in (1, 2):
                raise HeaderError("a handle %s is used through one or two pointers" % base)
            t = "ctypes.c_void_p" if pointers == 1 else "ctypes.POINTER(ctypes.c_void_p)"
        elif base == "void" and pointers < 2:
            t = None if pointers == 0 else "ctypes.c_void_p"
        elif base == "char" and pointers == 1:
            t, pointers = "ctypes.c_char_p", 0
        else:
            if base in CTYPES:
                t = CTYPES[base]
            elif base in self.enum_typedefs:
                t = "ctypes.c_int"
            elif base in (name for name, _f in self.structs):
                t = base
            else:
                raise HeaderError("unknown type %s" % base)
            for _ in range(pointers):
                t = "ctypes.POINTER(%s)" % t
        for n in reversed(dims):
            t = "%s * %d" % (t if " * " not in t else "(%s)" % t, n)
        return t

    def _types(self, code):
        for m in re.finditer(r"typedef\s+struct\s+(\w+)\s+(\w+)\s*;", code):
            self.handles.append(m.group(2))
        for m in re.finditer(r"typedef\s+struct\s+(\w+)\s*\{(.*?)\}\s*(\w+)\s*;", code, re.S):
            name, body = m.group(3), m.group(2)
            # The settings table expands to one field `type name;` per row.
            body = re.sub(r"\bPHOS_RENDER_SETTINGS\s*\([^)]*\)",
                          lambda _m: "".join("%s %s;" % (s["ctype"], s["name"]) for s in self.settings), body)
            fields = []
            for decl in filter(None, (d.strip() for d in body.split(";"))):
                first, *more = (p.strip() for p in decl.split(","))
                t = re.fullmatch(r"(?:const\s+)?(\w+)\s*(.*)", first, re.S)
                if not t:
                    raise HeaderError("struct %s: cannot read %r" % (name, decl))
                for declarator in [t.group(2)] + more:
                    d = re.fullmatch(r"((?:\*\s*)*)(\w+)\s*((?:\[[^\]]+\]\s*)*)", declarator)
                    if not d:
                        raise HeaderError("struct %s: cannot read %r" % (name, declarator))
                    dims = [evaluate(x, self.constants) for x in re.findall(r"\[([^\]]+)\]", d.group(3))]
                    fields.append((d.group(2), self._ctype(t.group(1), d.group(1).count("*"), dims)))
            self.structs.append((name, fields))
        if len(self.structs) != len(re.findall(r"\bstruct\s+\w+\s*\{", code)):
            raise HeaderError("a struct is not of the form typedef struct name { ... } name;")

    def _functions(self, code):
        for m in re.finditer(r"\bPHOS_API\s+([^;(){}]*?)\s*(\w+)\s*\(([^;(){}]*)\)\s*;", code):
            ret = re.fullmatch(r"(?:const\s+)?(\w+)\s*((?:\*\s*)*)", m.group(1).strip())
            if not ret:
                raise HeaderError("%s: cannot read the return type %r" % (m.group(2), m.group(1)))
            args = []
            params = m.group(3).strip()
            if params != "void":
                for p in (p.strip() for p in params.split(",")):
                    a = re.fullmatch(r"(?:const\s+)?(\w+)\s*((?:\*\s*)*)(\w+)", p)
                    if not a:
                        raise HeaderError("%s: cannot read the parameter %r" % (m.group(2), p))
                    args.append(self._ctype(a.group(1), a.group(2).count("*")))
            self.functions.append((m.group(2), self._ctype(ret.group(1), ret.group(2).count("*")), args))
        if len(self.functions) != len(re.findall(r"\bPHOS_API\b", code)):
            raise HeaderError("a PHOS_API declaration is not a prototype this script can read")


# ------------------------------------------------------------------ output

def render(h):
    out = [
        "# SPDX-License-Identifier: GPL-3.0-or-later",
        "# Generated from %s by tools/gen_binding.py: do not edit. Change phos.h," % HEADER,
        "# then run `make binding` (`make test` fails while this file is stale).",
        '"""The constants, enums, structs, function signatures and render settings',
        "of phos.h, for core.py: see core/include/phos.h for what each one means.",
        '"""',
        "",
        "import collections",
        "import ctypes",
        "",
        "# #define",
    ]
    names = []
    for name, value in h.defines:
        out.append("%s = %r" % (name, value))
        names.append(name)
    for enum, members in h.enums:
        out += ["", "# enum %s" % enum]
        for member, value in members:
            out.append("%s = %r" % (member, value))
            names.append(member)
    out += ["", "ENUMS = {"]
    for enum, members in h.enums:
        out.append("    %r: {%s}," % (enum, ", ".join("%r: %r" % mv for mv in members)))
    out += ["}", "", "# Opaque handles, passed as c_void_p.",
            "HANDLES = %r" % (tuple(h.handles),)]
    for name, fields in h.structs:
        out += ["", "", "class %s(ctypes.Structure):" % name, "    _fields_ = ["]
        out += ['        ("%s", %s),' % f for f in fields]
        out += ["    ]"]
        names.append(name)
    out += ["", "", "STRUCTS = ("] + ["    %s," % name for name, _f in h.structs] + [")"]
    out += ["", "# name: (restype, argtypes)", "FUNCTIONS = {"]
    for name, restype, args in h.functions:
        out.append('    "%s": (%s, [%s]),' % (name, restype, ", ".join(args)))
    out += ["}", "", "# PHOS_RENDER_SETTINGS: user (scene.phos.<prop>) or host-derived (prop None).",
            'RenderSetting = collections.namedtuple("RenderSetting", "%s")' % " ".join(SETTING_FIELDS),
            "RENDER_SETTINGS = ("]
    for s in h.settings:
        out.append("    RenderSetting(")
        out.append("        %s," % ", ".join("%s=%r" % (k, s[k]) for k in SETTING_FIELDS[:5]))
        out.append("        %s," % ", ".join("%s=%r" % (k, s[k]) for k in SETTING_FIELDS[5:10]))
        out.append("        label=%r," % s["label"])
        out.append("        description=%r)," % s["description"])
    out += [")", "", "# PHOS_PASSES, in enum phos_pass order.",
            'Pass = collections.namedtuple("Pass", "%s")' % " ".join(PASS_FIELDS),
            "PASSES = ("]
    for p in h.passes:
        out.append("    Pass(%s," % ", ".join("%s=%r" % (k, p[k]) for k in PASS_FIELDS[:-1]))
        out.append("         description=%r)," % p["description"])
    out += [")", ""]
    names += ["ENUMS", "HANDLES", "STRUCTS", "FUNCTIONS", "RenderSetting", "RENDER_SETTINGS", "Pass", "PASSES"]
    out += ["__all__ = ("] + ["    %r," % n for n in names] + [")", ""]
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--header", default=os.path.join(ROOT, HEADER))
    ap.add_argument("--output", default=os.path.join(ROOT, OUTPUT))
    args = ap.parse_args(argv)
    with open(args.header, encoding="utf-8") as f:
        try:
            text = render(Header(f.read()))
        except HeaderError as ex:
            print("gen_binding: %s: %s" % (args.header, ex), file=sys.stderr)
            return 1
    with open(args.output, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
