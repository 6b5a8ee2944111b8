//! `bench stable-poses`: the stable-pose search (seed 000) timed on the test objects,
//! each written as an OBJ file for trimesh to read the same meshes.

use anyhow::{Context, Result};
use std::path::Path;
use tabula_robot::ik::bench::thread_cpu_seconds;
use tabula_tasks::stable::{StableParams, of_mesh};

/// One object: its size, its poses, the most likely one, the search's CPU.
#[derive(serde::Serialize)]
pub struct BenchRow {
    pub object: String,
    pub vertices: usize,
    pub poses: usize,
    pub most_likely_normal: Option<[f64; 3]>,
    pub most_likely_probability: Option<f64>,
    pub cpu_ms_median: f64,
}

/// Writes each test object into `dir` and times the search on it (median CPU over
/// `reps`), calling `tick` after each.
pub fn run(dir: &Path, reps: usize, tick: &mut dyn FnMut()) -> Result<Vec<BenchRow>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let params = StableParams::default();
    let mut rows = Vec::new();
    let catalogue = tabula_sim::objects::catalogue();
    for o in catalogue {
        let path = dir.join(format!("{}.obj", o.name));
        std::fs::write(&path, o.to_obj())
            .with_context(|| format!("cannot write {}", path.display()))?;
        let mut times = Vec::with_capacity(reps);
        let mut last = None;
        for _ in 0..reps.max(1) {
            let c0 = thread_cpu_seconds();
            let s = of_mesh(&o.vertices, &o.triangles, &params)?;
            times.push((thread_cpu_seconds() - c0) * 1e3);
            last = Some(s);
        }
        times.sort_by(f64::total_cmp);
        let s = last.context("no repetition")?;
        let ml = s.most_likely.map(|i| &s.poses[i]);
        rows.push(BenchRow {
            object: o.name.clone(),
            vertices: o.vertices.len(),
            poses: s.poses.len(),
            most_likely_normal: ml.map(|p| p.support_normal.map(|x| (x * 1e3).round() / 1e3 + 0.0)),
            most_likely_probability: ml.map(|p| p.probability),
            cpu_ms_median: times[times.len() / 2],
        });
        tick();
    }
    Ok(rows)
}
