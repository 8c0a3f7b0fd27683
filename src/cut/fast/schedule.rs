//! Scheduling helpers: the cut run on a worker of the rayon pool with another kept awake
//! ([`on_pool`]), and a join whose calling thread never falls asleep while it waits
//! ([`join`]).

use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

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

/// Runs `f` on a worker of the current rayon pool (in place when already on one). The cut's
/// dozen parallel steps then start from inside the pool: called from outside, each would
/// hand its work over to the pool and put the caller to sleep until it is done, a round
/// trip through the scheduler that costs more than a small step itself.
///
/// Beside the cut, one more worker is kept awake ([`keep_warm`]) until it is done (or
/// panics: the flag is set on unwinding too).
pub(crate) fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    struct SetOnDrop<'a>(&'a AtomicBool);
    impl Drop for SetOnDrop<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }
    let done = AtomicBool::new(false);
    rayon::scope(|s| {
        if rayon::current_num_threads() > 1 {
            let caller = rayon::current_thread_index();
            let done = &done;
            s.spawn(move |_| keep_warm(caller, done));
        }
        let _done = SetOnDrop(&done);
        f()
    })
}

/// Runs the pool's pending jobs until `done`. Between its parallel steps the cut works on one
/// thread for tens of microseconds; an idle rayon worker falls asleep after a few, and waking
/// it (a futex call by the cut's thread, then a reschedule) cost each following step more
/// than its share of the work (seventeen context switches a cut). This worker stays awake
/// and takes each step's jobs at once. Never on the cut's own thread: there it would keep
/// that thread from returning to the cut. It also gives up after a millisecond without a
/// job (longer than the cut's longest serial step): a worker that runs it while its own job
/// waits for another cut on the same pool must not wait for that cut to end.
fn keep_warm(caller: Option<usize>, done: &AtomicBool) {
    if rayon::current_thread_index() == caller {
        return;
    }
    let mut last_job = std::time::Instant::now();
    while !done.load(Ordering::Acquire) {
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            last_job = std::time::Instant::now();
        } else if last_job.elapsed() > std::time::Duration::from_millis(1) {
            return;
        } else {
            std::hint::spin_loop();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::on_pool;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
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

    /// A panic inside the cut reaches the caller (the C ABI catches it) instead of leaving
    /// the kept-awake worker spinning and the pool's scope waiting for it forever; the pool
    /// still works afterwards.
    #[test]
    fn a_panic_inside_the_pool_ends_the_kept_worker() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        for _ in 0..20 {
            let r = pool.install(|| {
                std::panic::catch_unwind(|| on_pool(|| -> u32 { panic!("inside the cut") }))
            });
            assert!(r.is_err());
            let (a, b) = pool.install(|| on_pool(|| rayon::join(|| 1u64, || 2u64)));
            assert_eq!(a + b, 3);
        }
    }
}
