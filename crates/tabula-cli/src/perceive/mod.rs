//! `tabula perceive`: surfaces, the table, its objects and its free space in a PCD or
//! PLY frame, with an optional robot self-filter and a top-view report.

mod truth;

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::{Path, PathBuf};
use tabula_bench::report::frame::{perceive_page, perceived_lines};
use tabula_geom::{PointCloud, Pose, Quat, Vec2, Vec3};
use tabula_perception::TabletopParams;
use tabula_perception::frame::{Perceived, perceive};
use tabula_perception::freespace::{FreeSpaceMap, Placement};
use tabula_perception::selffilter::PlacedSolid;
use tabula_perception::tabletop::Tabletop;

pub use tabula_perception::frame::read_cloud_file;

#[derive(Args)]
pub struct PerceiveArgs {
    /// A frame: .pcd (ascii, binary, binary_compressed) or .ply. Points in the camera's
    /// optical frame (x right, y down, z forward) unless the PCD's `VIEWPOINT` places
    /// the sensor away from the origin (then the points are in a z-up world frame).
    #[arg(long, required_unless_present = "print_params")]
    cloud: Option<PathBuf>,
    /// world_from_camera as x y z qx qy qz qw: the points are in the camera's frame and
    /// this places them in the world (overrides what the file says).
    #[arg(long, num_args = 7, allow_negative_numbers = true, value_names = ["X", "Y", "Z", "QX", "QY", "QZ", "QW"], value_parser = crate::args::finite)]
    world_from_camera: Option<Vec<f64>>,
    /// Roughly which way is up, in the cloud's frame: the support is the dominant
    /// plane facing this way (default for camera-frame clouds: the optical frame's -y).
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], value_parser = crate::args::finite)]
    up: Option<Vec<f64>>,
    /// Pipeline parameters (TOML, keys of `TabletopParams`; defaults from SPEC §6).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Segment an organized frame on every N-th pixel of every N-th row, then label
    /// every pixel by its nearest sample (`frame_stride` of `--params`; 2 is ¼ of the
    /// work on a 640×480 frame).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=8))]
    stride: Option<u8>,
    /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
    /// TOML to start a file from, and exit.
    #[arg(long, exclusive = true)]
    print_params: bool,
    /// Remove the points of this robot (`golem3`, `wam`, `pr2` or a URDF path) first.
    #[arg(long)]
    robot: Option<String>,
    /// world_from_base of that robot: x y z qx qy qz qw.
    #[arg(long, num_args = 7, allow_negative_numbers = true, value_names = ["X", "Y", "Z", "QX", "QY", "QZ", "QW"], value_parser = crate::args::finite)]
    robot_base: Option<Vec<f64>>,
    /// Joint values of that robot, `name=value` (others at 0).
    #[arg(long = "joint", value_name = "NAME=VALUE")]
    joints: Vec<String>,
    /// Find a place for a footprint of this size (m, x and y) on the table …
    #[arg(long, num_args = 2, allow_negative_numbers = true, value_names = ["X", "Y"], value_parser = crate::args::finite)]
    place: Option<Vec<f64>>,
    /// … this far (m) from objects, unseen patches and the edge …
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true, value_parser = crate::args::finite)]
    margin: f64,
    /// … nearest to this world point (default: the table's centroid).
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], value_parser = crate::args::finite)]
    near: Option<Vec<f64>>,
    #[arg(long)]
    json: bool,
    /// Write a top view of the table (top.png, top.svg) into this folder.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Write the segmentation as a labelled cloud (PCD, PCL's convention): the input's
    /// grid with a `label` field, 0 not an object, k ≥ 1 segment k (`--json`'s `label`).
    #[arg(long, value_name = "OUT.pcd")]
    labels: Option<PathBuf>,
    /// Score the segmentation against a ground truth on the same grid: a PCD with a
    /// `label` field or a PNG of labels. Prints the overlap precision, recall and F
    /// (OSD/OCID's), the objects found at IoU ≥ 0.5 and the extra segments.
    #[arg(long, value_name = "GT.pcd|GT.png")]
    score: Option<PathBuf>,
    /// How the ground truth's labels name objects (default: mosd for a PCD, ocid for a PNG).
    #[arg(long, value_enum, requires = "score")]
    truth_format: Option<truth::TruthFormat>,
}

fn pose_arg(v: &[f64], what: &str) -> Result<Pose> {
    let q = Quat::from_xyzw(v[3], v[4], v[5], v[6]);
    if !v.iter().all(|x| x.is_finite()) || q.length() < 1e-9 {
        bail!("--{what} must be finite with a non-zero quaternion");
    }
    Ok(Pose::from_parts(Vec3::new(v[0], v[1], v[2]), q.normalize()))
}

/// Reads a PCD or PLY file (by its first bytes, whatever the extension).
pub fn read_cloud(path: &Path) -> Result<PointCloud> {
    Ok(read_cloud_file(path)?.cloud)
}

/// The robot's collision shapes placed by forward kinematics. Joints not given on the
/// command line are at mid-range, where the simulator starts them, so a scene's
/// `joints` table copied here describes the same robot.
fn robot_solids(name: &str, world_from_base: Pose, joints: &[String]) -> Result<Vec<PlacedSolid>> {
    let robot = tabula_robot::robots::load(name)?;
    let model = &robot.model;
    let mut values = model.mid_configuration();
    for j in joints {
        let (n, v) = j
            .split_once('=')
            .with_context(|| format!("--joint `{j}` is not NAME=VALUE"))?;
        let idx = model
            .joint(n)
            .with_context(|| format!("{name} has no joint `{n}`"))?;
        let value: f64 = v
            .parse()
            .with_context(|| format!("--joint `{j}`: bad value"))?;
        if !value.is_finite() {
            bail!("--joint `{j}`: the value must be finite");
        }
        values[idx] = value;
    }
    Ok(tabula_tasks::observe::robot_solids(
        model,
        &values,
        world_from_base,
    ))
}

pub fn run(a: PerceiveArgs) -> Result<()> {
    if a.print_params {
        return crate::tasks::print_params::<TabletopParams>();
    }
    let file = read_cloud_file(crate::args::given(&a.cloud, "--cloud")?)?;
    let world_from_camera = match &a.world_from_camera {
        Some(v) => Some(pose_arg(v, "world-from-camera")?),
        None => None,
    };
    let up = match &a.up {
        Some(v) => {
            let up = Vec3::new(v[0], v[1], v[2]);
            if !up.is_finite() || up.length() < 1e-9 {
                bail!("--up must be a finite, non-zero direction");
            }
            Some(up.normalize())
        }
        None => None,
    };
    let mut params: TabletopParams = crate::tasks::load_params(a.params.as_deref())?;
    if let Some(stride) = a.stride {
        params.frame_stride = stride.into();
    }
    let solids = match &a.robot {
        Some(robot) => {
            let base = match &a.robot_base {
                Some(v) => pose_arg(v, "robot-base")?,
                None => Pose::IDENTITY,
            };
            robot_solids(robot, base, &a.joints)?
        }
        None => Vec::new(),
    };
    let perceived = perceive(&file, world_from_camera, up, &solids, &params)?;
    let Perceived {
        cloud, result, map, ..
    } = &perceived;
    let placement = placement_of(&a, result, map)?;
    // A footprint that fits nowhere is "no solution": exit status 2 after the report.
    let no_place = matches!(placement, Some(None));
    let colors = file.colors.as_deref();
    let labels = perceived.segment_labels();
    if let Some(path) = &a.labels {
        truth::write_labels(path, &file, &labels)?;
    }
    let scored = match &a.score {
        Some(path) => Some(truth::score_against(path, a.truth_format, &file, &labels)?),
        None => None,
    };
    let json = || {
        let mut v = perceived.to_json(placement, colors);
        if let Some(s) = &scored {
            v["score"] = serde_json::to_value(s).unwrap_or_default();
        }
        v
    };
    if let Some(dir) = &a.report {
        let footprint = placement.flatten().zip(a.place.as_deref());
        perceive_page(dir, result, map, footprint, Some((cloud, colors)), &json())?;
        eprintln!("report: {}", dir.join("index.html").display());
    }
    if a.json {
        let v = json();
        println!("{}", serde_json::to_string_pretty(&v)?);
        if no_place {
            std::process::exit(crate::exit::NO_SOLUTION);
        }
        return Ok(());
    }
    for line in perceived_lines(&perceived, placement, colors) {
        println!("{line}");
    }
    for line in scored.iter().flat_map(truth::score_lines) {
        println!("{line}");
    }
    if no_place {
        std::process::exit(crate::exit::NO_SOLUTION);
    }
    Ok(())
}

/// Where `--place` (a footprint's size) fits on the table, near `--near` or the
/// table's centre: `None` without `--place`, `Some(None)` when it fits nowhere.
fn placement_of(
    a: &PerceiveArgs,
    result: &Tabletop,
    map: &FreeSpaceMap,
) -> Result<Option<Option<Placement>>> {
    let Some(size) = &a.place else {
        return Ok(None);
    };
    if !(size.iter().all(|s| s.is_finite() && *s > 0.0)) {
        bail!("--place sizes must be positive");
    }
    if !(a.margin.is_finite() && a.margin >= 0.0) {
        bail!("--margin must be a finite distance ≥ 0");
    }
    if a.near
        .as_ref()
        .is_some_and(|n| !n.iter().all(|v| v.is_finite()))
    {
        bail!("--near must be a finite point");
    }
    let (x, y) = (size[0] / 2.0, size[1] / 2.0);
    let footprint = [
        Vec2::new(-x, -y),
        Vec2::new(x, -y),
        Vec2::new(x, y),
        Vec2::new(-x, y),
    ];
    let near = a
        .near
        .as_ref()
        .map_or(result.table.centroid, |n| Vec3::new(n[0], n[1], n[2]));
    Ok(Some(map.find_place(&footprint, a.margin, near)))
}
