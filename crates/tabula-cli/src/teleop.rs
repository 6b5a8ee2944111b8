//! `tabula teleop`: the gripper tele-operated from the keyboard (seed 000 §1.6's
//! Module 0) in a terminal UI. Each key is one step of the tool along x, y, z or about
//! them, in the robot's base (odometry) frame or the tool's own; the step is a Cartesian
//! path through the arm's IK from the current joints, checked against the joints'
//! limits and the scene, executed in the simulator — or refused with the reason.

use crate::arm::{arm_name, save_scene};
use crate::tasks::{load_params, load_world, scene_robot_named};
use anyhow::{Result, anyhow};
use clap::Args;
use ratatui::crossterm::event::{self, Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use ratatui::layout::{Constraint, Layout};
use ratatui::style::{Color, Style};
use ratatui::text::Line;
use ratatui::widgets::{Block, LineGauge, Paragraph};
use std::path::PathBuf;
use tabula_geom::{Pose, Vec3};
use tabula_motion::group::{MoveGroup, MoveGroupParams};
use tabula_robot::driver::Grippers;
use tabula_sim::SimDriver;
use tabula_tasks::skills::SkillError;
use tabula_tasks::skills::jog::{Jog, JogFrame, JointReading};

#[derive(Args)]
pub struct TeleopArgs {
    #[arg(long, required_unless_present = "print_params")]
    scene: Option<PathBuf>,
    #[arg(long)]
    robot: Option<String>,
    /// The arm to drive (a name from the robot's description; default: its first).
    #[arg(long)]
    group: Option<String>,
    /// Refresh a picture of the scene (PNG) here after every step, for a viewer.
    #[arg(long)]
    snapshot: Option<PathBuf>,
    /// Motion parameters (TOML, `MoveGroupParams`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
    /// TOML to start a file from, and exit.
    #[arg(long, exclusive = true)]
    print_params: bool,
    /// Write the world as a scene file when the session ends (Ctrl+C, q or Esc).
    #[arg(long)]
    save_scene: Option<PathBuf>,
}

/// The tele-operation state: the jogged arm in the simulator, step sizes, the last
/// answer.
struct Teleop {
    jog: Jog<SimDriver>,
    step_m: f64,
    step_rad: f64,
    /// Squeeze of a close (N per finger; the joint's limit caps it).
    effort: f64,
    last: String,
    snapshot: Option<PathBuf>,
}

impl Teleop {
    /// One step: `translation` (m) and `rotation` (a rotation vector, rad) in the
    /// current frame.
    fn step(&mut self, translation: Vec3, rotation: Vec3, what: &str) {
        let frame = match self.jog.frame {
            JogFrame::Base => "base",
            JogFrame::Tool => "tool",
        };
        let moved = self.jog.step(translation, rotation);
        self.answer(
            what,
            moved.map(|()| format!("moved: {what} ({frame} frame)")),
        );
    }

    fn torso(&mut self, delta: f64) {
        let moved = self.jog.torso(delta);
        self.answer("torso", moved.map(|h| format!("moved: torso to {h:.3} m")));
    }

    fn gripper(&mut self, open: bool) {
        let held_before = self.held();
        let grip = self.jog.gripper((!open).then_some(self.effort));
        if open && grip.is_ok() {
            // What it held is let go: the physics runs until it comes to rest, so the
            // screen and a saved scene show where it fell, not the object hanging
            // between open fingers.
            self.jog.driver.world.settle();
        }
        self.answer(
            "gripper",
            grip.map(|s| match s {
                None if held_before.is_empty() => "gripper opened".into(),
                None => format!("gripper opened, released {}", held_before.join(", ")),
                Some(s) => format!(
                    "gripper closed to {:.1} mm{}",
                    s.width * 1e3,
                    if s.holding { ", holding" } else { "" }
                ),
            }),
        );
    }

    /// The driven arm's gripper, if it has one.
    fn arm_gripper(&self) -> Option<&tabula_robot::description::Gripper> {
        let d = &self.jog.robot.description;
        d.arm(&self.jog.arm).ok().and_then(|a| d.gripper_of(a))
    }

    /// The objects the driven arm's gripper holds now.
    fn held(&self) -> Vec<String> {
        let driver = &self.jog.driver;
        let palm = self.arm_gripper().map(|g| g.palm.clone());
        driver
            .world
            .attachments
            .iter()
            .filter(|a| a.robot == driver.robot_name() && Some(&a.link) == palm.as_ref())
            .map(|a| format!("`{}`", a.object))
            .collect()
    }

    /// The gripper's line on the screen: its gap and what it holds.
    fn gripper_line(&self) -> String {
        let Some(g) = self.arm_gripper() else {
            return "gripper: none on this arm".into();
        };
        let held = self.held();
        match self.jog.driver.grip_state(&g.name) {
            Ok(s) => format!(
                "gripper `{}`: {:.1} mm ({}){}",
                g.name,
                s.width * 1e3,
                if s.width >= g.open_width - 1e-4 {
                    "open"
                } else {
                    "closed"
                },
                if held.is_empty() {
                    ", holding nothing".to_string()
                } else {
                    format!(", holding {}", held.join(", "))
                }
            ),
            Err(e) => format!("gripper `{}`: {e}", g.name),
        }
    }

    fn look_at_gripper(&mut self) {
        let off = self.jog.look_at_gripper();
        self.answer(
            "look",
            off.map(|o| format!("looking at the gripper ({:.1}° off)", o.to_degrees())),
        );
    }

    /// The answer to a key, or why it was refused; the picture refreshed.
    fn answer(&mut self, what: &str, result: Result<String, SkillError>) {
        self.last = result.unwrap_or_else(|e| format!("refused: {what}: {e}"));
        self.refresh_snapshot();
    }

    fn refresh_snapshot(&self) {
        if let Some(path) = &self.snapshot
            && let Some(eye) = tabula_sim::replay::default_eyes(&self.jog.driver.world)
                .into_iter()
                .find(|e| e.camera.is_none())
        {
            let img =
                tabula_sim::camera::snapshot(&self.jog.driver.world, eye.eye, eye.target, 640, 480);
            let _ = img.save(path);
        }
    }

    /// Handles a key; `false` when it asks to quit. In raw mode Ctrl+C arrives as a key,
    /// not a signal: it (and Ctrl+D, Ctrl+\\) stops and quits, and no other
    /// Ctrl-chord does anything — Ctrl+C must never close the gripper as `c` does.
    fn key(&mut self, key: KeyEvent) -> bool {
        if key
            .modifiers
            .intersects(KeyModifiers::CONTROL | KeyModifiers::ALT)
        {
            if let KeyCode::Char('c' | 'd' | '\\') = key.code {
                return false;
            }
            self.last = "refused: not a key here (Ctrl+C, q or Esc quits)".into();
            return true;
        }
        let (m, r) = (self.step_m, self.step_rad);
        let cm = m * 100.0;
        let deg = r.to_degrees();
        match key.code {
            KeyCode::Char('q') | KeyCode::Esc => return false,
            KeyCode::Char('w') => self.step(Vec3::X * m, Vec3::ZERO, &format!("+x {cm:.1} cm")),
            KeyCode::Char('s') => self.step(-Vec3::X * m, Vec3::ZERO, &format!("-x {cm:.1} cm")),
            KeyCode::Char('a') => self.step(Vec3::Y * m, Vec3::ZERO, &format!("+y {cm:.1} cm")),
            KeyCode::Char('d') => self.step(-Vec3::Y * m, Vec3::ZERO, &format!("-y {cm:.1} cm")),
            KeyCode::Char('r') => self.step(Vec3::Z * m, Vec3::ZERO, &format!("+z {cm:.1} cm")),
            KeyCode::Char('f') => self.step(-Vec3::Z * m, Vec3::ZERO, &format!("-z {cm:.1} cm")),
            KeyCode::Char('u') => self.step(Vec3::ZERO, Vec3::X * r, &format!("+roll {deg:.1}°")),
            KeyCode::Char('o') => self.step(Vec3::ZERO, -Vec3::X * r, &format!("-roll {deg:.1}°")),
            KeyCode::Char('i') => self.step(Vec3::ZERO, Vec3::Y * r, &format!("+pitch {deg:.1}°")),
            KeyCode::Char('k') => self.step(Vec3::ZERO, -Vec3::Y * r, &format!("-pitch {deg:.1}°")),
            KeyCode::Char('j') => self.step(Vec3::ZERO, Vec3::Z * r, &format!("+yaw {deg:.1}°")),
            KeyCode::Char('l') => self.step(Vec3::ZERO, -Vec3::Z * r, &format!("-yaw {deg:.1}°")),
            KeyCode::Char('t') => {
                self.jog.frame = match self.jog.frame {
                    JogFrame::Base => JogFrame::Tool,
                    JogFrame::Tool => JogFrame::Base,
                };
                self.last = "frame switched".into();
            }
            KeyCode::Char('+') => {
                self.step_m = (self.step_m * 2.0).min(0.5);
                self.last = format!("step {:.1} cm", self.step_m * 100.0);
            }
            KeyCode::Char('-') => {
                self.step_m = (self.step_m / 2.0).max(0.001);
                self.last = format!("step {:.1} cm", self.step_m * 100.0);
            }
            KeyCode::Char(']') => {
                self.step_rad = (self.step_rad * 2.0).min(1.0);
                self.last = format!("turn {:.1}°", self.step_rad.to_degrees());
            }
            KeyCode::Char('[') => {
                self.step_rad = (self.step_rad / 2.0).max(0.005);
                self.last = format!("turn {:.1}°", self.step_rad.to_degrees());
            }
            KeyCode::Char('>') => {
                self.effort = (self.effort * 2.0).min(1000.0);
                self.last = format!("grip effort {:.1} N", self.effort);
            }
            KeyCode::Char('<') => {
                self.effort = (self.effort / 2.0).max(0.5);
                self.last = format!("grip effort {:.1} N", self.effort);
            }
            KeyCode::Char('c') => self.gripper(false),
            KeyCode::Char('v') => self.gripper(true),
            KeyCode::Char('y') => self.torso(0.02),
            KeyCode::Char('h') => self.torso(-0.02),
            KeyCode::Char('g') => self.look_at_gripper(),
            _ => {}
        }
        true
    }

    fn draw(
        &self,
        frame: &mut ratatui::Frame,
        status: &Result<(Pose, Vec<JointReading>), SkillError>,
    ) {
        let (pose, joints) = match status {
            Ok((p, j)) => (*p, j),
            Err(e) => {
                frame.render_widget(Paragraph::new(format!("error: {e}")), frame.area());
                return;
            }
        };
        let t = pose.translation;
        let [roll, pitch, yaw] = tabula_geom::rpy_from_quat(pose.rotation);
        let x_axis = pose.rotation * Vec3::X;
        let [top, gauges, help] = Layout::vertical([
            Constraint::Length(8),
            Constraint::Min(joints.len() as u16 + 2),
            Constraint::Length(5),
        ])
        .areas(frame.area());
        let refused = self.last.starts_with("refused");
        let lines = vec![
            Line::from(format!(
                "tool (base): x {:+.4} y {:+.4} z {:+.4} m   roll {:+.2} pitch {:+.2} yaw {:+.2} °",
                t.x,
                t.y,
                t.z,
                roll.to_degrees(),
                pitch.to_degrees(),
                yaw.to_degrees()
            )),
            Line::from(format!(
                "tool x axis (base): {:+.4} {:+.4} {:+.4}",
                x_axis.x, x_axis.y, x_axis.z
            )),
            Line::from(format!(
                "frame: {}   step: {:.1} cm, {:.1}°   grip effort: {:.1} N",
                match self.jog.frame {
                    JogFrame::Base => "base",
                    JogFrame::Tool => "tool",
                },
                self.step_m * 100.0,
                self.step_rad.to_degrees(),
                self.effort
            )),
            Line::from(self.gripper_line()),
            Line::styled(
                format!("last: {}", self.last),
                Style::default().fg(if refused { Color::Red } else { Color::Green }),
            ),
        ];
        frame.render_widget(
            Paragraph::new(lines).block(Block::bordered().title(format!(
                " tabula teleop — {} arm `{}` ",
                self.jog.robot.label, self.jog.arm
            ))),
            top,
        );
        let block = Block::bordered().title(" joints against their limits ");
        let inner = block.inner(gauges);
        frame.render_widget(block, gauges);
        let rows = Layout::vertical(vec![Constraint::Length(1); joints.len()]).split(inner);
        for ((name, v, lo, hi), row) in joints.iter().zip(rows.iter()) {
            let (v, lo, hi) = (*v, *lo, *hi);
            let ratio = if hi > lo && lo.is_finite() && hi.is_finite() {
                ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
            } else {
                0.5
            };
            frame.render_widget(
                LineGauge::default()
                    .ratio(ratio)
                    .label(format!("{name:<26} {v:+.3} [{lo:+.2}, {hi:+.2}]"))
                    .filled_style(Style::default().fg(if !(0.02..=0.98).contains(&ratio) {
                        Color::Red
                    } else {
                        Color::Cyan
                    })),
                *row,
            );
        }
        frame.render_widget(
            Paragraph::new(vec![
                Line::from(
                    "w/s ±x  a/d ±y  r/f ±z   u/o ±roll  i/k ±pitch  j/l ±yaw   t base/tool frame",
                ),
                Line::from(
                    "+/- step size  ]/[ turn size   c close  v open gripper  >/< grip effort  y/h torso",
                ),
                Line::from("g look at the gripper   q, Esc or Ctrl+C quit"),
            ])
            .block(Block::bordered().title(" keys ")),
            help,
        );
    }
}

pub fn run(a: TeleopArgs) -> Result<()> {
    if a.print_params {
        return crate::tasks::print_params::<MoveGroupParams>();
    }
    use std::io::IsTerminal;
    if !(std::io::stdin().is_terminal() && std::io::stdout().is_terminal()) {
        anyhow::bail!("teleop needs an interactive terminal (its input and output a terminal)");
    }
    let params: MoveGroupParams = load_params(a.params.as_deref())?;
    let (_, world) = load_world(crate::args::given(&a.scene, "--scene")?)?;
    let (robot_name, robot) = scene_robot_named(&world, a.robot.as_deref())?;
    let arm = arm_name(&robot, a.group.as_ref())?;
    let obstacles = world.planning_scene(&robot_name);
    let driver = SimDriver::new(world, &robot_name, 1)?;
    let group = MoveGroup::at_driver(&driver, (&robot, &arm), &obstacles, &params)?;
    let mut t = Teleop {
        jog: Jog {
            driver,
            robot,
            arm,
            group,
            frame: JogFrame::Base,
        },
        step_m: 0.01,
        step_rad: 5f64.to_radians(),
        effort: 20.0,
        last: "ready".into(),
        snapshot: a.snapshot,
    };
    t.refresh_snapshot();
    // ratatui's init puts the terminal in raw mode on the alternate screen and restores
    // it on a panic; restore() undoes it on every way out below.
    let mut terminal =
        ratatui::try_init().map_err(|e| anyhow!("teleop cannot take over the terminal: {e}"))?;
    // Raw mode turns Ctrl+C into a key (see `key`); a SIGINT from elsewhere (`kill
    // -INT`) asks the same stop, seen between keys.
    crate::exit::stop_on_ctrl_c();
    let result = (|| -> Result<()> {
        loop {
            let status = t.jog.status();
            terminal.draw(|f| t.draw(f, &status))?;
            if tabula_robot::driver::stop_requested() {
                return Ok(());
            }
            if !event::poll(std::time::Duration::from_millis(100))? {
                continue;
            }
            if let Event::Key(k) = event::read()?
                && k.kind == KeyEventKind::Press
                && !t.key(k)
            {
                return Ok(());
            }
        }
    })();
    ratatui::restore();
    result?;
    save_scene(&t.jog.driver.world, a.save_scene.as_ref())
}
