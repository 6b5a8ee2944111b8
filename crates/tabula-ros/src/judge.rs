//! A judged run on a served simulator, as a client of its own beside the driver: the
//! robot's interface knows nothing of judging. Begun before the task's first command,
//! told the task's moments, finished with the verdict the server's judge gives.

use crate::driver::{ZenohDriver, hardware, send, unexpected};
use crate::msgs::{CallRequest, CallResponse};
use crate::node::Client;
use crate::protocol::{Answer, CALL_TYPE, Command, DRIVER_SERVICE, JudgedTask, pose_to_array};
use std::time::Duration;
use tabula_geom::{Pose, Vec3};
use tabula_robot::driver::DriverError;

/// One judged run (see [`JudgedTask`]).
pub struct JudgeSession {
    call: Client<CallRequest, CallResponse>,
    timeout: Duration,
}

impl JudgeSession {
    /// Begins a judged run of `task` on the robot `driver` drives.
    pub fn begin(driver: &ZenohDriver, task: JudgedTask) -> Result<Self, DriverError> {
        let call = driver
            .node
            .client(DRIVER_SERVICE, CALL_TYPE)
            .map_err(hardware)?;
        let session = Self {
            call,
            timeout: driver.timeout,
        };
        match send(&session.call, &Command::Begin { task }, session.timeout)? {
            Answer::Begun => Ok(session),
            other => Err(unexpected(other)),
        }
    }

    /// Tells the judge what the task is about to do (`Some`: the target and what it
    /// shoves, as seen) or that it did it (`None`).
    pub fn moment(&self, event: Option<(Vec3, Vec<Vec3>)>) -> Result<(), DriverError> {
        let (target, shoved) = match event {
            Some((t, s)) => (Some(t.to_array()), s.iter().map(|p| p.to_array()).collect()),
            None => (None, Vec::new()),
        };
        match send(
            &self.call,
            &Command::ClearEvent { target, shoved },
            self.timeout,
        )? {
            Answer::Done => Ok(()),
            other => Err(unexpected(other)),
        }
    }

    /// Ends the run (a placing task gives the object's planned resting pose); the
    /// verdict, as the task's verdict type in JSON.
    pub fn finish(self, planned: Option<Pose>) -> Result<serde_json::Value, DriverError> {
        let planned = planned.map(|p| pose_to_array(&p));
        // The judge lets the world settle first.
        let timeout = self.timeout + Duration::from_secs(60);
        match send(&self.call, &Command::Finish { planned }, timeout)? {
            Answer::Verdict { verdict } => Ok(verdict),
            other => Err(unexpected(other)),
        }
    }
}
