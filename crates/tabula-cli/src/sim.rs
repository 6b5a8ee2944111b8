//! `tabula sim …`: the simulator from the command line.

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use std::path::PathBuf;
use std::time::Instant;
use tabula_geom::{Vec3, rpy_from_quat};
use tabula_sim::camera::{Camera, capture, snapshot};
use tabula_sim::world::MODELS;
use tabula_sim::{PhysicsParams, Scene, SimWorld};

#[derive(Subcommand)]
pub enum SimCommand {
    /// Settle a scene (until every body sleeps) and print where everything rests.
    Settle {
        #[arg(long)]
        scene: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Capture a depth frame as an organized PCD (or PLY) in the camera's optical frame.
    Capture(CaptureArgs),
    /// Render a shaded PNG of the scene.
    Snapshot(SnapshotArgs),
    /// Spawn a catalogue model into a scene, settle, and print the result.
    Spawn {
        #[arg(long)]
        scene: PathBuf,
        #[arg(long)]
        model: String,
        #[arg(long)]
        name: String,
        #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], value_parser = crate::args::finite)]
        at: Vec<f64>,
        /// Lower it onto the surface below before settling.
        #[arg(long)]
        on_surface: bool,
    },
    /// Run the seed's scene commands on a scene, in order: `spawn MODEL NAME X Y Z`,
    /// `move NAME X Y Z [ROLL PITCH YAW]`, `put NAME` (onto the surface below),
    /// `delete NAME`, `list`, `models`, `settle`.
    Do {
        #[arg(long)]
        scene: PathBuf,
        /// One command; repeat for several.
        #[arg(long = "cmd", required = true)]
        commands: Vec<String>,
        /// Write a snapshot of the result.
        #[arg(long)]
        png: Option<PathBuf>,
    },
    /// List the models `spawn` accepts.
    Models,
    /// Time frame capture and settling on a scene.
    Bench {
        #[arg(long)]
        scene: PathBuf,
        #[arg(long, default_value_t = 20, value_parser = crate::args::count)]
        frames: usize,
        #[arg(long)]
        json: bool,
    },
}

#[derive(Args)]
pub struct CaptureArgs {
    #[arg(long)]
    scene: PathBuf,
    /// Camera name (default: the scene's first camera).
    #[arg(long)]
    camera: Option<String>,
    #[arg(long)]
    out: PathBuf,
    /// Also write per-pixel ground-truth labels: JSON (every entity, with names), or
    /// with a `.pcd` path the frame's grid with a `label` field — each object's entity
    /// label, 0 for the table, floor, robot and no return (`perceive --score F
    /// --truth-format plain` reads it).
    #[arg(long)]
    labels: Option<PathBuf>,
    /// Noise seed.
    #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
    seed: u64,
    /// Write binary instead of ASCII (PCD, or PLY when `--out` ends in `.ply`).
    #[arg(long)]
    binary: bool,
    /// Settle the scene before capturing.
    #[arg(long)]
    settle: bool,
    /// Write the points in the world frame with the camera's pose as the PCD's
    /// `VIEWPOINT` (as PCL writes registered clouds), instead of the optical frame.
    #[arg(long)]
    world: bool,
}

#[derive(Args)]
pub struct SnapshotArgs {
    #[arg(long)]
    scene: PathBuf,
    #[arg(long)]
    png: PathBuf,
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], value_parser = crate::args::finite)]
    eye: Option<Vec<f64>>,
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], value_parser = crate::args::finite)]
    target: Option<Vec<f64>>,
    #[arg(long, default_value_t = 960, value_parser = crate::args::pixels)]
    width: usize,
    #[arg(long, default_value_t = 720, value_parser = crate::args::pixels)]
    height: usize,
}

fn load(scene: &std::path::Path) -> Result<(Scene, SimWorld)> {
    let s = Scene::load(scene)?;
    let w = SimWorld::from_scene(&s, PhysicsParams::default())
        .with_context(|| format!("building {}", scene.display()))?;
    Ok((s, w))
}

fn camera_of(scene: &Scene, world: &SimWorld, name: Option<&str>) -> Result<Camera> {
    let spec = match name {
        Some(n) => scene
            .cameras
            .iter()
            .find(|c| c.name.get_ref() == n)
            .with_context(|| {
                let names: Vec<&str> = scene
                    .cameras
                    .iter()
                    .map(|c| c.name.get_ref().as_str())
                    .collect();
                format!(
                    "no camera `{n}` in the scene; cameras: {}",
                    names.join(", ")
                )
            })?,
        None => scene
            .cameras
            .first()
            .context("the scene has no [[camera]]")?,
    };
    Ok(Camera::from_spec(spec, world)?)
}

fn print_poses(world: &SimWorld) {
    for (name, p) in world.object_poses() {
        let [r, pi, y] = rpy_from_quat(p.rotation);
        let t = p.translation;
        println!(
            "  {name:<16} xyz {:>7.4} {:>7.4} {:>7.4}   rpy {:>7.4} {:>7.4} {:>7.4}",
            t.x, t.y, t.z, r, pi, y
        );
    }
}

fn run_command(world: &mut SimWorld, line: &str) -> Result<()> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let num = |i: usize| -> Result<f64> {
        let w = words
            .get(i)
            .with_context(|| format!("missing argument {i}"))?;
        let v: f64 = w
            .parse()
            .with_context(|| format!("`{}` is not a number", tabula_geom::input::clip(w, 40)))?;
        if !v.is_finite() {
            bail!("`{}` is not finite", tabula_geom::input::clip(w, 40));
        }
        Ok(v)
    };
    let name = |i: usize| {
        words
            .get(i)
            .copied()
            .with_context(|| format!("missing argument {i}"))
    };
    match words.first().copied() {
        Some("spawn") => {
            world.spawn(name(1)?, name(2)?, [num(3)?, num(4)?, num(5)?])?;
            println!("spawned {} as {}", name(1)?, name(2)?);
        }
        Some("move") => {
            let rpy = if words.len() >= 8 {
                [num(5)?, num(6)?, num(7)?]
            } else {
                [0.0; 3]
            };
            world.move_to(
                name(1)?,
                tabula_geom::pose_from_xyz_rpy([num(2)?, num(3)?, num(4)?], rpy),
            )?;
            println!("moved {}", name(1)?);
        }
        Some("put") => {
            world.put_on_surface(name(1)?)?;
            let t = world.pose(name(1)?)?.translation;
            println!("put {} on the surface below, at z = {:.4}", name(1)?, t.z);
        }
        Some("delete") => {
            world.delete(name(1)?)?;
            println!("deleted {}", name(1)?);
        }
        Some("list") => {
            for n in world.list(None) {
                println!("  {n}");
            }
        }
        Some("models") => {
            for (n, what) in MODELS {
                println!("  {n:<14} {what}");
            }
        }
        Some("settle") => {
            let r = world.settle();
            println!("settled in {} steps, all asleep: {}", r.steps, r.all_asleep);
            print_poses(world);
        }
        other => bail!(
            "unknown command {other:?}; commands: spawn, move, put, delete, list, models, settle"
        ),
    }
    Ok(())
}

pub fn run(cmd: SimCommand) -> Result<()> {
    match cmd {
        SimCommand::Settle { scene, json } => settle(&scene, json)?,
        SimCommand::Capture(a) => capture_to_file(&a)?,
        SimCommand::Snapshot(a) => {
            let (_, world) = load(&a.scene)?;
            if a.width == 0 || a.height == 0 || a.width * a.height > 16_000_000 {
                bail!("snapshot size must be between 1 and 16 million pixels");
            }
            let v3 = |v: &Option<Vec<f64>>, d: Vec3| {
                v.as_ref().map_or(d, |v| Vec3::new(v[0], v[1], v[2]))
            };
            let eye = v3(&a.eye, Vec3::new(2.2, -1.6, 1.9));
            let target = v3(&a.target, Vec3::new(0.7, 0.0, 0.6));
            if !eye.is_finite() || !target.is_finite() || eye == target {
                bail!("--eye and --target must be finite and distinct");
            }
            snapshot(&world, eye, target, a.width, a.height)
                .save(&a.png)
                .with_context(|| format!("cannot write {}", a.png.display()))?;
            println!("wrote {}", a.png.display());
        }
        SimCommand::Spawn {
            scene,
            model,
            name,
            at,
            on_surface,
        } => {
            let (_, mut world) = load(&scene)?;
            world.spawn(&model, &name, [at[0], at[1], at[2]])?;
            if on_surface {
                world.put_on_surface(&name)?;
            }
            let report = world.settle();
            println!(
                "spawned `{name}` ({model}); settled in {} steps",
                report.steps
            );
            print_poses(&world);
        }
        SimCommand::Do {
            scene,
            commands,
            png,
        } => {
            let (_, mut world) = load(&scene)?;
            for (i, line) in commands.iter().enumerate() {
                run_command(&mut world, line)
                    .with_context(|| format!("command {} `{line}`", i + 1))?;
            }
            if let Some(path) = png {
                tabula_bench::report::default_snapshot(&world, &path)?;
                println!("wrote {}", path.display());
            }
        }
        SimCommand::Models => {
            for (name, what) in MODELS {
                println!("{name:<14} {what}");
            }
        }
        SimCommand::Bench {
            scene,
            frames,
            json,
        } => bench(&scene, frames, json)?,
    }
    Ok(())
}

/// `sim settle`: the scene settled, its objects' poses.
fn settle(scene: &std::path::Path, json: bool) -> Result<()> {
    let (_, mut world) = load(scene)?;
    let t0 = Instant::now();
    let report = world.settle();
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    if json {
        let poses: Vec<_> = world
            .object_poses()
            .into_iter()
            .map(|(n, p)| serde_json::json!({"name": n, "xyz": p.translation.to_array(), "quat_xyzw": p.rotation.to_array()}))
            .collect();
        println!(
            "{}",
            serde_json::json!({"report": report, "wall_ms": ms, "objects": poses})
        );
    } else {
        println!(
            "settled in {} steps ({:.2} s simulated, {ms:.1} ms wall), all asleep: {}",
            report.steps, report.simulated_seconds, report.all_asleep
        );
        print_poses(&world);
    }
    Ok(())
}

/// The frame (optical frame) with a `label` field holding only the objects' labels.
fn object_labels_pcd(
    world: &SimWorld,
    frame: &tabula_sim::camera::DepthFrame,
    path: &std::path::Path,
) -> Result<()> {
    let is_object = |l: u32| {
        l > 0
            && world
                .entities
                .get(l as usize - 1)
                .is_some_and(|e| e.kind == tabula_sim::world::EntityKind::Object)
    };
    let labels: Vec<u32> = frame
        .labels
        .iter()
        .map(|&l| if is_object(l) { l } else { 0 })
        .collect();
    let mut out = std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("--labels {}", path.display()))?,
    );
    let extras = tabula_geom::PcdExtras {
        labels: Some(&labels),
        ..Default::default()
    };
    frame
        .cloud
        .write_pcd_with(&mut out, tabula_geom::PcdEncoding::Binary, &extras)
        .and_then(|()| std::io::Write::flush(&mut out))
        .with_context(|| format!("--labels {}", path.display()))
}

/// `sim capture`: one frame of a scene camera written as PCD or PLY (and its labels).
fn capture_to_file(a: &CaptureArgs) -> Result<()> {
    let (scene, mut world) = load(&a.scene)?;
    if a.settle {
        world.settle();
    }
    let camera = camera_of(&scene, &world, a.camera.as_deref())?;
    let t0 = Instant::now();
    let frame = capture(&world, &camera, a.seed);
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let how = tabula_sim::frame_file::FrameFile {
        binary: a.binary,
        world: a.world,
    };
    frame.write_file(&a.out, how)?;
    match &a.labels {
        Some(path)
            if path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("pcd")) =>
        {
            object_labels_pcd(&world, &frame, path)?
        }
        Some(path) => frame.write_labels(path)?,
        None => {}
    }
    let p = frame.world_from_camera;
    let [r, pi, y] = rpy_from_quat(p.rotation);
    println!(
        "{}×{} frame, {} valid points, {ms:.1} ms; world_from_camera (optical) xyz {:.4} {:.4} {:.4} rpy {:.4} {:.4} {:.4} (--world-from-camera {} {} {} {} {} {} {}); wrote {}",
        frame.width,
        frame.height,
        frame.cloud.finite_count(),
        p.translation.x,
        p.translation.y,
        p.translation.z,
        r,
        pi,
        y,
        p.translation.x,
        p.translation.y,
        p.translation.z,
        p.rotation.x,
        p.rotation.y,
        p.rotation.z,
        p.rotation.w,
        a.out.display()
    );
    Ok(())
}

/// `sim bench`: capture and settle times of a scene, medians.
fn bench(scene: &std::path::Path, frames: usize, json: bool) -> Result<()> {
    let (s, world) = load(scene)?;
    let camera = camera_of(&s, &world, None)?;
    let mut capture_ms = Vec::new();
    for seed in 0..frames.max(1) as u64 {
        let t0 = Instant::now();
        std::hint::black_box(capture(&world, &camera, seed));
        capture_ms.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    let mut settle_ms = Vec::new();
    let mut steps = 0;
    for _ in 0..frames.max(1) {
        let (_, mut w) = load(scene)?;
        let t0 = Instant::now();
        steps = w.settle().steps;
        settle_ms.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (c, st) = (median(&mut capture_ms), median(&mut settle_ms));
    if json {
        println!(
            "{}",
            serde_json::json!({"capture_ms_median": c, "settle_ms_median": st, "settle_steps": steps, "width": camera.width, "height": camera.height, "threads": rayon::current_num_threads()})
        );
    } else {
        println!(
            "{}: {}×{} capture median {c:.1} ms wall ({} threads); settle median {st:.1} ms wall ({steps} steps)",
            scene.display(),
            camera.width,
            camera.height,
            rayon::current_num_threads()
        );
    }
    Ok(())
}

/// `tabula scenes [NAME]`: the built-in scenes with what each is, or one's TOML.
pub fn scenes(name: Option<&str>) -> Result<()> {
    use tabula_sim::builtin;
    match name {
        Some(n) => {
            let s = builtin::scene(n).ok_or_else(|| {
                anyhow::anyhow!("no built-in scene `{n}`; built-in: {}", builtin::names())
            })?;
            print!("{}", s.text);
        }
        None => {
            for s in &builtin::SCENES {
                println!("{:<14} {}", s.name, s.about());
            }
        }
    }
    Ok(())
}
