"""pbrt-v4's sphere normal (src/pbrt/shapes.h, Sphere::InteractionFromIntersection:
n = dpdu x dpdv with sinTheta = SafeSqrt(1 - Sqr(cosTheta)), cosTheta = pHit.z / radius)
evaluated in float32 with numpy, against the exact normal pHit / radius, for hit points
theta from the sphere's +z pole; and with sinTheta = zRadius / radius instead
(sphere_sintheta.patch). Usage: python3 sphere_normal_f32.py (needs numpy)."""
import numpy as np

f = np.float32
r = f(0.5)


def normal_error(th, phi, patched):
    p = (np.array([np.sin(th) * np.cos(phi), np.sin(th) * np.sin(phi), np.cos(th)]) * float(r)).astype(f)
    p = (p * (r / np.sqrt((p * p).sum(dtype=f)))).astype(f)  # pbrt's refinement of pHit
    cos_t = f(p[2] / r)
    zr = np.sqrt(p[0] * p[0] + p[1] * p[1])
    sin_t = f(zr / r) if patched else np.sqrt(max(f(0), f(1) - cos_t * cos_t))
    cphi, sphi = p[0] / zr, p[1] / zr
    phimax, dth = f(2 * np.pi), f(np.pi)
    dpdu = np.array([-phimax * p[1], phimax * p[0], 0], dtype=f)
    dpdv = dth * np.array([p[2] * cphi, p[2] * sphi, -r * sin_t], dtype=f)
    n = np.cross(dpdu, dpdv).astype(np.float64)
    n /= np.linalg.norm(n)
    exact = p.astype(np.float64) / np.linalg.norm(p.astype(np.float64))
    return np.arccos(min(1.0, abs(n @ exact)))


print("theta (rad)  normal error, pbrt-v4 (rad)  with sinTheta = zRadius/radius (rad)")
for th in [1e-1, 1e-2, 3e-3, 1e-3, 9.9e-4, 3e-4, 1e-4]:
    phis = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    a = max(normal_error(th, p, False) for p in phis)
    b = max(normal_error(th, p, True) for p in phis)
    print("%.1e      %.2e                     %.2e" % (th, a, b))
