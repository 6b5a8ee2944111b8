//! What a clearing run reports: every frame's decision time, every action, the totals.

use serde::Serialize;

/// One executed action.
#[derive(Debug, Clone, Serialize)]
pub struct ActionRecord {
    pub frame: usize,
    pub action: String,
    /// Tracked object id.
    pub object: usize,
    /// Where the object was seen (world, footprint centre at mid-height).
    pub position: [f64; 3],
    /// For pushes: the direction (world, unit) and length (m).
    pub push: Option<([f64; 2], f64)>,
    /// For chain pushes: where the objects it shoves along were seen.
    pub shoves: Vec<[f64; 3]>,
    pub ok: bool,
    pub error: Option<String>,
}

/// Where the decision time of one frame went (CPU ms).
#[derive(Debug, Clone, Default, Serialize)]
pub struct FrameReport {
    pub objects: usize,
    pub perception_ms: f64,
    pub predicates_ms: f64,
    pub planning_ms: f64,
    pub ik_ms: f64,
    /// Frame in → first action chosen.
    pub decision_ms: f64,
    pub plan: Vec<String>,
    pub ik_backtracks: usize,
}

/// Median, 95th percentile and maximum (the IK benchmark's summary).
pub use tabula_robot::ik::bench::Spread as Stats;

/// The metrics of a run (issue "Clearing a cluttered table", item 6); `collisions` and
/// accidental moves are judged by whoever watches the world (the simulator's harness).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ClearReport {
    /// Objects seen in the first frame.
    pub objects: usize,
    /// Objects grasped and let go over the drop point.
    pub removed: usize,
    pub actions: usize,
    pub grasps: usize,
    pub failed_grasps: usize,
    pub pushes: usize,
    pub no_plan_frames: usize,
    pub ik_backtracks: usize,
    /// Pushes of an object against the direction it was pushed before.
    pub push_loops: usize,
    /// Objects the planner found it can never remove (they left the goal).
    pub dropped_from_goal: usize,
    pub decision_ms: Stats,
    /// Median CPU ms of each part of a decision.
    pub perception_ms: f64,
    pub predicates_ms: f64,
    pub planning_ms: f64,
    pub ik_ms: f64,
    /// Why the loop ended.
    pub stop: String,
    /// The objects the last frame saw when the loop ended, each with why it stays
    /// (empty when the table was cleared).
    pub left: Vec<super::LeftObject>,
    pub frames: Vec<FrameReport>,
    pub log: Vec<ActionRecord>,
}

impl ClearReport {
    /// Fills the summary (decision spread, median of each part) from the frames.
    pub(super) fn summarise(&mut self) {
        let decisions: Vec<f64> = self.frames.iter().map(|f| f.decision_ms).collect();
        self.decision_ms = Stats::of(&decisions);
        let median = |f: fn(&FrameReport) -> f64| {
            Stats::of(&self.frames.iter().map(f).collect::<Vec<_>>()).median
        };
        self.perception_ms = median(|f| f.perception_ms);
        self.predicates_ms = median(|f| f.predicates_ms);
        self.planning_ms = median(|f| f.planning_ms);
        self.ik_ms = median(|f| f.ik_ms);
    }
}
