//! The loop seed 000 could not close: perceive a cluttered table, ask the free-space map
//! where a new box fits, put the box there in the simulator, and let physics judge —
//! it must go in without touching anything, rest where it was put, and disturb nothing.

use tabula_geom::{Vec2, Vec3};
use tabula_perception::freespace::{FreeSpaceMap, FreeSpaceParams};
use tabula_perception::{TabletopParams, extract, to_world};
use tabula_sim::Scene;
use tabula_sim::generate::{TABLE_TOP, TabletopLayout, tabletop_frame};

#[test]
fn boxes_placed_where_the_map_says_rest_there_and_disturb_nothing() {
    let (sx, sy, sz) = (0.10, 0.07, 0.06);
    let footprint = [
        Vec2::new(-sx / 2.0, -sy / 2.0),
        Vec2::new(sx / 2.0, -sy / 2.0),
        Vec2::new(sx / 2.0, sy / 2.0),
        Vec2::new(-sx / 2.0, sy / 2.0),
    ];
    let mut placed = 0;
    for seed in 1..=8u64 {
        let mut g = tabletop_frame(seed, &TabletopLayout::random(seed)).unwrap();
        let cloud = to_world(&g.frame.world_from_camera, &g.frame.cloud);
        let t = extract(
            &cloud,
            g.frame.world_from_camera.translation,
            &TabletopParams::default(),
        )
        .unwrap();
        let map =
            FreeSpaceMap::from_tabletop(&t, &cloud.points, &FreeSpaceParams::default()).unwrap();
        let objects: Vec<Vec<Vec3>> = t
            .objects
            .iter()
            .map(|o| o.indices.iter().map(|&i| cloud.points[i]).collect())
            .collect();
        // Near the middle of the clutter, where free space is scarce.
        let near = objects.iter().flatten().copied().sum::<Vec3>()
            / objects.iter().map(Vec::len).sum::<usize>().max(1) as f64;
        let Some(place) = map.find_place(&footprint, 0.02, near) else {
            continue;
        };
        let before = g.world.object_poses();
        let yaw = {
            let x = place.world_from_footprint.rotation * Vec3::X;
            x.y.atan2(x.x)
        };
        let at = place.position;
        let text = format!(
            "[[object]]\nname = \"new_box\"\nshape = {{ box = [{sx}, {sy}, {sz}] }}\npose = {{ xyz = [{}, {}, {}], rpy = [0.0, 0.0, {yaw}] }}\nmass = 0.2\n",
            at.x,
            at.y,
            TABLE_TOP + sz / 2.0 + 0.001
        );
        let spec = Scene::parse(&text, "new box").unwrap().objects.remove(0);
        // Refused if it would overlap anything already there.
        g.world
            .add_object(&spec)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        let expected = g.world.pose("new_box").unwrap();
        g.world.settle();
        let (moved, turned) = g.world.pose_error("new_box", &expected).unwrap();
        assert!(
            moved < 0.01 && turned < 0.05,
            "seed {seed}: the box moved {moved} m, turned {turned} rad"
        );
        for (name, pose) in &before {
            let (d, _) = g.world.pose_error(name, pose).unwrap();
            assert!(d < 0.005, "seed {seed}: {name} was pushed {d} m");
        }
        placed += 1;
    }
    assert!(placed >= 6, "a place was found on {placed} of 8 tables");
}
