//! # 1. Photons, phase space, energy and power
//!
//! Geometric optics describes light as photons. A photon's state is a point of phase
//! space: a position x (m), a direction of travel ω (unit vector), a wavelength λ (m),
//! plus the time t (s) at which it is there. Left alone it moves along a straight
//! trajectory x(t') = x + c (t' − t) ω.
//!
//! Each photon carries the energy e = h c / λ (J), so radiant energy Q (J) is a photon
//! count times e, and radiant power (flux) Φ = dQ/dt (W) is a photon rate times e.
//!
//! This example simulates the photons a Lambertian disk of radiance L emits during a time
//! window T as a Poisson process in phase space: photons are born uniformly in time, at
//! uniform points of the disk, in uniform directions of the hemisphere, and each is kept
//! with probability cos θ (Lewis–Shedler thinning: emission per unit projected area is
//! what radiance holds constant). Nothing in the simulation knows that ∫ cos θ dω = π,
//! yet the counted power comes out at Φ = π L A. Then the photons fly: a second disk
//! counts the ones that reach it, with their time of flight, and receives Φ·F (F the
//! disk-to-disk view factor) once the first photons have had time to arrive.
//!
//! Then the same two ideas run through the engine itself, where wavelength and time are
//! dimensions of the estimator: the photon radiance of a blackbody (each path draws
//! wavelengths by the emitter's spectrum and divides the energy by hc/λ) against
//! 4ζ(3)k³T³/(h³c²), and a pulsed disk whose light reaches a receiver spread over time
//! (each path's length ℓ gives its arrival time ℓ/c), bin by bin against
//! π L h² (1/r₁² − 1/r₂²).
//!
//! Picture: target/examples/01_photon_flux.svg, the power leaving the source and the
//! power arriving at the detector against time (the detector's ramp is time of flight).
//!
//! Run: `cargo run --release --example 01_phase_space -- [PHOTONS]`

use glam::{DVec2, DVec3};
use lightproof::sampling::Sampler;
use lightproof::sampling::disk::concentric_disk;
use lightproof::sampling::hemisphere::uniform_hemisphere;
use lightproof::stats::Verdict;
use lightproof_analytic::radiometry::{SPEED_OF_LIGHT, lambertian_power, photon_energy};
use lightproof_analytic::view_factor::disk_to_coaxial_disk;
use plotters::prelude::*;
use std::f64::consts::PI;

/// The source: a disk of radius 0.5 m in the plane z = 0 facing +z, radiance
/// L = 2e-8 W/(m²·sr) of green light (555 nm). The detector: a disk of radius 0.5 m
/// at height 1 m, facing the source.
const SOURCE: (f64, f64, f64, f64, f64) = (2e-8, 555e-9, 0.5, 0.5, 1.0);

/// The fewest candidate photons the example runs. The time window T = N / (candidate
/// rate) must outlast the longest time of flight (rim to opposite rim, √2 m / c =
/// 4.7 ns, reached at N ≈ 1300), and the detector must count enough arrivals after it
/// for the normal approximation of its Poisson count: at N = 4096 about 240 arrive
/// (0.086 N − 111 on average).
const MIN_PHOTONS: u64 = 4096;

/// Candidate photons per second: the rate of a source emitting the photon radiance
/// L / e in *every* direction of the hemisphere (2π sr); thinning by cos θ then keeps
/// the right ones.
fn candidate_rate() -> f64 {
    let (radiance, lambda, r_src, _, _) = SOURCE;
    radiance / photon_energy(lambda) * PI * r_src * r_src * 2.0 * PI
}

/// The longest time of flight from source to detector (s): rim to opposite rim.
fn longest_flight() -> f64 {
    let (_, _, r_src, r_det, height) = SOURCE;
    (height * height + (r_src + r_det) * (r_src + r_det)).sqrt() / SPEED_OF_LIGHT
}

/// A photon: a point of phase space (position, direction, wavelength) at a time.
#[derive(Clone, Copy, Debug)]
struct Photon {
    /// Position x (m) at time `t`.
    x: DVec3,
    /// Unit direction of travel ω.
    omega: DVec3,
    /// Vacuum wavelength λ (m).
    lambda: f64,
    /// Time (s) at which the photon is at `x` (here: its emission time).
    t: f64,
}

impl Photon {
    /// Its position at time `t` (a straight trajectory at the speed of light).
    fn at(&self, t: f64) -> DVec3 {
        self.x + SPEED_OF_LIGHT * (t - self.t) * self.omega
    }

    /// Its energy e = h c / λ (J).
    fn energy(&self) -> f64 {
        photon_energy(self.lambda)
    }

    /// Where and after how long its trajectory crosses the plane z = h (if it does).
    fn cross_plane(&self, h: f64) -> Option<(DVec3, f64)> {
        let s = (h - self.x.z) / self.omega.z;
        (s > 0.0).then(|| (self.x + s * self.omega, s / SPEED_OF_LIGHT))
    }
}

fn main() {
    let n = samples_at_least(
        1 << 22,
        MIN_PHOTONS,
        &format!(
            "\n(01_phase_space: N photons span a time window T = N / {:.4e} s, shorter than the {:.2} ns flight\n to the detector below N = {:.0}; below {MIN_PHOTONS} too few arrive after it to judge)",
            candidate_rate(),
            longest_flight() * 1e9,
            (longest_flight() * candidate_rate()).ceil()
        ),
    );
    let (radiance, lambda, r_src, r_det, height) = SOURCE;
    let area = PI * r_src * r_src;
    let e = photon_energy(lambda);
    // Photon radiance: photons per second, per m², per sr.
    let photon_radiance = radiance / e;
    let candidate_rate = candidate_rate();
    let window = n as f64 / candidate_rate;

    println!(
        "1. Phase space: a photon is (x, ω, λ) at time t; it moves as x(t') = x + c (t' − t) ω"
    );
    println!(
        "   energy per photon e = h c / λ [J];  radiant energy Q = N e [J];  power Φ = dQ/dt [W]\n"
    );
    println!(
        "Source: Lambertian disk, radius {r_src} m, radiance L = {radiance:e} W/(m²·sr) at λ = {} nm",
        lambda * 1e9
    );
    println!(
        "  e = h c / λ = {e:.6e} J per photon;  photon radiance L / e = {photon_radiance:.4e} photons/(s·m²·sr)"
    );
    println!(
        "  simulating ~{n} candidate photons: a time window T = {:.4e} s",
        window
    );
    print_rule(&format!(
        "{n} candidate photons, engine estimates {} samples each",
        engine_samples(n)
    ));

    // The detector sees a photon after its time of flight; the earliest steady-state
    // arrival is after the longest flight (rim to opposite rim).
    let steady_from = longest_flight();
    // Times of flight of the detected photons, for the picture.
    const BINS: usize = 120;
    let plot_until = 6e-9;
    let mut flight_bins = [0u64; BINS];

    let sampler = Sampler::independent(1);
    let (mut emitted, mut received) = (0u64, 0u64);
    let mut q = 0.0; // radiant energy emitted (J): the sum of the photons' energies
    let mut t = 0.0;
    let mut shown = 0;
    for i in 0.. {
        let mut s = sampler.stream(i);
        // Poisson process in time: exponential gaps between candidate births.
        t += -(1.0 - s.next_1d() as f64).ln() / candidate_rate;
        if t > window {
            break;
        }
        let p = concentric_disk(s.next_2d()).as_dvec2() * r_src;
        let w = uniform_hemisphere(s.next_2d()).as_dvec3();
        // Thinning: keep the candidate with probability cos θ.
        if s.next_1d() as f64 >= w.z {
            continue;
        }
        let photon = Photon {
            x: DVec3::new(p.x, p.y, 0.0),
            omega: w,
            lambda,
            t,
        };
        emitted += 1;
        q += photon.energy();
        if shown < 3 {
            shown += 1;
            let later = photon.t + 2e-9;
            println!(
                "  photon {shown}: x = ({:+.3}, {:+.3}, 0) m, ω = ({:+.3}, {:+.3}, {:.3}), λ = {:.0} nm, t = {:.4e} s; 2 ns later at ({:+.3}, {:+.3}, {:.3}) m",
                photon.x.x,
                photon.x.y,
                w.x,
                w.y,
                w.z,
                photon.lambda * 1e9,
                photon.t,
                photon.at(later).x,
                photon.at(later).y,
                photon.at(later).z
            );
        }
        // Where does the trajectory cross the detector's plane z = h, and when?
        if let Some((hit, flight)) = photon.cross_plane(height)
            && DVec2::new(hit.x, hit.y).length() <= r_det
        {
            let b = ((flight / plot_until * BINS as f64) as usize).min(BINS - 1);
            flight_bins[b] += 1;
            let arrival = photon.t + flight;
            if arrival >= steady_from && arrival <= window {
                received += 1;
            }
        }
    }

    let mut ok = true;
    println!("\n  {emitted} photons emitted in T: radiant energy Q = N e = {q:.6e} J");
    println!("\nPower = energy per time; a Poisson count N has standard error √N:");
    let phi = lambertian_power(radiance, area);
    ok &= report(
        "emitted power Φ = N e / T  vs  π L A",
        &poisson(emitted, e / window, phi),
    );
    let f = disk_to_coaxial_disk(r_src, r_det, height);
    let span = window - steady_from;
    println!(
        "  detector: disk r = {r_det} m at h = {height} m, view factor F = {f:.6}; counting arrivals in [{steady_from:.3e}, T] s"
    );
    // MIN_PHOTONS keeps the window longer than the flight (a shorter one has nothing
    // to judge: that is a count too small, not a disagreement).
    assert!(
        span > 0.0,
        "{n} ≥ {MIN_PHOTONS} photons give a window past the flight"
    );
    ok &= report(
        "received power M e / Δt  vs  Φ F",
        &poisson(received, e / span, phi * f),
    );

    // Switch the source on at t = 0: the detector receives, at time t, the photons whose
    // flight took less than t, at the rate they were counted (per second of emission).
    let dt = plot_until / BINS as f64;
    let (mut leaving, mut arriving) = (vec![(0.0, 0.0)], vec![(0.0, 0.0)]);
    let mut cumulative = 0u64;
    for (i, &c) in flight_bins.iter().enumerate() {
        cumulative += c;
        let t_ns = (i + 1) as f64 * dt * 1e9;
        leaving.push((t_ns, emitted as f64 * e / window * 1e9));
        arriving.push((t_ns, cumulative as f64 * e / window * 1e9));
    }
    ok &= engine_phase_space(n);

    match plot(
        &leaving,
        &arriving,
        phi * 1e9,
        phi * f * 1e9,
        plot_until * 1e9,
    ) {
        Ok(p) => println!(
            "\nwrote {p} (power against time after the source switches on at t = 0: the detector follows after the time of flight)"
        ),
        Err(err) => println!("\n(could not write the plot: {err})"),
    }
    finish(ok);
}

/// The engine's own spectral and time machinery: photon counts of a blackbody and the
/// arrival-time distribution of a pulse.
fn engine_phase_space(n: u64) -> bool {
    use lightproof::transport::Estimator;
    use lightproof_analytic::spectrum::photon_radiance;
    use lightproof_analytic::time::pulsed_disk_on_axis;
    let mut ok = true;
    let samples = engine_samples(n);
    println!("\nThe engine, with wavelength and time as sampled dimensions:");
    let t = 3000.0;
    let photons = load(serde_json::json!({
        "name": "photon radiance of a 3000 K blackbody",
        "teaches": "N = ∫ B_λ λ/(hc) dλ",
        "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": 4 },
            "emission": { "radiance": 1, "spectrum": { "blackbody": { "temperature": t } } } } ] },
        "measure": { "radiance": { "at": [0, 0, 0], "direction": [0, 0, 1] } },
        "spectral": { "band": [10, 1e7], "sampling": "emitter", "photons": true },
        "estimators": ["mis"]
    }));
    println!(
        "  effects.wavelength: {}",
        photons.plan.effects.wavelength.why
    );
    ok &= report(
        "photon radiance of a 3000 K blackbody  vs  4ζ(3)k³T³/(h³c²)",
        &judged(&photons, Estimator::Mis, samples, 1, photon_radiance(t)),
    );
    // A Dirac pulse from a disk of radius R at height h: light arrives between h/c and
    // √(h² + R²)/c. Eight bins over that spread.
    let (r, h, l) = (1.0, 1.0, 1.0);
    let (t0, t1) = (h / SPEED_OF_LIGHT, (h * h + r * r).sqrt() / SPEED_OF_LIGHT);
    println!(
        "  a pulse at t = 0 from a disk (R = {r} m, h = {h} m) arrives between {t0:.4e} and {t1:.4e} s:"
    );
    for k in 0..8 {
        let (a, b) = (
            t0 + (t1 - t0) * k as f64 / 8.0,
            t0 + (t1 - t0) * (k + 1) as f64 / 8.0,
        );
        let case = load(serde_json::json!({
            "name": format!("pulsed disk bin {k}"),
            "teaches": "time of flight",
            "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, h], "normal": [0, 0, -1], "radius": r },
                "emission": { "radiance": l, "pulse_at": 0 } } ] },
            "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
            "time": { "bin": [a, b] },
            "estimators": ["light"]
        }));
        let exact = pulsed_disk_on_axis(r, h, l, a, b, SPEED_OF_LIGHT);
        ok &= report(
            &format!("exposure in [{:.3}, {:.3}] ns", a * 1e9, b * 1e9),
            &judged(&case, Estimator::Light, samples, 2 + k, exact),
        );
    }
    ok
}

/// The engine's sample count per estimate for `n` photons.
fn engine_samples(n: u64) -> u64 {
    (n / 16).max(1 << 12)
}

/// Judge a Poisson count scaled to a rate: estimate k·scale, standard error √k·scale.
fn poisson(count: u64, scale: f64, exact: f64) -> Verdict {
    let est = count as f64 * scale;
    let se = (count as f64).sqrt() * scale;
    judge_mean(est, se, exact, count.max(2))
}

fn plot(
    leaving: &[(f64, f64)],
    arriving: &[(f64, f64)],
    phi: f64,
    phi_f: f64,
    t_max: f64,
) -> Result<String, Box<dyn std::error::Error>> {
    common::save_svg("01_photon_flux.svg", (800, 480), |root| {
        let y_max = leaving
            .iter()
            .chain(arriving)
            .map(|p| p.1)
            .fold(phi, f64::max)
            * 1.15;
        let mut chart = common::chart(
            root,
            "Photon counting: power leaving the source and reaching the detector",
        )
        .build_cartesian_2d(0.0..t_max, 0.0..y_max)?;
        chart
            .configure_mesh()
            .x_desc("time after switching on (ns)")
            .y_desc("power (nW) = photons per second × e")
            .draw()?;
        chart
            .draw_series(LineSeries::new(leaving.iter().copied(), &BLUE))?
            .label("leaving the source (photon count)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
        chart
            .draw_series(LineSeries::new(arriving.iter().copied(), &RED))?
            .label("arriving at the detector")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
        for (v, c, l) in [
            (phi, BLACK, "Φ = π L A"),
            (phi_f, RGBColor(120, 120, 120), "Φ F (view factor)"),
        ] {
            chart
                .draw_series(LineSeries::new([(0.0, v), (t_max, v)], c.stroke_width(1)))?
                .label(l)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::MiddleRight)
            .draw()?;
        Ok(())
    })
}

mod common;
#[allow(unused_imports)]
use common::*;
