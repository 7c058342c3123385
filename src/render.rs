//! Pinhole-camera images of a case file that has a `camera`, for looking: each pixel is the mean of `spp` MIS path-traced
//! radiance samples through jittered points of the pixel, written as an EXR.
//!
//! A grey scene renders grey (R = G = B = L). A scene that varies with wavelength (an
//! emitter's spectrum, a dispersive material) renders in colour: each path carries four
//! hero wavelengths drawn uniformly over 360–830 nm, its spectral radiance is weighted
//! by the CIE 1931 matching functions normalised to their integrals (so equal energy is
//! white, and Ŷ is the ȳ-weighted mean radiance, a grey scene's value), and the
//! tristimulus values go to linear sRGB (D65) through a Bradford adaptation from E to
//! D65 ([`crate::spectrum::cie`]): a flat spectrum L₀ renders to R = G = B = L₀.

use crate::case::CaseDesc;
use crate::error::{InputError, parse_json};
use crate::math::Frame;
use crate::sampling::SampleStream;
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::Scene;
use crate::spectrum::cie::{Observer, to_linear_srgb, xyz_e_to_linear_srgb};
use crate::spectrum::{Response, VISIBLE};
use crate::transport::Estimator;
use crate::transport::measure::Measure;
use crate::transport::path::{Config, MAX_PATH_BOUNCES, Prev, trace};
use crate::transport::phase::{Grey, Lanes, Phase, PhaseSample, TimeSetup};
use crate::transport::plan::{Plans, SpectralDesc, WavelengthSampling};
use glam::Vec3;
use glam::Vec4;
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

/// A rendered image and what the guard cut.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Linear sRGB radiance per pixel, row by row from the top left.
    pub pixels: Vec<[f32; 3]>,
    /// Paths still scattering at the path tracer's guard of [`MAX_DEPTH`] scatterings
    /// where no depth limit (`--max-depth`, the case's or the plan's) ended them first:
    /// each was cut there, its value short of the rest of the path's energy (the image
    /// is biased low by that much); `render` says so on stderr.
    pub cut_at_guard: u64,
}

/// The files a render of `path` reads: the scene file and its external files (OBJ
/// meshes, environment maps, [`crate::scene::load::SceneDesc::external_files`]), for refusing
/// an output that would replace one (`render -o env.exr` of a scene lit by `env.exr`).
pub fn input_files(path: &Path) -> Result<Vec<std::path::PathBuf>, InputError> {
    let file = path.display().to_string();
    let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
        .map_err(|e| InputError::new(&file, "-", e))?;
    let desc: CaseDesc = parse_json(&file, &text)?;
    let mut files = vec![path.to_path_buf()];
    files.extend(desc.scene.external_paths(path));
    Ok(files)
}

/// Render `path` with `spp` samples per pixel, paths ending after at most `max_depth`
/// scatterings (`None`: the case's own `max_depth`, else the plan's bound, else cut at the
/// guard of [`MAX_DEPTH`] with Russian roulette where more bounces can contribute, each
/// such cut counted).
pub fn render_file(
    path: &Path,
    spp: u64,
    seed: u64,
    max_depth: Option<u32>,
) -> Result<Rendered, InputError> {
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
    // The time section places moving objects (at the shutter's start): checked first.
    crate::case::build::check_spectral_and_time(&file, &desc)?;
    // One image is one bin: a histogram's edges would have rendered its whole span
    // without a word.
    if desc.time.as_ref().is_some_and(|t| t.bins.is_some()) {
        return Err(InputError::new(
            &file,
            "time.bins",
            "an image shows one arrival-time bin: give `time.bin` [t₁, t₂] to render one of them",
        ));
    }
    let scene = desc.scene.build(
        &file,
        "scene",
        crate::scene::load::folder_of(path),
        eye,
        crate::case::build::epoch(&desc),
    )?;
    let fwd = look.normalize().as_vec3();
    let frame = Frame::from_z(fwd);
    let upv = Vec3::from_array(c.up.map(|x| x as f32));
    let right = fwd.cross(upv).normalize_or(frame.s);
    let up = right.cross(fwd);
    let tan = (c.fov_degrees.to_radians() * 0.5).tan() as f32;
    let aspect = c.width as f32 / c.height as f32;
    // The same plan as `estimate` for radiance seen from the eye (effects depend on the
    // viewpoint, not on the pixel's direction): bounded depth, and no shadow rays where
    // nothing can occlude. Wavelength is sampled over the visible range where the scene
    // varies with it (whatever the case's own `spectral` section measures); time as the
    // case's `time` section says (a shutter where something moves, an arrival-time bin),
    // in a grey scene as in a spectral one.
    let eye_measure = Measure::Radiance {
        at: Vec3::ZERO,
        direction: fwd,
    };
    let visible = SpectralDesc {
        band: Some([VISIBLE.min as f64, VISIBLE.max as f64]),
        wavelength: None,
        response: Response::Flat,
        sampling: WavelengthSampling::Uniform,
        hero: true,
        photons: false,
    };
    let plans = Plans::decide(
        &file,
        &scene,
        &eye_measure,
        Some(&visible),
        desc.time.as_ref(),
    )?;
    let dims = &plans.pruned.dims;
    let spectral = dims.spectral.is_some();
    let timed = dims.time != TimeSetup::default();
    let observer = Observer::over(VISIBLE.min as f64, VISIBLE.max as f64);
    let to_rgb = xyz_e_to_linear_srgb();
    let mut cfg = plans.pruned.config(Estimator::Mis);
    // 0: only emission seen directly; 1: direct lighting; and so on. An image is for
    // looking: without a depth limit a path still scattering at the path tracer's guard
    // of 2¹⁶ scatterings returns +∞ (where a measurement fails); it is traced again, the
    // same path from the same stream, with the guard as its limit (`cut`), and counted.
    // `--max-depth` where given, else the case's own `max_depth` (k scatterings after the
    // emission seen directly, as for `radiance`), else no limit.
    let case_depth = crate::case::build::max_bounces(&file, &desc, &eye_measure)?;
    cfg.max_bounces = cfg
        .max_bounces
        .min(max_depth.or(case_depth).unwrap_or(u32::MAX));
    let cut = Config {
        max_bounces: cfg.max_bounces.min(MAX_DEPTH),
        ..cfg
    };
    let cut = (cut.max_bounces != cfg.max_bounces).then_some(&cut);
    let sampler = Sampler::new(SamplerKind::Independent, seed, 1);
    let (w, h) = (c.width, c.height);
    let traced: Vec<([f32; 3], u64)> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % w, i / w);
            // Grey: the radiance in [0]; spectral: the E-normalised X̂, Ŷ, Ẑ.
            let mut sum = [0.0f64; 3];
            let mut cuts = 0u64;
            for k in 0..spp {
                let index = i as u64 * spp + k;
                let mut s = sampler.stream(index);
                let j = s.next_2d();
                let px = (2.0 * (x as f32 + j.x) / w as f32 - 1.0) * tan * aspect;
                let py = (1.0 - 2.0 * (y as f32 + j.y) / h as f32) * tan;
                let d = (fwd + right * px + up * py).normalize();
                let o = Vec3::ZERO;
                if spectral {
                    let phase: PhaseSample<Vec4> = dims.draw(&mut s);
                    let l = trace_cut(&scene, &cfg, cut, &phase, o, d, &mut s, &mut cuts);
                    for lane in 0..Vec4::LANES {
                        let v = l.lane(lane) * phase.weight.lane(lane);
                        let cmf = observer.weights(phase.lambda[lane]);
                        for c in 0..3 {
                            sum[c] += (v * cmf[c]) as f64;
                        }
                    }
                } else if timed {
                    // Grey but moving or time resolved: the time drawn as for a measurement
                    // (its weight, the pruned wavelength factor, is not a radiance's).
                    let phase: PhaseSample<f32> = dims.draw(&mut s);
                    sum[0] += trace_cut(&scene, &cfg, cut, &phase, o, d, &mut s, &mut cuts) as f64;
                } else {
                    sum[0] += trace_cut(&scene, &cfg, cut, &Grey, o, d, &mut s, &mut cuts) as f64;
                }
            }
            let mean = sum.map(|v| v / spp.max(1) as f64);
            let rgb = if spectral {
                to_linear_srgb(&to_rgb, mean)
            } else {
                [mean[0] as f32; 3]
            };
            (rgb, cuts)
        })
        .collect();
    Ok(Rendered {
        width: w,
        height: h,
        cut_at_guard: traced.iter().map(|t| t.1).sum(),
        pixels: traced.into_iter().map(|t| t.0).collect(),
    })
}

/// The radiance along the camera ray o + t d under `cfg`; where `cut` is given and the
/// path came back +∞ from the guard, the same path (the stream as it was) traced under
/// `cut`, whose depth limit is the guard, counted in `cuts` (a path that is still not
/// finite is a bug, kept as it is).
#[allow(clippy::too_many_arguments)]
fn trace_cut<P: Phase>(
    scene: &Scene,
    cfg: &Config,
    cut: Option<&Config>,
    phase: &P,
    o: Vec3,
    d: Vec3,
    stream: &mut SampleStream,
    cuts: &mut u64,
) -> P::L {
    let resume = cut.map(|c| (c, stream.clone()));
    let l = trace(scene, cfg, phase, o, d, Prev::sensor(o), 0, stream);
    if let Some((cut, mut again)) = resume
        && l.max_lane() == f32::INFINITY
    {
        let cut_l = trace(scene, cut, phase, o, d, Prev::sensor(o), 0, &mut again);
        if cut_l.all_finite() {
            *cuts += 1;
            return cut_l;
        }
    }
    l
}

/// The pixels of an image with a component that is not finite (NaN or ±∞: a bug of the
/// engine, which `render` reports and exits 1 on, the image written as it is), and the
/// first of them, (x, y) for an image `w` pixels wide.
pub fn non_finite_pixels(w: usize, data: &[[f32; 3]]) -> (usize, Option<(usize, usize)>) {
    let bad = |p: &&[f32; 3]| p.iter().any(|c| !c.is_finite());
    let first = data.iter().position(|p| bad(&p)).map(|i| (i % w, i / w));
    (data.iter().filter(bad).count(), first)
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value clipped to [0, 1], as
/// an 8-bit code.
fn srgb_byte(v: f32) -> u8 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    let e = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}

/// `v` times the exposure factor `k`: a finite value stays finite (clamped to ±`f32::MAX`
/// rather than overflowing to ±∞, which would read as an engine bug), and a value that is
/// not finite is kept as it is, never masked (`f32::min` would turn NaN into `f32::MAX`).
fn expose(v: f32, k: f32) -> f32 {
    if v.is_finite() {
        (v * k).clamp(-f32::MAX, f32::MAX)
    } else {
        v
    }
}

/// Check `render`'s output name before any work: it must end in `.exr` or `.png` (any
/// case), the two formats [`write_image`] writes; another extension (`out.jpg`) would get
/// an EXR under a name that says otherwise.
pub fn check_output_name(path: &Path) -> Result<(), InputError> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if ext.eq_ignore_ascii_case("exr") || ext.eq_ignore_ascii_case("png") {
        Ok(())
    } else {
        Err(InputError::new(
            "<command line>",
            "--output",
            format!(
                "the image must be named .exr (linear) or .png (8-bit sRGB), got `{}`",
                path.display()
            ),
        ))
    }
}

/// Write the image times 2^`exposure` atomically: an 8-bit sRGB PNG (linear values
/// clipped at 1, then the sRGB transfer curve; NaN black, +∞ white) when `path` ends in
/// `.png`, else a linear RGB EXR ([`write_exr`]) where a pixel that is not finite keeps
/// its NaN or ±∞.
pub fn write_image(
    path: &Path,
    w: usize,
    h: usize,
    data: &[[f32; 3]],
    exposure: f32,
) -> std::io::Result<()> {
    let k = exposure.exp2();
    let scaled: Vec<[f32; 3]> = data.iter().map(|p| p.map(|v| expose(v, k))).collect();
    let data = &scaled[..];
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        || w.checked_mul(h) != Some(data.len())
    {
        return write_exr(path, w, h, data);
    }
    let bytes: Vec<u8> = data.iter().flat_map(|p| p.map(srgb_byte)).collect();
    crate::io::write_atomic(path, &crate::report::png::encode_rgb(w, h, &bytes))
}

/// Write linear sRGB radiance as an RGB EXR, atomically.
pub fn write_exr(path: &Path, w: usize, h: usize, data: &[[f32; 3]]) -> std::io::Result<()> {
    if w.checked_mul(h) != Some(data.len()) {
        return Err(std::io::Error::other(format!(
            "an image of {w} × {h} pixels needs {} values, got {}",
            w.saturating_mul(h),
            data.len()
        )));
    }
    crate::io::write_exr_atomic(path, w, h, |x, y| {
        let [r, g, b] = data[y * w + x];
        (r, g, b)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_output_is_named_exr_or_png() {
        for ok in ["out.exr", "a/b.PNG", "x.Exr", "img.png"] {
            assert!(check_output_name(Path::new(ok)).is_ok(), "{ok}");
        }
        for bad in ["out.jpg", "out", "out.exr.tmp", "png", ".png"] {
            let e = check_output_name(Path::new(bad)).unwrap_err();
            assert!(
                e.field == "--output" && e.reason.contains(bad),
                "{bad}: {e}"
            );
        }
    }

    /// A pixel that is not finite is kept as it is (never masked): NaN and ±∞ stay in the
    /// EXR, a PNG shows NaN black and +∞ white; a finite pixel that the exposure would
    /// overflow stays finite (±`f32::MAX`), and the exposure scales by 2^stops.
    #[test]
    fn non_finite_pixels_are_kept_in_the_written_image() {
        let dir =
            std::env::temp_dir().join(format!("lightproof-render-nan-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let data = [
            [f32::NAN, f32::INFINITY, f32::NEG_INFINITY],
            [3e38, -3e38, 0.25],
        ];
        let exr = dir.join("img.exr");
        write_image(&exr, 2, 1, &data, 1.0).unwrap();
        let img = exr::prelude::read_first_rgba_layer_from_file(
            &exr,
            |r, _| vec![[0.0f32; 3]; r.width() * r.height()],
            |px: &mut Vec<[f32; 3]>, pos, (r, g, b, _): (f32, f32, f32, f32)| {
                px[pos.y() * 2 + pos.x()] = [r, g, b]
            },
        )
        .unwrap();
        let px = &img.layer_data.channel_data.pixels;
        assert!(px[0][0].is_nan(), "{px:?}");
        assert_eq!(px[0][1..], [f32::INFINITY, f32::NEG_INFINITY], "{px:?}");
        assert_eq!(px[1], [f32::MAX, -f32::MAX, 0.5], "{px:?}");
        assert_eq!(non_finite_pixels(2, px).0, 1);
        let png = dir.join("img.png");
        write_image(&png, 2, 1, &data, 0.0).unwrap();
        let mut reader =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()))
                .read_info()
                .unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (2, 1));
        // NaN black, +∞ white, −∞ black; 3e38 white, −3e38 black, 0.25 → sRGB 137.
        assert_eq!(&buf[..6], &[0, 255, 0, 255, 0, 137]);
        let _ = std::fs::remove_dir_all(dir);
    }

    /// Every component is looked at: a NaN in blue or an infinity in green counts, the
    /// first is named in row-major order, and finite pixels (however large) do not count.
    #[test]
    fn non_finite_pixels_are_counted_in_every_channel() {
        let mut data = vec![[1.0f32, f32::MAX, 0.0]; 12];
        assert_eq!(non_finite_pixels(4, &data), (0, None));
        data[9] = [1.0, f32::INFINITY, 1.0];
        data[6] = [1.0, 1.0, f32::NAN];
        data[11] = [f32::NEG_INFINITY, 1.0, 1.0];
        assert_eq!(non_finite_pixels(4, &data), (3, Some((2, 1))));
    }

    #[test]
    fn the_srgb_curve_meets_its_standard_points() {
        assert_eq!(srgb_byte(0.0), 0);
        assert_eq!(srgb_byte(f32::NAN), 0);
        assert_eq!(srgb_byte(1.0), 255);
        assert_eq!(srgb_byte(7.0), 255);
        // 18% grey encodes to 0.4614 (118/255); the linear segment ends at 0.0031308.
        assert_eq!(srgb_byte(0.18), 118);
        assert_eq!(srgb_byte(0.003), 10);
    }

    /// The white point, end to end: a disk emitting a flat (equal-energy) tabulated
    /// spectrum of 2 — spectral, so paths carry hero wavelengths weighted by x̄, ȳ, z̄ —
    /// renders to R = G = B = 2 up to Monte Carlo noise: each channel's mean over 256
    /// independent pixels within 4.5 standard errors of 2 (Šidák over 3 channels at
    /// α ≈ 2·10⁻⁵), with the standard error below 0.2%, so a white point off by 1%
    /// (D65's unadapted white is 5–10% off) would fail.
    #[test]
    fn a_flat_spectrum_renders_white() {
        let case = r#"{"name": "flat", "teaches": "white",
          "scene": {"shapes": [{"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 10},
            "emission": {"radiance": 2, "spectrum": {"sampled": {"wavelengths": [300, 900], "values": [1, 1]}}}}]},
          "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 30, "width": 16, "height": 16},
          "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
          "spectral": {"band": [360, 830]}, "estimators": ["mis"]}"#;
        let image = render_case("flat", case, &[(1024, 9, None)]).remove(0);
        assert_eq!(image.cut_at_guard, 0);
        let (w, h, px) = (image.width, image.height, image.pixels);
        let n = (w * h) as f64;
        for c in 0..3 {
            let mean = px.iter().map(|p| p[c] as f64).sum::<f64>() / n;
            let var = px.iter().map(|p| (p[c] as f64 - mean).powi(2)).sum::<f64>() / (n - 1.0);
            let se = (var / n).sqrt();
            assert!(se > 0.0 && se < 0.002 * 2.0, "channel {c}: se {se}");
            assert!((mean - 2.0).abs() < 4.5 * se, "channel {c}: {mean} ± {se}");
        }
    }

    /// An image is for looking: without `--max-depth` a path still scattering at the
    /// guard of [`MAX_DEPTH`] scatterings (where a measurement's path returns +∞) is cut
    /// there and counted. Inside a white closed sphere emitting 1 (an infinite answer;
    /// roulette keeps every path, β = 1) the one path reaches it: the pixel is finite,
    /// more than the emission seen directly (which `--max-depth 0` gives exactly), the
    /// same to the bit as `--max-depth 65536` (the same path, cut by a limit the user
    /// chose, so not counted), and the one cut is counted.
    #[test]
    fn an_unbounded_render_is_cut_at_the_guard_and_counted() {
        let case = r#"{"name": "white furnace", "teaches": "the guard",
          "scene": {"materials": {"white": {"type": "lambertian", "albedo": 1}},
            "shapes": [{"geometry": {"type": "sphere", "center": [0, 0, 0], "radius": 1},
              "material": "white", "flip_normals": true, "emission": {"radiance": 1}}]},
          "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 30, "width": 1, "height": 1},
          "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}}, "estimators": ["mis"]}"#;
        let runs = [(1, 3, None), (1, 3, Some(MAX_DEPTH)), (1, 3, Some(0))];
        let [image, limited, direct] = <[Rendered; 3]>::try_from(render_case("guard", case, &runs))
            .unwrap_or_else(|_| unreachable!());
        let v = image.pixels[0][0];
        assert!(v.is_finite() && v > 1.0, "{v}");
        assert_eq!(image.cut_at_guard, 1);
        assert_eq!((limited.pixels[0][0], limited.cut_at_guard), (v, 0));
        assert_eq!((direct.pixels[0][0], direct.cut_at_guard), (1.0, 0));
    }

    /// A rectangle light of radiance 3 over x ∈ [1.4, 2.1], y ∈ [0.4, 1.1] on z = 1,
    /// seen by an 8×4 camera at fov 90° looking along +z.
    const PINHOLE: &str = r#"{"name": "corner light", "teaches": "the pinhole",
          "scene": {"shapes": [{"geometry": {"type": "rectangle", "corner": [1.4, 0.4, 1], "edge_u": [0, 0.7, 0], "edge_v": [0.7, 0, 0]},
            "emission": {"radiance": 3}}]},
          "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 90, "width": 8, "height": 4},
          "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}}, "estimators": ["mis"]}"#;

    /// The pinhole's geometry: pixel (i, j) sees the directions fwd + right·px + up·py
    /// with px ∈ [−1 + 2i/w, −1 + 2(i + 1)/w]·tan(fov/2)·(w/h) and py ∈ [1 − 2(j + 1)/h,
    /// 1 − 2j/h]·tan(fov/2), right = fwd × up (−x looking along +z with +y up). An 8×4
    /// image at fov 90° (tan = 1, aspect 2) looking along +z: the top-left pixel sees
    /// x ∈ [1.5, 2], y ∈ [0.5, 1] on the plane z = 1, which a rectangle light of
    /// radiance 3 over x ∈ [1.4, 2.1], y ∈ [0.4, 1.1] covers (every jittered ray hits
    /// it: exactly 3), and no pixel beyond its neighbours sees any of it (exactly 0). A
    /// flipped axis, a wrong aspect or field of view, or a pixel offset fails.
    #[test]
    fn the_pinhole_maps_pixels_to_directions() {
        let image = render_case("pinhole", PINHOLE, &[(64, 5, None)]).remove(0);
        assert_eq!((image.width, image.height, image.pixels.len()), (8, 4, 32));
        for (k, p) in image.pixels.iter().enumerate() {
            let (i, j) = (k % 8, k / 8);
            match (i, j) {
                (0, 0) => assert_eq!(*p, [3.0; 3], "({i}, {j})"),
                (0 | 1, 0 | 1) => assert!(p[0] < 3.0, "({i}, {j}): {p:?}"),
                _ => assert_eq!(*p, [0.0; 3], "({i}, {j})"),
            }
        }
    }

    /// A grey scene samples time as a measurement does. Motion blur: a rectangle light of
    /// radiance 1 (y ∈ [−2, 2] on z = 1) covering x ∈ [2.1, 3.9] at the shutter's start
    /// moves by (−2, 0, 0) over the shutter [0, 1] s; a 4×1 image at fov 90° (pixel i sees
    /// x ∈ [4 − 2(i+1), 4 − 2i], y ∈ [−1, 1]) then has pixels 0 and 1 each covered for
    /// 0.45 of pixel × shutter (∫₀¹ overlap dt / 2 = 0.9/2), pixels 2 and 3 never. Each
    /// lit pixel is judged by a z test at 4.5σ of its binomial spread (4096 paths: σ =
    /// 0.0078; at the shutter's start alone they read 0.9 and 0). A time bin [0, 0.25] s
    /// of a steady light weighs the radiance by its width: the covered pixel reads 3 ×
    /// 0.25 exactly.
    #[test]
    fn a_grey_render_samples_the_shutter_and_the_bin() {
        let case = r#"{"name": "moving light", "teaches": "motion blur",
          "scene": {"shapes": [{"geometry": {"type": "rectangle", "corner": [2.1, -2, 1], "edge_u": [0, 4, 0], "edge_v": [1.8, 0, 0]},
            "emission": {"radiance": 1}, "velocity": [-2, 0, 0]}]},
          "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 90, "width": 4, "height": 1},
          "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
          "time": {"shutter": [0, 1]}, "estimators": ["mis"]}"#;
        let n = 4096;
        let px = render_case("blur", case, &[(n, 7, None)]).remove(0).pixels;
        let sigma = (0.45f64 * 0.55 / n as f64).sqrt();
        for (i, p) in px.iter().enumerate() {
            if i < 2 {
                let z = (p[0] as f64 - 0.45) / sigma;
                assert!(z.abs() < 4.5, "pixel {i}: {p:?}, z = {z}");
            } else {
                assert_eq!(*p, [0.0; 3], "pixel {i}");
            }
        }
        let binned = PINHOLE.replace(
            r#""estimators""#,
            r#""time": {"bin": [0, 0.25]}, "estimators""#,
        );
        let px = render_case("bin", &binned, &[(16, 5, None)])
            .remove(0)
            .pixels;
        assert_eq!(px[0], [0.75; 3]);
        // A histogram's edges are no one image: refused, naming `time.bins`.
        let histogram = PINHOLE.replace(
            r#""estimators""#,
            r#""time": {"bins": [0, 0.25, 0.5]}, "estimators""#,
        );
        let dir = std::env::temp_dir().join(format!("lightproof-bins-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("case.json"), histogram).unwrap();
        let e = render_file(&dir.join("case.json"), 1, 1, None).unwrap_err();
        assert_eq!(e.field, "time.bins");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Render the case text `case` once per (spp, seed, max_depth) in `runs`, from a file
    /// in a folder of its own named after `name`.
    fn render_case(name: &str, case: &str, runs: &[(u64, u64, Option<u32>)]) -> Vec<Rendered> {
        let dir = std::env::temp_dir().join(format!("lightproof-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("case.json");
        std::fs::write(&path, case).unwrap();
        let images = runs
            .iter()
            .map(|&(spp, seed, depth)| render_file(&path, spp, seed, depth).unwrap())
            .collect();
        std::fs::remove_dir_all(dir).unwrap();
        images
    }
}
