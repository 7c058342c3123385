//! Tabulated functions of wavelength {(λᵢ, vᵢ)}: validation, linear interpolation,
//! exact integrals and maxima. Shared by [`super::Spectrum`] (zero outside the table),
//! [`super::Ior`] (end values held outside) and [`super::Response`].
//!
//! Every function here tolerates malformed tables (unequal lengths, unsorted or NaN
//! wavelengths) without panicking; `validate_at` is what rejects them.

use super::MIN_RELATIVE_BANDWIDTH;
use serde::{Deserialize, Serialize};

/// What a table is worth outside [λ₀, λₙ₋₁].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Outside {
    /// Zero (an emission or response spectrum).
    Zero,
    /// The nearest end value (a refractive index).
    Clamp,
}

/// Linear interpolation: v(λ) = vᵢ₋₁ + t (vᵢ − vᵢ₋₁), t = (λ − λᵢ₋₁)/(λᵢ − λᵢ₋₁), on the
/// interval holding λ. May return a negative or non-finite value for an unvalidated
/// table (callers clamp); NaN for NaN λ with [`Outside::Clamp`].
pub(crate) fn interpolate(w: &[f32], v: &[f32], lambda: f32, outside: Outside) -> f32 {
    let n = w.len().min(v.len());
    if n == 0 {
        return f32::NAN;
    }
    let (first, last) = (w[0], w[n - 1]);
    if !(lambda >= first && lambda <= last) {
        return match outside {
            Outside::Zero => 0.0,
            Outside::Clamp if lambda.is_nan() => f32::NAN,
            Outside::Clamp if lambda < first => v[0],
            Outside::Clamp => v[n - 1],
        };
    }
    if n == 1 {
        return v[0];
    }
    let i = w[..n].partition_point(|&x| x <= lambda).clamp(1, n - 1);
    let (l0, l1) = (w[i - 1], w[i]);
    let t = if l1 > l0 {
        ((lambda - l0) / (l1 - l0)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    v[i - 1] + t * (v[i] - v[i - 1])
}

/// The table's linear pieces clipped to [a, b]: (c, d, v) for each non-empty
/// [c, d] = [λᵢ₋₁, λᵢ] ∩ [a, b], with v(x) the interpolant of that piece.
fn clipped_pieces(
    w: &[f32],
    v: &[f32],
    a: f64,
    b: f64,
) -> impl Iterator<Item = (f64, f64, impl Fn(f64) -> f64)> {
    let n = w.len().min(v.len());
    (1..n).filter_map(move |i| {
        let (l0, l1) = (w[i - 1] as f64, w[i] as f64);
        let (c, d) = (l0.max(a), l1.min(b));
        let (v0, v1) = (v[i - 1] as f64, v[i] as f64);
        let at = move |x: f64| v0 + (x - l0) / (l1 - l0) * (v1 - v0);
        (d > c && l1 > l0).then_some((c, d, at))
    })
}

/// ∫ v(λ) dλ over [a, b] ∩ [λ₀, λₙ₋₁] (zero outside the table), exact for the
/// piecewise-linear function: Σ over the clipped intervals of (d − c)(v(c) + v(d))/2.
pub(crate) fn integral(w: &[f32], v: &[f32], a: f64, b: f64) -> f64 {
    clipped_pieces(w, v, a, b).fold(0.0, |s, (c, d, at)| s + 0.5 * (d - c) * (at(c) + at(d)))
}

/// ∫ v(λ) λ dλ over [a, b] ∩ [λ₀, λₙ₋₁] (nm², zero outside the table), exact for the
/// piecewise-linear function: v·λ is quadratic on each clipped interval [c, d], so
/// Simpson's rule (d − c)/6 · (f(c) + 4f((c + d)/2) + f(d)), exact for cubics, is exact.
pub(crate) fn moment(w: &[f32], v: &[f32], a: f64, b: f64) -> f64 {
    clipped_pieces(w, v, a, b).fold(0.0, |s, (c, d, at)| {
        let f = |x: f64| at(x) * x;
        s + (d - c) / 6.0 * (f(c) + 4.0 * f(0.5 * (c + d)) + f(d))
    })
}

/// max v over [a, b] (zero outside the table): the larger of the interpolated ends and
/// the entries inside, exact for a piecewise-linear function.
pub(crate) fn max_in(w: &[f32], v: &[f32], a: f32, b: f32) -> f32 {
    let n = w.len().min(v.len());
    let mut m = interpolate(w, v, a, Outside::Zero).max(interpolate(w, v, b, Outside::Zero));
    for i in 0..n {
        if w[i] >= a && w[i] <= b {
            m = m.max(v[i]);
        }
    }
    m
}

/// At least two entries, equal lengths, positive finite strictly increasing
/// wavelengths, finite values that are non-negative (or positive with `positive`). An
/// error comes with the path inside the table's JSON, `{"sampled": {...}}`, that it points
/// at: `.sampled.wavelengths`, `.sampled.values`, or `.sampled` for the table as a whole.
/// Each piece [λᵢ₋₁, λᵢ] is at least
/// [`MIN_RELATIVE_BANDWIDTH`]·λᵢ wide, as a band is: f32 wavelengths (a step of
/// 2⁻²³·λ to 2⁻²⁴·λ) resolve it into ~10³ values, so its rounded ends move its width by
/// at most 0.12 %. A spike [499.9995, 500, 500.0005] nm of peak 10⁶ integrated to 488.6
/// (the rounded table's 488.28) for 500, and one ten times narrower to 53.3 for 50.
pub(crate) fn validate_at(
    w: &[f32],
    v: &[f32],
    positive: bool,
) -> Result<(), (&'static str, String)> {
    let whole = |r: String| (".sampled", r);
    let wl = |r: String| (".sampled.wavelengths", r);
    if w.len() != v.len() {
        return Err(whole(format!(
            "wavelengths and values must have the same length, got {} and {}",
            w.len(),
            v.len()
        )));
    }
    if w.len() < 2 {
        return Err(whole(format!(
            "a table needs at least 2 wavelengths, got {}",
            w.len()
        )));
    }
    for (i, &l) in w.iter().enumerate() {
        if !(l.is_finite() && l > 0.0) {
            return Err(wl(format!(
                "wavelengths[{i}] must be a positive finite wavelength in nm, got {l}"
            )));
        }
        if i > 0 && !(l > w[i - 1]) {
            return Err(wl(format!(
                "wavelengths must increase strictly: wavelengths[{i}] = {l} does not exceed wavelengths[{}] = {}",
                i - 1,
                w[i - 1]
            )));
        }
        if i > 0 && !(l as f64 - w[i - 1] as f64 >= MIN_RELATIVE_BANDWIDTH * l as f64) {
            return Err(wl(format!(
                "the piece [wavelengths[{}], wavelengths[{i}]] = [{}, {l}] nm is too narrow for f32 wavelengths: λᵢ − λᵢ₋₁ must be at least {MIN_RELATIVE_BANDWIDTH}·λᵢ ({:.3e} nm here), as for a band",
                i - 1,
                w[i - 1],
                MIN_RELATIVE_BANDWIDTH * l as f64
            )));
        }
    }
    for (i, &x) in v.iter().enumerate() {
        let ok = x.is_finite() && if positive { x > 0.0 } else { x >= 0.0 };
        if !ok {
            return Err((
                ".sampled.values",
                format!(
                    "values[{i}] must be {} and finite, got {x}",
                    if positive { "positive" } else { "non-negative" }
                ),
            ));
        }
    }
    Ok(())
}

/// JSON body of a table: `{"wavelengths": [...], "values": [...]}`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TableBody {
    #[serde(deserialize_with = "crate::error::json_f32::list")]
    pub wavelengths: Vec<f32>,
    #[serde(deserialize_with = "crate::error::json_f32::list")]
    pub values: Vec<f32>,
}

/// Borrowed [`TableBody`] for serialisation.
#[derive(Serialize)]
pub(crate) struct TableRef<'a> {
    pub wavelengths: &'a [f32],
    pub values: &'a [f32],
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: [f32; 4] = [400.0, 500.0, 600.0, 700.0];
    const V: [f32; 4] = [0.0, 1.0, 3.0, 1.0];

    #[test]
    fn interpolation_outside_and_ends() {
        assert_eq!(interpolate(&W, &V, 450.0, Outside::Zero), 0.5);
        assert_eq!(interpolate(&W, &V, 600.0, Outside::Zero), 3.0);
        assert_eq!(interpolate(&W, &V, 700.0, Outside::Zero), 1.0);
        assert_eq!(interpolate(&W, &V, 400.0, Outside::Zero), 0.0);
        assert_eq!(interpolate(&W, &V, 399.0, Outside::Zero), 0.0);
        assert_eq!(interpolate(&W, &V, 701.0, Outside::Clamp), 1.0);
        assert_eq!(interpolate(&W, &V, 10.0, Outside::Clamp), 0.0);
        assert_eq!(interpolate(&W, &V, f32::NAN, Outside::Zero), 0.0);
        assert!(interpolate(&W, &V, f32::NAN, Outside::Clamp).is_nan());
        // Malformed tables never panic.
        assert!(interpolate(&[], &[], 500.0, Outside::Zero).is_nan());
        let _ = interpolate(&[500.0, 400.0, 450.0], &[1.0, 2.0], 420.0, Outside::Zero);
        let _ = interpolate(&[f32::NAN, 400.0], &[1.0, 2.0], 420.0, Outside::Clamp);
    }

    #[test]
    fn exact_integral_and_max() {
        // Trapezoids: 50 + 200 + 200 over [400, 700].
        assert_eq!(integral(&W, &V, 0.0, 1e4), 450.0);
        // Clipped to [450, 550]: 25·(0.5+1)/... = (0.5+1)/2·50 + (1+2)/2·50 = 37.5 + 75.
        assert!((integral(&W, &V, 450.0, 550.0) - 112.5).abs() < 1e-12);
        assert_eq!(max_in(&W, &V, 450.0, 550.0), 2.0);
        assert_eq!(max_in(&W, &V, 0.0, 1e4), 3.0);
        assert_eq!(max_in(&W, &V, 800.0, 900.0), 0.0);
    }

    #[test]
    fn validation_messages() {
        assert!(validate_at(&W, &V, false).is_ok());
        assert!(
            validate_at(&W, &V, true)
                .unwrap_err()
                .1
                .contains("values[0] must be positive")
        );
        let e = validate_at(&[400.0, 400.0], &[1.0, 1.0], false)
            .unwrap_err()
            .1;
        assert!(e.contains("wavelengths[1] = 400 does not exceed"), "{e}");
        let e = validate_at(&W, &[1.0, 2.0, 3.0, -1.0], false).unwrap_err();
        assert_eq!(e.0, ".sampled.values");
        assert_eq!(e.1, "values[3] must be non-negative and finite, got -1");
        assert!(
            validate_at(&[500.0], &[1.0], false)
                .unwrap_err()
                .1
                .contains("at least 2")
        );
        assert!(
            validate_at(&W, &V[..3], false)
                .unwrap_err()
                .1
                .contains("same length")
        );
        assert!(
            validate_at(&[f32::NAN, 1.0], &V[..2], false)
                .unwrap_err()
                .1
                .contains("wavelengths[0]")
        );
    }

    /// A piece narrower than 10⁻⁴·λ is refused, as a band is, pointing at `wavelengths`:
    /// the audit's spikes [499.9995, 500, 500.0005] (integrated to 488.6 for 500) and ten
    /// times narrower (53.3 for 50); 0.06 nm at 500 nm passes, 0.049 does not.
    #[test]
    fn pieces_narrower_than_the_band_rule_are_refused() {
        for w in [
            [499.9995f32, 500.0, 500.0005],
            [499.99995, 500.0, 500.00005],
        ] {
            let (at, e) = validate_at(&w, &[0.0, 1e6, 0.0], false).unwrap_err();
            assert_eq!(at, ".sampled.wavelengths", "{e}");
            assert!(e.contains("too narrow for f32 wavelengths"), "{e}");
            assert!(e.contains("[wavelengths[0], wavelengths[1]]"), "{e}");
        }
        assert!(validate_at(&[499.94, 500.0, 500.06], &[0.0, 1.0, 0.0], false).is_ok());
        let e = validate_at(&[400.0, 499.951, 500.0], &[0.0, 1.0, 0.0], true)
            .unwrap_err()
            .1;
        assert!(e.contains("[wavelengths[1], wavelengths[2]]"), "{e}");
        // At 10⁷ nm the rule asks for 1000 nm.
        assert!(validate_at(&[9.9995e6, 1e7], &[1.0, 1.0], false).is_err());
        assert!(validate_at(&[9.999e6, 1e7], &[1.0, 1.0], false).is_ok());
        assert_eq!(validate_at(&W, &V, true).unwrap_err().0, ".sampled.values");
        assert_eq!(validate_at(&W, &V[..3], false).unwrap_err().0, ".sampled");
    }
}
