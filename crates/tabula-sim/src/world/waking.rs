//! Waking a sleeping pile without dropping it.
//!
//! When something touches a sleeping island, rapier wakes it inside the step, after
//! the narrow phase skipped the island's sleeping pairs: on that one step every body
//! of the island is integrated under gravity with no contact holding it up (measured
//! on pile seed 2: a finger coming down beside one object gave all 22 objects of the
//! pile 9.81 · dt = 8.2 cm/s downwards and no spin). The next step's contacts then
//! catch them, penetrating, and push them back up with a jolt that sets marginally
//! resting objects going: a can lying across two others rolled off its perch, across
//! the table and over the edge while the fingers went down 22 cm away. Nothing real
//! happens to a resting pile when a finger touches its far side.
//!
//! The fix: bodies asleep before a step and awake after it are put back where they
//! were and at rest, so they join the next step as they slept, with their contacts.
//! The one thing this delays by a step (1/120 s) is how a woken body answers the
//! touch that woke it; the touch's contact is still there on the next step.

use super::SimWorld;
use rapier3d_f64::prelude::RigidBodyHandle;
use tabula_geom::{Pose, Vec3};

impl SimWorld {
    /// The dynamic bodies asleep now, with their poses.
    pub(super) fn sleeping_bodies(&self) -> Vec<(RigidBodyHandle, Pose)> {
        self.physics
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic() && b.is_sleeping())
            .map(|(h, b)| (h, *b.position()))
            .collect()
    }

    /// Puts every body of `slept` that this step woke back where it slept, at rest.
    pub(super) fn undo_wake_fall(&mut self, slept: &[(RigidBodyHandle, Pose)]) {
        for &(h, pose) in slept {
            let Some(b) = self.physics.bodies.get_mut(h) else {
                continue;
            };
            if b.is_sleeping() {
                continue;
            }
            b.set_position(pose, false);
            b.set_linvel(Vec3::ZERO, false);
            b.set_angvel(Vec3::ZERO, false);
        }
    }
}
