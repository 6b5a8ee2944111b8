//! Where on a surface the object goes: free spots away from edges and objects, and the
//! base pose that brings the arm to them (Alg. 10).

use super::body::{
    base_half_extent, forward_extent, shoulder_lateral, shoulder_position, surface_slab,
    world_from_base,
};
use super::model::Resting;
use super::outline::{Outline, footprint_of, nearest_edge, path_blocked};
use super::run::{FreeSpot, Run, Spot, Target};
use super::sequence::Sequence;
use super::{PlaceError, PlaceTopView, pose_array};
use crate::skills::base::{BACK_OFF, drive_back, heading};
use tabula_geom::polygon::convex_hull_2d;
use tabula_geom::{Pose, Vec2, Vec3};
use tabula_perception::freespace::FreeSpaceMap;
use tabula_perception::surfaces::Surface;
use tabula_robot::driver::{DriverError, RobotDriver};

/// Approaches to a surface tried before placing on it fails: each after a stop looks
/// at what stopped the base.
const APPROACH_TRIES: usize = 3;

impl Run<'_> {
    /// Free spots for each usable pose (the footprint of the object resting so) on the
    /// target surface: (pose index, position, yaw, clearance), best first.
    fn spots(&mut self, t: Target<'_>, scene: &[Vec3]) -> Result<Vec<FreeSpot>, PlaceError> {
        self.phase("free space", |r| {
            r.decide(|r| r.free_spots(t.poses, t.surface, scene))
        })
    }

    /// Puts the held object down on `t.surface`: free spots, the base driven to them
    /// when out of reach (Alg. 10), a placement planned and executed (Algs 11–12).
    pub(super) fn place_on(
        &mut self,
        driver: &mut impl RobotDriver,
        t: Target<'_>,
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        let p = self.params;
        let mut spots = self.spots(t, scene)?;
        if spots.is_empty() {
            return Err(PlaceError::NoRoom(format!(
                "the surface at {:.2} m has no room for the object's footprint with {:.0} mm to spare",
                t.surface.centroid.z,
                p.place_margin * 1e3
            )));
        }
        let mut sh = self.shoulder(driver, t.arm)?;
        if !spots.iter().any(|s| s.1.distance(sh) <= p.reach) {
            self.approach(driver, t, &spots, scene)?;
            spots = self.spots(t, scene)?;
            sh = self.shoulder(driver, t.arm)?;
        }
        let (seq, spot, pose_index) = self.plan_on(driver, t, &spots, sh, scene)?;
        self.report.stable_pose = Some(t.poses[pose_index].pose.clone());
        self.report.planned_world_from_tool = Some(pose_array(&spot.world_from_tool));
        self.record_spot(&spot, t.surface);
        self.execute_placement(driver, t.arm, &seq)
    }

    /// Where `arm`'s shoulder is now (world).
    fn shoulder(&self, driver: &mut impl RobotDriver, arm: &str) -> Result<Vec3, PlaceError> {
        let state = driver.joint_state()?;
        shoulder_position(self.robot, arm, &state, driver.world_from_root()?)
    }

    /// Drives the base to the surface (Alg. 10): turn while still clear of it, then
    /// straight in (a base turning at the edge would sweep its corners into it), and
    /// look at the surface from there — what is near it now counts. The way is checked
    /// against what the camera has seen; furniture it has not seen (behind the robot, out
    /// of the search's view) can still stop the base (the driver's guard). Then the robot
    /// looks at what stopped it, backs to where it started and tries again with that in
    /// its scene, [`APPROACH_TRIES`] times in all.
    fn approach(
        &mut self,
        driver: &mut impl RobotDriver,
        t: Target<'_>,
        spots: &[FreeSpot],
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        let start = world_from_base(self.robot, driver)?;
        let mut stopped_by = String::new();
        for _ in 0..APPROACH_TRIES {
            let goal = self.approach_goal(driver, t, spots, scene)?;
            let stop = self.phase("approach", |r| r.drive_in(driver, goal))?;
            let Some((ahead, by)) = stop else {
                return self.look_and_add(driver, t.arm, t.hull, t.surface.centroid, scene);
            };
            stopped_by = format!(
                "blocked by `{by}` on the way to ({:.2}, {:.2})",
                goal[0], goal[1]
            );
            self.mark(&format!("{stopped_by}: looking at what stopped it"));
            self.look_and_add(driver, t.arm, t.hull, ahead, scene)?;
            drive_back(driver, self.robot, &start, BACK_OFF)
                .map_err(|e| PlaceError::ApproachBlocked(e.to_string()))?;
        }
        Err(PlaceError::ApproachBlocked(stopped_by))
    }

    /// Where the base stands to place on one of `spots` (see [`Run::base_goal`]).
    fn approach_goal(
        &mut self,
        driver: &mut impl RobotDriver,
        t: Target<'_>,
        spots: &[FreeSpot],
        scene: &[Vec3],
    ) -> Result<[f64; 3], PlaceError> {
        let base = world_from_base(self.robot, driver)?;
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        // How far the robot reaches forward below the surface's top (an elbow hanging
        // low, a tucked arm): that, not the base's edge, meets the edge.
        let front = forward_extent(self.robot, &state, root, base, t.surface.centroid.z + 0.05)
            .max(base_half_extent(self.robot));
        self.mark(&format!(
            "robot reaches {front:.2} m forward below the surface"
        ));
        let goal = self.decide(|r| r.base_goal(base, front, t.arm, t.surface, spots, scene))?;
        self.report.base_goal = Some(goal);
        Ok(goal)
    }

    /// Drives to the run-up before `goal` and in to it. `Some((point, what))` when the
    /// driver's guard stopped the base on the way (`what` stopped it): a point 0.6 m
    /// ahead of where it stopped, towards where it was going, at a typical table's
    /// height (0.7 m) — where to look for it.
    fn drive_in(
        &mut self,
        driver: &mut impl RobotDriver,
        goal: [f64; 3],
    ) -> Result<Option<(Vec3, String)>, PlaceError> {
        let (c, s) = (goal[2].cos(), goal[2].sin());
        let back = self.params.approach_run;
        for to in [[goal[0] - c * back, goal[1] - s * back], [goal[0], goal[1]]] {
            match driver.drive_to(to[0], to[1], goal[2]) {
                Ok(()) => {}
                Err(DriverError::Blocked { by, .. }) => {
                    let at = world_from_base(self.robot, driver)?;
                    let way = Vec2::from(to) - at.translation.truncate();
                    let dir = if way.length() > 0.05 {
                        way.normalize()
                    } else {
                        let h = heading(&at);
                        Vec2::new(h.cos(), h.sin())
                    };
                    let p = at.translation.truncate() + dir * 0.6;
                    return Ok(Some((Vec3::new(p.x, p.y, 0.7), by)));
                }
                Err(e) => return Err(e.into()),
            }
        }
        let base = world_from_base(self.robot, driver)?;
        let off = base
            .translation
            .truncate()
            .distance(Vec2::new(goal[0], goal[1]));
        if off > 0.05 {
            return Err(PlaceError::ApproachBlocked(format!(
                "stopped {:.2} m short of ({:.2}, {:.2})",
                off, goal[0], goal[1]
            )));
        }
        Ok(None)
    }

    /// Plans a placement on one of `spots` within reach of the shoulder at `sh`.
    fn plan_on(
        &mut self,
        driver: &mut impl RobotDriver,
        t: Target<'_>,
        spots: &[FreeSpot],
        sh: Vec3,
        scene: &[Vec3],
    ) -> Result<(Sequence, Spot, usize), PlaceError> {
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let mut group = self.group(t.arm, &state, root)?;
        let surface = t.surface;
        self.phase("plan placement", |r| {
            r.decide(|r| {
                // The surface itself is an exact slab at its measured height (seed 000
                // added the found surface to the planning scene), not occupancy voxels
                // that would stand up to a voxel above it.
                // What stands on it comes from `Outline::objects_on`, as free space's
                // does (from the band's top here, 1.2 cm up there): a lone noise point
                // the map ignored would otherwise block the spot it chose.
                let outline = Outline::of(surface);
                let on_top = 0.015;
                let mut rest: Vec<Vec3> = scene
                    .iter()
                    .copied()
                    .filter(|q| {
                        let h = outline.height(*q);
                        let band =
                            h > -0.025 && h < on_top && outline.distance(q.truncate()) < 0.02;
                        !band && !outline.holds(*q, on_top)
                    })
                    .collect();
                let gap = r.params.observe.cluster_gap;
                rest.extend(outline.objects_on(scene, on_top, gap).into_iter().flatten());
                r.occupy(&mut group, &rest, None);
                if let Some(slab) = surface_slab(surface, 0.0) {
                    group.add_object("surface", slab, Pose::IDENTITY)?;
                }
                // What stays of it while the hand is within millimetres of it (lowering,
                // releasing, backing out): the slab sunk by the padding, so the fingers
                // may pass just above the top and the wrist still cannot sweep through.
                let sunk = group.world.params.padding + 0.004;
                if let Some(slab) = surface_slab(surface, sunk) {
                    group.add_object("surface below", slab, Pose::IDENTITY)?;
                }
                r.plan_placement(&mut group, &state, t, spots, sh)
            })
        })
    }

    /// The object's outline resting at the spot, as the top view's map sees it.
    fn record_spot(&mut self, spot: &Spot, surface: &Surface) {
        let Some(view) = self.report.top_view.as_mut() else {
            return;
        };
        let flat: Vec<Vec2> = self
            .report
            .model_points
            .iter()
            .map(|q| spot.world_from_tool.transform_point(*q).truncate())
            .collect();
        let z = surface.centroid.z;
        view.spot = Some(
            convex_hull_2d(&flat)
                .into_iter()
                .map(|i| flat[i].extend(z))
                .collect(),
        );
    }

    /// Runs the planned placement: above the spot, down, release slowly, back off,
    /// the arm aside.
    fn execute_placement(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        seq: &Sequence,
    ) -> Result<(), PlaceError> {
        let gripper = self
            .robot
            .description
            .arm(arm)
            .ok()
            .and_then(|a| a.gripper.clone())
            .ok_or(PlaceError::NotHolding)?;
        self.phase("move above spot", |_| {
            Ok(driver.execute(&seq.to_above.trajectory)?)
        })?;
        self.phase("lower", |_| Ok(driver.execute(&seq.lower.trajectory)?))?;
        let speed = self.params.release_speed;
        self.phase("release", |_| Ok(driver.open_slowly(&gripper, speed)?))?;
        self.phase("retreat", |_| Ok(driver.execute(&seq.retreat.trajectory)?))?;
        if let Some(aside) = &seq.aside {
            self.phase("arm aside", |_| Ok(driver.execute(&aside.trajectory)?))?;
        }
        Ok(())
    }

    /// Free spots on `surface` for each usable pose: (pose index, world position of the
    /// footprint origin, yaw in the world, score), best first.
    pub(super) fn free_spots(
        &mut self,
        poses: &[Resting],
        surface: &Surface,
        scene: &[Vec3],
    ) -> Result<Vec<FreeSpot>, PlaceError> {
        let p = self.params;
        let pts = scene;
        // Objects on the surface: what stands above it inside its outline.
        let outline = Outline::of(surface);
        let above = p.observe.object_clearance + 0.004;
        let objects = outline.objects_on(pts, above, p.observe.cluster_gap);
        let mut fs = p.free_space.clone();
        fs.yaw_samples = p.roll_samples.max(1);
        // The surface's seen cells: its points in the merged scene (the search ran on
        // another sampling of it).
        let on_surface =
            |q: Vec3| outline.height(q).abs() <= p.surfaces.ransac.threshold && outline.over(q);
        let mut seen = surface.clone();
        // From near, once near views cover a footprint's worth of it: the far points'
        // range noise would carry its edges outward.
        let near: Vec<usize> = (0..self.near.len())
            .filter(|&i| on_surface(self.near[i]))
            .collect();
        let cell = p.search_leaf * p.search_leaf;
        let footprint_cells = poses
            .iter()
            .map(|s| s.pose.area_m2 / cell)
            .fold(f64::INFINITY, f64::min);
        let edge_points = if near.len() as f64 >= 4.0 * footprint_cells.max(25.0) {
            seen.inliers = near;
            &self.near
        } else {
            seen.inliers = (0..pts.len()).filter(|&i| on_surface(pts[i])).collect();
            pts
        };
        let map = FreeSpaceMap::build(&seen, edge_points, &objects, &fs)
            .map_err(|e| PlaceError::NoRoom(e.to_string()))?;
        self.report.top_view = Some(PlaceTopView {
            map: map.clone(),
            outline: surface.hull.clone(),
            objects,
            spot: None,
        });
        let u_yaw = map.u.y.atan2(map.u.x);
        let mut out = Vec::new();
        for (k, pose) in poses.iter().enumerate() {
            let footprint = footprint_of(&pose.pose, &self.report.model_points);
            // Spots all over the surface: which the arm reaches decides later.
            for pl in map.places(&footprint, p.place_margin, 400, 0.04) {
                out.push((k, pl.position, pl.yaw + u_yaw, pl.clearance));
            }
        }
        Ok(out)
    }

    /// Alg. 10: a base pose facing the surface, the shoulder in front of the best free
    /// spot, the base's front `standoff` from the surface's edge.
    pub(super) fn base_goal(
        &self,
        base: Pose,
        front: f64,
        arm: &str,
        surface: &Surface,
        spots: &[FreeSpot],
        scene: &[Vec3],
    ) -> Result<[f64; 3], PlaceError> {
        let p = self.params;
        let me = base.translation.truncate();
        let hull2: Vec<Vec2> = surface.hull.iter().map(|q| q.truncate()).collect();
        let half = base_half_extent(self.robot);
        // The shoulder's offset in the base frame (left/right of the centre line).
        let lateral = shoulder_lateral(self.robot, arm);
        let mut best: Option<(f64, [f64; 3])> = None;
        // The shoulder stands about the base's half-length and the standoff from the
        // edge: spots deeper in than the rest of the reach cannot be placed from there.
        let depth = p.reach - front - p.standoff - 0.05;
        for s in spots {
            let spot = s.1.truncate();
            // Nearest point of the outline to the spot: the edge to stand at.
            let (edge, outward) = nearest_edge(&hull2, spot);
            if edge.distance(spot) > depth {
                continue;
            }
            let along = Vec2::new(-outward.y, outward.x);
            let facing = -outward;
            let theta = facing.y.atan2(facing.x);
            // Base centre: out from the edge; shifted so the shoulder faces the spot.
            let side_shift = (spot - edge).dot(along);
            let centre = edge + outward * (front + p.standoff) + along * side_shift
                - Vec2::new(-facing.y, facing.x) * lateral;
            let cost = me.distance(centre);
            if best.is_some_and(|(c, _)| cost >= c) {
                continue;
            }
            // The base must not sweep through anything seen on the way.
            let run_up = centre - facing * p.approach_run;
            let blocked = path_blocked(me, run_up, half * std::f64::consts::SQRT_2, scene)
                || path_blocked(run_up, centre, half, scene);
            let cost = cost + if blocked { 100.0 } else { 0.0 };
            if best.is_none_or(|(c, _)| cost < c) {
                best = Some((cost, [centre.x, centre.y, theta]));
            }
        }
        match best {
            Some((c, g)) if c < 100.0 => Ok(g),
            Some((_, g)) => Err(PlaceError::ApproachBlocked(format!(
                "something stands between the robot and ({:.2}, {:.2})",
                g[0], g[1]
            ))),
            None => Err(PlaceError::NoRoom("no spot to approach".into())),
        }
    }
}
