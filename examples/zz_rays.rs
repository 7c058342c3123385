use glam::Vec3;
use lightproof::sampling::Sampler;
use lightproof::sampling::sphere::uniform_sphere;
use lightproof::scene::accel::Accel;
use lightproof::scene::shape::Primitive;
fn mesh() -> Vec<Primitive> {
    let (nt, np) = (158usize, 316usize);
    let p = |i: usize, j: usize| {
        let t = std::f32::consts::PI * i as f32 / nt as f32;
        let f = 2.0 * std::f32::consts::PI * j as f32 / np as f32;
        Vec3::new(t.sin() * f.cos(), t.sin() * f.sin(), t.cos())
    };
    let mut out = Vec::new();
    for i in 0..nt {
        for j in 0..np {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            out.push(Primitive::Triangle { p: [a, b, c] });
            out.push(Primitive::Triangle { p: [a, c, d] });
        }
    }
    out.retain(|t| t.area() > 0.0);
    out
}
fn main() {
    let accel = Accel::new(mesh());
    let s = Sampler::independent(3);
    let rays: Vec<(Vec3, Vec3)> = (0..65536u64)
        .map(|i| {
            let mut st = s.stream(i);
            let o = uniform_sphere(st.next_2d()) * 3.0;
            let target = uniform_sphere(st.next_2d()) * 0.5;
            (o, (target - o).normalize())
        })
        .collect();
    let mut best = f64::MAX;
    let mut hits = 0;
    for _ in 0..30 {
        let t = std::time::Instant::now();
        hits = rays
            .iter()
            .filter(|(o, d)| accel.intersect(*o, *d, 0.0, f32::INFINITY).is_some())
            .count();
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "{hits} hits, best {:.2} M rays/s",
        rays.len() as f64 / best / 1e6
    );
}
