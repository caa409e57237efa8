//! Running a batch of cases (scene x mode) on one or two workers and
//! reporting each result in the cases' order as it comes in: `check`,
//! `render` with many scenes or modes, and `golden` share it.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

use shadelab::memory::MemoryLimit;

use super::failure::Failure;

/// How many cases run at once, each on a device of its own: two where there
/// are two cores and the memory limit holds two of the largest case. Each
/// case is mostly single-threaded work (lavapipe's pipeline creation and
/// code generation, FLIP, PNG encoding), so a second case fills the other
/// core: on a fresh machine, whose code generation is most of the time,
/// the cases' pipelines are generated two at a time.
pub(in crate::cli) fn case_workers(
    cases: usize,
    largest_estimate: u64,
    memory: &MemoryLimit,
) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let fits_two = largest_estimate.saturating_mul(2) <= memory.bytes;
    if cases >= 2 && cores >= 2 && fits_two {
        2
    } else {
        1
    }
}

/// Runs `run` on every job, on `workers` threads (the first with `context`,
/// each other with one of its own from `open_another`, or none if that
/// gives none),
/// and hands each result to `report` in the jobs' order as soon as those
/// before it are in. An error from `report` stops the workers after their
/// current job and is returned.
pub(in crate::cli) fn in_order<C: Sync, J: Copy + Sync, T: Send>(
    context: &C,
    open_another: impl Fn() -> Option<C> + Sync,
    jobs: &[J],
    workers: usize,
    run: impl Fn(&C, J) -> T + Sync,
    mut report: impl FnMut(usize, T) -> Result<(), Failure>,
) -> Result<(), Failure> {
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (sender, received) = mpsc::channel::<(usize, T)>();
    let work = |context: &C, sender: mpsc::Sender<(usize, T)>| loop {
        let k = next.fetch_add(1, Ordering::Relaxed);
        if k >= jobs.len() || stop.load(Ordering::Relaxed) {
            break;
        }
        if sender.send((k, run(context, jobs[k]))).is_err() {
            break;
        }
    };
    let work = &work;
    std::thread::scope(|scope| {
        for _ in 1..workers {
            let sender = sender.clone();
            let open_another = &open_another;
            scope.spawn(move || {
                if let Some(own) = open_another() {
                    work(&own, sender);
                }
            });
        }
        let sender_main = sender;
        let main_worker = scope.spawn(move || work(context, sender_main));
        let mut waiting = BTreeMap::new();
        let mut due = 0;
        let mut outcome = Ok(());
        for (k, result) in received.iter() {
            waiting.insert(k, result);
            while let Some(result) = waiting.remove(&due) {
                due += 1;
                if outcome.is_ok() {
                    outcome = report(due - 1, result);
                    if outcome.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
        }
        let _ = main_worker.join();
        outcome
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Results come back in the jobs' order however the workers finish:
    /// here the early jobs take the longest, so they finish last.
    #[test]
    fn results_are_reported_in_the_jobs_order() {
        let jobs: Vec<u64> = (0..12).collect();
        let slow_first = |_: &(), j: u64| {
            std::thread::sleep(std::time::Duration::from_millis(2 * (12 - j)));
            j * 10
        };
        let mut seen = Vec::new();
        in_order(
            &(),
            || Some(()),
            &jobs,
            2,
            slow_first,
            |k, t| {
                seen.push((k, t));
                Ok(())
            },
        )
        .unwrap_or_else(|f| panic!("{}", f.message));
        let expected: Vec<(usize, u64)> = (0..12).map(|j| (j as usize, j * 10)).collect();
        assert_eq!(seen, expected);
    }

    /// An error from the report stops the run: it is returned, and no later
    /// result is reported.
    #[test]
    fn a_report_error_stops_the_run() {
        let jobs: Vec<u64> = (0..50).collect();
        let mut reported = 0;
        let result = in_order(
            &(),
            || Some(()),
            &jobs,
            2,
            |_, j| j,
            |k, _| {
                reported += 1;
                if k == 3 {
                    Err(Failure::usage("stop".into()))
                } else {
                    Ok(())
                }
            },
        );
        assert_eq!(result.err().map(|f| f.message), Some("stop".to_string()));
        assert_eq!(reported, 4);
    }

    /// Without a second context the first worker does every job.
    #[test]
    fn one_worker_does_all_when_no_other_opens() {
        let jobs: Vec<u64> = (0..5).collect();
        let mut seen = Vec::new();
        in_order(
            &(),
            || None,
            &jobs,
            2,
            |_, j| j,
            |_, t| {
                seen.push(t);
                Ok(())
            },
        )
        .unwrap_or_else(|f| panic!("{}", f.message));
        assert_eq!(seen, jobs);
    }
}
