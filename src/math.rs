//! Frames, spherical coordinates and robust floating-point helpers.
//!
//! Engine arithmetic is `f32` (as in production renderers); the helpers here keep it
//! finite where naive formulas produce NaN: `safe_sqrt` and `safe_acos` clamp their
//! argument into the domain, [`difference_of_products`] evaluates `a·b − c·d` with
//! Kahan's FMA trick (error ≤ 1.5 ulp; Jeannerod, Louvet & Muller 2013), and
//! [`offset_ray_origin`] moves a spawned ray's origin past the intersection's
//! floating-point error box (pbrt-v4, §6.8.6) so a ray never re-hits its own surface.

use glam::{Vec2, Vec3};

/// π in `f32`.
pub const PI: f32 = std::f32::consts::PI;
/// 1/π in `f32`.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// 2π in `f32`.
pub const TWO_PI: f32 = 2.0 * std::f32::consts::PI;
/// 1/(4π) in `f32`.
pub const INV_FOUR_PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;

/// `sqrt(max(x, 0))`: never NaN for a slightly negative rounding error.
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// `acos(clamp(x, −1, 1))`.
#[inline]
pub fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

/// `asin(clamp(x, −1, 1))`.
#[inline]
pub fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}

/// c/|c| for every finite c ≠ 0 (the zero vector gives NaN). Where |c|² is a normal
/// `f32` this is `c.normalize()`, bit for bit; beyond (|c| above ~1.8·10¹⁹, whose square
/// overflows, or below ~1.1·10⁻¹⁹, whose square underflows, as for the cross product of
/// a triangle's edges 10¹⁰ or 10⁻¹⁰ long) c is first divided by its largest component,
/// where `normalize` alone would give 0 or NaN.
#[inline]
pub fn unit_vector(c: Vec3) -> Vec3 {
    let l2 = c.length_squared();
    if (f32::MIN_POSITIVE..f32::INFINITY).contains(&l2) {
        c.normalize()
    } else {
        unit_vector_scaled(c)
    }
}

#[cold]
fn unit_vector_scaled(c: Vec3) -> Vec3 {
    (c / c.abs().max_element()).normalize()
}

/// The power of two 2^−⌊log₂ m⌋ that brings a positive finite `m` into [1, 2): scaling
/// by it is exact (short of the subnormal range), so a scale-invariant formula gives the
/// same value on the scaled inputs while their squares stay normal.
#[inline]
pub fn pow2_scale(m: f32) -> f32 {
    2f32.powi(-(m.log2().floor() as i32))
}

/// `a·b − c·d` with one rounding error (Kahan's algorithm with an FMA).
#[inline]
pub fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    let dop = a.mul_add(b, -cd);
    dop + err
}

/// γ_n = n·ε/(1 − n·ε), the bound on the relative error of n chained roundings
/// (Higham 2002, §3.1; pbrt-v4 eq. 6.22).
#[inline]
pub fn gamma(n: i32) -> f32 {
    let eps = f32::EPSILON * 0.5;
    (n as f32 * eps) / (1.0 - n as f32 * eps)
}

/// The direction with the given spherical coordinates about +z.
#[inline]
pub fn spherical_direction(sin_theta: f32, cos_theta: f32, phi: f32) -> Vec3 {
    let s = sin_theta.clamp(-1.0, 1.0);
    Vec3::new(s * phi.cos(), s * phi.sin(), cos_theta.clamp(-1.0, 1.0))
}

/// An orthonormal frame; `to_local` maps world vectors into the frame whose +z is `n`.
///
/// Built with the branchless construction of Duff et al. 2017, "Building an
/// Orthonormal Basis, Revisited" (JCGT 6(1)), which stays orthonormal for every
/// unit `n`, including `n = ±z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub s: Vec3,
    /// Second tangent.
    pub t: Vec3,
    /// Normal (local +z).
    pub n: Vec3,
}

impl Frame {
    /// A frame whose +z axis is the unit vector `n`.
    pub fn from_z(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// World → local.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local → world.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// Ray-origin offsetting (pbrt-v4 `OffsetRayOrigin`): push `p` along the normal `n`
/// by the projection of its error box `p_error` onto `n`, on the side `w` leaves, and
/// round the result away from `p` so the offset survives rounding.
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    Vec3::new(
        step_towards(po.x, offset.x),
        step_towards(po.y, offset.y),
        step_towards(po.z, offset.z),
    )
}

/// `x.next_up()` where `s > 0`, `x.next_down()` where `s < 0`, `x` where `s` is ±0 or
/// NaN: the same bits as the standard library's, on the bits (one step away from zero
/// adds one, towards zero subtracts one). Compiled, it keeps a branch on whether x and s
/// share a sign and one on an infinity, and chooses the ±0 or NaN direction by a select:
/// the standard library's pair branched on the direction's sign, which of an
/// axis-aligned wall's three offset components are zero changing from hit to hit, and
/// `offset_ray_origin` ran 5% of the Cornell box's time faster this way (README, issue
/// 16, session 56).
#[inline(always)]
pub fn step_towards(x: f32, s: f32) -> f32 {
    const SIGN: u32 = 0x8000_0000;
    let bits = x.to_bits();
    let abs = bits & !SIGN;
    // Where x is ±0 the step gives the smallest subnormal with s's sign.
    let zero_step = (s.to_bits() & SIGN) | 1;
    // Away from zero where x and s have the same sign; an infinity cannot go further.
    let away = (bits ^ s.to_bits()) & SIGN == 0;
    let stepped = if away {
        if abs == f32::INFINITY.to_bits() {
            bits
        } else {
            bits.wrapping_add(1)
        }
    } else {
        bits.wrapping_sub(1)
    };
    let out = if abs == 0 { zero_step } else { stepped };
    // NaN x, or s = ±0 or NaN: unchanged.
    // `!(|s| > 0)` is true for ±0 and NaN alike (`s == 0` would step a NaN direction).
    if x.is_nan() || !(s.abs() > 0.0) {
        x
    } else {
        f32::from_bits(out)
    }
}

/// `(x, y)` of a unit direction's azimuth in [0, 2π).
#[inline]
pub fn azimuth(v: Vec3) -> f32 {
    let p = v.y.atan2(v.x);
    if p < 0.0 { p + TWO_PI } else { p }
}

/// Convert 24 random bits into a float in [0, 1): every value exactly representable.
#[inline]
pub fn unit_float_from_bits(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The largest `f32` below one: uniform samples are clamped to [0, ONE_MINUS_EPSILON].
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON * 0.5;

/// Clamp a 2-D uniform sample into [0, 1)².
#[inline]
pub fn clamp_unit(u: Vec2) -> Vec2 {
    u.clamp(Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON))
}

#[cfg(test)]
mod tests {
    #[test]
    fn unit_vector_holds_beyond_the_f32_squares() {
        // Within the normal range: normalize's bits.
        for c in [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-1e-9, 3e-10, 0.0),
            Vec3::new(1e18, 0.0, -1e18),
        ] {
            assert_eq!(super::unit_vector(c), c.normalize());
        }
        // Beyond it (|c|² overflows or underflows), a unit vector along c, where
        // normalize gives 0 or NaN.
        for c in [
            Vec3::new(3e20, -4e20, 0.0),
            Vec3::new(3e-25, -4e-25, 0.0),
            Vec3::new(f32::MAX, f32::MAX, 0.0),
            Vec3::new(0.0, f32::from_bits(1), 0.0),
        ] {
            let u = super::unit_vector(c);
            assert!((u.length() - 1.0).abs() < 1e-6, "{c:?}: {u:?}");
            let e = c.as_dvec3().normalize();
            assert!(
                (u.as_dvec3() - e).length() < 1e-6,
                "{c:?}: {u:?} against {e:?}"
            );
            assert!(!c.normalize().is_normalized());
        }
    }

    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn frame_is_orthonormal(x in -1.0f32..1.0, y in -1.0f32..1.0, z in -1.0f32..1.0) {
            let v = Vec3::new(x, y, z);
            prop_assume!(v.length() > 1e-3);
            let f = Frame::from_z(v.normalize());
            prop_assert!((f.s.length() - 1.0).abs() < 1e-5);
            prop_assert!((f.t.length() - 1.0).abs() < 1e-5);
            prop_assert!(f.s.dot(f.t).abs() < 1e-5);
            prop_assert!(f.s.dot(f.n).abs() < 1e-5);
            let w = Vec3::new(0.3, -0.2, 0.9).normalize();
            prop_assert!((f.to_world(f.to_local(w)) - w).length() < 1e-5);
        }
    }

    #[test]
    fn frame_at_poles() {
        for n in [Vec3::Z, -Vec3::Z] {
            let f = Frame::from_z(n);
            assert!(f.s.is_finite() && f.t.is_finite());
            assert!((f.s.cross(f.t) - n).length() < 1e-6);
        }
    }

    #[test]
    fn difference_of_products_is_exact_where_naive_cancels() {
        let a = 1.0f32 + f32::EPSILON;
        let r = difference_of_products(a, a, 1.0, 1.0);
        let exact = (a as f64) * (a as f64) - 1.0;
        assert!(((r as f64) - exact).abs() <= exact * 1e-6);
    }

    /// `step_towards` gives the standard library's `next_up`/`next_down` bit for bit:
    /// at the special values (±0, subnormals, ±MAX, ±∞, NaN, either sign of the
    /// direction, a zero or NaN direction) and at 2¹⁸ random bit patterns.
    #[test]
    fn step_towards_is_next_up_or_next_down() {
        let std_step = |x: f32, s: f32| {
            if s > 0.0 {
                x.next_up()
            } else if s < 0.0 {
                x.next_down()
            } else {
                x
            }
        };
        let specials = [
            0.0,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1.0,
            -1.0,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        let same = |x: f32, s: f32| {
            let (a, b) = (step_towards(x, s), std_step(x, s));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "x = {x:e} ({:#x}), s = {s:e}: {a:e} against {b:e}",
                x.to_bits()
            );
        };
        for &x in &specials {
            for &s in &specials {
                same(x, s);
            }
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..1 << 18 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let (x, s) = (
                f32::from_bits((state >> 32) as u32),
                f32::from_bits(state as u32),
            );
            same(x, s);
        }
    }

    /// The origin moves along n by the error box's projection, |n|·err, then one ulp
    /// further: p + offset, not some other combination of the two.
    #[test]
    fn offset_is_the_error_bounds_projection_along_the_normal() {
        let (p, err, n) = (Vec3::new(1.0, 2.0, 3.0), Vec3::splat(1e-3), Vec3::Z);
        let up = offset_ray_origin(p, err, n, Vec3::Z);
        assert_eq!(up, Vec3::new(1.0, 2.0, (3.0f32 + 1e-3).next_up()));
        let down = offset_ray_origin(p, err, n, -Vec3::Z);
        assert_eq!(down, Vec3::new(1.0, 2.0, (3.0f32 - 1e-3).next_down()));
        let n = Vec3::new(0.6, 0.0, -0.8);
        let side = offset_ray_origin(p, err, n, n);
        let d = 1.4e-3f32;
        assert_eq!(
            side,
            Vec3::new((1.0 + 0.6 * d).next_up(), 2.0, (3.0 - 0.8 * d).next_down())
        );
    }

    #[test]
    fn offset_moves_to_the_right_side() {
        let p = Vec3::new(1e5, 1e5, 0.0);
        let err = Vec3::splat(gamma(7) * p.abs().max_element());
        let n = Vec3::Z;
        let up = offset_ray_origin(p, err, n, Vec3::Z);
        let down = offset_ray_origin(p, err, n, -Vec3::Z);
        assert!(up.z > 0.0 && down.z < 0.0);
    }

    #[test]
    fn safe_functions_clamp() {
        assert_eq!(safe_sqrt(-1e-9), 0.0);
        assert_eq!(safe_acos(1.0000001), 0.0);
        assert!(safe_asin(-1.1).is_finite());
        assert!(unit_float_from_bits(u32::MAX) < 1.0);
    }
}
