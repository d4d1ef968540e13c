//! The histogram of a result's batch values: groups of batches (the diffusing and the bounded
//! ones of a field run) as bars on common bins, with the estimate marked.

use std::path::Path;

use crate::Error;
use crate::report::figures::{PlotSpec, Series, plot};

/// A histogram of the batch values of each group `(label, values)`, on bins common to all, as
/// bars (translucent, so groups show through each other), with `mean` marked; `(title,
/// x_label)` name it.
pub(super) fn histogram(
    groups: &[(String, &[f64])],
    mean: f64,
    (title, x_label): (&str, &str),
    stem: &Path,
) -> Result<(), Error> {
    let all = || groups.iter().flat_map(|g| g.1.iter().copied());
    let lo = all().fold(f64::INFINITY, f64::min);
    let hi = all().fold(f64::NEG_INFINITY, f64::max);
    let bins = ((all().count() as f64).sqrt().ceil() as usize).max(4);
    let width = ((hi - lo) / bins as f64).max(f64::MIN_POSITIVE);
    let mut series = Vec::new();
    let mut top = 1.0f64;
    for (label, x) in groups.iter().filter(|g| !g.1.is_empty()) {
        let mut counts = vec![0u32; bins];
        for v in x.iter() {
            counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
        }
        top = top.max(f64::from(*counts.iter().max().unwrap_or(&1)));
        series.push(Series {
            label: label.clone(),
            points: counts
                .iter()
                .enumerate()
                .map(|(i, c)| (lo + (i as f64 + 0.5) * width, f64::from(*c), 0.0))
                .collect(),
            notes: Vec::new(),
            line: false,
        });
    }
    series.push(Series {
        label: "mean".into(),
        points: vec![(mean, 0.0, 0.0), (mean, top, 0.0)],
        notes: Vec::new(),
        line: true,
    });
    let spec = PlotSpec {
        count_y: true,
        bar_width: Some(width),
        ..PlotSpec::new(title, x_label, "batches")
    };
    plot(stem, &spec, &series)
}
