//! Parallel jobs whose results one thread consumes in order, each as soon as it is ready: the
//! consuming thread works through the serial part while the pool runs the later jobs (rayon
//! has no ordered streaming; `par_iter().collect()` waits for every job first). And a join
//! whose calling thread never falls asleep while it waits ([`join`]).

use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};

/// Runs `job(0)`, …, `job(n − 1)` on the current rayon pool and calls `consume(i, &result)`
/// on this thread in order of `i`, each as soon as its result is there.
/// Job 0 is spawned last, after jobs 1 to n − 1 in order: this thread takes the newest job
/// of its queue, so job 0 first and, while it waits, jobs from the end, and idle workers
/// steal the oldest, so jobs 1, 2, … in the order they are consumed. (Spawned last to first,
/// a worker took the last jobs first and this thread the second: the consumption waited for
/// it, normalization −14% on spot, through all, per-call A/B.) A job that panics is caught,
/// so this thread stops waiting and panics in turn instead of spinning for ever.
pub(crate) fn in_order<T: Send + Sync>(
    n: usize,
    job: impl Fn(usize) -> T + Sync,
    mut consume: impl FnMut(usize, &T) + Send,
) {
    let slots: Vec<OnceLock<Option<T>>> = (0..n).map(|_| OnceLock::new()).collect();
    rayon::scope(|s| {
        let job = &job;
        for i in (1..n).chain(0..n.min(1)) {
            let slot = &slots[i];
            s.spawn(move |_| {
                let _ = slot.set(std::panic::catch_unwind(AssertUnwindSafe(|| job(i))).ok());
            });
        }
        for (i, slot) in slots.iter().enumerate() {
            wait_awake(|| slot.get().is_some());
            consume(
                i,
                slot.get()
                    .and_then(Option::as_ref)
                    .expect("a parallel job panicked"),
            );
        }
    });
}

/// Until `ready()`, runs the pool's pending jobs on this thread, or spins when there are
/// none (never sleeps: see [`join`]).
fn wait_awake(ready: impl Fn() -> bool) {
    while !ready() {
        if rayon::yield_now() != Some(rayon::Yield::Executed) {
            std::hint::spin_loop();
        }
    }
}

/// `rayon::join(a, b)` for a thread that must not fall asleep: `b` is offered to the pool
/// and `a` run here; then, until `b` is done, this thread runs pending jobs (`b` itself if no
/// one took it) or spins. Rayon's join lets a thread that runs out of work sleep, and waking
/// it again (a futex call, then a reschedule) cost tens of microseconds each time the cut's
/// thread waited for a long job on the other one. A panic in `b` is caught and raised here.
pub(crate) fn join<RA: Send, RB: Send>(
    a: impl FnOnce() -> RA + Send,
    b: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    // `b`'s result (`None` if it panicked), and whether it is there.
    let slot: Mutex<Option<Option<RB>>> = Mutex::new(None);
    let done = AtomicBool::new(false);
    let ra = rayon::scope(|s| {
        let (slot, done) = (&slot, &done);
        s.spawn(move |_| {
            let rb = std::panic::catch_unwind(AssertUnwindSafe(b)).ok();
            *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(rb);
            done.store(true, Ordering::Release);
        });
        let ra = a();
        wait_awake(|| done.load(Ordering::Acquire));
        ra
    });
    let rb = slot
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .flatten();
    (ra, rb.expect("a parallel job panicked"))
}

#[cfg(test)]
mod tests {
    use super::in_order;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    #[test]
    fn results_come_in_order_on_any_pool() {
        for threads in [1, 2, 4] {
            let pool = pool(threads);
            let mut seen = Vec::new();
            pool.install(|| {
                in_order(
                    100,
                    |i| (0..(i * 37) % 1000).map(|x| x as u64).sum::<u64>() + i as u64,
                    |i, r| seen.push((i, *r)),
                )
            });
            let expect: Vec<u64> = (0..100)
                .map(|i| (0..(i * 37) % 1000).map(|x| x as u64).sum::<u64>() + i as u64)
                .collect();
            assert_eq!(seen, expect.iter().copied().enumerate().collect::<Vec<_>>());
        }
    }

    #[test]
    fn join_gives_both_results_on_any_pool() {
        for threads in [1, 2, 4] {
            let pool = pool(threads);
            let sum = |n: u64| (0..n).sum::<u64>();
            for n in [0u64, 10, 100_000] {
                let (a, b) = pool.install(|| super::join(|| sum(n), || vec![sum(2 * n)]));
                assert_eq!((a, b), (sum(n), vec![sum(2 * n)]));
            }
        }
    }

    #[test]
    fn join_panics_when_either_side_does() {
        let pool = pool(2);
        let a = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pool.install(|| super::join(|| panic!("a"), || 1))
        }));
        assert!(a.is_err());
        let b = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pool.install(|| super::join(|| 1, || panic!("b")))
        }));
        assert!(b.is_err());
    }

    #[test]
    fn a_panicking_job_panics_the_caller() {
        let r = std::panic::catch_unwind(|| {
            in_order(8, |i| if i == 5 { panic!("job 5") } else { i }, |_, _| {})
        });
        assert!(r.is_err());
    }
}
