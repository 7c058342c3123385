//! Pinhole-camera images of a case file that has a `camera`, for looking: each pixel is the mean of `spp` MIS path-traced
//! radiance samples through jittered points of the pixel, written as an EXR.

use crate::case::CaseDesc;
use crate::error::{InputError, parse_json};
use crate::math::Frame;
use crate::sampling::{Sampler, SamplerKind};
use crate::transport::Estimator;
use crate::transport::measure::Measure;
use crate::transport::path::{MAX_PATH_BOUNCES, Prev, trace};
use crate::transport::phase::Grey;
use crate::transport::plan::Plans;
use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;

/// Largest image: 2²⁶ pixels (64 Mpixel).
pub const MAX_PIXELS: usize = 1 << 26;

/// Most samples per pixel.
pub const MAX_SPP: u64 = 1 << 20;

/// Most samples of a whole image (pixels × spp): 2⁴⁰, as for an estimate.
pub const MAX_RENDER_SAMPLES: u64 = 1 << 40;

/// Most bounces `--max-depth` accepts (the path tracer's own guard,
/// [`MAX_PATH_BOUNCES`]).
pub const MAX_DEPTH: u32 = MAX_PATH_BOUNCES;

/// Render `path` with `spp` samples per pixel, paths ending after at most `max_depth`
/// scatterings (`None`: the plan's bound, unlimited with Russian roulette where more
/// bounces can contribute); returns (width, height, radiance).
pub fn render_file(
    path: &Path,
    spp: u64,
    seed: u64,
    max_depth: Option<u32>,
) -> Result<(usize, usize, Vec<f32>), InputError> {
    let file = path.display().to_string();
    let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
        .map_err(|e| InputError::new(&file, "-", e))?;
    let desc: CaseDesc = parse_json(&file, &text)?;
    let Some(c) = &desc.camera else {
        return Err(InputError::new(
            &file,
            "camera",
            "a file to render needs a `camera`",
        ));
    };
    let eye = crate::error::check_point(&file, "camera.position", c.position)?;
    let look = crate::error::check_point(&file, "camera.look_at", c.look_at)? - eye;
    if !(look.length() > 0.0) {
        return Err(InputError::new(
            &file,
            "camera.look_at",
            "must differ from camera.position",
        ));
    }
    crate::error::check_direction(&file, "camera.up", c.up)?;
    for (field, v) in [("camera.width", c.width), ("camera.height", c.height)] {
        if v == 0 {
            return Err(InputError::new(
                &file,
                field,
                "must be a positive number of pixels, got 0",
            ));
        }
    }
    let pixels = c.width.checked_mul(c.height).filter(|&n| n <= MAX_PIXELS);
    let Some(pixels) = pixels else {
        return Err(InputError::new(
            &file,
            "camera.width",
            format!(
                "camera.width × camera.height = {} × {} is more than {MAX_PIXELS} pixels (64 Mpixel)",
                c.width, c.height
            ),
        ));
    };
    if !(1..=MAX_SPP).contains(&spp) || (pixels as u64).saturating_mul(spp) > MAX_RENDER_SAMPLES {
        return Err(InputError::new(
            "<command line>",
            "--spp",
            format!(
                "must be 1 to {MAX_SPP} samples per pixel, with pixels × spp at most 2^40; got {spp} for {pixels} pixels"
            ),
        ));
    }
    crate::error::check_number(
        &file,
        "camera.fov_degrees",
        c.fov_degrees,
        |x| x > 0.0 && x < 180.0,
        "in (0, 180) degrees",
    )?;
    let scene = desc
        .scene
        .build(&file, "scene", path.parent().unwrap_or(Path::new(".")), eye)?;
    let fwd = look.normalize().as_vec3();
    let frame = Frame::from_z(fwd);
    let upv = Vec3::from_array(c.up.map(|x| x as f32));
    let right = fwd.cross(upv).normalize_or(frame.s);
    let up = right.cross(fwd);
    let tan = (c.fov_degrees.to_radians() * 0.5).tan() as f32;
    let aspect = c.width as f32 / c.height as f32;
    // The same plan as `estimate` for radiance seen from the eye (effects depend on the
    // viewpoint, not on the pixel's direction): bounded depth, and no shadow rays where
    // nothing can occlude. Rendering is grey: the plan's dimensions are not sampled.
    let eye_measure = Measure::Radiance {
        at: Vec3::ZERO,
        direction: fwd,
    };
    let plans = Plans::decide(
        &file,
        &scene,
        &eye_measure,
        desc.spectral.as_ref(),
        desc.time.as_ref(),
    )?;
    let mut cfg = plans.pruned.config(Estimator::Mis);
    if let Some(depth) = max_depth {
        // 0: only emission seen directly; 1: direct lighting; and so on.
        cfg.max_bounces = cfg.max_bounces.min(depth);
    }
    let sampler = Sampler::new(SamplerKind::Independent, seed, 1);
    let (w, h) = (c.width, c.height);
    let pixels: Vec<f32> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let mut sum = 0.0f64;
            for k in 0..spp {
                let mut s = sampler.stream(i as u64 * spp + k);
                let j = s.next_2d();
                let px = (2.0 * (x as f32 + j.x) / w as f32 - 1.0) * tan * aspect;
                let py = (1.0 - 2.0 * (y as f32 + j.y) / h as f32) * tan;
                let d = (fwd + right * px + up * py).normalize();
                sum += trace(
                    &scene,
                    &cfg,
                    &Grey,
                    Vec3::ZERO,
                    d,
                    Prev::sensor(Vec3::ZERO),
                    0,
                    &mut s,
                ) as f64;
            }
            (sum / spp.max(1) as f64) as f32
        })
        .collect();
    Ok((w, h, pixels))
}

/// Write grey radiance as an RGB EXR, atomically.
pub fn write_exr(path: &Path, w: usize, h: usize, data: &[f32]) -> std::io::Result<()> {
    if w.checked_mul(h) != Some(data.len()) {
        return Err(std::io::Error::other(format!(
            "an image of {w} × {h} pixels needs {} values, got {}",
            w.saturating_mul(h),
            data.len()
        )));
    }
    crate::io::write_exr_atomic(path, w, h, |x, y| {
        let v = data[y * w + x];
        (v, v, v)
    })
}
