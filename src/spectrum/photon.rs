//! The exact SI constants and the energy of one photon.

/// Speed of light in vacuum c (m/s), exact by the SI definition of the metre (2019).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Planck constant h (J·s), exact by the SI definition of the kilogram (2019).
pub const PLANCK: f64 = 6.626_070_15e-34;
/// Boltzmann constant k (J/K), exact by the SI definition of the kelvin (2019).
pub const BOLTZMANN: f64 = 1.380_649e-23;

/// Energy of one photon of vacuum wavelength `lambda_nm` (nm), in joules.
///
/// **Formula.** e = hc/λ (Planck–Einstein relation, E = hν with ν = c/λ); 550 nm gives
/// 3.6118e-19 J. A radiant energy Q carried at λ is Q/e photons.
///
/// **Degenerate input.** The result always lies in [`f64::MIN_POSITIVE`, `f64::MAX`], so
/// a photon count Q/e stays finite: a wavelength that is not positive (0, negative, NaN)
/// carries no photons and gives `f64::MAX`; +∞ gives `f64::MIN_POSITIVE`.
pub fn photon_energy(lambda_nm: f64) -> f64 {
    if !(lambda_nm > 0.0) {
        return f64::MAX;
    }
    (PLANCK * SPEED_OF_LIGHT / (lambda_nm * 1e-9)).clamp(f64::MIN_POSITIVE, f64::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn green_photon_and_degenerate_wavelengths() {
        // hc = 1.98644586e-25 J·m; at 550 nm: 3.61172e-19 J.
        let e = photon_energy(550.0);
        assert!((e / 3.611_719_7e-19 - 1.0).abs() < 1e-7, "{e}");
        for l in [
            0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-300,
            1e300,
        ] {
            let e = photon_energy(l);
            assert!(
                e.is_finite() && e > 0.0 && (1.0 / e).is_finite(),
                "{l}: {e}"
            );
        }
    }
}
