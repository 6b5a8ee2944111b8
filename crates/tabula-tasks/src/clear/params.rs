//! Clearing's parameters (SPEC §3.2 and §6, seed 002's repository, where it gives them),
//! loadable from TOML with the seed's defaults for what a file leaves out.

use super::{AtRisk, ClearError};
use crate::skills::carried::CarriedCheck;
use crate::skills::grasp::{Fallback, NarrowPartGrasps, TopGrasps};
use tabula_geom::input::{Validate, check_count, nested};
use tabula_motion::MoveGroupParams;
use tabula_perception::tabletop::TabletopParams;

/// Parameters of clearing (SPEC §3.2 and §6, seed 002's repository, where it gives them).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClearParams {
    pub tabletop: TabletopParams,
    pub motion: MoveGroupParams,
    /// The fixed camera that sees the table.
    pub camera: String,
    /// Frames are decimated to every `decimate`-th pixel of every `decimate`-th row (the
    /// Kinect's 320 × 240 mode for 2); the tabletop pipeline's point counts and pixel
    /// steps are scaled to match.
    pub decimate: usize,
    /// Self-filter padding (m), SPEC §1.1: 0.9 cm.
    pub self_filter_padding: f64,
    /// The closing point lies this far below the object's top (m): SPEC §3.2's "lowered
    /// by half the finger height" with SPEC §6's 6 cm fingers.
    pub grasp_depth: f64,
    /// Fingertips stay at least this far above what the object stands on (m), SPEC §6's
    /// push height 1 cm.
    pub fingertip_clearance: f64,
    /// Pre-grasp distance back along the approach (m), SPEC §3.2: 10 cm.
    pub pregrasp: f64,
    /// Lift after grasping along the table normal (m), SPEC §3.2: 20 cm.
    pub lift: f64,
    /// The held object's bottom is let go this far above the drop point (m).
    pub drop_clearance: f64,
    /// The gripper opening must exceed the object's width by this much on each side (m).
    pub grasp_margin: f64,
    /// A grasp leaving less than this on each side of the open fingers (m) is taken
    /// only where no roomier one holds the object ([`TopGrasps::snug_room`]). Not in
    /// the seed.
    pub grasp_snug_room: f64,
    /// Before a grasp the fingers open to the object's width plus this on each side (m),
    /// not fully: in clutter a finger 1 cm from the object fits gaps a fully opened one
    /// (the seed's 7 cm, SPEC §6) does not. Not in the seed; a value at least the
    /// gripper's opening restores the seed's full opening.
    pub pregrasp_gap: f64,
    /// A grasp may hold an object only this deep below its top (m) where that passes
    /// over lower neighbours a full-depth grasp would meet (tried after the full-depth
    /// ones). Not in the seed.
    pub shallow_grip: f64,
    /// Distance between the closed fingers and the object before a push (m), SPEC §6
    /// (the seed's code): 3 cm.
    pub push_distance: f64,
    /// Longest push (m), SPEC §6: 0.6 m.
    pub push_max_length: f64,
    /// Push sweep resolution (m), SPEC §6: 3 cm.
    pub push_resolution: f64,
    /// Seed's push length factor k (× the box size along the push), SPEC §6: 1.0 —
    /// used when no length makes the grasp free.
    pub push_factor: f64,
    /// Pushed a little past the point where the grasp becomes free (m).
    pub push_margin: f64,
    /// After a push the fingers back off this far (m) before rising.
    pub push_back_off: f64,
    /// What a push moves must end at least this far (m) from the table's edge ahead of
    /// it, beyond its half size: a pushed can rolls on after the fingers stop, a block
    /// slides. Not in the seed (its table had walls of clutter, not edges).
    pub push_edge_clearance: f64,
    /// Pre-push and post-push height above the push (m), SPEC §3.2: 20 cm.
    pub pre_push_height: f64,
    /// Clearance the predicates demand between the gripper or a moving hull and
    /// another object (m).
    pub clearance: f64,
    /// A pushed hull may overlap a neighbour by this much (m) and still slide past it:
    /// touching objects seen with noise overlap by a few millimetres from the start.
    pub sweep_tolerance: f64,
    /// An object counts as the same one across frames when it is this near where it was
    /// (or where a push should have put it) (m).
    pub track_radius: f64,
    /// Most objects a chain push may shove along.
    pub max_chain: usize,
    /// Chain pushes are tried this many times the box's size along the push long (the
    /// seed's k = 1 first).
    pub chain_push_factors: Vec<f64>,
    /// The last resort when neither the seed's actions nor chain pushes can go on
    /// (pairs blocking each other's grasp in a pile): a grasp whose open fingers reach
    /// at most this far (m) into neighbours' hulls, pushing them aside as they come
    /// down — VPG's grasps do. The neighbours it moves are handled by the action, as a
    /// chain push's are. Shallowest first, so a deeper one is taken only where no
    /// shallower one has IK. 8 mm left pile cores of 9–23 objects each blocking the
    /// next on the table (pile seeds 82, 98); 2 cm clears them. Not in the seed; 0
    /// gives up instead.
    pub nudge_depth: f64,
    /// After a lift, what the camera must see hanging with the hand, outside the held
    /// object, for the grasp to count as carrying another object along. Not in the
    /// seed (its bin stood away from the table's objects, nothing was lifted with
    /// another).
    pub carried: CarriedCheck,
    /// Which objects a plan's grasps take first: those held up or leaning.
    pub at_risk: AtRisk,
    /// Pushes allowed per tracked object.
    pub max_pushes_per_object: usize,
    /// Split pushes (one half of an object no grasp takes pushed away from the other:
    /// it may be two objects seen as one) allowed per tracked object, beyond
    /// `max_pushes_per_object`.
    /// One: where the first parts nothing the segment is one object, and a second only
    /// turns it again (limits seed 118: 11 actions with two, 8 with one). Not in the
    /// seed; 0 gives such objects up at once.
    pub max_split_pushes: usize,
    /// A split push moves the half past its own size and this much more (m), so two
    /// objects it parts are seen apart.
    pub split_gap: f64,
    /// A push that moved its object less than this share of its length was jammed: it
    /// is not tried that way again. Not in the seed.
    pub push_jam_share: f64,
    /// Grasp attempts per tracked object before its grasp counts as infeasible.
    pub max_grasp_attempts: usize,
    /// Frames in a row without a plan before giving up.
    pub max_no_plan_frames: usize,
    /// States one search may expand (each plan, each unreachable-goal test). A count, not
    /// a time, so a decision is the same on a loaded machine. Not in the seed, which
    /// ran Fast Downward without a limit; greedy search takes 26,000 (0.7 s) on the pile
    /// suite's hardest frame, where the old 1 s limit failed under load.
    pub plan_max_expanded: usize,
    /// Wall time per search (s): a safety net far above what `plan_max_expanded` takes.
    pub plan_timeout_s: f64,
    /// Optimal (A* + LM-cut) plans up to this many objects, greedy plans above. The seed
    /// planned every frame with Fast Downward; 10 here until greedy search was measured
    /// wandering 26,000 states on pile frames that A* solves in 40.
    pub optimal_up_to: usize,
    /// States A* may expand before the frame is planned greedily instead (within
    /// `plan_max_expanded`). Not in the seed.
    pub optimal_max_expanded: usize,
    /// IK restarts for the feasibility check of the first action.
    pub ik_attempts: usize,
}

impl ClearParams {
    /// Every length finite and in range, every step positive: a zero resolution or an
    /// infinite push would make the sweeps endless.
    pub fn validate(&self) -> Result<(), ClearError> {
        let positive = [
            ("push_resolution", self.push_resolution),
            ("push_max_length", self.push_max_length),
            ("push_factor", self.push_factor),
            ("plan_timeout_s", self.plan_timeout_s),
            ("track_radius", self.track_radius),
        ];
        let non_negative = [
            ("self_filter_padding", self.self_filter_padding),
            ("grasp_depth", self.grasp_depth),
            ("fingertip_clearance", self.fingertip_clearance),
            ("pregrasp", self.pregrasp),
            ("lift", self.lift),
            ("drop_clearance", self.drop_clearance),
            ("grasp_margin", self.grasp_margin),
            ("grasp_snug_room", self.grasp_snug_room),
            ("pregrasp_gap", self.pregrasp_gap),
            ("shallow_grip", self.shallow_grip),
            ("push_distance", self.push_distance),
            ("push_margin", self.push_margin),
            ("push_back_off", self.push_back_off),
            ("push_edge_clearance", self.push_edge_clearance),
            ("pre_push_height", self.pre_push_height),
            ("clearance", self.clearance),
            ("sweep_tolerance", self.sweep_tolerance),
            ("push_jam_share", self.push_jam_share),
            ("nudge_depth", self.nudge_depth),
            ("split_gap", self.split_gap),
            ("carried.margin", self.carried.margin),
            ("carried.reach", self.carried.reach),
            ("at_risk.held_up", self.at_risk.held_up),
            ("at_risk.lean_rise", self.at_risk.lean_rise),
            ("at_risk.lean_slope", self.at_risk.lean_slope),
            ("at_risk.perched", self.at_risk.perched),
            ("at_risk.touch", self.at_risk.touch),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0 && v <= 100.0) {
                return Err(ClearError::Params(format!(
                    "`{name}` = {v}: must be in (0, 100]"
                )));
            }
        }
        for (name, v) in non_negative {
            if !(v.is_finite() && (0.0..=10.0).contains(&v)) {
                return Err(ClearError::Params(format!(
                    "`{name}` = {v}: must be in [0, 10]"
                )));
            }
        }
        if self.push_max_length / self.push_resolution > 10_000.0 {
            return Err(ClearError::Params(
                "`push_max_length` / `push_resolution` over 10,000 steps".into(),
            ));
        }
        if !(1..=100_000).contains(&self.carried.min_points) {
            return Err(ClearError::Params(format!(
                "`carried.min_points` = {}: must be 1 to 100,000",
                self.carried.min_points
            )));
        }
        if !(1..=16).contains(&self.decimate) {
            return Err(ClearError::Params(format!(
                "`decimate` = {}: must be 1 to 16",
                self.decimate
            )));
        }
        if let Some(f) = self
            .chain_push_factors
            .iter()
            .find(|f| !(f.is_finite() && **f > 0.0 && **f <= 100.0))
        {
            return Err(ClearError::Params(format!(
                "`chain_push_factors` holds {f}: each must be in (0, 100]"
            )));
        }
        Ok(())
    }
}

impl Default for ClearParams {
    fn default() -> Self {
        let mut motion = MoveGroupParams::default();
        // Pushes run the fingertips 1 cm above the table (SPEC §6).
        motion.world.padding = 0.008;
        // A push or a descent may leave its line by a few millimetres where the arm
        // cannot follow it exactly (the near-line fallback of the move group).
        motion.cartesian_tolerance = 0.005;
        Self {
            // The overhead camera is 1 m above the table: a tile standing on edge 1 cm
            // thick shows ~150 points at full resolution, under SPEC §6's 200 (made for
            // seed 002's head camera); 100 keeps it (2.6 cm² seen at 1 m). Measured on
            // every clearing family: no suite lost an object, blocks 92.1 → 96.2 %.
            tabletop: TabletopParams {
                min_object_points: 100,
                ..TabletopParams::default()
            },
            motion,
            camera: "overhead".into(),
            decimate: 2,
            self_filter_padding: 0.009,
            grasp_depth: 0.03,
            fingertip_clearance: 0.01,
            pregrasp: 0.10,
            lift: 0.20,
            drop_clearance: 0.08,
            grasp_margin: 0.0,
            grasp_snug_room: 0.0015,
            pregrasp_gap: 0.01,
            shallow_grip: 0.02,
            push_distance: 0.03,
            push_max_length: 0.6,
            push_resolution: 0.03,
            push_factor: 1.0,
            push_margin: 0.02,
            push_back_off: 0.015,
            push_edge_clearance: 0.12,
            pre_push_height: 0.20,
            clearance: 0.004,
            sweep_tolerance: 0.005,
            track_radius: 0.06,
            max_chain: 4,
            chain_push_factors: vec![1.0, 1.6, 2.2],
            nudge_depth: 0.02,
            carried: CarriedCheck::default(),
            at_risk: AtRisk::default(),
            max_pushes_per_object: 3,
            max_split_pushes: 1,
            split_gap: 0.03,
            push_jam_share: 0.35,
            max_grasp_attempts: 2,
            max_no_plan_frames: 3,
            plan_max_expanded: 100_000,
            plan_timeout_s: 30.0,
            optimal_up_to: 64,
            optimal_max_expanded: 1_000,
            ik_attempts: 40,
        }
    }
}

impl Validate for ClearParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.tabletop.check(&nested(at, "tabletop"))?;
        self.motion.check(&nested(at, "motion"))?;
        check_count(at, "decimate", self.decimate, 1)?;
        check_count(at, "plan_max_expanded", self.plan_max_expanded, 1)?;
        check_count(at, "optimal_max_expanded", self.optimal_max_expanded, 1)?;
        ClearParams::validate(self).map_err(|e| e.to_string())
    }
}

impl ClearParams {
    /// The grasp planners clearing uses, from its grasp parameters: whole objects from
    /// above (full depth, then shallow), else their narrow parts.
    pub fn grasp_planner(&self) -> Fallback<TopGrasps, NarrowPartGrasps> {
        let top = TopGrasps {
            depth: self.grasp_depth,
            fingertip_clearance: self.fingertip_clearance,
            margin: self.grasp_margin,
            snug_room: self.grasp_snug_room,
            pregrasp_gap: self.pregrasp_gap,
            shallow_grip: self.shallow_grip,
        };
        Fallback(top, NarrowPartGrasps { top })
    }

    /// How this run looks at the table.
    pub fn observer(&self) -> crate::scene::Observer<'_> {
        crate::scene::Observer::new(
            &self.camera,
            self.decimate,
            self.self_filter_padding,
            &self.tabletop,
        )
    }
}
