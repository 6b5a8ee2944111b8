//! `tabula perceive`: seed 002's tabletop pipeline on a PCD frame.

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_perception::{TabletopParams, extract, read_pcd, to_world};

#[derive(Args)]
pub struct PerceiveArgs {
    /// Organized PCD frame in the camera's optical frame.
    #[arg(long)]
    cloud: PathBuf,
    /// world_from_camera as x y z qx qy qz qw (default: identity, cloud already in world).
    #[arg(long, num_args = 7, allow_negative_numbers = true, value_names = ["X", "Y", "Z", "QX", "QY", "QZ", "QW"])]
    world_from_camera: Option<Vec<f64>>,
    #[arg(long)]
    json: bool,
}

pub fn run(a: PerceiveArgs) -> Result<()> {
    let bytes =
        std::fs::read(&a.cloud).with_context(|| format!("cannot read {}", a.cloud.display()))?;
    let cloud = read_pcd(&bytes).with_context(|| format!("{}", a.cloud.display()))?;
    let pose = match &a.world_from_camera {
        Some(v) => {
            let q = Quat::from_xyzw(v[3], v[4], v[5], v[6]);
            if !v.iter().all(|x| x.is_finite()) || q.length() < 1e-9 {
                bail!("--world-from-camera must be finite with a non-zero quaternion");
            }
            Pose::from_parts(Vec3::new(v[0], v[1], v[2]), q.normalize())
        }
        None => Pose::IDENTITY,
    };
    let t0 = Instant::now();
    let points = to_world(&pose, &cloud.points);
    let result = extract(
        &points,
        cloud.width,
        cloud.height,
        &TabletopParams::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    if a.json {
        let objects: Vec<_> = result
            .objects
            .iter()
            .map(|o| serde_json::json!({"points": o.indices.len(), "centroid": o.centroid.to_array(), "obb_center": o.obb_center.to_array(), "obb_half": o.obb_half.to_array(), "axes": o.axes.map(|a| a.to_array()), "height": o.height}))
            .collect();
        println!(
            "{}",
            serde_json::json!({"table": {"normal": result.plane.normal.to_array(), "d": result.plane.d, "points": result.table_indices.len(), "hull": result.hull.iter().map(|p| p.to_array()).collect::<Vec<_>>()}, "objects": objects, "ms": ms})
        );
        return Ok(());
    }
    println!(
        "table: {} points, normal ({:.3}, {:.3}, {:.3}), height {:.3} m, hull of {} corners; {ms:.1} ms",
        result.table_indices.len(),
        result.plane.normal.x,
        result.plane.normal.y,
        result.plane.normal.z,
        -result.plane.d,
        result.hull.len()
    );
    for (i, o) in result.objects.iter().enumerate() {
        println!(
            "  object {}: {} points, centre ({:.3}, {:.3}, {:.3}), box {:.3} × {:.3} × {:.3} m, {:.3} m tall",
            i + 1,
            o.indices.len(),
            o.obb_center.x,
            o.obb_center.y,
            o.obb_center.z,
            2.0 * o.obb_half.x,
            2.0 * o.obb_half.y,
            2.0 * o.obb_half.z,
            o.height
        );
    }
    Ok(())
}
