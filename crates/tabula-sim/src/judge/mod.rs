//! Judges: what physics says a task achieved, from ground truth the task never sees —
//! one file per task, behind [`Judge`], and one judged run ([`run`]) for any of them.
//! Only tests, reports and benchmarks read verdicts; no decision does.

pub mod clear;
pub mod pick_place;
pub mod place;
pub mod tidy;

pub use clear::{ClearJudge, ClearSetup, ClearVerdict};
pub use pick_place::{PlaceTolerance, PlaceVerdict, PlacementJudge, judge_placement};
pub use place::{StablePlaceJudge, StablePlaceTolerance, StablePlaceVerdict};
pub use tidy::{TidyStart, TidyVerdict};

use crate::SimDriver;
use crate::world::{EntityKind, SimError, SimWorld};
use std::sync::{Arc, Mutex};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::{Pose, Vec3};

/// A judge of one task's run: made from the settled world before it (ground truth),
/// watching its physics steps and told its moments, giving a verdict on the settled
/// world after it.
pub trait Judge {
    type Verdict;
    /// What the task tells the judge when it ends (placing: the tool pose it planned
    /// with the object resting; others: nothing).
    type Told;
    /// Starts watching every physics step of the run (contacts, a release).
    fn watch(&mut self, _driver: &mut SimDriver) {}
    /// A moment of the task: `Some((target, shoved))` before an action (where the object
    /// it acts on and those it shoves along were seen), `None` after it.
    fn moment(&mut self, _world: &SimWorld, _moment: Option<(Vec3, Vec<Vec3>)>) {}
    /// The verdict on the world after the run (settled).
    fn verdict(self, world: &SimWorld, told: Self::Told) -> Result<Self::Verdict, SimError>;
}

/// The judge's hook a task is handed: see [`Judge::moment`].
pub type Hook<'a> = dyn FnMut(&mut SimDriver, Option<(Vec3, Vec<Vec3>)>) + 'a;

/// Runs `task` on robot `robot` of `world` (settled first) through a [`SimDriver`]
/// (camera noise from `seed`), judged by the judge `judge` makes of the settled world;
/// the task's answer, the verdict and the world afterwards.
pub fn run<J: Judge, R>(
    mut world: SimWorld,
    robot: &str,
    seed: u64,
    judge: impl FnOnce(&SimWorld) -> Result<J, SimError>,
    task: impl FnOnce(&mut SimDriver, &mut Hook<'_>) -> (R, J::Told),
) -> Result<(R, J::Verdict, SimWorld), SimError> {
    world.settle();
    let mut judge = judge(&world)?;
    let mut driver = SimDriver::new(world, robot, seed)?;
    judge.watch(&mut driver);
    let (answer, told) = task(&mut driver, &mut |d, m| judge.moment(&d.world, m));
    let mut world = driver.world;
    world.settle();
    let verdict = judge.verdict(&world, told)?;
    Ok((answer, verdict, world))
}

/// Records every robot–furniture contact deeper than 1 mm; hand [`Self::observer`] to
/// [`crate::SimDriver::observe`] so every physics step of a motion is checked.
#[derive(Debug, Clone, Default)]
pub struct ContactWatch {
    pub contacts: Arc<Mutex<Vec<(String, String)>>>,
}

impl ContactWatch {
    pub fn observer(&self, robot: &str) -> impl FnMut(&SimWorld) + Send + 'static {
        let contacts = self.contacts.clone();
        let robot = robot.to_string();
        move |w: &SimWorld| {
            if let Ok(found) = w.robot_contacts(&robot, &[EntityKind::Furniture], 1e-3)
                && let Ok(mut c) = contacts.lock()
            {
                for pair in found {
                    if !c.contains(&pair) {
                        if tracing::enabled!(tracing::Level::DEBUG) {
                            tracing::debug!(
                                "contact at t = {:.2} s: {pair:?} at {:?}",
                                w.time(),
                                w.pose(&pair.0).map(|p| p.translation)
                            );
                        }
                        c.push(pair);
                    }
                }
            }
        }
    }

    pub fn seen(&self) -> Vec<(String, String)> {
        self.contacts.lock().map(|c| c.clone()).unwrap_or_default()
    }
}

/// The bounds of every part of a piece of furniture.
pub fn furniture_bounds(world: &SimWorld, name: &str) -> Option<Aabb> {
    world
        .furniture_shapes()
        .into_iter()
        .filter(|(n, _, _)| n == name)
        .map(|(_, s, p)| s.compute_aabb(&p))
        .reduce(|a, b| a.merged(&b))
}

/// Over the footprint of `bounds` and above its top.
pub(crate) fn above(bounds: &Aabb, p: Vec3) -> bool {
    p.x >= bounds.mins.x
        && p.x <= bounds.maxs.x
        && p.y >= bounds.mins.y
        && p.y <= bounds.maxs.y
        && p.z > bounds.maxs.z
}

/// The object (among `before`, everything's poses at the start) nearest `point`.
pub fn nearest_object(before: &[(String, Pose)], point: Vec3) -> Option<(String, Pose)> {
    before
        .iter()
        .min_by(|a, b| {
            (a.1.translation - point)
                .length()
                .total_cmp(&(b.1.translation - point).length())
        })
        .map(|(n, p)| (n.clone(), *p))
}
