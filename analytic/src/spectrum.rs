//! Blackbody radiation and dispersion (SI units: wavelengths in metres unless stated).

use crate::radiometry::{BOLTZMANN, PLANCK, SPEED_OF_LIGHT};
use std::f64::consts::PI;

/// Stefan–Boltzmann constant σ = 2π⁵k⁴/(15h³c²) (W·m⁻²·K⁻⁴), from the exact SI constants.
pub fn stefan_boltzmann() -> f64 {
    2.0 * PI.powi(5) * BOLTZMANN.powi(4) / (15.0 * PLANCK.powi(3) * SPEED_OF_LIGHT.powi(2))
}

/// Second radiation constant c₂ = hc/k_B (m·K).
fn c2() -> f64 {
    PLANCK * SPEED_OF_LIGHT / BOLTZMANN
}

/// Planck's law: spectral radiance of a blackbody per unit wavelength (W·sr⁻¹·m⁻³).
///
/// **Formula.** B_λ(λ, T) = 2hc²/λ⁵ · 1/(exp(hc/(λ k_B T)) − 1), with `expm1` for the
/// long-wavelength (Rayleigh–Jeans) end.
///
/// **Derivation.** Bose–Einstein occupancy of the electromagnetic modes of a cavity,
/// times the mode density and photon energy, converted from frequency to wavelength.
///
/// **Source.** M. Planck, 1901; Siegel & Howell, *Thermal Radiation Heat Transfer*, ch. 1.
///
/// **Extreme arguments.** Where λ⁵ leaves the normal range or ζ = hc/(λ k_B T) lies
/// beyond [10⁻⁸, 700] (λ = 10⁻⁷⁰ gave ∞/∞ = NaN; λ = 10⁷⁰ gave 0 for 4.8·10⁻²⁹¹), B_λ
/// is formed as exp(ln 2hc² − 5 ln λ + g) with g = −ln(e^ζ − 1) from logarithms that
/// cannot overflow: g = −ζ above 700 (the neglected ln(1 − e^{−ζ}) is below 10⁻³⁰⁴),
/// g = −ln ζ − ζ/2 below 10⁻⁸ (Rayleigh–Jeans; the next term ζ²/24 is below 10⁻¹⁷),
/// with ln ζ = ln c₂ − ln λ − ln T, and −ln(expm1 ζ) between. Its relative error is
/// about |ln B_λ|·2⁻⁵³, below 2·10⁻¹³ wherever B_λ is a normal `f64`.
pub fn planck(wavelength: f64, temperature: f64) -> f64 {
    let l = wavelength;
    let a = 2.0 * PLANCK * SPEED_OF_LIGHT * SPEED_OF_LIGHT;
    let l5 = l.powi(5);
    let z = c2() / l / temperature;
    if l5.is_normal() && (1e-8..=700.0).contains(&z) {
        return a / l5 / z.exp_m1();
    }
    let g = if z > 700.0 {
        -z
    } else if z < 1e-8 {
        let ln_z = c2().ln() - l.ln() - temperature.ln();
        -ln_z - z / 2.0
    } else {
        -z.exp_m1().ln()
    };
    (a.ln() - 5.0 * l.ln() + g).exp()
}

/// Total (all-wavelength) radiance of a blackbody (W·sr⁻¹·m⁻²).
///
/// **Formula.** L = σ T⁴ / π. **Derivation.** ∫₀^∞ B_λ dλ = 2k⁴T⁴/(h³c²) · π⁴/15.
/// **Source.** Stefan 1879, Boltzmann 1884; Siegel & Howell ch. 1.
pub fn total_radiance(temperature: f64) -> f64 {
    stefan_boltzmann() * temperature.powi(4) / PI
}

/// Fraction of blackbody emission between 0 and λ at temperature T.
///
/// **Formula.** With ζ = hc/(λ k_B T):
/// F(0→λT) = 15/π⁴ Σ_{n≥1} e^{−nζ}/n · (ζ³ + 3ζ²/n + 6ζ/n² + 6/n³);
/// for ζ < 1 the complementary small-ζ series
/// F = 1 − 15/π⁴ ζ³ (1/3 − ζ/8 + ζ²/60 − ζ⁴/5040 + ζ⁶/272160 − ζ⁸/13305600 + …)
/// (Bernoulli-number expansion of ∫₀^ζ x³/(eˣ−1) dx) converges faster.
///
/// **Derivation.** F = (15/π⁴)∫_ζ^∞ x³/(eˣ−1) dx; expand 1/(eˣ−1) = Σ e^{−nx} and
/// integrate x³e^{−nx} by parts.
///
/// **Source.** Siegel & Howell, *Thermal Radiation Heat Transfer*, §2 (blackbody
/// fractions; Chang & Rhee 1984 series).
pub fn band_fraction_below(wavelength: f64, temperature: f64) -> f64 {
    let z = c2() / (wavelength * temperature);
    let k = 15.0 / PI.powi(4);
    if z >= 1.0 {
        let mut sum = 0.0;
        for n in 1..200 {
            let nf = n as f64;
            let term = (-nf * z).exp() / nf
                * (z.powi(3) + 3.0 * z * z / nf + 6.0 * z / (nf * nf) + 6.0 / nf.powi(3));
            sum += term;
            if term < 1e-18 * sum {
                break;
            }
        }
        k * sum
    } else {
        // ∫₀^ζ x³/(eˣ−1) dx = Σ B_m ζ^{m+3}/(m!(m+3)), B the Bernoulli numbers; the
        // first omitted term, |B₁₆| ζ¹⁹/(16!·19) ≈ 1.8e-14 ζ¹⁹, is < 2e-14 for ζ < 1.
        1.0 - band_fraction_above_small(z)
    }
}

/// The small-ζ (ζ < 1) complement 1 − F(0→λT) = 15/π⁴ ∫₀^ζ x³/(eˣ−1) dx of
/// [`band_fraction_below`], by the same Bernoulli series, without the subtraction from 1.
fn band_fraction_above_small(z: f64) -> f64 {
    const B: [(i32, f64); 9] = [
        (0, 1.0),
        (1, -0.5),
        (2, 1.0 / 6.0),
        (4, -1.0 / 30.0),
        (6, 1.0 / 42.0),
        (8, -1.0 / 30.0),
        (10, 5.0 / 66.0),
        (12, -691.0 / 2730.0),
        (14, 7.0 / 6.0),
    ];
    let mut fact = 1.0;
    let mut last = 0;
    let mut s = 0.0;
    for (m, b) in B {
        for j in (last + 1)..=m {
            fact *= j as f64;
        }
        last = m;
        s += b * z.powi(m + 3) / (fact * (m + 3) as f64);
    }
    15.0 / PI.powi(4) * s
}

/// Fraction of blackbody emission in the band [λ₁, λ₂] at temperature T.
///
/// **Formula.** F(0→λ₂T) − F(0→λ₁T), see [`band_fraction_below`]; when both ends are in
/// the Rayleigh–Jeans tail (ζ = hc/(λ k_B T) < 1 at both), the difference of the two
/// complements, (1 − F(0→λ₁T)) − (1 − F(0→λ₂T)), each from the small-ζ series. There
/// the direct difference of two numbers near 1 keeps only the digits above 1e-16: the
/// band [1, 2] m at 300 K (≈ 4.954e-15) came out 0.84% high.
///
/// **Derivation.** F(0→λT) = 1 − 15/π⁴ ∫₀^ζ x³/(eˣ−1) dx; the 1s cancel exactly.
pub fn band_fraction(l1: f64, l2: f64, temperature: f64) -> f64 {
    let (z1, z2) = (c2() / (l1 * temperature), c2() / (l2 * temperature));
    if z1 < 1.0 && z2 < 1.0 {
        return band_fraction_above_small(z1) - band_fraction_above_small(z2);
    }
    band_fraction_below(l2, temperature) - band_fraction_below(l1, temperature)
}

/// Wien's displacement law: wavelength of maximum B_λ (m).
///
/// **Formula.** λ_max = b/T, b = hc/(k_B x), x the root of x = 5(1 − e^{−x})
/// (x = 4.965114231744276…), b = 2.897771955… × 10⁻³ m·K.
///
/// **Derivation.** ∂B_λ/∂λ = 0. **Source.** Wien 1893; CODATA 2018.
pub fn wien_peak(temperature: f64) -> f64 {
    let mut x = 5.0f64;
    for _ in 0..50 {
        // Newton on g(x) = x − 5 + 5e^{−x}.
        let g = x - 5.0 + 5.0 * (-x).exp();
        let dg = 1.0 - 5.0 * (-x).exp();
        x -= g / dg;
    }
    c2() / x / temperature
}

/// Total photon radiance of a blackbody (photons·s⁻¹·m⁻²·sr⁻¹).
///
/// **Formula.** N = 4 ζ(3) k_B³ T³ / (h³ c²), ζ(3) = 1.2020569031595942 (Apéry).
///
/// **Derivation.** ∫ B_ν/(hν) dν = (2/c²)(kT/h)³ ∫₀^∞ x²/(eˣ−1) dx = (2/c²)(kT/h)³ · 2ζ(3).
///
/// **Source.** Siegel & Howell ch. 1; any statistical-mechanics text (photon gas).
pub fn photon_radiance(temperature: f64) -> f64 {
    const ZETA3: f64 = 1.202_056_903_159_594_2;
    let kt_h = BOLTZMANN * temperature / PLANCK;
    4.0 * ZETA3 * kt_h.powi(3) / (SPEED_OF_LIGHT * SPEED_OF_LIGHT)
}

/// Cauchy's dispersion formula n(λ) = A + B/λ², with λ in micrometres and B in µm².
/// **Source.** A.-L. Cauchy 1836; Born & Wolf §2.3.
pub fn cauchy(a: f64, b: f64, wavelength_um: f64) -> f64 {
    a + b / (wavelength_um * wavelength_um)
}

/// Sellmeier's dispersion formula n²(λ) = 1 + Σᵢ Bᵢ λ²/(λ² − Cᵢ), λ in µm, Cᵢ in µm².
/// **Source.** W. Sellmeier 1872; Born & Wolf §2.3; coefficients of glasses from the
/// Schott catalogue (see [`BK7_B`], [`BK7_C`]).
pub fn sellmeier(b: &[f64; 3], c: &[f64; 3], wavelength_um: f64) -> f64 {
    let l2 = wavelength_um * wavelength_um;
    (1.0 + (0..3).map(|i| b[i] * l2 / (l2 - c[i])).sum::<f64>()).sqrt()
}

/// Schott N-BK7 Sellmeier B coefficients.
pub const BK7_B: [f64; 3] = [1.039_612_12, 0.231_792_344, 1.010_469_45];
/// Schott N-BK7 Sellmeier C coefficients (µm²).
pub const BK7_C: [f64; 3] = [6.000_698_67e-3, 2.001_791_44e-2, 103.560_653];

/// Transmittance of a non-absorbing slab at normal incidence, summing all incoherent
/// inter-reflections.
///
/// **Formula.** T = (1 − R)/(1 + R), R = ((n−1)/(n+1))².
///
/// **Derivation.** T = (1−R)² Σₖ R²ᵏ = (1−R)²/(1−R²).
///
/// **Source.** Born & Wolf §1.6 / §7.6 (incoherent limit); Siegel & Howell (slab).
pub fn slab_transmittance(index: f64) -> f64 {
    let r = crate::fresnel::normal_reflectance(index);
    (1.0 - r) / (1.0 + r)
}

/// Blackbody radiance in the band [λ₁, λ₂] (W/(m²·sr)).
///
/// **Formula.** L = σT⁴/π · [F(0→λ₂T) − F(0→λ₁T)] with the series fractions of
/// [`band_fraction_below`]. **Source.** Siegel & Howell ch. 1–2.
pub fn band_radiance(l1: f64, l2: f64, temperature: f64) -> f64 {
    total_radiance(temperature) * band_fraction(l1, l2, temperature)
}

/// Normal-incidence transmittance of a non-absorbing N-BK7 slab at a wavelength (µm).
///
/// **Formula.** T(λ) = (1 − R)/(1 + R), R = ((n(λ) − 1)/(n(λ) + 1))², n from the
/// Sellmeier formula with Schott's coefficients ([`sellmeier`], [`slab_transmittance`]).
pub fn bk7_slab_transmittance(wavelength_um: f64) -> f64 {
    slab_transmittance(sellmeier(&BK7_B, &BK7_C, wavelength_um))
}

/// Mean normal-incidence transmittance of a non-absorbing N-BK7 slab over the band
/// [λ₁, λ₂] (µm) under a flat spectrum.
///
/// **Formula.** T̄ = (1/(λ₂ − λ₁)) ∫ T(λ) dλ with T from [`bk7_slab_transmittance`];
/// evaluated by adaptive bisection of a 12-point Gauss–Legendre rule
/// ([`crate::quadrature::adaptive`]; T is smooth and slowly varying over
/// the visible, far from BK7's absorption poles).
pub fn bk7_slab_band_transmittance(l1_um: f64, l2_um: f64) -> f64 {
    if l2_um <= l1_um {
        return bk7_slab_transmittance(l1_um);
    }
    crate::quadrature::adaptive(bk7_slab_transmittance, l1_um, l2_um, 1e-13) / (l2_um - l1_um)
}

/// Normal-incidence transmittance of a non-absorbing slab whose index follows Cauchy's
/// formula n = a + b/λ² (λ in µm, b in µm²): (1 − R)/(1 + R) at n(λ).
pub fn cauchy_slab_transmittance(a: f64, b: f64, wavelength_um: f64) -> f64 {
    slab_transmittance(cauchy(a, b, wavelength_um))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::adaptive;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// ∫ B_λ dλ over [l1, l2] by quadrature in log λ.
    fn planck_integral(l1: f64, l2: f64, t: f64) -> f64 {
        adaptive(
            |x: f64| planck(x.exp(), t) * x.exp(),
            l1.ln(),
            l2.ln(),
            1e-14,
        )
    }

    /// Extreme wavelengths and temperatures: finite, and right where the value is a normal
    /// `f64` (λ = 10⁻⁷⁰ gave NaN, λ = 10⁷⁰ gave 0). References from mpmath at 50 digits:
    /// `2*h*c**2/l**5/mp.expm1(h*c/(l*k*T))` with the exact SI constants.
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn planck_at_extreme_arguments() {
        for (l, t, want) in [
            (1e70, 5778.0, 4.783_122_666_281_616_552e-291),
            (1e100, 1e300, 8.278_163_146_904_84e-115),
            (1e60, 1.0, 8.278_163_146_904_84e-255),
            (5e-7, 5778.0, 2.637_566_986_661_479_715_4e13),
            // λ⁵ subnormal, through each branch of g: ζ = 719 (beyond expm1's range),
            // ζ = 685, and ζ = 4.8·10⁻⁹ (Rayleigh–Jeans, where the −ζ/2 term is 2.4·10⁻⁹).
            (1e-62, 2e57, 4.461_677_095_938_368_529_7e-19),
            (1e-62, 2.1e57, 3.364_706_212_469_962_118e-4),
            (1.0, 3e6, 2.483_448_938_116_237_142_8e-8),
        ] {
            let got = planck(l, t);
            assert!(rel(got, want) < 2e-13, "λ = {l}, T = {t}: {got} vs {want}");
        }
        // True values far below the smallest f64: 0, not NaN.
        for (l, t) in [
            (1e-70, 5778.0),
            (1e70, 1e-300),
            (1e-6, 1e-300),
            (1e-200, 1e-200),
        ] {
            assert_eq!(planck(l, t), 0.0, "λ = {l}, T = {t}");
        }
        // Never NaN: +∞ only where the true value exceeds f64::MAX (λ = 10⁻³⁰⁰ at
        // T = 10³⁰⁰: ζ = 0.0144, B_λ ≈ 10¹⁴⁸⁵), which the catalog refuses as non-finite.
        assert_eq!(planck(1e-300, 1e300), f64::INFINITY);
        for l in [1e-300, 1e-100, 1e-30, 1e-9, 1e-3, 1e10, 1e100, 1e300] {
            for t in [1e-300, 1e-10, 1.0, 5778.0, 1e10, 1e300] {
                let v = planck(l, t);
                assert!(v >= 0.0, "λ = {l}, T = {t}: {v}");
            }
        }
    }

    #[test]
    fn planck_integrates_to_stefan_boltzmann() {
        assert!(rel(stefan_boltzmann(), 5.670_374_419e-8) < 1e-9);
        for t in [300.0, 5778.0] {
            let q = planck_integral(1e-9, 1.0, t)
                + adaptive(|x: f64| planck(1.0 / x, t) / (x * x), 1e-12, 1.0, 1e-14);
            assert!(rel(total_radiance(t), q) < 1e-9, "T={t}");
        }
    }

    /// In the Rayleigh–Jeans tail (ζ ≪ 1) the band fraction is
    /// 15/π⁴ ∫_{ζ₂}^{ζ₁} x³/(eˣ−1) dx = 15/π⁴ [(ζ₁³ − ζ₂³)/3 − (ζ₁⁴ − ζ₂⁴)/8 + (ζ₁⁵ − ζ₂⁵)/60 − …]
    /// (1/(eˣ−1) = 1/x − 1/2 + x/12 − …): [1, 2] m at 300 K is ≈ 4.954e-15, where the
    /// difference of the two F(0→λT) ≈ 1 gave 4.996e-15 (0.84% high).
    #[test]
    fn band_fraction_in_the_rayleigh_jeans_tail() {
        let k = 15.0 / PI.powi(4);
        for (l1, l2, t) in [(1.0, 2.0, 300.0), (0.05, 0.5, 1000.0), (1e-3, 1.0, 1e4)] {
            let (z1, z2) = (c2() / (l1 * t), c2() / (l2 * t));
            assert!(z1 < 1e-2 && z2 < z1, "{z1} {z2}");
            let d = |p: i32| z1.powi(p) - z2.powi(p);
            let series = k * (d(3) / 3.0 - d(4) / 8.0 + d(5) / 60.0 - d(7) / 5040.0);
            let got = band_fraction(l1, l2, t);
            assert!(
                rel(got, series) < 1e-12,
                "[{l1}, {l2}] m at {t} K: {got} vs {series}"
            );
        }
        // Across ζ = 1 and on the Wien side the direct difference is kept.
        let l1 = c2() / (1.5 * 1000.0);
        let l2 = c2() / (0.5 * 1000.0);
        let q = band_fraction_below(l2, 1000.0) - band_fraction_below(l1, 1000.0);
        assert_eq!(band_fraction(l1, l2, 1000.0), q);
    }

    #[test]
    fn band_fractions_by_quadrature() {
        let t = 5778.0;
        for (l1, l2) in [
            (380e-9, 780e-9),
            (1e-7, 2e-7),
            (2e-6, 5e-5),
            (500e-9, 500.5e-9),
        ] {
            let q = planck_integral(l1, l2, t) / total_radiance(t);
            assert!(rel(band_fraction(l1, l2, t), q) < 1e-9, "{l1} {l2}");
        }
        // Both branches of the series agree at the switch ζ = 1.
        let l = c2() / t;
        let (a, b) = (
            band_fraction_below(l * (1.0 - 1e-12), t),
            band_fraction_below(l * (1.0 + 1e-12), t),
        );
        assert!((a - b).abs() < 1e-12);
    }

    #[test]
    fn wien_and_photons() {
        assert!(rel(wien_peak(1.0), 2.897_771_955e-3) < 1e-9);
        // Maximum of B_λ by golden-section search.
        let t = 3000.0;
        let (mut a, mut b) = (0.5e-6, 2e-6);
        for _ in 0..200 {
            let m1 = b - (b - a) * 0.618_033_988_75;
            let m2 = a + (b - a) * 0.618_033_988_75;
            if planck(m1, t) < planck(m2, t) {
                a = m1
            } else {
                b = m2
            }
        }
        assert!(rel(wien_peak(t), 0.5 * (a + b)) < 1e-7);
        let q = adaptive(
            |x: f64| {
                let l = x.exp();
                planck(l, t) / crate::radiometry::photon_energy(l) * l
            },
            (1e-8f64).ln(),
            (1.0f64).ln(),
            1e-14,
        );
        assert!(rel(photon_radiance(t), q) < 1e-7);
    }

    #[test]
    fn dispersion_and_slab() {
        // N-BK7 at the d line (587.56 nm): n_d = 1.5168.
        assert!((sellmeier(&BK7_B, &BK7_C, 0.587_56) - 1.5168).abs() < 1e-4);
        assert!(rel(cauchy(1.5046, 0.00420, 0.5), 1.5046 + 0.0168) < 1e-15);
        let n = 1.5;
        let r = crate::fresnel::normal_reflectance(n);
        let series: f64 = (0..100)
            .map(|k| (1.0 - r) * (1.0 - r) * r.powi(2 * k))
            .sum();
        assert!(rel(slab_transmittance(n), series) < 1e-14);
        // The band mean of a slowly varying T lies between its end values, and equals a
        // 2000-point midpoint rule.
        let (l1, l2) = (0.4, 0.7);
        let m = bk7_slab_band_transmittance(l1, l2);
        let mid: f64 = (0..2000)
            .map(|i| bk7_slab_transmittance(l1 + (i as f64 + 0.5) * (l2 - l1) / 2000.0))
            .sum::<f64>()
            / 2000.0;
        assert!(rel(m, mid) < 1e-9);
        assert!(m > bk7_slab_transmittance(l1) && m < bk7_slab_transmittance(l2));
        assert!(
            rel(
                cauchy_slab_transmittance(1.5, 0.0, 0.55),
                slab_transmittance(1.5)
            ) < 1e-15
        );
        let t = 4000.0;
        assert!(rel(band_radiance(1e-9, 1.0, t), total_radiance(t)) < 1e-6);
    }
}
