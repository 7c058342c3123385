//! Refractive index as a function of wavelength (dispersion).

use super::Band;
use super::json::{NumberOrMap, kind_key, no_more_keys, number_or_map};
use super::table::{self, Outside, TableBody, TableRef};
use serde::de::{self, MapAccess};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A (real) refractive index n(λ), relative to the outside medium.
///
/// JSON: a number (constant); `{"cauchy": {"a": 1.5046, "b": 0.00420, "c": 0}}` (b, c
/// default to 0); `{"sellmeier": {"b": [b₁, b₂, b₃], "c": [c₁, c₂, c₃]}}`;
/// `{"sampled": {"wavelengths": [..], "values": [..]}}` (linear interpolation, **the end
/// values held outside the table**: an index cannot drop to zero, and glass does not
/// stop refracting where a catalogue's table ends).
#[derive(Clone, Debug, PartialEq)]
pub enum Ior {
    /// The same index at every wavelength.
    Constant(f32),
    /// Cauchy's formula n = a + b/λ² + c/λ⁴, λ in µm, b in µm², c in µm⁴
    /// (A.-L. Cauchy 1836; Born & Wolf, *Principles of Optics*, §2.3.4).
    Cauchy {
        /// a (dimensionless).
        a: f32,
        /// b (µm²).
        b: f32,
        /// c (µm⁴).
        c: f32,
    },
    /// Sellmeier's formula n² = 1 + Σᵢ bᵢλ²/(λ² − cᵢ), λ in µm, cᵢ in µm² (poles at
    /// λ = √cᵢ) (W. Sellmeier 1872; Born & Wolf §2.3.4).
    Sellmeier {
        /// b₁, b₂, b₃ (dimensionless).
        b: [f32; 3],
        /// c₁, c₂, c₃ (µm²).
        c: [f32; 3],
    },
    /// A table (nm, strictly increasing; indices), linearly interpolated, end values
    /// outside.
    Sampled {
        /// Wavelengths (nm), strictly increasing.
        wavelengths: Vec<f32>,
        /// Indices at those wavelengths.
        values: Vec<f32>,
    },
}

/// Schott N-BK7, the common borosilicate crown glass, by its Sellmeier coefficients.
///
/// **Source.** Schott optical glass data sheet N-BK7 (517642.251):
/// B₁ = 1.03961212, B₂ = 0.231792344, B₃ = 1.01046945, C₁ = 0.00600069867 µm²,
/// C₂ = 0.0200179144 µm², C₃ = 103.560653 µm² (stored as `f32`). The data sheet gives
/// n_d(587.5618 nm) = 1.51680, n_F(486.1327 nm) = 1.52238, n_C(656.2725 nm) = 1.51432,
/// Abbe number ν_d = 64.17.
pub fn bk7() -> Ior {
    Ior::Sellmeier {
        b: [1.039_612, 0.231_792_34, 1.010_469_5],
        c: [6.000_698_7e-3, 2.001_791_4e-2, 103.560_65],
    }
}

/// Intervals of the grid on which [`Ior::validate`] checks a formula over a band.
const GRID: usize = 1024;

impl Ior {
    /// The formula's raw value in `f64` (NaN or ≤ 0 where it is not physical).
    fn raw(&self, lambda_nm: f32) -> f64 {
        let l = lambda_nm as f64 * 1e-3;
        let l2 = l * l;
        match self {
            Ior::Constant(n) => *n as f64,
            Ior::Cauchy { a, b, c } => *a as f64 + *b as f64 / l2 + *c as f64 / (l2 * l2),
            Ior::Sellmeier { b, c } => sellmeier_n2(b, c, l2).sqrt(),
            Ior::Sampled {
                wavelengths,
                values,
            } => table::interpolate(wavelengths, values, lambda_nm, Outside::Clamp) as f64,
        }
    }

    /// (min, max) of n over the band (nm), for checking a material's admissible range
    /// (e.g. a dielectric BSDF's η ∈ [0.01, 100]) at every wavelength: exact for a
    /// constant, a table (its entries and interpolated ends) and Cauchy (the quadratic in
    /// 1/λ² at its ends and vertex); on a 1024-interval grid for Sellmeier (monotone
    /// between poles for positive coefficients). Values are [`Ior::eval`]'s, so always
    /// positive and finite; a malformed band gives n at its finite end (or (1, 1)).
    pub fn range_in(&self, band: Band) -> (f32, f32) {
        let (lo, hi) = (band.min, band.max);
        if !(lo <= hi) {
            let l = if lo.is_finite() { lo } else { hi };
            let n = self.eval(l);
            return (n, n);
        }
        let mut points: Vec<f32> = vec![lo, hi];
        match self {
            Ior::Constant(_) => {}
            Ior::Cauchy { b, c, .. } => {
                if *c != 0.0 {
                    // dn/ds = b + 2cs = 0 at s = 1/λ² (µm⁻²).
                    let s = -(*b as f64) / (2.0 * *c as f64);
                    if s > 0.0 {
                        let l = (1e3 / s.sqrt()) as f32;
                        if band.contains(l) {
                            points.push(l);
                        }
                    }
                }
            }
            Ior::Sellmeier { .. } => {
                points.extend((1..GRID).map(|k| {
                    (lo as f64 + (hi as f64 - lo as f64) * k as f64 / GRID as f64) as f32
                }));
            }
            Ior::Sampled { wavelengths, .. } => {
                points.extend(wavelengths.iter().copied().filter(|&l| band.contains(l)));
            }
        }
        points
            .iter()
            .fold((f32::MAX, f32::MIN_POSITIVE), |(a, b), &l| {
                let n = self.eval(l);
                (a.min(n), b.max(n))
            })
    }

    /// n(λ), always positive and finite.
    ///
    /// **Formulas.** See the variants: Cauchy a + b/λ² + c/λ⁴; Sellmeier
    /// √(1 + Σ bᵢλ²/(λ² − cᵢ)) (λ in µm, evaluated in `f64`); a table interpolated
    /// linearly with its end values outside. Where the formula gives nothing physical
    /// (λ ≤ 0 or NaN, at or between Sellmeier poles, a non-positive or overflowing
    /// value) the index is 1, as in vacuum. [`Ior::validate`] rejects data that would
    /// need this fallback inside the band.
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        physical(self.raw(lambda_nm)).unwrap_or(1.0)
    }

    /// Whether n is the same at every wavelength (a constant; Cauchy with b = c = 0;
    /// Sellmeier with every bᵢ = 0; a table of equal values).
    pub fn is_constant(&self) -> bool {
        match self {
            Ior::Constant(_) => true,
            Ior::Cauchy { b, c, .. } => *b == 0.0 && *c == 0.0,
            Ior::Sellmeier { b, .. } => b.iter().all(|&x| x == 0.0),
            Ior::Sampled { values, .. } => values.windows(2).all(|w| w[0] == w[1]),
        }
    }

    /// Check the index over `band` (nm): finite coefficients; n > 0 and finite over the
    /// whole band; Sellmeier poles λ = √cᵢ (for bᵢ ≠ 0, cᵢ > 0) outside it; a table with
    /// positive values. Cauchy's minimum over the band is found exactly (a quadratic in
    /// 1/λ²); the other kinds are also checked on a 1024-interval grid. An error comes
    /// with the path inside the index's JSON that it points at (`.cauchy.a`,
    /// `.sellmeier.c`, `.sampled.values`, …), or `""` for the index as a whole.
    pub fn validate(&self, band: Band) -> Result<(), (&'static str, String)> {
        let whole = |r: String| ("", r);
        band.validate()
            .map_err(|r| whole(format!("the band {r}")))?;
        let (lo, hi) = (band.min, band.max);
        match self {
            Ior::Constant(n) => {
                if physical(*n as f64).is_none() {
                    return Err(whole(format!("must be a positive finite index, got {n}")));
                }
            }
            Ior::Cauchy { a, b, c } => {
                for (at, name, v) in [
                    (".cauchy.a", "a", a),
                    (".cauchy.b", "b", b),
                    (".cauchy.c", "c", c),
                ] {
                    if !v.is_finite() {
                        return Err((at, format!("cauchy.{name} must be finite, got {v}")));
                    }
                }
                // n = a + b s + c s², s = 1/λ² (µm⁻²) over [1/hi², 1/lo²].
                let s_of = |l: f32| 1.0 / (l as f64 * 1e-3).powi(2);
                let (s0, s1) = (s_of(hi), s_of(lo));
                let mut candidates = vec![s0, s1];
                if *c != 0.0 {
                    let v = -(*b as f64) / (2.0 * *c as f64);
                    if v > s0 && v < s1 {
                        candidates.push(v);
                    }
                }
                for s in candidates {
                    let n = *a as f64 + *b as f64 * s + *c as f64 * s * s;
                    if physical(n).is_none() {
                        return Err((
                            ".cauchy",
                            format!(
                                "the Cauchy index a + b/λ² + c/λ⁴ must be positive and finite over [{lo}, {hi}] nm; at {:.1} nm it is {n}",
                                1e3 / s.sqrt()
                            ),
                        ));
                    }
                }
            }
            Ior::Sellmeier { b, c } => {
                for (at, name, v) in [(".sellmeier.b", "b", b), (".sellmeier.c", "c", c)] {
                    if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                        return Err((at, format!("sellmeier.{name}[{i}] must be finite, got {x}")));
                    }
                }
                for i in 0..3 {
                    if b[i] != 0.0 && c[i] > 0.0 {
                        let pole = (c[i] as f64).sqrt() * 1e3;
                        if pole >= lo as f64 && pole <= hi as f64 {
                            return Err((
                                ".sellmeier.c",
                                format!(
                                    "the Sellmeier pole λ = √c[{i}] = {pole:.1} nm (c[{i}] = {} µm²) lies inside the band [{lo}, {hi}] nm",
                                    c[i]
                                ),
                            ));
                        }
                    }
                }
            }
            Ior::Sampled {
                wavelengths,
                values,
            } => {
                table::validate_at(wavelengths, values, true)?;
                // Interpolation stays between neighbouring entries: checking them suffices.
                if let Some((i, v)) = values
                    .iter()
                    .enumerate()
                    .find(|(_, v)| physical(**v as f64).is_none())
                {
                    return Err((
                        ".sampled.values",
                        format!("values[{i}] must be a positive finite index, got {v}"),
                    ));
                }
            }
        }
        for k in 0..=GRID {
            let l = if k == GRID {
                hi
            } else {
                (lo as f64 + (hi - lo) as f64 * k as f64 / GRID as f64) as f32
            };
            let n = self.raw(l);
            if physical(n).is_none() {
                return Err(whole(format!(
                    "the index must be positive and finite over [{lo}, {hi}] nm; at {l} nm it is {n}"
                )));
            }
        }
        Ok(())
    }
}

/// n² of Sellmeier's formula at λ² (µm²).
fn sellmeier_n2(b: &[f32; 3], c: &[f32; 3], l2: f64) -> f64 {
    1.0 + (0..3)
        .map(|i| b[i] as f64 * l2 / (l2 - c[i] as f64))
        .sum::<f64>()
}

/// n as a positive, finite, normal `f32` (≥ `f32::MIN_POSITIVE`, so that 1/n and n² keep
/// their relative precision), if it is one.
fn physical(n: f64) -> Option<f32> {
    let f = n as f32;
    (f.is_finite() && f >= f32::MIN_POSITIVE).then_some(f)
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct CauchyBody {
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    a: f32,
    #[serde(default, deserialize_with = "crate::error::json_f32::scalar")]
    b: f32,
    #[serde(default, deserialize_with = "crate::error::json_f32::scalar")]
    c: f32,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct SellmeierBody {
    #[serde(deserialize_with = "crate::error::json_f32::triple")]
    b: [f32; 3],
    #[serde(deserialize_with = "crate::error::json_f32::triple")]
    c: [f32; 3],
}

const KINDS: &[&str] = &["cauchy", "sellmeier", "sampled"];

impl<'de> NumberOrMap<'de> for Ior {
    const EXPECTING: &'static str = "an index of refraction: a number, {\"cauchy\": {..}}, {\"sellmeier\": {..}} or {\"sampled\": {..}}";
    fn from_number<E: de::Error>(v: f64) -> Result<Self, E> {
        Ok(Ior::Constant(v as f32))
    }
    fn from_map<A: MapAccess<'de>>(mut map: A) -> Result<Self, A::Error> {
        let key = kind_key(&mut map, KINDS)?;
        let ior = match key.as_str() {
            "cauchy" => {
                let CauchyBody { a, b, c } = map.next_value()?;
                Ior::Cauchy { a, b, c }
            }
            "sellmeier" => {
                let SellmeierBody { b, c } = map.next_value()?;
                Ior::Sellmeier { b, c }
            }
            _ => {
                let TableBody {
                    wavelengths,
                    values,
                } = map.next_value()?;
                Ior::Sampled {
                    wavelengths,
                    values,
                }
            }
        };
        no_more_keys(&mut map, &key, KINDS)?;
        Ok(ior)
    }
}

impl<'de> Deserialize<'de> for Ior {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        number_or_map(d)
    }
}

impl Serialize for Ior {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if let Ior::Constant(n) = self {
            return s.serialize_f32(*n);
        }
        let mut m = s.serialize_map(Some(1))?;
        match self {
            Ior::Cauchy { a, b, c } => m.serialize_entry(
                "cauchy",
                &CauchyBody {
                    a: *a,
                    b: *b,
                    c: *c,
                },
            )?,
            Ior::Sellmeier { b, c } => {
                m.serialize_entry("sellmeier", &SellmeierBody { b: *b, c: *c })?
            }
            Ior::Sampled {
                wavelengths,
                values,
            } => m.serialize_entry(
                "sampled",
                &TableRef {
                    wavelengths,
                    values,
                },
            )?,
            Ior::Constant(_) => unreachable!(),
        }
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::VISIBLE;

    #[test]
    fn bk7_d_line_and_cauchy() {
        assert!((bk7().eval(587.5618) - 1.5168).abs() < 1e-4);
        let c = Ior::Cauchy {
            a: 1.5046,
            b: 0.0042,
            c: 0.0,
        };
        assert!((c.eval(500.0) - (1.5046 + 0.0168)).abs() < 1e-6);
        assert!(bk7().validate(VISIBLE).is_ok() && c.validate(VISIBLE).is_ok());
        assert!(!bk7().is_constant() && !c.is_constant() && Ior::Constant(1.5).is_constant());
    }

    #[test]
    fn unphysical_falls_back_to_one_and_fails_validation() {
        let bad = Ior::Cauchy {
            a: -1.0,
            b: 0.0,
            c: 0.0,
        };
        assert!(bad.validate(VISIBLE).is_err());
        assert_eq!(bad.eval(500.0), 1.0);
        // A pole at 500 nm.
        let pole = Ior::Sellmeier {
            b: [1.0, 0.0, 0.0],
            c: [0.25, 0.0, 0.0],
        };
        let (at, e) = pole.validate(VISIBLE).unwrap_err();
        assert!(
            at == ".sellmeier.c" && e.contains("500.0 nm") && e.contains("inside the band"),
            "{at}: {e}"
        );
        for l in [500.0, 0.0, -1.0, f32::NAN, f32::INFINITY] {
            let n = pole.eval(l);
            assert!(n.is_finite() && n > 0.0, "{l} {n}");
        }
        // Cauchy dipping below zero inside the band (vertex of the quadratic in 1/λ²).
        let dip = Ior::Cauchy {
            a: 1.0,
            b: -2.0,
            c: 0.9,
        };
        let (at, e) = dip.validate(VISIBLE).unwrap_err();
        assert!(at == ".cauchy" && e.contains("Cauchy"), "{at}: {e}");
        assert!(Ior::Constant(0.0).validate(VISIBLE).is_err());
        assert!(
            Ior::Constant(1.5)
                .validate(Band::new(700.0, 400.0))
                .is_err()
        );
    }

    #[test]
    fn range_over_a_band() {
        let (lo, hi) = bk7().range_in(VISIBLE);
        assert_eq!((lo, hi), (bk7().eval(830.0), bk7().eval(360.0)));
        assert_eq!(Ior::Constant(1.5).range_in(VISIBLE), (1.5, 1.5));
        // Cauchy with an interior minimum: n = 1.5 − 0.02 s + 0.001 s², minimum at s = 10
        // (λ = 316.2 nm): 1.4.
        let c = Ior::Cauchy {
            a: 1.5,
            b: -0.02,
            c: 0.001,
        };
        let (lo, _) = c.range_in(Band::new(250.0, 800.0));
        assert!((lo - 1.4).abs() < 1e-6, "{lo}");
        let t = Ior::Sampled {
            wavelengths: vec![400.0, 500.0, 600.0],
            values: vec![1.5, 1.7, 1.4],
        };
        assert_eq!(t.range_in(Band::new(450.0, 550.0)), (1.55, 1.7));
        // Subnormal indices are not physical: rejected, and eval falls back to 1.
        let tiny = Ior::Constant(1e-40);
        assert!(tiny.validate(VISIBLE).is_err() && tiny.eval(500.0) == 1.0);
    }

    #[test]
    fn json_forms_round_trip() {
        let parse = |s: &str| serde_json::from_str::<Ior>(s).map_err(|e| e.to_string());
        assert_eq!(parse("1.5").unwrap(), Ior::Constant(1.5));
        assert_eq!(
            parse(r#"{"cauchy": {"a": 1.5, "b": 0.004}}"#).unwrap(),
            Ior::Cauchy {
                a: 1.5,
                b: 0.004,
                c: 0.0
            }
        );
        for ior in [
            Ior::Constant(1.33),
            bk7(),
            Ior::Cauchy {
                a: 1.5,
                b: 0.01,
                c: 1e-4,
            },
            Ior::Sampled {
                wavelengths: vec![400.0, 700.0],
                values: vec![1.6, 1.5],
            },
        ] {
            let j = serde_json::to_string(&ior).unwrap();
            assert_eq!(parse(&j).unwrap(), ior, "{j}");
        }
        assert!(parse(r#"{"sellmeier": {"b": [1, 2], "c": [1, 2, 3]}}"#).is_err());
        assert!(
            parse(r#"{"cauchy": {"a": 1.5, "d": 1}}"#)
                .unwrap_err()
                .contains("unknown field `d`")
        );
        assert!(
            parse(r#"{"abbe": 64}"#)
                .unwrap_err()
                .contains("unknown variant")
        );
    }
}
