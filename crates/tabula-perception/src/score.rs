//! Segmentation scored as the unseen-object benchmarks score it (OSD, OCID; Xie et al.,
//! "Unseen Object Instance Segmentation", 2021): segments matched one to one with the
//! ground truth's objects by the Hungarian method on their F-measure, then the overlap
//! precision, recall and F over all pixels of the frame, the share of objects whose
//! match has F ≥ 0.75 and IoU ≥ 0.5, and the segments that match nothing.
//!
//! Both labellings are per point of the same grid: 0 = not an object, k ≥ 1 = segment
//! or object k (a ground truth's own convention is mapped to this one by its reader).

use pathfinding::prelude::{Matrix, kuhn_munkres};
use serde::Serialize;
use std::collections::HashMap;

/// Segments smaller than this that match no object are noise, not extra objects (the
/// issue's "≥ 500 points").
pub const MIN_EXTRA_POINTS: usize = 500;

/// How a segmentation compares with a ground truth.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SegmentationScore {
    /// Objects in the ground truth, segments in the answer.
    pub objects: usize,
    pub segments: usize,
    /// Overlap precision, recall and F-measure (matched pixels over all segment pixels,
    /// over all object pixels; their harmonic mean).
    pub precision: f64,
    pub recall: f64,
    pub f_measure: f64,
    /// Objects whose matched segment has F ≥ 0.75 (OCID's "%75"), as a share.
    pub objects_f75: f64,
    /// Objects whose matched segment has IoU ≥ 0.5, as a count and a share.
    pub found_iou50: usize,
    pub found_iou50_share: f64,
    /// Segments of at least [`MIN_EXTRA_POINTS`] points matched to no object (or to one
    /// they overlap by IoU < 0.5).
    pub extra_segments: usize,
    /// Per object: its ground-truth label, size, the segment matched (0: none) and the
    /// match's IoU.
    pub per_object: Vec<ObjectMatch>,
}

/// One ground-truth object and what it was matched to.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ObjectMatch {
    pub label: u32,
    pub points: usize,
    pub segment: u32,
    pub iou: f64,
    pub f_measure: f64,
    /// Whether the object reaches the image's border (within [`BORDER_PIXELS`]): only
    /// part of it is in view, so a segmentation may call it partial. Set by
    /// [`mark_image_border`] (a grid is needed).
    pub at_image_border: bool,
}

/// An object with a pixel this near the image's border is cut by it (a Kinect's last
/// three or four rows have almost no depth, so its objects end a few rows short).
pub const BORDER_PIXELS: usize = 5;

/// Marks the objects of `truth` (labels on a `width` × `height` grid) that reach the
/// image's border (none on an unorganized cloud's one row: it has no image).
pub fn mark_image_border(s: &mut SegmentationScore, truth: &[u32], width: usize, height: usize) {
    if width == 0 || height < 2 || truth.len() != width * height {
        return;
    }
    let mut cut = std::collections::HashSet::new();
    for (i, &l) in truth.iter().enumerate().filter(|&(_, &l)| l != 0) {
        let (x, y) = (i % width, i / width);
        let b = BORDER_PIXELS;
        if x < b || y < b || x + b >= width || y + b >= height {
            cut.insert(l);
        }
    }
    for m in &mut s.per_object {
        m.at_image_border = cut.contains(&m.label);
    }
}

/// Compares `segments` with `truth`, one label per point each (0 = not an object).
/// `None` when the two differ in length.
pub fn score(segments: &[u32], truth: &[u32]) -> Option<SegmentationScore> {
    if segments.len() != truth.len() {
        return None;
    }
    let (seg_ids, seg_sizes) = sizes(segments);
    let (obj_ids, obj_sizes) = sizes(truth);
    let mut overlap = vec![vec![0usize; seg_ids.len()]; obj_ids.len()];
    let seg_index: HashMap<u32, usize> = seg_ids.iter().enumerate().map(|(i, &l)| (l, i)).collect();
    let obj_index: HashMap<u32, usize> = obj_ids.iter().enumerate().map(|(i, &l)| (l, i)).collect();
    for (&s, &t) in segments.iter().zip(truth) {
        if s != 0 && t != 0 {
            overlap[obj_index[&t]][seg_index[&s]] += 1;
        }
    }
    let f = |o: usize, s: usize| {
        let both = overlap[o][s] as f64;
        if both == 0.0 {
            0.0
        } else {
            2.0 * both / (obj_sizes[o] + seg_sizes[s]) as f64
        }
    };
    let iou = |o: usize, s: usize| {
        let both = overlap[o][s];
        both as f64 / (obj_sizes[o] + seg_sizes[s] - both).max(1) as f64
    };
    let assignment = hungarian(obj_ids.len(), seg_ids.len(), &f);
    let mut per_object = Vec::with_capacity(obj_ids.len());
    let mut matched_pixels = 0usize;
    let mut good_segments = vec![false; seg_ids.len()];
    for (o, matched) in assignment.iter().enumerate() {
        let (segment, iou_o, f_o) = match *matched {
            Some(s) if overlap[o][s] > 0 => {
                matched_pixels += overlap[o][s];
                good_segments[s] = iou(o, s) >= 0.5;
                (seg_ids[s], iou(o, s), f(o, s))
            }
            _ => (0, 0.0, 0.0),
        };
        per_object.push(ObjectMatch {
            label: obj_ids[o],
            points: obj_sizes[o],
            segment,
            iou: iou_o,
            f_measure: f_o,
            at_image_border: false,
        });
    }
    let total_seg: usize = seg_sizes.iter().sum();
    let total_obj: usize = obj_sizes.iter().sum();
    let ratio = |a: usize, b: usize| if b == 0 { 0.0 } else { a as f64 / b as f64 };
    let (precision, recall) = (
        ratio(matched_pixels, total_seg),
        ratio(matched_pixels, total_obj),
    );
    let found_iou50 = per_object.iter().filter(|m| m.iou >= 0.5).count();
    let extra_segments = (0..seg_ids.len())
        .filter(|&s| !good_segments[s] && seg_sizes[s] >= MIN_EXTRA_POINTS)
        .count();
    Some(SegmentationScore {
        objects: obj_ids.len(),
        segments: seg_ids.len(),
        precision,
        recall,
        f_measure: if precision + recall > 0.0 {
            2.0 * precision * recall / (precision + recall)
        } else {
            0.0
        },
        objects_f75: ratio(
            per_object.iter().filter(|m| m.f_measure >= 0.75).count(),
            obj_ids.len(),
        ),
        found_iou50,
        found_iou50_share: ratio(found_iou50, obj_ids.len()),
        extra_segments,
        per_object,
    })
}

/// The non-zero labels in order and how many points each has.
fn sizes(labels: &[u32]) -> (Vec<u32>, Vec<usize>) {
    let mut count: HashMap<u32, usize> = HashMap::new();
    for &l in labels.iter().filter(|&&l| l != 0) {
        *count.entry(l).or_default() += 1;
    }
    let mut ids: Vec<u32> = count.keys().copied().collect();
    ids.sort_unstable();
    let sizes = ids.iter().map(|l| count[l]).collect();
    (ids, sizes)
}

/// For each of `rows` objects, the column (segment) of a one-to-one assignment that
/// maximises the summed `weight`, or `None`.
fn hungarian(rows: usize, cols: usize, weight: &dyn Fn(usize, usize) -> f64) -> Vec<Option<usize>> {
    if rows == 0 || cols == 0 {
        return vec![None; rows];
    }
    // kuhn_munkres wants rows ≤ columns and integer weights: pad with zero columns,
    // weights in parts per 10⁹.
    let n_cols = cols.max(rows);
    let scaled = |r: usize, c: usize| {
        if c < cols {
            (weight(r, c) * 1e9).round() as i64
        } else {
            0
        }
    };
    let matrix = Matrix::from_fn(rows, n_cols, |(r, c)| scaled(r, c));
    let (_, assignment) = kuhn_munkres(&matrix);
    assignment
        .into_iter()
        .enumerate()
        .map(|(r, c)| (c < cols && scaled(r, c) > 0).then_some(c))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_perfect_segmentation_scores_one_and_a_merge_loses_an_object() {
        let truth = [0, 1, 1, 1, 2, 2, 2, 0, 3, 3];
        let same = [0, 7, 7, 7, 4, 4, 4, 0, 9, 9];
        let s = score(&same, &truth).unwrap();
        assert_eq!((s.precision, s.recall, s.f_measure), (1.0, 1.0, 1.0));
        assert_eq!(
            (s.found_iou50, s.extra_segments, s.objects_f75),
            (3, 0, 1.0)
        );
        // Objects 1 and 2 as one segment: one of them is matched, the other is not.
        let merged = [0, 5, 5, 5, 5, 5, 5, 0, 9, 9];
        let s = score(&merged, &truth).unwrap();
        assert_eq!(s.found_iou50, 2);
        assert!((s.precision - 5.0 / 8.0).abs() < 1e-12, "{}", s.precision);
        assert!((s.recall - 5.0 / 8.0).abs() < 1e-12);
        assert_eq!(s.per_object.iter().filter(|m| m.segment == 0).count(), 1);
    }

    #[test]
    fn a_split_object_and_a_segment_on_the_table() {
        // Object 1 split in halves; a big segment where there is no object.
        let mut truth = vec![0u32; 2000];
        let mut seg = vec![0u32; 2000];
        truth[..400].fill(1);
        seg[..200].fill(1);
        seg[200..400].fill(2);
        seg[1000..1600].fill(3);
        let s = score(&seg, &truth).unwrap();
        assert_eq!(s.found_iou50, 1, "a half is IoU 0.5");
        assert_eq!(
            s.extra_segments, 1,
            "the other half is small; the table segment is extra"
        );
        assert!(score(&seg[..10], &truth).is_none());
        let none = score(&[0; 5], &[0; 5]).unwrap();
        assert_eq!((none.objects, none.segments, none.f_measure), (0, 0, 0.0));
    }
}
