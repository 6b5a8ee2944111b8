//! The report's part for a pick and place, and the time-per-phase plot every task with
//! phases shows.

use super::{Recorded, Report, Section};
use crate::pick_place::PickPlaceRun;
use anyhow::Result;

/// The report's part for a pick and place: the verdict, the phases, the replay.
pub fn section(
    report: &mut Report,
    out: &PickPlaceRun,
    recorded: Option<&Recorded>,
) -> Result<Section> {
    let r = &out.report;
    let v = &out.verdict;
    let mut s = Section::new("Pick and place by coordinates (seed 001)");
    s.text(format!(
        "{}: arm {}, {} grasp; `{}` ended {:.1} cm from the target, tilted {:.1}°.",
        if out.success { "Success" } else { "Failed" },
        r.arm.as_deref().unwrap_or("-"),
        r.grasp
            .map_or("-".into(), |g| format!("{g:?}").to_lowercase()),
        v.object,
        v.target_error * 100.0,
        v.tilt.to_degrees()
    ));
    if let Some(e) = &out.error_message {
        s.text(format!("Error: {e}"));
    }
    s.number("success", out.success)
        .number("arm", r.arm.as_deref().unwrap_or("-"))
        .number("decision CPU (ms)", format!("{:.1}", r.decision_cpu_ms))
        .number("grasp candidates tried", r.candidates_tried)
        .number(
            "target error (cm)",
            format!("{:.2}", v.target_error * 100.0),
        )
        .number("tilt (°)", format!("{:.2}", v.tilt.to_degrees()))
        .number("furniture contacts", v.furniture_contacts.len());
    s.log = r
        .rejected
        .iter()
        .map(|w| format!("rejected: {w}"))
        .collect();
    phase_plot(report, &mut s, &r.phases)?;
    if let Some(rec) = recorded {
        report.recorded(&mut s, "pick-place", rec)?;
    }
    Ok(s)
}

/// Time per phase as bars (wall ms: the simulated motion is in it).
pub fn phase_plot(
    report: &mut Report,
    section: &mut Section,
    phases: &[tabula_tasks::pick_place::Phase],
) -> Result<()> {
    if phases.is_empty() {
        return Ok(());
    }
    let bars: Vec<(String, f64)> = phases
        .iter()
        .map(|p| {
            (
                format!("{}{}", p.name, if p.ok { "" } else { " (failed)" }),
                p.ms,
            )
        })
        .collect();
    let svg = super::plots::bars(
        "Time per phase",
        "ms (wall, simulated motion included)",
        &bars,
    )?;
    let fig = report.svg("phases", "Time per phase", &svg)?;
    section.figures.push(fig);
    Ok(())
}
