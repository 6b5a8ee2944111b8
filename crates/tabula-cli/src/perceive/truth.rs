//! `perceive --labels` and `perceive --score`: the segmentation as a labelled cloud in
//! PCL's convention, and a ground truth read from the benchmarks' files to score it.

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use std::path::Path;
use tabula_geom::input::{Format, read_bytes};
use tabula_geom::{CloudFile, PcdEncoding, PcdExtras};
use tabula_perception::frame::read_cloud_file;
use tabula_perception::score::{SegmentationScore, mark_image_border, score};

/// How a ground truth's labels name objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TruthFormat {
    /// mOSD (PCL's data, `segmentation/mOSD`): 0 nothing, 1–9 parts of the table,
    /// 10·k + j part j of object k, scored by object (its parts merged, as the
    /// dataset's `merge_object_parts.sh` does). The default for a PCD.
    Mosd,
    /// mOSD scored by part: every label ≥ 10 its own object (a geometry-only method
    /// cannot know that an occluded object's disjoint parts are one).
    MosdParts,
    /// OCID / OSD label images: 0 background, 1 the table, every other value an object.
    /// The default for a PNG.
    Ocid,
    /// 0 background, every other value an object (tabula's own `--labels`).
    Plain,
}

/// Writes the input's grid (its points, colours and viewpoint as read) with a `label`
/// field: 0 not an object, k ≥ 1 segment k (binary PCD, as `pcl_viewer` reads it).
pub fn write_labels(path: &Path, file: &CloudFile, labels: &[u32]) -> Result<()> {
    let mut out = std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("--labels {}", path.display()))?,
    );
    let extras = PcdExtras {
        viewpoint: file.viewpoint,
        colors: file.colors.as_deref(),
        labels: Some(labels),
    };
    file.cloud
        .write_pcd_with(&mut out, PcdEncoding::Binary, &extras)
        .and_then(|()| std::io::Write::flush(&mut out))
        .with_context(|| format!("--labels {}", path.display()))
}

/// Scores `labels` against the ground truth in `path` (a PCD with a `label` field or a
/// PNG of labels on the same grid).
pub fn score_against(
    path: &Path,
    format: Option<TruthFormat>,
    file: &CloudFile,
    labels: &[u32],
) -> Result<SegmentationScore> {
    let (raw, width, height, default) = if is_png(path)? {
        let (raw, w, h) = read_png_labels(path)?;
        (raw, w, h, TruthFormat::Ocid)
    } else {
        let truth = read_cloud_file(path)?;
        let Some(raw) = truth.labels else {
            bail!("--score {}: the cloud has no `label` field", path.display());
        };
        (
            raw,
            truth.cloud.width,
            truth.cloud.height,
            TruthFormat::Mosd,
        )
    };
    let (w, h) = (file.cloud.width, file.cloud.height);
    if (width, height) != (w, h) {
        bail!(
            "--score {}: the ground truth is {width} × {height}, the cloud {w} × {h} (the same grid is needed)",
            path.display()
        );
    }
    let truth = objects_of(&raw, format.unwrap_or(default));
    let mut scored =
        score(labels, &truth).context("ground truth and segmentation differ in size")?;
    mark_image_border(&mut scored, &truth, w, h);
    Ok(scored)
}

/// Ground-truth labels as object ids: 0 not an object, the same id for one object.
pub fn objects_of(raw: &[u32], format: TruthFormat) -> Vec<u32> {
    raw.iter()
        .map(|&l| match format {
            TruthFormat::Mosd | TruthFormat::MosdParts if l < 10 => 0,
            TruthFormat::Mosd => l / 10,
            TruthFormat::MosdParts => l,
            TruthFormat::Ocid if l <= 1 => 0,
            TruthFormat::Ocid | TruthFormat::Plain => l,
        })
        .collect()
}

fn is_png(path: &Path) -> Result<bool> {
    use std::io::Read;
    let mut head = [0u8; 8];
    let mut f = std::fs::File::open(path).with_context(|| format!("--score {}", path.display()))?;
    let n = f.read(&mut head).unwrap_or(0);
    Ok(n == 8 && head == *b"\x89PNG\r\n\x1a\n")
}

/// A PNG of labels: grey values (8 or 16 bits) are the labels; colours (a palette
/// image expanded) are told apart, black being 0.
fn read_png_labels(path: &Path) -> Result<(Vec<u32>, usize, usize)> {
    let bytes = read_bytes(path, Format::Cloud)?;
    let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .with_context(|| format!("--score {}", path.display()))?;
    let (w, h) = (image.width() as usize, image.height() as usize);
    let labels = match image {
        image::DynamicImage::ImageLuma8(g) => g.into_raw().into_iter().map(u32::from).collect(),
        image::DynamicImage::ImageLuma16(g) => g.into_raw().into_iter().map(u32::from).collect(),
        other => {
            let rgb = other.to_rgb8();
            let mut ids = std::collections::HashMap::from([([0u8; 3], 0u32)]);
            rgb.pixels()
                .map(|p| {
                    let next = ids.len() as u32;
                    *ids.entry(p.0).or_insert(next)
                })
                .collect()
        }
    };
    Ok((labels, w, h))
}

/// The score as the lines `perceive` prints.
pub fn score_lines(s: &SegmentationScore) -> Vec<String> {
    let mut lines = vec![format!(
        "score: {} objects, {} segments; overlap precision {:.3}, recall {:.3}, F {:.3}; objects at IoU ≥ 0.5: {} ({:.1} %), at F ≥ 0.75: {:.1} %; extra segments (≥ 500 points): {}",
        s.objects,
        s.segments,
        s.precision,
        s.recall,
        s.f_measure,
        s.found_iou50,
        100.0 * s.found_iou50_share,
        100.0 * s.objects_f75,
        s.extra_segments
    )];
    for m in &s.per_object {
        lines.push(match m.segment {
            0 => format!("  object {}: {} points, not found", m.label, m.points),
            k => format!(
                "  object {}: {} points, segment {k} (IoU {:.2}, F {:.2})",
                m.label, m.points, m.iou, m.f_measure
            ),
        });
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_format_names_its_objects() {
        let raw = [0, 1, 9, 10, 11, 23, 2];
        assert_eq!(objects_of(&raw, TruthFormat::Mosd), [0, 0, 0, 1, 1, 2, 0]);
        assert_eq!(
            objects_of(&raw, TruthFormat::MosdParts),
            [0, 0, 0, 10, 11, 23, 0]
        );
        assert_eq!(
            objects_of(&raw, TruthFormat::Ocid),
            [0, 0, 9, 10, 11, 23, 2]
        );
        assert_eq!(
            objects_of(&raw, TruthFormat::Plain),
            [0, 1, 9, 10, 11, 23, 2]
        );
    }
}
