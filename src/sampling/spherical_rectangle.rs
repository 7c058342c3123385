//! Uniform sampling of the solid angle a rectangle subtends (Ureña, Fajardo & King
//! 2013, "An Area-Preserving Parametrization for Spherical Rectangles", EGSR).
//!
//! In the rectangle's frame (edges along x and y, the viewer at the origin, the
//! rectangle in the plane z = z₀ < 0) the four great-circle normals give the interior
//! angles γᵢ and Ω = γ₀ + γ₁ − k with k = 2π − γ₂ − γ₃. The first uniform number fixes
//! the x coordinate of a vertical strip holding the fraction u₀ of Ω; the second picks
//! the height uniformly in the strip's projected (h = y/√(d² + y²)) coordinate.
//! Computed in `f64` because Ω = γ₀ + γ₁ − k cancels for small rectangles.

use glam::{DVec3, Vec2, Vec3};

/// A rectangle (corner `s`, orthogonal edges `ex`, `ey`) seen from a point.
#[derive(Clone, Copy, Debug)]
pub struct SphericalRectangle {
    o: DVec3,
    x: DVec3,
    y: DVec3,
    z: DVec3,
    z0: f64,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    b0: f64,
    b1: f64,
    k: f64,
    solid_angle: f64,
}

impl SphericalRectangle {
    /// The rectangle seen from `o`; `None` when `o` lies in its plane or it is degenerate.
    pub fn new(o: Vec3, s: Vec3, ex: Vec3, ey: Vec3) -> Option<Self> {
        let (o, s, ex, ey) = (o.as_dvec3(), s.as_dvec3(), ex.as_dvec3(), ey.as_dvec3());
        let (lx, ly) = (ex.length(), ey.length());
        if !(lx > 0.0 && ly > 0.0) {
            return None;
        }
        let x = ex / lx;
        let y = ey / ly;
        let mut z = x.cross(y);
        let d = s - o;
        let x0 = d.dot(x);
        let y0 = d.dot(y);
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z0 = -z0;
            z = -z;
        }
        if !(z0 < 0.0) {
            return None;
        }
        let x1 = x0 + lx;
        let y1 = y0 + ly;
        let n0 = DVec3::new(0.0, z0, -y0).normalize();
        let n1 = DVec3::new(-z0, 0.0, x1).normalize();
        let n2 = DVec3::new(0.0, -z0, y1).normalize();
        let n3 = DVec3::new(z0, 0.0, -x0).normalize();
        let g0 = (-n0.z * n1.z).clamp(-1.0, 1.0).acos();
        let g1 = (-n1.z * n2.z).clamp(-1.0, 1.0).acos();
        let g2 = (-n2.z * n3.z).clamp(-1.0, 1.0).acos();
        let g3 = (-n3.z * n0.z).clamp(-1.0, 1.0).acos();
        let k = 2.0 * std::f64::consts::PI - g2 - g3;
        let solid_angle = g0 + g1 - k;
        if !(solid_angle > 0.0) || !solid_angle.is_finite() {
            return None;
        }
        Some(SphericalRectangle {
            o,
            x,
            y,
            z,
            z0,
            x0,
            y0,
            x1,
            y1,
            b0: n0.z,
            b1: n2.z,
            k,
            solid_angle,
        })
    }

    /// Solid angle Ω in steradians.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle as f32
    }

    /// Density in solid angle, 1/Ω.
    pub fn pdf(&self) -> f32 {
        (1.0 / self.solid_angle) as f32
    }

    /// A point on the rectangle whose direction from `o` is uniform in solid angle.
    pub fn sample_point(&self, u: Vec2) -> Vec3 {
        let au = u.x as f64 * self.solid_angle + self.k;
        let (sin_au, cos_au) = au.sin_cos();
        let fu = (cos_au * self.b0 - self.b1) / sin_au;
        let mut cu = (1.0 / (fu * fu + self.b0 * self.b0).sqrt()).copysign(fu);
        cu = cu.clamp(-1.0, 1.0);
        let mut xu = -(cu * self.z0) / (1.0 - cu * cu).max(1e-300).sqrt();
        if !xu.is_finite() {
            xu = if cu > 0.0 { self.x1 } else { self.x0 };
        }
        xu = xu.clamp(self.x0, self.x1);
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + u.y as f64 * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-12 {
            hv * d / (1.0 - hv2).sqrt()
        } else {
            self.y1
        };
        let yv = yv.clamp(self.y0, self.y1);
        (self.o + xu * self.x + yv * self.y + self.z0 * self.z).as_vec3()
    }

    /// A direction uniformly distributed in the rectangle's solid angle.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let p = self.sample_point(u).as_dvec3();
        (p - self.o).normalize().as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_at_distance_one() {
        // Solid angle of a unit square centred on the axis at distance 1:
        // 4 asin(1/(1+1)·1/√... ) = 4·atan(0.25/ (1·sqrt(0.5+1)))... use the closed form
        // Ω = 4 atan(ab / (d √(a²+b²+d²))) with half-sides a = b = 0.5.
        let r = SphericalRectangle::new(Vec3::ZERO, Vec3::new(-0.5, -0.5, 1.0), Vec3::X, Vec3::Y)
            .unwrap();
        let exact = 4.0 * (0.25f64 / (1.0 * (0.25f64 + 0.25 + 1.0).sqrt())).atan();
        assert!((r.solid_angle() as f64 - exact).abs() < 1e-6);
        let p = r.sample_point(Vec2::new(0.3, 0.7));
        assert!((p.z - 1.0).abs() < 1e-6 && p.x.abs() <= 0.5 && p.y.abs() <= 0.5);
    }
}
