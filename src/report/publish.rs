//! Publishing a finished sweep (a whole run, or the merge of shards): the case reports
//! with their plots, then the index. Both [`super::sweep`] and [`super::shard`] end here,
//! so neither depends on the other for it.

use super::store::{plot_file, report_file, write_bytes, write_json};
use super::{CaseReport, Index};
use crate::error::Error;
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
pub fn publish(out: &Path, reports: &mut [CaseReport]) -> Result<Summary, Error> {
    for r in reports.iter_mut() {
        let svg = plot_file(&r.id);
        r.plot = match super::plot::svg(r) {
            Ok(text) => {
                write_bytes(&out.join(&svg), text.as_bytes())?;
                Some(svg)
            }
            Err(_) => None,
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
        notes: vec![],
    })
}
