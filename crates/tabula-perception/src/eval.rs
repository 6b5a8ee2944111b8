//! Scoring perception against ground-truth labels (one label per point), as the
//! simulator's camera provides them: table precision/recall and object IoU.

use crate::tabletop::Tabletop;

/// How well one frame was perceived.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Score {
    pub table_precision: f64,
    pub table_recall: f64,
    /// Objects in the frame with at least `min_points` visible points.
    pub objects: usize,
    /// Of those, how many have a segment with IoU above the threshold.
    pub recovered: usize,
    /// Best IoU per object (same order as the labels given).
    pub best_iou: Vec<f64>,
    pub segments: usize,
}

/// A frame's ground truth: which points are finite, every point's label
/// (`table_label` for the table, the objects' labels in `object_labels`), and which
/// table points are on its top surface (the plane to find; the table's edges and legs
/// are not).
#[derive(Debug, Clone, Copy)]
pub struct Truth<'a> {
    pub finite: &'a [bool],
    pub labels: &'a [u32],
    pub table_label: u32,
    pub table_top: &'a [bool],
    pub object_labels: &'a [u32],
}

/// Scores `result` against the ground truth; an object counts as found at IoU ≥
/// `iou_threshold`. Objects with fewer than `min_points` finite points in the frame are
/// not counted (nobody can find what the camera does not see).
pub fn score(result: &Tabletop, truth: &Truth<'_>, iou_threshold: f64, min_points: usize) -> Score {
    let Truth {
        finite,
        labels,
        table_label,
        table_top,
        object_labels,
    } = *truth;
    let label = |i: usize| labels.get(i).copied().unwrap_or(0);
    let on_top = |i: usize| table_top.get(i) == Some(&true) && label(i) == table_label;
    let table_hits = result
        .table
        .inliers
        .iter()
        .filter(|&&i| label(i) == table_label)
        .count();
    let top_hits = result.table.inliers.iter().filter(|&&i| on_top(i)).count();
    let table_truth = (0..labels.len())
        .filter(|&i| finite.get(i) == Some(&true) && on_top(i))
        .count();
    let mut best_iou = Vec::new();
    let mut objects = 0;
    let mut recovered = 0;
    for &l in object_labels {
        let truth = (0..labels.len())
            .filter(|&i| finite.get(i) == Some(&true) && label(i) == l)
            .count();
        let best = result
            .objects
            .iter()
            .map(|o| {
                let inter = o.indices.iter().filter(|&&i| label(i) == l).count() as f64;
                inter / (o.indices.len() as f64 + truth as f64 - inter)
            })
            .fold(0.0, f64::max);
        if truth >= min_points {
            objects += 1;
            recovered += usize::from(best > iou_threshold);
        }
        best_iou.push(best);
    }
    Score {
        table_precision: table_hits as f64 / result.table.inliers.len().max(1) as f64,
        table_recall: top_hits as f64 / table_truth.max(1) as f64,
        objects,
        recovered,
        best_iou,
        segments: result.objects.len(),
    }
}

/// Which points of a frame lie on a table top at `height` (world z): within the 1 cm
/// RANSAC threshold (SPEC §6) of it. The simulator labels the table's edges and legs as
/// table too; they are not the plane a perception pipeline should return.
pub fn table_top_truth(points: &[tabula_geom::Vec3], height: f64) -> Vec<bool> {
    points
        .iter()
        .map(|p| (p.z - height).abs() <= 0.01)
        .collect()
}
