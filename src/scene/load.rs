//! Scene description (JSON) and its validation.
//!
//! ```json
//! {
//!   "materials": { "white": { "type": "lambertian", "albedo": 0.5 } },
//!   "shapes": [
//!     { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
//!       "material": "white", "flip_normals": true,
//!       "emission": { "radiance": 1.0, "two_sided": false } }
//!   ],
//!   "emitters": [ { "type": "point", "position": [0, 0, 2], "intensity": 1 } ]
//! }
//! ```
//! Geometry types: `sphere` (center, radius; with `theta_max` in degrees and an optional
//! `axis`, a spherical cap), `rectangle` (corner, edge_u, edge_v), `disk` (center,
//! normal, radius; with `inner_radius`, an annulus), `triangle` (vertices), `mesh`
//! (vertices, indices),
//! `obj` (path, relative to the scene file). Emitter types: `point` (position,
//! intensity), `spot` (position, direction, intensity, cone_angle, falloff_start in
//! degrees), `directional` (direction of travel, irradiance), `constant` (radiance),
//! `envmap` (path to a lat-long EXR, scale). A shape may carry a `transform`
//! (`scale`, then `rotate` {axis, degrees}, then `translate`). Unknown fields are errors.

use super::dispersion::SpectralIor;
use super::emitter::{Emitter, EmitterKind, EmitterProps, EnvMap, SpotCone, area_distribution};
use super::shape::Primitive;
use super::{Material, Scene, Shape, ShapeKind};
use crate::bsdf::Bsdf;
use crate::error::{
    InputError, MAX_COORDINATE, check_derived, check_direction, check_number, check_point,
};
use crate::spectrum::Spectrum;
use glam::{DQuat, DVec3, Vec3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A scene as written in JSON.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// Named materials.
    #[serde(default)]
    pub materials: BTreeMap<String, Bsdf>,
    /// Shapes.
    #[serde(default)]
    pub shapes: Vec<ShapeDesc>,
    /// Emitters not attached to shapes.
    #[serde(default)]
    pub emitters: Vec<EmitterDesc>,
    /// Wavelength-dependent index of named materials (dispersion):
    /// `{"glass": {"eta": {"sellmeier": {"b": [...], "c": [...]}}}}`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub dispersion: BTreeMap<String, SpectralIor>,
}

/// A shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeDesc {
    /// Optional name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Geometry.
    pub geometry: GeometryDesc,
    /// Material name (none: a black absorber).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Emission, making the shape an area light.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission: Option<EmissionDesc>,
    /// Flip the normals (a sphere lit or seen from inside).
    #[serde(default)]
    pub flip_normals: bool,
    /// Transform applied to the geometry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// Linear velocity (units/s): the shape sits at its position + velocity · t
    /// (time sampled over the case's shutter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<[f64; 3]>,
}

/// Geometry of a shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum GeometryDesc {
    /// Sphere; with `theta_max`, the spherical cap within that polar angle of `axis`
    /// (pbrt's sphere with zmin = radius·cos θmax, zmax = radius, its z along `axis`).
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
        /// Polar half-angle of a cap in degrees, (0, 180]; 180 (or absent) is the sphere.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        theta_max: Option<f64>,
        /// The cap's axis (its pole is centre + radius · axis; default [0, 0, 1]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<[f64; 3]>,
    },
    /// Parallelogram corner + a·edge_u + b·edge_v.
    Rectangle {
        /// Corner.
        corner: [f64; 3],
        /// First edge.
        edge_u: [f64; 3],
        /// Second edge.
        edge_v: [f64; 3],
    },
    /// Disk.
    Disk {
        /// Centre.
        center: [f64; 3],
        /// Normal (normalised on load).
        normal: [f64; 3],
        /// Radius.
        radius: f64,
        /// Radius of a central hole (pbrt's `innerradius`): an annulus; in [0, radius),
        /// default 0.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        inner_radius: Option<f64>,
    },
    /// One triangle.
    Triangle {
        /// Vertices.
        vertices: [[f64; 3]; 3],
    },
    /// Inline triangle mesh.
    Mesh {
        /// Vertex positions.
        vertices: Vec<[f64; 3]>,
        /// Triangles as vertex index triples.
        indices: Vec<[u32; 3]>,
    },
    /// A Wavefront OBJ file (triangulated on load).
    Obj {
        /// Path relative to the scene file.
        path: String,
    },
}

impl GeometryDesc {
    /// A coordinate of the geometry as written (its centre, corner or first vertex);
    /// `None` for an OBJ file (not yet read) or an empty mesh.
    pub fn point(&self) -> Option<[f64; 3]> {
        match self {
            GeometryDesc::Sphere { center, .. } | GeometryDesc::Disk { center, .. } => {
                Some(*center)
            }
            GeometryDesc::Rectangle { corner, .. } => Some(*corner),
            GeometryDesc::Triangle { vertices } => Some(vertices[0]),
            GeometryDesc::Mesh { vertices, .. } => vertices.first().copied(),
            GeometryDesc::Obj { .. } => None,
        }
    }
}

impl ShapeDesc {
    /// The shape's own point (its centre, corner or first vertex; an OBJ's origin) where
    /// its transform places it, R(s p) + t in f64: a scene rebased there keeps the
    /// digits of a shape translated far from the world's origin. `None` where the point
    /// or the transform is not valid (the build names the field).
    pub fn placed_point(&self) -> Option<DVec3> {
        let b = Builder {
            file: "",
            base: PathBuf::new(),
            origin: DVec3::ZERO,
            epoch: 0.0,
        };
        let p = b
            .transform(self.transform.as_ref(), "")
            .ok()?
            .point(self.geometry.point().map_or(DVec3::ZERO, v3));
        p.is_finite().then_some(p)
    }
}

/// Diffuse emission of a shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmissionDesc {
    /// Radiance L (W·sr⁻¹·m⁻²), uniform and Lambertian.
    pub radiance: f64,
    /// Emit from both sides.
    #[serde(default)]
    pub two_sided: bool,
    /// Relative spectrum S(λ): the emitted spectral radiance is radiance · S(λ)
    /// (a number, `{"sampled": …}` or `{"blackbody": {"temperature": T}}`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spectrum: Option<Spectrum>,
    /// Emit one Dirac pulse at this time (s) instead of steadily; `radiance` is then the
    /// time-integrated radiance (J·m⁻²·sr⁻¹).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pulse_at: Option<f64>,
}

/// Scale, then rotate, then translate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    /// Uniform scale.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Rotation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<RotateDesc>,
    /// Translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translate: Option<[f64; 3]>,
}

/// Rotation about an axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    /// Axis (normalised on load).
    pub axis: [f64; 3],
    /// Angle in degrees.
    pub degrees: f64,
}

/// Emitters not attached to shapes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum EmitterDesc {
    /// Isotropic point light.
    Point {
        /// Position.
        position: [f64; 3],
        /// Intensity I (W/sr).
        intensity: f64,
        /// Relative spectrum S(λ).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spectrum: Option<Spectrum>,
        /// Dirac pulse time (s).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pulse_at: Option<f64>,
        /// Linear velocity (units/s): the light sits at position + velocity · t.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        velocity: Option<[f64; 3]>,
    },
    /// Spot light.
    Spot {
        /// Position.
        position: [f64; 3],
        /// Axis direction.
        direction: [f64; 3],
        /// Intensity on the axis.
        intensity: f64,
        /// Total half-angle in degrees.
        cone_angle: f64,
        /// Half-angle where the falloff starts, in degrees.
        falloff_start: f64,
        /// Relative spectrum S(λ).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spectrum: Option<Spectrum>,
        /// Dirac pulse time (s).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pulse_at: Option<f64>,
        /// Linear velocity (units/s).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        velocity: Option<[f64; 3]>,
    },
    /// Distant light.
    Directional {
        /// Direction of travel.
        direction: [f64; 3],
        /// Irradiance on a perpendicular surface.
        irradiance: f64,
        /// Relative spectrum S(λ).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spectrum: Option<Spectrum>,
    },
    /// Constant environment.
    Constant {
        /// Radiance.
        radiance: f64,
        /// Relative spectrum S(λ).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spectrum: Option<Spectrum>,
    },
    /// Lat-long environment map (grey: the mean of R, G, B).
    Envmap {
        /// EXR file, relative to the scene file.
        path: String,
        /// Radiance scale.
        #[serde(default = "one")]
        scale: f64,
        /// Relative spectrum S(λ).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spectrum: Option<Spectrum>,
    },
}

impl EmitterDesc {
    /// The light's linear velocity as written (point and spot lights; lights at infinity
    /// do not move).
    pub fn velocity(&self) -> Option<[f64; 3]> {
        match self {
            EmitterDesc::Point { velocity, .. } | EmitterDesc::Spot { velocity, .. } => *velocity,
            EmitterDesc::Directional { .. }
            | EmitterDesc::Constant { .. }
            | EmitterDesc::Envmap { .. } => None,
        }
    }
}

fn one() -> f64 {
    1.0
}

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// A point after its shape's transform: still within ±[`MAX_COORDINATE`].
/// Whether a triangle placed at `pd` (`f64`), and at `p` once rounded to `f32`, has zero
/// area: the `f64` cross product's length is not positive, or the `f32` cross product
/// vanishes. Only the vector must not vanish in `f32`, not its length: its square
/// underflows for edges below ~10⁻¹⁰, which the hit test handles (README "Planar shapes
/// at every accepted scale"). The rule of a lone `triangle` and of a mesh's triangles.
fn zero_area(pd: &[DVec3; 3], p: &[Vec3; 3]) -> bool {
    !((pd[1] - pd[0]).cross(pd[2] - pd[0]).length() > 0.0)
        || (p[1] - p[0]).cross(p[2] - p[0]) == Vec3::ZERO
}

fn placed(file: &str, field: &str, p: DVec3) -> Result<DVec3, InputError> {
    match p
        .to_array()
        .into_iter()
        .find(|x| !(x.abs() <= MAX_COORDINATE))
    {
        None => Ok(p),
        Some(x) => Err(InputError::new(
            file,
            field,
            format!(
                "after the transform a coordinate is {x:e}, out of range: coordinates must lie within ±{MAX_COORDINATE:e}"
            ),
        )),
    }
}

/// A length after the transform's scale: at most [`MAX_COORDINATE`].
fn length_in_range(file: &str, field: &str, v: f64, scale: f64) -> Result<f64, InputError> {
    let l = v * scale;
    if l <= MAX_COORDINATE {
        Ok(l)
    } else if scale == 1.0 {
        Err(InputError::new(
            file,
            field,
            format!(
                "{v:e} is too large: lengths must be at most {MAX_COORDINATE:e} (its area would overflow f32)"
            ),
        ))
    } else {
        Err(InputError::new(
            file,
            field,
            format!(
                "{v:e} times the transform's scale {scale:e} is {l:e}, too large: lengths must be at most {MAX_COORDINATE:e}"
            ),
        ))
    }
}

/// A shape's `transform`, x ↦ R(s x) + t (scale s, then rotation R, then translation
/// t), applied in `f64`.
#[derive(Clone, Copy, Debug)]
struct Placement {
    scale: f64,
    rot: DQuat,
    tr: DVec3,
}

impl Placement {
    /// Where point `p` lands in world coordinates.
    fn point(&self, p: DVec3) -> DVec3 {
        self.vector(p) + self.tr
    }

    /// A displacement (an edge, a vertex relative to the translation): R(s v), never
    /// translated, so that it keeps its digits however far the shape is moved.
    fn vector(&self, v: DVec3) -> DVec3 {
        self.rot * (v * self.scale)
    }

    /// A unit direction (a normal, an axis): R d, renormalised. The uniform scale
    /// cannot turn it, and leaving it out keeps a tiny scale from underflowing it.
    fn direction(&self, d: DVec3) -> DVec3 {
        (self.rot * d).normalize()
    }
}

/// Where a mesh's triangles come from, for the errors that name them.
#[derive(Clone, Copy)]
enum MeshSource<'a> {
    /// A case's own `vertices` and `indices`.
    Json,
    /// An OBJ file (its faces split into triangles by tobj).
    Obj(&'a std::path::Path),
}

/// Everything needed to turn the f64 description into f32 geometry.
#[derive(Clone)]
struct Builder<'a> {
    file: &'a str,
    base: PathBuf,
    origin: DVec3,
    /// The time t₀ (s) that becomes time 0: the shutter's start.
    epoch: f64,
}

impl Builder<'_> {
    fn to_f32(&self, p: DVec3) -> Vec3 {
        (p - self.origin).as_vec3()
    }

    /// The builder of an object whose `velocity` (field `field`) is v: it is placed where
    /// it is at the epoch t₀, p + v t₀ in f64 (rebased on the origin moved by −v t₀), so
    /// that its motion v τ runs over τ = t − t₀, which f32 resolves however far the
    /// shutter is from t = 0. Returns v (0 for a static object).
    fn moving(&self, field: &str, velocity: Option<[f64; 3]>) -> Result<(Self, Vec3), InputError> {
        let v = match velocity {
            None => DVec3::ZERO,
            Some(v) => check_point(self.file, field, v)?,
        };
        let mut b = self.clone();
        b.origin -= v * self.epoch;
        Ok((b, v.as_vec3()))
    }
}

/// The folder a scene file's relative paths are resolved against: the file's own
/// (the current folder for a bare file name).
pub fn folder_of(scene_file: &Path) -> &Path {
    scene_file.parent().unwrap_or(Path::new("."))
}

impl SceneDesc {
    /// [`SceneDesc::external_files`] resolved as [`SceneDesc::build`] resolves them for
    /// the scene of `scene_file` (against [`folder_of`] it).
    pub fn external_paths(&self, scene_file: &Path) -> Vec<PathBuf> {
        let base = folder_of(scene_file);
        self.external_files()
            .into_iter()
            .map(|f| base.join(f))
            .collect()
    }

    /// The external files the scene reads, as written (relative to the scene file's
    /// folder, where [`SceneDesc::build`] resolves them): each OBJ shape's and each
    /// environment map's `path`, in the order of the description.
    pub fn external_files(&self) -> Vec<&str> {
        let shapes = self.shapes.iter().filter_map(|s| match &s.geometry {
            GeometryDesc::Obj { path } => Some(path.as_str()),
            GeometryDesc::Sphere { .. }
            | GeometryDesc::Disk { .. }
            | GeometryDesc::Rectangle { .. }
            | GeometryDesc::Triangle { .. }
            | GeometryDesc::Mesh { .. } => None,
        });
        let emitters = self.emitters.iter().filter_map(|e| match e {
            EmitterDesc::Envmap { path, .. } => Some(path.as_str()),
            EmitterDesc::Point { .. }
            | EmitterDesc::Spot { .. }
            | EmitterDesc::Directional { .. }
            | EmitterDesc::Constant { .. } => None,
        });
        shapes.chain(emitters).collect()
    }

    /// Where shape `i`'s own point lands ([`ShapeDesc::placed_point`]), or
    /// [`SceneDesc::any_point`] when it has none.
    pub fn shape_point(&self, i: usize) -> DVec3 {
        self.shapes
            .get(i)
            .and_then(ShapeDesc::placed_point)
            .unwrap_or_else(|| self.any_point())
    }

    /// The first shape's placed point that is valid (used as a default origin), else 0.
    pub fn any_point(&self) -> DVec3 {
        self.shapes
            .iter()
            .find_map(ShapeDesc::placed_point)
            .unwrap_or(DVec3::ZERO)
    }

    /// Validate and build, with every position rebased on `origin` (in f64) before it
    /// becomes f32, and time on `epoch`: a moving object is placed where it is at
    /// t = `epoch` (in f64), and the scene's time 0 is that instant (a case's shutter
    /// start, [`crate::case::build::epoch`]). `file` names the file in errors; relative
    /// paths resolve against `base`.
    pub fn build(
        &self,
        file: &str,
        field: &str,
        base: &Path,
        origin: DVec3,
        epoch: f64,
    ) -> Result<Scene, InputError> {
        self.build_over(file, field, base, origin, epoch, crate::spectrum::VISIBLE)
    }

    /// [`SceneDesc::build`] with every dispersive index checked over `band` (nm), the
    /// wavelengths the scene is measured at: a case's `spectral` band (or its one
    /// wavelength), the visible range for an image. A Sellmeier pole at 600 nm was once
    /// refused as inside [360, 830] nm when the case measured [400, 500] nm.
    pub fn build_over(
        &self,
        file: &str,
        field: &str,
        base: &Path,
        origin: DVec3,
        epoch: f64,
        band: crate::spectrum::Band,
    ) -> Result<Scene, InputError> {
        let b = Builder {
            file,
            base: base.to_path_buf(),
            origin,
            epoch,
        };
        let mut materials: Vec<Material> = Vec::new();
        let mut material_index = BTreeMap::new();
        for (name, m) in &self.materials {
            m.validate().map_err(|r| {
                InputError::new(
                    file,
                    format!("{field}.materials.{name}.{}", r.field),
                    r.reason,
                )
            })?;
            material_index.insert(name.clone(), materials.len());
            materials.push(Material::grey(m.clone()));
        }
        for (name, d) in &self.dispersion {
            let f = format!("{field}.dispersion.{name}");
            let &m = material_index.get(name).ok_or_else(|| {
                InputError::new(
                    file,
                    &f,
                    format!("no material named `{name}` in `materials`"),
                )
            })?;
            let material = &mut materials[m];
            d.validate(&material.bsdf, band)
                .map_err(|(path, r)| InputError::new(file, format!("{f}{path}"), r))?;
            if d.is_dispersive() {
                material.ior = Some(d.clone());
            } else {
                // A constant index is just the grey material.
                material.bsdf = d.at(&material.bsdf, 550.0);
            }
        }
        let mut prims = Vec::new();
        let mut shapes = Vec::new();
        let mut emitters = Vec::new();
        let mut props = Vec::new();
        for (i, s) in self.shapes.iter().enumerate() {
            let f = format!("{field}.shapes[{i}]");
            let start = prims.len();
            let (bs, velocity) = b.moving(&format!("{f}.velocity"), s.velocity)?;
            let kind = bs.geometry(&s.geometry, s.transform.as_ref(), &f, &mut prims)?;
            let range = start..prims.len();
            let material = match &s.material {
                None => None,
                Some(name) => Some(*material_index.get(name).ok_or_else(|| {
                    InputError::new(
                        file,
                        format!("{f}.material"),
                        format!("no material named `{name}` in `materials`"),
                    )
                })?),
            };
            let emitter = match &s.emission {
                None => None,
                Some(e) => {
                    check_number(
                        file,
                        &format!("{f}.emission.radiance"),
                        e.radiance,
                        |x| x >= 0.0,
                        "a non-negative radiance",
                    )?;
                    let (p, scale) = b.props(
                        &format!("{f}.emission"),
                        e.spectrum.as_ref(),
                        e.pulse_at,
                        None,
                    )?;
                    let radiance =
                        b.strength(&format!("{f}.emission.radiance"), e.radiance, scale, &p)?;
                    props.push(p);
                    emitters.push(EmitterKind::Area {
                        shape: shapes.len(),
                        radiance,
                        two_sided: e.two_sided,
                    });
                    Some(emitters.len() - 1)
                }
            };
            let area_dist = area_distribution(&prims[range.clone()]);
            let area = prims[range.clone()].iter().map(|p| p.area()).sum::<f32>();
            if !area.is_finite() {
                return Err(InputError::new(
                    file,
                    format!("{f}.geometry"),
                    "is too large: its area overflows f32 (keep lengths well below 1e18)",
                ));
            }
            // A subnormal area (a sphere of radius 10⁻²⁰: 1.3·10⁻³⁹) has no finite f32
            // area density 1/A beside it: every area sample would be NaN.
            if !(area >= f32::MIN_POSITIVE) {
                return Err(InputError::new(
                    file,
                    format!("{f}.geometry"),
                    format!(
                        "is degenerate: its area {area:e} is zero or too small for f32 (below {:e})",
                        f32::MIN_POSITIVE
                    ),
                ));
            }
            if let Some(EmitterKind::Area {
                radiance,
                two_sided,
                ..
            }) = emitter.map(|i| &emitters[i])
            {
                let sides = if *two_sided { 2.0 } else { 1.0 };
                check_derived(
                    file,
                    &format!("{f}.emission.radiance"),
                    *radiance as f64 * std::f64::consts::PI * area as f64 * sides,
                    "the emitted power π·L·area",
                )?;
            }
            shapes.push(Shape {
                name: s.name.clone(),
                prims: range,
                area,
                area_dist,
                material,
                emitter,
                flip_normals: s.flip_normals,
                kind,
                velocity,
            });
        }
        for (i, e) in self.emitters.iter().enumerate() {
            let f = format!("{field}.emitters[{i}]");
            let (be, _) = b.moving(&format!("{f}.velocity"), e.velocity())?;
            let (e, p) = be.emitter(e, &f)?;
            emitters.push(e);
            props.push(p);
        }
        let emitters = emitters
            .into_iter()
            .zip(props)
            .map(|(kind, props)| Emitter { kind, props })
            .collect();
        Ok(Scene::new(shapes, prims, materials, emitters))
    }
}

impl Builder<'_> {
    fn transform(&self, t: Option<&TransformDesc>, f: &str) -> Result<Placement, InputError> {
        let mut pl = Placement {
            scale: 1.0,
            rot: DQuat::IDENTITY,
            tr: DVec3::ZERO,
        };
        if let Some(t) = t {
            if let Some(s) = t.scale {
                check_number(
                    self.file,
                    &format!("{f}.transform.scale"),
                    s,
                    |x| x > 0.0,
                    "a positive scale",
                )?;
                pl.scale = s;
            }
            if let Some(r) = &t.rotate {
                let axis =
                    check_direction(self.file, &format!("{f}.transform.rotate.axis"), r.axis)?;
                check_number(
                    self.file,
                    &format!("{f}.transform.rotate.degrees"),
                    r.degrees,
                    |_| true,
                    "finite",
                )?;
                pl.rot = DQuat::from_axis_angle(axis, r.degrees.to_radians());
            }
            if let Some(t) = t.translate {
                pl.tr = check_point(self.file, &format!("{f}.transform.translate"), t)?;
            }
        }
        Ok(pl)
    }

    /// Point `p` of a shape (field `field`) placed by `pl`, checked to lie within
    /// [`MAX_COORDINATE`] of the world's origin, and returned rebased on the scene's
    /// origin: R(s p) + (t − origin), so that a shape translated far from the world's
    /// origin keeps the digits of its own coordinates where the scene is measured
    /// (R(s p) + t would round them to the ulp of t first).
    fn place(&self, field: &str, pl: &Placement, p: DVec3) -> Result<DVec3, InputError> {
        placed(self.file, field, pl.point(p))?;
        Ok(pl.vector(p) + (pl.tr - self.origin))
    }

    /// A sphere's cap: (axis as placed, cos θmax, 1 − cos θmax), or `None` for the
    /// whole sphere (no `theta_max`; 180° is a cap that covers it all, as exact).
    fn cap(
        &self,
        gf: &str,
        theta_max: Option<f64>,
        axis: Option<[f64; 3]>,
        pl: &Placement,
    ) -> Result<Option<(Vec3, f32, f32)>, InputError> {
        let file = self.file;
        let a = match axis {
            None => DVec3::Z,
            Some(a) => check_direction(file, &format!("{gf}.axis"), a)?,
        };
        let Some(t) = theta_max else {
            if axis.is_some() {
                return Err(InputError::new(
                    file,
                    format!("{gf}.axis"),
                    "an axis needs a `theta_max` (the cap's polar half-angle in degrees)",
                ));
            }
            return Ok(None);
        };
        check_number(
            file,
            &format!("{gf}.theta_max"),
            t,
            |t| t > 0.0 && t <= 180.0,
            "a polar angle in (0, 180] degrees",
        )?;
        let half = 0.5 * t.to_radians();
        let one_minus_cos = 2.0 * half.sin() * half.sin();
        if !(one_minus_cos as f32 > 0.0) {
            return Err(InputError::new(
                file,
                format!("{gf}.theta_max"),
                format!("{t:e} degrees is too small: the cap's area underflows f32"),
            ));
        }
        let axis2 = pl.direction(a);
        Ok(Some((
            axis2.as_vec3(),
            (1.0 - one_minus_cos) as f32,
            one_minus_cos as f32,
        )))
    }

    fn geometry(
        &self,
        g: &GeometryDesc,
        t: Option<&TransformDesc>,
        f: &str,
        prims: &mut Vec<Primitive>,
    ) -> Result<ShapeKind, InputError> {
        let pl = self.transform(t, f)?;
        let file = self.file;
        let scale = pl.scale;
        let gf = format!("{f}.geometry");
        match g {
            GeometryDesc::Sphere {
                center,
                radius,
                theta_max,
                axis,
            } => {
                let c = check_point(file, &format!("{gf}.center"), *center)?;
                check_number(
                    file,
                    &format!("{gf}.radius"),
                    *radius,
                    |r| r > 0.0,
                    "a positive radius",
                )?;
                let r = length_in_range(file, &format!("{gf}.radius"), *radius, scale)?;
                let c2 = self.place(&format!("{gf}.center"), &pl, c)?;
                if let Some(cap) = self.cap(&gf, *theta_max, *axis, &pl)? {
                    prims.push(Primitive::SphericalCap {
                        center: c2.as_vec3(),
                        radius: r as f32,
                        axis: cap.0,
                        cos_max: cap.1,
                        one_minus_cos: cap.2,
                    });
                    // An open cap can see itself from inside: never closed or convex.
                    return Ok(ShapeKind::Mesh);
                }
                prims.push(Primitive::Sphere {
                    center: c2.as_vec3(),
                    radius: r as f32,
                });
                Ok(ShapeKind::Sphere)
            }
            GeometryDesc::Rectangle {
                corner,
                edge_u,
                edge_v,
            } => {
                let c = check_point(file, &format!("{gf}.corner"), *corner)?;
                let u = check_point(file, &format!("{gf}.edge_u"), *edge_u)?;
                let v = check_point(file, &format!("{gf}.edge_v"), *edge_v)?;
                if !(u.cross(v).length() > 0.0) {
                    return Err(InputError::new(
                        file,
                        gf,
                        "is degenerate: edge_u and edge_v are parallel or zero",
                    ));
                }
                // The far corners only need to be in range: the edges are placed as
                // displacements, R(s u), never as differences of placed points.
                let c2 = self.place(&format!("{gf}.corner"), &pl, c)?;
                placed(file, &format!("{gf}.edge_u"), pl.point(c + u))?;
                placed(file, &format!("{gf}.edge_v"), pl.point(c + v))?;
                prims.push(Primitive::Rectangle {
                    corner: c2.as_vec3(),
                    u: pl.vector(u).as_vec3(),
                    v: pl.vector(v).as_vec3(),
                });
                Ok(ShapeKind::Planar)
            }
            GeometryDesc::Disk {
                center,
                normal,
                radius,
                inner_radius,
            } => {
                let c = check_point(file, &format!("{gf}.center"), *center)?;
                let n = check_direction(file, &format!("{gf}.normal"), *normal)?;
                check_number(
                    file,
                    &format!("{gf}.radius"),
                    *radius,
                    |r| r > 0.0,
                    "a positive radius",
                )?;
                let r = length_in_range(file, &format!("{gf}.radius"), *radius, scale)?;
                let c2 = self.place(&format!("{gf}.center"), &pl, c)?;
                let n2 = pl.direction(n);
                let inner = match *inner_radius {
                    None => 0.0,
                    Some(ri) => {
                        let field = format!("{gf}.inner_radius");
                        check_number(
                            file,
                            &field,
                            ri,
                            |x| x >= 0.0 && x < *radius,
                            &format!("an inner radius in [0, radius = {radius})"),
                        )?;
                        (ri * scale) as f32
                    }
                };
                if inner > 0.0 && inner < r as f32 {
                    prims.push(Primitive::Annulus {
                        center: c2.as_vec3(),
                        normal: n2.as_vec3(),
                        inner,
                        radius: r as f32,
                    });
                    return Ok(ShapeKind::Planar);
                }
                if inner > 0.0 {
                    return Err(InputError::new(
                        file,
                        format!("{gf}.inner_radius"),
                        format!(
                            "{ri:e} is too close to the radius {radius:e} for f32: the annulus would have no area",
                            ri = inner_radius.unwrap_or(0.0)
                        ),
                    ));
                }
                prims.push(Primitive::Disk {
                    center: c2.as_vec3(),
                    normal: n2.as_vec3(),
                    radius: r as f32,
                });
                Ok(ShapeKind::Planar)
            }
            GeometryDesc::Triangle { vertices } => {
                let mut pd = [DVec3::ZERO; 3];
                for (k, v) in vertices.iter().enumerate() {
                    let field = format!("{gf}.vertices[{k}]");
                    pd[k] = self.place(&field, &pl, check_point(file, &field, *v)?)?;
                }
                let p = pd.map(DVec3::as_vec3);
                if zero_area(&pd, &p) {
                    return Err(InputError::new(
                        file,
                        gf,
                        "is degenerate: the triangle has zero area",
                    ));
                }
                prims.push(Primitive::Triangle { p });
                Ok(ShapeKind::Planar)
            }
            GeometryDesc::Mesh { vertices, indices } => {
                let vs: Vec<DVec3> = vertices
                    .iter()
                    .enumerate()
                    .map(|(k, v)| {
                        let field = format!("{gf}.vertices[{k}]");
                        self.place(&field, &pl, check_point(file, &field, *v)?)
                    })
                    .collect::<Result<_, _>>()?;
                self.mesh(&vs, indices, &gf, MeshSource::Json, prims)
            }
            GeometryDesc::Obj { path } => {
                let full = self.base.join(path);
                let field = format!("{gf}.path");
                // Read once, checked (a regular file within the asset limit), and parsed
                // from memory: the OBJ's `mtllib` lines name files tobj would otherwise
                // open itself, unchecked (`/dev/zero`, a FIFO); materials are a scene's
                // own, so none is read.
                let text =
                    crate::io::read_input(&full, crate::io::MAX_ASSET_BYTES).map_err(|r| {
                        InputError::new(file, &field, format!("OBJ `{}` {r}", full.display()))
                    })?;
                let opts = tobj::LoadOptions {
                    triangulate: true,
                    single_index: true,
                    // Points and lines are no surfaces (tobj would make them zero-area
                    // triangles).
                    ignore_points: true,
                    ignore_lines: true,
                };
                let (models, _) =
                    tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| Ok(Default::default()))
                        .map_err(|e| {
                            InputError::new(
                                file,
                                &field,
                                format!("cannot read OBJ `{}`: {e}", full.display()),
                            )
                        })?;
                let mut all = Vec::new();
                let mut idx = Vec::new();
                for m in models {
                    let base = all.len() as u32;
                    for c in m.mesh.positions.chunks(3) {
                        let p = [c[0] as f64, c[1] as f64, c[2] as f64];
                        all.push(self.place(&field, &pl, check_point(file, &field, p)?)?);
                    }
                    for t in m.mesh.indices.chunks(3) {
                        idx.push([base + t[0], base + t[1], base + t[2]]);
                    }
                }
                let source = MeshSource::Obj(&full);
                self.mesh(&all, &idx, &gf, source, prims)
            }
        }
    }

    /// A mesh of the placed vertices `vs` (rebased on the scene's origin, see
    /// [`Builder::place`]) and their triangles, read from `source` (which an error names).
    fn mesh(
        &self,
        vs: &[DVec3],
        indices: &[[u32; 3]],
        gf: &str,
        source: MeshSource,
        prims: &mut Vec<Primitive>,
    ) -> Result<ShapeKind, InputError> {
        let bad = |k: Option<usize>, why: String| match source {
            MeshSource::Json => InputError::new(
                self.file,
                match k {
                    Some(k) => format!("{gf}.indices[{k}]"),
                    None => format!("{gf}.indices"),
                },
                why,
            ),
            MeshSource::Obj(path) => InputError::new(
                self.file,
                format!("{gf}.path"),
                match k {
                    Some(k) => format!(
                        "OBJ `{}`: triangle {k} (counting from 0, polygons split into triangles) {why}",
                        path.display()
                    ),
                    None => format!("OBJ `{}`: {why}", path.display()),
                },
            ),
        };
        if indices.is_empty() {
            return Err(bad(None, "a mesh needs at least one triangle".into()));
        }
        let mut normal: Option<DVec3> = None;
        let mut planar = true;
        for (k, t) in indices.iter().enumerate() {
            let mut p = [Vec3::ZERO; 3];
            let mut pd = [DVec3::ZERO; 3];
            for j in 0..3 {
                let i = t[j] as usize;
                let v = vs.get(i).ok_or_else(|| {
                    bad(
                        Some(k),
                        format!(
                            "vertex index {i} is out of range (the mesh has {} vertices)",
                            vs.len()
                        ),
                    )
                })?;
                pd[j] = *v;
                p[j] = v.as_vec3();
            }
            if zero_area(&pd, &p) {
                return Err(bad(Some(k), "is a degenerate triangle (zero area)".into()));
            }
            let n = (pd[1] - pd[0]).cross(pd[2] - pd[0]).normalize();
            match normal {
                None => normal = Some(n),
                Some(m) => {
                    if m.dot(n) < 1.0 - 1e-9
                        || (pd[0] - vs[indices[0][0] as usize]).dot(m).abs()
                            > 1e-9 * (1.0 + pd[0].length())
                    {
                        planar = false;
                    }
                }
            }
            prims.push(Primitive::Triangle { p });
        }
        Ok(if planar {
            ShapeKind::Planar
        } else {
            ShapeKind::Mesh
        })
    }

    /// An emitter's strength (radiance, intensity, irradiance) times its constant
    /// spectrum, as `f32`: the product must fit, and so must its product with the peak
    /// of a varying spectrum.
    fn strength(
        &self,
        field: &str,
        value: f64,
        scale: f64,
        props: &EmitterProps,
    ) -> Result<f32, InputError> {
        let v = value * scale;
        if let Some(why) = crate::error::f32_problem(v) {
            return Err(InputError::new(
                self.file,
                field,
                format!("times the constant spectrum ({scale}) is {v:e}, which {why}"),
            ));
        }
        if let Some(s) = &props.spectrum {
            let peak = s.max_in(crate::spectrum::Band::new(1.0, 1e7)) as f64;
            if peak >= f32::MAX as f64 {
                return Err(InputError::new(
                    self.file,
                    field,
                    "the spectrum's peak overflows f32: use a smaller scale",
                ));
            }
            check_derived(
                self.file,
                field,
                v * peak,
                "this value times the spectrum's peak",
            )?;
        }
        Ok(v as f32)
    }

    /// Validate an emitter's spectrum, pulse and velocity. A constant spectrum folds
    /// into the emitter's strength: the returned factor multiplies it.
    fn props(
        &self,
        f: &str,
        spectrum: Option<&Spectrum>,
        pulse_at: Option<f64>,
        velocity: Option<[f64; 3]>,
    ) -> Result<(EmitterProps, f64), InputError> {
        let file = self.file;
        let mut props = EmitterProps::default();
        let mut scale = 1.0;
        if let Some(s) = spectrum {
            s.validate_at()
                .map_err(|(at, r)| InputError::new(file, format!("{f}.spectrum{at}"), r))?;
            match s {
                Spectrum::Constant(c) => scale = *c as f64,
                s => props.spectrum = Some(s.clone()),
            }
        }
        if let Some(t) = pulse_at {
            check_number(
                file,
                &format!("{f}.pulse_at"),
                t,
                |_| true,
                "a finite time in seconds",
            )?;
            props.pulse = Some(t);
        }
        if let Some(v) = velocity {
            props.velocity = check_point(file, &format!("{f}.velocity"), v)?.as_vec3();
        }
        Ok((props, scale))
    }

    fn emitter(&self, e: &EmitterDesc, f: &str) -> Result<(EmitterKind, EmitterProps), InputError> {
        let file = self.file;
        let nonneg = |name: &str, v: f64| {
            check_number(
                file,
                &format!("{f}.{name}"),
                v,
                |x| x >= 0.0,
                "non-negative",
            )
        };
        // A point or spot light's intensity, representable, with a finite power 4π·I.
        let intensity_of = |raw: f64, scale: f64, p: &EmitterProps, what: &str| {
            let field = format!("{f}.intensity");
            let intensity = self.strength(&field, raw, scale, p)?;
            check_derived(
                file,
                &field,
                4.0 * std::f64::consts::PI * intensity as f64,
                what,
            )?;
            Ok::<f32, InputError>(intensity)
        };
        Ok(match e {
            EmitterDesc::Point {
                position,
                intensity,
                spectrum,
                pulse_at,
                velocity,
            } => {
                nonneg("intensity", *intensity)?;
                let (p, scale) = self.props(f, spectrum.as_ref(), *pulse_at, *velocity)?;
                let intensity = intensity_of(*intensity, scale, &p, "the emitted power 4π·I")?;
                (
                    EmitterKind::Point {
                        position: self.to_f32(check_point(
                            file,
                            &format!("{f}.position"),
                            *position,
                        )?),
                        intensity,
                    },
                    p,
                )
            }
            EmitterDesc::Spot {
                position,
                direction,
                intensity,
                cone_angle,
                falloff_start,
                spectrum,
                pulse_at,
                velocity,
            } => {
                nonneg("intensity", *intensity)?;
                let (p, scale) = self.props(f, spectrum.as_ref(), *pulse_at, *velocity)?;
                check_number(
                    file,
                    &format!("{f}.cone_angle"),
                    *cone_angle,
                    |x| x > 0.0 && x <= 180.0,
                    "in (0, 180] degrees",
                )?;
                check_number(
                    file,
                    &format!("{f}.falloff_start"),
                    *falloff_start,
                    |x| x >= 0.0 && x <= *cone_angle,
                    "in [0, cone_angle] degrees",
                )?;
                let d = check_direction(file, &format!("{f}.direction"), *direction)?;
                let intensity =
                    intensity_of(*intensity, scale, &p, "the emitted power (at most 4π·I)")?;
                (
                    EmitterKind::Spot {
                        position: self.to_f32(check_point(
                            file,
                            &format!("{f}.position"),
                            *position,
                        )?),
                        intensity,
                        cone: SpotCone::new(d, cone_angle.to_radians(), falloff_start.to_radians()),
                    },
                    p,
                )
            }
            EmitterDesc::Directional {
                direction,
                irradiance,
                spectrum,
            } => {
                nonneg("irradiance", *irradiance)?;
                let (p, scale) = self.props(f, spectrum.as_ref(), None, None)?;
                (
                    EmitterKind::Directional {
                        direction: check_direction(file, &format!("{f}.direction"), *direction)?
                            .as_vec3(),
                        irradiance: self.strength(
                            &format!("{f}.irradiance"),
                            *irradiance,
                            scale,
                            &p,
                        )?,
                    },
                    p,
                )
            }
            EmitterDesc::Constant { radiance, spectrum } => {
                nonneg("radiance", *radiance)?;
                let (p, scale) = self.props(f, spectrum.as_ref(), None, None)?;
                let field = format!("{f}.radiance");
                let radiance = self.strength(&field, *radiance, scale, &p)?;
                check_derived(
                    file,
                    &field,
                    4.0 * std::f64::consts::PI * radiance as f64,
                    "the radiance integrated over the sphere, 4π·L,",
                )?;
                (EmitterKind::Constant { radiance }, p)
            }
            EmitterDesc::Envmap {
                path,
                scale,
                spectrum,
            } => {
                nonneg("scale", *scale)?;
                let (p, spectral_scale) = self.props(f, spectrum.as_ref(), None, None)?;
                let scale = &(*scale * spectral_scale);
                let full = self.base.join(path);
                let (w, h, data) = read_exr_grey(&full)
                    .map_err(|r| InputError::new(file, format!("{f}.path"), r))?;
                if let Some(bad) = data.iter().find(|v| !v.is_finite() || **v < 0.0) {
                    return Err(InputError::new(
                        file,
                        format!("{f}.path"),
                        format!("holds a negative or non-finite radiance ({bad})"),
                    ));
                }
                let field = format!("{f}.scale");
                let scale = self.strength(&field, *scale, 1.0, &p)?;
                let peak = data.iter().fold(0.0f32, |m, &v| m.max(v)) as f64;
                let sum: f64 = data.iter().map(|&v| v as f64).sum();
                check_derived(
                    file,
                    &field,
                    peak * scale as f64,
                    "the map's brightest pixel × scale",
                )?;
                check_derived(
                    file,
                    &field,
                    4.0 * std::f64::consts::PI * sum * scale as f64,
                    "the map's total radiance × 4π × scale",
                )?;
                (
                    EmitterKind::Map(Box::new(EnvMap::new(
                        w,
                        h,
                        data.into_iter().map(|v| v * scale).collect(),
                    ))),
                    p,
                )
            }
        })
    }
}

/// Largest environment map: 2²⁶ pixels (64 Mpixel, e.g. 11585 × 5792).
pub const MAX_ENVMAP_PIXELS: usize = 1 << 26;

/// Read an EXR's first RGBA layer as grey values (mean of R, G, B). Before anything is
/// allocated the file must be a regular file of at most [`crate::io::MAX_ASSET_BYTES`],
/// its header must claim at most [`MAX_ENVMAP_PIXELS`] pixels, and the file must be long
/// enough to hold the header's chunk offset table (a 200-byte file claiming 200000²
/// pixels is refused, not allocated). Every channel of every pixel must be finite and
/// non-negative (not only their mean).
pub fn read_exr_grey(path: &Path) -> Result<(usize, usize, Vec<f32>), String> {
    use exr::prelude::*;
    let name = path.display();
    let len = crate::io::check_input_file(path, crate::io::MAX_ASSET_BYTES)
        .map_err(|r| format!("EXR `{name}` {r}"))?;
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| format!("cannot read EXR `{name}`: {e}"))?;
    let Some(header) = meta.headers.first() else {
        return Err(format!("EXR `{name}` has no layer"));
    };
    let (w, h) = (header.layer_size.width(), header.layer_size.height());
    let pixels = w.checked_mul(h).filter(|&n| n <= MAX_ENVMAP_PIXELS);
    if pixels.is_none() {
        return Err(format!(
            "EXR `{name}` claims {w} × {h} pixels, more than the limit of {MAX_ENVMAP_PIXELS} (64 Mpixel)"
        ));
    }
    let table: u64 = meta.headers.iter().map(|h| h.chunk_count as u64 * 8).sum();
    if table > len {
        return Err(format!(
            "EXR `{name}` is truncated or corrupt: its header claims {w} × {h} pixels in {} chunks, but the file is only {len} bytes",
            header.chunk_count
        ));
    }
    type Bad = Option<(usize, usize, f32)>;
    let image = read_first_rgba_layer_from_file(
        path,
        |res, _| -> (usize, usize, Vec<f32>, Bad) {
            let n = res
                .width()
                .saturating_mul(res.height())
                .min(MAX_ENVMAP_PIXELS);
            (res.width(), res.height(), vec![0.0f32; n], None)
        },
        |(w, _, data, bad), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            if bad.is_none()
                && let Some(c) = [r, g, b]
                    .into_iter()
                    .find(|c| !(c.is_finite() && *c >= 0.0))
            {
                *bad = Some((pos.x(), pos.y(), c));
            }
            if let Some(v) = data.get_mut(pos.y() * *w + pos.x()) {
                *v = (r + g + b) / 3.0;
            }
        },
    )
    .map_err(|e| format!("cannot read EXR `{name}`: {e}"))?;
    let (w, h, data, bad) = image.layer_data.channel_data.pixels;
    if w == 0 || h == 0 || data.len() != w * h {
        return Err(format!("EXR `{name}` is empty"));
    }
    if let Some((x, y, c)) = bad {
        return Err(format!(
            "holds a negative or non-finite radiance: pixel ({x}, {y}) has a channel {c}"
        ));
    }
    Ok((w, h, data))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// Every kind of shape, with a transform of rotation and scale and, if `far`, a
    /// translation to (10¹⁷, −10¹⁷, 10¹⁷), where f64 coordinates are 16 apart.
    fn shapes(far: bool) -> SceneDesc {
        let mut t = json!({ "rotate": { "axis": [1, 2, 3], "degrees": 37 }, "scale": 0.75 });
        if far {
            t["translate"] = json!([1e17, -1e17, 1e17]);
        }
        let shape = |g: serde_json::Value| json!({ "geometry": g, "transform": t.clone() });
        serde_json::from_value(json!({ "shapes": [
            shape(json!({ "type": "sphere", "center": [0.25, -0.5, 1], "radius": 0.5,
                          "theta_max": 60, "axis": [1, 1, 0] })),
            shape(json!({ "type": "rectangle", "corner": [-0.5, -0.75, 1],
                          "edge_u": [0, 1.5, 0], "edge_v": [1, 0, 0.25] })),
            shape(json!({ "type": "disk", "center": [0.5, 0, -1], "normal": [0, 1, -1],
                          "radius": 0.5, "inner_radius": 0.125 })),
            shape(json!({ "type": "triangle",
                          "vertices": [[0, 0, 2], [1, 0, 2], [0, 1, 2.5]] })),
            shape(json!({ "type": "mesh", "vertices": [[0, 0, 3], [1, 0, 3], [0, 1, 3], [1, 1, 3.5]],
                          "indices": [[0, 1, 2], [1, 3, 2]] })),
        ]}))
        .unwrap()
    }

    /// A moving object is placed where it is at the epoch (p + v t₀ in f64, rebased on
    /// the origin): a sphere and a point light written at their t = 0 positions, built
    /// at t₀ = 10⁶ s, sit exactly where they are then; a static shape does not move.
    #[test]
    fn moving_objects_are_placed_at_the_epoch() {
        let d: SceneDesc = serde_json::from_value(json!({
            "shapes": [
                { "geometry": { "type": "sphere", "center": [-2000000.5, 0, 1], "radius": 0.25 },
                  "velocity": [2, 0, 0] },
                { "geometry": { "type": "sphere", "center": [0, 3, 1], "radius": 0.25 } } ],
            "emitters": [ { "type": "point", "position": [0, -500000, 2], "intensity": 3,
                            "velocity": [0, 0.5, 0] } ] }))
        .unwrap();
        let origin = DVec3::new(0.0, 0.0, 0.5);
        let s = d
            .build("t.json", "scene", Path::new("."), origin, 1e6)
            .unwrap();
        let centre = |i: usize| match s.prims()[s.shapes[i].prims.start] {
            Primitive::Sphere { center, .. } => center,
            ref p => panic!("{p:?}"),
        };
        assert_eq!(centre(0), Vec3::new(-0.5, 0.0, 0.5));
        assert_eq!(centre(1), Vec3::new(0.0, 3.0, 0.5));
        let EmitterKind::Point { position, .. } = s.emitters[0].kind else {
            panic!("a point light")
        };
        assert_eq!(position, Vec3::new(0.0, 0.0, 1.5));
        assert_eq!(s.shapes[0].velocity, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(s.emitters[0].props.velocity, Vec3::new(0.0, 0.5, 0.0));
    }

    /// The origin a case rebases on is a shape's point where its transform places it
    /// (R(s p) + t), not where the description writes it: a flux receiver translated to
    /// 10¹⁷ was once rebased on its untransformed centre, every coordinate 10¹⁷ in f32
    /// (the catalog's `view_factor/coaxial_disks_translated_1e17` read 0 for 0.117).
    #[test]
    fn a_shapes_point_is_placed_by_its_transform() {
        let scene = |shapes: serde_json::Value| -> SceneDesc {
            serde_json::from_value(json!({ "shapes": shapes })).unwrap()
        };
        let rect = json!({ "type": "rectangle", "corner": [1, 0, 0],
                           "edge_u": [1, 0, 0], "edge_v": [0, 1, 0] });
        let t = json!({ "scale": 2, "rotate": { "axis": [0, 0, 1], "degrees": 90 },
                        "translate": [1e17, 0, 3] });
        let s = scene(json!([{ "geometry": rect, "transform": t }]));
        let p = s.shape_point(0);
        assert!(
            (p - DVec3::new(1e17, 2.0, 3.0)).length() < 1e-15 * 1e17,
            "{p}"
        );
        assert_eq!(s.any_point(), p);
        // An OBJ's point is its own origin, placed; no transform leaves a point as written.
        let obj = scene(json!([{ "geometry": { "type": "obj", "path": "m.obj" },
                                 "transform": { "translate": [5, 6, 7] } },
                               { "geometry": rect }]));
        assert_eq!(obj.shape_point(0), DVec3::new(5.0, 6.0, 7.0));
        assert_eq!(obj.shape_point(1), DVec3::new(1.0, 0.0, 0.0));
        // An invalid transform or point has none: the first valid shape's point, else 0;
        // a shape that does not exist falls back the same way.
        let bad = scene(json!([{ "geometry": rect, "transform": { "scale": -1 } },
                               { "geometry": rect, "transform": { "translate": [0, 0, 2] } }]));
        assert_eq!(bad.shape_point(0), DVec3::new(1.0, 0.0, 2.0));
        assert_eq!(bad.shape_point(7), DVec3::new(1.0, 0.0, 2.0));
        let huge = json!({ "type": "sphere", "center": [1e308, 0, 0], "radius": 1 });
        let none = scene(json!([{ "geometry": huge, "transform": { "scale": 10 } }]));
        assert_eq!(none.any_point(), DVec3::ZERO);
    }

    /// A shape translated far from the world's origin, rebased on a point there, is the
    /// same `f32` geometry bit for bit as the untranslated shape rebased on the origin:
    /// positions are placed as R(s p) + (t − origin) and edges, normals and axes as
    /// displacements or directions, never as differences of rounded world points (which
    /// turned a unit normal or edge 10¹⁷ from the origin into 0 or 16).
    #[test]
    fn placement_far_from_the_origin_keeps_every_digit() {
        let far = shapes(true)
            .build(
                "t.json",
                "scene",
                Path::new("."),
                DVec3::new(1e17, -1e17, 1e17),
                0.0,
            )
            .unwrap();
        let near = shapes(false)
            .build("t.json", "scene", Path::new("."), DVec3::ZERO, 0.0)
            .unwrap();
        assert_eq!(far.prims().len(), 6);
        assert_eq!(far.prims(), near.prims());
        // The rotation and scale are applied: the rectangle's edge u is R(0.75 u).
        let rot = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 37f64.to_radians());
        let u = (rot * DVec3::new(0.0, 1.125, 0.0)).as_vec3();
        assert!(
            far.prims()
                .iter()
                .any(|p| matches!(p, Primitive::Rectangle { u: pu, .. } if *pu == u))
        );
    }

    /// A quad of an OBJ file is split into two triangles over its four corners (tobj's
    /// `triangulate`), placed by the shape's transform like any vertex, and a point
    /// placed out of range is refused whichever way its translation points.
    #[test]
    fn obj_quads_are_triangulated_and_placed() {
        let dir = std::env::temp_dir().join(format!("lightproof-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("quad.obj"),
            "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/4 2/3 3/2 4/1\n",
        )
        .unwrap();
        let d: SceneDesc = serde_json::from_value(json!({ "shapes": [{
            "geometry": { "type": "obj", "path": "quad.obj" },
            "transform": { "translate": [1e17, 0, 0] }
        }]}))
        .unwrap();
        let scene = d
            .build("t.json", "scene", &dir, DVec3::new(1e17, 0.0, 0.0), 0.0)
            .unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let area: f32 = scene
            .prims()
            .iter()
            .map(|p| match p {
                Primitive::Triangle { p } => 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length(),
                other => panic!("{other:?}"),
            })
            .sum();
        assert_eq!((scene.prims().len(), area), (2, 2.0));
        // Placed points are range-checked as R(s p) + t: 0.6e18 + 0.5e18 is out.
        let far = |t: f64, x: f64| -> Result<Scene, InputError> {
            serde_json::from_value::<SceneDesc>(json!({ "shapes": [{
                "geometry": { "type": "triangle", "vertices": [[x, 0, 0], [x, 1, 0], [x, 0, 1]] },
                "transform": { "translate": [t, 0, 0] }
            }]}))
            .unwrap()
            .build("t.json", "scene", Path::new("."), DVec3::ZERO, 0.0)
        };
        assert!(far(6e17, 5e17).is_err());
        assert!(far(6e17, -5e17).is_ok());
        // A zero scale is refused, naming the field.
        let e = serde_json::from_value::<SceneDesc>(json!({ "shapes": [{
            "geometry": { "type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]] },
            "transform": { "scale": 0 }
        }]}))
        .unwrap()
        .build("t.json", "scene", Path::new("."), DVec3::ZERO, 0.0)
        .map(|_| ())
        .unwrap_err();
        assert!(e.to_string().contains("transform.scale"), "{e}");
    }

    /// A scale too small for a unit vector's length to be formed (10⁻³²⁰: its square
    /// underflows) leaves normals and axes unit vectors: the scale cannot turn them.
    #[test]
    fn directions_ignore_the_scale() {
        let pl = Placement {
            scale: 1e-320,
            rot: DQuat::from_axis_angle(DVec3::Y, 0.5),
            tr: DVec3::ZERO,
        };
        let d = pl.direction(DVec3::new(0.0, 0.6, 0.8));
        assert!((d.length() - 1.0).abs() < 1e-15, "{d}");
        assert_eq!(pl.point(DVec3::ONE), pl.vector(DVec3::ONE));
    }
}
