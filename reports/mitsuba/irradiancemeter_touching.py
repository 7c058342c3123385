#!/usr/bin/env python3
"""Mitsuba 3.9.1: the irradiancemeter loses light next to a surface it touches.

The meter starts its rays at p + d * RayEpsilon (RayEpsilon = 8.9e-5, absolute, along the
sampled direction d, src/sensors/irradiancemeter.cpp), not off the surface along its
normal. A receiver point closer than that to another surface can start its ray behind
that surface. Here a receiver strip of height h stands on the edge of an emitting 2 x 1
rectangle (Howell C-14, perpendicular rectangles sharing an edge): receiver points below
8.9e-5 start part of their downward rays under the emitter's plane, so those rays miss
the light. Expected mean irradiance over the strip: E = F12 * pi * L * A1 / A2 (closed
form). The deficit grows like RayEpsilon / h: -3.6% (z = -18) at h = 1e-3 and -38% at
h = 1e-4 (this script, scalar_rgb, 2^18 samples each). At h = 1e-2 it is about -0.35%,
below what this script resolves; lightproof's catalog case
view_factor/perpendicular_rectangles_strip_0_01 sees it as -0.23% (z = -2.5, scalar_rgb)
and -0.36% (z = -3.6, llvm_ad_rgb), both inside the suite's Sidak critical value.

Run: python3 irradiancemeter_touching.py [VARIANT]   (default scalar_rgb; also llvm_ad_rgb)
"""
import math
import sys

import mitsuba as mi

mi.set_variant(sys.argv[1] if len(sys.argv) > 1 else 'scalar_rgb')


def c14(l, w, h):
    """Howell C-14: F from A1 = l x w to A2 = l x h, perpendicular, sharing the edge l."""
    H, W = h / l, w / l
    h2, w2 = H * H, W * W
    s = math.sqrt(h2 + w2)
    ln = math.log
    t = (ln(1 + w2) + ln(1 + h2) - ln(1 + w2 + h2)
         + w2 * (ln(w2) + ln(1 + w2 + h2) - ln(1 + w2) - ln(w2 + h2))
         + h2 * (ln(h2) + ln(1 + h2 + w2) - ln(1 + h2) - ln(h2 + w2)))
    return (W * math.atan(1 / W) + H * math.atan(1 / H) - s * math.atan(1 / s) + t / 4) / (math.pi * W)


def meter(h, passes=1024, spp=256):
    film = {'type': 'hdrfilm', 'width': 1, 'height': 1, 'rfilter': {'type': 'box'}, 'pixel_format': 'rgb'}
    scene = mi.load_dict({
        'type': 'scene', 'integrator': {'type': 'path'},
        # Emitter: x in [0, 2], y in [0, 1], z = 0, facing +z.
        'light': {'type': 'rectangle',
                  'to_world': mi.ScalarTransform4f().translate([1, 0.5, 0]).scale([1, 0.5, 1]),
                  'emitter': {'type': 'area', 'radiance': {'type': 'rgb', 'value': 1.0}}},
        # Receiver: x in [0, 2], y = 0, z in [0, h], facing +y (local x -> z, y -> x, z -> y).
        'strip': {'type': 'rectangle',
                  'to_world': mi.ScalarTransform4f([[0, 1, 0, 1], [0, 0, 1, 0], [h / 2, 0, 0, h / 2], [0, 0, 0, 1]]),
                  'bsdf': {'type': 'diffuse', 'reflectance': {'type': 'rgb', 'value': 0.0}},
                  'sensor': {'type': 'irradiancemeter', 'film': film}}})
    vals = []
    for q in range(passes):
        a = mi.render(scene, seed=q, spp=spp).array
        vals.append(sum(float(a[i]) for i in range(len(a))) / len(a))
    m = sum(vals) / passes
    se = math.sqrt(sum((v - m) ** 2 for v in vals) / (passes - 1) / passes)
    return m, se


for h in (1e-2, 1e-3, 1e-4):
    expected = c14(2.0, 1.0, h) * math.pi * 1.0 * 2.0 / (2.0 * h)
    m, se = meter(h)
    print(f'{mi.variant()} strip h = {h:g}: meter {m:.5f} +- {se:.5f}, closed form {expected:.5f} '
          f'({100 * (m / expected - 1):+.2f}%, z = {(m - expected) / se:+.1f})')
