//! # 2. Solid angle and projected solid angle
//!
//! The solid angle of a shape seen from a point is the area of its "shadow" on the unit
//! sphere around that point: σ = ∫_S dω, in steradians (sr). The whole sphere is 4π sr.
//! A small patch of area A at distance R, facing the viewer, subtends σ ≈ A/R²; in
//! general each patch dA contributes dω = cos θl dA / r² (θl: angle between the patch
//! normal and the line of sight).
//!
//! The projected solid angle weights each direction by the cosine to a receiver's
//! normal: σ⊥ = ∫_S cos θ dω. It is what irradiance needs (E = L σ⊥ for a uniform
//! emitter, example 4); the whole hemisphere has σ⊥ = π.
//!
//! The scenes are written as case files (JSON, the format `lightproof verify` reads) and
//! estimated by Monte Carlo two ways: uniform directions on the sphere (count the hits,
//! σ ≈ 4π · hits / N) and uniform points on the shape's area (sum cos θl / (r² p_A)).
//!
//! Run: `cargo run --release --example 02_solid_angle -- [SAMPLES]`

use lightproof::transport::Estimator;
use serde_json::json;

/// A case file: a sphere of radius 1 at distance 3 subtends the cap σ = 2π(1 − cos α),
/// sin α = R/d.
const SPHERE_CASE: &str = r#"{
  "name": "solid angle of a sphere",
  "teaches": "a sphere of radius R at distance d subtends σ = 2π(1 − √(1 − R²/d²))",
  "scene": { "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 3], "radius": 1 } } ] },
  "measure": { "solid_angle": { "from": [0, 0, 0], "shape": 0 } },
  "reference": { "closed_form": "solid_angle_sphere", "point": [0, 0, 0], "center": [0, 0, 3], "radius": 1 },
  "estimators": ["uniform", "area"],
  "samplers": ["sobol"], "samples": 1048576
}"#;

fn main() {
    let n = samples(1 << 20);
    println!(
        "2. Solid angle: σ = ∫_S dω = ∫_A cos θl / r² dA  [sr];  projected: σ⊥ = ∫_S cos θ dω  [sr]"
    );
    print_rule(&format!("{n} samples per estimate"));
    let mut ok = true;

    // A sphere of radius 1 at distance 3: the cap formula σ = 2π(1 − cos α), sin α = R/d.
    show_case_file("02_sphere.json", SPHERE_CASE);
    let sphere: serde_json::Value = serde_json::from_str(SPHERE_CASE).unwrap();
    ok &= check_all("sphere R = 1 at d = 3", sphere, n);

    let triangle = json!({
        "name": "solid angle of a triangle",
        "teaches": "Van Oosterom–Strackee: tan(σ/2) = r1·(r2×r3) / (r1r2r3 + (r1·r2)r3 + (r1·r3)r2 + (r2·r3)r1)",
        "scene": { "shapes": [ { "geometry": { "type": "triangle",
            "vertices": [[-1, -0.5, 2], [1, -0.5, 2], [0, 1, 2.5]] } } ] },
        "measure": { "solid_angle": { "from": [0, 0, 0], "shape": 0 } },
        "reference": { "closed_form": "solid_angle_triangle", "point": [0, 0, 0],
            "vertices": [[-1, -0.5, 2], [1, -0.5, 2], [0, 1, 2.5]] },
        "estimators": ["uniform", "area"]
    });
    ok &= check_all("triangle", triangle, n);

    let rect = |corner: [f64; 3], u: [f64; 3], v: [f64; 3], estimators: &[&str]| {
        json!({
            "name": "solid angle of a rectangle",
            "teaches": "σ of a rectangle by inclusion–exclusion of four corner rectangles",
            "scene": { "shapes": [ { "geometry": { "type": "rectangle", "corner": corner, "edge_u": u, "edge_v": v } } ] },
            "measure": { "solid_angle": { "from": [0, 0, 0], "shape": 0 } },
            "reference": { "closed_form": "solid_angle_rectangle", "point": [0, 0, 0], "corner": corner, "edge_u": u, "edge_v": v },
            "estimators": estimators
        })
    };
    ok &= check_all(
        "rectangle 2 × 1.5 at 2",
        rect(
            [-1.0, -1.0, 2.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.5, 0.0],
            &["uniform", "area"],
        ),
        n,
    );

    // σ ≈ A/R² for a small facing patch: a 0.1 × 0.1 square at distance 10. Uniform
    // directions would almost never hit it (σ/4π ≈ 8e-6): sample its area instead.
    let small = rect(
        [-0.05, -0.05, 10.0],
        [0.1, 0.0, 0.0],
        [0.0, 0.1, 0.0],
        &["area"],
    );
    let (area, r) = (0.01f64, 10.0f64);
    println!(
        "  small far patch: A/R² = {:.8} sr (the approximation); the exact value follows",
        area / (r * r)
    );
    ok &= check_all("square 0.1 × 0.1 at 10", small, n);

    // Projected solid angle of the rectangle for a receiver at the origin facing +z.
    let verts = json!([[-1, -1, 2], [1, -1, 2], [1, 0.5, 2], [-1, 0.5, 2]]);
    let projected = json!({
        "name": "projected solid angle of a rectangle",
        "teaches": "σ⊥ = ∫ cos θ dω = ½ Σ edges Θ_i n·(unit normal of the plane through p and edge i)",
        "scene": { "shapes": [ { "geometry": { "type": "rectangle", "corner": [-1, -1, 2], "edge_u": [2, 0, 0], "edge_v": [0, 1.5, 0] } } ] },
        "measure": { "projected_solid_angle": { "from": [0, 0, 0], "normal": [0, 0, 1], "shape": 0 } },
        "reference": { "closed_form": "polygon_projected_solid_angle", "point": [0, 0, 0], "normal": [0, 0, 1], "vertices": verts },
        "estimators": ["uniform", "cosine", "area"]
    });
    println!("\nProjected solid angle σ⊥ = ∫ cos θ dω (≤ σ; the hemisphere has σ⊥ = π, σ = 2π):");
    ok &= check_all("rectangle, receiver facing it", projected, n);

    finish(ok);
}

/// Load a case description, run each of its estimators and judge it against its
/// closed-form reference.
fn check_all(label: &str, desc: serde_json::Value, n: u64) -> bool {
    let case = load(desc);
    let exact = case.reference.expect("every case here names a closed form");
    let mut ok = true;
    for &est in &case.desc.estimators {
        let v = judged(&case, est, n, 2, exact);
        ok &= report(&format!("{label} [{}]", est_name(est)), &v);
    }
    ok
}

fn est_name(e: Estimator) -> &'static str {
    match e {
        Estimator::Uniform => "uniform directions",
        Estimator::Cosine => "cosine directions",
        Estimator::Area => "uniform area",
        // Path-tracer strategies: no direct measurement of this example takes them.
        e @ (Estimator::Light | Estimator::Bsdf | Estimator::Mis | Estimator::MisBalance) => {
            e.name()
        }
    }
}

mod common;
#[allow(unused_imports)]
use common::*;
