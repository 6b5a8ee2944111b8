//! `tabula demo`: the main job, one section per capability that has landed.

use anyhow::Result;
use std::time::Instant;
use tabula_geom::{Pose, Vec3, pose_from_xyz_rpy};
use tabula_robot::Chain;
use tabula_robot::ik::{
    ArmSide, Golem3Ik, Golem3Params, IkMode, IkSolver, NumericIk, NumericIkParams,
};
use tabula_robot::robots;

pub fn run() -> Result<()> {
    println!("tabula demo\n===========\n");
    kinematics()?;
    Ok(())
}

fn kinematics() -> Result<()> {
    println!("1. Kinematics (seed 001): Golem-III closed-form IK, all branches\n");
    let golem = robots::load("golem3")?;
    let ik = Golem3Ik::new(&golem.model, ArmSide::Right, Golem3Params::default())?;
    let chain = ik.chain().clone();
    let seed = vec![0.1, 0.3, 0.2, 0.3, 0.4, 0.0];
    let targets: [(&str, Pose); 3] = [
        (
            "in front of the right shoulder, tool level",
            pose_from_xyz_rpy([0.62, -0.43, 1.04], [0.0, 0.0, -0.2]),
        ),
        (
            "low, tool pitched down",
            chain.fk(&[0.3, 0.5, -0.4, 0.6, 0.5, 0.2])?,
        ),
        (
            "out of reach",
            pose_from_xyz_rpy([1.4, -0.2, 1.3], [0.0, 0.0, 0.0]),
        ),
    ];
    for (label, target) in &targets {
        let t = target.translation;
        println!(
            "  target: {label} at ({:.3}, {:.3}, {:.3}) in torso_lift_link",
            t.x, t.y, t.z
        );
        let t0 = Instant::now();
        let result = ik.solve(target, IkMode::Full, &seed);
        let us = t0.elapsed().as_secs_f64() * 1e6;
        match result {
            Ok(sols) => {
                crate::ik::print_solutions(&chain, &sols);
                println!("  nearest to the seed {:?}: #1 ({us:.1} µs)\n", seed);
            }
            Err(e) => println!("  {e} ({us:.1} µs)\n"),
        }
    }
    let reach = Vec3::new(0.35, -0.55, 1.0);
    let t0 = Instant::now();
    let sols = ik.solve(&Pose::from_translation(reach), IkMode::PositionOnly, &seed)?;
    println!(
        "  position only ({:.2}, {:.2}, {:.2}): {:?} in {:.1} µs\n",
        reach.x,
        reach.y,
        reach.z,
        sols[0]
            .joints
            .iter()
            .map(|v| (v * 1e4).round() / 1e4)
            .collect::<Vec<_>>(),
        t0.elapsed().as_secs_f64() * 1e6
    );

    println!("  Numeric IK on the 7-DOF WAM and the PR2 right arm (any URDF chain):");
    for name in ["wam", "pr2"] {
        let robot = robots::load(name)?;
        let chain = Chain::new(&robot.model, &robot.default_base, &robot.default_tip)?;
        let solver = NumericIk::new(chain.clone(), NumericIkParams::default());
        let q_true: Vec<f64> = chain
            .mid_configuration()
            .iter()
            .enumerate()
            .map(|(i, v)| v + 0.3 * ((i % 3) as f64 - 1.0))
            .collect();
        let target = chain.fk(&q_true)?;
        let t0 = Instant::now();
        let sols = solver.solve(&target, IkMode::Full, &chain.mid_configuration())?;
        println!(
            "    {name:<4} {} → {}: solved in {:.1} µs, error {:.1e} m / {:.1e} rad",
            chain.base_link,
            chain.tip_link,
            t0.elapsed().as_secs_f64() * 1e6,
            sols[0].position_error,
            sols[0].rotation_error
        );
    }
    println!(
        "\n  Benchmarks: `tabula ik bench --robot golem3 --solver analytic --poses 10000` (see BENCHMARKS.md)\n"
    );
    Ok(())
}
