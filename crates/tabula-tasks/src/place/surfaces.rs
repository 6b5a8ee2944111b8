//! Searching for surfaces with the head (Alg. 9): look, add what is seen, find the
//! horizontal ones within reach, try them in turn.

use super::body::{arm_gripper, heading, look_at, tool_pose, world_from_base};
use super::model::Resting;
use super::outline::Outline;
use super::run::{Run, Target};
use super::{PlaceError, SurfaceReport};
use crate::observe::{robot_solids, world_points_unthinned};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{PointCloud, Vec3};
use tabula_perception::selffilter::{PlacedSolid, Solid};
use tabula_perception::surfaces::{Surface, find_surfaces, surfaces_on};
use tabula_robot::driver::RobotDriver;

impl Run<'_> {
    /// Alg. 9: sweep the head, merge the views in the world frame (minus the robot and
    /// the held object), search planes, refine each accepted one by looking at it.
    pub(super) fn search_surfaces(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        scene: &mut Vec<Vec3>,
        not_on: &[Vec3],
    ) -> Result<Vec<Surface>, PlaceError> {
        let p = self.params;
        let root = world_from_base(self.robot, driver)?;
        let h = heading(&root);
        self.mark(&format!(
            "sweep from ({:.2}, {:.2}) heading {:.0}°",
            root.translation.x,
            root.translation.y,
            h.to_degrees()
        ));
        let looks: Vec<Vec3> = p
            .sweep_pans
            .iter()
            .map(|a| {
                let d = Vec3::new((h + a).cos(), (h + a).sin(), 0.0);
                Vec3::new(root.translation.x, root.translation.y, p.sweep_height)
                    + d * p.sweep_distance
            })
            .collect();
        for at in looks {
            self.look_and_add(driver, arm, hull, at, scene)?;
        }
        let mut surfaces = self.decide(|r| r.find(scene));
        // Refinement: look at each accepted surface again, search near its height, until
        // a look no longer moves its centroid (the next one would see the same).
        for surface in surfaces.iter_mut() {
            for _ in 0..p.refine_looks {
                let c = surface.centroid;
                self.look_and_add(driver, arm, hull, c, scene)?;
                let again = self.decide(|r| r.find_again(scene, surface));
                if let Some(best) = again
                    .into_iter()
                    .min_by(|a, b| a.centroid.distance(c).total_cmp(&b.centroid.distance(c)))
                {
                    *surface = best;
                }
                if surface.centroid.distance(c) < p.refine_converged {
                    break;
                }
            }
        }
        // Merged views may find one surface twice; surfaces the request rules out go.
        let mut unique: Vec<Surface> = Vec::new();
        let ruled_out = |s: &Surface| {
            let outline = Outline::of(s);
            not_on
                .iter()
                .any(|q| outline.over(*q) && (q.z - s.centroid.z).abs() <= 0.1)
        };
        for s in surfaces.into_iter().filter(|s| !ruled_out(s)) {
            if !unique.iter().any(|u| {
                (u.centroid.z - s.centroid.z).abs() < 0.03 && Outline::of(u).over(s.centroid)
            }) {
                unique.push(s);
            }
        }
        self.mark(&format!("{} surfaces", unique.len()));
        if unique.is_empty() {
            return Err(PlaceError::NoSurface(format!(
                "no horizontal surface of {:.0} cm² or more at {:.2}–{:.2} m",
                p.surfaces.min_area * 1e4,
                p.surfaces.height_range[0],
                p.surfaces.height_range[1]
            )));
        }
        Ok(unique)
    }

    /// Horizontal surfaces in the merged scene.
    pub(super) fn find(&self, scene: &[Vec3]) -> Vec<Surface> {
        let p = self.params;
        let cloud = self.reachable_heights(scene);
        let search = find_surfaces(&cloud, None, &p.surfaces, false);
        if self.trace {
            for t in &search.trials {
                tracing::debug!(
                    "place: plane of {} points at {:.2} m, tilt {:.2}: {:?} ({} points searched)",
                    t.points,
                    t.height,
                    t.tilt,
                    t.verdict,
                    cloud.points.len()
                );
            }
        }
        search
            .surfaces
            .into_iter()
            .filter(|s| s.area >= p.surfaces.min_area)
            .collect()
    }

    /// `surface` in the merged scene again after another look at it: the points within
    /// the refinement threshold of its plane, refined, split and checked as a search
    /// would (the plane needs no new search).
    pub(super) fn find_again(&self, scene: &[Vec3], surface: &Surface) -> Vec<Surface> {
        let p = self.params;
        let cloud = self.reachable_heights(scene);
        let keep: Vec<bool> = cloud
            .points
            .iter()
            .map(|q| surface.plane.distance(*q).abs() <= p.surfaces.refine_threshold)
            .collect();
        surfaces_on(&cloud, Some(&keep), surface.plane, &p.surfaces)
            .into_iter()
            .filter(|s| s.area >= p.surfaces.min_area)
            .collect()
    }

    /// The scene's points at heights a reachable surface can have. Gravity is known
    /// (the world frame), so the floor (most of a sweep) is not searched at all — the
    /// seed peeled it off plane by plane and then rejected it by height.
    pub(super) fn reachable_heights(&self, scene: &[Vec3]) -> PointCloud {
        let [lo, hi] = self.params.surfaces.height_range;
        PointCloud::unorganized(
            scene
                .iter()
                .copied()
                .filter(|q| q.z >= lo - 0.05 && q.z <= hi + 0.05)
                .collect(),
        )
    }

    pub(super) fn look_and_add(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        at: Vec3,
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        look_at(driver, at)?;
        let frame = driver.capture(&self.params.camera)?;
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let robot = self.robot;
        self.decide(|r| {
            let mut solids = robot_solids(&robot.model, &state.model_values(&robot.model), root);
            // The held object is the robot's too.
            if let Some(tool_link) = arm_gripper(robot, arm).map(|g| g.tool_link.as_str())
                && let Ok(world_from_tool) = tool_pose(robot, &state, root, tool_link)
                && let Some(points) = hull.as_convex_polyhedron().map(|c| c.points().to_vec())
                && let Some(solid) = Solid::convex_hull(&points)
            {
                solids.push(PlacedSolid {
                    world_from_solid: world_from_tool,
                    solid,
                });
            }
            let mut obs = r.params.observe.clone();
            obs.max_range = r.params.search_range;
            // Every other pixel: at a surface's range neighbouring pixels are a few
            // millimetres apart, well inside the search's centimetre leaf.
            let frame = tabula_robot::driver::CameraFrame {
                cloud: frame.cloud.decimated(r.params.search_decimate.max(1)),
                ..frame
            };
            // One point per search leaf is kept below, over every view at once.
            let seen = world_points_unthinned(&frame, &solids, &obs);
            let eye = frame.world_from_camera.translation;
            let range2 = r.params.edge_range * r.params.edge_range;
            // Neighbouring pixels often share a voxel: a run needs no hash lookups.
            let mut last = None;
            for q in seen {
                let key = tabula_geom::packed_voxel_key(q, r.params.search_leaf);
                if last.replace(key) == Some(key) {
                    continue;
                }
                if q.distance_squared(eye) <= range2 && r.near_keys.insert(key) {
                    r.near.push(q);
                }
                if r.scene_keys.insert(key) {
                    scene.push(q);
                }
            }
        });
        Ok(())
    }

    /// Tries the surfaces nearest first: a free spot, the base driven up to it if out
    /// of reach, then the placement.
    pub(super) fn try_surfaces(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        poses: &[Resting],
        surfaces: &[Surface],
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        let me = match self.prefer_near {
            Some(q) => q.truncate(),
            None => world_from_base(self.robot, driver)?.translation.truncate(),
        };
        let mut order: Vec<(f64, &Surface)> = surfaces
            .iter()
            .map(|s| (Outline::of(s).distance(me), s))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut last = PlaceError::NoRoom("no surface was tried".into());
        for (_, surface) in order {
            self.report.surface = Some(SurfaceReport {
                height: surface.centroid.z,
                centroid: surface.centroid.to_array(),
                area_m2: surface.area,
                tilt_deg: surface.plane.normal.angle_between(Vec3::Z).to_degrees(),
            });
            let target = Target {
                arm,
                hull,
                poses,
                surface,
            };
            match self.place_on(driver, target, scene) {
                Ok(()) => return Ok(()),
                Err(e @ PlaceError::Driver(_)) => return Err(e),
                Err(e) => {
                    self.report
                        .rejected
                        .push(format!("surface at {:.2} m: {e}", surface.centroid.z));
                    last = e;
                }
            }
        }
        Err(last)
    }
}
