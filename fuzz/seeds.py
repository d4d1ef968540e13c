#!/usr/bin/env python3
"""Writes the hand-made seed corpora fuzz/corpus/<target>/seed-* (byte layout:
proofs-notes/fuzzing.md). Run from the fuzz/ directory."""
import os
import struct

def w(mode, n):
    return bytes([mode]) + struct.pack("<I", n)

HALF = w(0, 0x80000000)         # w ~ w_inf/2 = w_0
NEAR_INF = w(3, 1 << 18)        # within 2^-32 (relative) of w_inf
TINY = w(2, 38)                 # w = 2^-40
SMALL = w(2, 5)                 # w = 2^-7

TRI, SQ = 0, 1                  # leading scene byte: even triangular, odd square

R_QUARTER = w(2, 0)             # r = 2^-2
R_NEAR_HALF = w(3, 51)          # r = 1/2 - 2^-53
R_TINY = w(2, 30)               # r = 2^-32
R_UNIFORM = w(0, 0x55555555)    # r ~ 1/6

def prim(sel, wb, events, body, pn=0, vn=0, scene=TRI):
    return bytes([scene, sel]) + wb + bytes([events]) + body + bytes([pn, vn])

def impact(disk, k, above, side, u1, u2):
    return bytes([disk, (0x80 if above else 0) | (k - 1), side]) + struct.pack("<HH", u1, u2)

def near(disk, k, motion, flags, psi, chi):
    return bytes([disk, k - 1, motion, flags]) + struct.pack("<HH", psi, chi)

def tangent(edge, line, back, s):
    return bytes([edge, line, back]) + struct.pack("<H", s)

def gap(edge, end, at, ang, u1, u2):
    return bytes([edge, end, at]) + struct.pack("<IHH", ang, u1, u2)

def corner(c, mode, which, ang, u1, u2):
    return bytes([c, mode, which]) + struct.pack("<IHH", ang, u1, u2)

def arbitrary(u1, u2, ang):
    return struct.pack("<HHI", u1, u2, ang)

PRIM = {
    "impact-disk0-b-1-2e-52": prim(0, HALF, 3, impact(0, 52, False, 0, 20000, 40000)),
    "impact-disk2-b-1+2e-52": prim(0, NEAR_INF, 3, impact(2, 52, True, 1, 50000, 9000)),
    "impact-disk1-b-1-2e-30-tiny-w": prim(0, TINY, 4, impact(1, 30, False, 1, 1234, 60000), 4, 40),
    "near-disk0-2e-60-in": prim(1, HALF, 2, near(0, 60, 0, 0, 30000, 32768)),
    "near-disk1-2e-40-out-excluded": prim(1, SMALL, 2, near(1, 40, 1, 1, 0, 20000)),
    "near-disk2-2e-53-tangent-excluded": prim(1, NEAR_INF, 3, near(2, 53, 2, 3, 65535, 0), 0, 17),
    "tangent-edge2-outer-near-winf": prim(2, NEAR_INF, 4, tangent(2, 0, 0, 10000), 0, 1),
    "tangent-edge0-inner1": prim(2, HALF, 4, tangent(0, 1, 1, 40000), 1, 2),
    "tangent-edge1-inner2-tiny-w": prim(2, TINY, 4, tangent(1, 2, 0, 0), 2, 3),
    "gap-edge2-end0-at-point": prim(3, HALF, 3, gap(2, 0, 1, 0x40000000, 0, 0)),
    "gap-edge1-end1-aimed": prim(3, SMALL, 3, gap(1, 1, 0, 0, 11111, 22222), 8, 80),
    "arbitrary": prim(4, w(1, 0x30000000), 4, arbitrary(12345, 23456, 0x9E3779B9)),
    "corner1-aimed": prim(5, HALF, 3, corner(1, 1, 0, 0, 30000, 1000)),
    "square-impact-b-r-2e-52": prim(0, R_QUARTER, 4, impact(0, 52, False, 0, 20000, 40000), scene=SQ),
    "square-impact-b-r+2e-40-near-half": prim(0, R_NEAR_HALF, 4, impact(0, 40, True, 1, 9000, 50000), scene=SQ),
    "square-near-2e-60-in": prim(1, R_UNIFORM, 3, near(0, 60, 0, 0, 30000, 32768), scene=SQ),
    "square-near-2e-53-tangent-excluded-tiny-r": prim(1, R_TINY, 3, near(0, 53, 2, 3, 65535, 0), 0, 17, scene=SQ),
    "square-corridor-top-edge": prim(2, R_QUARTER, 4, tangent(1, 0, 0, 10000), scene=SQ),
    "square-corridor-near-half": prim(2, R_NEAR_HALF, 4, tangent(0, 1, 1, 40000), 1, 2, scene=SQ),
    "square-corner0-at": prim(5, R_QUARTER, 4, corner(0, 0, 0, 0x20000000, 0, 0), scene=SQ),
    "square-corner2-aimed": prim(5, R_UNIFORM, 4, corner(2, 1, 0, 0, 11111, 22222), scene=SQ),
    "square-corner3-along-edge": prim(5, R_NEAR_HALF, 4, corner(3, 2, 1, 0, 0, 0), scene=SQ),
    "square-arbitrary": prim(4, R_TINY, 4, arbitrary(12345, 23456, 0x9E3779B9), scene=SQ),
}

def scene(i, j, down, steps, p):
    return struct.pack(
        "<IIBH", (i + 1_000_000_000), (j + 1_000_000_000), down, steps - 1) + p

SCENE = {
    "impact-origin-up": scene(0, 0, 0, 4096, PRIM["impact-disk0-b-1-2e-52"]),
    "near-far-down": scene(1_000_000_000, -1_000_000_000, 1, 4096, PRIM["near-disk0-2e-60-in"]),
    "tangent-corner-up": scene(-1_000_000_000, 1_000_000_000, 0, 3000, PRIM["tangent-edge2-outer-near-winf"]),
    "tangent-tiny-w-down": scene(123456789, -987654321, 1, 4096, PRIM["tangent-edge1-inner2-tiny-w"]),
    "gap-point-up": scene(-7, 3, 0, 2048, PRIM["gap-edge2-end0-at-point"]),
    "arbitrary-down": scene(999_999_999, 999_999_999, 1, 4096, PRIM["arbitrary"]),
    "corner-aimed-up": scene(5, 5, 0, 4096, PRIM["corner1-aimed"]),
    "square-corridor-far": scene(1_000_000_000, -1_000_000_000, 0, 4096, PRIM["square-corridor-top-edge"]),
    "square-near-tiny-r": scene(-3, 4, 0, 4096, PRIM["square-near-2e-53-tangent-excluded-tiny-r"]),
    "square-corner-along-edge": scene(0, 0, 0, 4096, PRIM["square-corner3-along-edge"]),
    "square-impact-near-half": scene(77, -77, 1, 4096, PRIM["square-impact-b-r+2e-40-near-half"]),
    "square-gap-falls-back": scene(1, 2, 0, 4096, prim(3, R_QUARTER, 4, gap(0, 0, 1, 0, 0, 0), scene=SQ)),
    "square-arbitrary": scene(-1, -1, 0, 4096, PRIM["square-arbitrary"]),
}

def electric(k, a):
    """The thermostat_kernel's field bytes: E = 10^(4k/255 - 3), angle 2*pi*a/65536."""
    return bytes([k]) + struct.pack("<H", a)

# Grazing and degenerate starts (impact parameters r(1 -/+ 2^-52), tangential starts on a disk,
# common tangents, corners) under weak, middling and strong fields at several angles.
GRAZING = ["impact-origin-up", "near-far-down", "tangent-corner-up", "tangent-tiny-w-down",
           "corner-aimed-up", "square-corridor-far", "square-near-tiny-r",
           "square-corner-along-edge", "square-impact-near-half"]
FIELDS = {"E1e-3-x": electric(0, 0), "E0.3-60deg": electric(158, 10923),
          "E10-minus-y": electric(255, 49152), "E1-135deg": electric(191, 24576)}
THERMO = {f"{name}-{f}": SCENE[name] + fb for name in GRAZING for f, fb in FIELDS.items()}

for target, seeds in (("collision_primitive", PRIM), ("scene_stepper", SCENE),
                      ("thermostat_kernel", THERMO)):
    d = os.path.join("corpus", target)
    os.makedirs(d, exist_ok=True)
    for name, b in seeds.items():
        with open(os.path.join(d, "seed-" + name), "wb") as f:
            f.write(b)
