//! The run: what placing carries from stage to stage, and its loop.

use super::body::{heading, holding_arm, retry_behind, world_from_base};
use super::model::Resting;
use super::{PlaceError, PlaceParams, PlaceReport, PlaceRequest};
use crate::skills::Phase;
use std::time::Instant;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveGroup;
use tabula_motion::group::thread_cpu;
use tabula_perception::surfaces::Surface;
use tabula_robot::driver::{JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// A spot the object may go: the tool pose that puts it there resting.
#[derive(Debug, Clone, Copy)]
pub(super) struct Spot {
    pub(super) world_from_tool: Pose,
    pub(super) score: f64,
}

/// A free spot on a surface: (stable pose index, world position of the footprint
/// origin, yaw in the world, clearance), as the free-space search ranks them.
pub(super) type FreeSpot = (usize, Vec3, f64, f64);

/// What is being placed and where: the arm holding it, the held object's hull (tool
/// frame), its usable stable poses, and the surface tried.
#[derive(Clone, Copy)]
pub(super) struct Target<'a> {
    pub(super) arm: &'a str,
    pub(super) hull: &'a SharedShape,
    pub(super) poses: &'a [Resting],
    pub(super) surface: &'a Surface,
}

pub(super) struct Run<'a> {
    pub(super) robot: &'a NamedRobot,
    pub(super) params: &'a PlaceParams,
    pub(super) report: PlaceReport,
    pub(super) decision_cpu: f64,
    /// CPU of the scan's own processing (Alg. 1), which the decision leaves out.
    pub(super) scan_cpu: f64,
    pub(super) trace: bool,
    /// The first move group: its allowed-collision matrix is sampled once per robot
    /// (MoveIt keeps it in the SRDF), so it is setup, not part of a decision.
    pub(super) template: Option<MoveGroup>,
    /// The voxels the scene already has a point in.
    pub(super) scene_keys: rustc_hash::FxHashSet<u64>,
    /// The scene's points seen from within `edge_range`, one per voxel.
    pub(super) near: Vec<Vec3>,
    pub(super) near_keys: rustc_hash::FxHashSet<u64>,
    /// How far from the tool frame what the hand holds reaches (m): the protective
    /// sphere while scanning, then the larger of it and the model.
    pub(super) held_reach: f64,
    /// Surfaces nearest this point are tried first (the request's `near`).
    pub(super) prefer_near: Option<Vec3>,
}

impl Run<'_> {
    /// Adds seen points to the scene, one per search-leaf voxel: views overlap, and
    /// every later step (surface search, free space, occupancy) works on the scene.
    pub(super) fn add_scene(&mut self, scene: &mut Vec<Vec3>, points: Vec<Vec3>) {
        for q in points {
            if self
                .scene_keys
                .insert(tabula_geom::packed_voxel_key(q, self.params.search_leaf))
            {
                scene.push(q);
            }
        }
    }

    /// A move group for `arm` at `state`, without world objects.
    pub(super) fn group(
        &mut self,
        arm: &str,
        state: &JointState,
        root: Pose,
    ) -> Result<MoveGroup, PlaceError> {
        let robot = self.robot;
        if self.template.is_none() {
            self.template = Some(MoveGroup::new(
                robot,
                arm,
                state,
                root,
                self.params.motion.clone(),
            )?);
        }
        let t = self.template.as_ref().ok_or(PlaceError::NotHolding)?;
        let mut g = t.for_arm(robot, arm)?;
        g.set_state(robot, state)?;
        Ok(g)
    }

    pub(super) fn mark(&self, what: &str) {
        if self.trace {
            tracing::debug!("place: {what}");
        }
    }

    /// Runs `f` as a named stage (wall-clock ms; CPU counted by the caller).
    pub(super) fn phase<T>(
        &mut self,
        name: &str,
        f: impl FnOnce(&mut Self) -> Result<T, PlaceError>,
    ) -> Result<T, PlaceError> {
        let (t0, cpu0) = (Instant::now(), self.decision_cpu);
        self.mark(&format!("phase {name}"));
        let out = f(self);
        tracing::info!(
            phase = name,
            ms = t0.elapsed().as_secs_f64() * 1e3,
            decision_cpu_ms = (self.decision_cpu - cpu0) * 1e3,
            ok = out.is_ok(),
            "place"
        );
        self.report.phases.push(Phase {
            name: name.into(),
            ms: t0.elapsed().as_secs_f64() * 1e3,
            ok: out.is_ok(),
            // The decision CPU spent in this stage.
            plan_ms: Some((self.decision_cpu - cpu0) * 1e3),
        });
        if let Err(e) = &out {
            self.mark(&format!("{name} failed: {e}"));
        }
        out
    }

    /// Runs CPU work counted toward the decision.
    pub(super) fn decide<T>(&mut self, f: impl FnOnce(&mut Self) -> T) -> T {
        let c0 = thread_cpu();
        let out = f(self);
        self.decision_cpu += thread_cpu() - c0;
        out
    }

    pub(super) fn run(
        &mut self,
        driver: &mut impl RobotDriver,
        request: &PlaceRequest,
    ) -> Result<(), PlaceError> {
        let robot = self.robot;
        let state = driver.joint_state()?;
        let arm = match &request.arm {
            Some(a) => {
                robot
                    .description
                    .arm(a)
                    .map_err(|e| PlaceError::Driver(e.to_string()))?;
                a.clone()
            }
            None => holding_arm(robot, &state).ok_or(PlaceError::NotHolding)?,
        };
        self.report.arm = Some(arm.clone());
        if self.params.raise_torso {
            self.phase("raise torso", |_| {
                crate::torso::raise_torso(driver, robot)?;
                Ok(())
            })?;
        }
        // ---- Object modelling (Alg. 1): scanning, not deciding.
        let c0 = self.decision_cpu;
        let modelled = self.phase("model object", |r| r.model_object(driver, &arm));
        self.scan_cpu += self.decision_cpu - c0;
        let (model, seen) = modelled?;
        driver.annotate("scanned the object in the hand");
        // ---- Stable poses (Algs 2–7) with the gripper clear of the surface.
        let poses = self.phase("stable poses", |r| {
            r.decide(|r| r.stable_poses(&arm, &model))
        })?;
        let hull = SharedShape::convex_hull(&model)
            .ok_or_else(|| PlaceError::Model("the scan has no solid hull".into()))?;
        // ---- Carry the object out of the camera's way, then look for surfaces.
        self.phase("carry", |r| r.carry(driver, &arm, &hull, &seen))?;
        driver.annotate("carrying it out of the camera's view");
        let mut scene = seen;
        let mut turned = false;
        loop {
            let found = self
                .phase("surface search", |r| {
                    r.search_surfaces(driver, &arm, &hull, &mut scene, &request.not_on)
                })
                .and_then(|surfaces| {
                    driver.annotate(&format!("found {} surface(s)", surfaces.len()));
                    self.report.surfaces_found = self.report.surfaces_found.max(surfaces.len());
                    self.try_surfaces(driver, &arm, &hull, &poses, &surfaces, &mut scene)
                });
            match found {
                Ok(()) => return Ok(()),
                Err(e) if self.params.turn_around && !turned && retry_behind(&e) => {
                    // Nothing usable in front: turn around and look behind.
                    turned = true;
                    let base = world_from_base(robot, driver)?;
                    let heading = heading(&base) + std::f64::consts::PI;
                    self.phase("turn around", |_| {
                        driver.drive_to(base.translation.x, base.translation.y, heading)?;
                        Ok(())
                    })?;
                }
                Err(e) => return Err(e),
            }
        }
    }
}
