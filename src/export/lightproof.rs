//! lightproof's own `render` as the renderer under test: the case file with a `camera`
//! inside (`scene.json`) and a shell driver. Only a closed furnace is exported this way
//! ([`Probe::Isotropic`]: every pixel of a pinhole camera sees the reference); for other
//! cases `lightproof estimate` is the tool. This closes the loop export → render → judge
//! without a peer renderer (`tests/proof/export_judge.rs`).

use super::{Manifest, Probe, Refusal, Target, Written, frame, render_size};
use crate::case::{CameraDesc, CaseDesc};

/// The driver written beside a lightproof suite.
pub const DRIVER: &str = include_str!("render_all_lightproof.sh");

/// The case with a camera inside, and `render.args` (its `max_depth` as `--max-depth`).
pub fn write(desc: &CaseDesc, probe: &Probe) -> Result<Written, Refusal> {
    let (at, direction) = match probe {
        Probe::Isotropic { at, direction } => (*at, *direction),
        Probe::Ray { .. }
        | Probe::Irradiance { .. }
        | Probe::Albedo { .. }
        | Probe::Flux { .. } => {
            return Err(Refusal(format!(
                "lightproof's `render` has a pinhole camera only, which sees the measured value in every pixel just inside a closed furnace; this {} case is for `lightproof estimate`",
                probe.sensor()
            )));
        }
    };
    let (w, h) = render_size(probe);
    let mut scene = desc.clone();
    scene.camera = Some(CameraDesc {
        position: at.to_array(),
        look_at: (at + direction).to_array(),
        up: frame(direction).0.to_array(),
        fov_degrees: 60.0,
        width: w,
        height: h,
    });
    let args = match desc.max_depth {
        Some(k) => format!("--max-depth {k}\n"),
        None => String::new(),
    };
    let json = serde_json::to_string_pretty(&scene).unwrap_or_default();
    Ok(Written {
        files: vec![
            ("scene.json".into(), json.into_bytes()),
            ("render.args".into(), args.into_bytes()),
        ],
        manifest: Manifest {
            renderer: Target::Lightproof,
            source: String::new(),
            name: desc.name.clone(),
            case: "case.json".into(),
            scene: "scene.json".into(),
            sensor: probe.sensor().into(),
            width: w,
            height: h,
            scale: 1.0,
            conventions: vec![
                "pinhole camera inside a closed furnace, 16×16 pixels, fov 60°: every pixel sees the reference".into(),
                "render --max-depth = the case's max_depth (scatterings, the same count)".into(),
            ],
        },
    })
}
