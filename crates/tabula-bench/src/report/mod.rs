//! `--report DIR`: a page a person opens after a run — `DIR/index.html` with the run's
//! numbers, pictures of its moments, plots, and an interactive 3D replay (three.js,
//! vendored into the binary: the page opens from disk without a network). The page
//! checks itself once loaded (images decoded, replays drawn, no script errors) and
//! writes the verdict into `#selftest`, which the browser test reads.

pub mod clear;
pub mod frame;
pub mod ik;
pub mod motion;
pub mod perception;
pub mod pick_place;
pub mod place;
pub mod plan;
pub mod plots;
pub mod stable;
pub mod tidy;

use anyhow::{Context, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use tabula_sim::replay::{Moment, Recorder, RecorderParams, Replay, default_eyes};
use tabula_sim::{SimDriver, SimWorld};

/// three.js r149, the last release with a classic-script build (`build/three.min.js`,
/// MIT, from the npm registry's `three` package); a page opened from disk may not load
/// ES modules.
const THREE_JS: &str = include_str!("../../assets/three.min.js");
const THREE_LICENSE: &str = include_str!("../../assets/three.LICENSE");
const REPORT_JS: &str = include_str!("../../assets/report.js");

/// A picture or plot file in the report, with its caption.
#[derive(Debug, Clone)]
pub struct Figure {
    pub file: String,
    pub caption: String,
}

/// One part of the page: a heading, text, a table of numbers, figures, replays.
#[derive(Debug, Clone, Default)]
pub struct Section {
    pub title: String,
    pub paragraphs: Vec<String>,
    pub numbers: Vec<(String, String)>,
    pub figures: Vec<Figure>,
    /// Replay ids (their data in `<id>.js`).
    pub replays: Vec<String>,
    /// Preformatted lines (an action log, say).
    pub log: Vec<String>,
}

impl Section {
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            ..Default::default()
        }
    }

    pub fn text(&mut self, s: impl Into<String>) -> &mut Self {
        self.paragraphs.push(s.into());
        self
    }

    pub fn number(&mut self, name: impl Into<String>, value: impl std::fmt::Display) -> &mut Self {
        self.numbers.push((name.into(), value.to_string()));
        self
    }
}

/// A report being written into a folder.
pub struct Report {
    dir: PathBuf,
    pub title: String,
    pub sections: Vec<Section>,
    files: usize,
}

/// Escapes text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A file name made of letters, digits and dashes.
fn slug(s: &str) -> String {
    let mut out: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    while out.contains("--") {
        out = out.replace("--", "-");
    }
    out.trim_matches('-').chars().take(48).collect()
}

impl Report {
    /// Starts a report in `dir` (created if missing).
    pub fn create(dir: &Path, title: impl Into<String>) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            anyhow::bail!(
                "{} is a file; a report is a folder (give a new or existing folder)",
                dir.display()
            );
        }
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            title: title.into(),
            sections: Vec::new(),
            files: 0,
        })
    }

    fn file_name(&mut self, name: &str, ext: &str) -> String {
        self.files += 1;
        format!("{:02}-{}.{ext}", self.files, slug(name))
    }

    fn write(&self, file: &str, bytes: &[u8]) -> Result<()> {
        let path = self.dir.join(file);
        std::fs::write(&path, bytes).with_context(|| format!("cannot write {}", path.display()))
    }

    /// Saves a picture; returns its figure.
    pub fn png(&mut self, name: &str, caption: &str, img: &image::RgbImage) -> Result<Figure> {
        let file = self.file_name(name, "png");
        let path = self.dir.join(&file);
        img.save(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(Figure {
            file,
            caption: caption.into(),
        })
    }

    /// Saves an SVG drawing (a plot); returns its figure.
    pub fn svg(&mut self, name: &str, caption: &str, svg: &str) -> Result<Figure> {
        let file = self.file_name(name, "svg");
        self.write(&file, svg.as_bytes())?;
        Ok(Figure {
            file,
            caption: caption.into(),
        })
    }

    /// Saves a replay's data as a script; returns its id for [`Section::replays`].
    pub fn replay(&mut self, name: &str, replay: &Replay) -> Result<String> {
        let file = self.file_name(&format!("replay-{name}"), "js");
        let id = file.trim_end_matches(".js").to_string();
        let json = serde_json::to_string(replay)?;
        let script = format!(
            "(window.TABULA_REPLAYS = window.TABULA_REPLAYS || {{}})[{}] = {json};\n",
            serde_json::to_string(&id)?
        );
        self.write(&file, script.as_bytes())?;
        Ok(id)
    }

    /// A section with a recorded run: its replay and the pictures of its moments.
    pub fn recorded(
        &mut self,
        section: &mut Section,
        name: &str,
        (replay, moments): &Recorded,
    ) -> Result<()> {
        let id = self.replay(name, replay)?;
        section.replays.push(id);
        for m in moments {
            for (eye, img) in &m.pictures {
                let fig = self.png(
                    &format!("{name}-{}-{eye}", m.label),
                    &format!("{} — t = {:.1} s, from {eye}", m.label, m.time),
                    img,
                )?;
                section.figures.push(fig);
            }
        }
        Ok(())
    }

    /// Writes `run.json`, the scripts and `index.html`; returns the page's path.
    pub fn finish(self, run: &impl Serialize) -> Result<PathBuf> {
        self.write("run.json", serde_json::to_string_pretty(run)?.as_bytes())?;
        self.write("three.min.js", THREE_JS.as_bytes())?;
        self.write("three.LICENSE", THREE_LICENSE.as_bytes())?;
        self.write("report.js", REPORT_JS.as_bytes())?;
        let mut html = String::new();
        html.push_str(&format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>{}</title>\n<style>{}</style>\n",
            esc(&self.title),
            STYLE
        ));
        html.push_str("<script src=\"three.min.js\"></script>\n");
        for s in &self.sections {
            for id in &s.replays {
                html.push_str(&format!("<script src=\"{}.js\"></script>\n", esc(id)));
            }
        }
        html.push_str("<script src=\"report.js\"></script>\n</head><body>\n");
        html.push_str(&format!("<h1>{}</h1>\n", esc(&self.title)));
        if self.sections.len() > 1 {
            html.push_str("<nav>");
            for (k, s) in self.sections.iter().enumerate() {
                html.push_str(&format!("<a href=\"#s{k}\">{}</a> ", esc(&s.title)));
            }
            html.push_str("</nav>\n");
        }
        for (k, s) in self.sections.iter().enumerate() {
            html.push_str(&format!(
                "<section id=\"s{k}\"><h2>{}</h2>\n",
                esc(&s.title)
            ));
            for p in &s.paragraphs {
                html.push_str(&format!("<p>{}</p>\n", esc(p)));
            }
            for id in &s.replays {
                html.push_str(&format!(
                    "<div class=\"replay\" data-replay=\"{}\"><canvas></canvas><div class=\"controls\"><button type=\"button\">play</button><input type=\"range\" min=\"0\" max=\"1\" value=\"0\" step=\"1\"><select><option value=\"0.5\">0.5×</option><option value=\"1\" selected>1×</option><option value=\"2\">2×</option><option value=\"4\">4×</option></select><span class=\"clock\"></span></div><p class=\"hint\">Drag to turn, shift- or right-drag to pan, wheel to zoom.</p></div>\n",
                    esc(id)
                ));
            }
            if !s.numbers.is_empty() {
                html.push_str("<table>\n");
                for (name, value) in &s.numbers {
                    html.push_str(&format!(
                        "<tr><th>{}</th><td>{}</td></tr>\n",
                        esc(name),
                        esc(value)
                    ));
                }
                html.push_str("</table>\n");
            }
            if !s.figures.is_empty() {
                html.push_str("<div class=\"figures\">\n");
                // Plots first and wide, pictures after.
                let (plots, pictures): (Vec<&Figure>, Vec<&Figure>) =
                    s.figures.iter().partition(|f| f.file.ends_with(".svg"));
                for f in plots.into_iter().chain(pictures) {
                    html.push_str(&format!(
                        "<figure class=\"{2}\"><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{1}</figcaption></figure>\n",
                        esc(&f.file),
                        esc(&f.caption),
                        if f.file.ends_with(".svg") { "plot" } else { "picture" }
                    ));
                }
                html.push_str("</div>\n");
            }
            if !s.log.is_empty() {
                html.push_str(&format!("<pre>{}</pre>\n", esc(&s.log.join("\n"))));
            }
            html.push_str("</section>\n");
        }
        html.push_str("<footer>Numbers: <a href=\"run.json\">run.json</a>. 3D: three.js r149 (MIT, <a href=\"three.LICENSE\">licence</a>).</footer>\n<pre id=\"selftest\"></pre>\n</body></html>\n");
        self.write("index.html", html.as_bytes())?;
        Ok(self.dir.join("index.html"))
    }
}

const STYLE: &str = "body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1180px;padding:0 1em;color:#1d2430}\
h1{font-size:1.6em}h2{border-bottom:1px solid #ccd;padding-bottom:.2em;margin-top:1.6em}\
nav a{margin-right:1em}table{border-collapse:collapse;margin:.8em 0}th,td{padding:.2em .8em;border-bottom:1px solid #e3e6ea;text-align:left;font-variant-numeric:tabular-nums}\
th{font-weight:500;color:#445}.figures{display:flex;flex-wrap:wrap;gap:12px}figure{margin:0;width:360px}figure.plot{width:560px}\
figure img{width:100%;border:1px solid #ccd;background:#fff}figcaption{font-size:.85em;color:#556}\
.replay canvas{width:100%;height:520px;display:block;border:1px solid #ccd;border-radius:4px}\
.controls{display:flex;gap:.6em;align-items:center;margin:.4em 0}.controls input{flex:1}.clock{font-variant-numeric:tabular-nums;min-width:22em}\
.hint{font-size:.8em;color:#778;margin:0}pre{background:#f5f6f8;padding:.6em;overflow-x:auto;font-size:.85em}\
#selftest{display:none}footer{margin-top:2em;font-size:.8em;color:#667}";

/// A bar chart: caption, unit, and (label, value) per bar.
pub type BarChart<'a> = (&'a str, &'a str, Vec<(String, f64)>);

/// What a benchmark reports: headline numbers, success per class (name, successes,
/// trials), timing distributions (caption, unit, samples), and its rows as run.json.
pub struct BenchSummary<'a> {
    pub title: &'a str,
    pub command: String,
    pub numbers: Vec<(String, String)>,
    pub classes: (&'a str, Vec<(String, usize, usize)>),
    pub distributions: Vec<(&'a str, &'a str, Vec<f64>)>,
    /// Bar charts (caption, unit, bars): CPU time per stage or per object, say.
    pub bars: Vec<BarChart<'a>>,
}

/// Writes a benchmark's report into `dir` and says where it is (on stderr).
pub fn bench_report(dir: &Path, b: BenchSummary<'_>, run: &impl Serialize) -> Result<()> {
    let mut report = Report::create(dir, b.title)?;
    let mut s = Section::new(b.title);
    s.text(format!("Command: {}", b.command));
    s.numbers = b.numbers;
    let (class_name, classes) = &b.classes;
    if !classes.is_empty() {
        let bars: Vec<(String, f64)> = classes
            .iter()
            .map(|(name, k, n)| {
                (
                    format!("{name} ({k} of {n})"),
                    100.0 * *k as f64 / (*n).max(1) as f64,
                )
            })
            .collect();
        let title = format!("Success per {class_name}");
        let svg = plots::bars(&title, "success (%)", &bars)?;
        let fig = report.svg("classes", &title, &svg)?;
        s.figures.push(fig);
    }
    for (caption, unit, bars) in &b.bars {
        let svg = plots::bars(caption, unit, bars)?;
        let fig = report.svg(caption, caption, &svg)?;
        s.figures.push(fig);
    }
    for (caption, unit, values) in &b.distributions {
        let bins = (values.len() as f64).sqrt().ceil().clamp(5.0, 40.0) as usize;
        let svg = plots::histogram(caption, unit, values, bins)?;
        let fig = report.svg(caption, caption, &svg)?;
        s.figures.push(fig);
    }
    report.sections.push(s);
    let page = report.finish(run)?;
    eprintln!("report: {}", page.display());
    Ok(())
}

/// Successes and trials per class, classes in first-seen order.
pub fn per_class<'a>(items: impl Iterator<Item = (&'a str, bool)>) -> Vec<(String, usize, usize)> {
    let mut out: Vec<(String, usize, usize)> = Vec::new();
    for (name, ok) in items {
        match out.iter_mut().find(|c| c.0 == name) {
            Some(c) => {
                c.1 += ok as usize;
                c.2 += 1;
            }
            None => out.push((name.to_string(), ok as usize, 1)),
        }
    }
    out
}

/// Writes a default snapshot of `world` next to the scene's camera view.
pub fn default_snapshot(world: &SimWorld, path: &std::path::Path) -> Result<()> {
    let img = tabula_sim::camera::snapshot(
        world,
        tabula_geom::Vec3::new(2.2, -1.6, 1.9),
        tabula_geom::Vec3::new(0.7, 0.0, 0.6),
        960,
        720,
    );
    img.save(path)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// A recorded run: its replay and the pictures of its moments.
pub type Recorded = (Replay, Vec<Moment>);

/// Runs `run` — which hands its driver to the starter it is given, once it has one —
/// recorded for the report when `enabled`: its output, the world afterwards, and the
/// recording.
pub fn recorded<T>(
    enabled: bool,
    run: impl FnOnce(&mut dyn FnMut(&mut SimDriver)) -> Result<(T, SimWorld)>,
) -> Result<(T, SimWorld, Option<Recorded>)> {
    let mut recording = Recording::new(enabled);
    let (out, world) = run(&mut |d| recording.start(d))?;
    let recorded = recording.finish(&world);
    Ok((out, world, recorded))
}

/// Records a run in the simulator when a report was asked for: a replay and pictures
/// before, at every grasp and release, and after.
#[derive(Default)]
pub struct Recording {
    enabled: bool,
    recorder: Option<Arc<Mutex<Recorder>>>,
}

impl Recording {
    pub fn new(enabled: bool) -> Self {
        Self {
            enabled,
            recorder: None,
        }
    }

    /// Starts watching `driver`'s world (pictures "before" now).
    pub fn start(&mut self, driver: &mut SimDriver) {
        if !self.enabled {
            return;
        }
        let eyes = default_eyes(&driver.world);
        let mut recorder = Recorder::new(&driver.world, eyes, RecorderParams::default());
        recorder.mark(&driver.world, "before");
        let (shared, feed) = recorder.shared();
        driver.observe(feed);
        self.recorder = Some(shared);
    }

    /// The recording, with pictures "after" of `world` (the world once settled).
    pub fn finish(self, world: &SimWorld) -> Option<Recorded> {
        let shared = self.recorder?;
        let mut recorder = match Arc::try_unwrap(shared) {
            Ok(m) => m.into_inner().ok()?,
            // The driver (and its observer) outlived the run: copy nothing, say so.
            Err(_) => return None,
        };
        recorder.mark(world, "after");
        Some(recorder.finish())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs_are_file_names() {
        assert_eq!(slug("wam grasps o3, lets go!"), "wam-grasps-o3-lets-go");
        assert_eq!(esc("<a & \"b\">"), "&lt;a &amp; &quot;b&quot;&gt;");
    }

    #[test]
    fn a_report_writes_its_page_and_files() {
        let dir = std::env::temp_dir().join(format!("tabula-report-{}", std::process::id()));
        let mut r = Report::create(&dir, "test <run>").unwrap();
        let mut s = Section::new("numbers");
        s.number("objects", 3).text("a & b");
        let fig = r
            .svg(
                "plot",
                "a plot",
                &plots::bars("t", "ms", &[("a".into(), 1.0)]).unwrap(),
            )
            .unwrap();
        s.figures.push(fig);
        r.sections.push(s);
        let page = r.finish(&serde_json::json!({"ok": true})).unwrap();
        let html = std::fs::read_to_string(&page).unwrap();
        assert!(html.contains("test &lt;run&gt;") && html.contains("a &amp; b"));
        assert!(html.contains("01-plot.svg") && dir.join("01-plot.svg").exists());
        assert!(dir.join("three.min.js").exists() && dir.join("run.json").exists());
        std::fs::remove_dir_all(&dir).ok();
    }
}
