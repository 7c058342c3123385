//! Time-resolved histograms: a case whose `time` section gives `bins` (arrival-time bin
//! edges t₀ < t₁ < … < t_K, seconds) measures the whole transient response, one
//! estimate ± error per bin [t_k, t_{k+1}] — the radiant exposure of the light arriving
//! in that bin.
//!
//! Each bin is a case of its own (the file's case with `time.bin` = [t_k, t_{k+1}]),
//! estimated with its own seed, so the K estimates are independent and judged as K
//! members of the Šidák family. A reference names its closed form without `t1`/`t2`:
//! every bin sets them to its own edges (the pulsed disk's
//! `pulsed_disk_on_axis`), and the whole span [t₀, t_K] is the case itself. Running the
//! K bins costs K estimates of one bin's work each (a path's arrival time is drawn once
//! per bin); a histogram filled from one set of paths would cost one, but its bins would
//! share samples.

use super::{Case, seed_for};
use crate::error::InputError;
use crate::sampling::SamplerKind;
use crate::scene::Scene;
use crate::transport::Estimator;
use crate::verdict::Outcome;
use std::path::Path;
use std::sync::Arc;

/// Most bins of a histogram.
pub const MAX_BINS: usize = 1024;

/// The bin edges of a case description, checked: at least two, strictly increasing,
/// finite, at most [`MAX_BINS`] bins, and not beside a single `time.bin`; `None` for an
/// unbinned case.
pub fn edges(f: &str, desc: &super::CaseDesc) -> Result<Option<Vec<f64>>, InputError> {
    let Some(time) = &desc.time else {
        return Ok(None);
    };
    let Some(e) = &time.bins else {
        return Ok(None);
    };
    let bad = |why: String| Err(InputError::new(f, "time.bins", why));
    if time.bin.is_some() {
        return bad(
            "give either `bin` (one bin) or `bins` (edges of a histogram), not both".into(),
        );
    }
    if e.len() < 2 || e.len() > MAX_BINS + 1 {
        return bad(format!(
            "must list 2 to {} edges (1 to {MAX_BINS} bins), got {}",
            MAX_BINS + 1,
            e.len()
        ));
    }
    if let Some(x) = e.iter().find(|x| !x.is_finite()) {
        return bad(format!(
            "every edge must be a finite time in seconds, got {x}"
        ));
    }
    for &x in e {
        crate::error::check_number(f, "time.bins", x, |_| true, "a time in seconds")?;
    }
    if let Some(w) = e.windows(2).find(|w| !(w[1] > w[0])) {
        return bad(format!(
            "edges must increase strictly, got {} then {}",
            w[0], w[1]
        ));
    }
    if let Some(map) = &desc.reference {
        for p in ["t1", "t2"] {
            if map.contains_key(p) {
                return Err(InputError::new(
                    f,
                    format!("reference.{p}"),
                    "is set per bin from time.bins: leave it out",
                ));
            }
        }
    }
    Ok(Some(e.clone()))
}

/// The case description of the bin [a, b]: `time.bin` set, `bins` gone, and a
/// reference's `t1`, `t2` set to the edges.
pub fn with_bin(desc: &super::CaseDesc, a: f64, b: f64) -> super::CaseDesc {
    let mut d = desc.clone();
    if let Some(t) = d.time.as_mut() {
        t.bins = None;
        t.bin = Some([a, b]);
    }
    if let Some(map) = d.reference.as_mut() {
        map.insert("t1".into(), a.into());
        map.insert("t2".into(), b.into());
    }
    d
}

/// Build the case of every bin of `edges`, all on `scene` (the whole span's, built from
/// the same description: a bin changes what is measured, not the scene), so that up to
/// [`MAX_BINS`] bins hold one copy of its meshes and maps, not one each.
pub fn build(
    desc: &super::CaseDesc,
    path: &Path,
    edges: &[f64],
    scene: &Arc<Scene>,
) -> Result<Vec<Case>, InputError> {
    edges
        .windows(2)
        .enumerate()
        .map(|(k, w)| {
            Case::with_scene(with_bin(desc, w[0], w[1]), path, Some(scene))
                .map_err(|e| name_the_bins(e, &format!("bin {k} [{}, {}] s", w[0], w[1])))
        })
        .collect()
}

/// An error of a case built with `time.bin` set from `time.bins` (a bin, or the whole
/// span): named as the field the file holds, `time.bins`, with which of its bins.
pub fn name_the_bins(mut e: InputError, which: &str) -> InputError {
    if e.field == "time.bin" {
        e.field = "time.bins".into();
        e.reason = format!("{which}: {}", e.reason);
    }
    e
}

impl Case {
    /// The unjudged outcomes of every bin of a time-resolved histogram (none for an
    /// unbinned case), each with its own seed, in bin order; each names its bin.
    pub fn run_bins(
        &self,
        est: Estimator,
        sampler: SamplerKind,
        samples: u64,
        base_seed: u64,
    ) -> Vec<Outcome> {
        self.bins
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let seed = seed_for(
                    base_seed,
                    &format!("{} bin {k}", self.desc.name),
                    est,
                    sampler,
                );
                let mut o = c.run(est, sampler, samples, seed);
                o.bin = c.desc.time.as_ref().and_then(|t| t.bin);
                o
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::CaseDesc;

    fn catalog_case() -> (CaseDesc, std::path::PathBuf) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("analytic/cases/time/pulsed_disk_transient.json");
        let text = std::fs::read_to_string(&path).unwrap();
        (serde_json::from_str(&text).unwrap(), path)
    }

    #[test]
    fn every_bin_is_a_case_with_its_own_edges_and_reference() {
        let (desc, path) = catalog_case();
        let c = Case::from_desc(desc.clone(), &path).unwrap();
        let e = desc.time.as_ref().unwrap().bins.clone().unwrap();
        assert_eq!(c.bins.len(), e.len() - 1);
        // The bins' references add up to the whole span's: the exposure is additive in time.
        let sum: f64 = c.bins.iter().map(|b| b.reference.unwrap()).sum();
        let whole = c.reference.unwrap();
        assert!((sum - whole).abs() <= 1e-12 * whole, "{sum} vs {whole}");
        for (b, w) in c.bins.iter().zip(e.windows(2)) {
            assert_eq!(b.desc.time.as_ref().unwrap().bin, Some([w[0], w[1]]));
        }
        // Each bin runs with its own seed: independent estimates, named by their bin.
        let o = c.run_bins(
            crate::transport::Estimator::Light,
            SamplerKind::Independent,
            1 << 10,
            3,
        );
        assert_eq!(o.len(), c.bins.len());
        assert!(o.windows(2).all(|p| p[0].seed != p[1].seed));
        assert_eq!(o[1].bin, Some([e[1], e[2]]));
        assert!(o[1].bin_suffix().contains("ns"));
        // One scene for the case and every bin (up to 1024 of them), not a copy each,
        // and the same one a bin would build on its own (the bin changes no origin).
        assert!(c.bins.iter().all(|b| Arc::ptr_eq(&b.scene, &c.scene)));
        let alone = Case::from_desc(with_bin(&desc, e[1], e[2]), &path).unwrap();
        assert_eq!(alone.scene.prims(), c.bins[1].scene.prims());
    }

    #[test]
    fn bad_edges_are_named() {
        let (desc, path) = catalog_case();
        let with = |f: &dyn Fn(&mut CaseDesc)| {
            let mut d = desc.clone();
            f(&mut d);
            Case::from_desc(d, &path).err().map(|e| e.to_string())
        };
        let set =
            |e: Vec<f64>| move |d: &mut CaseDesc| d.time.as_mut().unwrap().bins = Some(e.clone());
        for (edit, want) in [
            (
                Box::new(set(vec![1e-9])) as Box<dyn Fn(&mut CaseDesc)>,
                "2 to 1025 edges",
            ),
            (Box::new(set(vec![2e-9, 1e-9])), "increase strictly"),
            (Box::new(set(vec![1e-9, 1e-9, 2e-9])), "increase strictly"),
            (Box::new(set(vec![0.0, f64::NAN])), "finite"),
            (Box::new(set(vec![0.0, 1e300])), "time.bins"),
            (
                Box::new(|d: &mut CaseDesc| d.time.as_mut().unwrap().bin = Some([0.0, 1e-9])),
                "not both",
            ),
            (
                Box::new(|d: &mut CaseDesc| {
                    d.reference
                        .as_mut()
                        .unwrap()
                        .insert("t1".into(), 0.0.into());
                }),
                "reference.t1",
            ),
            // A bin's own check (its width a normal f32) names `time.bins` and the bin,
            // not the `time.bin` each bin is built with; so does the whole span's.
            (
                Box::new(set(vec![1e-30, 1e-30 + 1e-39, 1e-9])),
                "time.bins: bin 0 [",
            ),
            (
                Box::new(set(vec![2e-38, 2.5e-38, 3e-38])),
                "time.bins: the whole span: its width",
            ),
        ] {
            let e = with(&*edit).expect("refused");
            assert!(
                e.contains(want) && e.contains("pulsed_disk_transient") && !e.contains("time.bin:"),
                "{e}"
            );
        }
    }
}
