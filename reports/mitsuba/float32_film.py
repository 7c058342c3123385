#!/usr/bin/env python3
"""Mitsuba 3 (scalar_rgb): a pixel's samples are summed in float32.

A radiancemeter under a constant sky of radiance 0.7 sees 0.7 in every sample, yet the
pixel is not 0.7 at high sample counts (measured with 3.9.1: 0.7 at 64 spp, 0.699972 at
4096, 0.701811 at 2^18, 0.692734 at 2^20). Run: python3 float32_film.py
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")
scene = mi.load_dict({
    "type": "scene", "integrator": {"type": "path"},
    "sensor": {"type": "radiancemeter", "origin": [0, 0, 0], "direction": [0, 0, 1],
               "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}}},
    "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.7}}})
for spp in [64, 4096, 2**18, 2**20]:
    print(spp, mi.render(scene, spp=spp)[0, 0])
