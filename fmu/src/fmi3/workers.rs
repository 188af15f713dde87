//! The worker threads of an instance: started when its first step wants more than one thread, kept for
//! the following steps and joined when the instance is freed, so that no thread of the library is left
//! when a host unloads it after `fmi3FreeInstance`.
//!
//! A step hands every worker the same job, runs it on the calling thread too and returns when all have
//! finished it. Between steps a worker first waits spinning ([`IDLE_SPIN`]), then sleeps: waking a sleeping
//! thread costs tens of microseconds on a virtual machine (a halted virtual CPU), as much as a table step,
//! while a master's next step usually follows within that time. The caller waits for the last worker the
//! same way.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long a thread waits spinning for the next job (a worker) or for the other threads to finish a job
/// (the caller) before it sleeps.
pub const IDLE_SPIN: Duration = Duration::from_micros(200);

/// Spin iterations between two reads of the clock while waiting.
const SPINS_PER_CLOCK_READ: u32 = 64;

/// A job's closure, its lifetime erased: valid from the round that publishes it until the round's last
/// worker has returned from it, which [`Workers::run`] waits for before it returns.
#[derive(Clone, Copy)]
struct Job(*const (dyn Fn(usize) + Sync));

// SAFETY: the closure is `Sync` (callable from any thread through a shared reference), and `run` keeps it
// alive while any worker can reach it.
unsafe impl Send for Job {}

/// What the caller and the workers share.
struct Shared {
    /// The number of the current job (the workers compare it with the last they ran).
    round: AtomicU64,
    /// Set when the workers are to end.
    stop: AtomicBool,
    /// The current job; the workers sleep on this lock's condition `wake`.
    job: Mutex<Option<Job>>,
    wake: Condvar,
    /// Workers that have not finished the current job; the caller sleeps on `done` (with `done_lock`).
    pending: AtomicUsize,
    done_lock: Mutex<()>,
    done: Condvar,
    /// The first panic of a worker in the current job, resumed on the caller.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
}

/// Locks, ignoring poisoning (no lock here is held across a call that can panic).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Waits until `ready()`: spinning for [`IDLE_SPIN`], then sleeping on `condvar` with `guard`'s lock,
/// which whoever makes `ready()` true takes before notifying.
fn wait_for<T>(ready: impl Fn() -> bool, lock_of: &Mutex<T>, condvar: &Condvar) {
    let start = Instant::now();
    let mut spins = 0u32;
    while !ready() {
        std::hint::spin_loop();
        spins += 1;
        if spins.is_multiple_of(SPINS_PER_CLOCK_READ) && start.elapsed() >= IDLE_SPIN {
            let mut guard = lock(lock_of);
            while !ready() {
                guard = condvar.wait(guard).unwrap_or_else(PoisonError::into_inner);
            }
            return;
        }
    }
}

impl Shared {
    /// A worker's life: wait for a new round, run its job, report it done; until `stop`.
    fn serve(&self, me: usize) {
        let mut seen = 0;
        loop {
            wait_for(
                || self.round.load(Ordering::Acquire) != seen || self.stop.load(Ordering::Acquire),
                &self.job,
                &self.wake,
            );
            if self.stop.load(Ordering::Acquire) {
                return;
            }
            seen = self.round.load(Ordering::Acquire);
            if let Some(job) = *lock(&self.job) {
                // SAFETY: the job is alive until `pending` reaches zero, which happens after this call.
                let result = catch_unwind(AssertUnwindSafe(|| unsafe { (*job.0)(me) }));
                if let Err(p) = result {
                    lock(&self.panic).get_or_insert(p);
                }
            }
            if self.pending.fetch_sub(1, Ordering::AcqRel) == 1 {
                let _guard = lock(&self.done_lock);
                self.done.notify_one();
            }
        }
    }
}

/// Worker threads that run a job together with the calling thread.
pub struct Workers {
    shared: Arc<Shared>,
    threads: Vec<JoinHandle<()>>,
}

impl Workers {
    /// Starts `n` worker threads (fewer if the system refuses more).
    pub fn new(n: usize) -> Workers {
        let shared = Arc::new(Shared {
            round: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            job: Mutex::new(None),
            wake: Condvar::new(),
            pending: AtomicUsize::new(0),
            done_lock: Mutex::new(()),
            done: Condvar::new(),
            panic: Mutex::new(None),
        });
        let threads = (0..n)
            .map_while(|k| {
                let s = Arc::clone(&shared);
                std::thread::Builder::new()
                    .name(format!("wheelrail worker {}", k + 1))
                    .spawn(move || s.serve(k + 1))
                    .ok()
            })
            .collect();
        Workers { shared, threads }
    }

    /// The number of worker threads (besides the caller's).
    pub fn threads(&self) -> usize {
        self.threads.len()
    }

    /// Runs `job(t)` on every worker (t = 1, 2, …) and on this thread (t = 0); returns when all have
    /// returned from it. A panic of any of them is resumed here after all have returned.
    pub fn run(&self, job: &(dyn Fn(usize) + Sync)) {
        let s = &*self.shared;
        // SAFETY: only the lifetime is erased; this function does not return before every worker that
        // took the job has returned from it (`pending` zero), also when `job` panics on this thread.
        let erased: *const (dyn Fn(usize) + Sync + 'static) = unsafe { std::mem::transmute(job) };
        {
            let mut current = lock(&s.job);
            *current = Some(Job(erased));
            s.pending.store(self.threads.len(), Ordering::Relaxed);
            s.round.fetch_add(1, Ordering::Release);
        }
        s.wake.notify_all();
        let mine = catch_unwind(AssertUnwindSafe(|| job(0)));
        wait_for(
            || s.pending.load(Ordering::Acquire) == 0,
            &s.done_lock,
            &s.done,
        );
        *lock(&s.job) = None;
        if let Err(p) = mine {
            resume_unwind(p);
        }
        if let Some(p) = lock(&s.panic).take() {
            resume_unwind(p);
        }
    }

    /// Calls `f(t, item)` once on each item that `lists` names (each index at most once): thread t takes
    /// the items of `lists[t]` from the front, then, its list done, those still left in the others from
    /// their backs. With each list in decreasing cost, a thread that runs out early takes the cheapest
    /// items left, so the threads finish close together.
    pub fn each_mut<T: Send>(
        &self,
        items: &mut [T],
        lists: &[Vec<usize>],
        f: impl Fn(usize, &mut T) + Sync,
    ) {
        let mut listed = vec![false; items.len()];
        for &k in lists.iter().flatten() {
            assert!(
                !std::mem::replace(&mut listed[k], true),
                "item {k} listed twice"
            );
        }
        let base = Items(items.as_mut_ptr());
        let left: Vec<Mutex<std::ops::Range<usize>>> =
            lists.iter().map(|l| Mutex::new(0..l.len())).collect();
        let take = |list: usize, front: bool| {
            let mut range = lock(&left[list]);
            let i = match front {
                true => range.next(),
                false => range.next_back(),
            };
            i.map(|i| lists[list][i])
        };
        self.run(&|t| {
            let base = &base;
            let others = (1..=lists.len())
                .map(|d| (t + d) % lists.len())
                .filter(move |u| *u != t);
            let mine = (t < lists.len()).then(|| std::iter::from_fn(move || take(t, true)));
            let stolen = others.flat_map(|u| std::iter::from_fn(move || take(u, false)));
            for k in mine.into_iter().flatten().chain(stolen) {
                // SAFETY: k < items.len() (checked above) and is listed once, so exactly one thread takes
                // it, while `items` is borrowed mutably for the whole of `run`.
                f(t, unsafe { &mut *base.0.add(k) });
            }
        });
    }
}

/// The items of [`Workers::each_mut`] (a pointer shared by the threads, each dereferencing other items).
struct Items<T>(*mut T);

// SAFETY: the threads reach distinct items only (see `each_mut`), and `T: Send` lets an item be used on
// another thread.
unsafe impl<T: Send> Sync for Items<T> {}

impl Drop for Workers {
    /// Ends the workers and joins them.
    fn drop(&mut self) {
        let s = &*self.shared;
        {
            let _guard = lock(&s.job);
            s.stop.store(true, Ordering::Release);
        }
        s.wake.notify_all();
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_item_once_on_several_threads_and_workers_joined() {
        let w = Workers::new(3);
        assert_eq!(w.threads(), 3);
        let threads = Mutex::new(std::collections::HashSet::new());
        let mut items = vec![0u32; 100];
        // all listed for the caller: the workers steal
        let order = [(0..100)
            .rev()
            .filter(|k| k % 7 != 3)
            .collect::<Vec<usize>>()];
        for _ in 0..50 {
            w.each_mut(&mut items, &order, |_, x| {
                *x += 1;
                lock(&threads).insert(std::thread::current().id());
                std::thread::sleep(Duration::from_micros(10));
            });
        }
        for (k, x) in items.iter().enumerate() {
            assert_eq!(*x, if k % 7 == 3 { 0 } else { 50 }, "item {k}");
        }
        assert!(lock(&threads).len() > 1, "the work was shared");
        let shared = Arc::clone(&w.shared);
        drop(w);
        assert_eq!(Arc::strong_count(&shared), 1, "every worker ended");
    }

    #[test]
    fn sleeping_workers_wake_and_a_panic_reaches_the_caller_after_all_returned() {
        let w = Workers::new(1);
        std::thread::sleep(IDLE_SPIN * 5);
        let mut items = vec![0; 8];
        let order = [vec![0, 2, 4, 6], vec![1, 3, 5, 7]];
        let r = catch_unwind(AssertUnwindSafe(|| {
            w.each_mut(&mut items, &order, |_, x: &mut i32| {
                *x += 1;
                let name = std::thread::current().name().map(str::to_owned);
                assert!(
                    !name.is_some_and(|n| n.starts_with("wheelrail worker")),
                    "a worker's panic"
                );
                // the caller's items take long enough for the sleeping worker to wake and take one
                std::thread::sleep(Duration::from_millis(2));
            })
        }));
        assert!(r.is_err(), "the panic is resumed on the caller");
        w.each_mut(&mut items, &order, |_, x| *x += 1);
        assert!(
            items.iter().all(|x| *x >= 1),
            "the workers serve after a panic"
        );
    }

    #[test]
    #[should_panic(expected = "listed twice")]
    fn an_index_listed_twice_is_refused() {
        Workers::new(1).each_mut(&mut [0; 3], &[vec![0, 1], vec![0]], |_, x| *x += 1);
    }
}
