# SPDX-License-Identifier: GPL-3.0-or-later
"""Bob Jenkins' lookup3 hash (burtleburtle.net/bob/c/lookup3.c), as Cycles
hashes integers into random numbers: Object Info's Random (two words) and
Geometry's Random Per Island (one word)."""

_M = 0xFFFFFFFF


def _rot(x, k):
    return ((x << k) | (x >> (32 - k))) & _M


def _final(a, b, c):
    """lookup3's final mix of three words; returns c."""
    c ^= b; c = (c - _rot(b, 14)) & _M
    a ^= c; a = (a - _rot(c, 11)) & _M
    b ^= a; b = (b - _rot(a, 25)) & _M
    c ^= b; c = (c - _rot(b, 16)) & _M
    a ^= c; a = (a - _rot(c, 4)) & _M
    b ^= a; b = (b - _rot(a, 14)) & _M
    c ^= b; c = (c - _rot(b, 24)) & _M
    return c


def hash_uint(kx):
    """One word: lookup3's initial value for a length of 1, then the final mix."""
    a = b = c = (0xDEADBEEF + (1 << 2) + 13) & _M
    a = (a + kx) & _M
    return _final(a, b, c)


def hash_uint2(kx, ky):
    """Two words, as Cycles' hash_uint2."""
    a = b = c = (0xDEADBEEF + (2 << 2) + 13) & _M
    b = (b + ky) & _M
    a = (a + kx) & _M
    return _final(a, b, c)
