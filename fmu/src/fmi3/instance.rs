//! One FMI 3.0 instance: its state, logger and elements (each the values of the model's variable table and
//! a model of one element, as one FMI 2.0 instance has them), the rules for reading and writing array
//! values, and the evaluation of the elements in parallel.
//!
//! Each element is evaluated exactly as an FMI 2.0 instance of the model with the same values is (the same
//! model calls in the same order, on its own values and state), so the outputs are bit for bit those of one
//! FMI 2.0 instance per element, however many threads evaluate them: the elements share no mutable state
//! but the library's process-wide caches, which are safe to use from any thread.

use super::arrays::{ArrayInfo, ArrayModel, Slot, is_array, slot, type_name};
use super::state::{self, Interface, State};
use super::workers::{self, Lease};
use crate::fmi2::ffi::Status;
use crate::fmi2::instance::{Failure, Outcome};
use crate::fmi2::logging::{Logger, Message};
use crate::fmi2::snapshot::{ModelState, begin, open, put_values, seal};
use crate::fmi2::variables::{Causality, Type, Value, Values};
use std::ffi::CString;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Instant;

/// One element: its values, whether its outputs are stale, and its model.
pub struct Element<M> {
    values: Values,
    stale: bool,
    model: M,
    /// The wall times of its last two evaluations of its outputs after the first [s], the last first (zero
    /// where there is none yet).
    times: [f64; 2],
    /// The thread that evaluated it last (0: the caller's).
    thread: usize,
    /// Whether its outputs have been evaluated once (its set-up).
    evaluated: bool,
}

impl<M> Element<M> {
    /// The time its next evaluation is expected to take [s] (whether a call is shared between threads, and
    /// the order in which they take the elements): the smaller of its last two, so that one slow evaluation
    /// (the first lookups of a table touching its pages, a new grid's operators) does not count as a step's
    /// work; zero until there are two.
    fn cost(&self) -> f64 {
        self.times[0].min(self.times[1])
    }
}

/// An FMI 3.0 instance of `contacts` elements of model `M`.
pub struct Instance<M: ArrayModel> {
    /// The instance name given at instantiation.
    pub name: String,
    /// The interface type it was instantiated as.
    pub interface: Interface,
    /// Co-Simulation: whether the importer uses event mode (`eventModeUsed`).
    pub event_mode_used: bool,
    /// State-machine state.
    pub state: State,
    /// Logging.
    pub log: Logger,
    elements: Vec<Element<M>>,
    threads: u64,
    time: f64,
    resources: Option<PathBuf>,
    strings: Vec<CString>,
    /// Its claim on the process's worker threads, from the first step that evaluates the elements on
    /// several threads on.
    workers: Option<Lease>,
}

/// The states a snapshot may hold, with their codes in the serialized form.
fn state_code(s: State) -> u16 {
    s as u16
}

/// The cores this process may use, read once (a read costs about 10 µs on Linux: the cgroup's quota).
fn available_cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// The least work [s] (the sum of the expected times, [`Element::cost`], of the elements a call evaluates)
/// that is shared between threads; less runs on the calling thread. Handing a job to the workers and waiting
/// for them costs 2–15 µs while they wait spinning and 50–100 µs once they sleep (waking a halted virtual
/// CPU): a step of eight contacts by table (a few µs) would take longer on several threads than on one, a
/// step of exact contacts (tens to hundreds of µs each) gains.
const PARALLEL_WORK: f64 = 100e-6;

/// One element's evaluation: its status and the log messages it kept.
type Evaluated = (Result<Status, String>, Vec<Message>);
impl<M: ArrayModel> Instance<M> {
    /// A new instance of `interface` in the Instantiated state: one element, all variables at their start
    /// values.
    pub fn new(
        name: String,
        interface: Interface,
        log: Logger,
        resources: Option<PathBuf>,
    ) -> Instance<M> {
        let arrays = M::arrays();
        let mut inst = Instance {
            name,
            interface,
            event_mode_used: false,
            state: State::Instantiated,
            log,
            elements: Vec::new(),
            threads: arrays.threads.start,
            time: 0.0,
            resources,
            strings: Vec::new(),
            workers: None,
        };
        inst.resize(arrays.size.start as usize);
        inst
    }

    fn table() -> &'static [crate::fmi2::variables::Variable] {
        M::info().variables
    }

    /// The number of elements.
    pub fn size(&self) -> usize {
        self.elements.len()
    }

    /// The values of element `k` (for inspection).
    pub fn values(&self, k: usize) -> &Values {
        &self.elements[k].values
    }

    /// Whether a call has shared its elements with the workers.
    #[cfg(test)]
    pub fn has_shared(&self) -> bool {
        self.workers.is_some()
    }

    /// The current time [s].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Resizes to `n` elements: new ones take the shared parameters of the first and the start values of
    /// the array variables.
    fn resize(&mut self, n: usize) {
        let arrays = M::arrays();
        let table = Self::table();
        let mut template = Values::start(table);
        if let Some(first) = self.elements.first() {
            for (i, v) in table.iter().enumerate() {
                if !is_array(arrays, i, v) {
                    template.set(i, first.values.list()[i].clone());
                }
            }
        }
        self.elements.truncate(n);
        while self.elements.len() < n {
            self.elements.push(Element {
                values: template.clone(),
                stale: true,
                model: M::new(self.resources.clone()),
                times: [0.0; 2],
                thread: 0,
                evaluated: false,
            });
        }
    }

    /// The threads a step uses: `threads` (0: the cores the process may use), at most one per element.
    fn worker_count(&self) -> usize {
        let wanted = match self.threads {
            0 => available_cores(),
            n => n as usize,
        };
        wanted.min(self.elements.len()).max(1)
    }

    /// Runs `f` on every element (on several threads when `threads` asks for them), then passes on each
    /// element's log messages in element order, prefixed by the element's number; the status is the worst
    /// of the elements', the first failure (by element) fails the call.
    fn each(
        &mut self,
        f: impl Fn(&mut Element<M>, &Logger) -> Result<Status, String> + Sync,
    ) -> Outcome {
        let categories = self.log.categories();
        let run = |e: &mut Element<M>| -> Evaluated {
            let (log, kept) = Logger::keeping(categories);
            let (start, computes) = (Instant::now(), e.stale);
            let result = f(e, &log);
            // the first evaluation sets the element up (loads its table, builds its solver's operators):
            // its time says nothing of the steps
            match computes && e.evaluated {
                true => e.times = [start.elapsed().as_secs_f64(), e.times[0]],
                false => e.evaluated |= computes,
            }
            (result, kept.take())
        };
        // the work of the elements to evaluate, by their expected times: too little to gain from more threads
        // runs on this one
        let work: f64 = self
            .elements
            .iter()
            .filter(|e| e.stale)
            .map(Element::cost)
            .sum();
        let workers = match work < PARALLEL_WORK {
            true => 1,
            false => self.worker_count(),
        };
        let results: Vec<Evaluated> = if workers <= 1 {
            self.elements.iter_mut().map(run).collect()
        } else {
            let helpers = workers - 1;
            if self.workers.as_ref().is_none_or(|l| l.helpers() != helpers) {
                self.workers = Some(workers::PROCESS.lease(helpers));
            }
            let lease = self.workers.as_ref().expect("just leased");
            let elements = &mut self.elements;
            lease.with(|pool| {
                // each thread first takes the elements it evaluated last time (their data are in its caches),
                // the costliest first (by their expected times), then the cheapest left of the others'
                let threads = pool.threads() + 1;
                let mut lists = vec![Vec::new(); threads];
                for (k, e) in elements.iter().enumerate() {
                    lists[e.thread.min(threads - 1)].push(k);
                }
                for l in &mut lists {
                    l.sort_by(|a, b| elements[*b].cost().total_cmp(&elements[*a].cost()));
                }
                let mut slots: Vec<(&mut Element<M>, Option<Evaluated>)> =
                    elements.iter_mut().map(|e| (e, None)).collect();
                pool.each_mut(&mut slots, &lists, |t, (e, r)| {
                    e.thread = t;
                    *r = Some(run(e));
                });
                slots
                    .into_iter()
                    .map(|(_, r)| r.expect("every element evaluated"))
                    .collect()
            })
        };
        let element = M::arrays().element;
        let mut status = Status::Ok;
        let mut failure = None;
        for (k, (result, messages)) in results.into_iter().enumerate() {
            self.log
                .forward(&messages, &format!("{element} {}: ", k + 1));
            match result {
                Ok(s) => status = status.max(s),
                Err(e) if failure.is_none() => failure = Some(format!("{element} {}: {e}", k + 1)),
                Err(_) => {}
            }
        }
        match failure {
            Some(e) => Err(Failure::Failed(e)),
            None => Ok(status),
        }
    }

    /// Recomputes the outputs of the elements whose values changed: in Co-Simulation by
    /// [`Model::calculate`], in Model Exchange by [`Model::calculate_trial`].
    pub fn update(&mut self) -> Outcome {
        if self.elements.iter().all(|e| !e.stale) {
            return Ok(Status::Ok);
        }
        let me = self.interface == Interface::ModelExchange;
        self.each(|e, log| {
            if !e.stale {
                return Ok(Status::Ok);
            }
            let status = match me {
                true => e.model.calculate_trial(&mut e.values, log),
                false => e.model.calculate(&mut e.values, log),
            }?;
            e.stale = false;
            Ok(status)
        })
    }

    /// Model Exchange: accepts the current point of every element ([`Model::accept`]).
    pub fn accept(&mut self) -> Outcome {
        self.each(|e, log| {
            let mut status = Status::Ok;
            if e.stale {
                status = e.model.calculate_trial(&mut e.values, log)?;
                e.stale = false;
            }
            Ok(status.max(e.model.accept(&e.values, log)?))
        })
    }

    /// The slots of `vrs` for values of `ty` (None: UInt64) and the number of values they hold.
    fn slots(&self, vrs: &[u32], ty: Option<Type>) -> Result<(Vec<Slot>, usize), Failure> {
        let mut slots = Vec::with_capacity(vrs.len());
        let mut count = 0;
        for vr in vrs {
            let s = slot(Self::table(), M::arrays(), *vr, ty).ok_or_else(|| {
                Failure::Rejected(format!(
                    "no {} variable has value reference {vr}",
                    type_name(ty)
                ))
            })?;
            count += match s {
                Slot::PerElement(_) => self.elements.len(),
                _ => 1,
            };
            slots.push(s);
        }
        Ok((slots, count))
    }

    fn check_count(expected: usize, given: usize) -> Result<(), Failure> {
        match expected == given {
            true => Ok(()),
            false => Err(Failure::Rejected(format!(
                "nValues = {given}, but the variables hold {expected} values (an array variable holds one \
                 value per element)"
            ))),
        }
    }

    /// Reads values of table type `ty` into `out` (serialised: an array's elements in order), handing the
    /// n-th to `out(n, value)`; `n_values` must be the number the variables hold. Outputs are brought to the
    /// current inputs first in the initialization, event, step and continuous-time modes.
    pub fn get(
        &mut self,
        vrs: &[u32],
        ty: Type,
        n_values: usize,
        mut out: impl FnMut(usize, &Value),
    ) -> Outcome {
        let (slots, count) = self.slots(vrs, Some(ty))?;
        Self::check_count(count, n_values)?;
        let table = Self::table();
        let wants_output = slots
            .iter()
            .any(|s| matches!(s, Slot::PerElement(i) if table[*i].causality == Causality::Output));
        let status = match wants_output && state::UPDATE_OUTPUTS.allows(self.state) {
            true => self.update()?,
            false => Status::Ok,
        };
        let mut n = 0;
        for s in slots {
            match s {
                Slot::Shared(i) => {
                    out(n, &self.elements[0].values.list()[i]);
                    n += 1;
                }
                Slot::PerElement(i) => {
                    for e in &self.elements {
                        out(n, &e.values.list()[i]);
                        n += 1;
                    }
                }
                Slot::Time => {
                    out(n, &Value::Real(self.time));
                    n += 1;
                }
                Slot::Size | Slot::Threads => unreachable!("UInt64 slots are read by get_counts"),
            }
        }
        Ok(status)
    }

    /// Reads Strings; the returned pointers stay valid until the next `fmi3GetString` of this instance.
    pub fn get_strings(
        &mut self,
        vrs: &[u32],
        n_values: usize,
    ) -> Result<(Vec<*const std::ffi::c_char>, Status), Failure> {
        let mut strings = Vec::with_capacity(n_values);
        let status = self.get(vrs, Type::String, n_values, |_, v| match v {
            Value::String(s) => strings.push(crate::fmi2::logging::to_c_string(s)),
            _ => unreachable!("get hands out values of the requested type"),
        })?;
        self.strings = strings;
        Ok((self.strings.iter().map(|s| s.as_ptr()).collect(), status))
    }

    /// Reads the UInt64 parameters (the number of elements and of threads).
    pub fn get_counts(&mut self, vrs: &[u32], out: &mut [u64]) -> Outcome {
        let (slots, count) = self.slots(vrs, None)?;
        Self::check_count(count, out.len())?;
        for (o, s) in out.iter_mut().zip(slots) {
            *o = match s {
                Slot::Size => self.elements.len() as u64,
                _ => self.threads,
            };
        }
        Ok(Status::Ok)
    }

    /// Writes values of table type `ty` (serialised as [`Instance::get`] reads them): every value is
    /// checked first (known reference, the number of values, settable causality in this state, finite
    /// Reals); one bad value rejects the whole call. `value(n)` converts the n-th value of the call.
    pub fn set(
        &mut self,
        vrs: &[u32],
        ty: Type,
        n_values: usize,
        value: impl Fn(usize) -> Result<Value, Failure>,
    ) -> Outcome {
        let (slots, count) = self.slots(vrs, Some(ty))?;
        Self::check_count(count, n_values)?;
        let table = Self::table();
        let mut n = 0;
        for s in &slots {
            let (Slot::Shared(i) | Slot::PerElement(i)) = *s else {
                return Err(Failure::Rejected(
                    "time is the independent variable and cannot be set".into(),
                ));
            };
            let var = &table[i];
            let allowed = match var.causality {
                Causality::Output => {
                    return Err(Failure::Rejected(format!(
                        "{} is an output and cannot be set",
                        var.name
                    )));
                }
                Causality::Parameter => state::SET_FIXED_PARAMETER,
                Causality::Input => state::SET_INPUT,
            };
            if !allowed.allows(self.state) {
                return Err(Failure::Rejected(format!(
                    "{} cannot be set in state {:?} (a {} may be set in the states {})",
                    var.name,
                    self.state,
                    match var.causality {
                        Causality::Parameter => "fixed parameter",
                        _ => "input",
                    },
                    match var.causality {
                        Causality::Parameter => "Instantiated and InitializationMode",
                        _ =>
                            "Instantiated, InitializationMode, EventMode, StepMode, ContinuousTimeMode",
                    }
                )));
            }
            let values = match s {
                Slot::PerElement(_) => self.elements.len(),
                _ => 1,
            };
            for k in 0..values {
                if let Value::Real(x) = value(n + k)?
                    && !x.is_finite()
                {
                    return Err(Failure::Rejected(format!(
                        "{}[{}] = {x} is not a finite number",
                        var.name,
                        k + 1
                    )));
                }
            }
            n += values;
        }
        let mut n = 0;
        for s in slots {
            match s {
                Slot::Shared(i) => {
                    let v = value(n)?;
                    n += 1;
                    for e in &mut self.elements {
                        e.write(i, v.clone());
                    }
                }
                Slot::PerElement(i) => {
                    for e in &mut self.elements {
                        e.write(i, value(n)?);
                        n += 1;
                    }
                }
                Slot::Size | Slot::Threads | Slot::Time => unreachable!("table slots only"),
            }
        }
        Ok(Status::Ok)
    }

    /// Writes the UInt64 parameters: the number of elements only in configuration mode, within its range
    /// (the elements' array values return to their start values), the threads as a fixed parameter.
    pub fn set_counts(&mut self, vrs: &[u32], values: &[u64]) -> Outcome {
        let (slots, count) = self.slots(vrs, None)?;
        Self::check_count(count, values.len())?;
        let arrays: &ArrayInfo = M::arrays();
        for (s, x) in slots.iter().zip(values) {
            let (c, allowed, when) = match s {
                Slot::Size => (
                    arrays.size,
                    state::SET_STRUCTURAL_PARAMETER,
                    "in configuration mode (fmi3EnterConfigurationMode after instantiation)",
                ),
                _ => (
                    arrays.threads,
                    state::SET_FIXED_PARAMETER,
                    "in the states Instantiated and InitializationMode",
                ),
            };
            if !allowed.allows(self.state) {
                return Err(Failure::Rejected(format!(
                    "{} cannot be set in state {:?}: it may be set only {when}",
                    c.name, self.state
                )));
            }
            if !(c.min..=c.max).contains(x) {
                return Err(Failure::Rejected(format!(
                    "invalid value for {}: {x} (allowed: {} to {})",
                    c.name, c.min, c.max
                )));
            }
        }
        for (s, x) in slots.into_iter().zip(values) {
            match s {
                Slot::Size if *x as usize != self.elements.len() => {
                    // a changed dimension invalidates the arrays' values (FMI 3.0 §2.4.7.1)
                    let n = *x as usize;
                    self.resize(1);
                    let table = Self::table();
                    let arrays = M::arrays();
                    let start = Values::start(table);
                    let first = &mut self.elements[0];
                    for (i, v) in table.iter().enumerate() {
                        if is_array(arrays, i, v) {
                            first.write(i, start.list()[i].clone());
                        }
                    }
                    self.resize(n);
                }
                Slot::Size => {}
                _ => self.threads = *x,
            }
        }
        Ok(Status::Ok)
    }

    /// `fmi3EnterInitializationMode`: the start time.
    pub fn enter_initialization_mode(&mut self, start_time: f64) -> Outcome {
        if !start_time.is_finite() {
            return Err(Failure::Rejected(format!(
                "start time {start_time} is not finite"
            )));
        }
        self.time = start_time;
        self.state = State::InitializationMode;
        self.log.event("entered initialization mode");
        Ok(Status::Ok)
    }

    /// `fmi3ExitInitializationMode`: computes the outputs of the current inputs; Co-Simulation is then in
    /// step mode (event mode if used), Model Exchange in event mode with this point accepted.
    pub fn exit_initialization_mode(&mut self) -> Outcome {
        let status = match self.interface {
            Interface::CoSimulation => {
                let status = self.update()?;
                self.state = match self.event_mode_used {
                    true => State::EventMode,
                    false => State::StepMode,
                };
                status
            }
            Interface::ModelExchange => {
                let status = self.accept()?;
                self.state = State::EventMode;
                status
            }
        };
        self.log.event("initialization done");
        Ok(status)
    }

    /// `fmi3EnterConfigurationMode` / `fmi3ExitConfigurationMode`.
    pub fn configuration_mode(&mut self, enter: bool) -> Outcome {
        self.state = match enter {
            true => State::ConfigurationMode,
            false => State::Instantiated,
        };
        Ok(Status::Ok)
    }

    /// `fmi3EnterEventMode`: Co-Simulation only when instantiated with event mode used.
    pub fn enter_event_mode(&mut self) -> Outcome {
        if self.interface == Interface::CoSimulation && !self.event_mode_used {
            return Err(Failure::Rejected(
                "Illegal call sequence (event mode is not used: the instance was instantiated with \
                 eventModeUsed = false)"
                    .into(),
            ));
        }
        self.state = State::EventMode;
        Ok(Status::Ok)
    }

    /// `fmi3EnterStepMode`.
    pub fn enter_step_mode(&mut self) -> Outcome {
        self.state = State::StepMode;
        Ok(Status::Ok)
    }

    /// `fmi3EnterContinuousTimeMode`: the event's values are accepted.
    pub fn enter_continuous_time_mode(&mut self) -> Outcome {
        let status = self.accept()?;
        self.state = State::ContinuousTimeMode;
        Ok(status)
    }

    /// `fmi3SetTime`.
    pub fn set_time(&mut self, time: f64) -> Outcome {
        if !time.is_finite() {
            return Err(Failure::Rejected(format!("time {time} is not finite")));
        }
        self.time = time;
        Ok(Status::Ok)
    }

    /// `fmi3DoStep`: quasi-static, so the step brings the outputs to the current inputs and advances time.
    pub fn do_step(&mut self, current: f64, step: f64) -> Outcome {
        if !(current.is_finite() && step.is_finite() && step >= 0.0) {
            return Err(Failure::Rejected(format!(
                "invalid communication point {current} or step size {step}"
            )));
        }
        let status = self.update()?;
        self.time = current + step;
        Ok(status)
    }

    /// `fmi3Terminate`.
    pub fn terminate(&mut self) -> Outcome {
        self.state = State::Terminated;
        self.log.event("terminated");
        Ok(Status::Ok)
    }

    /// `fmi3Reset`: back to Instantiated with start values (one element, the threads' start value).
    pub fn reset(&mut self) -> Outcome {
        let arrays = M::arrays();
        self.elements.clear();
        self.resize(arrays.size.start as usize);
        self.threads = arrays.threads.start;
        self.time = 0.0;
        self.state = State::Instantiated;
        self.log.event("reset");
        Ok(Status::Ok)
    }

    /// A snapshot of the instance (`fmi3GetFMUState`).
    pub fn snapshot(&self) -> Snapshot<M::State> {
        Snapshot {
            state: self.state,
            time: self.time,
            threads: self.threads,
            elements: self
                .elements
                .iter()
                .map(|e| (e.values.clone(), e.stale, e.model.state()))
                .collect(),
        }
    }

    /// Restores a snapshot (`fmi3SetFMUState`), the number of elements, the state-machine state and the
    /// models' states included; a snapshot of a state the instance's interface type does not have is
    /// refused.
    pub fn restore(&mut self, s: &Snapshot<M::State>) -> Outcome {
        if !s.state.belongs_to(self.interface) {
            return Err(Failure::Rejected(format!(
                "the FMU state was taken in state {:?}, which a {} instance does not have",
                s.state,
                self.interface.name()
            )));
        }
        self.elements.truncate(s.elements.len());
        while self.elements.len() < s.elements.len() {
            self.elements.push(Element {
                values: Values::start(Self::table()),
                stale: true,
                model: M::new(self.resources.clone()),
                times: [0.0; 2],
                thread: 0,
                evaluated: false,
            });
        }
        for (e, (values, stale, model)) in self.elements.iter_mut().zip(&s.elements) {
            e.values = values.clone();
            e.stale = *stale;
            e.model.set_state(model);
        }
        self.threads = s.threads;
        self.time = s.time;
        self.state = s.state;
        Ok(Status::Ok)
    }

    /// The table indices of `vrs` as Float64 variables of `causality` (derivatives are of Float64 outputs
    /// with respect to Float64 inputs, all arrays).
    fn derivative_indices(&self, vrs: &[u32], causality: Causality) -> Result<Vec<usize>, Failure> {
        let table = Self::table();
        vrs.iter()
            .map(|vr| match slot(table, M::arrays(), *vr, Some(Type::Real)) {
                Some(Slot::PerElement(i)) if table[i].causality == causality => Ok(i),
                _ => Err(Failure::Rejected(format!(
                    "value reference {vr} is not a Float64 {causality:?}; derivatives are provided for \
                     Float64 outputs with respect to Float64 inputs"
                ))),
            })
            .collect()
    }

    /// `fmi3GetDirectionalDerivative` (`adjoint` false: sensitivity = J·seed, seed over the knowns'
    /// elements) and `fmi3GetAdjointDerivative` (true: sensitivity = Jᵀ·seed, seed over the unknowns'
    /// elements). The elements are independent, so J is block-diagonal: element k's outputs depend on
    /// element k's inputs only; J·v of one element is the model's directional derivative, Jᵀ·w the sum of
    /// its directional derivatives along each known, weighted by w. An element whose seed is zero has zero
    /// sensitivity without an evaluation.
    pub fn derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        n_sensitivity: usize,
        adjoint: bool,
    ) -> Result<Vec<f64>, Failure> {
        let unknown_idx = self.derivative_indices(unknowns, Causality::Output)?;
        let known_idx = self.derivative_indices(knowns, Causality::Input)?;
        let n = self.elements.len();
        let (seeded, sensed) = match adjoint {
            false => (known_idx.len(), unknown_idx.len()),
            true => (unknown_idx.len(), known_idx.len()),
        };
        if seed.len() != seeded * n || n_sensitivity != sensed * n {
            return Err(Failure::Rejected(format!(
                "nSeed = {} and nSensitivity = {n_sensitivity}, but the variables hold {} and {} values",
                seed.len(),
                seeded * n,
                sensed * n
            )));
        }
        if let Some(s) = seed.iter().find(|s| !s.is_finite()) {
            return Err(Failure::Rejected(format!("seed value {s} is not finite")));
        }
        let mut sensitivity = vec![0.0; sensed * n];
        let element = M::arrays().element;
        for (k, e) in self.elements.iter_mut().enumerate() {
            // the seed of element k: the k-th value of each seeded variable
            let own: Vec<f64> = (0..seeded).map(|j| seed[j * n + k]).collect();
            if own.iter().all(|s| *s == 0.0) {
                continue;
            }
            let fail = |m: String| Failure::Rejected(format!("{element} {}: {m}", k + 1));
            let sens = match adjoint {
                false => e
                    .model
                    .directional_derivative(&e.values, &unknown_idx, &known_idx, &own, &self.log)
                    .map_err(fail)?,
                true => {
                    let mut sens = vec![0.0; known_idx.len()];
                    for (j, s) in sens.iter_mut().enumerate() {
                        let mut unit = vec![0.0; known_idx.len()];
                        unit[j] = 1.0;
                        let column = e
                            .model
                            .directional_derivative(
                                &e.values,
                                &unknown_idx,
                                &known_idx,
                                &unit,
                                &self.log,
                            )
                            .map_err(fail)?;
                        *s = column.iter().zip(&own).map(|(c, w)| c * w).sum();
                    }
                    sens
                }
            };
            for (i, x) in sens.into_iter().enumerate() {
                sensitivity[i * n + k] = x;
            }
        }
        Ok(sensitivity)
    }
}

impl<M> Element<M> {
    /// Writes value `i`; a changed value marks the outputs stale.
    fn write(&mut self, i: usize, value: Value) {
        if self.values.list()[i] != value {
            self.values.set(i, value);
            self.stale = true;
        }
    }
}

const MAGIC: &[u8; 8] = b"FMI3SNAP";
const VERSION: u32 = 1;

/// A copy of an instance's defining data (`fmi3GetFMUState`); `S` is the model's own state.
///
/// Byte layout (little-endian), format version 1: `b"FMI3SNAP"`, version u32, instantiation token (u32
/// length + UTF-8), state u16, time f64, threads u64, element count u64, then per element: stale u8, the
/// values of all variables (as in the FMI 2.0 layer's FMU state: count u32, then per variable its value),
/// the model's state; finally the FNV-1a 64 checksum of all preceding bytes (u64). Every field is checked
/// when reading.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot<S> {
    state: State,
    time: f64,
    threads: u64,
    elements: Vec<(Values, bool, S)>,
}

impl<S: ModelState> Snapshot<S> {
    /// The serialized bytes; `token` identifies the model.
    pub fn to_bytes(&self, token: &str) -> Vec<u8> {
        let mut out = begin(MAGIC, VERSION, token);
        out.extend_from_slice(&state_code(self.state).to_le_bytes());
        out.extend_from_slice(&self.time.to_le_bytes());
        out.extend_from_slice(&self.threads.to_le_bytes());
        out.extend_from_slice(&(self.elements.len() as u64).to_le_bytes());
        for (values, stale, model) in &self.elements {
            out.push(u8::from(*stale));
            put_values(&mut out, values);
            model.write(&mut out);
        }
        seal(out)
    }

    /// Reads bytes written by [`Snapshot::to_bytes`] for the same model (`arrays` bound the counts).
    pub fn from_bytes(
        bytes: &[u8],
        token: &str,
        table: &'static [crate::fmi2::variables::Variable],
        arrays: &ArrayInfo,
    ) -> Result<Snapshot<S>, String> {
        let mut r = open(bytes, MAGIC, VERSION, token, "instantiation token")?;
        let code = u16::from_le_bytes(r.array()?);
        let state = State::ALL
            .into_iter()
            .find(|s| state_code(*s) == code)
            .ok_or_else(|| format!("serialized FMU state has an unknown state code {code}"))?;
        let time = f64::from_le_bytes(r.array()?);
        let threads = u64::from_le_bytes(r.array()?);
        let count = u64::from_le_bytes(r.array()?);
        let (size, th) = (arrays.size, arrays.threads);
        if !time.is_finite()
            || !(size.min..=size.max).contains(&count)
            || !(th.min..=th.max).contains(&threads)
        {
            return Err(format!(
                "serialized FMU state is corrupt (time {time}, {count} {}s, {threads} threads)",
                arrays.element
            ));
        }
        let mut elements = Vec::with_capacity(count as usize);
        for _ in 0..count {
            let stale = r.flag()?;
            let values = r.values(table)?;
            elements.push((values, stale, S::read(&mut r)?));
        }
        if !r.at_end() {
            return Err("serialized FMU state is corrupt (trailing bytes)".into());
        }
        Ok(Snapshot {
            state,
            time,
            threads,
            elements,
        })
    }
}
