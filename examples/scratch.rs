use lightproof::verify::*;
fn main() {
    for f in std::env::args().skip(1) {
        let c = Case::load(std::path::Path::new(&f)).unwrap_or_else(|e| panic!("{e}"));
        println!("{:?}", c.effects.max_bounces);
        for o in run_case(&c, 1, None, 1, 1e-4, 10) {
            let v = o.verdict.unwrap();
            println!("{} {:?} est {:.6} ± {:.6} ref {:.6} z {:.2} det {:.4} {:.3}s {}", o.case, o.estimator, o.estimate, o.std_error, v.reference, v.z, v.detectable_relative_bias, o.seconds, v.passed);
        }
    }
}
