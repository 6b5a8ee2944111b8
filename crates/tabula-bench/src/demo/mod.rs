//! `tabula demo`: the four jobs end to end in the simulator, then the capabilities they
//! stand on, told line by line and written into one report page.

use crate::report::{Report, Section};
use anyhow::Result;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Tells a line and keeps it for the report's capabilities section.
macro_rules! say {
    ($tour:expr, $($t:tt)*) => {{
        $tour.say(format!($($t)*));
    }};
}

/// Tells a line without keeping it.
macro_rules! tell {
    ($tour:expr, $($t:tt)*) => {{
        $tour.tell(format!($($t)*));
    }};
}

mod capabilities;
mod jobs;
mod perception;

/// Where the demo's lines go: told through the caller's printer, the capabilities'
/// lines kept for the report.
pub struct Tour<'a> {
    print: &'a mut dyn FnMut(&str),
    kept: Vec<String>,
}

impl<'a> Tour<'a> {
    fn new(print: &'a mut dyn FnMut(&str)) -> Self {
        Self {
            print,
            kept: Vec::new(),
        }
    }

    fn tell(&mut self, line: String) {
        (self.print)(&line);
    }

    fn say(&mut self, line: String) {
        (self.print)(&line);
        self.kept.push(line);
    }
}

/// Runs the jobs end to end in the simulator (placing, clearing, pick and place, tidying),
/// then the capabilities they stand on, and writes the report into `report_dir`.
pub fn run(
    report_dir: &Path,
    print: &mut dyn FnMut(&str),
    step: &mut dyn FnMut(&str),
) -> Result<PathBuf> {
    let mut tour = Tour::new(print);
    tour.tell("tabula demo\n===========\n".into());
    let t0 = Instant::now();
    let mut report = Report::create(report_dir, "tabula demo — the jobs in the simulator")?;
    let mut jobs = Vec::new();
    let mut summary = Vec::new();
    step("placing an unknown object");
    let (section, json, line) = jobs::placing(&mut tour, &mut report)?;
    jobs.push(section);
    summary.push(("placing", json, line));
    step("clearing a cluttered table");
    let (section, json, line) = jobs::clearing(&mut tour, &mut report)?;
    jobs.push(section);
    summary.push(("clearing", json, line));
    step("pick and place");
    let (section, json, line) = jobs::pick_place(&mut tour, &mut report)?;
    jobs.push(section);
    summary.push(("pick_place", json, line));
    step("tidying a table");
    let (section, json, line) = jobs::tidying(&mut tour, &mut report)?;
    jobs.push(section);
    summary.push(("tidying", json, line));
    step("kinematics");
    capabilities::kinematics(&mut tour)?;
    step("task planning");
    capabilities::planning(&mut tour)?;
    step("simulator");
    let frame = capabilities::simulator(&mut tour)?;
    step("perception");
    let perceived = perception::perception(&frame, &mut tour, &mut report)?;
    step("motion planning");
    capabilities::motion(&mut tour)?;

    let mut overview = Section::new("Summary");
    overview.text(
        "Four jobs, end to end in tabula's simulator, each judged by its physics: the PR2 \
         places an object it holds and has no model of (seed 000), the WAM clears a cluttered \
         table into a bin by grasps and pushes (seed 002), Golem-III moves a can from a shelf \
         to a table (seed 001), and the PR2 tidies a table onto another (built from the \
         other three's skills). Each section has a 3D replay (drag to turn, wheel to zoom, \
         the slider scrubs), pictures of every grasp and release from the scene's camera and \
         from an overview, and plots.",
    );
    for (name, _, line) in &summary {
        overview.number(name.replace('_', " "), line);
    }
    overview.number(
        "wall time (s)",
        format!("{:.1}", t0.elapsed().as_secs_f64()),
    );
    // One picture per job at the top: the overview eye when the hand lets go.
    for job in &jobs {
        if let Some(f) = job
            .figures
            .iter()
            .find(|f| f.caption.contains("lets go") && f.caption.ends_with("from overview"))
        {
            overview.figures.push(crate::report::Figure {
                file: f.file.clone(),
                caption: format!("{} — {}", job.title, f.caption),
            });
        }
    }
    let mut capabilities = Section::new("What the jobs stand on");
    capabilities.text(
        "Kinematics, task planning, the simulator, perception and motion planning on their \
         own (benchmarks against KDL/IKFast, Fast Downward, Gazebo, PCL and MoveIt are in \
         BENCHMARKS.md).",
    );
    capabilities.log = tour.kept;
    report.sections.push(overview);
    report.sections.extend(jobs);
    report.sections.push(perceived);
    report.sections.push(capabilities);
    let json = serde_json::json!({
        "jobs": summary.iter().map(|(n, j, _)| (n.to_string(), j.clone())).collect::<serde_json::Map<_, _>>(),
        "wall_s": t0.elapsed().as_secs_f64(),
    });
    let page = report.finish(&json)?;
    print("\nSummary");
    for (name, _, line) in &summary {
        print(&format!("  {:<11} {line}", name.replace('_', " ")));
    }
    Ok(page)
}
