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
