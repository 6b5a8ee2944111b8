//! The report's parts for placing: a run's section, the scanned model's line, the
//! bench's page.

use super::{Recorded, Report, Section};
use crate::place::{BenchRow, PlaceRun};
use crate::stats::wilson;
use anyhow::Result;
use tabula_tasks::place::PlaceParams;

/// The report's part for a placement: the verdict, the scanned model and its stable
/// poses, time per phase, the replay and pictures of the release.
pub fn section(
    report: &mut Report,
    out: &PlaceRun,
    params: &PlaceParams,
    recorded: Option<&Recorded>,
) -> Result<Section> {
    let r = &out.report;
    let v = &out.verdict;
    let mut s = Section::new("Placing an unknown object (seed 000)");
    s.text(format!(
        "{}: `{}` rests on {}, {:.1}° from the planned pose, moved {:.1} mm after release.",
        if out.success { "Placed" } else { "Failed" },
        v.object,
        v.surface.as_deref().unwrap_or("nothing"),
        v.orientation_error_deg,
        v.moved_after_release_m * 1e3
    ));
    if let Some(e) = &out.error {
        s.text(format!("Error ({}): {}", e.kind, e.message));
    }
    s.number("success", out.success)
        .number("arm", r.arm.as_deref().unwrap_or("-"))
        .number("decision CPU (ms)", format!("{:.1}", out.decision_ms))
        .number("scan processing CPU (ms)", format!("{:.1}", r.scan_cpu_ms))
        .number("stable poses found", r.poses_found)
        .number("surfaces found", r.surfaces_found)
        .number("spots tried", r.candidates_tried)
        .number(
            "orientation error (°)",
            format!("{:.2}", v.orientation_error_deg),
        )
        .number("furniture contacts", v.furniture_contacts.len());
    if let Some(m) = &r.model {
        s.number("scanned model", model_line(m));
    }
    s.log = r
        .rejected
        .iter()
        .map(|w| format!("rejected: {w}"))
        .collect();
    if !r.model_points.is_empty()
        && let Ok(poses) = tabula_tasks::stable::of_cloud(&r.model_points, &params.stable)
        && !poses.poses.is_empty()
    {
        let bars: Vec<(String, f64)> = poses
            .poses
            .iter()
            .take(12)
            .map(|p| {
                let chosen = out
                    .stable_pose
                    .as_ref()
                    .is_some_and(|c| c.normal().dot(p.normal()) > 0.999);
                (
                    format!(
                        "({:+.2} {:+.2} {:+.2}) margin {:.0} mm, {:.0}°{}",
                        p.support_normal[0],
                        p.support_normal[1],
                        p.support_normal[2],
                        p.margin_m * 1e3,
                        p.topple_deg,
                        if chosen { " — placed" } else { "" }
                    ),
                    100.0 * p.probability,
                )
            })
            .collect();
        let svg = super::plots::bars(
            "Stable poses of the scanned object (support normal in the hand)",
            "landing probability (%)",
            &bars,
        )?;
        let fig = report.svg(
            "stable-poses",
            "Stable poses of the scanned model: probability, stability margin, topple tilt",
            &svg,
        )?;
        s.figures.push(fig);
    }
    if let Some(view) = &r.top_view {
        // Objects as the outlines of their points seen from above.
        let objects = view
            .objects
            .iter()
            .map(|pts| {
                let flat: Vec<tabula_geom::Vec2> =
                    pts.iter().map(|q| view.map.to_plane(*q)).collect();
                tabula_geom::polygon::convex_hull_2d(&flat)
                    .into_iter()
                    .map(|i| pts[i])
                    .collect()
            })
            .collect();
        let (svg, _) = super::frame::top_view(&super::frame::TopView {
            map: &view.map,
            outline: &view.outline,
            objects,
            boxes: Vec::new(),
            labels: Vec::new(),
            spot: view.spot.clone(),
        })?;
        let fig = report.svg(
            "top-view",
            "The surface as the placement saw it: free (green), objects (red), unseen (grey), the object's footprint where it was planned to rest (blue)",
            &svg,
        )?;
        s.figures.push(fig);
    }
    super::pick_place::phase_plot(report, &mut s, &out.phases)?;
    if let Some(rec) = recorded {
        report.recorded(&mut s, "place", rec)?;
    }
    Ok(s)
}

/// The scanned model in one line: points, views, size in the tool frame, hull volume.
pub fn model_line(m: &tabula_tasks::place::ModelReport) -> String {
    format!(
        "{} points from {} of {} views, {:.0} × {:.0} × {:.0} mm, hull {:.1} cm³",
        m.points,
        m.views,
        m.views_tried,
        m.size[0] * 1e3,
        m.size[1] * 1e3,
        m.size[2] * 1e3,
        m.hull_volume_m3 * 1e6
    )
}

/// The report page of `bench place`: the success rate with its interval, failures by
/// cause, success per object class, decision times.
pub fn bench_page(
    dir: &std::path::Path,
    command: String,
    rows: &[BenchRow],
    causes: &std::collections::BTreeMap<&str, usize>,
) -> Result<()> {
    let n = rows.len();
    let k = rows.iter().filter(|r| r.success).count();
    let (lo, hi) = wilson(k, n);
    let mut numbers = vec![
        ("trials".to_string(), n.to_string()),
        (
            "placed (95 % interval)".to_string(),
            format!(
                "{k} = {:.1} % ({:.1}–{:.1} %)",
                100.0 * k as f64 / n.max(1) as f64,
                100.0 * lo,
                100.0 * hi
            ),
        ),
    ];
    numbers.extend(
        causes
            .iter()
            .map(|(c, count)| (format!("failed: {c}"), count.to_string())),
    );
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Placing an unknown object (seed 000)",
            command,
            numbers,
            classes: (
                "object class",
                super::per_class(rows.iter().map(|r| (r.object.as_str(), r.success))),
            ),
            distributions: vec![(
                "Decision CPU per task",
                "ms",
                rows.iter().map(|r| r.decision_ms).collect(),
            )],
            bars: Vec::new(),
        },
        &rows,
    )?;
    Ok(())
}

/// What `bench place` prints: a line per task, the success rate with its interval, the
/// table found, the grips that leave a resting face, failures by cause.
pub fn bench_lines(
    suite: &str,
    rows: &[BenchRow],
    causes: &std::collections::BTreeMap<&str, usize>,
) -> Vec<String> {
    let mut lines = Vec::new();
    for r in rows {
        lines.push(format!(
            "{:>5} {:<14} {:<7} clutter {} {:<5} {:<8} {:>6.1}° {:>7.1} mm {:>8.1} ms {:>6}  {}",
            r.seed,
            r.object,
            format!("{:?}", r.layout).to_lowercase(),
            r.clutter,
            r.arm,
            if r.success { "placed" } else { "FAILED" },
            r.orientation_error_deg.min(999.0),
            r.moved_after_release_mm.min(9999.0),
            r.decision_ms,
            r.normal_error_deg
                .map_or(String::new(), |e| format!("n{e:.1}°")),
            r.cause.as_deref().unwrap_or("")
        ));
    }
    let n = rows.len();
    let k = rows.iter().filter(|r| r.success).count();
    let (lo, hi) = wilson(k, n);
    let decisions: Vec<f64> = rows.iter().map(|r| r.decision_ms).collect();
    let d = tabula_robot::ik::bench::Spread::of(&decisions);
    lines.push(format!(
        "{suite}: {k}/{n} placed = {:.1} % (95 % interval {:.1}–{:.1} %); decision CPU median {:.0} ms, p95 {:.0} ms",
        100.0 * k as f64 / n.max(1) as f64,
        lo * 100.0,
        hi * 100.0,
        d.median,
        d.p95
    ));
    let found = rows.iter().filter(|r| r.table_found).count();
    let (flo, fhi) = wilson(found, n);
    lines.push(format!(
        "the table found by the sweep: {found}/{n} = {:.1} % (95 % interval {:.1}–{:.1} %)",
        100.0 * found as f64 / n.max(1) as f64,
        flo * 100.0,
        fhi * 100.0
    ));
    let free: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| r.grip_allows_rest == Some(true))
        .collect();
    let judged = rows.iter().filter(|r| r.grip_allows_rest.is_some()).count();
    if judged > 0 {
        let placed = free.iter().filter(|r| r.success).count();
        let (plo, phi) = wilson(placed, free.len());
        lines.push(format!(
            "grips that leave the true object a resting face: {}/{judged}; of those, {placed} placed = {:.1} % (95 % interval {:.1}–{:.1} %)",
            free.len(),
            100.0 * placed as f64 / free.len().max(1) as f64,
            plo * 100.0,
            phi * 100.0
        ));
    }
    if !causes.is_empty() {
        lines.push(format!(
            "failures by cause: {}",
            causes
                .iter()
                .map(|(c, n)| format!("{c} {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    lines
}
