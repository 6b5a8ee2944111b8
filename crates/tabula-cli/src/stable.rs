//! `tabula stable-poses` and `tabula bench stable-poses`: how an object rests (SPEC §1.2).

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use tabula_geom::Vec3;
use tabula_robot::ik::bench::thread_cpu_seconds;
use tabula_tasks::stable::{StableParams, StablePoses, of_cloud, of_mesh};

#[derive(clap::Args)]
pub struct StablePosesArgs {
    /// A mesh (OBJ, STL or PLY with faces), in the object's frame.
    #[arg(long, conflicts_with = "cloud", required_unless_present = "cloud")]
    mesh: Option<PathBuf>,
    /// A scanned cloud (PCD or PLY), in the object's frame.
    #[arg(long)]
    cloud: Option<PathBuf>,
    /// Parameters (TOML, `StableParams`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
    /// TOML to start a file from, and exit.
    #[arg(long, exclusive = true)]
    print_params: bool,
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct StableJson<'a> {
    #[serde(flatten)]
    poses: &'a StablePoses,
    cpu_ms: f64,
}

/// Stable poses of a mesh file or a cloud file, and the CPU time they took.
pub fn compute(
    mesh: Option<&Path>,
    cloud: Option<&Path>,
    params: &StableParams,
) -> Result<(StablePoses, f64)> {
    match (mesh, cloud) {
        (Some(path), None) => {
            let (v, t) = tabula_geom::mesh::load_mesh(path, [1.0; 3])
                .map_err(|e| anyhow::anyhow!("{}: {}", e.path, e.message))?;
            let c0 = thread_cpu_seconds();
            let s = of_mesh(&v, &t, params).with_context(|| format!("{}", path.display()))?;
            Ok((s, (thread_cpu_seconds() - c0) * 1e3))
        }
        (None, Some(path)) => {
            let cloud = crate::perceive::read_cloud(path)?;
            let points: Vec<Vec3> = cloud
                .points
                .iter()
                .copied()
                .filter(|p| p.is_finite())
                .collect();
            let c0 = thread_cpu_seconds();
            let s = of_cloud(&points, params).with_context(|| format!("{}", path.display()))?;
            Ok((s, (thread_cpu_seconds() - c0) * 1e3))
        }
        _ => bail!("give --mesh FILE or --cloud FILE"),
    }
}

pub fn run(args: StablePosesArgs) -> Result<()> {
    if args.print_params {
        return crate::tasks::print_params::<StableParams>();
    }
    let params: StableParams = crate::tasks::load_params(args.params.as_deref())?;
    let (s, cpu_ms) = compute(args.mesh.as_deref(), args.cloud.as_deref(), &params)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&StableJson { poses: &s, cpu_ms })?
        );
        return Ok(());
    }
    let c = s.center_of_mass;
    println!(
        "hull: {} vertices, {} facets, {:.1} cm³; centre of mass ({:.4}, {:.4}, {:.4}) m ({:?})",
        s.hull_vertices,
        s.hull_facets,
        s.hull_volume_m3 * 1e6,
        c[0],
        c[1],
        c[2],
        s.com_method
    );
    println!(
        "{:>3}  {:>24}  {:>7}  {:>8}  {:>8}  {:>8}",
        "#", "support normal (object)", "prob", "margin", "topple", "area"
    );
    for (i, p) in s.poses.iter().enumerate() {
        let n = p.support_normal;
        println!(
            "{:>3}  ({:>6.3}, {:>6.3}, {:>6.3})  {:>7.3}  {:>6.1}mm  {:>7.1}°  {:>6.1}cm²{}",
            i,
            n[0],
            n[1],
            n[2],
            p.probability,
            p.margin_m * 1e3,
            p.topple_deg,
            p.area_m2 * 1e4,
            if Some(i) == s.most_likely {
                "  most likely"
            } else {
                ""
            }
        );
    }
    println!(
        "{} stable poses, best (hardest to topple) first; {cpu_ms:.3} ms CPU",
        s.poses.len()
    );
    Ok(())
}

/// `tabula bench stable-poses`: the test objects written as OBJ files into `dir`, the
/// stable-pose search timed on each (for the side-by-side with trimesh,
/// `scripts/trimesh_stable_poses.py DIR`).
pub fn bench(dir: &Path, reps: usize, json: bool, report: Option<&Path>) -> Result<()> {
    let count = tabula_sim::objects::catalogue().len() as u64;
    let progress = crate::progress::steps(count, "objects");
    let rows = tabula_bench::stable::run(dir, reps, &mut || progress.inc(1))?;
    progress.finish_and_clear();
    if let Some(out) = report {
        tabula_bench::report::stable::bench_page(out, reps, &rows)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    for line in tabula_bench::report::stable::bench_lines(&rows) {
        println!("{line}");
    }
    println!("meshes written to {}", dir.display());
    Ok(())
}
