//! Progress of long work, on stderr: a bar on a terminal; in a log (stderr
//! not a terminal, as in every CI job) a line every few seconds saying
//! what is done, what is running and what is left; nothing with
//! `--quiet`. Every command that runs many cases or a long render uses
//! this one type, so they all read alike.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

static QUIET: AtomicBool = AtomicBool::new(false);

/// `--quiet`: no progress at all, for the whole process.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Seconds between two lines in a log: SHADELAB_PROGRESS_SECONDS (a
/// number >= 0; 0 prints a line at every step), default 5.
fn log_interval() -> Duration {
    std::env::var("SHADELAB_PROGRESS_SECONDS")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0)
        .map_or(Duration::from_secs(5), Duration::from_secs_f64)
}

/// What a log line reports.
struct State {
    done: u64,
    total: u64,
    now: String,
    finished: bool,
}

/// One long step's progress: `total` units (cases, rows), of which some
/// are done and one is running now.
pub struct Progress {
    inner: Inner,
}

enum Inner {
    Quiet,
    Bar(indicatif::ProgressBar),
    Log {
        state: Arc<(Mutex<State>, Condvar)>,
        ticker: Option<std::thread::JoinHandle<()>>,
    },
}

impl Progress {
    /// Progress of `what` (`compare`, `check`, ...) over `total` units.
    pub fn new(what: &str, total: u64) -> Self {
        let inner = if QUIET.load(Ordering::Relaxed) {
            Inner::Quiet
        } else if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new(total);
            bar.set_style(
                indicatif::ProgressStyle::with_template(&format!(
                    "{what} {{bar:30}} {{pos}}/{{len}} {{msg}} ({{elapsed}}, {{eta}} left)"
                ))
                .expect("a valid template"),
            );
            bar.enable_steady_tick(Duration::from_millis(250));
            Inner::Bar(bar)
        } else {
            let state = Arc::new((
                Mutex::new(State {
                    done: 0,
                    total,
                    now: String::new(),
                    finished: false,
                }),
                Condvar::new(),
            ));
            let ticker = spawn_ticker(what.to_string(), Arc::clone(&state), log_interval());
            Inner::Log {
                state,
                ticker: Some(ticker),
            }
        };
        Progress { inner }
    }

    /// `done` units finished; `now` is what runs next.
    pub fn set(&self, done: u64, now: &str) {
        match &self.inner {
            Inner::Quiet => {}
            Inner::Bar(bar) => {
                bar.set_position(done);
                bar.set_message(now.to_string());
            }
            Inner::Log { state, .. } => {
                let (lock, wake) = &**state;
                let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
                s.done = done;
                s.now = now.to_string();
                wake.notify_all();
            }
        }
    }

    /// Runs `print` with the bar hidden, so that lines printed to the same
    /// terminal do not run into it.
    pub fn suspend<T>(&self, print: impl FnOnce() -> T) -> T {
        match &self.inner {
            Inner::Bar(bar) => bar.suspend(print),
            _ => print(),
        }
    }

    /// Every unit done.
    pub fn finish(&self) {
        let total = match &self.inner {
            Inner::Quiet => return,
            Inner::Bar(bar) => bar.length().unwrap_or(0),
            Inner::Log { state, .. } => state.0.lock().unwrap_or_else(|e| e.into_inner()).total,
        };
        self.set(total, "");
    }

    /// Changes the total (a list that grew or shrank once known).
    pub fn set_total(&self, total: u64) {
        match &self.inner {
            Inner::Quiet => {}
            Inner::Bar(bar) => bar.set_length(total),
            Inner::Log { state, .. } => {
                state.0.lock().unwrap_or_else(|e| e.into_inner()).total = total
            }
        }
    }
}

/// Runs `work`, which counts its phases' units (the CPU reference's
/// triangles, then its rows) into the counter it is given, and shows them
/// as `what`'s progress meanwhile, a phase at a time.
pub fn counted<T>(what: &str, work: impl FnOnce(&shadelab::work_counter::WorkCounter) -> T) -> T {
    if QUIET.load(Ordering::Relaxed) {
        return work(&Default::default());
    }
    let counter = shadelab::work_counter::WorkCounter::default();
    let finished = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let poller = scope.spawn(|| {
            let mut shown: Option<(&str, Progress)> = None;
            loop {
                // Read before the flag: the last pass shows the final count.
                let last_pass = finished.load(Ordering::Relaxed);
                let (phase, done, total) = counter.read();
                if !phase.is_empty() && shown.as_ref().is_none_or(|(p, _)| *p != phase) {
                    // A new phase: a new count, timed from its start.
                    shown = Some((phase, Progress::new(&format!("{what}, {phase}"), total)));
                }
                if let Some((_, progress)) = &shown {
                    progress.set_total(total);
                    progress.set(done, "");
                }
                if last_pass {
                    break;
                }
                // Woken at once when the work ends: a sleep here added up
                // to 100 ms to every command that counts its progress.
                std::thread::park_timeout(Duration::from_millis(100));
            }
        });
        let out = work(&counter);
        finished.store(true, Ordering::Relaxed);
        poller.thread().unpark();
        out
    })
}

impl Drop for Progress {
    fn drop(&mut self) {
        match &mut self.inner {
            Inner::Quiet => {}
            Inner::Bar(bar) => bar.finish_and_clear(),
            Inner::Log { state, ticker } => {
                {
                    let (lock, wake) = &**state;
                    lock.lock().unwrap_or_else(|e| e.into_inner()).finished = true;
                    wake.notify_all();
                }
                if let Some(t) = ticker.take() {
                    let _ = t.join();
                }
            }
        }
    }
}

/// Prints a line every `interval` until the work is finished (a long step
/// is news too: its elapsed time), or with an interval of 0 one at every
/// step.
fn spawn_ticker(
    what: String,
    state: Arc<(Mutex<State>, Condvar)>,
    interval: Duration,
) -> std::thread::JoinHandle<()> {
    std::thread::spawn(move || {
        let started = Instant::now();
        let (lock, wake) = &*state;
        let mut last_line = Instant::now();
        // What the last line said, and whether there was one.
        let mut last: Option<(u64, u64, String)> = None;
        let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            let now = (s.done, s.total, s.now.clone());
            let changed = last.as_ref() != Some(&now);
            // Every `interval` while the work runs; with 0, at every step;
            // and where a line was said, the last state too, once done.
            let print = if s.finished {
                changed && (last.is_some() || interval.is_zero())
            } else if interval.is_zero() {
                changed
            } else {
                last_line.elapsed() >= interval
            };
            if print {
                eprintln!("{}", log_line(&what, &s, started.elapsed()));
                last_line = Instant::now();
                last = Some(now);
            }
            if s.finished {
                return;
            }
            let wait = if interval.is_zero() {
                Duration::from_secs(1)
            } else {
                interval
                    .saturating_sub(last_line.elapsed())
                    .max(Duration::from_millis(50))
            };
            s = wake
                .wait_timeout(s, wait)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
    })
}

/// `shadelab: compare: 3 of 12 done, running phong:segments=64; 41 s
/// elapsed, about 2 min 3 s left`.
fn log_line(what: &str, s: &State, elapsed: Duration) -> String {
    let mut line = format!("shadelab: {what}: {} of {} done", s.done, s.total);
    if !s.now.is_empty() && s.done < s.total {
        line.push_str(&format!(", running {}", s.now));
    }
    line.push_str(&format!("; {} elapsed", duration(elapsed.as_secs_f64())));
    if s.done > 0 && s.done < s.total {
        let left = elapsed.as_secs_f64() / s.done as f64 * (s.total - s.done) as f64;
        line.push_str(&format!(", about {} left", duration(left)));
    }
    line
}

/// `41 s`, `2 min 3 s`, `1 h 4 min`.
fn duration(seconds: f64) -> String {
    let s = seconds.round() as u64;
    match s {
        0..=59 => format!("{s} s"),
        60..=3599 => format!("{} min {} s", s / 60, s % 60),
        _ => format!("{} h {} min", s / 3600, s / 60 % 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_line_says_what_is_done_running_and_left() {
        let s = State {
            done: 3,
            total: 12,
            now: "phong:segments=64".into(),
            finished: false,
        };
        assert_eq!(
            log_line("compare", &s, Duration::from_secs(41)),
            "shadelab: compare: 3 of 12 done, running phong:segments=64; 41 s elapsed, about 2 min 3 s left"
        );
        let start = State { done: 0, ..s };
        assert_eq!(
            log_line("check", &start, Duration::from_secs(3700)),
            "shadelab: check: 0 of 12 done, running phong:segments=64; 1 h 1 min elapsed"
        );
    }
}
