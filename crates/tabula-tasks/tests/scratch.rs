use tabula_geom::Vec3;
use tabula_robot::driver::*;
use tabula_sim::{PhysicsParams, Scene, SimDriver, SimWorld};
use tabula_tasks::observe::*;

#[test]
fn scratch() {
    let scene = Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/golem_shelves.toml"
    )))
    .unwrap();
    let w = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let mut d = SimDriver::new(w, "golem", 1).unwrap();
    let at = Vec3::new(0.4, 0.63, 1.07);
    let left = d.look_at(at).unwrap();
    let f = d.capture("head").unwrap();
    println!(
        "left {left} cam {:?} finite {}",
        f.world_from_camera.translation,
        f.cloud.finite_count()
    );
    let r = d.world.robot("golem").unwrap();
    let robot = tabula_robot::robots::load("golem3").unwrap();
    let st = d.joint_state().unwrap();
    let solids = robot_solids(
        &robot.model,
        &st.model_values(&robot.model),
        r.world_from_root,
    );
    let p = ObserveParams::default();
    let pts = world_points(&f, &solids, &p);
    println!("points {}", pts.len());
    let near: Vec<&Vec3> = pts
        .iter()
        .filter(|q| (q.truncate() - at.truncate()).length() < 0.12)
        .collect();
    println!("near {}", near.len());
    let mut h = std::collections::BTreeMap::new();
    for q in &near {
        *h.entry((q.z * 100.0).floor() as i64).or_insert(0) += 1;
    }
    println!("{h:?}");
    println!("{:?}", support_under(&pts, at, at.z + 0.03, &p));
}

#[test]
fn scratch2() {
    let scene = Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/golem_shelves.toml"
    )))
    .unwrap();
    let w = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let mut d = SimDriver::new(w, "golem", 1).unwrap();
    let robot = tabula_robot::robots::load("golem3").unwrap();
    let p = ObserveParams::default();
    let mut pts = Vec::new();
    for at in [Vec3::new(0.4, -0.63, 1.07), Vec3::new(0.4, 0.63, 1.07)] {
        let left = d.look_at(at).unwrap();
        let f = d.capture("head").unwrap();
        println!(
            "left {left} {:?}",
            d.joint_state().unwrap().get("head_pan_joint")
        );
        let st = d.joint_state().unwrap();
        let solids = robot_solids(
            &robot.model,
            &st.model_values(&robot.model),
            d.world_from_root().unwrap(),
        );
        pts.extend(world_points(&f, &solids, &p));
        println!("{:?}", support_under(&pts, at, at.z + 0.03, &p));
    }
    let o = object_near(&pts, Vec3::new(0.4, -0.63, 1.07), &p).unwrap();
    println!(
        "obj {:?} {} {} n {}",
        o.footprint,
        o.bottom,
        o.top,
        o.points.len()
    );
}

#[test]
fn reach_map() {
    use tabula_geom::*;
    use tabula_robot::ik::*;
    let robot = tabula_robot::robots::load("golem3").unwrap();
    let arm = robot.description.arm("right").unwrap();
    let ik = arm
        .ik_solver(&robot.model, NumericIkParams::default())
        .unwrap();
    let chain = arm.chain(&robot.model).unwrap();
    for z in [1.11] {
        println!("z (chain) = {z}");
        for iy in (-12..=4).rev() {
            let y = iy as f64 * 0.1;
            let mut line = format!("{y:5.1} ");
            for ix in -2..=12 {
                let x = ix as f64 * 0.1;
                let mut n = 0;
                let facing = (y + 0.0f64).atan2(x);
                for k in -12..=12 {
                    let yaw = facing + k as f64 * 0.05;
                    let pose = Pose::from_parts(Vec3::new(x, y, z), Quat::from_rotation_z(yaw));
                    let pre = Pose::from_parts(
                        pose.translation - (pose.rotation * Vec3::X) * 0.1,
                        pose.rotation,
                    );
                    if ik
                        .solve(&pose, IkMode::Full, &chain.mid_configuration())
                        .is_ok()
                        && ik
                            .solve(&pre, IkMode::Full, &chain.mid_configuration())
                            .is_ok()
                    {
                        n += 1;
                    }
                }
                line += &format!("{:>3}", n);
            }
            println!("{line}");
        }
    }
}

#[test]
fn dump_task() {
    let seed: u64 = std::env::var("SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    let t = tabula_sim::generate::golem_shelf_task(seed);
    std::fs::write("/tmp/task.toml", &t.scene).unwrap();
    println!(
        "--pick {} {} {} --place {} {} {}",
        t.pick[0], t.pick[1], t.pick[2], t.place[0], t.place[1], t.place[2]
    );
}
