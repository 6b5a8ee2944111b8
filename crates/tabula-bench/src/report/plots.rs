//! Plots for reports, drawn with plotters into SVG: bars by category (time per phase,
//! success per object class), stacked bars over frames (decision latency and its
//! parts), histograms (timing distributions).

use anyhow::{Result, anyhow};
use plotters::coord::ranged1d::SegmentValue;
use plotters::prelude::*;

const SIZE: (u32, u32) = (720, 380);
const FONT: &str = "sans-serif";

/// The palette series are drawn in (colour-blind safe, Okabe–Ito).
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(213, 94, 0),
];

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("plot: {e}")
}

/// The series' labels in a box at the upper right.
fn legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Result<()> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .draw()
        .map_err(err)
}

/// Axis numbers with the digits their size needs (1e-6 is not "0.0").
fn tick(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-2..1e5).contains(&a) {
        format!("{v:.1e}")
    } else if a < 1.0 {
        format!("{v:.3}")
    } else if a < 100.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.0}")
    }
}

fn upper(max: f64) -> f64 {
    if max.is_finite() && max > 0.0 {
        max * 1.1
    } else {
        1.0
    }
}

/// Horizontal bars, one per `(label, value)`, top to bottom in the given order.
pub fn bars(title: &str, unit: &str, items: &[(String, f64)]) -> Result<String> {
    let mut svg = String::new();
    {
        let n = items.len().max(1);
        let height = (90 + 26 * n as u32).max(160);
        let root = SVGBackend::with_string(&mut svg, (SIZE.0, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let max = items.iter().map(|i| i.1).fold(0.0, f64::max);
        let label_width = items
            .iter()
            .map(|i| i.0.chars().count())
            .max()
            .unwrap_or(4)
            .clamp(4, 40) as u32
            * 7
            + 10;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FONT, 18))
            .margin(10)
            .x_label_area_size(32)
            .y_label_area_size(label_width)
            .build_cartesian_2d(0.0..upper(max), (0..n).into_segmented())
            .map_err(err)?;
        let labels: Vec<&str> = items.iter().map(|i| i.0.as_str()).collect();
        chart
            .configure_mesh()
            .disable_y_mesh()
            .x_desc(unit)
            .x_label_formatter(&tick)
            .y_labels(n)
            .y_label_formatter(&|v| match v {
                // Row 0 at the top: the first item reads first.
                SegmentValue::CenterOf(i) => labels
                    .get(n - 1 - *i)
                    .map(|s| s.to_string())
                    .unwrap_or_default(),
                _ => String::new(),
            })
            .draw()
            .map_err(err)?;
        chart
            .draw_series(items.iter().enumerate().map(|(k, (_, v))| {
                let row = n - 1 - k;
                let mut r = Rectangle::new(
                    [
                        (0.0, SegmentValue::Exact(row)),
                        (*v, SegmentValue::Exact(row + 1)),
                    ],
                    PALETTE[0].filled(),
                );
                r.set_margin(4, 4, 0, 0);
                r
            }))
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Bars stacked per step (e.g. per frame: perception, predicates, planning, IK).
pub fn stacked(
    title: &str,
    x_desc: &str,
    unit: &str,
    parts: &[&str],
    steps: &[Vec<f64>],
) -> Result<String> {
    let mut svg = String::new();
    {
        let n = steps.len().max(1);
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let max = steps
            .iter()
            .map(|s| s.iter().sum::<f64>())
            .fold(0.0, f64::max);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FONT, 18))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(56)
            .build_cartesian_2d((1..n + 1).into_segmented(), 0.0..upper(max))
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_desc(x_desc)
            .y_desc(unit)
            .y_label_formatter(&tick)
            .x_labels(n.min(20))
            .draw()
            .map_err(err)?;
        for (p, name) in parts.iter().enumerate() {
            let colour = PALETTE[p % PALETTE.len()];
            chart
                .draw_series(steps.iter().enumerate().map(|(k, s)| {
                    let below: f64 = s.iter().take(p).sum();
                    let here = s.get(p).copied().unwrap_or(0.0);
                    let mut r = Rectangle::new(
                        [
                            (SegmentValue::Exact(k + 1), below),
                            (SegmentValue::Exact(k + 2), below + here),
                        ],
                        colour.filled(),
                    );
                    r.set_margin(0, 0, 3, 3);
                    r
                }))
                .map_err(err)?
                .label(*name)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled())
                });
        }
        legend(&mut chart)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// A histogram of `values` in `bins` equal bins, with the median marked.
pub fn histogram(title: &str, unit: &str, values: &[f64], bins: usize) -> Result<String> {
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
        let max = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        // A few far outliers (a page fault, a preempted thread) would squash the rest
        // into one bar: the axis ends at the 99th percentile, the rest are counted in
        // the last bin and said in the legend.
        let p99 = quantile(&finite, 0.99).unwrap_or(max);
        let hi = if max > lo + 2.0 * (p99 - lo) {
            p99
        } else {
            max
        };
        let beyond = finite.iter().filter(|v| **v > hi).count();
        let (lo, hi) = if finite.is_empty() {
            (0.0, 1.0)
        } else if hi - lo < 1e-12 {
            (lo - 0.5 * lo.abs().max(1e-3), hi + 0.5 * hi.abs().max(1e-3))
        } else {
            (lo, hi)
        };
        let bins = bins.max(1);
        let width = (hi - lo) / bins as f64;
        let mut counts = vec![0usize; bins];
        for v in &finite {
            counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
        }
        let top = counts.iter().copied().max().unwrap_or(0).max(1) as f64;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FONT, 18))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(50)
            .build_cartesian_2d(lo..hi, 0.0..top * 1.1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_desc(if beyond > 0 {
                format!(
                    "{unit} ({beyond} values beyond the axis, up to {}, in the last bin)",
                    tick(&max)
                )
            } else {
                unit.to_string()
            })
            .x_label_formatter(&tick)
            .y_desc("count")
            .draw()
            .map_err(err)?;
        chart
            .draw_series(counts.iter().enumerate().map(|(b, c)| {
                let x0 = lo + b as f64 * width;
                let mut r =
                    Rectangle::new([(x0, 0.0), (x0 + width, *c as f64)], PALETTE[0].filled());
                r.set_margin(0, 0, 1, 1);
                r
            }))
            .map_err(err)?;
        if let Some(m) = median(&finite) {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(m, 0.0), (m, top * 1.05)],
                    PALETTE[5].stroke_width(2),
                )))
                .map_err(err)?
                .label(format!("median {m:.3}"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], PALETTE[5]));
            legend(&mut chart)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Box plots side by side: for each category (an axis, a measure) one box per series
/// (a solver), quartiles and 1.5 IQR whiskers; `log` draws the values on a log scale
/// (errors that span orders of magnitude), values below 1e-18 drawn at 1e-18.
pub fn boxes(
    title: &str,
    unit: &str,
    categories: &[&str],
    series: &[(&str, Vec<Vec<f64>>)],
    log: bool,
) -> Result<String> {
    const FLOOR: f64 = 1e-18;
    let clean = |v: &[f64]| -> Vec<f32> {
        v.iter()
            .filter(|x| x.is_finite())
            .map(|x| if log { x.max(FLOOR) } else { *x } as f32)
            .collect()
    };
    let data: Vec<Vec<Vec<f32>>> = series
        .iter()
        .map(|(_, per)| per.iter().map(|v| clean(v)).collect())
        .collect();
    let all = data.iter().flatten().flatten().copied();
    let (lo, hi) = all.fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else if lo.is_finite() {
        (lo * 0.5, lo * 2.0 + 1e-9)
    } else {
        (1e-6, 1.0)
    };
    let n = categories.len().max(1);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(title, (FONT, 18))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(64);
        let x = (0..n).into_segmented();
        let labels: Vec<&str> = categories.to_vec();
        let x_fmt = |v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(i) => labels.get(*i).map(|s| s.to_string()).unwrap_or_default(),
            _ => String::new(),
        };
        let width = (480 / (n * series.len().max(1))).clamp(6, 40) as u32;
        let step = width as f64 + 4.0;
        let first = -(series.len() as f64 - 1.0) / 2.0 * step;
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .disable_x_mesh()
                    .x_labels(n)
                    .x_label_formatter(&x_fmt)
                    .y_desc(unit)
                    .y_label_formatter(&|v: &f32| tick(&(*v as f64)))
                    .draw()
                    .map_err(err)?;
                for (k, (name, _)) in series.iter().enumerate() {
                    let colour = PALETTE[k % PALETTE.len()];
                    let offset = first + k as f64 * step;
                    chart
                        .draw_series(
                            data[k]
                                .iter()
                                .enumerate()
                                .filter(|(_, v)| !v.is_empty())
                                .map(|(c, v)| {
                                    Boxplot::new_vertical(
                                        SegmentValue::CenterOf(c),
                                        &Quartiles::new(v),
                                    )
                                    .width(width)
                                    .offset(offset)
                                    .style(colour.stroke_width(2))
                                }),
                        )
                        .map_err(err)?
                        .label(*name)
                        .legend(move |(x, y)| {
                            Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled())
                        });
                }
                legend(&mut chart)?;
            }};
        }
        if log {
            draw!(
                builder
                    .build_cartesian_2d(x, (lo * 0.5..hi * 2.0).log_scale())
                    .map_err(err)?
            );
        } else {
            let pad = (hi - lo) * 0.05;
            draw!(
                builder
                    .build_cartesian_2d(x, (lo - pad).min(0.0)..hi + pad)
                    .map_err(err)?
            );
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

pub use crate::stats::median;

/// The `q` quantile of the finite `values` (nearest rank), `None` when there are none.
fn quantile(values: &[f64], q: f64) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[((v.len() - 1) as f64 * q).round() as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_are_svg_with_their_labels() {
        let b = bars(
            "phases",
            "ms",
            &[("scan".into(), 3.0), ("plan".into(), 1.0)],
        )
        .unwrap();
        assert!(b.starts_with("<svg") && b.contains("scan") && b.contains("plan"));
        let s = stacked(
            "decision",
            "frame",
            "ms",
            &["perception", "planning"],
            &[vec![1.0, 2.0], vec![3.0, 0.5]],
        )
        .unwrap();
        assert!(s.contains("perception") && s.matches("<rect").count() >= 4);
        let h = histogram("ik", "µs", &[1.0, 2.0, 2.0, 3.0, f64::NAN], 5).unwrap();
        assert!(h.contains("median 2.000"));
        let mut slow = vec![1.0; 300];
        slow.push(4000.0);
        let h = histogram("ik", "µs", &slow, 5).unwrap();
        assert!(h.contains("1 values beyond the axis"), "{h}");
        assert_eq!(tick(&2.5e-7), "2.5e-7");
        let b = boxes(
            "errors",
            "m",
            &["x", "y"],
            &[
                ("a", vec![vec![1e-9, 2e-9, 3e-9], vec![0.0, 1e-12]]),
                ("b", vec![vec![1e-6, f64::NAN], vec![]]),
            ],
            true,
        )
        .unwrap();
        // The title, both legend entries, and a box (its rectangle) per non-empty group.
        let flat = b.replace('\n', "");
        assert!(
            flat.contains(">errors</text>")
                && flat.contains(">a</text>")
                && flat.contains(">b</text>"),
            "{b}"
        );
        assert!(b.matches("<rect").count() >= 3, "{b}");
    }

    #[test]
    fn empty_and_constant_inputs_still_plot() {
        assert!(bars("none", "ms", &[]).is_ok());
        assert!(stacked("none", "frame", "ms", &["a"], &[]).is_ok());
        assert!(histogram("same", "ms", &[2.0, 2.0], 10).is_ok());
        assert!(histogram("empty", "ms", &[], 10).is_ok());
    }
}
