//! The case file as written: every field, its default and its meaning. Parsing checks
//! only the shape (unknown fields are errors); [`super::Case::from_desc`] validates the
//! values and builds the case.

use crate::bsdf::{Bsdf, Distribution};
use crate::sampling::SamplerKind;
use crate::scene::load::SceneDesc;
use crate::transport::Estimator;
use crate::transport::microfacet_integral::MicrofacetIntegral;
use serde::{Deserialize, Serialize};

pub use crate::transport::plan::{SpectralDesc, TimeDesc, WavelengthSampling};

/// A measurement as written in a case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MeasureDesc {
    /// Solid angle of a shape from a point.
    SolidAngle {
        /// Viewpoint.
        from: [f64; 3],
        /// Index of the shape in `scene.shapes`.
        shape: usize,
    },
    /// Projected solid angle of a shape for a receiver.
    ProjectedSolidAngle {
        /// Viewpoint.
        from: [f64; 3],
        /// Receiver normal.
        normal: [f64; 3],
        /// Index of the shape.
        shape: usize,
    },
    /// Irradiance at a point.
    Irradiance {
        /// Point.
        at: [f64; 3],
        /// Receiver normal.
        normal: [f64; 3],
    },
    /// Radiance seen from a point looking along a direction.
    Radiance {
        /// Eye.
        at: [f64; 3],
        /// Viewing direction.
        direction: [f64; 3],
    },
    /// Directional albedo of a BSDF.
    Albedo {
        /// The BSDF (same JSON as a material).
        bsdf: Bsdf,
        /// Polar angle of ωo in degrees.
        theta_degrees: f64,
        /// Azimuth of ωo in degrees.
        #[serde(default)]
        phi_degrees: f64,
    },
    /// An integral of a microfacet distribution (`normalisation`, `projected_area`,
    /// `visible`), estimated over microfacet normals.
    Microfacet {
        /// `ggx` or `beckmann`.
        distribution: Distribution,
        /// Roughness α ∈ [0.01, 1] (normals drawn without knowledge of D resolve no
        /// narrower lobe).
        alpha: f64,
        /// Polar angle of ωo in degrees, [0, 90] (below 90 for `visible`): required by
        /// the integrals that depend on ωo, refused by `normalisation`, which does not.
        #[serde(default)]
        theta_degrees: Option<f64>,
        /// Which integral.
        integral: MicrofacetIntegral,
    },
    /// Power of an emitter: an emitting shape (`shape`) or an entry of `scene.emitters`.
    Power {
        /// Emitting shape.
        #[serde(default)]
        shape: Option<usize>,
        /// Entry of `scene.emitters`.
        #[serde(default)]
        emitter: Option<usize>,
    },
    /// Intensity of an emitter towards a direction.
    Intensity {
        /// Emitting shape.
        #[serde(default)]
        shape: Option<usize>,
        /// Entry of `scene.emitters`.
        #[serde(default)]
        emitter: Option<usize>,
        /// Direction.
        direction: [f64; 3],
    },
    /// Mean free-flight length of a diffuse random walk inside a closed shape (Cauchy's
    /// 4V/S); divided by c it is the mean time of flight between bounces.
    MeanPathLength {
        /// The closed shape.
        shape: usize,
        /// Flights averaged per path (default 8).
        #[serde(default = "default_segments")]
        segments: u32,
    },
    /// Power arriving on a receiver shape (on the side its normal faces), Φ = ∫ E dA;
    /// with `view_factor`, Φ / (π L A) of the scene's one emitter: the configuration
    /// factor from the emitter to the receiver.
    Flux {
        /// The receiver: an index of `scene.shapes`.
        shape: usize,
        /// Report the view factor F = Φ / (π L A_emitter) instead of Φ (default false).
        #[serde(default)]
        view_factor: bool,
    },
}

impl MeasureDesc {
    /// The key the measurement stands under in a case file (`measure.irradiance`), the
    /// first segment of its fields' paths in error messages.
    pub fn key(&self) -> &'static str {
        match self {
            MeasureDesc::SolidAngle { .. } => "solid_angle",
            MeasureDesc::ProjectedSolidAngle { .. } => "projected_solid_angle",
            MeasureDesc::Irradiance { .. } => "irradiance",
            MeasureDesc::Radiance { .. } => "radiance",
            MeasureDesc::Albedo { .. } => "albedo",
            MeasureDesc::Microfacet { .. } => "microfacet",
            MeasureDesc::Power { .. } => "power",
            MeasureDesc::Intensity { .. } => "intensity",
            MeasureDesc::MeanPathLength { .. } => "mean_path_length",
            MeasureDesc::Flux { .. } => "flux",
        }
    }

    /// The path of one of its fields in a case file: `measure.irradiance.normal`.
    pub fn field(&self, name: &str) -> String {
        format!("measure.{}.{name}", self.key())
    }
}

fn default_segments() -> u32 {
    8
}

/// A case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseDesc {
    /// Name.
    pub name: String,
    /// What it teaches, in one sentence.
    pub teaches: String,
    /// The scene.
    #[serde(default)]
    pub scene: SceneDesc,
    /// The measurement.
    pub measure: MeasureDesc,
    /// Wavelength: a band with a response, or one wavelength (default: grey).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spectral: Option<SpectralDesc>,
    /// Time: a shutter interval and/or an arrival-time bin (default: static).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeDesc>,
    /// The closed form (`closed_form` plus its parameters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<serde_json::Map<String, serde_json::Value>>,
    /// Estimators to run.
    pub estimators: Vec<Estimator>,
    /// Samplers to run (left out: independent; an empty list is refused).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samplers: Option<Vec<SamplerKind>>,
    /// Samples per estimate (default 2¹⁸).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<u64>,
    /// Most scatterings on a path, as pbrt's `maxdepth` counts them: 1 is direct light
    /// only. The virtual receiver of an `irradiance` or `flux` measurement counts as the
    /// first scattering (it "scatters" with f = 1), so there 1 is direct irradiance and
    /// k adds light that scattered k − 1 times; for `radiance` k scatterings follow the
    /// emission seen directly. Default: unbounded (Russian roulette ends paths).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<u32>,
    /// Why every estimator of this case is exact (samples without variance), when they
    /// all are: a catalog case must have an estimator with variance or say why not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exact: Option<String>,
    /// A camera for `lightproof render`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraDesc>,
}

/// A pinhole camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye.
    pub position: [f64; 3],
    /// Point looked at.
    pub look_at: [f64; 3],
    /// Up vector.
    #[serde(default = "up")]
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_degrees: f64,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
}

fn up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}
