# SPDX-License-Identifier: GPL-3.0-or-later
"""Shader programs: the values a compiled node tree computes, and the flat
program the core evaluates at each shading point (docs/architecture.md,
"Shader programs"; phos.h, phos_shader_program_desc).

A `Value` is a float (width 1) or a colour/vector (width 3) that is either
a constant (a numpy array) or the output of an instruction. Arithmetic on
Values folds constants here and emits Math / Vector Math instructions
otherwise, so the closure code (material.py, principled.py) reads the same
whether an input is a number or a texture. Instructions whose inputs are
all constants but that this module does not fold (a Color Ramp of a
constant, say) are folded by the core when the material is added, with the
core's own code: one implementation of every node.
"""

import ctypes

import numpy as np

from .. import core

NO_REGISTER = core.PHOS_SHADER_NO_REGISTER


class Value:
    """A float or a 3-vector: constant (`const`) or the registers an
    instruction writes (`ref`: ('t', temporary index))."""

    __slots__ = ("width", "const", "ref", "program")
    __array_ufunc__ = None  # numpy defers to the reflected operators below

    def __init__(self, width, const=None, ref=None, program=None):
        self.width, self.const, self.ref, self.program = width, const, ref, program

    @property
    def is_const(self):
        return self.const is not None

    def __repr__(self):
        return "Value(%d, %s)" % (self.width, self.const if self.is_const else self.ref)

    # Arithmetic emits through the program of the non-constant operand.
    def _binary(self, other, op, swap=False):
        prog = self.program or getattr(other, "program", None)
        a, b = (other, self) if swap else (self, other)
        return prog.arith(op, a, b) if prog is not None else constant(_fold(op, _arr(a), _arr(b)))

    def __add__(self, o): return self._binary(o, 'ADD')
    def __radd__(self, o): return self._binary(o, 'ADD', True)
    def __sub__(self, o): return self._binary(o, 'SUBTRACT')
    def __rsub__(self, o): return self._binary(o, 'SUBTRACT', True)
    def __mul__(self, o): return self._binary(o, 'MULTIPLY')
    def __rmul__(self, o): return self._binary(o, 'MULTIPLY', True)
    def __truediv__(self, o): return self._binary(o, 'DIVIDE')
    def __rtruediv__(self, o): return self._binary(o, 'DIVIDE', True)
    def __pow__(self, o): return self._binary(o, 'POWER')
    def __neg__(self): return self._binary(-1.0, 'MULTIPLY')


def constant(v):
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.size == 1:
        return Value(1, a.copy())
    return Value(3, a[:3].copy())


def _arr(x):
    if isinstance(x, Value):
        return x.const
    return np.asarray(x, dtype=np.float64).reshape(-1)


def _fold(op, a, b):
    with np.errstate(all='ignore'):
        if op == 'ADD':
            return a + b
        if op == 'SUBTRACT':
            return a - b
        if op == 'MULTIPLY':
            return a * b
        if op == 'DIVIDE':
            return np.where(b != 0.0, a / np.where(b != 0.0, b, 1.0), 0.0)  # Cycles' safe_divide
        if op == 'POWER':
            return np.power(a, b)
        if op == 'MINIMUM':
            return np.minimum(a, b)
        if op == 'MAXIMUM':
            return np.maximum(a, b)
    raise ValueError(op)


def varies(x):
    """A shader-program value that is not a constant."""
    return isinstance(x, Value) and not x.is_const


def may_exceed(x, threshold):
    """Whether x can be above threshold: a varying value may."""
    return True if varies(x) else float(np.max(_arr(x))) > threshold


def may_be_below(x, threshold):
    return True if varies(x) else float(np.min(_arr(x))) < threshold


def plain(x):
    """A constant Value as a float or numpy array; anything else unchanged."""
    if isinstance(x, Value) and x.is_const:
        return const_value(x)
    return x


def is_const(x):
    return not isinstance(x, Value) or x.is_const


def const_value(x):
    """The numpy value of a constant (float or array)."""
    a = _arr(x)
    return float(a[0]) if a.size == 1 else a


class Program:
    """Collects instructions, constants, tables and bindings; `desc()` lays
    them out as phos.h wants (constants first in the register file)."""

    def __init__(self):
        self.constants = []          # floats
        self.const_index = {}        # tuple(values) → first register
        self.temps = 0               # registers written by instructions
        self.instructions = []       # (op, mode, flags, table, param, ins, outs) with refs
        self.table = []              # floats
        self.bindings = []           # (closure, field, ref)
        self.memo = {}               # (op, mode, flags, table, param, inputs) → outputs
        self.attributes = set()      # the mesh attributes' keys it reads (mesh_attributes.py)
        self._keep = None

    # ----------------------------------------------------------- registers

    def const_ref(self, values):
        key = tuple(float(v) for v in values)
        if key not in self.const_index:
            self.const_index[key] = len(self.constants)
            self.constants.extend(key)
        return ('c', self.const_index[key])

    def ref(self, value, width):
        """Registers holding a value, widened or narrowed to `width`."""
        value = self.convert(value, width)
        if value.is_const:
            return self.const_ref(value.const)
        return value.ref

    def convert(self, value, width):
        """Cycles' implicit conversions: float → (f, f, f); colour → float
        by luminance (done by RGB to BW, the socket type is the caller's)."""
        if not isinstance(value, Value):
            value = constant(value)
        if value.width == width:
            return value
        if width == 3:
            if value.is_const:
                return constant(np.repeat(value.const[0], 3))
            return self.emit(core.PHOS_OP_COMBINE_XYZ, [value, value, value], [3])[0]
        return self.emit(core.PHOS_OP_RGB_TO_BW, [value], [1], in_widths=[3])[0]

    # -------------------------------------------------------- instructions

    def emit(self, op, inputs, out_widths, mode=0, flags=0, table=0, param=(0.0, 0.0, 0.0, 0.0),
             in_widths=None):
        """Emit one instruction; returns its outputs as Values. Identical
        instructions are emitted once (common subexpressions)."""
        if in_widths is None:
            in_widths = [v.width if isinstance(v, Value) else np.asarray(v).size for v in inputs]
        refs = tuple(self.ref(v, w) for v, w in zip(inputs, in_widths))
        param = tuple(float(p) for p in param) + (0.0,) * (4 - len(param))
        key = (op, mode, flags, table, param, refs, tuple(out_widths))
        if key in self.memo:
            return self.memo[key]
        outs = []
        for w in out_widths:
            outs.append(Value(w, ref=('t', self.temps), program=self))
            self.temps += w
        self.instructions.append((op, mode, flags, table, param, refs, [o.ref for o in outs]))
        self.memo[key] = outs
        return outs

    def add_table(self, floats):
        offset = len(self.table)
        self.table.extend(float(f) for f in floats)
        return offset

    def bind(self, closure, field, value, width):
        self.bindings.append((closure, field, self.ref(value, width)))

    # ---------------------------------------------------------- arithmetic

    def arith(self, op, a, b):
        a = a if isinstance(a, Value) else constant(a)
        b = b if isinstance(b, Value) else constant(b)
        if a.is_const and b.is_const:
            return constant(_fold(op, a.const, b.const))
        if op == 'MULTIPLY':  # x·1 = x, x·0 = 0 (weights scale by mix factors)
            for x, y in ((a, b), (b, a)):
                if y.is_const and np.all(y.const == 1.0) and x.width >= y.width:
                    return x
        if op == 'ADD':
            for x, y in ((a, b), (b, a)):
                if y.is_const and np.all(y.const == 0.0) and x.width >= y.width:
                    return x
        width = max(a.width, b.width)
        if width == 1:
            return self.emit(core.PHOS_OP_MATH, [a, b, 0.0], [1], mode=getattr(core, "PHOS_MATH_" + op))[0]
        return self.emit(core.PHOS_OP_VECTOR_MATH, [self.convert(a, 3), self.convert(b, 3), constant((0, 0, 0)), 1.0],
                         [3, 1], mode=getattr(core, "PHOS_VECTOR_MATH_" + op), in_widths=[3, 3, 3, 1])[0]

    # ---------------------------------------------------------------- desc

    def empty(self):
        return not self.bindings

    def desc(self):
        """The phos_shader_program_desc (its arrays kept alive by self)."""
        c = len(self.constants)

        def reg(r):
            return r[1] if r[0] == 'c' else c + r[1]

        n = len(self.instructions)
        ins = (core.phos_shader_instruction * max(n, 1))()
        for i, (op, mode, flags, table, param, refs, outs) in enumerate(self.instructions):
            d = ins[i]
            d.op, d.mode, d.flags, d.table = op, mode, flags, table
            d.param[:] = list(param)
            for k, r in enumerate(refs):
                d.inputs[k] = reg(r)
            for k in range(core.PHOS_SHADER_MAX_OUTPUTS):
                d.outputs[k] = reg(outs[k]) if k < len(outs) and outs[k] is not None else NO_REGISTER
        binds = (core.phos_shader_binding * max(len(self.bindings), 1))()
        for i, (closure, field, r) in enumerate(self.bindings):
            binds[i].closure, binds[i].field, binds[i].reg = closure, field, reg(r)
        consts = (ctypes.c_float * max(c, 1))(*self.constants)
        table = (ctypes.c_float * max(len(self.table), 1))(*self.table)
        d = core.phos_shader_program_desc()
        d.register_count = c + self.temps
        d.constant_count = c
        d.constants = ctypes.cast(consts, ctypes.POINTER(ctypes.c_float))
        d.instruction_count = n
        d.instructions = ctypes.cast(ins, ctypes.POINTER(core.phos_shader_instruction))
        d.table_size = len(self.table)
        d.table = ctypes.cast(table, ctypes.POINTER(ctypes.c_float))
        d.binding_count = len(self.bindings)
        d.bindings = ctypes.cast(binds, ctypes.POINTER(core.phos_shader_binding))
        self._keep = (ins, binds, consts, table)
        return d

    def too_large(self):
        return (len(self.constants) + self.temps > core.PHOS_SHADER_MAX_REGISTERS
                or len(self.instructions) > core.PHOS_SHADER_MAX_INSTRUCTIONS
                or len(self.table) > core.PHOS_SHADER_MAX_TABLE)


# ------------------------------------------------------ helpers for closures

def clamp(x, lo, hi):
    """min(max(x, lo), hi), folded for constants."""
    if is_const(x):
        if isinstance(x, Value):
            return constant(np.clip(x.const, lo, hi))
        if np.ndim(x):
            return np.clip(np.asarray(x, dtype=np.float64), lo, hi)
        return min(max(float(x), lo), hi)
    p = x.program
    if x.width == 1:
        return p.emit(core.PHOS_OP_CLAMP, [x, lo, hi], [1], mode=core.PHOS_CLAMP_MINMAX)[0]
    return p.arith('MINIMUM', p.arith('MAXIMUM', x, constant((lo,) * 3)), constant((hi,) * 3))


def maximum(x, lo):
    if is_const(x):
        if isinstance(x, Value):
            return constant(np.maximum(x.const, lo))
        if np.ndim(x):
            return np.maximum(np.asarray(x, dtype=np.float64), lo)
        return max(float(x), lo)
    return x.program.arith('MAXIMUM', x, constant((lo,) * x.width))


def sqrt(x):
    if is_const(x):
        v = np.sqrt(np.maximum(_arr(x), 0.0))
        if isinstance(x, Value):
            return constant(v)
        return v if np.ndim(x) else float(v[0])
    p = x.program
    if x.width == 1:
        return p.emit(core.PHOS_OP_MATH, [x, 0.0, 0.0], [1], mode=core.PHOS_MATH_SQRT)[0]
    return p.arith('POWER', maximum(x, 0.0), constant((0.5, 0.5, 0.5)))


def luminance(x):
    """Colour → float as Cycles converts it."""
    if is_const(x):
        a = _arr(x)
        return float(np.dot([0.2126, 0.7152, 0.0722], a)) if a.size == 3 else float(a[0])
    return x.program.convert(x, 1)
