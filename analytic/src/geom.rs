//! A minimal 3-vector in f64, private to the oracle.
//!
//! The oracle deliberately does not share a vector type with the renderer it judges.
//! Every geometric closed form takes absolute positions and forms *differences first*
//! ([`Vec3::sub`]) so that scenes placed far (1e5 units) from the origin lose no more
//! precision than the rounding of the input coordinates themselves.

use std::ops::{Add, Mul, Neg, Sub};

/// A 3-vector of f64.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec3 {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
    /// z component.
    pub z: f64,
}

impl Vec3 {
    /// Builds a vector.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }

    /// From an array `[x, y, z]`.
    pub const fn from_array(a: [f64; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }

    /// Dot product.
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Euclidean length (overflow-safe via `hypot`).
    pub fn length(self) -> f64 {
        self.x.hypot(self.y).hypot(self.z)
    }

    /// Squared length.
    pub fn length_squared(self) -> f64 {
        self.dot(self)
    }

    /// Unit vector in the same direction; `None` for the zero (or non-finite) vector.
    pub fn normalized(self) -> Option<Self> {
        let l = self.length();
        (l > 0.0 && l.is_finite()).then(|| self * (1.0 / l))
    }

    /// True when any component is NaN.
    pub fn has_nan(self) -> bool {
        self.x.is_nan() || self.y.is_nan() || self.z.is_nan()
    }

    /// True when every component is finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// Angle between two non-zero vectors, robust for tiny and near-π angles:
    /// `atan2(|a×b|, a·b)`.
    pub fn angle_between(self, o: Self) -> f64 {
        self.cross(o).length().atan2(self.dot(o))
    }

    /// Some orthonormal pair `(t, b)` completing the unit vector `self` to a right-handed
    /// frame `(t, b, self)` (Duff et al. 2017, "Building an orthonormal basis, revisited").
    pub fn orthonormal_basis(self) -> (Self, Self) {
        let n = self;
        let sign = 1.0f64.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        (
            Self::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            Self::new(b, sign + n.y * n.y * a, -n.y),
        )
    }
}

/// True when any of `vectors` or `scalars` is or holds a NaN: the oracle's functions then
/// return NaN, never a finite value that would pass for a reference.
pub(crate) fn any_nan(vectors: &[Vec3], scalars: &[f64]) -> bool {
    vectors.iter().any(|v| v.has_nan()) || scalars.iter().any(|s| s.is_nan())
}

/// Test support: `f` of the flat inputs `base` (a vector's components in a row) is not
/// NaN at each base point, and is NaN with each input in turn made NaN.
#[cfg(test)]
pub(crate) fn assert_nan_in_each(what: &str, bases: &[&[f64]], f: impl Fn(&[f64]) -> f64) {
    for (i, base) in bases.iter().enumerate() {
        let at_base = f(base);
        assert!(!at_base.is_nan(), "{what}, base {i} is NaN itself");
        for k in 0..base.len() {
            let mut x = base.to_vec();
            x[k] = f64::NAN;
            let got = f(&x);
            assert!(
                got.is_nan(),
                "{what}, base {i} ({at_base}), input {k} NaN: {got}"
            );
        }
    }
}

/// Test support: the vector of the flat inputs `x[i..i + 3]`.
#[cfg(test)]
pub(crate) fn vec_at(x: &[f64], i: usize) -> Vec3 {
    Vec3::new(x[i], x[i + 1], x[i + 2])
}

impl Add for Vec3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vec3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for Vec3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f64> for Vec3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        for n in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(1.0, 2.0, -3.0).normalized().unwrap(),
        ] {
            let (t, b) = n.orthonormal_basis();
            assert!((t.length() - 1.0).abs() < 1e-15);
            assert!((b.length() - 1.0).abs() < 1e-15);
            assert!(t.dot(b).abs() < 1e-15 && t.dot(n).abs() < 1e-15);
            assert!((t.cross(b) - n).length() < 1e-15);
        }
    }

    #[test]
    fn angle_is_robust() {
        let a = Vec3::new(1.0, 0.0, 0.0);
        assert!((a.angle_between(Vec3::new(1.0, 1e-12, 0.0)) - 1e-12).abs() < 1e-27);
        assert!(
            (a.angle_between(Vec3::new(-1.0, 1e-12, 0.0)) - (std::f64::consts::PI - 1e-12)).abs()
                < 1e-15
        );
    }
}
