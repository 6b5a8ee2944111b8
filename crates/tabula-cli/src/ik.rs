//! `tabula ik …`: solve, benchmark and inspect kinematic chains.

use anyhow::{Result, bail};
use clap::{Args, Subcommand, ValueEnum};
use std::path::PathBuf;
use tabula_geom::input::Validate;
use tabula_geom::{Pose, Vec3, pose_from_xyz_rpy, rpy_from_quat};
use tabula_robot::Chain;
use tabula_robot::ik::{
    ArmSide, Golem3Ik, Golem3Params, IkError, IkMode, IkSolver, NumericIk, NumericIkParams, bench,
};
use tabula_robot::robots::{self, NamedRobot};

#[derive(Subcommand)]
pub enum IkCommand {
    /// Print every IK solution for one target pose, nearest to the seed first.
    Solve(SolveArgs),
    /// Run seed 001's benchmark protocol (SPEC §2.4) on a chain.
    Bench(BenchArgs),
    /// Forward kinematics of a chain at given joint values.
    Fk(FkArgs),
    /// List a robot's links, joints and limits.
    Info(RobotArgs),
}

#[derive(Args, Clone)]
pub struct RobotArgs {
    /// golem3, wam, pr2, or a path to a .urdf file.
    #[arg(long, default_value = "golem3")]
    pub robot: String,
    /// First link of the chain (default: the robot's usual arm base).
    #[arg(long)]
    pub base: Option<String>,
    /// Last link of the chain (default: the robot's usual tool frame).
    #[arg(long)]
    pub tip: Option<String>,
    /// TOML file with [numeric_ik] and/or [golem3_ik] parameter tables.
    #[arg(long)]
    pub config: Option<PathBuf>,
}

#[derive(Copy, Clone, PartialEq, Eq, ValueEnum)]
pub enum SolverKind {
    /// Closed form where the chain has one (Golem-III, UR-type 6R, spherical-shoulder
    /// 7R with the numeric solver behind it), numeric otherwise.
    Auto,
    /// The chain's closed form alone (Golem-III, UR-type 6R, spherical-shoulder 7R).
    Analytic,
    /// Levenberg–Marquardt with restarts, any chain.
    Numeric,
}

#[derive(Args)]
pub struct SolveArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Target tip pose in the base frame: x y z (m) roll pitch yaw (rad, URDF convention).
    #[arg(long, required = true, num_args = 6, allow_negative_numbers = true, value_names = ["X", "Y", "Z", "ROLL", "PITCH", "YAW"], value_parser = crate::args::finite)]
    pose: Vec<f64>,
    /// Seed configuration (one value per chain joint); default mid-range.
    #[arg(long, num_args = 1.., allow_negative_numbers = true, value_parser = crate::args::finite)]
    seed_joints: Option<Vec<f64>>,
    /// Reach the position only; orientation is free.
    #[arg(long)]
    position_only: bool,
    #[arg(long, value_enum, default_value = "auto")]
    solver: SolverKind,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct BenchArgs {
    #[command(flatten)]
    robot: RobotArgs,
    #[arg(long, value_enum, default_value = "auto")]
    solver: SolverKind,
    /// Number of random reachable targets (and as many unreachable ones).
    #[arg(long, default_value_t = 10_000, value_parser = crate::args::count)]
    poses: usize,
    /// Seed of the target generator.
    #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
    seed: u64,
    #[arg(long)]
    position_only: bool,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Write a report into this folder: the solve-time distribution, errors per axis.
    #[arg(long)]
    report: Option<std::path::PathBuf>,
    /// Compare two solvers on the same targets (seed 001 §5.1): a Mann–Whitney U test
    /// (α = 0.05) on solve time and on each axis's error, box plots with --report.
    #[arg(long, num_args = 2, value_names = ["A", "B"], value_enum)]
    compare: Option<Vec<SolverKind>>,
}

#[derive(Args)]
pub struct FkArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Joint values in chain order (default: zero, or the nearest limit when zero is
    /// outside it).
    #[arg(long, num_args = 1.., allow_negative_numbers = true, value_parser = crate::args::finite)]
    joints: Option<Vec<f64>>,
    /// Print JSON: `base`, `tip`, `joint_names`, `joints`, `xyz`, `quat_xyzw`, `rpy`.
    #[arg(long)]
    json: bool,
}

/// Kinematics works without meshes; say which ones are missing, once each, and what
/// the URDF said that was ignored.
fn warn_unreadable_meshes(robot: &robots::NamedRobot) {
    for note in &robot.model.ignored {
        eprintln!("warning: {note}");
    }
    let missing = &robot.model.unreadable_meshes;
    // Collision meshes first: they decide what the robot may be used for.
    let mut ordered: Vec<_> = missing.iter().collect();
    ordered.sort_by_key(|u| u.role != "collision");
    for u in ordered.into_iter().take(5) {
        let consequence = if u.role == "collision" {
            "kinematics only; collision checks refuse this robot"
        } else {
            "not drawn; planning and the simulator use the collision geometry"
        };
        eprintln!("warning: {u} ({consequence})");
    }
    if missing.len() > 5 {
        eprintln!(
            "warning: … and {} more unreadable meshes",
            missing.len() - 5
        );
    }
}

#[derive(serde::Deserialize, serde::Serialize, Default)]
#[serde(default, deny_unknown_fields)]
struct Config {
    numeric_ik: NumericIkParams,
    golem3_ik: Golem3Params,
}

impl Validate for Config {
    fn check(&self, at: &str) -> Result<(), String> {
        self.numeric_ik
            .check(&tabula_geom::input::nested(at, "numeric_ik"))
    }
}

/// The robot, its chain and the solver the arguments ask for.
pub struct Setup {
    pub robot: NamedRobot,
    pub chain: Chain,
    pub solver: Box<dyn IkSolver>,
    pub solver_name: &'static str,
    numeric_params: NumericIkParams,
}

pub fn setup(args: &RobotArgs, kind: SolverKind) -> Result<Setup> {
    let config: Config = crate::tasks::load_params(args.config.as_deref())?;
    let robot = robots::load(&args.robot)?;
    let base = args
        .base
        .clone()
        .unwrap_or_else(|| robot.default_base.clone());
    let tip = args
        .tip
        .clone()
        .unwrap_or_else(|| robot.default_tip.clone());
    let chain = Chain::new(&robot.model, &base, &tip)?;
    if chain.dof() == 0 {
        bail!("the chain from `{base}` to `{tip}` has no moving joint");
    }
    let golem_side = match (base.as_str(), tip.as_str()) {
        ("torso_lift_link", "right_tool_link") => Some(ArmSide::Right),
        ("torso_lift_link", "left_tool_link") => Some(ArmSide::Left),
        _ => None,
    };
    // Asked for explicitly, a Golem-III chain that does not match the DH table is an
    // error worth showing; on `auto` it just means the numeric solver.
    let analytic =
        match golem_side.map(|side| Golem3Ik::new(&robot.model, side, config.golem3_ik.clone())) {
            Some(Err(e)) if kind == SolverKind::Analytic => return Err(e.into()),
            Some(Ok(a)) => Some(a),
            _ => None,
        };
    // 6R closed forms: complete, so nothing numeric behind them.
    let six_r: Option<(Box<dyn IkSolver>, &'static str)> =
        tabula_robot::ik::ThreeParallelIk::new(&chain)
            .map(|p| (Box::new(p) as Box<dyn IkSolver>, "analytic-3-parallel"))
            .or_else(|| {
                tabula_robot::ik::SphericalWristIk::new(&chain)
                    .map(|s| (Box::new(s) as Box<dyn IkSolver>, "analytic-spherical-wrist"))
            });
    let shoulder7 = tabula_robot::ik::SphericalShoulderIk::new(&chain);
    let numeric = || NumericIk::new(chain.clone(), config.numeric_ik.clone());
    let (solver, solver_name): (Box<dyn IkSolver>, &'static str) = match (
        kind, analytic, six_r, shoulder7,
    ) {
        (SolverKind::Analytic | SolverKind::Auto, Some(a), _, _) => {
            (Box::new(a), "analytic-golem3")
        }
        (SolverKind::Analytic | SolverKind::Auto, None, Some(six_r), _) => six_r,
        (SolverKind::Analytic, None, None, Some(s)) => (Box::new(s), "analytic-spherical-shoulder"),
        // Auto: the sweep over the redundancy, the numeric solver for what it misses.
        (SolverKind::Auto, None, None, Some(_)) => (
            Box::new(tabula_robot::ik::AutoIk::all_solutions(numeric())),
            "analytic-spherical-shoulder+numeric",
        ),
        (SolverKind::Analytic, None, None, None) => bail!(
            "no analytic solver for `{base}` → `{tip}` of {}: the closed forms cover the Golem-III arms \
                 (torso_lift_link → right_tool_link / left_tool_link), 6R arms with axes 2–4 parallel and \
                 axes 5 and 6 meeting (UR-type), 6R arms with a spherical wrist and axes 2 and 3 parallel \
                 or axes 1 and 2 meeting (KUKA, ABB, FANUC, Stäubli) and 7R arms with axes 1–3 meeting and axes 5 and 6 \
                 meeting (Panda, iiwa, WAM); use --solver numeric",
            robot.label
        ),
        _ => (Box::new(numeric()), "numeric-lm"),
    };
    Ok(Setup {
        robot,
        chain,
        solver,
        solver_name,
        numeric_params: config.numeric_ik,
    })
}

pub fn run(cmd: IkCommand) -> Result<()> {
    match cmd {
        IkCommand::Solve(a) => solve(a),
        IkCommand::Bench(a) => run_bench(a),
        IkCommand::Fk(a) => fk(a),
        IkCommand::Info(a) => info(a),
    }
}

fn solve(a: SolveArgs) -> Result<()> {
    let s = setup(&a.robot, a.solver)?;
    let p = &a.pose;
    let target = pose_from_xyz_rpy([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
    let seed = a
        .seed_joints
        .clone()
        .unwrap_or_else(|| s.chain.mid_configuration());
    let mode = if a.position_only {
        IkMode::PositionOnly
    } else {
        IkMode::Full
    };
    let sols = s.solver.solve(&target, mode, &seed);
    if a.json {
        let value = match &sols {
            Ok(sols) => serde_json::json!({
                "solver": s.solver_name, "joint_names": s.chain.joint_names,
                "solutions": sols.iter().map(|x| serde_json::json!({
                    "joints": x.joints, "position_error_m": x.position_error, "rotation_error_rad": x.rotation_error,
                })).collect::<Vec<_>>(),
            }),
            Err(e) => {
                serde_json::json!({"solver": s.solver_name, "solutions": [], "error": e.to_string()})
            }
        };
        println!("{}", serde_json::to_string_pretty(&value)?);
        return match sols {
            Ok(_) => Ok(()),
            Err(e) => no_solution_or_error(e),
        };
    }
    println!(
        "{} ({}): {} → {}, {} joints, solver {}",
        s.robot.label,
        s.robot.model.name,
        s.chain.base_link,
        s.chain.tip_link,
        s.chain.dof(),
        s.solver_name
    );
    match sols {
        Ok(sols) => {
            for line in tabula_bench::ik::solution_lines(&s.chain, &sols) {
                println!("{line}");
            }
            Ok(())
        }
        Err(e) => no_solution_or_error(e),
    }
}

/// A target nothing reaches is "no solution" (exit status 2, one line); anything else
/// is an error of the input.
fn no_solution_or_error(e: IkError) -> Result<()> {
    if matches!(e, IkError::NoSolution | IkError::NotFound { .. }) {
        eprintln!("{e}");
        std::process::exit(crate::exit::NO_SOLUTION);
    }
    Err(e.into())
}

/// `ik bench --compare A B`: both solvers on the same targets, 7 measures tested.
fn compare(a: &BenchArgs, kind_a: SolverKind, kind_b: SolverKind) -> Result<()> {
    let mode = if a.position_only {
        IkMode::PositionOnly
    } else {
        IkMode::Full
    };
    let mut runs = Vec::new();
    for kind in [kind_a, kind_b] {
        let s = setup(&a.robot, kind)?;
        let progress = crate::progress::spinner(&format!("{}: {} targets", s.solver_name, a.poses));
        runs.push(bench::run(
            s.solver.as_ref(),
            None,
            s.solver_name,
            mode,
            a.poses,
            a.seed,
        ));
        progress.finish_and_clear();
    }
    let (ra, rb) = (&runs[0], &runs[1]);
    let compared = tabula_bench::ik::compare(ra, rb);
    let out = serde_json::json!({
        "a": ra.solver, "b": rb.solver, "poses": a.poses, "seed": a.seed, "mode": ra.mode,
        "success_rate_a": ra.success_rate, "success_rate_b": rb.success_rate,
        "alpha": 0.05, "measures": compared,
    });
    if let Some(dir) = &a.report {
        let page = tabula_bench::report::ik::compare_page(dir, (ra, rb), &compared, &out)?;
        eprintln!("report: {}", page.display());
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    for line in tabula_bench::report::ik::compare_lines((ra, rb), &compared) {
        println!("{line}");
    }
    Ok(())
}

fn run_bench(a: BenchArgs) -> Result<()> {
    if let Some(pair) = &a.compare {
        return compare(&a, pair[0], pair[1]);
    }
    let s = setup(&a.robot, a.solver)?;
    if a.poses == 0 {
        bail!("--poses must be at least 1");
    }
    let mode = if a.position_only {
        IkMode::PositionOnly
    } else {
        IkMode::Full
    };
    let single = NumericIk::new(
        s.chain.clone(),
        NumericIkParams {
            max_attempts: 1,
            timeout_s: None,
            ..s.numeric_params.clone()
        },
    );
    let one_attempt: Option<&dyn IkSolver> =
        (s.solver_name == "numeric-lm").then_some(&single as &dyn IkSolver);
    let progress =
        crate::progress::spinner(&format!("{} reachable and unreachable targets", a.poses));
    let report = bench::run(
        s.solver.as_ref(),
        one_attempt,
        s.solver_name,
        mode,
        a.poses,
        a.seed,
    );
    progress.finish_and_clear();
    if let Some(dir) = &a.report {
        tabula_bench::report::ik::bench_page(dir, &s.robot.label, &report)?;
    }
    if a.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    for line in tabula_bench::report::ik::bench_lines(&s.robot.label, &report) {
        println!("{line}");
    }
    Ok(())
}

fn fk(a: FkArgs) -> Result<()> {
    let robot = robots::load(&a.robot.robot)?;
    warn_unreadable_meshes(&robot);
    let base = a
        .robot
        .base
        .clone()
        .unwrap_or_else(|| robot.default_base.clone());
    let tip = a
        .robot
        .tip
        .clone()
        .unwrap_or_else(|| robot.default_tip.clone());
    let chain = Chain::new(&robot.model, &base, &tip)?;
    let q = a.joints.unwrap_or_else(|| {
        (0..chain.dof())
            .map(|i| 0.0f64.clamp(chain.lower[i], chain.upper[i]))
            .collect()
    });
    if q.len() == chain.dof() {
        for (i, v) in q.iter().enumerate() {
            // Continuous joints have no limits; their angle is still an angle.
            let (lo, hi) = (
                chain.lower[i].max(-tabula_geom::input::MAX_MAGNITUDE),
                chain.upper[i].min(tabula_geom::input::MAX_MAGNITUDE),
            );
            if !(lo - 1e-9..=hi + 1e-9).contains(v) {
                let show = tabula_geom::input::shown;
                bail!(
                    "joint `{}` = {} is outside its limits [{}, {}]",
                    chain.joint_names[i],
                    show(*v),
                    show(lo),
                    show(hi)
                );
            }
        }
    }
    let pose: Pose = chain.fk(&q)?;
    let [r, p, y] = rpy_from_quat(pose.rotation);
    let t: Vec3 = pose.translation;
    if a.json {
        let quat = pose.rotation;
        let out = serde_json::json!({
            "base": base,
            "tip": tip,
            "joint_names": chain.joint_names,
            "joints": q,
            "xyz": [t.x, t.y, t.z],
            "quat_xyzw": [quat.x, quat.y, quat.z, quat.w],
            "rpy": [r, p, y],
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    println!(
        "{base} → {tip}: xyz {:.6} {:.6} {:.6}  rpy {:.6} {:.6} {:.6}",
        t.x, t.y, t.z, r, p, y
    );
    Ok(())
}

fn info(a: RobotArgs) -> Result<()> {
    let robot = robots::load(&a.robot)?;
    warn_unreadable_meshes(&robot);
    let m = &robot.model;
    for link in [&a.base, &a.tip].into_iter().flatten() {
        m.link(link)?;
    }
    println!(
        "{} ({}): {} links, {} joints; default chain {} → {}",
        robot.label,
        m.name,
        m.links.len(),
        m.joints.len(),
        robot.default_base,
        robot.default_tip
    );
    for j in &m.joints {
        let l = j.limits;
        println!(
            "  {:<32} {:<12} {} → {}  [{:.4}, {:.4}]  v≤{:.3}",
            j.name,
            format!("{:?}", j.kind).to_lowercase(),
            m.links[j.parent].name,
            m.links[j.child].name,
            l.lower,
            l.upper,
            l.velocity
        );
    }
    Ok(())
}
