//! Judging a clearing run: which objects the arm touched besides the one it acted on,
//! which it moved by accident, and which ended in the bin.

use super::{Judge, above, furniture_bounds, nearest_object};
use crate::SimDriver;
use crate::world::{EntityKind, SimError, SimWorld};
use std::sync::{Arc, Mutex};
use tabula_geom::parry::bounding_volume::Aabb;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};

/// Ground truth of a table-clearing run: which objects the arm touched besides the one
/// it was acting on, which it moved by accident, and which ended in the bin.
#[derive(Debug, Clone)]
pub struct ClearJudge {
    /// The table's bounds: only objects standing on it can be disturbed.
    table: Aabb,
    /// The objects the current action is meant for (the one it acts on, those it
    /// shoves along).
    target: Arc<Mutex<Vec<String>>>,
    /// Arm (or held object) – object contacts with anything but the target.
    contacts: Arc<Mutex<Vec<(String, String)>>>,
    /// How many of `contacts` were recorded before the current action.
    action_start: Arc<Mutex<usize>>,
    before: Vec<(String, Pose)>,
    /// Objects the current action shoves along on purpose.
    shoved: Vec<String>,
    /// Objects (other than the target) moved more than 2 cm by an action, per action.
    pub disturbed: Vec<String>,
    /// The robot watched, the objects on the table at the start and the bin to end in.
    robot: String,
    start: Vec<String>,
    bin: String,
}

/// The judged outcome of a clearing run.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ClearVerdict {
    /// Objects on the table at the start (above the table top, over its outline: an
    /// object overhanging the edge counts).
    pub objects: usize,
    /// Of those, how many rest inside the bin at the end.
    pub in_bin: usize,
    /// Of those, how many are still on the table.
    pub left_on_table: usize,
    /// Of those, how many are neither: knocked or dropped off the table.
    #[serde(default)]
    pub off_table: usize,
    /// Arm–object contacts with objects other than the target, as (link, object).
    pub collisions: Vec<(String, String)>,
    /// Objects moved more than 2 cm by an action not meant for them.
    pub disturbed: Vec<String>,
}

impl ClearJudge {
    /// A judge of `robot` clearing the furniture `table` of `world` into `bin`.
    pub fn new(
        world: &SimWorld,
        robot: &str,
        (table, bin): (&str, &str),
    ) -> Result<Self, SimError> {
        furniture_bounds(world, bin).ok_or_else(|| SimError::UnknownEntity(bin.into()))?;
        let table =
            furniture_bounds(world, table).ok_or_else(|| SimError::UnknownEntity(table.into()))?;
        Ok(Self {
            robot: robot.into(),
            start: objects_on(world, &table),
            bin: bin.into(),
            table,
            target: Arc::default(),
            contacts: Arc::default(),
            action_start: Arc::default(),
            before: Vec::new(),
            shoved: Vec::new(),
            disturbed: Vec::new(),
        })
    }

    /// Records every robot–object contact deeper than 1 mm with an object that is not
    /// the current target; hand it to [`crate::SimDriver::observe`].
    ///
    /// Only objects standing on the table count: a held object landing on those already
    /// in the bin touches nothing it should not. Nor does an object the hand takes count
    /// against what it already leaned on or touched (within 2 mm) when the fingers
    /// closed on it (in a pile, most objects rest against others): those pairs are
    /// excused while it is held; anything it meets afterwards counts. What the hand
    /// takes is handled by the action, whichever object the action was named for: the
    /// fingers' contacts with it on the way down are not collisions.
    pub fn observer(&self, robot: &str) -> impl FnMut(&SimWorld) + Send + 'static {
        let contacts = self.contacts.clone();
        let action_start = self.action_start.clone();
        let target = self.target.clone();
        let robot = robot.to_string();
        let table = self.table;
        let mut held: Vec<String> = Vec::new();
        let mut excused: Vec<(String, String)> = Vec::new();
        move |w: &SimWorld| {
            let Ok(mut found) = w.robot_contacts(&robot, &[EntityKind::Object], 1e-3) else {
                return;
            };
            let now = w.held_objects(&robot);
            excused.retain(|(h, _)| now.contains(h));
            for h in now.iter().filter(|h| !held.contains(h)) {
                excused.extend(w.objects_near(h, 2e-3).into_iter().map(|o| (h.clone(), o)));
                if let Ok(mut t) = target.lock()
                    && !t.contains(h)
                {
                    t.push(h.clone());
                }
                let start = action_start.lock().map(|s| *s).unwrap_or(usize::MAX);
                if let Ok(mut c) = contacts.lock() {
                    let mut k = 0;
                    c.retain(|(_, o)| {
                        k += 1;
                        k <= start || o != h
                    });
                }
            }
            held = now;
            found.retain(|pair| !excused.contains(pair));
            found.retain(|(_, o)| w.pose(o).is_ok_and(|p| above(&table, p.translation)));
            let target = target.lock().map(|t| t.clone()).unwrap_or_default();
            if let Ok(mut c) = contacts.lock() {
                for pair in found {
                    if !target.contains(&pair.1) && !c.contains(&pair) {
                        if tracing::enabled!(tracing::Level::DEBUG) {
                            tracing::debug!(
                                "contact at t = {:.2} s: {pair:?} (target {target:?})",
                                w.time()
                            );
                        }
                        c.push(pair);
                    }
                }
            }
        }
    }

    /// An action on the object nearest `position` begins.
    ///
    /// Objects seen at `shoved` are moved on purpose (a push that shoves them along):
    /// they are handled too — neither disturbed nor touched by accident.
    pub fn before(&mut self, world: &SimWorld, position: Vec3, shoved: &[Vec3]) {
        let t = self.table;
        self.before = world
            .object_poses()
            .into_iter()
            .filter(|(_, p)| above(&t, p.translation))
            .collect();
        let target = nearest_object(&self.before, position).map(|(n, _)| n);
        self.shoved = shoved
            .iter()
            .filter_map(|&p| nearest_object(&self.before, p).map(|(n, _)| n))
            .collect();
        if let Ok(mut t) = self.target.lock() {
            *t = target
                .into_iter()
                .chain(self.shoved.iter().cloned())
                .collect();
        }
        if let (Ok(mut s), Ok(c)) = (self.action_start.lock(), self.contacts.lock()) {
            *s = c.len();
        }
    }

    /// The action ended: objects other than its target that moved more than 2 cm.
    pub fn after(&mut self, world: &SimWorld) {
        let target = self.target.lock().map(|t| t.clone()).unwrap_or_default();
        for (name, pose) in &self.before {
            if target.contains(name) {
                continue;
            }
            let Ok(now) = world.pose(name) else {
                continue;
            };
            if (now.translation - pose.translation).length() > 0.02 {
                tracing::debug!(
                    "judge: {name} moved from {:.3?} to {:.3?} by an action on another",
                    pose.translation,
                    now.translation
                );
                if !self.disturbed.contains(name) {
                    self.disturbed.push(name.clone());
                }
            }
        }
        if let Ok(mut t) = self.target.lock() {
            t.clear();
        }
    }

    /// Counts the objects that stood on the table at the start and now rest inside
    /// the bin (over its footprint, on its floor or on what lies in it).
    pub fn verdict_on(&self, world: &SimWorld) -> ClearVerdict {
        let Some(b) = furniture_bounds(world, &self.bin) else {
            return ClearVerdict::default();
        };
        let in_bin = |p: Vec3| {
            p.x >= b.mins.x
                && p.x <= b.maxs.x
                && p.y >= b.mins.y
                && p.y <= b.maxs.y
                && p.z > b.mins.z
        };
        let on_table = objects_on(world, &self.table);
        let mut v = ClearVerdict {
            objects: self.start.len(),
            collisions: self.contacts.lock().map(|c| c.clone()).unwrap_or_default(),
            disturbed: self.disturbed.clone(),
            ..ClearVerdict::default()
        };
        for name in &self.start {
            match world.pose(name) {
                Ok(p) if in_bin(p.translation) => v.in_bin += 1,
                Ok(_) if on_table.contains(name) => v.left_on_table += 1,
                _ => v.off_table += 1,
            }
        }
        v
    }
}

/// The objects standing on a table: the middle of their bounds above its top, the
/// bounds over its outline (a prism's own origin may lie on its base).
fn objects_on(world: &SimWorld, table: &Aabb) -> Vec<String> {
    world
        .object_poses()
        .into_iter()
        .filter(|(name, _)| {
            world.entity_bounds(name).is_some_and(|o| {
                o.center().z > table.maxs.z
                    && o.maxs.x >= table.mins.x
                    && o.mins.x <= table.maxs.x
                    && o.maxs.y >= table.mins.y
                    && o.mins.y <= table.maxs.y
            })
        })
        .map(|(name, _)| name)
        .collect()
}

impl Judge for ClearJudge {
    type Verdict = ClearVerdict;
    type Told = ();

    fn watch(&mut self, driver: &mut SimDriver) {
        driver.observe(self.observer(&self.robot.clone()));
    }

    fn moment(&mut self, world: &SimWorld, moment: Option<(Vec3, Vec<Vec3>)>) {
        match moment {
            Some((target, shoved)) => self.before(world, target, &shoved),
            None => self.after(world),
        }
    }

    fn verdict(self, world: &SimWorld, (): ()) -> Result<ClearVerdict, SimError> {
        Ok(self.verdict_on(world))
    }
}

/// What the simulator tells a clearing task about its workcell (as a real cell's
/// configuration would): where the bin's opening is, how far around its centre objects
/// may be let go, and the furniture as known obstacles.
pub struct ClearSetup {
    pub drop_point: Vec3,
    pub drop_spread: f64,
    pub obstacles: Vec<(String, SharedShape, Pose)>,
}

impl ClearSetup {
    /// What a clearing task is told of `world`'s workcell: where over `bin` to let
    /// go, and the furniture as known obstacles.
    pub fn of(world: &SimWorld, bin: &str) -> Result<Self, SimError> {
        let b = furniture_bounds(world, bin).ok_or_else(|| SimError::UnknownEntity(bin.into()))?;
        let (c, half) = (b.center(), b.half_extents());
        Ok(Self {
            drop_point: Vec3::new(c.x, c.y, b.maxs.z),
            // A hand's width inside the walls.
            drop_spread: (half.x.min(half.y) - 0.1).max(0.0),
            obstacles: world.workcell_shapes(),
        })
    }
}
