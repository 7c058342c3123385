//! Planck's law of blackbody radiation, per nanometre, and its exact band integral.
//!
//! Everything is `f64` and in physical units: spectral radiance in W·m⁻²·sr⁻¹·nm⁻¹,
//! band radiance in W·m⁻²·sr⁻¹. Written independently of the oracle crate
//! (`lightproof-analytic`), which the tests compare against.

use super::photon::{BOLTZMANN, PLANCK, SPEED_OF_LIGHT};
use super::{finite_f64, gauss_legendre};
use std::f64::consts::PI;

/// The root x_w of x = 5(1 − e^{−x}) (the maximum of B_λ in x = hc/(λkT)).
const WIEN_X: f64 = 4.965_114_231_744_276;

/// Wien's displacement constant b = hc/(k x_w) = 2.897771955…e-3 m·K (CODATA 2018):
/// B_λ peaks at λ = b/T.
pub const WIEN_DISPLACEMENT: f64 = PLANCK * SPEED_OF_LIGHT / (BOLTZMANN * WIEN_X);

/// Second radiation constant c₂ = hc/k in nm·K.
const C2_NM_K: f64 = PLANCK * SPEED_OF_LIGHT / BOLTZMANN * 1e9;

/// π⁴/15 = ∫₀^∞ t³/(eᵗ − 1) dt.
const PI4_15: f64 = PI * PI * PI * PI / 15.0;

/// Blackbody spectral radiance per nanometre of wavelength (W·m⁻²·sr⁻¹·nm⁻¹).
///
/// **Formula.** Planck's law per unit wavelength,
/// B_λ(λ, T) = 2hc²/λ⁵ · 1/(exp(hc/(λkT)) − 1)  (W·m⁻²·sr⁻¹ per metre of λ),
/// times 10⁻⁹ m/nm. `exp_m1` keeps the Rayleigh–Jeans end (hc/λkT ≪ 1) accurate; where
/// λ⁵ or the exponential would leave the range of `f64`, the same formula is evaluated
/// in logarithms, so the result is 0 (deep Wien tail), finite and non-negative for every
/// input. λ or T not positive and finite gives 0.
///
/// **Source.** M. Planck, Ann. Phys. 4, 553 (1901); Siegel & Howell, *Thermal Radiation
/// Heat Transfer*, ch. 1.
pub fn planck_radiance(lambda_nm: f64, temperature: f64) -> f64 {
    if !(lambda_nm > 0.0 && temperature > 0.0 && lambda_nm.is_finite() && temperature.is_finite()) {
        return 0.0;
    }
    let x = C2_NM_K / lambda_nm / temperature;
    if x > 1e-250 && x < 700.0 && (1e-20..1e20).contains(&lambda_nm) {
        let l = lambda_nm * 1e-9;
        let l5 = l * l * l * l * l;
        let b = 2.0 * PLANCK * SPEED_OF_LIGHT * SPEED_OF_LIGHT / (l5 * x.exp_m1()) * 1e-9;
        if b.is_finite() && b > 0.0 {
            return b;
        }
    }
    // ln B = ln(2hc²) − 5 ln λ − ln(eˣ − 1) + ln 1e-9.
    let ln_l = lambda_nm.ln() + (1e-9f64).ln();
    let ln_em1 = if x.is_infinite() {
        return 0.0;
    } else if x > 30.0 {
        x + (-(-x).exp()).ln_1p()
    } else if x > 1e-8 {
        x.exp_m1().ln()
    } else {
        // eˣ − 1 = x(1 + x/2 + …); ln x from logarithms, immune to underflow.
        C2_NM_K.ln() - lambda_nm.ln() - temperature.ln() + 0.5 * x
    };
    let ln_b = (2.0 * PLANCK * SPEED_OF_LIGHT * SPEED_OF_LIGHT).ln() - 5.0 * ln_l - ln_em1
        + (1e-9f64).ln();
    finite_f64(ln_b.exp())
}

/// The Stefan–Boltzmann constant σ = 2π⁵k⁴/(15h³c²) = 5.670374419…e-8 W·m⁻²·K⁻⁴, from
/// the exact SI constants (Stefan 1879, Boltzmann 1884).
pub fn stefan_boltzmann() -> f64 {
    2.0 * PI.powi(5) * BOLTZMANN.powi(4) / (15.0 * PLANCK.powi(3) * SPEED_OF_LIGHT.powi(2))
}

/// Total radiance of a blackbody, ∫₀^∞ B_λ dλ = σT⁴/π (W·m⁻²·sr⁻¹); 0 for T not
/// positive, clamped to `f64::MAX`.
pub fn blackbody_total_radiance(temperature: f64) -> f64 {
    if !(temperature > 0.0) {
        return 0.0;
    }
    finite_f64(stefan_boltzmann() * temperature.powi(4) / PI)
}

/// Wavelength (nm) where B_λ(·, T) peaks: Wien's displacement law λ_max = b/T with
/// b = [`WIEN_DISPLACEMENT`] (Wien 1893). 0 for T not positive; clamped to `f64::MAX`.
pub fn wien_peak(temperature: f64) -> f64 {
    if !(temperature > 0.0) {
        return 0.0;
    }
    finite_f64(WIEN_DISPLACEMENT * 1e9 / temperature)
}

/// t³/(eᵗ − 1), → t² as t → 0.
fn bose(t: f64) -> f64 {
    if t <= 0.0 {
        0.0
    } else {
        t * t * t / t.exp_m1()
    }
}

/// F(x) = ∫ₓ^∞ t³/(eᵗ − 1) dt, to about 1e-15 relative.
///
/// For x ≥ 2 the series F(x) = Σ_{n≥1} e^{−nx} (x³/n + 3x²/n² + 6x/n³ + 6/n⁴) (expand
/// 1/(eᵗ − 1) = Σ e^{−nt} and integrate t³e^{−nt} by parts; Siegel & Howell §2, Chang &
/// Rhee 1984) converges as e^{−2n}. Below 2, F = π⁴/15 − ∫₀ˣ, the integral by
/// 16-panel Gauss–Legendre quadrature of an integrand analytic within 2π of [0, 2].
fn tail(x: f64) -> f64 {
    if x.is_nan() {
        return 0.0;
    }
    if x >= 800.0 {
        return 0.0;
    }
    if x >= 2.0 {
        let mut s = 0.0;
        for n in 1..=64 {
            let nf = n as f64;
            let term = (-nf * x).exp() / nf
                * (x * x * x + 3.0 * x * x / nf + 6.0 * x / (nf * nf) + 6.0 / (nf * nf * nf));
            s += term;
            if term <= 1e-17 * s {
                break;
            }
        }
        s
    } else if x > 0.0 {
        PI4_15 - gauss_legendre(0.0, x, 16, bose)
    } else {
        PI4_15
    }
}

/// Blackbody radiance in the band [λ₁, λ₂] (nm), ∫ B_λ dλ (W·m⁻²·sr⁻¹).
///
/// **Formula.** With x = hc/(λkT), ∫_{λ₁}^{λ₂} B_λ dλ = (2k⁴T⁴/(h³c²)) ∫_{x₂}^{x₁}
/// t³/(eᵗ − 1) dt = (2k⁴T⁴/(h³c²)) (F(x₂) − F(x₁)), F the upper incomplete integral
/// (series above, see `tail`); a band narrower than Δx = 1 is integrated directly
/// by 8-panel Gauss–Legendre in x, avoiding the cancellation of two close values of F.
/// [0, ∞] gives σT⁴/π. The relative error is about 1e-14.
///
/// **Degenerate input.** λ₁ < 0 counts as 0; an empty, NaN or reversed band, or T not
/// positive and finite, gives 0; overflow is clamped to `f64::MAX`.
///
/// **Source.** Siegel & Howell, *Thermal Radiation Heat Transfer*, ch. 1–2 (blackbody
/// fractions).
pub fn blackbody_band_radiance(lambda1_nm: f64, lambda2_nm: f64, temperature: f64) -> f64 {
    let c = 2.0 * BOLTZMANN.powi(4) / (PLANCK.powi(3) * SPEED_OF_LIGHT.powi(2));
    band_in_x(
        lambda1_nm,
        lambda2_nm,
        temperature,
        c * temperature.powi(4),
        bose,
        tail,
    )
}

/// `scale` · ∫_{x₂}^{x₁} f(t) dt over the band [λ₁, λ₂] (nm) mapped to x = hc/(λkT):
/// 8-panel Gauss–Legendre for a band narrower than Δx = 1 (no cancellation of two close
/// tails), else `upper(x₂) − upper(x₁)` with `upper` f's upper incomplete integral; 0
/// for a degenerate band or temperature, clamped to `f64::MAX`.
fn band_in_x(
    lambda1_nm: f64,
    lambda2_nm: f64,
    temperature: f64,
    scale: f64,
    f: fn(f64) -> f64,
    upper: fn(f64) -> f64,
) -> f64 {
    let l1 = lambda1_nm.max(0.0);
    if !(lambda2_nm > l1 && temperature > 0.0 && temperature.is_finite()) {
        return 0.0;
    }
    // x₁ ≥ x₂ (short wavelengths have large x).
    let x_of = |l: f64| C2_NM_K / l / temperature;
    let (x1, x2) = (x_of(l1), x_of(lambda2_nm));
    let integral = if x1.is_finite() && x1 - x2 <= 1.0 {
        gauss_legendre(x2, x1, 8, f)
    } else {
        upper(x2) - upper(x1)
    };
    finite_f64(scale * integral)
}

/// 2ζ(3) = ∫₀^∞ t²/(eᵗ − 1) dt (ζ(3) = 1.2020569031595942, Apéry's constant).
const TWO_ZETA3: f64 = 2.0 * 1.202_056_903_159_594_2;

/// t²/(eᵗ − 1), → t as t → 0.
fn bose2(t: f64) -> f64 {
    if t <= 0.0 { 0.0 } else { t * t / t.exp_m1() }
}

/// G(x) = ∫ₓ^∞ t²/(eᵗ − 1) dt, to about 1e-15 relative: as `tail`, the series
/// G(x) = Σ_{n≥1} e^{−nx} (x²/n + 2x/n² + 2/n³) for x ≥ 2, else 2ζ(3) − ∫₀ˣ by 16-panel
/// Gauss–Legendre (an integrand analytic within 2π of [0, 2]).
fn photon_tail(x: f64) -> f64 {
    if x.is_nan() || x >= 800.0 {
        return 0.0;
    }
    if x >= 2.0 {
        let mut s = 0.0;
        for n in 1..=64 {
            let nf = n as f64;
            let term = (-nf * x).exp() / nf * (x * x + 2.0 * x / nf + 2.0 / (nf * nf));
            s += term;
            if term <= 1e-17 * s {
                break;
            }
        }
        s
    } else if x > 0.0 {
        TWO_ZETA3 - gauss_legendre(0.0, x, 16, bose2)
    } else {
        TWO_ZETA3
    }
}

/// Blackbody photon radiance in the band [λ₁, λ₂] (nm), ∫ B_λ λ/(hc) dλ
/// (photons·s⁻¹·m⁻²·sr⁻¹, λ in metres in λ/(hc)).
///
/// **Formula.** With x = hc/(λkT), B_λ λ/(hc) dλ = (2k³T³/(h³c²)) x²/(eˣ − 1) dx, so the
/// band gives (2k³T³/(h³c²)) (G(x₂) − G(x₁)) (see `photon_tail`); a band narrower than
/// Δx = 1 by 8-panel Gauss–Legendre in x. [0, ∞] gives 4ζ(3)k³T³/(h³c²). Degenerate input
/// as [`blackbody_band_radiance`].
///
/// **Source.** Siegel & Howell, *Thermal Radiation Heat Transfer*, ch. 1 (photon gas).
pub fn blackbody_band_photon_radiance(lambda1_nm: f64, lambda2_nm: f64, temperature: f64) -> f64 {
    let c = 2.0 * BOLTZMANN.powi(3) / (PLANCK.powi(3) * SPEED_OF_LIGHT.powi(2));
    band_in_x(
        lambda1_nm,
        lambda2_nm,
        temperature,
        c * temperature.powi(3),
        bose2,
        photon_tail,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_and_continuity() {
        assert!((WIEN_DISPLACEMENT / 2.897_771_955e-3 - 1.0).abs() < 1e-9);
        assert!((stefan_boltzmann() / 5.670_374_419e-8 - 1.0).abs() < 1e-9);
        // x_w solves x = 5(1 − e^{−x}).
        assert!((WIEN_X - 5.0 * (1.0 - (-WIEN_X).exp())).abs() < 1e-14);
        // The two branches of F meet at x = 2: the series (x ≥ 2) against π⁴/15 minus
        // the quadrature, and both against F(2) = 5.3175968056598313 (mpmath, 30 digits).
        let series = tail(2.0);
        let quadrature = PI4_15 - gauss_legendre(0.0, 2.0, 16, bose);
        assert!(
            (series / 5.317_596_805_659_831 - 1.0).abs() < 1e-15,
            "{series}"
        );
        assert!(
            (quadrature / 5.317_596_805_659_831 - 1.0).abs() < 1e-15,
            "{quadrature}"
        );
        assert_eq!(tail(0.0), PI4_15);
        assert_eq!(tail(f64::INFINITY), 0.0);
    }

    #[test]
    fn direct_and_logarithmic_paths_agree() {
        // Just inside the direct path against the log path's formula.
        for (l, t) in [(500.0, 5800.0), (1e6, 300.0), (10.0, 1e5), (1e-3, 1e9)] {
            let b = planck_radiance(l, t);
            let x = C2_NM_K / l / t;
            let ln_b = (2.0 * PLANCK * SPEED_OF_LIGHT * SPEED_OF_LIGHT).ln()
                - 5.0 * (l * 1e-9).ln()
                - x.exp_m1().ln()
                + (1e-9f64).ln();
            assert!((b / ln_b.exp() - 1.0).abs() < 1e-12, "{l} {t}");
        }
    }

    #[test]
    fn extremes_are_finite() {
        for (l, t) in [
            (0.0, 5000.0),
            (-1.0, 5000.0),
            (f64::NAN, 5000.0),
            (1e9, 5000.0),
            (500.0, 1.0),
            (500.0, 1e6),
            (1e-3, 1e6),
            (500.0, 0.0),
            (5e-324, 1e300),
            (1e300, 1e300),
            (1e300, 5e-324),
            (f64::MAX, f64::MAX),
            (f64::INFINITY, 1.0),
        ] {
            let b = planck_radiance(l, t);
            assert!(b.is_finite() && b >= 0.0, "{l} {t} {b}");
            let i = blackbody_band_radiance(l, l * 2.0 + 1.0, t);
            assert!(i.is_finite() && i >= 0.0, "{l} {t} {i}");
        }
        assert_eq!(planck_radiance(500.0, 1.0), 0.0); // e^{-28777}
    }
}
