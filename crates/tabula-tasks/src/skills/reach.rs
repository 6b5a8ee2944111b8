//! Choosing what to pick with which hand: for objects in order of preference, the first
//! grasp of any hand that no neighbour is in the way of, whose pre-grasp has
//! collision-free IK and whose straight lines down and up the arm can follow.

use super::hand::HandArm;
use super::pick::{PickMotion, first_reachable};
use super::world::{load_objects, without};
use super::{GraspCandidate, GraspPlanner};
use crate::scene::{SeenObject, Table};
use tabula_geom::Pose;
use tabula_motion::MoveGroup;
use tabula_robot::driver::JointState;
use tabula_robot::robots::NamedRobot;

/// A chosen pick: the hand (index into the hands), its group (the table and the other
/// objects in its world), the object, the grasp and its pre-grasp joint values.
pub struct Pick {
    pub hand: usize,
    pub group: MoveGroup,
    pub object: usize,
    pub grasp: GraspCandidate,
    pub ik: Vec<f64>,
}

/// The hands to choose from and how they grasp.
pub struct Picker<'a, P> {
    pub robot: &'a NamedRobot,
    pub hands: &'a [HandArm],
    /// A group whose settings (and allowed-collision matrix) every hand's group copies.
    pub template: &'a MoveGroup,
    pub planner: &'a P,
    pub motion: PickMotion,
    /// Clearance the open hand keeps from other objects (m).
    pub clearance: f64,
}

impl<P: GraspPlanner> Picker<'_, P> {
    /// The first of `order` (object indices) a hand can pick at the robot's `state`;
    /// `on` lists which object stands on which (those pairs do not block each other).
    pub fn choose(
        &self,
        state: &JointState,
        (table, objects, on): (&Table, &[SeenObject], &[(usize, usize)]),
        order: &[usize],
    ) -> Option<Pick> {
        let mut groups: Vec<Option<MoveGroup>> = (0..self.hands.len())
            .map(|k| self.group(k, state, table, objects))
            .collect();
        for &i in order {
            let skip = |a: usize| a == i || on.contains(&(a, i)) || on.contains(&(i, a));
            for (k, slot) in groups.iter_mut().enumerate() {
                let Some(group) = slot.as_mut() else { continue };
                let seed = group.arm_values(state);
                let hand = &self.hands[k].hand;
                let candidates =
                    self.planner
                        .candidates(&objects[i].grasp_target(), hand, table.up);
                let found = without(group, objects, &[i], |g| {
                    first_reachable(
                        g,
                        hand,
                        candidates,
                        (objects, &skip),
                        (table.up, self.motion, self.clearance),
                        &seed,
                    )
                });
                if let Some((grasp, ik)) = found {
                    let group = slot.take()?;
                    return Some(Pick {
                        hand: k,
                        group,
                        object: i,
                        grasp,
                        ik,
                    });
                }
            }
        }
        None
    }

    /// Hand `k`'s group at `state` with the table (down to the floor) and the objects'
    /// hulls in its world.
    fn group(
        &self,
        k: usize,
        state: &JointState,
        table: &Table,
        objects: &[SeenObject],
    ) -> Option<MoveGroup> {
        let mut group = self.template.for_arm(self.robot, &self.hands[k].arm).ok()?;
        group.set_state(self.robot, state).ok()?;
        group
            .add_object("table", table.prism()?, Pose::IDENTITY)
            .ok()?;
        load_objects(&mut group, objects);
        Some(group)
    }
}
