//! Judging a tidying run: every object that stood on the table to clear should end
//! resting on another piece of furniture's top, and nothing that already stood there
//! may be knocked over or pushed aside.

use super::Judge;
use crate::world::EntityKind;
use crate::{SimError, SimWorld};
use tabula_geom::parry::bounding_volume::Aabb;
use tabula_geom::{Pose, Vec3};

/// An object's bottom within this of a top counts as resting on it (m).
const RESTING: f64 = 0.015;
/// Moved farther than this (m) or tilted more than [`TILTED_RAD`], an object that
/// already stood on a target surface was disturbed.
const DISTURBED: f64 = 0.02;
const TILTED_RAD: f64 = 0.17;

/// Where each object stood at the start, and on what.
#[derive(Debug, Clone)]
pub struct TidyStart {
    /// The furniture to clear.
    pub source: String,
    /// Objects and their poses, with the furniture each rested on.
    pub objects: Vec<(String, Pose, Option<String>)>,
}

/// What physics says about a tidying run.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct TidyVerdict {
    /// Objects that stood on the table to clear at the start.
    pub objects: usize,
    /// Of those, resting on another piece of furniture at the end.
    pub moved: usize,
    /// Still on the table to clear.
    pub left: usize,
    /// Neither (on the floor, in a gripper, nowhere at rest).
    pub lost: Vec<String>,
    /// Objects that stood on other furniture at the start and were moved more than
    /// 2 cm or tilted more than 10°.
    pub knocked: Vec<String>,
    /// Where each object of the table ended: (object, furniture it rests on).
    pub ended_on: Vec<(String, Option<String>)>,
}

/// The furniture whose top `bounds` (an object's) rests on, if any.
fn resting_on(tops: &[(String, Aabb)], bounds: &Aabb) -> Option<String> {
    let c = bounds.center();
    tops.iter()
        .find(|(_, t)| {
            c.x >= t.mins.x
                && c.x <= t.maxs.x
                && c.y >= t.mins.y
                && c.y <= t.maxs.y
                && (bounds.mins.z - t.maxs.z).abs() <= RESTING
        })
        .map(|(n, _)| n.clone())
}

/// Every part of every piece of furniture (a table's top, a shelf's boards) with the
/// furniture's name: objects rest on their tops.
fn tops(world: &SimWorld) -> Vec<(String, Aabb)> {
    world
        .furniture_shapes()
        .into_iter()
        .map(|(n, s, p)| (n, s.compute_aabb(&p)))
        .collect()
}

impl TidyStart {
    /// The objects of `world` (settled) and what each rests on; `source` names the
    /// furniture to clear.
    pub fn of(world: &SimWorld, source: &str) -> Result<Self, SimError> {
        let tops = tops(world);
        if world.entity(source).is_none()
            || !world
                .list(Some(EntityKind::Furniture))
                .iter()
                .any(|n| n == source)
        {
            return Err(SimError::UnknownEntity(source.into()));
        }
        let objects = world
            .object_poses()
            .into_iter()
            .map(|(n, p)| {
                let on = world.entity_bounds(&n).and_then(|b| resting_on(&tops, &b));
                (n, p, on)
            })
            .collect();
        Ok(Self {
            source: source.into(),
            objects,
        })
    }

    /// The verdict on `world` after the run (settle it first).
    pub fn verdict(&self, world: &SimWorld) -> TidyVerdict {
        let tops = tops(world);
        let mut v = TidyVerdict::default();
        for (name, start, on) in &self.objects {
            let now = world.pose(name).ok();
            let ends = world
                .entity_bounds(name)
                .and_then(|b| resting_on(&tops, &b));
            if on.as_deref() == Some(self.source.as_str()) {
                v.objects += 1;
                match &ends {
                    Some(f) if *f == self.source => v.left += 1,
                    Some(_) => v.moved += 1,
                    None => v.lost.push(name.clone()),
                }
                v.ended_on.push((name.clone(), ends));
            } else if on.is_some() {
                let disturbed = now.is_none_or(|p| {
                    let up = |q: &Pose| q.rotation * Vec3::Z;
                    p.translation.distance(start.translation) > DISTURBED
                        || up(&p).angle_between(up(start)) > TILTED_RAD
                });
                if disturbed {
                    v.knocked.push(name.clone());
                }
            }
        }
        v
    }
}

impl Judge for TidyStart {
    type Verdict = TidyVerdict;
    type Told = ();

    fn verdict(self, world: &SimWorld, (): ()) -> Result<TidyVerdict, SimError> {
        Ok(TidyStart::verdict(&self, world))
    }
}
