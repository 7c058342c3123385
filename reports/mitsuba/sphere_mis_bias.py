#!/usr/bin/env python3
"""Mitsuba 3 (scalar_rgb): MIS over-counts an emitting sphere seen from inside.

One scattering in a closed sphere of albedo 0.5 emitting Le = 1 is exactly L = 1.5.
Emitter sampling alone and BSDF sampling alone give 1.5; their MIS combination gives
1.508 (+0.5%): the two strategies' MIS weights do not sum to one here (presumably the light
density in the weight of a BSDF-sampled hit is not the one emitter sampling draws with).
Run: python3 sphere_mis_bias.py
"""
import mitsuba as mi
mi.set_variant('scalar_rgb')
def scene(integrator):
    return mi.load_dict({'type': 'scene', 'integrator': integrator,
        'sensor': {'type': 'perspective', 'fov': 60,
                   'to_world': mi.ScalarTransform4f().look_at(origin=[0.1, 0, 0.05], target=[0.1, 0.6, 0.85], up=[0, 0, 1]),
                   'film': {'type': 'hdrfilm', 'width': 16, 'height': 16, 'rfilter': {'type': 'box'}}},
        'sphere': {'type': 'sphere', 'flip_normals': True,
                   'bsdf': {'type': 'diffuse', 'reflectance': {'type': 'rgb', 'value': 0.5}},
                   'emitter': {'type': 'area', 'radiance': {'type': 'rgb', 'value': 1.0}}}})
def mean(s, passes=16, spp=256):
    t = 0.0
    for q in range(passes):
        img = mi.render(s, seed=q, spp=spp)
        a = img.array
        t += sum(float(a[i]) for i in range(len(a))) / len(a)
    return t / passes
# One scattering of a closed sphere, rho = 0.5, Le = 1: L = Le (1 + rho) = 1.5 exactly.
print('direct, emitter sampling only:', mean(scene({'type': 'direct', 'emitter_samples': 1, 'bsdf_samples': 0})))
print('direct, BSDF sampling only:   ', mean(scene({'type': 'direct', 'emitter_samples': 0, 'bsdf_samples': 1})))
print('direct, MIS:                  ', mean(scene({'type': 'direct'})))
