//! Spectra as data: what varies with wavelength, and how wavelengths are drawn.
//!
//! | item | concept |
//! |---|---|
//! | [`Spectrum`] | relative emission S(λ): constant, tabulated (linear), or Planck's blackbody |
//! | [`Ior`] | refractive index n(λ): constant, Cauchy, Sellmeier, tabulated |
//! | [`Response`] | a sensor's spectral response R(λ): flat, photopic (CIE 1931 ȳ), tabulated |
//! | [`WavelengthSampler`] | drawing λ over a band, uniformly or by importance, with its density |
//!
//! Wavelengths are vacuum wavelengths in nanometres (f32 in the engine, f64 inside the
//! closed forms). No function here returns NaN, Inf or a negative value, whatever its
//! input: out-of-range input gives 0 (spectra, responses) or a finite index.

mod blackbody;
mod ior;
mod response;
mod table;
mod wavelength;

pub use blackbody::planck_per_nm;
pub use ior::{Ior, bk7};
pub use response::{LUMINOUS_EFFICACY, Response, photopic};
pub use table::Table;
pub use wavelength::WavelengthSampler;

use serde::{Deserialize, Serialize};

/// Speed of light in vacuum (m/s), exact (SI 2019).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Planck constant (J·s), exact (SI 2019).
pub const PLANCK: f64 = 6.626_070_15e-34;
/// Boltzmann constant (J/K), exact (SI 2019).
pub const BOLTZMANN: f64 = 1.380_649e-23;

/// Energy of one photon of vacuum wavelength `lambda_nm` (nm): e = hc/λ (J).
/// Non-positive or non-finite wavelengths give +∞ energy's reciprocal-safe stand-in,
/// `f64::MAX`, so that photon counts E/e stay finite (zero).
pub fn photon_energy(lambda_nm: f64) -> f64 {
    if lambda_nm > 0.0 && lambda_nm.is_finite() {
        PLANCK * SPEED_OF_LIGHT / (lambda_nm * 1e-9)
    } else {
        f64::MAX
    }
}

/// A wavelength band [min, max] in nm; JSON `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "[f32; 2]", into = "[f32; 2]")]
pub struct Band {
    /// Shortest wavelength (nm).
    pub min: f32,
    /// Longest wavelength (nm).
    pub max: f32,
}

impl From<[f32; 2]> for Band {
    fn from(a: [f32; 2]) -> Self {
        Band {
            min: a[0],
            max: a[1],
        }
    }
}

impl From<Band> for [f32; 2] {
    fn from(b: Band) -> Self {
        [b.min, b.max]
    }
}

impl Band {
    /// λ₂ − λ₁ (nm).
    pub fn width(&self) -> f32 {
        self.max - self.min
    }

    /// Whether λ lies in [min, max].
    pub fn contains(&self, lambda: f32) -> bool {
        lambda >= self.min && lambda <= self.max
    }

    /// 0 < min < max, both finite.
    pub fn validate(&self) -> Result<(), String> {
        if self.min.is_finite() && self.max.is_finite() && self.min > 0.0 && self.max > self.min
        {
            Ok(())
        } else {
            Err(format!(
                "must be [λ₁, λ₂] in nm with 0 < λ₁ < λ₂, got [{}, {}]",
                self.min, self.max
            ))
        }
    }
}

/// The visible range used where a band is needed and none is given (nm).
pub const VISIBLE: Band = Band {
    min: 360.0,
    max: 830.0,
};

/// Blackbody parameters in JSON: `{"temperature": T, "scale": s}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Planck {
    /// Temperature (K).
    pub temperature: f32,
    /// Factor on Planck's radiance (default 1).
    #[serde(default = "one")]
    pub scale: f32,
}

fn one() -> f32 {
    1.0
}

/// A relative spectral distribution S(λ). JSON: a number (constant),
/// `{"sampled": {"wavelengths": [...], "values": [...]}}` (linear interpolation, zero
/// outside the table) or `{"blackbody": {"temperature": T, "scale": s}}` (Planck's law
/// in W·m⁻²·sr⁻¹·nm⁻¹ times s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// A table, linearly interpolated.
    Sampled {
        /// The table.
        sampled: Table,
    },
    /// Planck's blackbody radiance.
    Blackbody {
        /// Its parameters.
        blackbody: Planck,
    },
}

impl Spectrum {
    /// S(λ), finite and non-negative.
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        let v = match self {
            Spectrum::Constant(c) => *c,
            Spectrum::Sampled { sampled } => sampled.eval(lambda_nm),
            Spectrum::Blackbody { blackbody } => {
                (planck_per_nm(lambda_nm as f64, blackbody.temperature as f64)
                    * blackbody.scale as f64) as f32
            }
        };
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }

    /// Whether S is the same at every wavelength.
    pub fn is_constant(&self) -> bool {
        matches!(self, Spectrum::Constant(_))
    }

    /// Check the values: finite, non-negative, a sorted table, a positive temperature.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Spectrum::Constant(c) => {
                if c.is_finite() && *c >= 0.0 {
                    Ok(())
                } else {
                    Err(format!("must be a finite non-negative value, got {c}"))
                }
            }
            Spectrum::Sampled { sampled } => sampled.validate(),
            Spectrum::Blackbody { blackbody } => {
                let t = blackbody.temperature;
                if !(t.is_finite() && t > 0.0) {
                    return Err(format!("blackbody.temperature must be a positive number of kelvins, got {t}"));
                }
                let s = blackbody.scale;
                if !(s.is_finite() && s >= 0.0) {
                    return Err(format!("blackbody.scale must be finite and non-negative, got {s}"));
                }
                Ok(())
            }
        }
    }

    /// ∫ S dλ over the band (nm): exact for constants and tables, 4096-panel
    /// Gauss–Legendre for Planck.
    pub fn integral(&self, band: Band) -> f64 {
        match self {
            Spectrum::Constant(c) => *c as f64 * band.width() as f64,
            Spectrum::Sampled { sampled } => sampled.integral(band),
            _ => gauss_legendre(band.min as f64, band.max as f64, 4096, |l| {
                self.eval(l as f32) as f64
            }),
        }
    }

    /// max S over the band (sampled on a fine grid; exact for constants and tables).
    pub fn max_in(&self, band: Band) -> f32 {
        let n = 1024;
        let mut m = self.eval(band.min).max(self.eval(band.max));
        if let Spectrum::Sampled { sampled } = self {
            for (&l, &v) in sampled.wavelengths.iter().zip(&sampled.values) {
                if band.contains(l) {
                    m = m.max(v);
                }
            }
        }
        for i in 0..=n {
            let l = band.min + band.width() * i as f32 / n as f32;
            m = m.max(self.eval(l));
        }
        m
    }
}

/// ∫ f over [a, b] by `panels` two-point-pair (4-point) Gauss–Legendre panels.
pub(crate) fn gauss_legendre(a: f64, b: f64, panels: usize, f: impl Fn(f64) -> f64) -> f64 {
    const X: [f64; 2] = [0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
    const W: [f64; 2] = [0.652_145_154_862_546_1, 0.347_854_845_137_453_9];
    let h = (b - a) / panels as f64;
    let mut s = 0.0;
    for i in 0..panels {
        let m = a + (i as f64 + 0.5) * h;
        for k in 0..2 {
            s += W[k] * (f(m - 0.5 * h * X[k]) + f(m + 0.5 * h * X[k]));
        }
    }
    s * 0.5 * h
}
