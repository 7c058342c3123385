//! Spectral responses of sensors: flat, the CIE photopic curve, or a table.

use super::json::{NumberOrMap, no_more_keys, number_or_map};
use super::spectrum::spectrum_value;
use super::table::TableRef;
use super::{Band, Spectrum, finite_f64};
use serde::de::{self, MapAccess};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The maximum luminous efficacy of photopic vision K_m = 683.002 lm/W: the SI candela
/// fixes 683 lm/W at 540 THz (555.016 nm), where ȳ = 0.999997; CIE 15 rounds the peak
/// value at 555 nm to 683.002. Luminous quantities are K_m ∫ ȳ(λ) X_λ dλ.
pub const LUMINOUS_EFFICACY: f64 = 683.002;

/// An upper bound of [`photopic`] over every wavelength (the fit peaks just above 1).
pub const PHOTOPIC_MAX: f32 = 1.01;

/// The CIE 1931 2° photopic luminosity function ȳ(λ) (= V(λ)), λ in nm.
///
/// **Formula.** The multi-lobe piecewise-Gaussian fit of C. Wyman, P.-P. Sloan and
/// P. Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching Functions",
/// JCGT 2(2), 1–11, 2013, eq. 2:
/// ȳ(λ) = 0.821 g(λ; 568.8, 46.9, 40.5) + 0.286 g(λ; 530.9, 16.3, 31.1), with
/// g(λ; μ, σ₁, σ₂) = exp(−½ ((λ − μ)/σ)²), σ = σ₁ for λ < μ and σ₂ otherwise.
///
/// **Accuracy** (measured in `tests/proof/spectrum.rs` against the CIE 15 5-nm table,
/// 380–780 nm): at most 0.0070 absolute error (0.7 % of the peak, at 620 nm);
/// ȳ(555) = 0.99804 instead of 1; ∫ȳ dλ over 360–830 nm = 106.922 nm against the
/// tables' 106.857 nm (+0.061 %). The authors state that the fit's error is below the
/// spread of the observers' data the CIE standard aggregates. 0 for NaN.
pub fn photopic(lambda_nm: f32) -> f32 {
    super::cie::Y.eval(lambda_nm)
}

/// A sensor's spectral response R(λ), weighting a spectral measurement ∫ R(λ) M(λ) dλ.
///
/// JSON: `"flat"` (R = 1: radiometric), `"photopic"` (CIE 1931 ȳ; multiply by
/// [`LUMINOUS_EFFICACY`] for lumens), or `{"sampled": {"wavelengths": [..], "values":
/// [..]}}` (linear, zero outside; the body may also be any [`Spectrum`] JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Response {
    /// R = 1.
    Flat,
    /// CIE 1931 ȳ(λ), see [`photopic`].
    Photopic,
    /// Any spectrum, usually a table.
    Sampled(
        #[serde(
            deserialize_with = "response_body",
            serialize_with = "ser_response_body"
        )]
        Spectrum,
    ),
}

impl Response {
    /// R(λ), finite and non-negative.
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        match self {
            Response::Flat => 1.0,
            Response::Photopic => photopic(lambda_nm),
            Response::Sampled(s) => s.eval(lambda_nm),
        }
    }

    /// ∫ R dλ over the band (nm), exact for every kind (the photopic fit by erf); 0 for
    /// an empty or malformed band.
    pub fn integral(&self, band: Band) -> f64 {
        let Some((a, b)) = band.ends() else {
            return 0.0;
        };
        match self {
            Response::Flat => finite_f64(b - a),
            Response::Photopic => finite_f64(super::cie::Y.integral(a, b)),
            Response::Sampled(s) => s.integral(band),
        }
    }

    /// ∫ R(λ) λ/(hc) dλ over the band (photons per joule, integrated over nm; λ/(hc) with
    /// λ in metres), exact for every kind: (λ₂² − λ₁²)/2 for flat, the photopic fit's
    /// first moment by erf and exp ([`super::cie::Cmf::moment`]), both times 10⁻⁹/(hc),
    /// and [`Spectrum::photon_integral`]; 0 for an empty or malformed band.
    pub fn photon_integral(&self, band: Band) -> f64 {
        let Some((a, b)) = band.ends() else {
            return 0.0;
        };
        let per_joule = super::spectrum::PER_JOULE_NM;
        match self {
            Response::Flat => finite_f64(0.5 * (b - a) * (b + a) * per_joule),
            Response::Photopic => finite_f64(super::cie::Y.moment(a, b) * per_joule),
            Response::Sampled(s) => s.photon_integral(band),
        }
    }

    /// A bound on R over the band: 1 for flat, [`PHOTOPIC_MAX`] for the photopic fit
    /// (its peak near 555 nm, `tests::the_photopic_bound_holds`), and the table's
    /// [`Spectrum::max_in`]; 0 for a malformed band.
    pub fn max_in(&self, band: Band) -> f32 {
        if !(band.min <= band.max) {
            return 0.0;
        }
        match self {
            Response::Flat => 1.0,
            Response::Photopic => PHOTOPIC_MAX,
            Response::Sampled(s) => s.max_in(band),
        }
    }

    /// Whether R = 1 everywhere (flat, or a constant spectrum of 1).
    pub fn is_flat(&self) -> bool {
        matches!(
            self,
            Response::Flat | Response::Sampled(Spectrum::Constant(1.0))
        )
    }

    /// Check a sampled response (see [`Spectrum::validate`]).
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Response::Sampled(s) => s.validate(),
            Response::Flat | Response::Photopic => Ok(()),
        }
    }
}

/// The body of `{"sampled": ...}`: a bare table, or any spectrum.
struct Body(Spectrum);

const BODY_KEYS: &[&str] = &["wavelengths", "values", "sampled", "blackbody"];

impl<'de> NumberOrMap<'de> for Body {
    const EXPECTING: &'static str =
        "a response table {\"wavelengths\": [..], \"values\": [..]} or a spectrum";
    fn from_number<E: de::Error>(v: f64) -> Result<Self, E> {
        Ok(Body(Spectrum::Constant(v as f32)))
    }
    fn from_map<A: MapAccess<'de>>(mut map: A) -> Result<Self, A::Error> {
        let key = super::json::kind_key(&mut map, BODY_KEYS)?;
        if key == "sampled" || key == "blackbody" {
            let s = spectrum_value(&key, &mut map)?;
            no_more_keys(&mut map, &key, &["sampled", "blackbody"])?;
            return Ok(Body(s));
        }
        let (mut w, mut v): (Option<Vec<f32>>, Option<Vec<f32>>) = (None, None);
        let mut next = Some(key);
        while let Some(k) = next {
            let slot = match k.as_str() {
                "wavelengths" => &mut w,
                "values" => &mut v,
                other => return Err(de::Error::unknown_field(other, &["wavelengths", "values"])),
            };
            if slot.is_some() {
                return Err(de::Error::custom(format!("duplicate field `{k}`")));
            }
            *slot = Some(map.next_value::<crate::error::json_f32::List>()?.0);
            next = map.next_key()?;
        }
        Ok(Body(Spectrum::Sampled {
            wavelengths: w.ok_or_else(|| de::Error::missing_field("wavelengths"))?,
            values: v.ok_or_else(|| de::Error::missing_field("values"))?,
        }))
    }
}

fn response_body<'de, D: Deserializer<'de>>(d: D) -> Result<Spectrum, D::Error> {
    number_or_map::<D, Body>(d).map(|b| b.0)
}

fn ser_response_body<S: Serializer>(s: &Spectrum, ser: S) -> Result<S::Ok, S::Error> {
    match s {
        Spectrum::Sampled {
            wavelengths,
            values,
        } => TableRef {
            wavelengths,
            values,
        }
        .serialize(ser),
        other => other.serialize(ser),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{VISIBLE, gauss_legendre};

    /// [`PHOTOPIC_MAX`] bounds the fit at every f32 wavelength from 1 to 10⁷ nm (every
    /// f32 in [540, 570] nm, where the peak is, and a 10⁻³ nm grid up to 2000 nm, past
    /// which the lobes are negligible), and is within 2% of its peak.
    #[test]
    fn the_photopic_bound_holds() {
        let mut peak = 0.0f32;
        let mut l = 540.0f32;
        while l <= 570.0 {
            peak = peak.max(photopic(l));
            l = l.next_up();
        }
        for i in 0..2_000_000 {
            peak = peak.max(photopic(i as f32 * 1e-3));
        }
        for l in [3e3, 1e4, 1e5, 1e7] {
            peak = peak.max(photopic(l));
        }
        assert!(peak <= PHOTOPIC_MAX && peak > PHOTOPIC_MAX - 0.02, "{peak}");
        let band = |a: f32, b: f32| Band { min: a, max: b };
        assert_eq!(Response::Photopic.max_in(band(400.0, 700.0)), PHOTOPIC_MAX);
        assert_eq!(Response::Flat.max_in(band(400.0, 700.0)), 1.0);
        assert_eq!(Response::Flat.max_in(band(700.0, 400.0)), 0.0);
        let table: Spectrum = serde_json::from_value(
            serde_json::json!({"sampled": {"wavelengths": [400, 500], "values": [1, 3]}}),
        )
        .unwrap();
        assert_eq!(Response::Sampled(table).max_in(band(400.0, 450.0)), 2.0);
    }

    #[test]
    fn photopic_peak_and_area() {
        assert!((photopic(555.0) - 1.0).abs() < 0.005);
        let a = Response::Photopic.integral(VISIBLE);
        let q = gauss_legendre(360.0, 830.0, 4096, |l| photopic(l as f32) as f64);
        assert!((a - q).abs() < 1e-5 * a, "{a} {q}");
        assert!((a - 106.857).abs() / 106.857 < 0.005, "{a}");
        assert_eq!(Response::Flat.integral(VISIBLE), 470.0);
        for l in [f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0, -1e30, 1e30] {
            let y = photopic(l);
            assert!(y.is_finite() && y >= 0.0);
        }
    }

    #[test]
    fn json_forms() {
        let parse = |s: &str| serde_json::from_str::<Response>(s).map_err(|e| e.to_string());
        assert_eq!(parse(r#""flat""#).unwrap(), Response::Flat);
        assert_eq!(parse(r#""photopic""#).unwrap(), Response::Photopic);
        let t = parse(r#"{"sampled": {"wavelengths": [400, 700], "values": [1, 0]}}"#).unwrap();
        assert_eq!(
            t,
            Response::Sampled(Spectrum::sampled(vec![400.0, 700.0], vec![1.0, 0.0]))
        );
        let bb = Response::Sampled(Spectrum::blackbody(3000.0));
        for r in [Response::Flat, Response::Photopic, t, bb] {
            let j = serde_json::to_string(&r).unwrap();
            assert_eq!(parse(&j).unwrap(), r, "{j}");
        }
        assert!(
            parse(r#""scotopic""#)
                .unwrap_err()
                .contains("unknown variant")
        );
        assert!(
            parse(r#"{"sampled": {"wavelengths": [1, 2]}}"#)
                .unwrap_err()
                .contains("missing field `values`")
        );
        assert!(
            parse(r#"{"sampled": {"wavelengths": [1, 2], "values": [1, 2], "x": 1}}"#)
                .unwrap_err()
                .contains("unknown field `x`")
        );
        assert!(Response::Sampled(Spectrum::Constant(1.0)).is_flat());
    }
}
