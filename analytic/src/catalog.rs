//! The dispatcher the case files use: a closed form by name, with named parameters.
//!
//! A case file's reference reads
//! `{"closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1}`;
//! the loader passes the object (with or without the `closed_form` key) to [`evaluate`].
//! Parameters are numbers, points `[x, y, z]`, or lists of points `[[x, y, z], ...]`.
//! Every parameter is required; unknown, missing, ill-typed, non-finite or out-of-range
//! parameters are errors naming the closed form, the parameter and the reason.
//! [`names`] lists every closed form with its parameters and a description with units.

use crate::geom::Vec3;
use crate::microfacet::{self, Distribution, Masking};
use crate::oren_nayar::{self, Form};
use crate::{
    fresnel, furnace, irradiance, partial_shapes, radiometry, solid_angle, spectrum, time,
    view_factor,
};
use serde_json::{Map, Value};
use std::f64::consts::PI;

/// Why a closed form could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CatalogError {
    /// No closed form of that name is registered.
    #[error("unknown closed form `{name}`; registered: {known}")]
    UnknownClosedForm {
        /// The name asked for.
        name: String,
        /// Comma-separated registered names.
        known: String,
    },
    /// A required parameter is absent.
    #[error("closed form `{form}`: missing parameter `{param}` (expects: {expected})")]
    MissingParameter {
        /// The closed form.
        form: &'static str,
        /// The parameter.
        param: &'static str,
        /// All parameters the form expects.
        expected: String,
    },
    /// A parameter the closed form does not take.
    #[error("closed form `{form}`: unknown parameter `{param}` (expects: {expected})")]
    UnknownParameter {
        /// The closed form.
        form: &'static str,
        /// The offending key.
        param: String,
        /// All parameters the form expects.
        expected: String,
    },
    /// A parameter of the wrong type, non-finite, or out of range.
    #[error("closed form `{form}`: parameter `{param}` {reason}")]
    InvalidParameter {
        /// The closed form.
        form: &'static str,
        /// The parameter.
        param: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The parameters are individually valid but together outside the formula's domain.
    #[error("closed form `{form}`: {reason}")]
    Domain {
        /// The closed form.
        form: &'static str,
        /// What is wrong.
        reason: String,
    },
}

/// A registered closed form: its name, parameter names (as a case file spells them) and
/// a one-line description with units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClosedFormInfo {
    /// The `closed_form` value a case file uses.
    pub name: &'static str,
    /// Parameter keys, all required.
    pub params: &'static [&'static str],
    /// What it computes, with units.
    pub description: &'static str,
}

type Result<T> = std::result::Result<T, CatalogError>;

/// Parameter access for one evaluation.
struct Params<'a> {
    form: &'static str,
    map: &'a Map<String, Value>,
}

impl Params<'_> {
    fn invalid(&self, param: &'static str, reason: impl Into<String>) -> CatalogError {
        CatalogError::InvalidParameter {
            form: self.form,
            param,
            reason: reason.into(),
        }
    }

    fn domain(&self, reason: impl Into<String>) -> CatalogError {
        CatalogError::Domain {
            form: self.form,
            reason: reason.into(),
        }
    }

    fn get(&self, name: &'static str) -> Result<&Value> {
        self.map
            .get(name)
            .ok_or_else(|| CatalogError::MissingParameter {
                form: self.form,
                param: name,
                expected: expected(self.form),
            })
    }

    fn number_of(&self, name: &'static str, v: &Value) -> Result<f64> {
        let x = v
            .as_f64()
            .ok_or_else(|| self.invalid(name, format!("must be a number, got {v}")))?;
        if !x.is_finite() {
            return Err(self.invalid(name, format!("must be finite, got {x}")));
        }
        Ok(x)
    }

    /// Any finite number.
    fn num(&self, name: &'static str) -> Result<f64> {
        let v = self.get(name)?;
        // serde_json has no NaN; a string "NaN"/"inf" is reported as such.
        if let Some(s) = v.as_str() {
            return Err(self.invalid(
                name,
                format!("must be a finite number, got the string {s:?}"),
            ));
        }
        self.number_of(name, v)
    }

    fn positive(&self, name: &'static str) -> Result<f64> {
        let x = self.num(name)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.invalid(name, format!("must be > 0, got {x}")))
        }
    }

    fn non_negative(&self, name: &'static str) -> Result<f64> {
        let x = self.num(name)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.invalid(name, format!("must be ≥ 0, got {x}")))
        }
    }

    /// A spot light's half-angles, in radians: `cone_angle_degrees` in [0, 180] and
    /// `falloff_start_degrees` in [0, cone_angle_degrees].
    fn spot_angles(&self) -> Result<(f64, f64)> {
        let total = self.range("cone_angle_degrees", 0.0, 180.0, false)?;
        let start = self.range("falloff_start_degrees", 0.0, total, false)?;
        Ok((total.to_radians(), start.to_radians()))
    }

    /// A number in [lo, hi] (or [lo, hi) when `open_hi`).
    fn range(&self, name: &'static str, lo: f64, hi: f64, open_hi: bool) -> Result<f64> {
        let x = self.num(name)?;
        let ok = x >= lo && if open_hi { x < hi } else { x <= hi };
        if ok {
            Ok(x)
        } else {
            let b = if open_hi { ")" } else { "]" };
            Err(self.invalid(name, format!("must lie in [{lo}, {hi}{b}, got {x}")))
        }
    }

    fn vec_of(&self, name: &'static str, v: &Value) -> Result<Vec3> {
        let arr = v
            .as_array()
            .filter(|a| a.len() == 3)
            .ok_or_else(|| self.invalid(name, format!("must be a point [x, y, z], got {v}")))?;
        let mut c = [0.0; 3];
        for (ci, x) in c.iter_mut().zip(arr) {
            *ci = self.number_of(name, x)?;
        }
        Ok(Vec3::from_array(c))
    }

    fn point(&self, name: &'static str) -> Result<Vec3> {
        let v = self.get(name)?;
        self.vec_of(name, v)
    }

    fn direction(&self, name: &'static str) -> Result<Vec3> {
        self.point(name)?
            .normalized()
            .ok_or_else(|| self.invalid(name, "must be a non-zero direction"))
    }

    fn points(&self, name: &'static str, min: usize) -> Result<Vec<Vec3>> {
        let v = self.get(name)?;
        let arr = v
            .as_array()
            .ok_or_else(|| self.invalid(name, "must be a list of points [[x, y, z], ...]"))?;
        if arr.len() < min {
            return Err(self.invalid(
                name,
                format!("needs at least {min} points, got {}", arr.len()),
            ));
        }
        arr.iter().map(|p| self.vec_of(name, p)).collect()
    }

    /// One of the named values `choices` (a string), returned as its index.
    fn choice(&self, name: &'static str, choices: &[&str]) -> Result<usize> {
        let v = self.get(name)?;
        v.as_str()
            .and_then(|s| choices.iter().position(|c| *c == s))
            .ok_or_else(|| {
                self.invalid(
                    name,
                    format!("must be one of {}, got {v}", choices.join(", ")),
                )
            })
    }

    /// A microfacet distribution: `"ggx"` or `"beckmann"`.
    fn distribution(&self) -> Result<Distribution> {
        const D: [Distribution; 2] = [Distribution::Ggx, Distribution::Beckmann];
        Ok(D[self.choice("distribution", &["ggx", "beckmann"])?])
    }

    /// A masking–shadowing form: `"height_correlated"` or `"uncorrelated"`.
    fn masking(&self) -> Result<Masking> {
        const M: [Masking; 2] = [Masking::HeightCorrelated, Masking::Uncorrelated];
        Ok(M[self.choice("masking", &["height_correlated", "uncorrelated"])?])
    }

    /// A microfacet roughness α ∈ [1e-4, 1] (the engine's range).
    fn alpha(&self) -> Result<f64> {
        self.range("alpha", 1e-4, 1.0, false)
    }

    fn triple(&self, name: &'static str) -> Result<[f64; 3]> {
        let p = self.point(name)?;
        Ok([p.x, p.y, p.z])
    }
}

/// A planar polygon's unit normal (Newell's method) or a domain error.
fn check_planar(p: &Params<'_>, name: &'static str, v: &[Vec3]) -> Result<()> {
    let o = v[0];
    let mut nrm = Vec3::default();
    for i in 0..v.len() {
        nrm = nrm + (v[i] - o).cross(v[(i + 1) % v.len()] - o);
    }
    let Some(n) = nrm.normalized() else {
        return Err(p.invalid(name, "is degenerate (zero area)"));
    };
    let size = v.iter().map(|&x| (x - o).length()).fold(0.0, f64::max);
    for &x in v {
        if n.dot(x - o).abs() > 1e-9 * size {
            return Err(p.invalid(name, "must be planar"));
        }
    }
    Ok(())
}

/// Refuses a point in the plane of the planar polygon `v` and inside it or on its
/// boundary (within 1e-12 of the polygon's size from the plane): the solid angle jumps
/// there between 2π (just off the plane) and 0 (the plane itself), and the forms
/// disagreed (the polygon gave 0, the triangle and rectangle 2π). Inside is a winding
/// angle Σ atan2(n·(a × b), a·b) over the edges (a, b from the point to their ends) of
/// magnitude ≥ π/2 (2π inside, π on an edge, 0 outside).
fn check_off_polygon(p: &Params<'_>, x: Vec3, v: &[Vec3]) -> Result<()> {
    let o = v[0];
    let mut nrm = Vec3::default();
    for i in 0..v.len() {
        nrm = nrm + (v[i] - o).cross(v[(i + 1) % v.len()] - o);
    }
    let Some(n) = nrm.normalized() else {
        return Ok(());
    };
    let size = v.iter().map(|&y| (y - o).length()).fold(0.0, f64::max);
    if n.dot(x - o).abs() > 1e-12 * size {
        return Ok(());
    }
    let mut winding = 0.0;
    for i in 0..v.len() {
        let (a, b) = (v[i] - x, v[(i + 1) % v.len()] - x);
        if a.length() == 0.0 {
            winding = PI;
            break;
        }
        winding += n.dot(a.cross(b)).atan2(a.dot(b));
    }
    if winding.abs() >= 0.5 * PI {
        return Err(p.domain(
            "the point lies on the emitter (in its plane, inside it or on its boundary), \
             where the solid angle jumps between 2π and 0",
        ));
    }
    Ok(())
}

struct Entry {
    info: ClosedFormInfo,
    eval: fn(&Params<'_>) -> Result<f64>,
}

macro_rules! entry {
    ($name:literal, [$($p:literal),*], $desc:literal, $eval:expr) => {
        Entry {
            info: ClosedFormInfo { name: $name, params: &[$($p),*], description: $desc },
            eval: $eval,
        }
    };
}

fn outside_sphere(p: &Params<'_>, point: Vec3, center: Vec3, radius: f64) -> Result<()> {
    if (center - point).length() <= radius {
        Err(p.domain("the point must lie outside the sphere"))
    } else {
        Ok(())
    }
}

/// A number of scatterings: an integer in [0, 65536].
fn bounces(p: &Params<'_>) -> Result<u32> {
    let k = p.range("bounces", 0.0, 65536.0, false)?;
    if k.fract() != 0.0 {
        return Err(p.invalid("bounces", format!("must be a whole number, got {k}")));
    }
    Ok(k as u32)
}

/// A cap's polar half-angle given in degrees, returned in radians: in (0, 180], or
/// (0, 180) where the cap must leave a port.
fn cap_angle(p: &Params<'_>, name: &'static str, closed_ok: bool) -> Result<f64> {
    let t = p.num(name)?;
    let ok = t > 0.0 && if closed_ok { t <= 180.0 } else { t < 180.0 };
    if ok {
        Ok(t.to_radians())
    } else {
        let hi = if closed_ok { "180]" } else { "180)" };
        Err(p.invalid(name, format!("must lie in (0, {hi} degrees, got {t}")))
    }
}

/// Le, ρ and the port fraction f = cos²(θmax/2) of an integrating sphere whose wall is a
/// cap; f > 0, so the balance's denominator (1 − ρ) + ρ f is positive (evaluated in that
/// form: 1 − ρ(1 − f) rounds to 0 at ρ = 1 and θmax within 10⁻⁸ degrees of 180).
fn integrating_sphere_cap(p: &Params<'_>) -> Result<(f64, f64, f64)> {
    let le = p.non_negative("emitted_radiance")?;
    let rho = p.range("albedo", 0.0, 1.0, false)?;
    cap_angle(p, "wall_theta_max_degrees", false)?;
    let t = p.num("wall_theta_max_degrees")?;
    Ok((le, rho, partial_shapes::port_fraction_of_cap_degrees(t)))
}

/// The distribution, masking, α and cos θo ∈ (0, 1] of a rough mirror's albedo.
fn rough_mirror(p: &Params<'_>) -> Result<(Distribution, Masking, f64, f64)> {
    let (d, a) = (p.distribution()?, p.alpha()?);
    let m = p.masking()?;
    let c = p.range("cos_theta", 0.0, 1.0, false)?;
    if c == 0.0 {
        return Err(p.invalid(
            "cos_theta",
            "must be > 0 (the albedo at exactly grazing is a limit)",
        ));
    }
    Ok((d, m, a, c))
}

/// Inner and outer radii of an annulus: 0 ≤ r < R.
fn annulus_radii(p: &Params<'_>) -> Result<(f64, f64)> {
    let (r, big_r) = (p.non_negative("inner_radius")?, p.positive("outer_radius")?);
    if r >= big_r {
        return Err(p.domain(format!(
            "inner_radius {r} must be smaller than outer_radius {big_r}"
        )));
    }
    Ok((r, big_r))
}

static ENTRIES: &[Entry] = &[
    // ---- solid angles ----
    entry!(
        "solid_angle_cap",
        ["half_angle"],
        "solid angle (sr) of a cone of half-angle half_angle (rad, in [0, π])",
        |p| { Ok(solid_angle::cap(p.range("half_angle", 0.0, PI, false)?)) }
    ),
    entry!(
        "solid_angle_sphere",
        ["point", "center", "radius"],
        "solid angle (sr) of a sphere seen from an outside point",
        |p| {
            let (x, c, r) = (p.point("point")?, p.point("center")?, p.positive("radius")?);
            outside_sphere(p, x, c, r)?;
            Ok(solid_angle::sphere_from_point(x, c, r))
        }
    ),
    entry!(
        "solid_angle_triangle",
        ["point", "vertices"],
        "solid angle (sr) of a triangle (3 vertices) seen from a point (Van Oosterom–Strackee)",
        |p| {
            let (x, v) = (p.point("point")?, p.points("vertices", 3)?);
            if v.len() != 3 {
                return Err(p.invalid(
                    "vertices",
                    format!("must be exactly 3 points, got {}", v.len()),
                ));
            }
            check_planar(p, "vertices", &v)?;
            check_off_polygon(p, x, &v)?;
            Ok(solid_angle::triangle(x, v[0], v[1], v[2]))
        }
    ),
    entry!(
        "solid_angle_polygon",
        ["point", "vertices"],
        "solid angle (sr) of a planar simple polygon seen from a point",
        |p| {
            let (x, v) = (p.point("point")?, p.points("vertices", 3)?);
            check_planar(p, "vertices", &v)?;
            check_off_polygon(p, x, &v)?;
            Ok(solid_angle::polygon(x, &v))
        }
    ),
    entry!(
        "solid_angle_rectangle",
        ["point", "corner", "edge_u", "edge_v"],
        "solid angle (sr) of the rectangle corner + s·edge_u + t·edge_v (s, t ∈ [0,1], edges perpendicular) seen from a point",
        |p| {
            let (x, c, u, v) = (
                p.point("point")?,
                p.point("corner")?,
                p.point("edge_u")?,
                p.point("edge_v")?,
            );
            if u.length() == 0.0
                || v.length() == 0.0
                || u.dot(v).abs() > 1e-9 * u.length() * v.length()
            {
                return Err(p.domain("edge_u and edge_v must be non-zero and perpendicular"));
            }
            check_off_polygon(p, x, &[c, c + u, c + u + v, c + v])?;
            Ok(solid_angle::rectangle(x, c, u, v))
        }
    ),
    // ---- irradiance ----
    entry!(
        "polygon_irradiance",
        ["point", "normal", "vertices", "radiance"],
        "irradiance (W/m²) at point/normal from a uniform Lambertian planar polygon of radiance (W/(m²·sr)), clipped to the receiver's hemisphere (Lambert)",
        |p| {
            let (x, n, v, l) = (
                p.point("point")?,
                p.direction("normal")?,
                p.points("vertices", 3)?,
                p.non_negative("radiance")?,
            );
            check_planar(p, "vertices", &v)?;
            Ok(irradiance::polygon(x, n, &v, l))
        }
    ),
    entry!(
        "polygon_projected_solid_angle",
        ["point", "normal", "vertices"],
        "projected solid angle (sr) ∫max(0, n·ω)dω of a planar polygon seen from point/normal",
        |p| {
            let (x, n, v) = (
                p.point("point")?,
                p.direction("normal")?,
                p.points("vertices", 3)?,
            );
            check_planar(p, "vertices", &v)?;
            Ok(irradiance::polygon_projected_solid_angle(x, n, &v))
        }
    ),
    entry!(
        "disk_irradiance_on_axis",
        ["radius", "height", "radiance"],
        "irradiance (W/m²) on the axis of a uniform disk facing the receiver: π L R²/(R²+h²)",
        |p| {
            Ok(irradiance::disk_on_axis(
                p.positive("radius")?,
                p.positive("height")?,
                p.non_negative("radiance")?,
            ))
        }
    ),
    entry!(
        "disk_irradiance_parallel_offset",
        ["radius", "height", "offset", "radiance"],
        "irradiance (W/m²) from a uniform disk on a receiver parallel to it, at height above its plane and offset (m) from its axis",
        |p| {
            Ok(irradiance::disk_parallel_offset(
                p.positive("radius")?,
                p.positive("height")?,
                p.non_negative("offset")?,
                p.non_negative("radiance")?,
            ))
        }
    ),
    entry!(
        "disk_irradiance",
        ["point", "normal", "center", "axis", "radius", "radiance"],
        "irradiance (W/m²) at point/normal (any tilt, horizon clipping included) from a uniform two-sided disk (center, axis, radius)",
        |p| {
            let (x, n, c, m) = (
                p.point("point")?,
                p.direction("normal")?,
                p.point("center")?,
                p.direction("axis")?,
            );
            let (r, l) = (p.positive("radius")?, p.non_negative("radiance")?);
            let w = x - c;
            let h = w.dot(m);
            if h.abs() <= 1e-12 * r && (w - m * h).length() <= r {
                return Err(p.domain("the point lies on the disk"));
            }
            Ok(irradiance::disk(x, n, c, m, r, l))
        }
    ),
    entry!(
        "sphere_irradiance",
        ["point", "normal", "center", "radius", "radiance"],
        "irradiance (W/m²) at point/normal (any tilt, horizon clipping included) from a uniform sphere (Snyder 1996)",
        |p| {
            let (x, n, c) = (
                p.point("point")?,
                p.direction("normal")?,
                p.point("center")?,
            );
            let (r, l) = (p.positive("radius")?, p.non_negative("radiance")?);
            outside_sphere(p, x, c, r)?;
            Ok(irradiance::sphere(x, n, c, r, l))
        }
    ),
    entry!(
        "spherical_cap_irradiance",
        [
            "point",
            "normal",
            "center",
            "axis",
            "radius",
            "theta_max_degrees",
            "radiance"
        ],
        "irradiance (W/m²) at point/normal (any tilt, horizon clipping included), outside the sphere, from the outer side of a uniform Lambertian spherical cap: the part of the sphere (center, radius) within θmax (degrees, (0, 180]) of axis; contour integral",
        |p| {
            let (x, n, c, m) = (
                p.point("point")?,
                p.direction("normal")?,
                p.point("center")?,
                p.direction("axis")?,
            );
            let r = p.positive("radius")?;
            let t = cap_angle(p, "theta_max_degrees", true)?;
            let l = p.non_negative("radiance")?;
            if (x - c).length() <= r * (1.0 + 1e-12) {
                return Err(p.domain(
                    "the point must lie strictly outside the sphere (|point − center| > radius·(1 + 1e-12)); \
                     on it the cap's irradiance jumps, inside it the outer side is out of sight",
                ));
            }
            Ok(irradiance::spherical_cap(x, n, c, m, r, t, l))
        }
    ),
    entry!(
        "point_light_irradiance",
        ["point", "normal", "light", "intensity"],
        "irradiance (W/m²) from an isotropic point light of intensity (W/sr): I cos θ / r²",
        |p| {
            let (x, n, s, i) = (
                p.point("point")?,
                p.direction("normal")?,
                p.point("light")?,
                p.non_negative("intensity")?,
            );
            if s == x {
                return Err(p.domain("the light coincides with the receiver"));
            }
            Ok(irradiance::point(x, n, s, i))
        }
    ),
    entry!(
        "spot_light_irradiance",
        [
            "point",
            "normal",
            "light",
            "axis",
            "intensity",
            "cone_angle_degrees",
            "falloff_start_degrees"
        ],
        "irradiance (W/m²) from a spot light of intensity I (W/sr) on its axis with pbrt-v4's smoothstep falloff from falloff_start to cone_angle: I s(θ) cos θr / r²",
        |p| {
            let (x, n, s, a, i) = (
                p.point("point")?,
                p.direction("normal")?,
                p.point("light")?,
                p.direction("axis")?,
                p.non_negative("intensity")?,
            );
            let (total, start) = p.spot_angles()?;
            if s == x {
                return Err(p.domain("the light coincides with the receiver"));
            }
            Ok(irradiance::spot(x, n, s, a, i, total, start))
        }
    ),
    entry!(
        "constant_environment_irradiance",
        ["radiance"],
        "irradiance (W/m²) from a constant environment of radiance L: π L",
        |p| {
            Ok(irradiance::constant_environment(
                p.non_negative("radiance")?,
            ))
        }
    ),
    // ---- view factors ----
    entry!(
        "view_factor_element_to_coaxial_disk",
        ["radius", "height"],
        "view factor (1) from a differential element to a parallel coaxial disk: R²/(R²+h²)",
        |p| {
            Ok(view_factor::element_to_coaxial_disk(
                p.positive("radius")?,
                p.positive("height")?,
            ))
        }
    ),
    entry!(
        "view_factor_disk_to_coaxial_disk",
        ["radius1", "radius2", "height"],
        "view factor (1) from disk 1 to a parallel coaxial disk 2 at distance height (Howell C-41)",
        |p| {
            Ok(view_factor::disk_to_coaxial_disk(
                p.positive("radius1")?,
                p.positive("radius2")?,
                p.positive("height")?,
            ))
        }
    ),
    entry!(
        "view_factor_parallel_rectangles",
        ["width", "length", "separation"],
        "view factor (1) between identical directly opposed parallel width × length rectangles at distance separation (Howell C-11)",
        |p| {
            Ok(view_factor::parallel_rectangles(
                p.positive("width")?,
                p.positive("length")?,
                p.positive("separation")?,
            ))
        }
    ),
    entry!(
        "view_factor_perpendicular_rectangles",
        ["common_edge", "width", "height"],
        "view factor (1) from rectangle common_edge × width to perpendicular rectangle common_edge × height sharing the edge (Howell C-14)",
        |p| {
            Ok(view_factor::perpendicular_rectangles(
                p.positive("common_edge")?,
                p.positive("width")?,
                p.positive("height")?,
            ))
        }
    ),
    entry!(
        "view_factor_element_to_sphere",
        ["distance", "radius"],
        "view factor (1) from an element facing a sphere's centre at distance: (R/d)²",
        |p| {
            let (d, r) = (p.positive("distance")?, p.positive("radius")?);
            if d <= r {
                return Err(p.domain("distance must exceed radius"));
            }
            Ok(view_factor::element_to_sphere(d, r))
        }
    ),
    entry!(
        "view_factor_element_to_sphere_tilted",
        ["distance", "radius", "tilt"],
        "view factor (1) from an element whose normal is tilted (rad, [0, π]) from the direction to a sphere's centre",
        |p| {
            let (d, r, t) = (
                p.positive("distance")?,
                p.positive("radius")?,
                p.range("tilt", 0.0, PI, false)?,
            );
            if d <= r {
                return Err(p.domain("distance must exceed radius"));
            }
            Ok(view_factor::element_to_sphere_tilted(d, r, t))
        }
    ),
    entry!(
        "view_factor_sphere_wall_to_cap",
        ["theta_max_degrees"],
        "view factor (1) from any part of a sphere's inner wall to a cap of the same sphere of half-angle θmax (degrees, (0, 180]): (1 − cos θmax)/2",
        |p| {
            Ok(view_factor::sphere_wall_to_cap(cap_angle(
                p,
                "theta_max_degrees",
                true,
            )?))
        }
    ),
    // ---- furnace ----
    entry!(
        "furnace_closed_enclosure",
        ["emitted_radiance", "albedo"],
        "radiance (W/(m²·sr)) inside a closed diffuse enclosure: Le/(1−ρ), albedo in [0, 1)",
        |p| {
            Ok(furnace::closed_enclosure(
                p.non_negative("emitted_radiance")?,
                p.range("albedo", 0.0, 1.0, true)?,
            ))
        }
    ),
    entry!(
        "furnace_convex_object",
        ["albedo", "radiance"],
        "radiance (W/(m²·sr)) reflected by a convex Lambertian object under a constant environment: ρ L",
        |p| {
            Ok(furnace::convex_object(
                p.range("albedo", 0.0, 1.0, false)?,
                p.non_negative("radiance")?,
            ))
        }
    ),
    entry!(
        "dielectric_furnace_irradiance",
        ["radiance", "index_at_receiver"],
        "irradiance (W/m²) beside or inside a lossless smooth dielectric sphere under a constant environment of radiance L: π n² L, n the index at the receiver (1 beside the sphere; η inside, within R/η of its centre)",
        |p| {
            Ok(furnace::dielectric_furnace_irradiance(
                p.non_negative("radiance")?,
                p.positive("index_at_receiver")?,
            ))
        }
    ),
    entry!(
        "furnace_integrating_sphere",
        ["emitted_radiance", "albedo", "port_fraction"],
        "wall radiance (W/(m²·sr)) of an emitting integrating sphere with a black port: Le/(1−ρ(1−f))",
        |p| {
            let (le, rho, f) = (
                p.non_negative("emitted_radiance")?,
                p.range("albedo", 0.0, 1.0, false)?,
                p.range("port_fraction", 0.0, 1.0, false)?,
            );
            if rho * (1.0 - f) >= 1.0 {
                return Err(p.domain("albedo = 1 with no port never reaches equilibrium"));
            }
            Ok(furnace::integrating_sphere(le, rho, f))
        }
    ),
    // ---- partial sums and partial shapes ----
    entry!(
        "furnace_closed_enclosure_bounces",
        ["emitted_radiance", "albedo", "bounces"],
        "radiance (W/(m²·sr)) inside a closed diffuse enclosure with paths cut after `bounces` scatterings: Le(1−ρ^{k+1})/(1−ρ), albedo in [0, 1]",
        |p| {
            Ok(partial_shapes::closed_enclosure_bounces(
                p.non_negative("emitted_radiance")?,
                p.range("albedo", 0.0, 1.0, false)?,
                bounces(p)?,
            ))
        }
    ),
    entry!(
        "furnace_integrating_sphere_cap",
        ["emitted_radiance", "albedo", "wall_theta_max_degrees"],
        "wall radiance (W/(m²·sr)) of an integrating sphere whose emitting diffuse wall is the cap of half-angle θmax (degrees, (0, 180)), the rest a black port: Le/(1−ρ(1−f)), f = cos²(θmax/2)",
        |p| {
            let (le, rho, f) = integrating_sphere_cap(p)?;
            Ok(furnace::integrating_sphere(le, rho, f))
        }
    ),
    entry!(
        "furnace_integrating_sphere_cap_bounces",
        [
            "emitted_radiance",
            "albedo",
            "wall_theta_max_degrees",
            "bounces"
        ],
        "the same wall radiance (W/(m²·sr)) with paths cut after `bounces` scatterings: Le Σ_{j≤k} (ρ(1−f))^j",
        |p| {
            let (le, rho, f) = integrating_sphere_cap(p)?;
            Ok(partial_shapes::integrating_sphere_bounces(
                le,
                rho,
                f,
                bounces(p)?,
            ))
        }
    ),
    entry!(
        "annulus_irradiance_on_axis",
        ["inner_radius", "outer_radius", "height", "radiance"],
        "irradiance (W/m²) on the axis of a uniform annulus facing the receiver: π L h²(R²−r²)/((R²+h²)(r²+h²))",
        |p| {
            let (r, big_r) = annulus_radii(p)?;
            Ok(partial_shapes::annulus_irradiance_on_axis(
                r,
                big_r,
                p.positive("height")?,
                p.non_negative("radiance")?,
            ))
        }
    ),
    entry!(
        "annulus_power",
        ["inner_radius", "outer_radius", "radiance"],
        "power (W) of a one-sided Lambertian annulus: π L · π(R²−r²)",
        |p| {
            let (r, big_r) = annulus_radii(p)?;
            Ok(partial_shapes::annulus_power(
                r,
                big_r,
                p.non_negative("radiance")?,
            ))
        }
    ),
    entry!(
        "spherical_cap_power",
        ["radius", "theta_max_degrees", "radiance"],
        "power (W) of a one-sided Lambertian spherical cap of polar half-angle θmax (degrees, (0, 180]): π L · 2πR²(1 − cos θmax)",
        |p| {
            Ok(partial_shapes::spherical_cap_power(
                p.positive("radius")?,
                cap_angle(p, "theta_max_degrees", true)?,
                p.non_negative("radiance")?,
            ))
        }
    ),
    entry!(
        "spherical_cap_irradiance_at_centre",
        ["theta_max_degrees", "radiance"],
        "irradiance (W/m²) at a sphere's centre, facing the axis, from the cap of half-angle θmax (degrees, (0, 180]) emitting inwards: π L sin² min(θmax, 90°)",
        |p| {
            Ok(partial_shapes::spherical_cap_irradiance_at_centre(
                cap_angle(p, "theta_max_degrees", true)?,
                p.non_negative("radiance")?,
            ))
        }
    ),
    // ---- Fresnel ----
    entry!(
        "fresnel_dielectric",
        ["cos_theta", "eta"],
        "unpolarised dielectric reflectance (1), TIR included; cos_theta in [−1, 1] (negative: from the other side), eta = n_t/n_i",
        |p| {
            Ok(fresnel::dielectric(
                p.range("cos_theta", -1.0, 1.0, false)?,
                p.positive("eta")?,
            ))
        }
    ),
    entry!(
        "fresnel_conductor",
        ["cos_theta", "eta", "k"],
        "unpolarised conductor reflectance (1) for complex index eta + i·k, cos_theta in [0, 1]",
        |p| {
            Ok(fresnel::conductor(
                p.range("cos_theta", 0.0, 1.0, false)?,
                p.positive("eta")?,
                p.non_negative("k")?,
            ))
        }
    ),
    entry!(
        "fresnel_dielectric_average",
        ["eta"],
        "cosine-weighted hemispherical average of the dielectric reflectance (1), light from index 1 into eta (eta < 1: from the denser side)",
        |p| { Ok(fresnel::dielectric_average(p.positive("eta")?)) }
    ),
    entry!(
        "fresnel_dielectric_average_inside",
        ["eta"],
        "cosine-weighted hemispherical average reflectance (1) from inside a medium of relative index eta ≥ 1: 1 − (1 − F̄_out)/η²",
        |p| {
            let eta = p.num("eta")?;
            if eta < 1.0 {
                return Err(p.invalid(
                    "eta",
                    format!("must be ≥ 1 (the inside is the denser medium), got {eta}"),
                ));
            }
            Ok(fresnel::dielectric_average_inside(eta))
        }
    ),
    // ---- microfacets ----
    entry!(
        "microfacet_normalisation",
        ["distribution", "alpha"],
        "∫ D(m) cos θm dm (1) of a GGX or Beckmann distribution (distribution \"ggx\" | \"beckmann\", alpha in [1e-4, 1]): 1 by definition, quadrature-checked",
        |p| {
            p.distribution()?;
            p.alpha()?;
            Ok(1.0)
        }
    ),
    entry!(
        "microfacet_projected_area",
        ["distribution", "alpha", "cos_theta"],
        "∫ ⟨ωo, m⟩⁺ D(m) dm = cos θo (1 + Λ(ωo)) (1), the microsurface's area projected towards ωo (Heitz 2014); cos_theta in [0, 1]",
        |p| {
            let (d, a) = (p.distribution()?, p.alpha()?);
            Ok(microfacet::projected_area(
                d,
                a,
                p.range("cos_theta", 0.0, 1.0, false)?,
            ))
        }
    ),
    entry!(
        "microfacet_visible_normalisation",
        ["distribution", "alpha", "cos_theta"],
        "∫ D_ωo(m) dm (1) of the visible normals G1(ωo) ⟨ωo, m⟩⁺ D(m)/cos θo: 1 (Heitz 2014, eq. 38); cos_theta in (0, 1]",
        |p| {
            p.distribution()?;
            p.alpha()?;
            let c = p.range("cos_theta", 0.0, 1.0, false)?;
            if c == 0.0 {
                return Err(p.invalid("cos_theta", "must be > 0 (D_ωo divides by cos θo)"));
            }
            Ok(1.0)
        }
    ),
    entry!(
        "microfacet_white_albedo",
        ["distribution", "masking", "alpha", "cos_theta"],
        "directional albedo (1) of a rough mirror with F ≡ 1 (weak white furnace: the single-scattering masking–shadowing loss), masking \"height_correlated\" | \"uncorrelated\"; 1 − ln 2 for GGX at alpha = 1, cos_theta = 1, quadrature elsewhere; cos_theta in (0, 1]",
        |p| {
            let (d, m, a, c) = rough_mirror(p)?;
            Ok(if d == Distribution::Ggx && a == 1.0 && c == 1.0 {
                microfacet::ggx_white_albedo_normal_alpha1()
            } else {
                microfacet::white_albedo(d, m, a, c)
            })
        }
    ),
    entry!(
        "microfacet_conductor_albedo",
        ["distribution", "masking", "alpha", "cos_theta", "eta", "k"],
        "directional albedo (1) of a rough conductor: the Cook–Torrance BRDF F(⟨ωo, h⟩) D G2/(4 cos θo cos θi) (Walter et al. 2007, eq. 20) with the conductor Fresnel of complex index eta + i·k, by quadrature over half vectors; distribution and masking as microfacet_white_albedo, cos_theta in (0, 1]",
        |p| {
            let (d, m, a, c) = rough_mirror(p)?;
            let (eta, k) = (p.positive("eta")?, p.non_negative("k")?);
            if eta == 1.0 && k == 0.0 {
                // A matched index reflects nothing: F ≡ 0 exactly, where the quadrature
                // would chase the rounding noise of F to its evaluation cap.
                return Ok(0.0);
            }
            Ok(microfacet::conductor_albedo(d, m, a, c, eta, k))
        }
    ),
    entry!(
        "microfacet_dielectric_albedo",
        ["distribution", "masking", "alpha", "cos_theta", "eta"],
        "directional albedo ∫ f |cos θi| dωi (1) over both hemispheres of a rough dielectric (Walter et al. 2007, eqs. 20–21: reflection F D G2/(4|cos θo cos θi|) plus transmission with the refraction Jacobian, radiance convention: transmitted radiance scaled by 1/η′²), eta = η_inside/η_outside with the inside below; cos_theta in [−1, 1], ≠ 0, negative from inside (η′ = 1/eta, total internal reflection included); eta in [0.1, 10], where the quadrature is validated; distribution and masking as microfacet_white_albedo, height_correlated meaning 1/(1 + Λo + Λi) for transmission too (pbrt-v4); quadrature over half vectors; the smooth limit is R + (1 − R)/η′²",
        |p| {
            let (d, m, a) = (p.distribution()?, p.masking()?, p.alpha()?);
            let c = p.range("cos_theta", -1.0, 1.0, false)?;
            if c == 0.0 {
                return Err(p.invalid(
                    "cos_theta",
                    "must be ≠ 0 (the albedo at exactly grazing is a limit; the sign says the side)",
                ));
            }
            // The validated range: beyond it the Fresnel kink from the denser side
            // (√(1 − 1/η²) > 0.995) squeezes the split pieces against normal incidence and
            // the quadrature's cost grows without bound (η = 30 from inside: over 20 s;
            // fuzzing found 10¹² taking minutes), where η ≤ 10 takes at most a few
            // seconds. Near η = 1 (1 + 10⁻⁷, 1.01, grazing) the tests bound it at 10⁸
            // integrand evaluations (7.2·10⁷ at most, 2–5 s; it took minutes before the
            // cancellation-free Fresnel forms and the quadrature's absolute floor).
            let eta = p.range("eta", 0.1, 10.0, false)?;
            Ok(microfacet::dielectric_albedo(d, m, a, c, eta))
        }
    ),
    // ---- Oren–Nayar ----
    entry!(
        "oren_nayar_classic_albedo",
        ["albedo", "sigma", "cos_theta"],
        "directional albedo (1) of the classic Oren–Nayar model (Oren & Nayar 1994; pbrt-v3), albedo in [0, 1], sigma (rad) in [0, π/2], cos_theta in [0, 1]",
        |p| {
            Ok(oren_nayar::albedo(
                Form::Classic,
                p.range("albedo", 0.0, 1.0, false)?,
                p.range("sigma", 0.0, PI / 2.0, false)?,
                p.range("cos_theta", 0.0, 1.0, false)?,
            ))
        }
    ),
    entry!(
        "oren_nayar_fujii_albedo",
        ["albedo", "sigma", "cos_theta"],
        "directional albedo (1) of Fujii's energy-conserving Oren–Nayar form (2012), albedo in [0, 1], sigma in [0, 1], cos_theta in [0, 1]",
        |p| {
            Ok(oren_nayar::albedo(
                Form::Fujii,
                p.range("albedo", 0.0, 1.0, false)?,
                p.range("sigma", 0.0, 1.0, false)?,
                p.range("cos_theta", 0.0, 1.0, false)?,
            ))
        }
    ),
    // ---- radiometry ----
    entry!(
        "lambertian_power",
        ["radiance", "area"],
        "power (W) leaving one side of a uniform Lambertian emitter: π L A",
        |p| {
            Ok(radiometry::lambertian_power(
                p.non_negative("radiance")?,
                p.positive("area")?,
            ))
        }
    ),
    entry!(
        "isotropic_point_power",
        ["intensity"],
        "power (W) of an isotropic point light of intensity I (W/sr): 4π I, the power crossing any closed surface around it",
        |p| {
            Ok(radiometry::isotropic_point_power(
                p.non_negative("intensity")?,
            ))
        }
    ),
    entry!(
        "spot_light_power",
        ["intensity", "cone_angle_degrees", "falloff_start_degrees"],
        "power (W) of a spot light of intensity I (W/sr) on its axis with pbrt-v4's smoothstep falloff: 2π I [(1 − cos θs) + (cos θs − cos θt)/2]",
        |p| {
            let i = p.non_negative("intensity")?;
            let (total, start) = p.spot_angles()?;
            Ok(radiometry::spot_light_power(i, total, start))
        }
    ),
    entry!(
        "lambertian_intensity",
        ["radiance", "area", "theta"],
        "intensity (W/sr) of a flat Lambertian emitter at angle theta (rad) from its normal: L A cos θ",
        |p| {
            Ok(radiometry::lambertian_intensity(
                p.non_negative("radiance")?,
                p.positive("area")?,
                p.range("theta", 0.0, PI, false)?,
            ))
        }
    ),
    entry!(
        "photon_energy",
        ["wavelength"],
        "energy (J) of a photon of vacuum wavelength (m): hc/λ",
        |p| { Ok(radiometry::photon_energy(p.positive("wavelength")?)) }
    ),
    entry!(
        "radiance_across_interface",
        ["radiance", "n1", "n2"],
        "radiance (W/(m²·sr)) after a lossless crossing from index n1 to n2: L (n2/n1)²",
        |p| {
            Ok(radiometry::radiance_across_interface(
                p.non_negative("radiance")?,
                p.positive("n1")?,
                p.positive("n2")?,
            ))
        }
    ),
    entry!(
        "radiance_at_dielectric_sphere_centre",
        ["radiance", "eta"],
        "radiance (W/(m²·sr)) seen from the centre of a smooth dielectric sphere of index eta looking at an emitter of radiance L, black behind: η² L/(1 + R₀)",
        |p| {
            Ok(radiometry::radiance_at_dielectric_sphere_centre(
                p.non_negative("radiance")?,
                p.positive("eta")?,
            ))
        }
    ),
    // ---- spectrum ----
    entry!(
        "planck_radiance",
        ["wavelength", "temperature"],
        "blackbody spectral radiance (W·sr⁻¹·m⁻³) at wavelength (m) and temperature (K)",
        |p| {
            Ok(spectrum::planck(
                p.positive("wavelength")?,
                p.positive("temperature")?,
            ))
        }
    ),
    entry!(
        "blackbody_total_radiance",
        ["temperature"],
        "total blackbody radiance (W/(m²·sr)): σT⁴/π",
        |p| { Ok(spectrum::total_radiance(p.positive("temperature")?)) }
    ),
    entry!(
        "blackbody_band_fraction",
        ["wavelength_min", "wavelength_max", "temperature"],
        "fraction (1) of blackbody emission between two wavelengths (m) at temperature (K)",
        |p| {
            let (a, b, t) = (
                p.positive("wavelength_min")?,
                p.positive("wavelength_max")?,
                p.positive("temperature")?,
            );
            if b < a {
                return Err(p.domain("wavelength_max must be ≥ wavelength_min"));
            }
            Ok(spectrum::band_fraction(a, b, t))
        }
    ),
    entry!(
        "blackbody_band_radiance",
        ["wavelength_min", "wavelength_max", "temperature"],
        "blackbody radiance (W/(m²·sr)) between two wavelengths (m): σT⁴/π · band fraction",
        |p| {
            let (a, b, t) = (
                p.positive("wavelength_min")?,
                p.positive("wavelength_max")?,
                p.positive("temperature")?,
            );
            if b < a {
                return Err(p.domain("wavelength_max must be ≥ wavelength_min"));
            }
            Ok(spectrum::band_radiance(a, b, t))
        }
    ),
    entry!(
        "wien_peak_wavelength",
        ["temperature"],
        "wavelength (m) of maximum blackbody spectral radiance: b/T",
        |p| { Ok(spectrum::wien_peak(p.positive("temperature")?)) }
    ),
    entry!(
        "blackbody_photon_radiance",
        ["temperature"],
        "total blackbody photon radiance (photons·s⁻¹·m⁻²·sr⁻¹): 4ζ(3)k³T³/(h³c²)",
        |p| { Ok(spectrum::photon_radiance(p.positive("temperature")?)) }
    ),
    entry!(
        "cauchy_index",
        ["a", "b", "wavelength_um"],
        "refractive index (1) by Cauchy's formula a + b/λ² (λ in µm, b in µm²); an index ≤ 0 is refused",
        |p| {
            let n = spectrum::cauchy(p.num("a")?, p.num("b")?, p.positive("wavelength_um")?);
            if n <= 0.0 {
                return Err(p.domain(format!(
                    "a + b/λ² = {n} is not a refractive index (must be > 0)"
                )));
            }
            Ok(n)
        }
    ),
    entry!(
        "sellmeier_index",
        ["b", "c", "wavelength_um"],
        "refractive index (1) by the 3-term Sellmeier formula, b = [B1,B2,B3], c = [C1,C2,C3] (µm²), λ in µm",
        |p| {
            let (b, c, l) = (p.triple("b")?, p.triple("c")?, p.positive("wavelength_um")?);
            let n = spectrum::sellmeier(&b, &c, l);
            if n.is_finite() {
                Ok(n)
            } else {
                Err(p.domain("wavelength lies on or inside an absorption pole (n² ≤ 0)"))
            }
        }
    ),
    entry!(
        "bk7_index",
        ["wavelength_um"],
        "refractive index (1) of Schott N-BK7 by its Sellmeier coefficients, λ in µm",
        |p| {
            Ok(spectrum::sellmeier(
                &spectrum::BK7_B,
                &spectrum::BK7_C,
                p.range("wavelength_um", 0.3, 2.5, false)?,
            ))
        }
    ),
    entry!(
        "slab_transmittance",
        ["index"],
        "normal-incidence transmittance (1) of a non-absorbing slab with incoherent inter-reflections: (1−R)/(1+R)",
        |p| { Ok(spectrum::slab_transmittance(p.positive("index")?)) }
    ),
    entry!(
        "bk7_slab_transmittance",
        ["wavelength_um"],
        "normal-incidence transmittance (1) of a non-absorbing N-BK7 slab at a wavelength (µm): (1−R)/(1+R) at n(λ)",
        |p| {
            Ok(spectrum::bk7_slab_transmittance(p.range(
                "wavelength_um",
                0.3,
                2.5,
                false,
            )?))
        }
    ),
    entry!(
        "bk7_slab_band_transmittance",
        ["wavelength_min_um", "wavelength_max_um"],
        "mean normal-incidence transmittance (1) of a non-absorbing N-BK7 slab over a band (µm), flat spectrum",
        |p| {
            let (a, b) = (
                p.range("wavelength_min_um", 0.3, 2.5, false)?,
                p.range("wavelength_max_um", 0.3, 2.5, false)?,
            );
            if b < a {
                return Err(p.domain("wavelength_max_um must be ≥ wavelength_min_um"));
            }
            Ok(spectrum::bk7_slab_band_transmittance(a, b))
        }
    ),
    entry!(
        "cauchy_slab_transmittance",
        ["a", "b", "wavelength_um"],
        "normal-incidence transmittance (1) of a non-absorbing slab with Cauchy index a + b/λ² at a wavelength (µm)",
        |p| {
            let n = spectrum::cauchy(p.num("a")?, p.num("b")?, p.positive("wavelength_um")?);
            if n > 0.0 {
                Ok(spectrum::slab_transmittance(n))
            } else {
                Err(p.domain("the Cauchy index must be positive"))
            }
        }
    ),
    // ---- time ----
    entry!(
        "pulsed_disk_on_axis",
        ["radius", "height", "radiance", "t1", "t2", "speed"],
        "irradiance (W/m²) on a uniform disk's axis carried by paths of travel time in [t1, t2] (s) at speed (m/s): π L h²(1/r1² − 1/r2²)",
        |p| {
            let (r, h, l) = (
                p.positive("radius")?,
                p.positive("height")?,
                p.non_negative("radiance")?,
            );
            let (t1, t2, v) = (
                p.non_negative("t1")?,
                p.non_negative("t2")?,
                p.positive("speed")?,
            );
            if t2 < t1 {
                return Err(p.domain("t2 must be ≥ t1"));
            }
            Ok(time::pulsed_disk_on_axis(r, h, l, t1, t2, v))
        }
    ),
    entry!(
        "mean_chord_length",
        ["volume", "surface_area"],
        "mean isotropic chord length (m) of a convex body: 4V/S",
        |p| {
            Ok(time::mean_chord_length(
                p.positive("volume")?,
                p.positive("surface_area")?,
            ))
        }
    ),
    entry!(
        "mean_chord_sphere",
        ["radius"],
        "mean isotropic chord length (m) of a sphere: 4R/3",
        |p| { Ok(time::mean_chord_sphere(p.positive("radius")?)) }
    ),
    entry!(
        "mean_chord_box",
        ["a", "b", "c"],
        "mean isotropic chord length (m) of an a × b × c box: 2abc/(ab+bc+ca)",
        |p| {
            Ok(time::mean_chord_box(
                p.positive("a")?,
                p.positive("b")?,
                p.positive("c")?,
            ))
        }
    ),
    entry!(
        "moving_sphere_light_average",
        ["radius", "radiance", "height", "x0", "speed", "t0", "t1"],
        "shutter-averaged irradiance (W/m²) at the origin (normal +z) from a uniform sphere (radius m, radiance) whose centre moves as (x0 + speed·t, 0, height), over [t0, t1] (s)",
        |p| {
            let (r, h) = (p.positive("radius")?, p.positive("height")?);
            if h <= r {
                return Err(p.domain("the sphere must stay above the receiver: height > radius"));
            }
            let (t0, t1) = (p.num("t0")?, p.num("t1")?);
            if t1 < t0 {
                return Err(p.domain("t1 must be ≥ t0"));
            }
            Ok(time::moving_sphere_light_average(
                r,
                p.non_negative("radiance")?,
                h,
                p.num("x0")?,
                p.num("speed")?,
                t0,
                t1,
            ))
        }
    ),
    entry!(
        "moving_point_light_average",
        ["intensity", "distance", "speed", "t0", "t1"],
        "shutter-averaged irradiance (W/m²) over [t0, t1] (s) from a point light (W/sr) passing at closest distance (m) with speed (m/s), t = 0 at closest approach, receiver facing the line",
        |p| {
            let (i, d, v) = (
                p.non_negative("intensity")?,
                p.positive("distance")?,
                p.non_negative("speed")?,
            );
            let (t0, t1) = (p.num("t0")?, p.num("t1")?);
            if t1 < t0 {
                return Err(p.domain("t1 must be ≥ t0"));
            }
            Ok(time::moving_point_light_average(i, d, v, t0, t1))
        }
    ),
];

fn find(name: &str) -> Option<&'static Entry> {
    ENTRIES.iter().find(|e| e.info.name == name)
}

fn expected(form: &str) -> String {
    find(form)
        .map(|e| e.info.params.join(", "))
        .unwrap_or_default()
}

/// Every registered closed form, in catalog order.
pub fn names() -> Vec<ClosedFormInfo> {
    ENTRIES.iter().map(|e| e.info).collect()
}

/// Evaluates the closed form `name` with parameters `params` (a `closed_form` key, if
/// present, is ignored).
pub fn evaluate(name: &str, params: &Map<String, Value>) -> std::result::Result<f64, CatalogError> {
    let entry = find(name).ok_or_else(|| CatalogError::UnknownClosedForm {
        name: name.to_string(),
        known: ENTRIES
            .iter()
            .map(|e| e.info.name)
            .collect::<Vec<_>>()
            .join(", "),
    })?;
    let form = entry.info.name;
    for key in params.keys() {
        if key != "closed_form" && !entry.info.params.contains(&key.as_str()) {
            return Err(CatalogError::UnknownParameter {
                form,
                param: key.clone(),
                expected: entry.info.params.join(", "),
            });
        }
    }
    let p = Params { form, map: params };
    let v = (entry.eval)(&p)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(p.domain(format!("the parameters give a non-finite result ({v})")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn obj(v: Value) -> Map<String, Value> {
        v.as_object().unwrap().clone()
    }

    #[test]
    fn design_example_evaluates() {
        let m = obj(
            json!({"closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1}),
        );
        let v = evaluate("disk_irradiance_on_axis", &m).unwrap();
        assert!((v - PI / 5.0).abs() < 1e-15);
    }

    /// Thin strips, distant and touching plates evaluate at any ratio (a 1e-9 × 1 strip
    /// 1 apart, once 0 for 2.5e-10, was refused beyond 10⁴ × min(width, length)), as do
    /// perpendicular rectangles with a side 10⁻²⁰⁰ or 10²⁰⁰ of the others (once a
    /// non-finite result) and coaxial disks at extreme ratios. References: mpmath at 50+
    /// digits of Howell's C-11 and C-14 as written (the commands in view_factor.rs's
    /// `*_at_extreme_ratios` tests).
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn view_factor_domains() {
        for (a, b, c, want) in [
            (1e-9, 1.0, 1.0, 2.5000000000000001549e-10),
            (1e-4, 1.0, 1.0, 2.4999999924237089692e-5),
            (1.0, 1.0, 1e150, 3.1830988618379068374e-301),
            (1e-200, 1e200, 1.0, 4.9999999999999999105e-201),
            (1.0, 2.0, 1e-300, 1.0),
            (1e-300, 1e-300, 1e-300, 0.19982489569838738304),
        ] {
            let v = evaluate(
                "view_factor_parallel_rectangles",
                &obj(json!({"width": a, "length": b, "separation": c})),
            )
            .unwrap();
            assert!((v / want - 1.0).abs() < 1e-13, "{a} {b} {c}: {v}");
        }
        for (l, w, h, want) in [
            (1.0, 1e-200, 1.0, 0.5),
            (1.0, 1.0, 1e-200, 4.9999999999999999105e-201),
            (1e-200, 1.0, 1.0, 7.3477133402542452880e-199),
            (1e200, 1.0, 1.0, 0.29289321881345247560),
            (1.0, 1e-300, 1e300, 0.5),
            (1e300, 1e-300, 3e-300, 0.41886116991581033825),
            (3.3e-300, 3.7e9, 3.3e10, 1.0122482188820601821e-307),
        ] {
            let v = evaluate(
                "view_factor_perpendicular_rectangles",
                &obj(json!({"common_edge": l, "width": w, "height": h})),
            )
            .unwrap();
            assert!((v / want - 1.0).abs() < 1e-13, "{l} {w} {h}: {v}");
        }
        // A true value below the f64 range is 0, not a non-finite-result error.
        for (name, params) in [
            (
                "view_factor_parallel_rectangles",
                json!({"width": 1e-300, "length": 1e300, "separation": 1e300}),
            ),
            (
                "view_factor_perpendicular_rectangles",
                json!({"common_edge": 1, "width": 1e300, "height": 1e-300}),
            ),
        ] {
            assert_eq!(evaluate(name, &obj(params)).unwrap(), 0.0, "{name}");
        }
        for (r1, h, want) in [(1e-80, 1.0, 0.5), (1.0, 1e-160, 1.0)] {
            let v = evaluate(
                "view_factor_disk_to_coaxial_disk",
                &obj(json!({"radius1": r1, "radius2": 1, "height": h})),
            )
            .unwrap();
            assert!((v - want).abs() < 1e-15, "{r1} {h}: {v}");
        }
        let v = evaluate(
            "view_factor_element_to_coaxial_disk",
            &obj(json!({"radius": 1e200, "height": 1e200})),
        )
        .unwrap();
        assert_eq!(v, 0.5);
    }

    /// The spherical cap's irradiance: the oracle's value through the catalog (degrees to
    /// radians, the axis and normal normalised), the whole sphere at 180° (Snyder), and
    /// its refusals: a point on or inside the sphere, or within 10⁻¹² R of it, is a
    /// domain error; θmax outside (0, 180] degrees names the parameter.
    #[test]
    fn spherical_cap_irradiance_through_the_catalog() {
        let cap = |point: Value, theta: Value| {
            evaluate(
                "spherical_cap_irradiance",
                &obj(
                    json!({"point": point, "normal": [0, 0.6, -2], "center": [1, 2, 3],
                    "axis": [0, 0, 3], "radius": 2, "theta_max_degrees": theta, "radiance": 1.5}),
                ),
            )
        };
        let v = cap(json!([1.4, 2, 7]), json!(60)).unwrap();
        let n = Vec3::new(0.0, 0.6, -2.0).normalized().unwrap();
        let want = irradiance::spherical_cap(
            Vec3::new(1.4, 2.0, 7.0),
            n,
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.0, 1.0),
            2.0,
            60f64.to_radians(),
            1.5,
        );
        assert!(v > 0.0 && v == want, "{v} vs {want}");
        let whole = cap(json!([1.4, 2, 7]), json!(180)).unwrap();
        let sphere = evaluate(
            "sphere_irradiance",
            &obj(
                json!({"point": [1.4, 2, 7], "normal": [0, 0.6, -2], "center": [1, 2, 3],
                "radius": 2, "radiance": 1.5}),
            ),
        )
        .unwrap();
        assert!(
            (whole - sphere).abs() <= 1e-12 * sphere,
            "{whole} vs {sphere}"
        );
        for point in [
            json!([1, 2, 5]),
            json!([1, 2, 4]),
            json!([1, 2, 3]),
            json!([1, 2, 5.000000000001]),
        ] {
            let e = cap(point.clone(), json!(60)).unwrap_err();
            assert!(matches!(e, CatalogError::Domain { .. }), "{point}: {e}");
            assert!(e.to_string().contains("outside the sphere"), "{e}");
        }
        assert!(cap(json!([1, 2, 5.00001]), json!(60)).unwrap() > 0.0);
        for theta in [json!(0), json!(-10), json!(180.5), json!(360)] {
            let e = cap(json!([1.4, 2, 7]), theta.clone()).unwrap_err();
            assert!(
                matches!(
                    e,
                    CatalogError::InvalidParameter {
                        param: "theta_max_degrees",
                        ..
                    }
                ),
                "{theta}: {e}"
            );
        }
    }

    /// A point in the emitter's plane: refused inside and on the boundary for all three
    /// polygon forms (they gave 0 and 2π), evaluated (0) outside; the sphere seen from
    /// 10²⁰⁰ away with R = 10¹⁹⁹ subtends 2π(1 − √0.99) ≈ 0.0315 (was 0); the
    /// integrating sphere at ρ = 1 and a port within 10⁻⁸ degrees of the whole sphere
    /// is finite (was ∞).
    #[test]
    fn solid_angle_and_furnace_edges() {
        let quad = json!([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]]);
        for (pt, inside) in [
            (json!([1, 1, 0]), true),
            (json!([2, 1, 0]), true),
            (json!([0, 0, 0]), true),
            (json!([3, 1, 0]), false),
        ] {
            let cases = [
                (
                    "solid_angle_polygon",
                    json!({"point": pt, "vertices": quad}),
                ),
                (
                    "solid_angle_triangle",
                    json!({"point": pt, "vertices": [[0, 0, 0], [2, 0, 0], [2, 2, 0]]}),
                ),
                (
                    "solid_angle_rectangle",
                    json!({"point": pt, "corner": [0, 0, 0], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0]}),
                ),
            ];
            for (name, params) in cases {
                let r = evaluate(name, &obj(params));
                if inside {
                    let e = r.unwrap_err();
                    assert!(matches!(e, CatalogError::Domain { .. }), "{name} {pt}: {e}");
                } else {
                    assert_eq!(r.unwrap(), 0.0, "{name} {pt}");
                }
            }
        }
        let v = evaluate(
            "solid_angle_sphere",
            &obj(json!({"point": [0, 0, 0], "center": [1e200, 0, 0], "radius": 1e199})),
        )
        .unwrap();
        let want = 2.0 * PI * (1.0 - 0.99f64.sqrt());
        assert!((v / want - 1.0).abs() < 1e-14, "{v} vs {want}");
        let v = evaluate(
            "furnace_integrating_sphere_cap",
            &obj(
                json!({"emitted_radiance": 1, "albedo": 1, "wall_theta_max_degrees": 179.99999999}),
            ),
        );
        // 1/cos²(θmax/2) at the f64 θmax, in 40-digit mpmath (session 40).
        let v = v.unwrap();
        assert!((v / 1.313_120_456_651_320_4e20 - 1.0).abs() < 1e-12, "{v}");
    }

    /// A tiny port's fraction is taken from 180° − θmax, exact in degrees: through
    /// radians, π − θmax rounded (2.5·10⁻¹¹ relative at 179.999°, 2.7·10⁻⁸ at
    /// 179.999999°). References: 1/cos²(θmax/2) at the f64 θmax, 40-digit mpmath.
    #[test]
    fn integrating_sphere_tiny_port_keeps_its_digits() {
        for (t, want) in [
            (179.999, 13_131_225_400.254_91),
            (179.999999, 1.313_122_546_635_329e16),
            (90.0, 2.0),
            (1e-6, 1.000_000_000_000_000_1),
        ] {
            let v = evaluate(
                "furnace_integrating_sphere_cap",
                &obj(json!({"emitted_radiance": 1, "albedo": 1, "wall_theta_max_degrees": t})),
            )
            .unwrap();
            assert!((v / want - 1.0).abs() < 1e-13, "θmax {t}: {v} vs {want}");
        }
    }

    /// Finite true values at extreme scales come out finite (they were "non-finite
    /// result" errors), and a Cauchy index ≤ 0 is refused (a = −5 returned −5).
    #[test]
    fn extreme_scales_and_cauchy_domain() {
        let v = evaluate(
            "disk_irradiance_on_axis",
            &obj(json!({"radius": 1e200, "height": 1e200, "radiance": 1})),
        )
        .unwrap();
        assert!((v - PI / 2.0).abs() < 1e-15, "{v}");
        let v = evaluate(
            "pulsed_disk_on_axis",
            &obj(
                json!({"radius": 1, "height": 1e-200, "radiance": 1, "t1": 0, "t2": 1, "speed": 1}),
            ),
        )
        .unwrap();
        assert!((v - PI).abs() < 1e-15, "{v}");
        // An interior bin: π h²(1/r₁² − 1/r₂²) with r = c t.
        let v = evaluate(
            "pulsed_disk_on_axis",
            &obj(json!({"radius": 2, "height": 1, "radiance": 1, "t1": 1.5, "t2": 2, "speed": 1})),
        )
        .unwrap();
        let want = PI * (1.0 / 2.25 - 0.25);
        assert!((v / want - 1.0).abs() < 1e-15, "{v} vs {want}");
        let e = evaluate(
            "cauchy_index",
            &obj(json!({"a": -5, "b": 0, "wavelength_um": 0.5})),
        )
        .unwrap_err();
        assert!(matches!(e, CatalogError::Domain { .. }), "{e}");
        // Huge and tiny indices: F̄ → 1 (η = 10^±80 were non-finite results).
        for (form, eta) in [
            ("fresnel_dielectric_average", 1e80),
            ("fresnel_dielectric_average", 1e-80),
            ("fresnel_dielectric_average", 1e300),
            ("fresnel_dielectric_average_inside", 1e80),
        ] {
            let v = evaluate(form, &obj(json!({ "eta": eta }))).unwrap();
            assert!(v > 0.999_999 && v <= 1.0, "{form} at {eta}: {v}");
        }
        // Planck's law far outside the visible: 0 where the true value underflows
        // (λ = 10⁻⁷⁰ was a non-finite result), 4.78·10⁻²⁹¹ at λ = 10⁷⁰ (was 0).
        let planck = |l: f64| {
            evaluate(
                "planck_radiance",
                &obj(json!({"wavelength": l, "temperature": 5778})),
            )
            .unwrap()
        };
        assert_eq!(planck(1e-70), 0.0);
        assert!((planck(1e70) / 4.783_122_666_281_616_5e-291 - 1.0).abs() < 2e-13);
    }

    #[test]
    fn errors_are_clear() {
        let e = evaluate("disk_irradiance_on_axe", &Map::new()).unwrap_err();
        assert!(matches!(e, CatalogError::UnknownClosedForm { .. }));
        assert!(e.to_string().contains("disk_irradiance_on_axe"));

        let e = evaluate(
            "disk_irradiance_on_axis",
            &obj(json!({"radius": 1, "radiance": 1})),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "closed form `disk_irradiance_on_axis`: missing parameter `height` (expects: radius, height, radiance)"
        );

        // JSON has no NaN: a case writing "NaN" gets a clear message.
        let e = evaluate(
            "disk_irradiance_on_axis",
            &obj(json!({"radius": "NaN", "height": 1, "radiance": 1})),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("`radius`") && e.to_string().contains("finite"),
            "{e}"
        );
        // A NaN smuggled in programmatically.
        let mut m = obj(json!({"height": 1, "radiance": 1}));
        m.insert("radius".into(), Value::from(f64::NAN)); // serde_json turns NaN into null
        let e = evaluate("disk_irradiance_on_axis", &m).unwrap_err();
        assert!(e.to_string().contains("`radius`"), "{e}");

        let e = evaluate(
            "disk_irradiance_on_axis",
            &obj(json!({"radius": -1, "height": 1, "radiance": 1})),
        )
        .unwrap_err();
        assert!(e.to_string().contains("must be > 0"), "{e}");

        let e = evaluate(
            "disk_irradiance_on_axis",
            &obj(json!({"radius": 1, "height": 1, "radiance": 1, "hieght": 2})),
        )
        .unwrap_err();
        assert!(
            matches!(e, CatalogError::UnknownParameter { .. }) && e.to_string().contains("hieght")
        );

        let e = evaluate(
            "solid_angle_sphere",
            &obj(json!({"point": [0, 0], "center": [0, 0, 5], "radius": 1})),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("`point`") && e.to_string().contains("[x, y, z]"),
            "{e}"
        );

        let e = evaluate(
            "solid_angle_sphere",
            &obj(json!({"point": [0, 0, 0], "center": [0, 0, 0.5], "radius": 1})),
        )
        .unwrap_err();
        assert!(matches!(e, CatalogError::Domain { .. }), "{e}");

        let e = evaluate(
            "furnace_closed_enclosure",
            &obj(json!({"emitted_radiance": 1, "albedo": 1})),
        )
        .unwrap_err();
        assert!(e.to_string().contains("`albedo`"), "{e}");

        // Named choices: a wrong one is named with the choices.
        let e = evaluate(
            "microfacet_white_albedo",
            &obj(json!({"distribution": "phong", "masking": "uncorrelated", "alpha": 0.5, "cos_theta": 0.5})),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("`distribution`") && e.to_string().contains("ggx, beckmann"),
            "{e}"
        );
        let e = evaluate(
            "microfacet_white_albedo",
            &obj(json!({"distribution": "ggx", "masking": 1, "alpha": 0.5, "cos_theta": 0.5})),
        )
        .unwrap_err();
        assert!(e.to_string().contains("`masking`"), "{e}");
        let e = evaluate(
            "microfacet_white_albedo",
            &obj(json!({"distribution": "ggx", "masking": "uncorrelated", "alpha": 0.5, "cos_theta": 0})),
        )
        .unwrap_err();
        assert!(e.to_string().contains("`cos_theta`"), "{e}");
        // The closed form at α = 1, normal incidence, and the quadrature next to it.
        let at = |c: f64| {
            evaluate(
                "microfacet_white_albedo",
                &obj(json!({"distribution": "ggx", "masking": "height_correlated", "alpha": 1, "cos_theta": c})),
            )
            .unwrap()
        };
        assert_eq!(at(1.0), 1.0 - std::f64::consts::LN_2);
        assert!((at(1.0 - 1e-12) - at(1.0)).abs() < 1e-8);

        // The rough conductor: its index is validated as `fresnel_conductor`'s, its mirror
        // parameters as `microfacet_white_albedo`'s.
        let rough = |eta: f64, k: f64, c: f64| {
            evaluate(
                "microfacet_conductor_albedo",
                &obj(
                    json!({"distribution": "ggx", "masking": "height_correlated", "alpha": 0.5, "cos_theta": c, "eta": eta, "k": k}),
                ),
            )
        };
        let e = rough(-0.2, 3.9, 0.5).unwrap_err();
        assert!(
            e.to_string().contains("`eta`") && e.to_string().contains("must be > 0"),
            "{e}"
        );
        let e = rough(0.2, -1.0, 0.5).unwrap_err();
        assert!(
            e.to_string().contains("`k`") && e.to_string().contains("must be ≥ 0"),
            "{e}"
        );
        let e = rough(0.2, 3.9, 0.0).unwrap_err();
        assert!(e.to_string().contains("`cos_theta`"), "{e}");
        let e = evaluate(
            "microfacet_conductor_albedo",
            &obj(json!({"distribution": "ggx", "masking": "correlated", "alpha": 0.5, "cos_theta": 0.5, "eta": 0.2, "k": 3.9})),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("`masking`")
                && e.to_string().contains("height_correlated, uncorrelated"),
            "{e}"
        );
        // Indices far beyond any metal (fuzzing's 10³⁰⁸; before, NaN Fresnel factors
        // made the nested quadrature bisect to its caps for over ten minutes): F ≈ 1, so
        // the white albedo; at |η̃| near f64::MAX the formula overflows and the result is
        // refused at once as non-finite.
        let white = evaluate(
            "microfacet_white_albedo",
            &obj(
                json!({"distribution": "ggx", "masking": "height_correlated", "alpha": 0.5, "cos_theta": 0.5}),
            ),
        )
        .unwrap();
        for (eta, k) in [(1e308, 0.5), (1.5, 1e308), (1e200, 1e200)] {
            let v = rough(eta, k, 0.5).unwrap();
            assert!(
                (v - white).abs() < 1e-12,
                "η = {eta}, k = {k}: {v} vs {white}"
            );
        }
        let e = rough(1.7e308, 1.7e308, 0.5).unwrap_err();
        assert!(e.to_string().contains("non-finite"), "{e}");
        // A matched index (η = 1, k = 0) reflects nothing; a conductor less than F ≡ 1.
        assert_eq!(rough(1.0, 0.0, 0.5).unwrap(), 0.0);
        let near = rough(1.01, 0.0, 0.5).unwrap();
        assert!(near > 0.0 && near < 1e-3, "{near}");
        let gold = rough(0.2, 3.9, 0.5).unwrap();
        let white = evaluate(
            "microfacet_white_albedo",
            &obj(json!({"distribution": "ggx", "masking": "height_correlated", "alpha": 0.5, "cos_theta": 0.5})),
        )
        .unwrap();
        assert!(gold > 0.8 * white && gold < white, "{gold} vs {white}");

        // The rough dielectric: cos θo signed (negative from inside, never 0), eta in
        // [0.1, 10],
        // mirror parameters as `microfacet_white_albedo`'s.
        let glass = |c: Value, eta: Value| {
            evaluate(
                "microfacet_dielectric_albedo",
                &obj(
                    json!({"distribution": "ggx", "masking": "height_correlated", "alpha": 0.5, "cos_theta": c, "eta": eta}),
                ),
            )
        };
        let e = glass(json!(0), json!(1.5)).unwrap_err();
        assert!(
            e.to_string().contains("`cos_theta`") && e.to_string().contains("≠ 0"),
            "{e}"
        );
        let e = glass(json!(-1.5), json!(1.5)).unwrap_err();
        assert!(
            e.to_string().contains("`cos_theta`") && e.to_string().contains("[-1, 1]"),
            "{e}"
        );
        // eta within its validated range [0.1, 10], ends included (fuzzing's 1.5·10¹²
        // took the quadrature minutes).
        for bad in [0.0, 0.0999, 10.001, 1.5e12] {
            let e = glass(json!(0.5), json!(bad)).unwrap_err();
            assert!(
                e.to_string().contains("`eta`") && e.to_string().contains("[0.1, 10]"),
                "{bad}: {e}"
            );
        }
        // Both ends seen from the rarer side (from the denser side each takes seconds).
        for (c, ok) in [(-0.5, 0.1), (0.5, 10.0)] {
            assert!(glass(json!(c), json!(ok)).is_ok(), "{ok}");
        }
        let e = glass(json!(0.5), json!("glass")).unwrap_err();
        assert!(e.to_string().contains("`eta`"), "{e}");
        let e = evaluate(
            "microfacet_dielectric_albedo",
            &obj(json!({"distribution": "ggx", "masking": "smith", "alpha": 0.5, "cos_theta": 0.5, "eta": 1.5})),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("`masking`")
                && e.to_string().contains("height_correlated, uncorrelated"),
            "{e}"
        );
        let e = evaluate(
            "microfacet_dielectric_albedo",
            &obj(json!({"distribution": "ggx", "masking": "uncorrelated", "alpha": 0, "cos_theta": 0.5, "eta": 1.5})),
        )
        .unwrap_err();
        assert!(e.to_string().contains("`alpha`"), "{e}");
        // Inside is below: from inside the relative index is 1/eta, the same albedo as
        // from outside a boundary of index 1/eta.
        let inside = glass(json!(-0.5), json!(1.5)).unwrap();
        assert_eq!(inside, glass(json!(0.5), json!(1.0 / 1.5)).unwrap());
        // From outside it carries less than 1 (1/η² on the transmitted radiance), from
        // inside at normal incidence more (η² on it).
        let outside = glass(json!(0.5), json!(1.5)).unwrap();
        assert!(outside > 0.3 && outside < 0.6, "{outside}");
        let up = glass(json!(-1), json!(1.5)).unwrap();
        assert!(up > 1.5 && up < 2.25, "{up}");
    }

    #[test]
    fn every_form_has_unique_name_and_evaluates_on_sample_input() {
        let infos = names();
        let mut seen = std::collections::HashSet::new();
        for i in &infos {
            assert!(seen.insert(i.name), "duplicate {}", i.name);
            assert!(!i.description.is_empty());
        }
        let samples: Value = serde_json::from_str(
            r#"{
            "solid_angle_cap": {"half_angle": 0.5},
            "solid_angle_sphere": {"point": [1e5, 1e5, 1e5], "center": [1e5, 1e5, 100003.0], "radius": 1},
            "solid_angle_triangle": {"point": [0, 0, 0], "vertices": [[0, 0, 1], [1, 0, 1], [0, 1, 1]]},
            "solid_angle_polygon": {"point": [0, 0, 0], "vertices": [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]},
            "solid_angle_rectangle": {"point": [0, 0, 0], "corner": [0, 0, 1], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0]},
            "polygon_irradiance": {"point": [0, 0, 0], "normal": [0, 0, 1], "vertices": [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], "radiance": 1},
            "polygon_projected_solid_angle": {"point": [0, 0, 0], "normal": [0, 0, 1], "vertices": [[0, 0, 1], [1, 0, 1], [1, 1, 1]]},
            "disk_irradiance_on_axis": {"radius": 1, "height": 2, "radiance": 1},
            "disk_irradiance_parallel_offset": {"radius": 1, "height": 2, "offset": 0.5, "radiance": 1},
            "disk_irradiance": {"point": [0, 0, 0], "normal": [1, 0, 0.2], "center": [0, 0, 1], "axis": [0, 0, 1], "radius": 1, "radiance": 1},
            "sphere_irradiance": {"point": [0, 0, 0], "normal": [0, 1, 0], "center": [0, 0, 3], "radius": 1, "radiance": 1},
            "spherical_cap_irradiance": {"point": [0.2, 0, 2], "normal": [0, 0.3, -1], "center": [0, 0, 0], "axis": [0, 0, 1], "radius": 1, "theta_max_degrees": 60, "radiance": 1},
            "point_light_irradiance": {"point": [0, 0, 0], "normal": [0, 0, 1], "light": [0, 0, 2], "intensity": 4},
            "spot_light_irradiance": {"point": [0.5, 0, 0], "normal": [0, 0, 1], "light": [0, 0, 2], "axis": [0, 0, -1], "intensity": 4, "cone_angle_degrees": 30, "falloff_start_degrees": 10},
            "constant_environment_irradiance": {"radiance": 1},
            "view_factor_element_to_coaxial_disk": {"radius": 1, "height": 1},
            "view_factor_disk_to_coaxial_disk": {"radius1": 1, "radius2": 1, "height": 1},
            "view_factor_parallel_rectangles": {"width": 1, "length": 1, "separation": 1},
            "view_factor_perpendicular_rectangles": {"common_edge": 1, "width": 1, "height": 1},
            "view_factor_element_to_sphere": {"distance": 2, "radius": 1},
            "view_factor_element_to_sphere_tilted": {"distance": 2, "radius": 1, "tilt": 1.5},
            "view_factor_sphere_wall_to_cap": {"theta_max_degrees": 120},
            "furnace_closed_enclosure": {"emitted_radiance": 1, "albedo": 0.5},
            "furnace_convex_object": {"albedo": 0.5, "radiance": 1},
            "dielectric_furnace_irradiance": {"radiance": 1, "index_at_receiver": 1.5},
            "furnace_integrating_sphere": {"emitted_radiance": 1, "albedo": 0.9, "port_fraction": 0.05},
            "furnace_closed_enclosure_bounces": {"emitted_radiance": 1, "albedo": 0.8, "bounces": 2},
            "furnace_integrating_sphere_cap": {"emitted_radiance": 1, "albedo": 0.9, "wall_theta_max_degrees": 170},
            "furnace_integrating_sphere_cap_bounces": {"emitted_radiance": 1, "albedo": 0.9, "wall_theta_max_degrees": 170, "bounces": 1},
            "annulus_irradiance_on_axis": {"inner_radius": 0.5, "outer_radius": 1, "height": 2, "radiance": 1},
            "annulus_power": {"inner_radius": 0.5, "outer_radius": 1, "radiance": 1},
            "spherical_cap_power": {"radius": 1, "theta_max_degrees": 60, "radiance": 1},
            "spherical_cap_irradiance_at_centre": {"theta_max_degrees": 60, "radiance": 1},
            "fresnel_dielectric": {"cos_theta": 0.5, "eta": 1.5},
            "fresnel_conductor": {"cos_theta": 0.5, "eta": 0.2, "k": 3},
            "fresnel_dielectric_average": {"eta": 1.5},
            "fresnel_dielectric_average_inside": {"eta": 1.5},
            "lambertian_power": {"radiance": 1, "area": 2},
            "isotropic_point_power": {"intensity": 2},
            "spot_light_power": {"intensity": 2, "cone_angle_degrees": 40, "falloff_start_degrees": 25},
            "lambertian_intensity": {"radiance": 1, "area": 2, "theta": 0.5},
            "photon_energy": {"wavelength": 5.5e-7},
            "radiance_across_interface": {"radiance": 1, "n1": 1, "n2": 1.5},
            "radiance_at_dielectric_sphere_centre": {"radiance": 1, "eta": 1.5},
            "planck_radiance": {"wavelength": 5e-7, "temperature": 5778},
            "blackbody_total_radiance": {"temperature": 5778},
            "blackbody_band_radiance": {"wavelength_min": 3.8e-7, "wavelength_max": 7.8e-7, "temperature": 5778},
            "bk7_slab_transmittance": {"wavelength_um": 0.55},
            "bk7_slab_band_transmittance": {"wavelength_min_um": 0.4, "wavelength_max_um": 0.7},
            "cauchy_slab_transmittance": {"a": 1.5046, "b": 0.0042, "wavelength_um": 0.55},
            "moving_sphere_light_average": {"radius": 0.3, "radiance": 2, "height": 1.5, "x0": -1, "speed": 2, "t0": 0, "t1": 1},
            "blackbody_band_fraction": {"wavelength_min": 3.8e-7, "wavelength_max": 7.8e-7, "temperature": 5778},
            "wien_peak_wavelength": {"temperature": 5778},
            "blackbody_photon_radiance": {"temperature": 5778},
            "cauchy_index": {"a": 1.5046, "b": 0.0042, "wavelength_um": 0.55},
            "sellmeier_index": {"b": [1.03961212, 0.231792344, 1.01046945], "c": [0.00600069867, 0.0200179144, 103.560653], "wavelength_um": 0.58756},
            "bk7_index": {"wavelength_um": 0.58756},
            "slab_transmittance": {"index": 1.5},
            "pulsed_disk_on_axis": {"radius": 1, "height": 2, "radiance": 1, "t1": 0, "t2": 1, "speed": 1},
            "mean_chord_length": {"volume": 1, "surface_area": 6},
            "mean_chord_sphere": {"radius": 1},
            "mean_chord_box": {"a": 1, "b": 2, "c": 3},
            "moving_point_light_average": {"intensity": 1, "distance": 1, "speed": 1, "t0": -1, "t1": 1},
            "microfacet_normalisation": {"distribution": "ggx", "alpha": 0.3},
            "microfacet_projected_area": {"distribution": "beckmann", "alpha": 0.3, "cos_theta": 0.5},
            "microfacet_visible_normalisation": {"distribution": "ggx", "alpha": 0.3, "cos_theta": 0.5},
            "microfacet_white_albedo": {"distribution": "ggx", "masking": "uncorrelated", "alpha": 0.5, "cos_theta": 0.5},
            "microfacet_conductor_albedo": {"distribution": "beckmann", "masking": "height_correlated", "alpha": 0.3, "cos_theta": 0.5, "eta": 0.2, "k": 3.9},
            "microfacet_dielectric_albedo": {"distribution": "ggx", "masking": "uncorrelated", "alpha": 0.3, "cos_theta": -0.5, "eta": 1.5},
            "oren_nayar_classic_albedo": {"albedo": 0.8, "sigma": 0.3, "cos_theta": 0.5},
            "oren_nayar_fujii_albedo": {"albedo": 0.8, "sigma": 0.3, "cos_theta": 0.5}
        }"#,
        )
        .unwrap();
        let samples = samples.as_object().unwrap();
        for i in &infos {
            let m = samples
                .get(i.name)
                .unwrap_or_else(|| panic!("no sample for {}", i.name));
            let m = m.as_object().unwrap();
            let keys: Vec<&str> = m.keys().map(String::as_str).collect();
            for k in i.params {
                assert!(keys.contains(k), "{}: sample lacks {k}", i.name);
            }
            let v = evaluate(i.name, m).unwrap_or_else(|e| panic!("{e}"));
            assert!(v.is_finite() && v >= 0.0, "{}: {v}", i.name);
            // Dropping any one parameter is a MissingParameter naming it.
            for k in i.params {
                let mut less = m.clone();
                less.remove(*k);
                match evaluate(i.name, &less) {
                    Err(CatalogError::MissingParameter { param, .. }) => assert_eq!(param, *k),
                    other => panic!("{}: dropping {k} gave {other:?}", i.name),
                }
            }
        }
        assert_eq!(samples.len(), infos.len());
        // Spot values.
        let v = evaluate(
            "solid_angle_rectangle",
            samples["solid_angle_rectangle"].as_object().unwrap(),
        )
        .unwrap();
        assert!((v - (1.0f64 / 3.0f64.sqrt()).atan()).abs() < 1e-15);
        let v = evaluate("bk7_index", samples["bk7_index"].as_object().unwrap()).unwrap();
        let w = evaluate(
            "sellmeier_index",
            samples["sellmeier_index"].as_object().unwrap(),
        )
        .unwrap();
        assert_eq!(v, w);
    }
}
