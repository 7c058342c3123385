//! Fresnel reflectance and the reflection/refraction of directions.
//!
//! - [`fr_dielectric`]: unpolarised reflectance of a smooth interface between two
//!   dielectrics, R = ½(r∥² + r⊥²) with r∥ = (η cos θi − cos θt)/(η cos θi + cos θt),
//!   r⊥ = (cos θi − η cos θt)/(cos θi + η cos θt), sin θt = sin θi/η, and R = 1 past
//!   the critical angle (total internal reflection). Born & Wolf, *Principles of
//!   Optics*, §1.5; pbrt-v4 §9.5.1 (`FrDielectric`).
//! - [`fr_conductor`]: unpolarised reflectance of a conductor of complex relative index
//!   n̂ = η + ik (Born & Wolf §14.2): with w = √(n̂² − sin²θ) and d = n̂² − 1,
//!   R⊥ = |cos θ − w|²/|cos θ + w|² = |d|²/|cos θ + w|⁴,
//!   R∥ = R⊥ |w cos θ − sin²θ|²/|w cos θ + sin²θ|², in real arithmetic without
//!   cancellation (pbrt-v3 §8.2.1's `FrConductor` form, used before, cancels
//!   near the matched index n̂ = 1 and at grazing incidence).
//! - [`fresnel_diffuse_reflectance`]: the hemispherical average
//!   F_dr(η) = ∫₀¹ R(μ, η) 2μ dμ of the dielectric reflectance under uniform
//!   (Lambertian) illumination, by adaptive Gauss–Legendre quadrature in `f64`
//!   (a constant computed once per material, so the cost does not matter; the
//!   polynomial fits in the literature are good to about 1%, not enough for a test
//!   that resolves 1%).
//!
//! The tests compare these `f32` formulas against an independent `f64` complex-number
//! implementation (`tests/proof/bsdf_contract.rs`).

use glam::Vec3;

/// The incident side's |cos θi|, the relative index η seen from that side (1/η for a
/// direction inside), cos θt by Snell's law and d = η² − 1 of that side's index; `None`
/// under total internal reflection (or a NaN argument). cos²θt = 1 − sin²θi/η² =
/// (d + cos²θi)/η²: no cancellation as η → 1. d is formed from the given η on both sides,
/// (η − 1)(η + 1) outside and −(η − 1)(η + 1)/η² inside: (1/η)² − 1 from the rounded
/// 1/η would carry its rounding, 6·10⁻⁸, as 3·10⁻⁴ of d at |η − 1| = 10⁻⁴.
#[inline]
fn refraction_cosines(cos_i: f32, eta: f32) -> Option<(f32, f32, f32, f32)> {
    let cos_i = cos_i.clamp(-1.0, 1.0);
    let d = (eta - 1.0) * (eta + 1.0);
    let (cos_i, eta, d) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta, -d / (eta * eta))
    } else {
        (cos_i, eta, d)
    };
    let cos2_t = (d + cos_i * cos_i) / (eta * eta);
    (cos2_t > 0.0).then(|| (cos_i, eta, cos2_t.min(1.0).sqrt(), d))
}

/// Unpolarised Fresnel reflectance of a dielectric interface.
///
/// `cos_i` is the cosine between the incident direction and the normal; positive when
/// the direction is on the side of the normal (outside), in which case `eta` is
/// η_inside/η_outside; a negative cosine means the direction is inside and the
/// relative index becomes 1/`eta`. Returns a value in [0, 1]; 1 under total internal
/// reflection and at grazing incidence.
///
/// The amplitudes without cancellation as η → 1: with d = (η − 1)(η + 1) and η² cos²θt =
/// d + cos²θi ([`refraction_cosines`]), cos θi − η cos θt = −d/(cos θi + η cos θt) and
/// η cos θi − cos θt = d((η² + 1) cos²θi − 1)/(η²(η cos θi + cos θt)), so
/// r⊥ = −d/(cos θi + η cos θt)² and r∥ = d((η² + 1) cos²θi − 1)/(η (η cos θi + cos θt))².
/// The textbook differences lost up to 7 567 ulps of a reflectance of 10⁻⁹ at η = 1.0001
/// (session 52's audit) and 4.6·10⁵ at η = 1 + 2⁻²⁰; this form keeps F within 8 ulps
/// and gives R = 0 exactly at η = 1 (`dielectric_is_accurate_near_the_matched_index`).
#[inline]
pub fn fr_dielectric(cos_i: f32, eta: f32) -> f32 {
    let Some((cos_i, eta, cos_t, d)) = refraction_cosines(cos_i, eta) else {
        return 1.0;
    };
    let (a, b) = (eta * cos_i + cos_t, cos_i + eta * cos_t);
    // r⊥ = −d/b²; only its square enters R.
    let r_perp = d / (b * b);
    let ea = eta * a;
    let r_parl = d * ((eta * eta + 1.0) * (cos_i * cos_i) - 1.0) / (ea * ea);
    let r = 0.5 * (r_parl * r_parl + r_perp * r_perp);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Unpolarised Fresnel transmittance 1 − R of a dielectric interface (same arguments
/// as [`fr_dielectric`]), computed directly as
/// T = 2η cos θi cos θt (1/(η cos θi + cos θt)² + 1/(cos θi + η cos θt)²)
/// (from 1 − r² = (1 − r)(1 + r)): where R → 1 (grazing, near total internal
/// reflection), 1 − R in `f32` keeps no digits, and this form keeps all of them, which
/// the reciprocity of a rough dielectric's transmission (evaluated once from each side)
/// needs.
#[inline]
pub fn tr_dielectric(cos_i: f32, eta: f32) -> f32 {
    let Some((cos_i, eta, cos_t, _)) = refraction_cosines(cos_i, eta) else {
        return 0.0;
    };
    let a = eta * cos_i + cos_t;
    let b = cos_i + eta * cos_t;
    let t = 2.0 * eta * cos_i * cos_t * (1.0 / (a * a) + 1.0 / (b * b));
    if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Unpolarised Fresnel reflectance of a conductor with complex relative index
/// `eta` + i`k`, at incidence cosine `|cos_i|`.
///
/// Written so that no step cancels (the pbrt-v3 form it replaces lost every digit near
/// the matched index). With n̂ = η + ik, d = n̂² − 1 = (η − 1)(η + 1) − k² + 2iηk and
/// w = a + ib = √(n̂² − sin²θ) = √(d + cos²θ) (principal root, a, b ≥ 0):
/// - R⊥ = |cos θ − w|²/|cos θ + w|² = |d|²/|cos θ + w|⁴, from cos θ − w = −d/(cos θ + w),
///   with |cos θ + w|² = |w|² + cos²θ + 2a cos θ, a sum of non-negative terms;
/// - R∥ = R⊥ |w cos θ − sin²θ|²/|w cos θ + sin²θ|², each |·|² summed from its real and
///   imaginary parts, (a cos θ ∓ sin²θ)² + (b cos θ)²;
/// - Re w² = t₀ = η² − k² − sin²θ is formed as d_re + cos²θ below 45° of grazing and as
///   (η² − k²) − sin²θ (sin²θ = (1 − cos θ)(1 + cos θ)) nearer the normal, so that its
///   error is ε times its own terms (the old 1 − cos²θ rounded to 1 within 0.014° of
///   grazing and made F = 1 at η = 1, k = 0);
/// - a² = ½(|w|² + t₀) for t₀ ≥ 0 and (ηk)²/b² with b² = ½(|w|² − t₀) for t₀ < 0 (the
///   other root cancels: a metal's a lost up to ~2 digits); b² = ½(|w|² − t₀) is used
///   as it is: it enters only as b² cos²θ in sums ≤ |w cos θ + sin²θ|², where its
///   absolute error ε|w|² cos²θ moves R∥/R⊥ by at most ~ε.
///
/// At the matched index (d = 0 exactly: η = 1, k = 0) F is 0 at every angle, grazing
/// included. Within a few `f32` ulps of the `f64` complex Fresnel equations for the
/// validated indices (`conductor_is_accurate_near_the_matched_index`,
/// `conductor_is_accurate_for_extreme_indices`), but where |d|² or |w|² underflow
/// (η = 1 and 0 < k < 10⁻¹⁹ within ~√k of grazing). Never NaN, negative or above 1.
#[inline]
pub fn fr_conductor(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = cos_i.abs().min(1.0);
    fr_conductor_cs(c, (1.0 - c) * (1.0 + c), eta, k)
}

/// [`fr_conductor`] at an incidence given by cos θ ∈ [0, 1] and sin²θ = 1 − cos²θ, for a
/// caller that has a sin²θ more accurate than (1 − cos θ)(1 + cos θ) of a rounded
/// cosine (|ω × m|² of two unit vectors near the normal, where cos θ ≈ 1 keeps only
/// its absolute `f32` error).
#[inline]
pub fn fr_conductor_cs(c: f32, s2: f32, eta: f32, k: f32) -> f32 {
    let c2 = c * c;
    let k2 = k * k;
    // d = n̂² − 1.
    let dr = (eta - 1.0) * (eta + 1.0) - k2;
    let di = 2.0 * eta * k;
    if dr == 0.0 && di == 0.0 {
        // The matched index: no interface.
        return 0.0;
    }
    let t0 = if c2 < 0.5 {
        dr + c2
    } else {
        (eta * eta - k2) - s2
    };
    // |w|² and the squares of w's parts.
    let m = (t0 * t0 + di * di).sqrt();
    let b2 = (0.5 * (m - t0)).max(0.0);
    let a2 = if t0 >= 0.0 {
        0.5 * (m + t0)
    } else {
        (0.5 * di) * (0.5 * di / b2)
    };
    let ca = c * a2.sqrt();
    let cb2 = c2 * b2;
    let den_s = m + c2 + 2.0 * ca;
    let p_minus = (ca - s2) * (ca - s2) + cb2;
    let p_plus = (ca + s2) * (ca + s2) + cb2;
    // ½(R⊥ + R∥) = ½ R⊥ (1 + p₋/p₊), one division.
    let r = 0.5 * (dr * dr + di * di) * (p_plus + p_minus) / (den_s * den_s * p_plus);
    // r ≥ 0 by construction; NaN (0/0: a NaN argument, or |d| underflowing at grazing,
    // where the limit is 1) and ∞ become 1.
    if r.is_finite() { r.min(1.0) } else { 1.0 }
}

/// `f64` dielectric reflectance (for constants computed once, e.g. [`fresnel_diffuse_reflectance`]).
pub fn fr_dielectric_f64(cos_i: f64, eta: f64) -> f64 {
    let (mut c, mut eta) = (cos_i.clamp(-1.0, 1.0), eta);
    if c < 0.0 {
        eta = 1.0 / eta;
        c = -c;
    }
    let sin2_t = (1.0 - c * c) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - sin2_t).max(0.0).sqrt();
    let rp = (eta * c - ct) / (eta * c + ct);
    let rs = (c - eta * ct) / (c + eta * ct);
    0.5 * (rp * rp + rs * rs)
}

/// Hemispherical average F_dr(η) = ∫₀¹ R(μ, η) 2μ dμ of the reflectance seen from the
/// side whose relative index is `eta` (η > 1: from outside a denser medium; η < 1: from
/// inside, where total internal reflection makes the average large).
///
/// For η < 1 the integral is split at the critical cosine, where R has a kink; the
/// identity 1 − F_dr(1/η) = η²(1 − F_dr(η)) (étendue) holds to the quadrature's
/// tolerance and is tested.
pub fn fresnel_diffuse_reflectance(eta: f64) -> f64 {
    let f = |mu: f64| fr_dielectric_f64(mu, eta) * 2.0 * mu;
    if eta >= 1.0 {
        crate::quadrature::adaptive(f, 0.0, 1.0, 1e-12, 1e-15)
    } else {
        let mu_c = (1.0 - eta * eta).max(0.0).sqrt();
        mu_c * mu_c + crate::quadrature::adaptive(f, mu_c, 1.0, 1e-12, 1e-15)
    }
}

/// Mirror `w` about the normal `n`: 2(w·n)n − w.
#[inline]
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    2.0 * w.dot(n) * n - w
}

/// Refract `w` (pointing away from the surface, on the side `n` points to, so
/// w·n > 0) through a surface with relative index `eta` = η_(other side)/η_(side of w).
/// Returns the refracted direction (pointing away on the other side), or `None` under
/// total internal reflection.
#[inline]
pub fn refract(w: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = w.dot(n);
    if eta * eta < 0.0625 {
        return refract_from_denser(w, n, cos_i, eta);
    }
    // cos²θt = ((η − 1)(η + 1) + cos²θi)/η² (see fr_dielectric).
    let cos2_t = ((eta - 1.0) * (eta + 1.0) + cos_i * cos_i) / (eta * eta);
    if !(cos2_t > 0.0) {
        return None;
    }
    let cos_t = cos2_t.min(1.0).sqrt();
    // cos_i/η − cos_t written as ((1 − η²)/η²)/(cos_i/η + cos_t): the difference cancels
    // catastrophically as η → 1 (four digits lost at η = 1.0001), the quotient does not.
    let k = ((1.0 - eta) * (1.0 + eta) / (eta * eta)) / (cos_i / eta + cos_t);
    let k = if k.is_finite() {
        k
    } else {
        cos_i / eta - cos_t
    };
    Some(-w / eta + k * n)
}

/// [`refract`] out of a much denser side (η < 1/4), by Snell's law written per part
/// (Hecht, Optics, §4.4): with ω_t the part of ω along the surface (ω minus its normal
/// part, projected twice so that no multiple of n survives to be magnified by 1/η),
/// t = −ω_t/η − cos θt n and cos²θt = 1 − |ω_t|²/η², so |t|² = 1 to rounding. The general
/// form −ω/η + k n cancels two terms of size 1/η there, and cos²θi's rounding is
/// magnified by 1/η²: at η = 0.01, ω = (2⁻¹¹, 0, 0.9999999) it gave |t| = 1 + 9.4·10⁻⁵.
#[cold]
fn refract_from_denser(w: Vec3, n: Vec3, cos_i: f32, eta: f32) -> Option<Vec3> {
    let wt = w - cos_i * n;
    let wt = wt - wt.dot(n) * n;
    let cos2_t = 1.0 - wt.length_squared() / (eta * eta);
    if !(cos2_t > 0.0) {
        return None;
    }
    Some(-wt / eta - cos2_t.min(1.0).sqrt() * n)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Refraction out of a much denser side keeps unit length: for η = 0.01 … 0.2 and
    /// unit ω at every angle up to the critical one, |t| − 1 ≤ 4ε. At η = 0.01 and
    /// ω = (2⁻¹¹, 0, 0.9999999) it once returned (−0.048828, 0, −0.998901), of length
    /// 1 + 9.4·10⁻⁵ (cos²θi's rounding magnified by 1/η²).
    #[test]
    fn refraction_from_a_denser_side_is_unit() {
        let w = Vec3::new(0.000_488_281_25, 0.0, 0.999_999_9);
        let t = refract(w, Vec3::Z, 0.01).unwrap();
        assert!((t.length() - 1.0).abs() <= 4.0 * f32::EPSILON, "{t}");
        let mut refracted = 0;
        for eta in [0.01f32, 0.02, 0.05, 0.1, 0.2, 0.249] {
            for k in 0..=1000 {
                let sin = eta * k as f32 / 1000.0;
                let w = Vec3::new(sin * 0.6, sin * 0.8, (1.0 - sin * sin).sqrt()).normalize();
                let Some(t) = refract(w, Vec3::Z, eta) else {
                    continue;
                };
                refracted += 1;
                // Onto the other side.
                assert!(t.z < 0.0, "η {eta}, ω {w}: t {t}");
                assert!(
                    (t.length() - 1.0).abs() <= 4.0 * f32::EPSILON,
                    "η {eta}, ω {w}: t {t}, |t| − 1 = {:e}",
                    t.length() - 1.0
                );
                // Snell: the tangential part is ω's over −η.
                let tan = Vec3::new(t.x, t.y, 0.0) + Vec3::new(w.x, w.y, 0.0) / eta;
                assert!(tan.length() <= 4.0 * f32::EPSILON, "η {eta}, ω {w}: t {t}");
            }
        }
        // Every ω up to the critical angle sin θc = η refracts (k = 1000 may not).
        assert!(refracted >= 6 * 1000, "{refracted}");
        // About a tilted normal (a microfacet's m, whose squared length is 1 only to
        // rounding), where ω's normal part is not removed exactly by one projection: the
        // second removes what is left, which 1/η would magnify.
        let mut worst = 0.0f32;
        for (i, m) in [(0.3f32, -0.2, 1.0), (-0.7, 0.1, 0.4), (0.05, 0.9, 0.3)]
            .into_iter()
            .enumerate()
        {
            let n = Vec3::from(m).normalize();
            let f = crate::math::Frame::from_z(n);
            for eta in [0.01f32, 0.05, 0.2] {
                for k in 0..=200 {
                    let sin = eta * k as f32 / 200.0;
                    let local = Vec3::new(sin * 0.6, sin * 0.8, (1.0 - sin * sin).sqrt());
                    let w = f.to_world(local).normalize();
                    let Some(t) = refract(w, n, eta) else {
                        continue;
                    };
                    assert!(t.dot(n) < 0.0, "normal {i}, η {eta}, ω {w}: t {t}");
                    worst = worst.max((t.length() - 1.0).abs());
                    assert!(
                        (t.length() - 1.0).abs() <= 8.0 * f32::EPSILON,
                        "normal {i}, η {eta}, ω {w}: |t| − 1 = {:e}",
                        t.length() - 1.0
                    );
                }
            }
        }
        println!("tilted normals: worst |t| − 1 = {worst:e}");
    }

    /// `fr_dielectric` against the textbook form in `f64` (`fr_dielectric_f64`, whose
    /// cancellation costs ~10⁻¹² relative at |η − 1| = 10⁻⁴) at the same `f32` cosine and
    /// index, from both sides, normal incidence to 89.9°: within 8 ulps of F for indices
    /// from 1 + 2⁻²⁰ to glass, and 0 exactly at η = 1. The textbook form in `f32` was off
    /// by up to 458 745 ulps (η = 1 + 2⁻²⁰, 45° from inside), and d from the rounded 1/η
    /// by 2 866 (η = 1.0001, 89° from inside).
    #[test]
    fn dielectric_is_accurate_near_the_matched_index() {
        let mut worst = (0.0f64, 0.0, 0.0);
        for eta in [
            1.0 + 2f32.powi(-20),
            1.0001,
            0.9999,
            1.001,
            0.999,
            1.5,
            1.0 / 1.5,
            2.4,
        ] {
            for deg in [0.0f64, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0, 89.9] {
                for side in [1.0f32, -1.0] {
                    let c = side * deg.to_radians().cos() as f32;
                    let got = f64::from(fr_dielectric(c, eta));
                    let want = fr_dielectric_f64(f64::from(c), f64::from(eta));
                    let ulps = (got - want).abs() / (want * f64::from(f32::EPSILON));
                    if ulps > worst.0 {
                        worst = (ulps, f64::from(eta), f64::from(c));
                    }
                    assert_eq!(fr_dielectric(c, 1.0), 0.0, "η = 1, cos θ = {c}");
                }
            }
        }
        assert!(
            worst.0 <= 8.0,
            "{} ulps at η = {}, cos θ = {}",
            worst.0,
            worst.1,
            worst.2
        );
    }

    #[test]
    fn dielectric_limits() {
        assert!(fr_dielectric(1.0, 1.0).abs() < 1e-7);
        assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fr_dielectric(0.0, 1.5), 1.0);
        // From inside glass past the critical angle.
        assert_eq!(fr_dielectric(-0.3, 1.5), 1.0);
        for c in [-0.9, -0.5, 0.01, 0.3, 0.7, 1.0] {
            for eta in [1.0001, 1.33, 2.4, 0.5] {
                assert!(
                    (fr_dielectric(c, eta) + tr_dielectric(c, eta) - 1.0).abs() < 1e-6,
                    "{c} {eta}"
                );
            }
        }
        // The matched index has no interface, grazing included (it gave 1 before).
        assert_eq!(fr_conductor(0.0, 1.0, 0.0), 0.0);
        assert_eq!(fr_conductor(0.0, 1.5, 0.0), 1.0);
        assert!((fr_conductor(1.0, 1.5, 0.0) - 0.04).abs() < 1e-6);
    }

    /// F_dr: zero without an interface, about 0.092 for glass seen from outside (the
    /// literature's value for η = 1.5, e.g. d'Eon & Irving 2011) and 0.596 from inside,
    /// 1 − (1 − 0.092)/1.5² by the étendue identity `diffuse_reflectance_etendue_identity`
    /// checks; the inside one is larger (its total-internal-reflection cone).
    #[test]
    fn diffuse_reflectance_holds_its_values() {
        assert!(fresnel_diffuse_reflectance(1.0).abs() < 1e-15);
        let glass = fresnel_diffuse_reflectance(1.5);
        assert!((0.091..0.093).contains(&glass), "{glass}");
        let inside = fresnel_diffuse_reflectance(1.0 / 1.5);
        assert!((0.595..0.598).contains(&inside), "{inside}");
        for eta in [1.1f64, 1.33, 2.4] {
            let (out, inside) = (
                fresnel_diffuse_reflectance(eta),
                fresnel_diffuse_reflectance(1.0 / eta),
            );
            assert!(
                0.0 < out && out < inside && inside < 1.0,
                "{eta}: {out} {inside}"
            );
        }
    }

    /// Snell's law in f64: the refracted direction is a unit vector on the other side, in
    /// the plane of w and n, with sin θt = sin θi/η; none past the critical angle.
    #[test]
    fn refract_obeys_snells_law() {
        let n = Vec3::new(0.2, -0.1, 0.97).normalize();
        for w in [
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(-0.3, 0.5, 0.81),
            Vec3::new(0.05, 0.02, 0.99),
        ] {
            let w = w.normalize();
            for eta in [1.5f32, 1.0001, 2.4, 0.8] {
                let (ci, si) = (w.dot(n) as f64, w.cross(n).length() as f64);
                let st = si / eta as f64;
                match refract(w, n, eta) {
                    None => assert!(st > 1.0 - 1e-6, "{w} {eta}"),
                    Some(t) => {
                        assert!(ci > 0.0 && st < 1.0, "{w} {eta}");
                        assert!((t.length() - 1.0).abs() < 1e-5, "{t}");
                        assert!((t.dot(n) as f64 + (1.0 - st * st).sqrt()).abs() < 1e-5);
                        assert!(((t.cross(n).length() as f64) - st).abs() < 1e-5);
                        assert!(t.dot(n.cross(w)).abs() < 1e-5, "in the plane");
                    }
                }
            }
        }
    }

    /// The mirror direction 2(w·n)n − w: about +z and about a tilted normal, where it
    /// keeps w's angle to n and stays in the plane of w and n.
    #[test]
    fn reflect_mirrors_about_the_normal() {
        let w = Vec3::new(0.6, 0.0, 0.8);
        assert!((reflect(w, Vec3::Z) - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-7);
        let n = Vec3::new(0.3, -0.2, 0.9).normalize();
        let w = Vec3::new(-0.5, 0.4, 0.3).normalize();
        let r = reflect(w, n);
        assert!((r.length() - 1.0).abs() < 1e-6);
        assert!((r.dot(n) - w.dot(n)).abs() < 1e-6);
        assert!((r + w - 2.0 * w.dot(n) * n).length() < 1e-6);
        assert!(r.dot(n.cross(w)).abs() < 1e-6);
        assert!((r - w).length() > 0.1, "not the identity");
    }

    /// The conductor's reflectance against the Fresnel equations with a complex index
    /// n̂ = η + ik written out in `f64` complex arithmetic (Born & Wolf, Principles of
    /// Optics, §14.2): with w = √(n̂² − sin²θ) on the principal branch,
    /// R_s = |(cos θ − w)/(cos θ + w)|², R_p = |(n̂² cos θ − w)/(n̂² cos θ + w)|², R = ½(R_s + R_p);
    /// metals (gold, aluminium), a dielectric-like index and near-vacuum, normal to grazing.
    #[test]
    fn conductor_matches_the_complex_fresnel_equations() {
        type C = (f64, f64);
        let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let sqrt = |a: C| {
            let r = a.0.hypot(a.1);
            let re = ((r + a.0) / 2.0).sqrt();
            let im = ((r - a.0) / 2.0).sqrt().copysign(a.1);
            (re, im)
        };
        let norm2 = |a: C| a.0 * a.0 + a.1 * a.1;
        for (eta, k) in [
            (0.2f64, 3.9f64),
            (1.5, 0.5),
            (0.05, 2.0),
            (2.9, 3.1),
            (1.0, 1e-3),
        ] {
            for c in [1.0f64, 0.8, 0.5, 0.2, 0.05] {
                let n2 = mul((eta, k), (eta, k));
                let w = sqrt((n2.0 - (1.0 - c * c), n2.1));
                let rs = norm2(div((c - w.0, -w.1), (c + w.0, w.1)));
                let n2c = (n2.0 * c, n2.1 * c);
                let rp = norm2(div((n2c.0 - w.0, n2c.1 - w.1), (n2c.0 + w.0, n2c.1 + w.1)));
                let want = 0.5 * (rs + rp);
                let got = fr_conductor(c as f32, eta as f32, k as f32) as f64;
                assert!(
                    (got - want).abs() < 2e-6,
                    "R({c}, {eta} + {k}i) = {got}, not {want}"
                );
                // The side of the incident direction does not matter.
                assert_eq!(fr_conductor(-c as f32, eta as f32, k as f32) as f64, got);
            }
        }
    }

    /// The conductor's F in `f64`, from the cancellation-free complex form (as the
    /// oracle's near-matched branch, Born & Wolf §14.2): d = (n̂ − 1)(n̂ + 1),
    /// cos θt = √((d + cos²θ)/n̂²), r⊥ = −d/(cos θ + n̂ cos θt)²,
    /// r∥ = d((n̂² + 1) cos²θ − 1)/(n̂ (n̂ cos θ + cos θt))², F = ½(|r⊥|² + |r∥|²): an
    /// identity valid at every index, and free of cancellation but at a critical angle.
    pub(crate) fn conductor_f64(c: f64, eta: f64, k: f64) -> f64 {
        type C = (f64, f64);
        let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let add = |a: C, b: C| (a.0 + b.0, a.1 + b.1);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let sqrt = |a: C| {
            let r = a.0.hypot(a.1);
            let re = ((r + a.0) / 2.0).max(0.0).sqrt();
            let im = ((r - a.0) / 2.0).max(0.0).sqrt().copysign(a.1);
            (re, im)
        };
        let norm2 = |a: C| a.0 * a.0 + a.1 * a.1;
        let n = (eta, k);
        let d = mul((eta - 1.0, k), (eta + 1.0, k));
        let (ci, c2) = ((c, 0.0), (c * c, 0.0));
        let cos_t = sqrt(div(div(add(d, c2), n), n));
        let s = add(ci, mul(n, cos_t));
        let rs = div(d, mul(s, s));
        let n2 = mul(n, n);
        let p = mul(n, add(mul(n, ci), cos_t));
        let rp = div(
            mul(d, add(mul(add(n2, (1.0, 0.0)), c2), (-1.0, 0.0))),
            mul(p, p),
        );
        0.5 * (norm2(rs) + norm2(rp))
    }

    /// |F − F_f64| in `f32` ulps of F_f64 (ε F_f64), at the `f32` cosine of `deg`.
    fn conductor_ulps(deg: f64, eta: f32, k: f32) -> (f32, f64, f64) {
        let c = deg.to_radians().cos() as f32;
        let got = fr_conductor(c, eta, k);
        let want = conductor_f64(f64::from(c), f64::from(eta), f64::from(k));
        let ulps = (f64::from(got) - want).abs() / (want * f64::from(f32::EPSILON));
        (got, want, ulps)
    }

    /// At the matched index η = 1, k = 0 there is no interface: F = 0 exactly at every
    /// angle, grazing included. The pbrt-v3 form gave 1.5·10⁻⁸ at 45°, 3.0·10⁻⁵ at
    /// 89.98°, 1.2·10⁻³ at 89.985°, 0.028 at 89.99° and 1 from 89.995° on (1 − cos²θ
    /// rounded to 1, so η² − k² − sin²θ = 0 and R⊥ = t/t).
    #[test]
    fn conductor_reflects_nothing_at_the_matched_index() {
        for deg in [
            0.0f64, 10.0, 45.0, 80.0, 89.9, 89.98, 89.985, 89.99, 89.995, 89.999, 89.9999, 90.0,
        ] {
            let c = deg.to_radians().cos() as f32;
            assert_eq!(fr_conductor(c, 1.0, 0.0), 0.0, "{deg}°");
            assert_eq!(fr_conductor(-c, 1.0, 0.0), 0.0, "{deg}°");
        }
        for c in [0.0f32, 1e-30, f32::MIN_POSITIVE, 1e-45, 2.4e-4, 1.0] {
            assert_eq!(fr_conductor(c, 1.0, 0.0), 0.0, "cos θ = {c:e}");
        }
    }

    /// Near the matched index, η = 1 ± 10⁻⁴ with k = 0 or 10⁻⁴ (and η = 1, k = 10⁻⁴), F is
    /// within 4 `f32` ulps of the `f64` reference at 0°, 45°, 80° and 89.9° (worst seen:
    /// 2.4 ulps). The pbrt-v3 form missed by up to 1.7·10⁷ ulps: F = 0 at 0°–45° (exact
    /// 2.5·10⁻⁹ at 0° for η = 1.0001), 2.579017·10⁻⁶ for 2.571405·10⁻⁶ (+0.30%) at 80°,
    /// +0.77% at 80° for η = 0.9999, 168 ulps at 89.9° for η = 1.0001.
    #[test]
    fn conductor_is_accurate_near_the_matched_index() {
        for (eta, k) in [
            (1.0001f32, 0.0f32),
            (0.9999, 0.0),
            (1.0001, 1e-4),
            (0.9999, 1e-4),
            (1.0, 1e-4),
        ] {
            for deg in [0.0, 45.0, 80.0, 89.9] {
                let (got, want, ulps) = conductor_ulps(deg, eta, k);
                assert!(
                    ulps <= 4.0,
                    "F({deg}°, {eta} + {k}i) = {got:e}, not {want:e} ({ulps:.1} ulps)"
                );
            }
        }
    }

    /// Extreme indices of the validated range, normal to grazing: F within 4 `f32` ulps
    /// of the `f64` reference (worst seen: 2.3 ulps, gold-like 0.2 + 3.9i at 0°; 1.9 at
    /// 0.001 + 0i at 0°, where sin²θ < η² = 10⁻⁶). The pbrt-v3 form failed 0.001 + 100i
    /// (4.2 ulps at 60°, 72 at 89°: a = √(½(|w|² + t₀)) cancelled for t₀ < 0) and
    /// 0.001 + 1i (346 ulps at 30°).
    #[test]
    fn conductor_is_accurate_for_extreme_indices() {
        for (eta, k) in [
            (0.2f32, 3.9f32),
            (100.0, 100.0),
            (0.001, 0.0),
            (0.001, 100.0),
            (0.001, 1.0),
            (100.0, 0.0),
            (1.5, 0.0),
            (2.9, 3.1),
        ] {
            for deg in [0.0, 0.03, 1.0, 30.0, 45.0, 60.0, 80.0, 89.0, 89.9] {
                let (got, want, ulps) = conductor_ulps(deg, eta, k);
                assert!(
                    ulps <= 4.0,
                    "F({deg}°, {eta} + {k}i) = {got:e}, not {want:e} ({ulps:.1} ulps)"
                );
            }
        }
    }

    /// F is finite and in [0, 1] for every index and cosine, also where squares underflow
    /// (η = 1 with k down to 10⁻³⁰, subnormal and zero cosines) and for NaN arguments.
    #[test]
    fn conductor_is_bounded() {
        for eta in [
            1e-3f32,
            0.5,
            0.9999999,
            1.0,
            1.0000001,
            1.5,
            100.0,
            f32::NAN,
        ] {
            for k in [0.0f32, 1e-30, 1e-19, 1e-10, 1e-4, 1.0, 100.0, f32::NAN] {
                for c in [
                    0.0f32,
                    1e-45,
                    1e-30,
                    1e-20,
                    1e-10,
                    1e-5,
                    0.5,
                    0.9999999,
                    1.0,
                    f32::NAN,
                ] {
                    let f = fr_conductor(c, eta, k);
                    assert!((0.0..=1.0).contains(&f), "F({c:e}, {eta} + {k}i) = {f}");
                }
            }
        }
    }

    /// Both sides of the interface against the Fresnel equations in their angle form
    /// (Hecht, Optics, eqs. 4.42–4.43): R_s = sin²(θi − θt)/sin²(θi + θt),
    /// R_p = tan²(θi − θt)/tan²(θi + θt), θt from Snell's law sin θt = sin θi/η, with 1/η
    /// for a direction inside; total internal reflection gives R = 1, T = 0.
    #[test]
    fn dielectric_matches_the_angle_form_on_both_sides() {
        for c in [-0.95, -0.6, -0.3, -0.05, 0.05, 0.3, 0.6, 0.95] {
            for eta in [1.0001f64, 1.33, 1.5, 2.4, 0.7] {
                let rel = if c < 0.0 { 1.0 / eta } else { eta };
                let ti = (c as f64).abs().acos();
                let st = ti.sin() / rel;
                let (r, t) = if st >= 1.0 {
                    (1.0, 0.0)
                } else {
                    let tt = st.asin();
                    let rs = ((ti - tt).sin() / (ti + tt).sin()).powi(2);
                    let rp = ((ti - tt).tan() / (ti + tt).tan()).powi(2);
                    let r = 0.5 * (rs + rp);
                    (r, 1.0 - r)
                };
                let (fr, tr) = (fr_dielectric(c, eta as f32), tr_dielectric(c, eta as f32));
                assert!(
                    (fr as f64 - r).abs() < 2e-6,
                    "R({c}, {eta}) = {fr}, not {r}"
                );
                assert!(
                    (tr as f64 - t).abs() < 2e-6,
                    "T({c}, {eta}) = {tr}, not {t}"
                );
                assert!(
                    (fr_dielectric_f64(c as f64, eta) - r).abs() < 1e-12,
                    "{c} {eta}"
                );
            }
        }
    }

    #[test]
    fn diffuse_reflectance_etendue_identity() {
        for eta in [1.0001, 1.33, 1.5, 2.4] {
            let ext = fresnel_diffuse_reflectance(eta);
            let int = fresnel_diffuse_reflectance(1.0 / eta);
            assert!(
                ((1.0 - int) * eta * eta - (1.0 - ext)).abs() < 1e-8,
                "{eta}: {ext} {int}"
            );
        }
    }

    #[test]
    fn refraction_obeys_snell() {
        let w = Vec3::new(0.6, 0.0, 0.8);
        let t = refract(w, Vec3::Z, 1.5).unwrap();
        assert!((t.length() - 1.0).abs() < 1e-6);
        assert!((0.6 - 1.5 * (-t.x)).abs() < 1e-6);
        assert!(refract(Vec3::new(0.9, 0.0, 0.436), Vec3::Z, 1.0 / 1.5).is_none());
    }
}
