//! `tabula demo`: the main job — the tour in `tabula_bench::demo`, told on the terminal
//! under a progress bar.

use anyhow::Result;
use std::path::Path;

pub fn run(report_dir: &Path) -> Result<()> {
    let progress = crate::progress::steps(9, "demo");
    let mut started = false;
    let page = tabula_bench::demo::run(
        report_dir,
        &mut |line| progress.suspend(|| println!("{line}")),
        &mut |part| {
            if started {
                progress.inc(1);
            }
            started = true;
            progress.set_message(part.to_string());
        },
    )?;
    progress.finish_and_clear();
    println!("\nreport (pictures, plots, 3D replays): {}", page.display());
    Ok(())
}
