//! `bench perception` as one measurement: every stage timed on the nine-object frame,
//! its quality against the labels, and the generated suite's frames one by one.

use super::{StageTime, SuiteRow, Timer, frame, quality, stage_times, suite_row};
use crate::stats::median;
use anyhow::Result;
use tabula_perception::TabletopParams;
use tabula_perception::eval::Score;
use tabula_sim::generate::TabletopLayout;

/// What `bench perception` measured.
pub struct PerceptionBench {
    pub scenes: u64,
    pub reps: usize,
    pub stages: Vec<StageTime>,
    pub reference: Score,
    pub valid_points: usize,
    pub suite: Vec<SuiteRow>,
}

impl PerceptionBench {
    /// Times every stage `reps` times on the nine-object frame, then runs the suite's
    /// `scenes` frames (at most 5 repetitions each), calling `tick` after each.
    pub fn run(scenes: u64, reps: usize, tick: &mut dyn FnMut()) -> Result<Self> {
        let timer = Timer::new(reps)?;
        let params = TabletopParams::default();
        let nine = frame(0, &TabletopLayout::nine())?;
        let (stages, valid_points) = stage_times(&nine, &params, &timer)?;
        let reference = quality(&nine, &params)?;
        let suite_timer = timer.with_reps(reps.min(5));
        let mut suite = Vec::new();
        for seed in 1..=scenes {
            suite.push(suite_row(seed, &params, &suite_timer)?);
            tick();
        }
        Ok(Self {
            scenes,
            reps,
            stages,
            reference,
            valid_points,
            suite,
        })
    }

    /// The suite's objects and how many were recovered.
    pub fn recovered(&self) -> (usize, usize) {
        let objects = self.suite.iter().map(|s| s.objects).sum();
        let recovered = self.suite.iter().map(|s| s.recovered).sum();
        (recovered, objects)
    }

    /// The pipeline's CPU per suite frame (ms).
    pub fn cpu(&self) -> Vec<f64> {
        self.suite.iter().map(|s| s.cpu_ms).collect()
    }

    /// What `bench perception --json` prints.
    pub fn to_json(&self) -> Result<serde_json::Value> {
        let (recovered, objects) = self.recovered();
        let cpu = self.cpu();
        Ok(serde_json::json!({
            "stages": self.stages,
            "reference_frame": self.reference,
            "reference_frame_valid_points": self.valid_points,
            "suite": self.suite,
            "suite_objects": objects,
            "suite_recovered": recovered,
            "suite_pipeline_cpu_ms_median": median(&cpu).unwrap_or(0.0),
            "suite_pipeline_cpu_ms_max": cpu.iter().copied().fold(0.0, f64::max),
        }))
    }

    /// What `bench perception` prints: each stage, the reference frame's quality, each
    /// suite frame, the suite's totals.
    pub fn lines(&self) -> Vec<String> {
        let mut lines: Vec<String> = self
            .stages
            .iter()
            .map(|r| {
                format!(
                    "{:<90} {:>8.2} ms CPU  {:>8.2} ms wall   anchor {}",
                    r.stage, r.cpu_ms_1_thread, r.wall_ms_2_threads, r.anchor
                )
            })
            .collect();
        let r = &self.reference;
        lines.push(format!(
            "\nnine-object frame ({} valid points): table precision {:.4} recall {:.4}; {} of {} objects with IoU > 0.8 ({} segments)",
            self.valid_points, r.table_precision, r.table_recall, r.recovered, r.objects, r.segments
        ));
        for (seed, s) in (1..).zip(&self.suite) {
            lines.push(format!(
                "scene {seed:>3}: {:>2} objects ({} touching pairs, {} stacked), {:>2} recovered, table P {:.4} R {:.4}, {:.1} ms CPU, {:.1} ms wall",
                s.objects,
                s.touching_pairs,
                s.stacked_pairs,
                s.recovered,
                s.table_precision,
                s.table_recall,
                s.cpu_ms,
                s.wall_ms
            ));
        }
        if self.scenes > 0 {
            let (recovered, objects) = self.recovered();
            let cpu = self.cpu();
            let min = |f: fn(&SuiteRow) -> f64| self.suite.iter().map(f).fold(1.0, f64::min);
            lines.push(format!(
                "suite: {recovered} of {objects} objects ({:.1} %), table found in all {} frames, table precision ≥ {:.4}, recall ≥ {:.4}; pipeline CPU median {:.1} ms, max {:.1} ms",
                100.0 * recovered as f64 / objects.max(1) as f64,
                self.scenes,
                min(|s| s.table_precision),
                min(|s| s.table_recall),
                median(&cpu).unwrap_or(0.0),
                cpu.iter().copied().fold(0.0, f64::max)
            ));
        }
        lines
    }
}
