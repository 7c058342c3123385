//! Directional albedos of the two Oren–Nayar forms, in closed form.
//!
//! **Classic "qualitative" model** (Oren & Nayar 1994, eq. 30; pbrt-v3 §8.4.2), σ the
//! standard deviation of the facet slope angle in radians:
//! f = ρ/π (A + B max(0, cos(φi − φo)) sin α tan β), α = max(θi, θo), β = min(θi, θo),
//! A = 1 − σ²/(2(σ² + 0.33)), B = 0.45 σ²/(σ² + 0.09).
//!
//! **Fujii's form** (Y. Fujii 2012, "A tiny improvement of Oren-Nayar reflectance
//! model"): f = ρ/π (A + B s/t), s = cos(φi − φo) sin θi sin θo, t = 1 if s ≤ 0 else
//! max(cos θi, cos θo), A = 1/(1 + (π/2 − 2/3)σ), B = σA.
//!
//! **Derivation.** sin α tan β = sin θi sin θo / max(cos θi, cos θo) (whichever angle is
//! larger), so both forms integrate over φi with ∫ max(0, cos φ) dφ = 2 and
//! ∫ min(0, cos φ) dφ = −2. With μ = cos θi, μo = cos θo, dωi = dμ dφ and
//! K(μo) = ∫₀¹ μ √(1 − μ²)/max(μ, μo) dμ
//!       = (1 − (1 − μo²)^{3/2})/(3μo) + π/4 − (μo √(1 − μo²) + asin μo)/2:
//!
//! - classic: ρ(θo)/ρ = A + (2B/π) sin θo K(μo),
//! - Fujii:   ρ(θo)/ρ = A + (2B/π) sin θo (K(μo) − 1/3)  (the s ≤ 0 half gives
//!   −2 sin θo ∫₀¹ μ √(1 − μ²) dμ = −(2/3) sin θo).
//!
//! At grazing, K → π/4, so the classic albedo tends to ρ(A + B/2), above ρ for small σ
//! (1.0078 ρ at σ = 0.1): the classic model is not energy conserving there. The tests
//! check both against a quadrature of the BRDFs as written (angles, tan β), not the
//! rearranged forms.

use std::f64::consts::PI;

/// Which Oren–Nayar form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Oren & Nayar 1994 (pbrt-v3), σ in radians.
    Classic,
    /// Fujii 2012, σ ∈ [0, 1].
    Fujii,
}

/// (A, B) of the form at roughness σ.
pub fn coefficients(form: Form, sigma: f64) -> (f64, f64) {
    match form {
        Form::Classic => {
            let s2 = sigma * sigma;
            (1.0 - s2 / (2.0 * (s2 + 0.33)), 0.45 * s2 / (s2 + 0.09))
        }
        Form::Fujii => {
            let a = 1.0 / (1.0 + (PI / 2.0 - 2.0 / 3.0) * sigma);
            (a, sigma * a)
        }
    }
}

/// K(μo) of the module doc, its first term written (1 + s + s²)μo/(3(1 + s)) with
/// s = sin θo so that it is exact at μo = 0.
fn k(mu_o: f64) -> f64 {
    let s = (1.0 - mu_o * mu_o).max(0.0).sqrt();
    (1.0 + s + s * s) * mu_o / (3.0 * (1.0 + s)) + PI / 4.0 - (mu_o * s + mu_o.asin()) / 2.0
}

/// Directional albedo ρ(θo) of the form with albedo ρ and roughness σ, cos θo ∈ [0, 1].
pub fn albedo(form: Form, rho: f64, sigma: f64, cos_theta: f64) -> f64 {
    let mu = cos_theta.clamp(0.0, 1.0);
    let s = (1.0 - mu * mu).sqrt();
    let (a, b) = coefficients(form, sigma);
    let shift = match form {
        Form::Classic => 0.0,
        Form::Fujii => 1.0 / 3.0,
    };
    rho * (a + 2.0 * b / PI * s * (k(mu) - shift))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::adaptive_2d;

    /// ∫ f cos θi dωi of the BRDF as written, by quadrature over (θi, φi) with the kinks
    /// (θi = θo, cos φ = 0) as sub-interval ends.
    fn brute(form: Form, rho: f64, sigma: f64, theta_o: f64) -> f64 {
        let (a, b) = coefficients(form, sigma);
        let f = |ti: f64, phi: f64| {
            let shape = match form {
                Form::Classic => {
                    let (al, be) = (ti.max(theta_o), ti.min(theta_o));
                    a + b * phi.cos().max(0.0) * al.sin() * be.tan()
                }
                Form::Fujii => {
                    let s = phi.cos() * ti.sin() * theta_o.sin();
                    let t = if s <= 0.0 {
                        1.0
                    } else {
                        ti.cos().max(theta_o.cos())
                    };
                    a + b * s / t
                }
            };
            rho / PI * shape * ti.cos() * ti.sin()
        };
        let mut total = 0.0;
        let cuts = [0.0, theta_o.min(PI / 2.0), PI / 2.0];
        for w in cuts.windows(2) {
            for (p0, p1) in [(0.0, PI / 2.0), (PI / 2.0, PI)] {
                total += adaptive_2d(f, w[0], w[1], |_| p0, |_| p1, 1e-11);
            }
        }
        2.0 * total
    }

    #[test]
    fn closed_forms_match_quadrature() {
        for form in [Form::Classic, Form::Fujii] {
            for sigma in [0.0, 0.1, 0.35, 1.0] {
                for theta in [0.0f64, 20.0, 55.0, 80.0, 89.0] {
                    let t = theta.to_radians();
                    let c = albedo(form, 0.8, sigma, t.cos());
                    let q = brute(form, 0.8, sigma, t);
                    assert!(
                        (c - q).abs() < 1e-8,
                        "{form:?} σ = {sigma} θ = {theta}: {c} vs {q}"
                    );
                }
            }
        }
    }

    /// A and B at σ = 0.5, worked by hand from the papers' formulas (pbrt-v3:
    /// 1 − 0.25/1.16 and 0.1125/0.34; Fujii: 1/(1 + (π/2 − 2/3)/2) and half of it): the
    /// quadrature check above shares `coefficients` with the closed form, this pins it.
    #[test]
    fn coefficients_by_hand() {
        let (a, b) = coefficients(Form::Classic, 0.5);
        assert!((a - 0.7844827586206897).abs() < 1e-15, "{a}");
        assert!((b - 0.3308823529411765).abs() < 1e-15, "{b}");
        let (a, b) = coefficients(Form::Fujii, 0.5);
        assert!((a - 0.6886744856673139).abs() < 1e-15, "{a}");
        assert!((b - 0.34433724283365696).abs() < 1e-15, "{b}");
    }

    #[test]
    fn limits() {
        // σ = 0 is Lambertian; at normal incidence only A remains.
        for form in [Form::Classic, Form::Fujii] {
            assert_eq!(albedo(form, 0.7, 0.0, 0.3), 0.7);
            let (a, _) = coefficients(form, 0.5);
            assert!((albedo(form, 1.0, 0.5, 1.0) - a).abs() < 1e-15);
        }
        // Classic at grazing: A + B/2 (1.0078 at σ = 0.1, above 1).
        let (a, b) = coefficients(Form::Classic, 0.1);
        assert!((albedo(Form::Classic, 1.0, 0.1, 0.0) - (a + b / 2.0)).abs() < 1e-15);
        assert!(albedo(Form::Classic, 1.0, 0.1, 0.0) > 1.0);
    }
}
