#!/usr/bin/env python3
"""Mitsuba 3 (scalar_rgb): MIS over-counts an emitting sphere seen from inside.

One scattering in a closed sphere of albedo 0.5 emitting Le = 1 is exactly L = 1.5.
Emitter sampling alone and BSDF sampling alone give 1.5; their MIS combination gives
1.508 (+0.5%) in scalar_rgb, 1.5001 in llvm_ad_rgb: the two strategies' MIS weights do
not sum to one.

The cause (checked below): src/shapes/sphere.cpp decides "is the reference point inside
the sphere?" two ways. sample_direction() treats a point as inside when
|c - p|^2 <= (R (1 + RayEpsilon))^2 with flipped normals (RayEpsilon = 8.9e-5) and then
samples by area (pdf = dist^2 / (A |cos|)); pdf_direction() treats it as outside as soon
as R / |c - p| < 1 - 6e-8 and returns the cone pdf 1/(2 pi (1 - cos alpha)). A point on
the wall that rounds a hair outside the sphere is inside for one and outside for the
other, so the light density in the MIS weight of a BSDF-sampled hit is not the one
emitter sampling draws with. At wall points found by ray casting the two disagree at
~16% of points in scalar_rgb (ratios up to 11.7) and ~2% in llvm_ad_rgb (whose bias is smaller).
Run: python3 sphere_mis_bias.py [VARIANT]   (default scalar_rgb; also llvm_ad_rgb)
"""
import sys
import mitsuba as mi
mi.set_variant(sys.argv[1] if len(sys.argv) > 1 else 'scalar_rgb')
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

# The root cause: at points on the wall (where paths scatter) the sphere's pdf_direction
# disagrees with the pdf its own sample_direction drew with.
import math, random
shape_scene = mi.load_dict({'type': 'scene', 'sphere': {'type': 'sphere', 'flip_normals': True,
    'bsdf': {'type': 'diffuse'}, 'emitter': {'type': 'area'}}})
shape = shape_scene.shapes()[0]
rng = random.Random(1)
n, mismatch, worst = 2000, 0, 0.0
first = lambda x: float(x[0]) if hasattr(x, '__len__') else float(x)
for _ in range(n):
    z = 2 * rng.random() - 1
    phi = 2 * math.pi * rng.random()
    s = math.sqrt(1 - z * z)
    si = shape_scene.ray_intersect(mi.Ray3f(mi.Point3f(0.1, 0, 0.05), mi.Vector3f(s * math.cos(phi), s * math.sin(phi), z)))
    it = mi.Interaction3f(si)
    ds = shape.sample_direction(it, mi.Point2f(rng.random(), rng.random()))
    r = first(shape.pdf_direction(it, ds)) / first(ds.pdf)
    if abs(r - 1) > 1e-3:
        mismatch += 1
        worst = max(worst, abs(r - 1))
print(f'pdf_direction != sample_direction pdf at {mismatch} of {n} wall points (largest |ratio - 1| = {worst:.3g})')
