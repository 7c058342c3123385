//! Judge any renderer: a case exported as a scene another renderer can render (Mitsuba 3,
//! pbrt-v4, or lightproof's own `render`), whose renders [`crate::judge`] then compares
//! with the case's closed form.
//!
//! **What is measured.** Every export reduces the case's measurement to a [`Probe`], in
//! world coordinates (f64, as written):
//!
//! - radiance → [`Probe::Ray`]: one ray, `at` along `direction` (Mitsuba's
//!   `radiancemeter`; pbrt-v4, which has none, a 1×1 perspective camera 10⁻³° wide);
//! - radiance in a closed uniformly emitting diffuse enclosure (references
//!   [`ISOTROPIC_CLOSED_FORMS`]) → [`Probe::Isotropic`]: the radiance is the same along
//!   every ray from the eye, so a camera inside with many pixels sees the measured value
//!   everywhere;
//! - irradiance → [`Probe::Irradiance`]: Mitsuba's `irradiancemeter` on an invisible
//!   (`null` BSDF) disk at the point, of radius 1/100 of the distance to the nearest
//!   geometry (a lower bound computed from the shapes), so that the disk's average of a
//!   field smooth on that scale differs from the point value by O(10⁻⁴) relative at most;
//!   refused when that disk would be below f32 resolution ([`MIN_RECEIVER_RELATIVE`]);
//! - a BSDF's directional albedo → [`Probe::Albedo`]: the BSDF on a plane 2·10³ wide
//!   under a unit constant sky, seen by one ray from ωo: L(ωo) = ∫ f cos θi dωi · 1 is
//!   the albedo (one scattering: a plane cannot see itself). Transmitting BSDFs are
//!   refused (the sky below the plane would count with the η² radiance scaling);
//! - flux onto a receiver shape, or a view factor → [`Probe::Flux`]: a sensor on the
//!   receiver itself (Mitsuba's `irradiancemeter`: a point sampled on the shape by area,
//!   a cosine-weighted direction about its normal, weight π) measures the mean irradiance
//!   Ē = Φ/A₂ over it, so a pixel's expected value is the reference times
//!   [`Probe::Flux::scale`] = 1/A₂ for a flux, π L₁ A₁/A₂ for a view factor
//!   F₁₂ = Φ₂/(π L₁ A₁). The receiver keeps its own material (black without one): in
//!   lightproof it is an ordinary shape of the scene, which occludes and reflects.
//!
//! Everything else (solid angles, power, intensity, microfacet integrals, path
//! lengths; spectral and time-resolved cases; moving, transformed or OBJ shapes; pulsed or
//! spectral emitters) is refused with the reason; each target adds its own refusals
//! (matches on the project's enums are exhaustive: a new variant must decide).
//!
//! **Layout.** `export` writes, per case, a folder holding the scene (`scene.xml`,
//! `scene.pbrt` or `scene.json`), its meshes (`meshes/*.ply`), a verbatim copy of the
//! case (`case.json`, the reference's source) and `export.json` (the [`Manifest`]: what
//! the sensor measures, the expected render size, the conventions applied); the suite's
//! `suite.json` lists the exported cases and the refused ones with their reasons, and the
//! driver (`render_all.py` or `render_all.sh`) writes independent renders as
//! `renders/NNN.exr` in every case folder, render k with seeds of its own (pbrt-v4 and
//! lightproof `--seed k`; Mitsuba one seed per pass q, k·passes + q).

pub mod lightproof;
pub mod mitsuba;
pub mod pbrt;
pub mod ply;

use crate::bsdf::Bsdf;
use crate::case::{CaseDesc, MeasureDesc};
use crate::error::InputError;
use crate::scene::load::{EmitterDesc, GeometryDesc, SceneDesc};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Closed forms whose radiance field is isotropic at every interior point: a closed,
/// uniformly emitting, uniformly diffuse enclosure (L = Le/(1 − ρ), and its partial sums
/// over bounces). A camera inside such a case sees the reference in every pixel.
pub const ISOTROPIC_CLOSED_FORMS: [&str; 2] = [
    "furnace_closed_enclosure",
    "furnace_closed_enclosure_bounces",
];

/// Smallest irradiance receiver, relative to max(1, the point's largest coordinate):
/// 10⁻⁵, about 170 f32 ulps, so that the receiver disk is resolved.
pub const MIN_RECEIVER_RELATIVE: f64 = 1e-5;

/// Half-width of the plane an albedo is measured on.
pub const ALBEDO_PLANE_HALF_WIDTH: f64 = 1e3;

/// The renderer an export is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Target {
    /// Mitsuba 3 (XML scene, Python driver).
    Mitsuba,
    /// pbrt-v4 (scene file, shell driver).
    Pbrt,
    /// lightproof's own `render` (a case file with a camera, shell driver).
    Lightproof,
}

impl Target {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Target::Mitsuba => "mitsuba",
            Target::Pbrt => "pbrt",
            Target::Lightproof => "lightproof",
        }
    }

    /// Parse `mitsuba`, `pbrt` or `lightproof`.
    pub fn parse(s: &str) -> Result<Target, String> {
        match s {
            "mitsuba" => Ok(Target::Mitsuba),
            "pbrt" => Ok(Target::Pbrt),
            "lightproof" => Ok(Target::Lightproof),
            _ => Err(format!(
                "unknown renderer `{s}` (mitsuba, pbrt, lightproof)"
            )),
        }
    }
}

/// What the exported sensor measures, in world coordinates.
#[derive(Clone, Debug, PartialEq)]
pub enum Probe {
    /// Radiance along one ray.
    Ray {
        /// Eye.
        at: DVec3,
        /// Viewing direction (unit).
        direction: DVec3,
    },
    /// Radiance that is the same along every ray from `at` (a closed furnace).
    Isotropic {
        /// Eye.
        at: DVec3,
        /// Where the camera looks (unit).
        direction: DVec3,
    },
    /// Irradiance at a point, averaged over an invisible disk of `radius`.
    Irradiance {
        /// Point.
        at: DVec3,
        /// Receiver normal (unit).
        normal: DVec3,
        /// Receiver disk radius.
        radius: f64,
    },
    /// Directional albedo of `bsdf` seen from `wo` (unit, local frame = world, normal +z).
    Albedo {
        /// The BSDF.
        bsdf: Bsdf,
        /// Outgoing direction.
        wo: DVec3,
    },
    /// Power onto receiver `shape` (on the side its normal faces), measured as the mean
    /// irradiance Ē = Φ/A over it.
    Flux {
        /// The receiver: an index of `scene.shapes`.
        shape: usize,
        /// Its area A (f64, from the case's geometry).
        area: f64,
        /// Ē per unit of the reference: 1/A for a flux, π L₁ A₁/A for a view factor.
        scale: f64,
    },
}

impl Probe {
    /// The scatterings a renderer's path may have for this probe: lightproof's
    /// `max_depth` (None: unbounded) as it counts them; an albedo is one scattering.
    pub fn scatterings(&self, max_depth: Option<u32>) -> Option<u32> {
        match self {
            Probe::Albedo { .. } => Some(1),
            Probe::Ray { .. }
            | Probe::Isotropic { .. }
            | Probe::Irradiance { .. }
            | Probe::Flux { .. } => max_depth,
        }
    }

    /// Short name of the sensor.
    pub fn sensor(&self) -> &'static str {
        match self {
            Probe::Ray { .. } => "ray",
            Probe::Isotropic { .. } => "camera_inside",
            Probe::Irradiance { .. } => "irradiance",
            Probe::Albedo { .. } => "albedo",
            Probe::Flux { .. } => "flux",
        }
    }

    /// A pixel's expected value per unit of the case's reference (the manifest's `scale`).
    pub fn scale(&self) -> f64 {
        match self {
            Probe::Flux { scale, .. } => *scale,
            Probe::Ray { .. }
            | Probe::Isotropic { .. }
            | Probe::Irradiance { .. }
            | Probe::Albedo { .. } => 1.0,
        }
    }
}

/// `export.json`: what a render of an exported case holds and how to judge it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// The renderer.
    pub renderer: Target,
    /// The case file it came from (as given).
    pub source: String,
    /// The case's name.
    pub name: String,
    /// Its verbatim copy beside the scene (the reference's source).
    pub case: String,
    /// The scene file for the renderer.
    pub scene: String,
    /// The sensor (`ray`, `camera_inside`, `irradiance`, `albedo`, `flux`).
    pub sensor: String,
    /// Render width in pixels.
    pub width: usize,
    /// Render height in pixels.
    pub height: usize,
    /// Every pixel's expected value is the reference times this factor.
    pub scale: f64,
    /// The conventions applied (what maps to what).
    pub conventions: Vec<String>,
}

/// The range of an export's `scale` (both exporting and judging hold it): a pixel of f32
/// range (1.4·10⁻⁴⁵ ≤ |x| ≤ 3.4·10³⁸) divided by a scale in [10⁻¹⁰⁰, 10¹⁰⁰] lies within
/// [10⁻¹⁴⁵, 3.4·10¹³⁸], whose squares (a variance's terms) stay finite and normal in f64.
/// A scale of 0, 10⁻³²⁰ or +∞ once printed `± inf`; a negative one, a negative estimate.
pub const SCALE_RANGE: (f64, f64) = (1e-100, 1e100);

impl Manifest {
    /// Every number of an `export.json` that `judge` uses is one an export writes, and its
    /// `case` a file name beside it: a `scale` within [`SCALE_RANGE`], `width` and `height` at least 1 with at most
    /// [`crate::scene::load::MAX_ENVMAP_PIXELS`] pixels, the most a render may have. The
    /// schema cannot say these; without them a scale of 0 printed `± inf` and a width of
    /// 0 blamed every render for its size.
    pub fn check(&self, file: &str) -> Result<(), InputError> {
        // The case beside the renders, as an export writes it: a plain file name (a path
        // out of the folder judged its renders against another case, unflagged).
        let mut parts = Path::new(&self.case).components();
        if !matches!(
            (parts.next(), parts.next()),
            (Some(std::path::Component::Normal(_)), None)
        ) {
            return Err(InputError::new(
                file,
                "case",
                format!(
                    "must name the case file beside it (a file name, as an export writes `case.json`), got `{}`",
                    self.case
                ),
            ));
        }
        let (lo, hi) = SCALE_RANGE;
        if !(lo..=hi).contains(&self.scale) {
            return Err(InputError::new(
                file,
                "scale",
                format!(
                    "must be a number from {lo:e} to {hi:e}, got {:?}",
                    self.scale
                ),
            ));
        }
        let max = crate::scene::load::MAX_ENVMAP_PIXELS;
        for (field, n) in [("width", self.width), ("height", self.height)] {
            if n == 0 {
                return Err(InputError::new(
                    file,
                    field,
                    "must be at least 1 pixel, got 0",
                ));
            }
        }
        if self.width.checked_mul(self.height).is_none_or(|n| n > max) {
            // The culprit where one alone is too large, else the product.
            let field = if self.width > max {
                "width"
            } else if self.height > max {
                "height"
            } else {
                "width × height"
            };
            return Err(InputError::new(
                file,
                field,
                format!(
                    "width × height = {} × {} is more than {max} pixels, the most a render may have",
                    self.width, self.height
                ),
            ));
        }
        Ok(())
    }
}

/// A case a renderer cannot express: the reason.
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal(pub String);

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Why exporting failed: a case the target cannot express (exit 2), bad input (exit 2),
/// or an output that cannot be written (exit 3).
#[derive(Debug)]
pub enum ExportError {
    /// The renderer cannot express the case.
    Refused(String, Refusal),
    /// The case file is invalid.
    Input(InputError),
    /// Writing failed.
    Io(crate::error::IoError),
}

impl From<InputError> for ExportError {
    fn from(e: InputError) -> Self {
        ExportError::Input(e)
    }
}

impl From<crate::error::IoError> for ExportError {
    fn from(e: crate::error::IoError) -> Self {
        ExportError::Io(e)
    }
}

/// A scene written for one target: the files (relative path, bytes) and the manifest.
pub struct Written {
    /// Files to write under the case's folder.
    pub files: Vec<(String, Vec<u8>)>,
    /// The manifest.
    pub manifest: Manifest,
}

/// The refusals every target shares: what lightproof measures that no sensor of theirs
/// does, and the scene features the exporters do not carry over.
pub fn probe(desc: &CaseDesc) -> Result<Probe, Refusal> {
    if desc.spectral.is_some() {
        return refuse("spectral cases are not exported (renders are RGB; grey cases only)");
    }
    if desc.time.is_some() {
        return refuse("time-resolved and moving cases are not exported");
    }
    common_scene(&desc.scene)?;
    let v = DVec3::from_array;
    match &desc.measure {
        MeasureDesc::Radiance { at, direction } => {
            let (at, direction) = (v(*at), v(*direction).normalize());
            let isotropic = desc
                .reference
                .as_ref()
                .and_then(|r| r.get("closed_form"))
                .and_then(|n| n.as_str())
                .is_some_and(|n| ISOTROPIC_CLOSED_FORMS.contains(&n));
            Ok(if isotropic {
                Probe::Isotropic { at, direction }
            } else {
                Probe::Ray { at, direction }
            })
        }
        MeasureDesc::Irradiance { at, normal } => {
            let at = v(*at);
            let clearance = clearance(&desc.scene, at);
            // Nothing nearby (an empty scene under a sky): any small receiver will do.
            let radius = if clearance.is_finite() {
                clearance / 100.0
            } else {
                0.01 * at.abs().max_element().max(1.0)
            };
            let floor = MIN_RECEIVER_RELATIVE * at.abs().max_element().max(1.0);
            if !(radius >= floor) {
                return refuse(format!(
                    "the irradiance point is {clearance:.3e} from the nearest geometry: a receiver disk 1/100 of that ({radius:.3e}) is below f32 resolution here ({floor:.1e})"
                ));
            }
            Ok(Probe::Irradiance {
                at,
                normal: v(*normal).normalize(),
                radius,
            })
        }
        MeasureDesc::Albedo {
            bsdf,
            theta_degrees,
            phi_degrees,
        } => {
            let (t, p) = (theta_degrees.to_radians(), phi_degrees.to_radians());
            if transmits(bsdf) {
                return refuse(format!(
                    "the albedo of a transmitting BSDF ({}) is not exported: the sky below the plane would count with the η² radiance scaling",
                    bsdf.name()
                ));
            }
            Ok(Probe::Albedo {
                bsdf: bsdf.clone(),
                wo: DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()),
            })
        }
        MeasureDesc::SolidAngle { .. }
        | MeasureDesc::ProjectedSolidAngle { .. }
        | MeasureDesc::Microfacet { .. }
        | MeasureDesc::MeanPathLength { .. }
        | MeasureDesc::Power { .. }
        | MeasureDesc::Intensity { .. } => Err(sensorless(&desc.measure)
            .unwrap_or_else(|| Refusal("no renderer sensor measures it".into()))),
        MeasureDesc::Flux { shape, view_factor } => flux(&desc.scene, *shape, *view_factor),
    }
}

/// Why no renderer's sensor measures `measure` (a geometric integral, an emitter's power
/// or intensity), or `None` where one does. [`probe`] refuses these, and `judge` too: a
/// render's pixels are light at a sensor, so their mean is never such a quantity, and a
/// comparison of it with the case's reference is meaningless (it once passed).
pub fn sensorless(measure: &MeasureDesc) -> Option<Refusal> {
    let why = match measure {
        MeasureDesc::Radiance { .. }
        | MeasureDesc::Irradiance { .. }
        | MeasureDesc::Albedo { .. }
        | MeasureDesc::Flux { .. } => return None,
        MeasureDesc::SolidAngle { .. }
        | MeasureDesc::ProjectedSolidAngle { .. }
        | MeasureDesc::Microfacet { .. }
        | MeasureDesc::MeanPathLength { .. } => {
            "a geometric integral, not light a renderer's sensor measures"
        }
        MeasureDesc::Power { .. } | MeasureDesc::Intensity { .. } => {
            "power and intensity of an emitter have no renderer sensor"
        }
    };
    Some(Refusal(why.into()))
}

/// The flux probe of receiver `shape`: its area and the scale from the reference to the
/// mean irradiance over it (module notes). The case has been validated (one one-sided
/// shape emitter for a view factor); what does not fit is refused, not a panic.
fn flux(scene: &SceneDesc, shape: usize, view_factor: bool) -> Result<Probe, Refusal> {
    let field = format!("measure.flux.shape: scene.shapes[{shape}]");
    let Some(receiver) = scene.shapes.get(shape) else {
        return refuse(format!("{field} does not exist"));
    };
    let positive = |a: Option<f64>| a.filter(|a| a.is_finite() && *a > 0.0);
    let Some(a2) = positive(area(&receiver.geometry)) else {
        return refuse(format!("{field}: its area is not a positive finite number"));
    };
    let scale = if view_factor {
        let emitting: Vec<_> = scene
            .shapes
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.emission.as_ref().map(|e| (i, s, e)))
            .collect();
        let [(i, emitter, emission)] = emitting.as_slice() else {
            return refuse(format!(
                "measure.flux.view_factor: {} emitting shapes, a view factor needs one",
                emitting.len()
            ));
        };
        let Some(a1) = positive(area(&emitter.geometry)) else {
            return refuse(format!(
                "scene.shapes[{i}]: the emitter's area is not a positive finite number"
            ));
        };
        std::f64::consts::PI * emission.radiance * a1 / a2
    } else {
        1.0 / a2
    };
    let (lo, hi) = SCALE_RANGE;
    if !(lo..=hi).contains(&scale) {
        return refuse(format!(
            "{field}: the mean irradiance per unit of the reference ({scale:e}) is not within [{lo:e}, {hi:e}]"
        ));
    }
    Ok(Probe::Flux {
        shape,
        area: a2,
        scale,
    })
}

/// Area of a shape in f64 from its description: a sphere 4πR², a cap 2πR²(1 − cos θmax);
/// a disk πR², an annulus π(R² − r²); planar shapes and meshes the sum of their
/// triangles' ½‖(p₁ − p₀) × (p₂ − p₀)‖. `None` for OBJ files (not read here) and meshes
/// whose indices are out of range.
pub fn area(g: &GeometryDesc) -> Option<f64> {
    use std::f64::consts::PI;
    match g {
        GeometryDesc::Sphere {
            radius, theta_max, ..
        } => {
            let one_minus_cos = theta_max.map_or(2.0, |t| 1.0 - t.to_radians().cos());
            Some(2.0 * PI * radius * radius * one_minus_cos)
        }
        GeometryDesc::Disk {
            radius,
            inner_radius,
            ..
        } => {
            let r = inner_radius.unwrap_or(0.0);
            Some(PI * (radius * radius - r * r))
        }
        GeometryDesc::Rectangle { .. }
        | GeometryDesc::Triangle { .. }
        | GeometryDesc::Mesh { .. } => {
            let (vs, fs) = triangles(g)?;
            fs.iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| vs.get(i as usize).copied());
                    let (a, b, c) = (a?, b?, c?);
                    Some(0.5 * (b - a).cross(c - a).length())
                })
                .sum()
        }
        GeometryDesc::Obj { .. } => None,
    }
}

fn refuse<T>(why: impl Into<String>) -> Result<T, Refusal> {
    Err(Refusal(why.into()))
}

/// Whether a BSDF transmits light.
fn transmits(b: &Bsdf) -> bool {
    match b {
        Bsdf::Dielectric(_) | Bsdf::RoughDielectric(_) => true,
        Bsdf::Lambertian(_)
        | Bsdf::OrenNayar(_)
        | Bsdf::OrenNayarClassic(_)
        | Bsdf::Conductor(_)
        | Bsdf::RoughConductor(_)
        | Bsdf::Plastic(_) => false,
    }
}

/// Scene features no exporter carries over.
fn common_scene(scene: &SceneDesc) -> Result<(), Refusal> {
    if !scene.dispersion.is_empty() {
        return refuse("dispersive materials are not exported (grey cases only)");
    }
    for (i, s) in scene.shapes.iter().enumerate() {
        if s.transform.is_some() {
            return refuse(format!(
                "scene.shapes[{i}].transform: transformed shapes are not exported yet"
            ));
        }
        if s.velocity.is_some() {
            return refuse(format!("scene.shapes[{i}]: moving shapes are not exported"));
        }
        if let Some(e) = &s.emission
            && (e.spectrum.is_some() || e.pulse_at.is_some())
        {
            return refuse(format!(
                "scene.shapes[{i}].emission: spectral or pulsed emission is not exported"
            ));
        }
        match &s.geometry {
            GeometryDesc::Obj { .. } => {
                return refuse(format!(
                    "scene.shapes[{i}]: OBJ geometry is not exported yet (inline `mesh` is)"
                ));
            }
            GeometryDesc::Sphere { .. }
            | GeometryDesc::Rectangle { .. }
            | GeometryDesc::Disk { .. }
            | GeometryDesc::Triangle { .. }
            | GeometryDesc::Mesh { .. } => {}
        }
    }
    for (i, e) in scene.emitters.iter().enumerate() {
        let (spectrum, pulsed, moving) = match e {
            EmitterDesc::Point {
                spectrum,
                pulse_at,
                velocity,
                ..
            }
            | EmitterDesc::Spot {
                spectrum,
                pulse_at,
                velocity,
                ..
            } => (spectrum.is_some(), pulse_at.is_some(), velocity.is_some()),
            EmitterDesc::Directional { spectrum, .. }
            | EmitterDesc::Constant { spectrum, .. }
            | EmitterDesc::Envmap { spectrum, .. } => (spectrum.is_some(), false, false),
        };
        if spectrum || pulsed || moving {
            return refuse(format!(
                "scene.emitters[{i}]: spectral, pulsed or moving emitters are not exported"
            ));
        }
    }
    Ok(())
}

/// A lower bound of the distance from `p` to every shape and point-like emitter of the
/// scene (∞ when there is none): spheres |‖p − c‖ − R| (a cap is part of its sphere);
/// planar shapes the larger of the distance to their plane and to their bounding ball.
pub fn clearance(scene: &SceneDesc, p: DVec3) -> f64 {
    let v = DVec3::from_array;
    // A planar polygon through `pts`: distance to its plane and to its bounding ball.
    let planar = |pts: &[DVec3]| -> f64 {
        let c = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
        let r = pts.iter().map(|q| (*q - c).length()).fold(0.0, f64::max);
        let n = (pts[1] - pts[0]).cross(pts[2] - pts[0]).normalize_or_zero();
        ((p - pts[0]).dot(n).abs()).max((p - c).length() - r)
    };
    let mut d = f64::INFINITY;
    for s in &scene.shapes {
        let ds = match &s.geometry {
            GeometryDesc::Sphere { center, radius, .. } => {
                ((p - v(*center)).length() - radius).abs()
            }
            GeometryDesc::Disk {
                center,
                normal,
                radius,
                ..
            } => {
                let n = v(*normal).normalize_or_zero();
                let q = p - v(*center);
                q.dot(n).abs().max(q.length() - radius)
            }
            GeometryDesc::Rectangle { .. }
            | GeometryDesc::Triangle { .. }
            | GeometryDesc::Mesh { .. } => match triangles(&s.geometry) {
                Some((vs, fs)) => fs
                    .iter()
                    .filter_map(|t| {
                        let q = t.map(|i| vs.get(i as usize).copied());
                        Some(planar(&[q[0]?, q[1]?, q[2]?]))
                    })
                    .fold(f64::INFINITY, f64::min),
                None => 0.0,
            },
            GeometryDesc::Obj { .. } => 0.0,
        };
        d = d.min(ds);
    }
    for e in &scene.emitters {
        match e {
            EmitterDesc::Point { position, .. } | EmitterDesc::Spot { position, .. } => {
                d = d.min((p - v(*position)).length());
            }
            EmitterDesc::Directional { .. }
            | EmitterDesc::Constant { .. }
            | EmitterDesc::Envmap { .. } => {}
        }
    }
    d
}

/// An orthonormal, right-handed frame (t, b, n) around unit `n`.
pub fn frame(n: DVec3) -> (DVec3, DVec3) {
    let helper = if n.z.abs() < 0.9 { DVec3::Z } else { DVec3::X };
    let t = helper.cross(n).normalize();
    (t, n.cross(t))
}

/// The scene of a probe: the case's own, or for an albedo a plane carrying the BSDF
/// under a unit constant sky.
pub fn probe_scene(desc: &CaseDesc, probe: &Probe) -> SceneDesc {
    match probe {
        Probe::Albedo { bsdf, .. } => {
            let h = ALBEDO_PLANE_HALF_WIDTH;
            let mut scene = SceneDesc::default();
            scene.materials.insert("probe".into(), bsdf.clone());
            scene.shapes.push(crate::scene::load::ShapeDesc {
                name: Some("albedo plane".into()),
                geometry: GeometryDesc::Rectangle {
                    corner: [-h, -h, 0.0],
                    edge_u: [2.0 * h, 0.0, 0.0],
                    edge_v: [0.0, 2.0 * h, 0.0],
                },
                material: Some("probe".into()),
                emission: None,
                flip_normals: false,
                transform: None,
                velocity: None,
            });
            scene.emitters.push(EmitterDesc::Constant {
                radiance: 1.0,
                spectrum: None,
            });
            scene
        }
        Probe::Ray { .. }
        | Probe::Isotropic { .. }
        | Probe::Irradiance { .. }
        | Probe::Flux { .. } => desc.scene.clone(),
    }
}

/// The eye and viewing direction of an albedo probe: a unit distance along ωo, looking
/// back at the origin.
pub fn albedo_eye(wo: DVec3) -> (DVec3, DVec3) {
    (wo, -wo)
}

/// Triangles of a planar or mesh shape (world coordinates, winding kept: the normal is
/// (p₁ − p₀) × (p₂ − p₀) as lightproof orients it); `None` for spheres and disks.
pub fn triangles(g: &GeometryDesc) -> Option<(Vec<DVec3>, Vec<[u32; 3]>)> {
    let v = DVec3::from_array;
    match g {
        GeometryDesc::Rectangle {
            corner,
            edge_u,
            edge_v,
        } => {
            let (c, u, w) = (v(*corner), v(*edge_u), v(*edge_v));
            Some((vec![c, c + u, c + u + w, c + w], vec![[0, 1, 2], [0, 2, 3]]))
        }
        GeometryDesc::Triangle { vertices } => Some((vertices.map(v).to_vec(), vec![[0, 1, 2]])),
        GeometryDesc::Mesh { vertices, indices } => {
            Some((vertices.iter().map(|p| v(*p)).collect(), indices.clone()))
        }
        GeometryDesc::Sphere { .. } | GeometryDesc::Disk { .. } | GeometryDesc::Obj { .. } => None,
    }
}

/// Write a planar or mesh shape `i` as `meshes/shape{i}.ply` into `files`; its name.
pub fn mesh_file(
    i: usize,
    g: &GeometryDesc,
    files: &mut Vec<(String, Vec<u8>)>,
) -> Result<String, Refusal> {
    let Some((vs, fs)) = triangles(g) else {
        return refuse(format!("scene.shapes[{i}]: no triangles"));
    };
    let name = format!("meshes/shape{i}.ply");
    files.push((name.clone(), ply::ascii(&vs, &fs).into_bytes()));
    Ok(name)
}

/// Render size of a probe: 16 × 16 pixels for a camera inside, else 1 × 1 (a ray or an
/// irradiance meter, also on a receiver shape; replicates come from independent renders).
pub fn render_size(probe: &Probe) -> (usize, usize) {
    match probe {
        Probe::Isotropic { .. } => (16, 16),
        Probe::Ray { .. }
        | Probe::Irradiance { .. }
        | Probe::Albedo { .. }
        | Probe::Flux { .. } => (1, 1),
    }
}

/// Write `case_file` for `target` into `dir` (created): the scene, meshes, `case.json`
/// and `export.json`. The case must load (bad input exits 2 with the usual message).
pub fn export_case(case_file: &Path, target: Target, dir: &Path) -> Result<Manifest, ExportError> {
    let case = crate::case::Case::load(case_file)?;
    let desc = &case.desc;
    let file = case_file.display().to_string();
    let refused = |r: Refusal| ExportError::Refused(file.clone(), r);
    let probe = probe(desc).map_err(refused)?;
    let written = match target {
        Target::Mitsuba => mitsuba::write(desc, &probe),
        Target::Pbrt => pbrt::write(desc, &probe),
        Target::Lightproof => lightproof::write(desc, &probe),
    }
    .map_err(refused)?;
    let mut manifest = written.manifest;
    manifest.source = file.clone();
    let text = crate::io::read_input(case_file, crate::io::MAX_JSON_BYTES)
        .map_err(|e| InputError::new(&file, "-", e))?;
    let mut files = written.files;
    files.push(("case.json".into(), text.into_bytes()));
    let json = serde_json::to_string_pretty(&manifest).unwrap_or_default();
    files.push(("export.json".into(), json.into_bytes()));
    // A file written over the case itself (`export scene.json --to lightproof --out .`
    // wrote the exported scene over the case) is refused before anything is written;
    // the suite's own files land beside a single case's.
    let input = [case_file.to_path_buf()];
    let suite_files = ["suite.json", "cases.txt", "render_all.py", "render_all.sh"];
    for name in files.iter().map(|(n, _)| n.as_str()).chain(suite_files) {
        crate::io::refuse_output_on_input("--out", &dir.join(name), &input, &[])?;
    }
    for (name, bytes) in &files {
        let path = dir.join(name);
        crate::io::write_atomic(&path, bytes)
            .map_err(|e| crate::error::IoError::write(&path, e))?;
    }
    Ok(manifest)
}

/// `suite.json`: the exported cases (folders under the suite) and the refused ones.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    /// The renderer.
    pub renderer: Option<Target>,
    /// Exported cases: their ids (folders under the suite).
    pub cases: Vec<String>,
    /// Refused cases: id and reason.
    pub refused: Vec<(String, String)>,
}

/// Export every case under `paths` into `out`: one folder per case id (its path under
/// the folder given, without `.json`), the suite's `suite.json`, `cases.txt` and the
/// driver. Refused cases are listed, not errors; invalid case files are errors.
pub fn export_suite(paths: &[PathBuf], target: Target, out: &Path) -> Result<Suite, ExportError> {
    let mut suite = Suite {
        renderer: Some(target),
        ..Suite::default()
    };
    for p in paths {
        let root = p.is_dir().then_some(p.as_path());
        for f in crate::case::collect_cases(std::slice::from_ref(p))? {
            let id = crate::report::store::case_id(root, &f);
            // `cases.txt` lists one id a line for the shell drivers: a newline in a file's
            // name once split its id over two lines (a stray folder, a failed render).
            if id.chars().any(char::is_control) {
                return Err(InputError::new(
                    f.display().to_string().escape_debug().to_string(),
                    "-",
                    format!("its id {id:?} holds a control character (a newline, a tab): rename the case file"),
                )
                .into());
            }
            match export_case(&f, target, &out.join(&id)) {
                Ok(_) => suite.cases.push(id),
                Err(ExportError::Refused(_, why)) => suite.refused.push((id, why.0)),
                Err(e) => return Err(e),
            }
        }
    }
    write_suite(&suite, target, out)?;
    Ok(suite)
}

/// Write `suite.json`, `cases.txt` (one id a line, for the shell drivers) and the driver.
fn write_suite(suite: &Suite, target: Target, out: &Path) -> Result<(), ExportError> {
    let write = |name: &str, bytes: &[u8]| {
        let path = out.join(name);
        crate::io::write_atomic(&path, bytes).map_err(|e| crate::error::IoError::write(&path, e))
    };
    let json = serde_json::to_string_pretty(suite).unwrap_or_default();
    write("suite.json", json.as_bytes())?;
    let list: String = suite.cases.iter().map(|c| format!("{c}\n")).collect();
    write("cases.txt", list.as_bytes())?;
    let (driver, text) = match target {
        Target::Mitsuba => ("render_all.py", mitsuba::DRIVER),
        Target::Pbrt => ("render_all.sh", pbrt::DRIVER),
        Target::Lightproof => ("render_all.sh", lightproof::DRIVER),
    };
    write(driver, text.as_bytes())?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(out.join(driver), std::fs::Permissions::from_mode(0o755));
    }
    Ok(())
}

impl From<ExportError> for crate::error::Error {
    fn from(e: ExportError) -> Self {
        match e {
            ExportError::Refused(file, why) => InputError::new(
                file,
                "-",
                format!("cannot be expressed for this renderer: {why}"),
            )
            .into(),
            ExportError::Input(e) => e.into(),
            ExportError::Io(e) => e.into(),
        }
    }
}

/// The `export` command: one case file into `out` (a suite of one, id `.`; a refusal is
/// bad input), or with `all` every case under `paths`. Returns what to print.
pub fn run(
    paths: &[PathBuf],
    all: bool,
    target: Target,
    out: &Path,
) -> Result<String, crate::error::Error> {
    let driver = match target {
        Target::Mitsuba => "python3 render_all.py",
        Target::Pbrt | Target::Lightproof => "sh render_all.sh",
    };
    let next = format!(
        "render: (cd {0} && {driver}); judge: lightproof judge --suite {0}",
        out.display()
    );
    if all {
        let suite = export_suite(paths, target, out)?;
        let mut text = String::new();
        for (id, why) in &suite.refused {
            text.push_str(&format!("refused {id}: {why}\n"));
        }
        text.push_str(&format!(
            "exported {} cases to {} for {} ({} refused)\n{next}",
            suite.cases.len(),
            out.display(),
            target.name(),
            suite.refused.len()
        ));
        return Ok(text);
    }
    let [case] = paths else {
        return Err(InputError::new(
            "<command line>",
            "CASE.json",
            format!("give one case file (or --all), got {}", paths.len()),
        )
        .into());
    };
    let m = export_case(case, target, out)?;
    let suite = Suite {
        renderer: Some(target),
        cases: vec![".".into()],
        refused: vec![],
    };
    write_suite(&suite, target, out)?;
    Ok(format!(
        "wrote {} ({} sensor, {}×{} pixels) for {}\n{next}",
        out.join(&m.scene).display(),
        m.sensor,
        m.width,
        m.height,
        target.name()
    ))
}

/// Format a number for a scene file: the shortest text that reads back as the same f64.
pub fn num(x: f64) -> String {
    if x == 0.0 { "0".into() } else { format!("{x}") }
}

/// What the exporters' mapping tests share: a small case exported for one renderer, and
/// checks on the scene file it writes or on the refusal.
#[cfg(test)]
pub(crate) mod mapping {
    use super::*;

    /// A disk light of radiance 2 at height 3 facing down.
    pub const DISK_LIGHT: &str = r#"{"geometry":{"type":"disk","center":[0,0,3],"normal":[0,0,-1],"radius":1},"emission":{"radiance":2}}"#;

    /// A radiance case along the ray (0, 0, 0) → +z with these `materials`, `shapes`,
    /// `emitters` (JSON fragments) and `extra` top-level fields, exported for `target`:
    /// its scene file, or the refusal.
    pub fn export(
        target: Target,
        materials: &str,
        shapes: &str,
        emitters: &str,
        extra: &str,
    ) -> Result<String, String> {
        measured(
            target,
            &format!(
                r#"{{"name":"n","teaches":"t",
                  "scene":{{"materials":{{{materials}}},"shapes":[{shapes}],"emitters":[{emitters}]}},
                  "measure":{{"radiance":{{"at":[0,0,0],"direction":[0,0,1]}}}},
                  "estimators":["mis"]{extra}}}"#
            ),
        )
    }

    /// A whole case (JSON) exported for `target`: its scene file, or the refusal.
    pub fn measured(target: Target, json: &str) -> Result<String, String> {
        let desc: CaseDesc = serde_json::from_str(json).map_err(|e| e.to_string())?;
        let probe = probe(&desc).map_err(|r| r.0)?;
        let w = match target {
            Target::Mitsuba => mitsuba::write(&desc, &probe),
            Target::Pbrt => pbrt::write(&desc, &probe),
            Target::Lightproof => lightproof::write(&desc, &probe),
        }
        .map_err(|r| r.0)?;
        let scene = &w.manifest.scene;
        let (_, bytes) = w.files.iter().find(|(n, _)| n == scene).unwrap();
        Ok(String::from_utf8(bytes.clone()).unwrap())
    }

    /// `material` (a BSDF's JSON) on a sphere beside the disk light, exported.
    pub fn with_material(target: Target, bsdf: &str) -> Result<String, String> {
        export(
            target,
            &format!(r#""m":{bsdf}"#),
            &format!(
                r#"{DISK_LIGHT},{{"geometry":{{"type":"sphere","center":[0,5,0],"radius":1}},"material":"m"}}"#
            ),
            "",
            "",
        )
    }

    /// The scene file holds every one of `parts`.
    #[track_caller]
    pub fn has(r: &Result<String, String>, parts: &[&str]) {
        let x = r.as_ref().unwrap_or_else(|e| panic!("refused: {e}"));
        for p in parts {
            assert!(x.contains(p), "`{p}` missing from\n{x}");
        }
    }

    /// The export was refused for a reason containing `why`.
    #[track_caller]
    pub fn refused(r: &Result<String, String>, why: &str) {
        match r {
            Ok(x) => panic!("exported, expected a refusal ({why}):\n{x}"),
            Err(e) => assert!(e.contains(why), "{e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(json: &str) -> CaseDesc {
        serde_json::from_str(json).unwrap()
    }

    /// A case file whose name holds a newline is refused before anything is written, in
    /// a message of one line: its id, one line of `cases.txt` for the shell drivers, was
    /// split over two (a stray folder, then a failed render).
    #[test]
    fn ids_with_control_characters_are_refused() {
        let dir = std::env::temp_dir().join(format!("lightproof-export-nl-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("in")).unwrap();
        let disk = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("analytic/cases/irradiance/disk_on_axis.json");
        std::fs::copy(disk, dir.join("in/new\nline.json")).unwrap();
        let e = export_suite(&[dir.join("in")], Target::Lightproof, &dir.join("out")).unwrap_err();
        let ExportError::Input(e) = e else {
            panic!("{e:?}")
        };
        let e = e.to_string();
        assert!(e.contains("control character") && !e.contains('\n'), "{e}");
        assert!(!dir.join("out").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn clearance_bounds_distance_from_below() {
        let d = case(
            r#"{"name":"n","teaches":"t","scene":{"shapes":[
              {"geometry":{"type":"sphere","center":[0,0,0],"radius":1}},
              {"geometry":{"type":"disk","center":[0,0,5],"normal":[0,0,-1],"radius":1}}]},
              "measure":{"irradiance":{"at":[0,0,2],"normal":[0,0,1]}},"estimators":["mis"]}"#,
        );
        // The sphere is 1 away, the disk 3.
        assert!((clearance(&d.scene, DVec3::new(0.0, 0.0, 2.0)) - 1.0).abs() < 1e-12);
        // Beside the disk's plane but far from the disk: the ball bound wins.
        let far = clearance(&d.scene, DVec3::new(100.0, 0.0, 5.0));
        assert!(far > 98.0 && far <= 99.0 + 1e-9, "{far}");
    }

    #[test]
    fn probes_follow_the_measurement() {
        let furnace = case(
            r#"{"name":"n","teaches":"t","scene":{"materials":{"g":{"type":"lambertian","albedo":0.5}},
              "shapes":[{"geometry":{"type":"sphere","center":[0,0,0],"radius":1},"material":"g",
              "flip_normals":true,"emission":{"radiance":1}}]},
              "measure":{"radiance":{"at":[0,0,0],"direction":[0,0,2]}},
              "reference":{"closed_form":"furnace_closed_enclosure","emitted_radiance":1,"albedo":0.5},
              "estimators":["mis"]}"#,
        );
        assert!(
            matches!(probe(&furnace), Ok(Probe::Isotropic { direction, .. }) if direction == DVec3::Z)
        );
        let mut ray = furnace.clone();
        ray.reference = None;
        assert!(matches!(probe(&ray), Ok(Probe::Ray { .. })));
        let mut near = furnace.clone();
        near.measure = MeasureDesc::Irradiance {
            at: [0.0, 0.0, 1.0 - 1e-6],
            normal: [0.0, 0.0, 1.0],
        };
        let why = probe(&near).unwrap_err().0;
        assert!(why.contains("f32 resolution"), "{why}");
        let mut inside = near.clone();
        inside.measure = MeasureDesc::Irradiance {
            at: [0.0, 0.0, 0.5],
            normal: [0.0, 0.0, 1.0],
        };
        assert!(
            matches!(probe(&inside), Ok(Probe::Irradiance { radius, .. }) if (radius - 0.005).abs() < 1e-12)
        );
        let mut timed = furnace;
        timed.time = Some(Default::default());
        assert!(probe(&timed).unwrap_err().0.contains("time"));
        // The floor is 10⁻⁵ of the point's largest coordinate, not of its length: at
        // (7e4, 7e4, 7e4), 100 from a sphere, the receiver of radius 1 is above 0.7 (and
        // would be below 10⁻⁵ |p| = 1.21).
        let far = case(
            r#"{"name":"n","teaches":"t","scene":{"shapes":[{"geometry":{"type":"sphere",
              "center":[70000,70000,70101],"radius":1},"emission":{"radiance":1}}]},
              "measure":{"irradiance":{"at":[70000,70000,70000],"normal":[0,0,1]}},
              "estimators":["light"]}"#,
        );
        assert!(
            matches!(probe(&far), Ok(Probe::Irradiance { radius, .. }) if (radius - 1.0).abs() < 1e-9),
            "{:?}",
            probe(&far).map(|_| ())
        );
    }

    /// An albedo probe is the BSDF on a plane 2000 wide (corner at −1000, −1000) under a
    /// constant sky of radiance 1, whatever the case's own scene.
    #[test]
    fn the_albedo_probe_is_a_wide_plane_under_a_white_sky() {
        let albedo = case(
            r#"{"name":"n","teaches":"t","measure":{"albedo":{"bsdf":{"type":"lambertian","albedo":0.5},
              "theta_degrees":30}},"estimators":["bsdf"]}"#,
        );
        let p = probe(&albedo).unwrap_or_else(|r| panic!("{}", r.0));
        let scene = probe_scene(&albedo, &p);
        assert_eq!(scene.shapes.len(), 1);
        assert!(
            matches!(
                scene.shapes[0].geometry,
                GeometryDesc::Rectangle {
                    corner: [-1000.0, -1000.0, 0.0],
                    edge_u: [2000.0, 0.0, 0.0],
                    edge_v: [0.0, 2000.0, 0.0]
                }
            ),
            "{:?}",
            scene.shapes[0].geometry
        );
        assert_eq!(scene.shapes[0].material.as_deref(), Some("probe"));
        assert!(matches!(
            scene.emitters[..],
            [EmitterDesc::Constant {
                radiance: 1.0,
                spectrum: None
            }]
        ));
    }

    /// `export.json`'s numbers are checked at their limits: a scale at either end of
    /// [`SCALE_RANGE`] and a render of 1 × 1 or of exactly the pixel limit pass; a scale
    /// just outside, 0, negative or +∞, a width or height of 0 and one pixel more than
    /// the limit (or a product that overflows) are named, by the field too large alone
    /// (a height of 2⁶⁴ − 1 once blamed the width), else as `width × height`.
    #[test]
    fn a_manifest_the_judge_cannot_use_is_named() {
        let ok = Manifest {
            renderer: Target::Mitsuba,
            source: "c.json".into(),
            name: "c".into(),
            case: "case.json".into(),
            scene: "scene.xml".into(),
            sensor: "irradiance".into(),
            width: 4,
            height: 2,
            scale: 1.0,
            conventions: vec![],
        };
        let max = crate::scene::load::MAX_ENVMAP_PIXELS;
        let (lo, hi) = SCALE_RANGE;
        type Edit = fn(&mut Manifest, usize);
        let good: [Edit; 5] = [
            |m, _| m.scale = SCALE_RANGE.0,
            |m, _| m.scale = SCALE_RANGE.1,
            |m, _| (m.width, m.height) = (1, 1),
            |m, max| (m.width, m.height) = (max, 1),
            |m, max| (m.width, m.height) = (1, max),
        ];
        for edit in good {
            let mut m = ok.clone();
            edit(&mut m, max);
            assert!(m.check("export.json").is_ok(), "{m:?}");
        }
        // Too many pixels blames the field too large alone, else the product.
        let bad: [(Edit, &str); 14] = [
            (|m, _| m.scale = 0.0, "scale"),
            (|m, _| m.scale = -1.0, "scale"),
            (|m, _| m.scale = 1e-320, "scale"),
            (|m, _| m.scale = f64::INFINITY, "scale"),
            (|m, _| m.scale = f64::NAN, "scale"),
            (|m, _| m.width = 0, "width"),
            (|m, _| m.height = 0, "height"),
            (|m, max| (m.width, m.height) = (max + 1, 1), "width"),
            (|m, max| (m.width, m.height) = (1, max + 1), "height"),
            (
                |m, max| (m.width, m.height) = (max / 2, 3),
                "width × height",
            ),
            // One side at the limit is not the culprit alone: the product is.
            (|m, max| (m.width, m.height) = (max, 2), "width × height"),
            (|m, max| (m.width, m.height) = (2, max), "width × height"),
            (|m, _| (m.width, m.height) = (usize::MAX, 2), "width"),
            (|m, _| (m.width, m.height) = (2, usize::MAX), "height"),
        ];
        for (edit, field) in bad {
            let mut m = ok.clone();
            edit(&mut m, max);
            let e = m.check("export.json").unwrap_err();
            assert_eq!(
                (e.file.as_str(), e.field.as_str()),
                ("export.json", field),
                "{e}"
            );
        }
        for scale in [lo * (1.0 - 1e-15), hi * (1.0 + 1e-15)] {
            let m = Manifest {
                scale,
                ..ok.clone()
            };
            assert_eq!(m.check("export.json").unwrap_err().field, "scale");
        }
    }

    #[test]
    fn flux_probes_scale_the_reference_to_the_mean_irradiance() {
        use std::f64::consts::PI;
        // C-41: unit disk emitter (L = 2 here), receiver disk of radius 0.5.
        let c41 = |view_factor: bool| {
            case(&format!(
                r#"{{"name":"n","teaches":"t","scene":{{"shapes":[
                  {{"geometry":{{"type":"disk","center":[0,0,1],"normal":[0,0,-1],"radius":1}},"emission":{{"radiance":2}}}},
                  {{"geometry":{{"type":"disk","center":[0,0,0],"normal":[0,0,1],"radius":0.5}}}}]}},
                  "measure":{{"flux":{{"shape":1,"view_factor":{view_factor}}}}},"estimators":["mis"]}}"#
            ))
        };
        let Ok(Probe::Flux { shape, area, scale }) = probe(&c41(true)) else {
            panic!("{:?}", probe(&c41(true)));
        };
        assert_eq!(shape, 1);
        assert!((area - PI / 4.0).abs() < 1e-15);
        assert!(
            (scale - PI * 2.0 * PI / (PI / 4.0)).abs() < 1e-12,
            "{scale}"
        );
        let flux = probe(&c41(false)).unwrap();
        assert!((flux.scale() - 4.0 / PI).abs() < 1e-15, "{flux:?}");
        assert_eq!(flux.sensor(), "flux");
        // A receiver (not validated here) of area 0 or +∞ is refused for its area, and
        // one whose scale 1/A₂ falls outside SCALE_RANGE (A₂ = π·10¹²⁰) for its scale.
        let receiver = |radius: &str| {
            let mut c = c41(false);
            let text = serde_json::to_string(&c).unwrap();
            c = case(&text.replace("\"radius\":0.5", &format!("\"radius\":{radius}")));
            probe(&c)
        };
        for (radius, why) in [
            ("0", "its area is not a positive finite number"),
            ("1e200", "its area is not a positive finite number"),
            ("1e60", "is not within [1e-100, 1e100]"),
        ] {
            match receiver(radius) {
                Err(Refusal(r)) => assert!(r.contains(why), "{radius}: {r}"),
                other => panic!("radius {radius}: {other:?}"),
            }
        }
        assert!(
            receiver("1e40").is_ok(),
            "a scale of 1/(π·10⁸⁰) is in range"
        );
    }

    #[test]
    fn areas_follow_the_geometry() {
        use std::f64::consts::PI;
        let g = |json: &str| serde_json::from_str::<GeometryDesc>(json).unwrap();
        let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() <= 1e-13 * b);
        let cases = [
            (
                r#"{"type":"sphere","center":[0,0,0],"radius":2}"#,
                16.0 * PI,
            ),
            // A hemisphere cap: half the sphere.
            (
                r#"{"type":"sphere","center":[0,0,0],"radius":2,"theta_max":90}"#,
                8.0 * PI,
            ),
            (
                r#"{"type":"disk","center":[0,0,0],"normal":[0,0,1],"radius":2,"inner_radius":1}"#,
                3.0 * PI,
            ),
            (
                r#"{"type":"rectangle","corner":[0,0,0],"edge_u":[2,0,0],"edge_v":[0,0,3]}"#,
                6.0,
            ),
            (
                r#"{"type":"triangle","vertices":[[0,0,0],[2,0,0],[0,2,0]]}"#,
                2.0,
            ),
            (
                r#"{"type":"mesh","vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,1]],"indices":[[0,1,2],[0,2,3]]}"#,
                0.5 + 0.5 * 3f64.sqrt(),
            ),
        ];
        for (json, want) in cases {
            assert!(
                close(area(&g(json)), want),
                "{json}: {:?} for {want}",
                area(&g(json))
            );
        }
        let broken =
            g(r#"{"type":"mesh","vertices":[[0,0,0],[1,0,0],[1,1,0]],"indices":[[0,1,7]]}"#);
        assert_eq!(area(&broken), None);
    }
}
