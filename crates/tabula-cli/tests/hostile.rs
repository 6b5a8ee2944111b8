//! The hostile corpus (INPUT_POLICY.md): hundreds of malformed, adversarial and odd
//! but legal inputs — every file format tabula reads and every kind of number a user
//! types — each run through the real binary under a 20 s and 1 GiB budget. Every case
//! must end cleanly with the right kind of answer: success (exit 0) with the right
//! output, a one-line error (exit 1), "no solution" (exit 2) or a usage error (64);
//! never a panic, an abort, a hang or a runaway allocation.
//!
//! The cases are generated here, deterministically, and written to
//! `target/hostile-corpus/<format>/` where `scripts/fuzz_all.sh` picks them up as seeds.

#[path = "hostile/corpus.rs"]
mod corpus;

use corpus::{Case, Expect};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Cases with their place in the corpus (their run folder's name).
type Numbered<'a> = Vec<(usize, &'a Case)>;

const TIME_LIMIT: Duration = Duration::from_secs(20);
const MEMORY_LIMIT_KIB: i64 = 1 << 20;

/// What one run did.
struct Outcome {
    code: Option<i32>,
    signal: Option<i32>,
    stdout: String,
    stderr: String,
    wall: Duration,
    max_rss_kib: i64,
}

/// Runs the binary with `args` in `dir`, killing it after the time limit; the address
/// space is capped at 4 GiB so a runaway cannot take the machine down (the 1 GiB
/// criterion is checked on the measured peak RSS).
fn run(args: &[String], dir: &Path) -> Outcome {
    let out_path = dir.join(".stdout");
    let err_path = dir.join(".stderr");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tabula"));
    cmd.args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE");
    // SAFETY: setrlimit is async-signal-safe; nothing else runs between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            let cap = libc::rlimit {
                rlim_cur: 4 << 30,
                rlim_max: 4 << 30,
            };
            libc::setrlimit(libc::RLIMIT_AS, &cap);
            Ok(())
        });
    }
    let start = Instant::now();
    // Reaped below by wait4, which also reports the child's peak memory.
    #[allow(clippy::zombie_processes)]
    let child = cmd.spawn().expect("the binary starts");
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let mut killed = false;
    loop {
        // SAFETY: waiting on our own child, with valid out-pointers.
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if r == pid {
            break;
        }
        if start.elapsed() > TIME_LIMIT && !killed {
            // SAFETY: signalling our own child.
            unsafe { libc::kill(pid, libc::SIGKILL) };
            killed = true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let wall = start.elapsed();
    let read = |p: &Path| {
        let bytes = std::fs::read(p).unwrap_or_default();
        String::from_utf8_lossy(&bytes[..bytes.len().min(4 << 20)]).into_owned()
    };
    Outcome {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        signal: libc::WIFSIGNALED(status).then(|| libc::WTERMSIG(status)),
        stdout: read(&out_path),
        stderr: read(&err_path),
        wall,
        max_rss_kib: usage.ru_maxrss,
    }
}

/// Why a case's outcome is wrong, if it is.
fn judge(case: &Case, o: &Outcome) -> Option<String> {
    if let Some(sig) = o.signal {
        return Some(format!("killed by signal {sig} after {:.1?}", o.wall));
    }
    if o.wall > TIME_LIMIT {
        return Some(format!("ran {:.1?}", o.wall));
    }
    if o.max_rss_kib > MEMORY_LIMIT_KIB {
        return Some(format!("peak memory {} MiB", o.max_rss_kib >> 10));
    }
    for bad in [
        "panicked",
        "stack backtrace",
        "internal error",
        "RUST_BACKTRACE",
    ] {
        if o.stderr.contains(bad) || o.stdout.contains(bad) {
            return Some(format!("printed `{bad}`"));
        }
    }
    let code = o.code.unwrap_or(-1);
    let wanted = match case.expect {
        Expect::Ok => 0,
        Expect::Error => 1,
        Expect::NoSolution => 2,
        Expect::Usage => 64,
    };
    if code != wanted {
        return Some(format!("exit {code}, wanted {wanted}"));
    }
    if matches!(case.expect, Expect::Error) {
        let lines: Vec<&str> = o.stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        if lines.len() != 1 || !lines[0].starts_with("error: ") || lines[0].len() > 1200 {
            return Some(format!("not one error line: {} lines", lines.len()));
        }
    }
    if matches!(case.expect, Expect::Usage) {
        let lines = o.stderr.lines().filter(|l| !l.trim().is_empty()).count();
        if lines != 1 || !o.stderr.starts_with("error: ") {
            return Some(format!("not one usage error line: {lines} lines"));
        }
    }
    if let Some(needle) = &case.needle {
        let all = format!("{}\n{}", o.stdout, o.stderr).to_lowercase();
        if !all.contains(&needle.to_lowercase()) {
            return Some(format!("output lacks `{needle}`"));
        }
    }
    None
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/hostile-corpus")
}

#[test]
fn every_hostile_input_gets_a_clean_answer_in_time_and_memory() {
    let root = corpus_dir();
    let _ = std::fs::remove_dir_all(&root);
    let cases = corpus::all(&root);
    let counts = corpus::count_by_class(&cases);
    assert!(cases.len() >= 300, "only {} cases", cases.len());
    for class in corpus::CLASSES {
        assert!(
            counts.get(class).copied().unwrap_or(0) >= 3,
            "class `{class}` has fewer than 3 cases: {counts:?}"
        );
    }
    // `HOSTILE_ONLY=moveit-` runs the cases whose names start so (while working on them).
    let mut cases = cases;
    if let Ok(prefix) = std::env::var("HOSTILE_ONLY") {
        cases.retain(|c| c.name.starts_with(&prefix));
    }
    let failures = Mutex::new(Vec::new());
    let slowest = Mutex::new((Duration::ZERO, String::new()));
    let run_case = |i: usize, case: &Case| {
        let dir = root.join("runs").join(format!("{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        let args = case.args(&root);
        let outcome = run(&args, &dir);
        {
            let mut slow = slowest.lock().unwrap();
            if outcome.wall > slow.0 {
                *slow = (outcome.wall, case.name.clone());
            }
        }
        if let Some(why) = judge(case, &outcome) {
            failures.lock().unwrap().push(format!(
                "{} [{}]: {why}\n    tabula {}\n    stderr: {}",
                case.name,
                case.class,
                args.join(" "),
                outcome
                    .stderr
                    .lines()
                    .take(3)
                    .collect::<Vec<_>>()
                    .join(" | ")
            ));
        }
    };
    // The heavy cases (10,000 bodies settling, half a million triangles) use every core
    // themselves: each runs alone after the others, so its budget measures it and not
    // whatever shared the machine with it.
    let (heavy, light): (Numbered, Numbered) = cases
        .iter()
        .enumerate()
        .partition(|(_, c)| c.name.starts_with("heavy-"));
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                while let Some(&(i, case)) = light.get(next.fetch_add(1, Ordering::Relaxed)) {
                    run_case(i, case);
                }
            });
        }
    });
    for (i, case) in heavy {
        run_case(i, case);
    }
    let failures = failures.into_inner().unwrap();
    let (wall, name) = slowest.into_inner().unwrap();
    eprintln!(
        "{} hostile cases, {} failed; slowest {name} {wall:.1?}; by class {counts:?}",
        cases.len(),
        failures.len()
    );
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}
