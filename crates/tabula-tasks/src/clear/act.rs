//! Executing a frame's chosen action within the run: logged, watched, counted, and
//! the arm brought back whatever happened.

use super::execute::{Executor, GraspAction, drop_offset};
use super::run::{Act, Run, Step};
use super::track::shoved_along;
use super::{ActionKind, ActionRecord, ClearEvent};
use crate::skills::SkillError;
use crate::skills::motion::go_home;
use crate::skills::pick::Manipulator;
use tabula_robot::driver::RobotDriver;

impl<D: RobotDriver> Run<'_, D> {
    /// What will be logged of `act`: the object where it was seen, a push's direction
    /// and length, what it shoves along.
    fn record_of(&self, step: &Step<'_>, act: &Act) -> ActionRecord {
        let objects = step.objects;
        let centre = |a: usize| objects[a].center().to_array();
        let mut record = ActionRecord {
            frame: step.frame_no,
            action: act.kind.pddl(),
            object: objects[act.i].id,
            position: centre(act.i),
            push: None,
            shoves: act.nudged.iter().map(|&a| centre(a)).collect(),
            ok: false,
            error: None,
        };
        if let ActionKind::Push(k) = act.kind {
            let p = &step.geometry.pushes[act.i][k];
            record.push = Some((p.direction.to_array(), p.length));
            record.shoves = p.chain.iter().map(|&a| centre(a)).collect();
        }
        record
    }

    /// Executes `act`, tells `watch` before and after, logs it; `Err` when the driver
    /// failed and the run must stop.
    pub(super) fn act(
        &mut self,
        step: &Step<'_>,
        act: Act,
        watch: &mut dyn FnMut(&mut D, ClearEvent<'_>),
    ) -> Result<(), SkillError> {
        let mut record = self.record_of(step, &act);
        let (i, kind) = (act.i, act.kind);
        let o = &step.objects[i];
        let t = self
            .tracks
            .iter()
            .position(|t| t.id == o.id)
            .unwrap_or_default();
        if let ActionKind::Push(k) = kind {
            let direction = step.geometry.pushes[i][k].direction;
            if self.tracks[t]
                .pushes
                .iter()
                .any(|d| d.dot(direction) < -0.5)
            {
                self.report.push_loops += 1;
            }
        }
        watch(self.driver, ClearEvent::Before(&record));
        self.report.actions += 1;
        let result = self.execute(step, act, t);
        match result {
            Ok(()) => {
                record.ok = true;
                if kind == ActionKind::Grasp {
                    self.report.removed += 1;
                    // It is in the bin: whatever is seen there next is something else.
                    self.tracks.remove(t);
                    // What lay on an object put back may have been this one.
                    for tr in &mut self.tracks {
                        tr.carried_along = false;
                    }
                }
            }
            Err(e) => {
                record.error = Some(e.to_string());
                if matches!(e, SkillError::CarriedAlong(_)) {
                    // Not a failed grasp of it: tried again once something else is gone.
                    self.tracks[t].grasp_attempts = self.tracks[t].grasp_attempts.saturating_sub(1);
                    self.tracks[t].carried_along = true;
                }
                self.recover(step, i, kind);
                if matches!(e, SkillError::Driver(_)) {
                    self.report.log.push(record.clone());
                    watch(self.driver, ClearEvent::After(&record));
                    return Err(e);
                }
            }
        }
        watch(self.driver, ClearEvent::After(&record));
        if record.action != "grasp" {
            // Grasps are moments already (the hand takes and lets go); pushes are not.
            self.driver.annotate(&format!(
                "{} o{}{}",
                record.action,
                record.object,
                if record.ok { "" } else { " (failed)" }
            ));
        }
        tracing::info!(
            frame = record.frame,
            action = record.action.as_str(),
            object = record.object,
            ok = record.ok,
            error = record.error.as_deref().unwrap_or(""),
            "clear: action"
        );
        self.report.log.push(record);
        Ok(())
    }

    /// Runs the action on the robot; `t` is its object's track.
    fn execute(&mut self, step: &Step<'_>, act: Act, t: usize) -> Result<(), SkillError> {
        let i = act.i;
        let o = &step.objects[i];
        let drop_at =
            self.request.drop_point + drop_offset(self.report.removed, self.request.drop_spread);
        let mut exec = Executor {
            arm: Manipulator {
                driver: &mut *self.driver,
                robot: self.robot,
                group: &mut self.group,
                hand: &self.hand,
                gripper: &self.gripper,
                up: step.table.up,
            },
            home: &self.home,
            params: self.params,
        };
        match act.kind {
            ActionKind::Grasp => {
                self.report.grasps += 1;
                self.tracks[t].grasp_attempts += 1;
                // Taken away: its place no longer splits what is seen there.
                self.tracks[t].live = false;
                let Some(grasp) = &step.geometry.grasps[i] else {
                    return Err(SkillError::Motion("no grasp fits the object".into()));
                };
                exec.grasp(GraspAction {
                    objects: step.objects,
                    i,
                    grasp,
                    ik: act.ik,
                    nudged: &act.nudged,
                    drop_at,
                })
            }
            ActionKind::Push(k) => {
                self.report.pushes += 1;
                let p = &step.geometry.pushes[i][k];
                let track = &mut self.tracks[t];
                if p.split {
                    // Beyond the pushes it may have: one half moves, the middle half as
                    // far, and the half left behind was not jammed.
                    track.splits += 1;
                    // What its grasps failed on was the segment; what the next frame
                    // sees there is tried afresh.
                    track.grasp_attempts = 0;
                    track.expected = o.rect.center + p.direction * (p.length / 2.0);
                } else {
                    track.pushes.push(p.direction);
                    track.expected = o.rect.center + p.direction * p.length;
                    track.pending = Some((p.direction, p.length, o.rect.center));
                }
                track.pushed_together |= !p.chain.is_empty();
                shoved_along(&mut self.tracks, step.objects, i, p);
                exec.push(step.objects, i, p, act.ik)
            }
        }
    }

    /// After a failed action: counted, a failed push not tried that way again, and the
    /// arm backed out of the camera's view whatever happened. A grasp that failed after
    /// closing leaves its object attached in the planning world: the hand has let go of
    /// it, and the next frame sees where it fell.
    fn recover(&mut self, step: &Step<'_>, i: usize, kind: ActionKind) {
        let id = step.objects[i].id;
        match kind {
            ActionKind::Grasp => self.report.failed_grasps += 1,
            ActionKind::Push(k) => {
                if let Some(tr) = self.tracks.iter_mut().find(|tr| tr.id == id) {
                    tr.failed_pushes.push(step.geometry.pushes[i][k].direction);
                }
            }
        }
        let _ = self.driver.open(&self.gripper.name);
        let _ = self.group.remove_object(&format!("obj:{id}"));
        let _ = go_home(self.driver, self.robot, &mut self.group, &self.home);
    }
}
