//! `tabula perceive`: surfaces, the table, its objects and its free space in a PCD or
//! PLY frame, with an optional robot self-filter and a top-view report.

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tabula_geom::input::{Format, read_bytes};
use tabula_geom::read_pcd_file;
use tabula_geom::{CloudFile, PointCloud, Pose, Quat, Vec2, Vec3};
use tabula_perception::freespace::{Cell, FreeSpaceMap, FreeSpaceParams, Placement};
use tabula_perception::selffilter::{PlacedSolid, SelfFilterParams, self_filter};
use tabula_perception::support::{FrameSource, SupportParams, frame_cloud};
use tabula_perception::surfaces::find_surfaces;
use tabula_perception::tabletop::Tabletop;
use tabula_perception::tabletop::{TableObject, extract_framed};
use tabula_perception::{TabletopParams, read_ply, to_world};

#[derive(Args)]
pub struct PerceiveArgs {
    /// A frame: .pcd (ascii, binary, binary_compressed) or .ply. Points in the camera's
    /// optical frame (x right, y down, z forward) unless the PCD's `VIEWPOINT` places
    /// the sensor away from the origin (then the points are in a z-up world frame).
    #[arg(long)]
    cloud: PathBuf,
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
    read_cloud_file(path).map(|f| f.cloud)
}

/// Reads a PCD or PLY file with its colours and sensor pose.
pub fn read_cloud_file(path: &Path) -> Result<CloudFile> {
    let bytes = read_bytes(path, Format::Cloud)?;
    let file = if bytes.starts_with(b"ply") {
        read_ply(&bytes)
            .map(CloudFile::plain)
            .map_err(anyhow::Error::from)
    } else {
        read_pcd_file(&bytes).map_err(anyhow::Error::from)
    };
    file.with_context(|| format!("{}", path.display()))
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
    let file = read_cloud_file(&a.cloud)?;
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
    let params: TabletopParams = crate::tasks::load_params(a.params.as_deref())?;
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
        framing,
        cloud,
        result,
        surfaces,
        map,
        removed,
        ms,
    } = &perceived;
    let placement = match &a.place {
        Some(size) => {
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
            Some(map.find_place(&footprint, a.margin, near))
        }
        None => None,
    };
    // A footprint that fits nowhere is "no solution": exit status 2 after the report.
    let no_place = matches!(placement, Some(None));
    let colors = file.colors.as_deref();
    let json = || perceived.to_json(placement, colors);
    if let Some(dir) = &a.report {
        let footprint = placement.flatten().zip(a.place.as_deref());
        write_report(dir, result, map, footprint, Some((cloud, colors)), &json())?;
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
    let t = &framing.world_from_cloud;
    match framing.source {
        FrameSource::GivenPose => println!("frame: the world, from the sensor pose given"),
        FrameSource::Viewpoint => println!(
            "frame: the cloud's own (z up), sensor at ({:.3}, {:.3}, {:.3}) from its VIEWPOINT",
            framing.eye.x, framing.eye.y, framing.eye.z
        ),
        FrameSource::Support => println!(
            "frame: the support's (z up, support at z = 0, sensor {:.3} m above it looking along +x); \
             world_from_cloud ({:.3}, {:.3}, {:.3}) ({:.4}, {:.4}, {:.4}, {:.4})",
            framing.eye.z,
            t.translation.x,
            t.translation.y,
            t.translation.z,
            t.rotation.x,
            t.rotation.y,
            t.rotation.z,
            t.rotation.w
        ),
    }
    println!(
        "table: {} points, height {:.3} m, normal ({:.3}, {:.3}, {:.3}), {:.2} m² seen, hull {:.2} m² ({} corners); free {:.2} m²",
        result.table.inliers.len(),
        result.table.centroid.z,
        result.plane.normal.x,
        result.plane.normal.y,
        result.plane.normal.z,
        result.table.area,
        result.table.hull_area,
        result.table.hull.len(),
        map.free_area()
    );
    if *removed > 0 {
        println!("self-filter: {removed} robot points removed");
    }
    println!("surfaces (all horizontal surfaces in reach):");
    for s in &surfaces.surfaces {
        println!(
            "  at {:.3} m: {} points, {:.2} m², centroid ({:.3}, {:.3}, {:.3})",
            s.centroid.z,
            s.inliers.len(),
            s.area,
            s.centroid.x,
            s.centroid.y,
            s.centroid.z
        );
    }
    let line = |i: usize, o: &TableObject| {
        let (c, s) = (o.obb.center, o.obb.half_extents * 2.0);
        println!(
            "  {}: {} points, box centre ({:.3}, {:.3}, {:.3}), {:.3} × {:.3} × {:.3} m, yaw {:.0}°{}{}",
            i + 1,
            o.indices.len(),
            c.x,
            c.y,
            c.z,
            s.x,
            s.y,
            s.z,
            box_yaw(o).to_degrees(),
            o.top.as_ref().map_or(String::new(), |t| format!(
                ", flat top {:.0} cm²",
                t.area * 1e4
            )),
            colors.map_or(String::new(), |c| {
                let [r, g, b] = mean_colour(c, &o.indices);
                format!(", colour #{r:02x}{g:02x}{b:02x}")
            })
        );
    };
    println!("objects:");
    for (i, o) in result.objects.iter().enumerate() {
        line(i, o);
    }
    if !result.partial.is_empty() {
        println!("cut by the frame's edge (partly seen):");
        for (i, o) in result.partial.iter().enumerate() {
            line(i, o);
        }
    }
    match placement {
        Some(Some(p)) => println!(
            "place: ({:.3}, {:.3}, {:.3}) yaw {:.0}°, {:.3} m clear",
            p.position.x,
            p.position.y,
            p.position.z,
            p.yaw.to_degrees(),
            p.clearance
        ),
        Some(None) => println!("place: the footprint fits nowhere on the table with that margin"),
        None => {}
    }
    println!(
        "{ms:.1} ms (outliers {:.1}, planes {:.1}, prism {:.1}, normals {:.1}, segmentation {:.1}, objects {:.1})",
        result.times.outliers,
        result.times.planes,
        result.times.prism,
        result.times.normals,
        result.times.segmentation,
        result.times.objects
    );
    if no_place {
        std::process::exit(crate::exit::NO_SOLUTION);
    }
    Ok(())
}

/// Yaw (rad) of a box's long side from the world x axis, in [-90°, 90°): a box turned
/// by 180° is the same box.
fn box_yaw(o: &TableObject) -> f64 {
    let a = o.obb.axes[0];
    let yaw = a.y.atan2(a.x);
    let half = std::f64::consts::FRAC_PI_2;
    (yaw + half).rem_euclid(std::f64::consts::PI) - half
}

/// Mean colour of some points.
fn mean_colour(colors: &[[u8; 3]], indices: &[usize]) -> [u8; 3] {
    let mut sum = [0u64; 3];
    for &i in indices {
        for (s, c) in sum.iter_mut().zip(colors[i]) {
            *s += c as u64;
        }
    }
    let n = indices.len().max(1) as u64;
    sum.map(|s| (s / n) as u8)
}

fn pose_json(p: &Pose) -> [f64; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}

fn arr(v: Vec3) -> [f64; 3] {
    v.to_array()
}

/// What perception makes of one frame: how it was framed, the cloud in that frame
/// (robot removed), the tabletop, every surface, the support's free space.
pub struct Perceived {
    pub framing: tabula_perception::support::Framing,
    pub cloud: PointCloud,
    pub result: Tabletop,
    pub surfaces: tabula_perception::surfaces::SurfaceSearch,
    pub map: FreeSpaceMap,
    /// Points the robot's self-filter removed.
    pub removed: usize,
    /// Wall time of framing and the tabletop pipeline.
    pub ms: f64,
}

/// Frames `file` (a given pose, `up`, its VIEWPOINT or the optical frame), removes the
/// robot's `solids`, and runs the tabletop pipeline, the surface search and the free
/// space map.
pub fn perceive(
    file: &CloudFile,
    world_from_camera: Option<Pose>,
    up: Option<Vec3>,
    solids: &[PlacedSolid],
    params: &TabletopParams,
) -> Result<Perceived> {
    let t0 = Instant::now();
    let framing = frame_cloud(
        &file.cloud,
        &file.viewpoint,
        world_from_camera,
        up,
        &SupportParams::default(),
    )?;
    let mut cloud = to_world(&framing.world_from_cloud, &file.cloud);
    let mut removed = 0;
    if !solids.is_empty() {
        let keep = self_filter(&cloud.points, solids, &SelfFilterParams::default());
        for (p, k) in cloud.points.iter_mut().zip(&keep) {
            if !k && p.is_finite() {
                *p = Vec3::NAN;
                removed += 1;
            }
        }
    }
    let result = extract_framed(&cloud, &framing, params)?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let surfaces = find_surfaces(&cloud, None, &params.surfaces, false);
    let map = FreeSpaceMap::from_tabletop(&result, &cloud.points, &FreeSpaceParams::default())?;
    Ok(Perceived {
        framing,
        cloud,
        result,
        surfaces,
        map,
        removed,
        ms,
    })
}

impl Perceived {
    /// What `perceive --json` prints (`placement`: the answer to `--place`, if asked).
    pub fn to_json(
        &self,
        placement: Option<Option<Placement>>,
        colors: Option<&[[u8; 3]]>,
    ) -> serde_json::Value {
        let mut v = to_json(
            &self.result,
            &self.surfaces.surfaces,
            &self.map,
            placement,
            self.removed,
            self.ms,
            colors,
        );
        v["frame"] = serde_json::json!({
            "source": self.framing.source,
            "world_from_cloud": pose_json(&self.framing.world_from_cloud),
            "sensor": arr(self.framing.eye),
        });
        v
    }
}

fn to_json(
    t: &Tabletop,
    surfaces: &[tabula_perception::Surface],
    map: &FreeSpaceMap,
    placement: Option<Option<Placement>>,
    removed: usize,
    ms: f64,
    colors: Option<&[[u8; 3]]>,
) -> serde_json::Value {
    use serde_json::json;
    let object = |o: &TableObject| {
        json!({
            "points": o.indices.len(),
            "size": arr(o.obb.half_extents * 2.0),
            "yaw": box_yaw(o),
            "color": colors.map(|c| mean_colour(c, &o.indices)),
            "centroid": arr(o.centroid),
            "axes": o.axes.map(arr),
            "table_axes": o.table_axes.map(arr),
            "obb": {"center": arr(o.obb.center), "axes": o.obb.axes.map(arr), "half_extents": arr(o.obb.half_extents)},
            "height": o.height,
            "footprint": o.footprint.iter().map(|p| arr(*p)).collect::<Vec<_>>(),
            "hull": {"vertices": o.hull_vertices.iter().map(|p| arr(*p)).collect::<Vec<_>>(), "triangles": o.hull_triangles},
            "top": o.top.as_ref().map(|s| json!({"height": s.height, "area": s.area, "centroid": arr(s.centroid), "hull": s.hull.iter().map(|p| arr(*p)).collect::<Vec<_>>()})),
        })
    };
    let objects: Vec<_> = t.objects.iter().map(object).collect();
    let partial: Vec<_> = t.partial.iter().map(object).collect();
    let surfaces: Vec<_> = surfaces
        .iter()
        .map(|s| json!({"normal": arr(s.plane.normal), "d": s.plane.d, "points": s.inliers.len(), "area": s.area, "hull_area": s.hull_area, "centroid": arr(s.centroid), "hull": s.hull.iter().map(|p| arr(*p)).collect::<Vec<_>>()}))
        .collect();
    json!({
        "partial_objects": partial,
        "table": {"height": t.table.centroid.z, "normal": arr(t.plane.normal), "d": t.plane.d, "points": t.table.inliers.len(), "area": t.table.area, "hull_area": t.table.hull_area, "centroid": arr(t.table.centroid), "hull": t.table.hull.iter().map(|p| arr(*p)).collect::<Vec<_>>()},
        "surfaces": surfaces,
        "objects": objects,
        "free_area": map.free_area(),
        "placement": placement.map(|p| p.map(|p| json!({"position": arr(p.position), "yaw": p.yaw, "clearance": p.clearance}))),
        "self_filtered_points": removed,
        "kept_after_outlier_removal": t.kept,
        "times_ms": t.times,
        "ms": ms,
    })
}

/// What a top view shows: a surface's occupancy grid (free green, objects red, unseen
/// grey), its outline, object outlines and boxes, labels, and a chosen spot (blue).
/// Every polygon is in the world; the view is the surface's plane seen from above.
pub struct TopView<'a> {
    pub map: &'a FreeSpaceMap,
    pub outline: &'a [Vec3],
    pub objects: Vec<Vec<Vec3>>,
    pub boxes: Vec<Vec<Vec3>>,
    pub labels: Vec<(String, Vec3)>,
    pub spot: Option<Vec<Vec3>>,
}

impl<'a> TopView<'a> {
    /// The tabletop pipeline's result: footprints, minimal-area boxes, numbers, and a
    /// footprint of `size` placed where the map found room.
    pub fn of_tabletop(
        t: &'a Tabletop,
        map: &'a FreeSpaceMap,
        placement: Option<(Placement, &[f64])>,
    ) -> Self {
        let boxes = t
            .objects
            .iter()
            .map(|o| {
                let b = o.obb;
                [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .iter()
                    .map(|(sx, sy)| {
                        b.center
                            + b.axes[0] * (sx * b.half_extents.x)
                            + b.axes[1] * (sy * b.half_extents.y)
                    })
                    .collect()
            })
            .collect();
        let spot = placement.map(|(p, size)| {
            let f = p.world_from_footprint;
            let (x, y) = (size[0] / 2.0, size[1] / 2.0);
            [(-x, -y), (x, -y), (x, y), (-x, y)]
                .iter()
                .map(|(a, b)| f * Vec3::new(*a, *b, 0.0))
                .collect()
        });
        Self {
            map,
            outline: &t.table.hull,
            objects: t.objects.iter().map(|o| o.footprint.clone()).collect(),
            boxes,
            labels: t
                .objects
                .iter()
                .enumerate()
                .map(|(n, o)| (format!("{}", n + 1), o.centroid))
                .collect(),
            spot,
        }
    }
}

/// A top view drawn with plotters: the SVG and a PNG of it (the PNG without text:
/// plotters' bitmap backend would need a font).
pub fn top_view(view: &TopView<'_>) -> Result<(String, image::RgbImage)> {
    const PX_PER_M: f64 = 400.0;
    let map = view.map;
    let (w_m, h_m) = (
        map.nx as f64 * map.resolution,
        map.ny as f64 * map.resolution,
    );
    let size = (
        ((w_m * PX_PER_M) as u32).clamp(120, 1600),
        ((h_m * PX_PER_M) as u32).clamp(120, 1600),
    );
    let mut svg = String::new();
    draw_top_view(
        plotters::prelude::SVGBackend::with_string(&mut svg, (size.0 + 70, size.1 + 60)),
        view,
        true,
    )?;
    let mut buf = vec![255u8; (size.0 * size.1 * 3) as usize];
    draw_top_view(
        plotters::prelude::BitMapBackend::with_buffer(&mut buf, size),
        view,
        false,
    )?;
    let png = image::RgbImage::from_raw(size.0, size.1, buf)
        .context("top view: buffer of the wrong size")?;
    Ok((svg, png))
}

fn draw_top_view<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    view: &TopView<'_>,
    labels: bool,
) -> Result<()> {
    use plotters::prelude::*;
    let map = view.map;
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("top view: {e}");
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (x0, y0) = (map.lo.x, map.lo.y);
    let (x1, y1) = (
        x0 + map.nx as f64 * map.resolution,
        y0 + map.ny as f64 * map.resolution,
    );
    let mut builder = ChartBuilder::on(&root);
    if labels {
        builder
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(50);
    }
    let mut chart = builder
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(&e))?;
    if labels {
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("u (m, in the surface's plane)")
            .y_desc("v (m)")
            .draw()
            .map_err(|e| err(&e))?;
    }
    // Runs of equal cells along a row become one rectangle.
    let colour = |c: &Cell| match c {
        Cell::Outside => None,
        Cell::Free => Some(RGBColor(200, 235, 200)),
        Cell::Occupied => Some(RGBColor(225, 120, 110)),
        Cell::Unknown => Some(RGBColor(190, 190, 190)),
    };
    let r = map.resolution;
    let mut cells = Vec::new();
    for j in 0..map.ny {
        let mut i = 0;
        while i < map.nx {
            let c = &map.cells[j * map.nx + i];
            let mut end = i + 1;
            while end < map.nx && map.cells[j * map.nx + end] == *c {
                end += 1;
            }
            if let Some(col) = colour(c) {
                cells.push(Rectangle::new(
                    [
                        (x0 + i as f64 * r, y0 + j as f64 * r),
                        // A hair taller than the row: no seam between rows once drawn.
                        (x0 + end as f64 * r, y0 + (j as f64 + 1.05) * r),
                    ],
                    col.filled(),
                ));
            }
            i = end;
        }
    }
    chart.draw_series(cells).map_err(|e| err(&e))?;
    let closed = |pts: &[Vec3]| -> Vec<(f64, f64)> {
        let mut q: Vec<(f64, f64)> = pts
            .iter()
            .map(|p| {
                let v = map.to_plane(*p);
                (v.x, v.y)
            })
            .collect();
        if let Some(first) = q.first().copied() {
            q.push(first);
        }
        q
    };
    let mut lines = vec![PathElement::new(
        closed(view.outline),
        RGBColor(60, 60, 60).stroke_width(2),
    )];
    for o in &view.objects {
        lines.push(PathElement::new(
            closed(o),
            RGBColor(150, 30, 30).stroke_width(2),
        ));
    }
    for b in &view.boxes {
        lines.push(PathElement::new(
            closed(b),
            RGBColor(40, 40, 40).stroke_width(1),
        ));
    }
    chart.draw_series(lines).map_err(|e| err(&e))?;
    if let Some(spot) = &view.spot {
        let rect = closed(spot);
        chart
            .draw_series([Polygon::new(rect.clone(), RGBColor(120, 160, 240).filled())])
            .map_err(|e| err(&e))?;
        chart
            .draw_series([PathElement::new(
                rect,
                RGBColor(20, 40, 160).stroke_width(2),
            )])
            .map_err(|e| err(&e))?;
    }
    if labels {
        chart
            .draw_series(view.labels.iter().map(|(text, at)| {
                let c = map.to_plane(*at);
                Text::new(text.clone(), (c.x, c.y), ("sans-serif", 13))
            }))
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// `perceive --report DIR`: the top view (top.svg, top.png), the labelled frame
/// (frame.png) and index.html with the numbers.
fn write_report(
    dir: &Path,
    t: &Tabletop,
    map: &FreeSpaceMap,
    placement: Option<(Placement, &[f64])>,
    frame: Option<(&PointCloud, Option<&[[u8; 3]]>)>,
    json: &serde_json::Value,
) -> Result<()> {
    let mut report = crate::report::Report::create(dir, "tabula perceive")?;
    let mut s = crate::report::Section::new("The table, its objects and free space");
    s.number("objects", t.objects.len())
        .number("objects cut by the frame's edge", t.partial.len())
        .number("table area seen (m²)", format!("{:.3}", t.table.area))
        .number("free area (m²)", format!("{:.3}", map.free_area()));
    if let Some((p, size)) = placement {
        s.number(
            "free spot",
            format!(
                "{:.2} × {:.2} m footprint at ({:.3}, {:.3}, {:.3}), turned {:.0}°, {:.0} mm clear",
                size[0],
                size[1],
                p.position.x,
                p.position.y,
                p.position.z,
                p.yaw.to_degrees(),
                p.clearance * 1e3
            ),
        );
    }
    let (svg, png) = top_view(&TopView::of_tabletop(t, map, placement))?;
    std::fs::write(dir.join("top.svg"), &svg).context("cannot write top.svg")?;
    png.save(dir.join("top.png"))
        .context("cannot write top.png")?;
    s.figures.push(crate::report::Figure {
        file: "top.svg".into(),
        caption:
            "Top view: free (green), objects (red), unseen (grey), boxes, the free spot (blue)"
                .into(),
    });
    if let Some((cloud, colors)) = frame
        && cloud.is_organized()
    {
        write_frame_image(dir, cloud, colors, t)?;
        s.figures.push(crate::report::Figure {
            file: "frame.png".into(),
            caption: "The frame: the support green, each object in its own colour".into(),
        });
    }
    report.sections.push(s);
    report.finish(json)?;
    Ok(())
}

/// Object colours in the labelled frame: distinct hues, repeated after twelve.
const LABEL_COLOURS: [[u8; 3]; 12] = [
    [230, 25, 75],
    [60, 180, 75],
    [255, 225, 25],
    [0, 130, 200],
    [245, 130, 48],
    [145, 30, 180],
    [70, 240, 240],
    [240, 50, 230],
    [210, 245, 60],
    [250, 190, 212],
    [0, 128, 128],
    [170, 110, 40],
];

/// The organized frame as the sensor saw it (its colours, or grey by depth), the
/// support tinted green and each object in its own colour: `frame.png`.
fn write_frame_image(
    dir: &Path,
    cloud: &PointCloud,
    colors: Option<&[[u8; 3]]>,
    t: &Tabletop,
) -> Result<()> {
    let (w, h) = (cloud.width, cloud.height);
    let (lo, hi) = cloud
        .points
        .iter()
        .filter(|p| p.is_finite())
        .map(|p| p.z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
            (a.min(z), b.max(z))
        });
    let base = |i: usize| -> [u8; 3] {
        let p = cloud.points[i];
        if !p.is_finite() {
            return [0, 0, 0];
        }
        match colors {
            Some(c) => c[i],
            None => {
                let g = (60.0 + 160.0 * (p.z - lo) / (hi - lo).max(1e-9)) as u8;
                [g, g, g]
            }
        }
    };
    let mut label = vec![None; w * h];
    for &i in &t.table.inliers {
        label[i] = Some([40u8, 200, 60]);
    }
    for (k, o) in t.objects.iter().enumerate() {
        for &i in &o.indices {
            label[i] = Some(LABEL_COLOURS[k % LABEL_COLOURS.len()]);
        }
    }
    // Objects cut by the frame's edge: white.
    for &i in t.partial.iter().flat_map(|o| &o.indices) {
        label[i] = Some([255, 255, 255]);
    }
    let pixels: Vec<u8> = label
        .iter()
        .enumerate()
        .flat_map(|(i, l)| {
            let b = base(i);
            match l {
                Some(l) => [0, 1, 2].map(|c| ((b[c] as u16 + 2 * l[c] as u16) / 3) as u8),
                None => b,
            }
        })
        .collect();
    let img = image::RgbImage::from_raw(w as u32, h as u32, pixels)
        .context("frame.png: the frame's size and its points disagree")?;
    img.save(dir.join("frame.png"))
        .context("cannot write frame.png")?;
    Ok(())
}
