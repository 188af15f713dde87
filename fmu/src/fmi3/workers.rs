//! The worker threads that evaluate the elements of a step besides the calling thread.
//!
//! A step hands every worker of a pool the same job, runs it on the calling thread too and returns when all
//! have finished it. Between steps a worker first waits spinning ([`IDLE_SPIN`]), then sleeps: waking a
//! sleeping thread costs tens of microseconds on a virtual machine (a halted virtual CPU), as much as a
//! table step, while a master's next step usually follows within that time. The caller waits for the last
//! worker the same way.
//!
//! The pools belong to the process, not to an instance ([`Registry`]): a master that steps several
//! instances one after another steps them all on one pool, whose workers are then the threads that wait
//! spinning for the next instance's step (a pool per instance would leave each instance's workers
//! spinning while the next instance's take the cores). Instances stepped at the same time from different
//! threads each take a pool of their own. An instance holds a [`Lease`] from its first parallel step on;
//! when the last lease ends (the last such instance is freed), every pool's workers are joined, so that no
//! thread of the library is left when a host unloads it after `fmi3FreeInstance`.

use crate::fmi2::x87;
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

/// Waits until `ready()`: spinning for [`IDLE_SPIN`], then sleeping on `condvar` with the lock `lock_of`,
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
    /// The number of threads asked for (the system may have started fewer).
    asked: usize,
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
                    // computing as the caller does inside every FMI call, whatever the thread started with
                    .spawn(move || x87::standard(|| s.serve(k + 1)))
                    .ok()
            })
            .collect();
        Workers {
            shared,
            threads,
            asked: n,
        }
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
        // a worker's panic is taken in any case: it belongs to this job, not to the next
        let theirs = lock(&s.panic).take();
        if let Some(p) = mine.err().or(theirs) {
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

/// The idle pools of a process and the number of leases on them.
pub struct Registry {
    pools: Mutex<Pools>,
}

struct Pools {
    leases: usize,
    idle: Vec<Workers>,
}

/// The process's pools.
pub static PROCESS: Registry = Registry::new();

impl Registry {
    /// No pools, no leases.
    const fn new() -> Registry {
        Registry {
            pools: Mutex::new(Pools {
                leases: 0,
                idle: Vec::new(),
            }),
        }
    }

    /// A lease on pools of `helpers` workers.
    pub fn lease(&'static self, helpers: usize) -> Lease {
        lock(&self.pools).leases += 1;
        Lease {
            registry: self,
            helpers,
        }
    }

    /// The number of worker threads in idle pools.
    #[cfg(test)]
    fn idle_threads(&self) -> usize {
        lock(&self.pools).idle.iter().map(Workers::threads).sum()
    }
}

/// A holder's claim on a registry's pools of one size: while any lease lasts, the registry keeps its idle
/// pools; the last lease to end joins their workers.
pub struct Lease {
    registry: &'static Registry,
    helpers: usize,
}

impl Lease {
    /// The number of workers asked for.
    pub fn helpers(&self) -> usize {
        self.helpers
    }

    /// Calls `f` with a pool of this lease's size: the idle one used last, else a new one; the pool
    /// returns to the idle ones afterwards (also when `f` panics: a pool is idle again once `run` returns).
    pub fn with<R>(&self, f: impl FnOnce(&Workers) -> R) -> R {
        let taken = {
            let mut pools = lock(&self.registry.pools);
            let found = pools.idle.iter().rposition(|w| w.asked == self.helpers);
            found.map(|i| pools.idle.remove(i))
        };
        let back = Return {
            registry: self.registry,
            pool: Some(taken.unwrap_or_else(|| Workers::new(self.helpers))),
        };
        f(back.pool.as_ref().expect("held until dropped"))
    }
}

impl Drop for Lease {
    fn drop(&mut self) {
        let ended = {
            let mut pools = lock(&self.registry.pools);
            pools.leases -= 1;
            match pools.leases {
                0 => std::mem::take(&mut pools.idle),
                _ => Vec::new(),
            }
        };
        // joined outside the registry's lock
        drop(ended);
    }
}

/// Puts a pool back among the registry's idle ones when dropped.
struct Return {
    registry: &'static Registry,
    pool: Option<Workers>,
}

impl Drop for Return {
    fn drop(&mut self) {
        if let Some(pool) = self.pool.take() {
            lock(&self.registry.pools).idle.push(pool);
        }
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
    fn a_job_that_panics_on_every_thread_leaves_no_panic_for_the_next() {
        let w = Workers::new(1);
        let order = [vec![0, 1, 2, 3], vec![4, 5, 6, 7]];
        let mut items = vec![0; 8];
        let r = catch_unwind(AssertUnwindSafe(|| {
            w.each_mut(&mut items, &order, |_, _: &mut i32| panic!("every thread"))
        }));
        assert!(r.is_err());
        w.each_mut(&mut items, &order, |_, x| *x += 1);
        assert_eq!(items, vec![1; 8]);
    }

    #[test]
    fn leases_share_one_pool_and_the_last_lease_joins_its_workers() {
        let registry: &'static Registry = Box::leak(Box::new(Registry::new()));
        let (a, b) = (registry.lease(2), registry.lease(2));
        let pool_of = |l: &Lease| l.with(|w| Arc::as_ptr(&w.shared));
        let first = pool_of(&a);
        assert_eq!(pool_of(&b), first, "one after the other: the same pool");
        assert_eq!(registry.idle_threads(), 2);
        // a lease that asks while the pool is out gets a pool of its own
        a.with(|outer| {
            let inner = b.with(|w| Arc::as_ptr(&w.shared));
            assert_ne!(inner, Arc::as_ptr(&outer.shared));
        });
        assert_eq!(registry.idle_threads(), 4);
        let shared = a.with(|w| Arc::clone(&w.shared));
        drop(a);
        assert_eq!(
            registry.idle_threads(),
            4,
            "a lease remains: the pools stay"
        );
        drop(b);
        assert_eq!(registry.idle_threads(), 0);
        assert_eq!(
            Arc::strong_count(&shared),
            1,
            "the workers ended with the last lease"
        );
    }

    #[test]
    #[should_panic(expected = "listed twice")]
    fn an_index_listed_twice_is_refused() {
        Workers::new(1).each_mut(&mut [0; 3], &[vec![0, 1], vec![0]], |_, x| *x += 1);
    }
}
