//! The CIE 1931 2° colour-matching functions x̄, ȳ, z̄ and the conversion of a spectrum's
//! tristimulus values to linear sRGB, for `lightproof render` of spectral scenes.
//!
//! **Matching functions.** The multi-lobe piecewise-Gaussian fit of C. Wyman,
//! P.-P. Sloan and P. Shirley, "Simple Analytic Approximations to the CIE XYZ Color
//! Matching Functions", JCGT 2(2), 1–11, 2013, eq. 2 (λ in nm):
//!
//! x̄ = 1.056 g(λ; 599.8, 37.9, 31.0) + 0.362 g(λ; 442.0, 16.0, 26.7) − 0.065 g(λ; 501.1, 20.4, 26.2)
//! ȳ = 0.821 g(λ; 568.8, 46.9, 40.5) + 0.286 g(λ; 530.9, 16.3, 31.1)
//! z̄ = 1.217 g(λ; 437.0, 11.8, 36.0) + 0.681 g(λ; 459.0, 26.0, 13.8)
//!
//! with g(λ; μ, σ₁, σ₂) = exp(−½ ((λ − μ)/σ)²), σ = σ₁ below μ and σ₂ above. The fit's
//! small negative dip of x̄ near 500 nm is clamped to 0 (no negative response). Its
//! integrals are exact by erf ([`Cmf::integral`]).
//!
//! **White.** The CIE tables are normalised so that the equal-energy spectrum
//! (illuminant E) has X = Y = Z. The fit's integrals differ slightly, so a spectrum's
//! tristimulus values are divided by the fit's own integrals over the rendered band:
//! X̂ = ∫ x̄ L dλ / ∫ x̄ dλ, likewise Ŷ, Ẑ. A flat spectrum L(λ) = L₀ then gives
//! X̂ = Ŷ = Ẑ = L₀, and Ŷ of any spectrum is its ȳ-weighted mean radiance (a grey scene's
//! value). **Equal energy is white**: [`XYZ_E_TO_LINEAR_SRGB`] adapts E's white to D65
//! (Bradford, Lam 1985) and converts to linear sRGB (IEC 61966-2-1: BT.709 primaries,
//! D65 white), so a flat spectrum renders to R = G = B = L₀, while a D65-like spectrum
//! renders slightly blue. Colours outside the sRGB gamut (negative components) are
//! clipped to 0.

use glam::{DMat3, DVec3};

/// One lobe of a fit: weight, μ, σ below μ, σ above μ (nm).
type Lobe = (f64, f64, f64, f64);

/// A colour-matching function as its lobes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cmf(&'static [Lobe]);

/// x̄ (Wyman, Sloan and Shirley 2013, eq. 2).
pub const X: Cmf = Cmf(&[
    (1.056, 599.8, 37.9, 31.0),
    (0.362, 442.0, 16.0, 26.7),
    (-0.065, 501.1, 20.4, 26.2),
]);
/// ȳ, the photopic luminosity function V(λ) ([`super::photopic`]).
pub const Y: Cmf = Cmf(&[(0.821, 568.8, 46.9, 40.5), (0.286, 530.9, 16.3, 31.1)]);
/// z̄.
pub const Z: Cmf = Cmf(&[(1.217, 437.0, 11.8, 36.0), (0.681, 459.0, 26.0, 13.8)]);

impl Cmf {
    /// The function at `lambda_nm`, in f32; finite and ≥ 0 (0 for NaN).
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        if lambda_nm.is_nan() {
            return 0.0;
        }
        let mut y = 0.0f32;
        for &(w, mu, s1, s2) in self.0 {
            let (mu, s) = (
                mu as f32,
                if (lambda_nm as f64) < mu { s1 } else { s2 } as f32,
            );
            let t = (lambda_nm - mu) / s;
            y += w as f32 * (-0.5 * t * t).exp();
        }
        if y.is_finite() && y > 0.0 { y } else { 0.0 }
    }

    /// ∫ over [a, b] nm of the fit (without the clamp: the clamped dip of x̄ holds under
    /// 10⁻³ nm of its 106 nm), exactly: on each side of a lobe's centre,
    /// ∫ exp(−½((λ − μ)/σ)²) dλ = σ√(π/2) [erf((λ − μ)/(σ√2))].
    pub fn integral(&self, a: f64, b: f64) -> f64 {
        let side = |lo: f64, hi: f64, mu: f64, s: f64| {
            if hi <= lo {
                return 0.0;
            }
            let e = |x: f64| statrs::function::erf::erf((x - mu) / (s * 2f64.sqrt()));
            s * (std::f64::consts::PI / 2.0).sqrt() * (e(hi) - e(lo))
        };
        self.0
            .iter()
            .map(|&(w, mu, s1, s2)| w * (side(a, b.min(mu), mu, s1) + side(a.max(mu), b, mu, s2)))
            .sum()
    }

    /// ∫ λ·f(λ) dλ over [a, b] nm (nm²) of the fit, exactly: on each side of a lobe's
    /// centre, with g = exp(−½((λ − μ)/σ)²), λ = μ + (λ − μ) and d(−σ²g)/dλ = (λ − μ)g,
    /// ∫ λ g dλ = μ ∫ g dλ + σ² [g(lo) − g(hi)] (the erf part as in [`Cmf::integral`]).
    pub fn moment(&self, a: f64, b: f64) -> f64 {
        let side = |lo: f64, hi: f64, mu: f64, s: f64| {
            if hi <= lo {
                return 0.0;
            }
            let e = |x: f64| statrs::function::erf::erf((x - mu) / (s * 2f64.sqrt()));
            let g = |x: f64| (-0.5 * ((x - mu) / s).powi(2)).exp();
            mu * s * (std::f64::consts::PI / 2.0).sqrt() * (e(hi) - e(lo)) + s * s * (g(lo) - g(hi))
        };
        self.0
            .iter()
            .map(|&(w, mu, s1, s2)| w * (side(a, b.min(mu), mu, s1) + side(a.max(mu), b, mu, s2)))
            .sum()
    }
}

/// Chromaticity (x, y) to XYZ with Y = 1.
fn xyz(x: f64, y: f64) -> DVec3 {
    DVec3::new(x / y, 1.0, (1.0 - x - y) / y)
}

/// Linear sRGB to XYZ, derived from the primaries' and D65's chromaticities (IEC
/// 61966-2-1 / ITU-R BT.709: R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06), white
/// (0.3127, 0.3290)): the columns are the primaries scaled so that RGB (1, 1, 1) is the
/// white with Y = 1.
pub fn linear_srgb_to_xyz() -> DMat3 {
    let p = DMat3::from_cols(xyz(0.64, 0.33), xyz(0.30, 0.60), xyz(0.15, 0.06));
    let s = p.inverse() * xyz(0.3127, 0.3290);
    p * DMat3::from_diagonal(s)
}

/// The Bradford cone response matrix (Lam 1985, as in CIECAM97s).
const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// Bradford adaptation of XYZ from the white `from` to the white `to`:
/// B⁻¹ diag(B·to / B·from) B.
pub fn bradford(from: DVec3, to: DVec3) -> DMat3 {
    let b = DMat3::from_cols_array_2d(&BRADFORD).transpose();
    let (f, t) = (b * from, b * to);
    b.inverse() * DMat3::from_diagonal(t / f) * b
}

/// The matrix of E-normalised tristimulus values (X̂, Ŷ, Ẑ) to linear sRGB (module
/// notes): Bradford from E (1, 1, 1) to D65, then XYZ → linear sRGB.
pub fn xyz_e_to_linear_srgb() -> DMat3 {
    let to_xyz = linear_srgb_to_xyz();
    let d65 = to_xyz * DVec3::ONE;
    to_xyz.inverse() * bradford(DVec3::ONE, d65)
}

/// The tristimulus weights of a render over `[a, b]` nm: x̄/∫x̄, ȳ/∫ȳ, z̄/∫z̄ at λ.
#[derive(Clone, Copy, Debug)]
pub struct Observer {
    norm: [f32; 3],
}

impl Observer {
    /// The E-normalised observer over [a, b] nm.
    pub fn over(a: f64, b: f64) -> Observer {
        Observer {
            norm: [X, Y, Z].map(|c| (1.0 / c.integral(a, b)) as f32),
        }
    }

    /// (x̄, ȳ, z̄)(λ) divided by their integrals.
    pub fn weights(&self, lambda_nm: f32) -> [f32; 3] {
        let [nx, ny, nz] = self.norm;
        [
            X.eval(lambda_nm) * nx,
            Y.eval(lambda_nm) * ny,
            Z.eval(lambda_nm) * nz,
        ]
    }
}

/// E-normalised tristimulus values to linear sRGB, clipped to ≥ 0 (outside the gamut)
/// and finite values to the largest finite f32; NaN and +∞ are kept (a bug upstream,
/// which the image must show, not hide).
pub fn to_linear_srgb(m: &DMat3, xyz: [f64; 3]) -> [f32; 3] {
    let rgb = *m * DVec3::from_array(xyz);
    rgb.to_array().map(|v| {
        if v.is_nan() {
            // A NaN radiance is a bug upstream: kept, never painted black.
            f32::NAN
        } else if v > 0.0 {
            // +∞ stays +∞; a finite value beyond f32's range is clamped to f32::MAX.
            if v.is_finite() {
                v.min(f32::MAX as f64) as f32
            } else {
                f32::INFINITY
            }
        } else {
            0.0
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_energy_renders_white() {
        // A flat spectrum L₀: X̂ = Ŷ = Ẑ = L₀ by the normalisation (checked by quadrature
        // of the weights), and the matrix maps (1, 1, 1) to R = G = B = 1.
        let o = Observer::over(360.0, 830.0);
        let n = 47_000;
        let h = 470.0 / n as f64;
        let mut s = [0.0f64; 3];
        for i in 0..n {
            let w = o.weights((360.0 + (i as f64 + 0.5) * h) as f32);
            for c in 0..3 {
                s[c] += w[c] as f64 * h;
            }
        }
        for v in s {
            assert!((v - 1.0).abs() < 2e-5, "{s:?}");
        }
        let m = xyz_e_to_linear_srgb();
        let rgb = m * DVec3::ONE;
        assert!((rgb - DVec3::ONE).abs().max_element() < 1e-12, "{rgb}");
        assert_eq!(
            to_linear_srgb(&m, [2.0; 3]).map(|v| (v * 1e5).round()),
            [2e5; 3]
        );
        // D65's white itself (without adaptation) is not E: the adaptation matters.
        let plain = linear_srgb_to_xyz().inverse() * DVec3::ONE;
        assert!((plain.x - plain.z).abs() > 0.05, "{plain}");
    }

    /// The README's two colour facts: a spectral green (a narrow band at 520 nm, outside
    /// the sRGB gamut) has negative red and blue in linear sRGB, which are clipped to 0,
    /// green kept; a 6500 K blackbody, against the equal-energy white, renders slightly
    /// blue (B > G > R; B/R = 1.34).
    #[test]
    fn out_of_gamut_clips_and_6500_k_is_slightly_blue() {
        let o = Observer::over(360.0, 830.0);
        let m = xyz_e_to_linear_srgb();
        let tristimulus = |spectrum: &dyn Fn(f64) -> f64| {
            let n = 4700;
            let h = 470.0 / n as f64;
            let mut s = [0.0f64; 3];
            for i in 0..n {
                let l = 360.0 + (i as f64 + 0.5) * h;
                let w = o.weights(l as f32);
                for c in 0..3 {
                    s[c] += w[c] as f64 * spectrum(l) * h;
                }
            }
            s
        };
        let green = tristimulus(&|l| if (l - 520.0).abs() < 1.0 { 1.0 } else { 0.0 });
        let raw = m * DVec3::from_array(green);
        assert!(raw.x < 0.0 && raw.z < 0.0 && raw.y > 0.0, "{raw}");
        assert_eq!(to_linear_srgb(&m, green), [0.0, raw.y as f32, 0.0]);
        // Not finite stays not finite (a NaN is a bug to be seen, not a black pixel);
        // finite beyond f32 is clamped to its largest value.
        let ones = DMat3::from_cols_array(&[1.0; 9]);
        let out = |x: f64| to_linear_srgb(&ones, [x, 0.0, 0.0]);
        assert!(out(f64::NAN).iter().all(|c| c.is_nan()));
        assert_eq!(out(f64::INFINITY), [f32::INFINITY; 3]);
        assert_eq!(out(1e300), [f32::MAX; 3]);
        assert_eq!(out(-1.0), [0.0; 3]);
        assert_eq!(out(f64::NEG_INFINITY), [0.0; 3]);
        let bb = tristimulus(&|l| crate::spectrum::blackbody::planck_radiance(l, 6500.0));
        let [r, g, b] = to_linear_srgb(&m, bb);
        assert!(
            b > g && g > r && (1.3..1.4).contains(&(b / r)),
            "6500 K: {r} {g} {b}"
        );
    }

    #[test]
    fn the_srgb_matrix_matches_the_standard() {
        // IEC 61966-2-1's published XYZ → linear sRGB matrix (4 decimals, from a white
        // rounded to (0.9505, 1, 1.089)).
        let published = [
            [3.2406, -1.5372, -0.4986],
            [-0.9689, 1.8758, 0.0415],
            [0.0557, -0.2040, 1.0570],
        ];
        let m = linear_srgb_to_xyz()
            .inverse()
            .transpose()
            .to_cols_array_2d();
        for r in 0..3 {
            for c in 0..3 {
                assert!((m[r][c] - published[r][c]).abs() < 6e-4, "{m:?}");
            }
        }
    }

    #[test]
    fn the_fit_follows_the_cie_tables() {
        // CIE 1931 2° table values (CIE 15:2004): x̄(600) = 1.0622, x̄(445) = 0.3481,
        // ȳ(555) = 1.0000, z̄(445) = 1.7826, z̄(600) = 0.0008; the fit stays within 0.03.
        for (c, l, v) in [
            (X, 600.0, 1.0622),
            (X, 445.0, 0.3481),
            (Y, 555.0, 1.0),
            (Z, 445.0, 1.7826),
            (Z, 600.0, 0.0008),
        ] {
            assert!(
                (c.eval(l) as f64 - v).abs() < 0.03,
                "{c:?} at {l}: {}",
                c.eval(l)
            );
        }
        // Equal-energy white: the three tables integrate to the same 106.857 nm; the
        // fit's integrals agree to 1%.
        for c in [X, Y, Z] {
            let i = c.integral(360.0, 830.0);
            assert!((i / 106.857 - 1.0).abs() < 0.01, "{c:?}: {i}");
        }
        // Never negative, never NaN.
        for l in [f32::NAN, -1.0, 0.0, 500.0, 501.1, 1e9, f32::INFINITY] {
            for c in [X, Y, Z] {
                let v = c.eval(l);
                assert!(v.is_finite() && v >= 0.0, "{l}: {v}");
            }
        }
    }
}
