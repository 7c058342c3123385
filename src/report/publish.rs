//! Publishing a finished sweep (a whole run, or the merge of shards): the case reports
//! with their plots, then the index. Both [`super::sweep`] and [`super::shard`] end here,
//! so neither depends on the other for it.

use super::store::{plot_file, report_file, write_bytes, write_json};
use super::{CaseReport, Index};
use crate::error::{Error, IoError};
use std::path::{Path, PathBuf};

/// What a run (or a merge) wrote.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The case reports (not for a shard).
    pub reports: Vec<CaseReport>,
    /// The index, after this run.
    pub index: Option<Index>,
    /// A shard's partial file.
    pub partial: Option<PathBuf>,
    /// Points computed.
    pub computed: u64,
    /// Points kept from an earlier run.
    pub resumed: u64,
    /// Whether the budget stopped the run.
    pub budget_cut: bool,
    /// Things worth telling (a report started afresh, ...).
    pub notes: Vec<String>,
}

/// A note naming a case whose points counted non-finite samples (left out of their
/// estimates): otherwise only each point's `non_finite` in the JSON says so.
fn non_finite_note(r: &CaseReport) -> Option<String> {
    let (mut samples, mut points, mut series) = (0u64, 0usize, 0usize);
    for s in &r.series {
        let bad = s.points.iter().filter(|p| p.non_finite > 0);
        let n = bad.clone().count();
        samples = samples.saturating_add(bad.map(|p| p.non_finite).sum::<u64>());
        points += n;
        series += usize::from(n > 0);
    }
    (points > 0).then(|| {
        format!(
            "{}: {samples} non-finite sample(s) in {points} point(s) of {series} series, left out of their estimates (each point's `non_finite`)",
            r.id
        )
    })
}

/// Write the final case reports with their plots, then the index.
///
/// A case with nothing to plot (an error of zero at every point: an exact case) gets
/// `plot: null`, a note saying why, and no SVG: one an earlier run left is removed, so
/// that no picture contradicts its report.
pub fn publish(out: &Path, reports: &mut [CaseReport]) -> Result<Summary, Error> {
    let mut notes = vec![];
    for r in reports.iter_mut() {
        let svg = plot_file(&r.id);
        r.plot = match super::plot::svg(r) {
            Ok(text) => {
                write_bytes(&out.join(&svg), text.as_bytes())?;
                Some(svg)
            }
            Err(why) => {
                let stale = out.join(&svg);
                if stale.symlink_metadata().is_ok() {
                    std::fs::remove_file(&stale).map_err(|e| IoError::write(&stale, e))?;
                }
                notes.push(format!("{}: no plot ({why})", r.id));
                None
            }
        };
        write_json(&out.join(report_file(&r.id)), r, true)?;
        notes.extend(non_finite_note(r));
    }
    let index = super::index::update(out, reports)?;
    Ok(Summary {
        reports: reports.to_vec(),
        index: Some(index),
        partial: None,
        computed: 0,
        resumed: 0,
        budget_cut: reports.iter().any(|r| r.run.budget_cut),
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Non-finite samples are told on stderr, naming the case and how many samples,
    /// points and series; none, no note.
    #[test]
    fn non_finite_samples_are_noted() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports/examples/disk_on_axis.json");
        let text = std::fs::read_to_string(&path).unwrap();
        let mut r: CaseReport = crate::error::parse_json("r.json", &text).unwrap();
        assert_eq!(non_finite_note(&r), None);
        r.series[0].points[1].non_finite = 2;
        r.series[0].points[3].non_finite = 1;
        r.series[2].points[0].non_finite = 4;
        let note = non_finite_note(&r).unwrap();
        assert_eq!(
            note,
            "disk_on_axis: 7 non-finite sample(s) in 3 point(s) of 2 series, left out of their estimates (each point's `non_finite`)"
        );
    }
}
