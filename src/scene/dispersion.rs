//! Dispersion: a material whose refractive index varies with wavelength.
//!
//! A dielectric's relative index η(λ) (Cauchy, Sellmeier or tabulated, see
//! [`crate::spectrum::Ior`]) and a conductor's complex index η(λ) + i k(λ) replace the
//! grey parameters of the material's BSDF at each path's (hero) wavelength. Because the
//! refracted direction depends on η, a dispersive surface ends a path's secondary
//! wavelength lanes ([`crate::transport::phase`]).

use crate::bsdf::{Bsdf, Index, ModelFacts};
use crate::spectrum::{Band, Ior, Spectrum};
use serde::{Deserialize, Serialize};

/// Largest extinction coefficient k a conductor accepts (as its BSDF's own check).
const MAX_K: f32 = 100.0;

/// The wavelength-dependent index of one material, as written in a scene's
/// `dispersion` map: `{"glass": {"eta": {"sellmeier": {...}}}}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpectralIor {
    /// Real part of the index (relative to the outside medium).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Ior>,
    /// Extinction coefficient k(λ) of a conductor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<Spectrum>,
}

impl SpectralIor {
    /// Check the index over `band` against the material it modifies: only dielectrics
    /// take `eta`, only conductors take `k`. An error comes with the path inside this
    /// entry's JSON that it points at (`.eta`, `.eta.sellmeier.c`, `.k.sampled.values`,
    /// …), or `""` for the entry as a whole.
    pub fn validate(&self, bsdf: &Bsdf, band: Band) -> Result<(), (String, String)> {
        let at = |path: &str, r: String| (path.to_string(), r);
        let (takes_eta, takes_k) = match bsdf.clone().index() {
            Index::Dielectric(_) => (true, false),
            Index::Conductor(..) => (true, true),
            Index::Fixed => {
                return Err(at(
                    "",
                    format!(
                        "a `{}` material has no refractive index to vary (use dielectric, rough_dielectric, conductor or rough_conductor)",
                        bsdf.name()
                    ),
                ));
            }
        };
        if self.eta.is_none() && self.k.is_none() {
            return Err(at("", "give `eta`, `k` or both".into()));
        }
        if let Some(eta) = &self.eta {
            if !takes_eta {
                return Err(at(".eta", "this material takes no `eta`".into()));
            }
            eta.validate(band)
                .map_err(|(path, r)| at(&format!(".eta{path}"), format!("eta: {r}")))?;
            // The BSDF's own bounds on η hold at every wavelength of the band.
            let (lo, hi) = eta.range_in(band);
            let (min, max) = if takes_k {
                (1e-3, 100.0)
            } else {
                (0.01, 100.0)
            };
            if !(lo >= min && hi <= max) {
                return Err(at(
                    ".eta",
                    format!(
                        "eta: the index spans [{lo}, {hi}] over [{}, {}] nm; a `{}` needs it within [{min}, {max}]",
                        band.min,
                        band.max,
                        bsdf.name()
                    ),
                ));
            }
            // A rough dielectric's index stays MIN_ETA_GAP from 1 at every wavelength.
            let gap = crate::bsdf::rough_dielectric::MIN_ETA_GAP;
            let nearest = if lo <= 1.0 && hi >= 1.0 {
                0.0
            } else {
                (lo - 1.0).abs().min((hi - 1.0).abs())
            };
            if matches!(bsdf, Bsdf::RoughDielectric(_))
                && !crate::bsdf::rough_dielectric::resolves(nearest.into())
            {
                return Err(at(
                    ".eta",
                    format!(
                        "eta: the index spans [{lo}, {hi}] over [{}, {}] nm, within {gap:e} of 1 somewhere: a rough dielectric does not resolve an interface that weak (see its `eta`)",
                        band.min, band.max
                    ),
                ));
            }
        }
        if let Some(k) = &self.k {
            if !takes_k {
                return Err(at(
                    ".k",
                    format!(
                        "`k` (extinction) applies to conductors, not to a `{}`",
                        bsdf.name()
                    ),
                ));
            }
            k.validate_at()
                .map_err(|(path, r)| at(&format!(".k{path}"), format!("k: {r}")))?;
            // The conductor's own bound on k (as in `materials`) holds over the band.
            let kmax = k.max_in(band);
            if !(kmax <= MAX_K) {
                return Err(at(
                    ".k",
                    format!(
                        "k: the extinction coefficient reaches {kmax} over [{}, {}] nm; a `{}` needs it within [0, {MAX_K}]",
                        band.min,
                        band.max,
                        bsdf.name()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Whether anything varies with wavelength.
    pub fn is_dispersive(&self) -> bool {
        self.eta.as_ref().is_some_and(|e| !e.is_constant())
            || self.k.as_ref().is_some_and(|k| !k.is_constant())
    }

    /// The material at wavelength `lambda` (nm).
    pub fn at(&self, bsdf: &Bsdf, lambda: f32) -> Bsdf {
        let mut b = bsdf.clone();
        let eta = self.eta.as_ref().map(|e| e.eval(lambda));
        let k = self.k.as_ref().map(|k| k.eval(lambda).max(0.0));
        match b.index() {
            Index::Dielectric(e) => *e = eta.unwrap_or(*e),
            Index::Conductor(e, kk) => {
                *e = eta.unwrap_or(*e);
                *kk = k.unwrap_or(*kk);
            }
            Index::Fixed => {}
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Conductor, Dielectric, Lambertian};

    /// Each refusal names the path inside the entry that it points at, so the loader's
    /// field reads e.g. `scene.dispersion.glass.eta.sellmeier.c`, not just the entry.
    #[test]
    fn refusals_name_the_part_of_the_entry() {
        let glass = Bsdf::Dielectric(Dielectric::new(1.5));
        let metal = Bsdf::Conductor(Conductor::new(0.2, 3.9));
        let band = crate::spectrum::VISIBLE;
        let at = |d: serde_json::Value, b: &Bsdf| {
            let d: SpectralIor = serde_json::from_value(d).unwrap();
            d.validate(b, band).unwrap_err().0
        };
        use serde_json::json;
        let table = |v: f64| json!({"sampled": {"wavelengths": [400, 700], "values": [1.5, v]}});
        for (d, b, want) in [
            (
                json!({"eta": 1.5}),
                &Bsdf::Lambertian(Lambertian::new(0.5)),
                "",
            ),
            (json!({}), &glass, ""),
            (
                json!({"eta": {"sellmeier": {"b": [1, 0, 0], "c": [0.25, 0, 0]}}}),
                &glass,
                ".eta.sellmeier.c",
            ),
            (
                json!({"eta": {"cauchy": {"a": -1, "b": 0}}}),
                &glass,
                ".eta.cauchy",
            ),
            (json!({"eta": 150}), &glass, ".eta"),
            (json!({"eta": table(-1.0)}), &glass, ".eta.sampled.values"),
            (
                json!({"eta": {"sampled": {"wavelengths": [700, 400], "values": [1.5, 1.5]}}}),
                &glass,
                ".eta.sampled.wavelengths",
            ),
            (json!({"k": 1.0}), &glass, ".k"),
            (json!({"k": 1000}), &metal, ".k"),
            (json!({"k": table(-1.0)}), &metal, ".k.sampled.values"),
        ] {
            assert_eq!(at(d.clone(), b), want, "{d}");
        }
    }
}
