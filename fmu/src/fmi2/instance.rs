//! One FMU instance: its state, values, logger and model, and the rules for reading and writing values.

use super::ffi::Status;
use super::logging::Logger;
use super::model::Model;
use super::snapshot::Snapshot;
use super::state::{self, Interface, State};
use super::variables::{Causality, Type, Value, Values};
use std::ffi::CString;

/// Why a call failed.
#[derive(Debug, Clone, PartialEq)]
pub enum Failure {
    /// The call was refused and changed nothing (bad argument, illegal value, unknown reference).
    Rejected(String),
    /// A model computation failed: the instance enters the Error state (`fmi2Error` semantics: only
    /// inquiries, `fmi2SetFMUstate`, `fmi2Reset` and `fmi2FreeInstance` remain).
    Failed(String),
}

/// The result of a call: the status to return, or why it failed.
pub type Outcome = Result<Status, Failure>;

/// An FMU instance.
pub struct Instance<M: Model> {
    /// The instance name given at instantiation.
    pub name: String,
    /// The interface type it was instantiated as.
    pub interface: Interface,
    /// State-machine state.
    pub state: State,
    /// Logging.
    pub log: Logger,
    values: Values,
    stale: bool,
    time: f64,
    last_step: Status,
    model: M,
    strings: Vec<CString>,
}

impl<M: Model> Instance<M> {
    /// A new instance of `interface` in the Instantiated state, all variables at their start values.
    pub fn new(name: String, interface: Interface, log: Logger, model: M) -> Instance<M> {
        Instance {
            name,
            interface,
            state: State::Instantiated,
            log,
            values: Values::start(M::info().variables),
            stale: true,
            time: 0.0,
            last_step: Status::Ok,
            model,
            strings: Vec::new(),
        }
    }

    /// The current values (for inspection).
    pub fn values(&self) -> &Values {
        &self.values
    }

    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The current time [s]: the communication time (Co-Simulation) or that of `fmi2SetTime` (Model
    /// Exchange).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The status of the last `fmi2DoStep`.
    pub fn last_step_status(&self) -> Status {
        self.last_step
    }

    fn index(&self, vr: u32, ty: Type) -> Result<usize, Failure> {
        self.values.index_of(vr, ty).ok_or_else(|| {
            Failure::Rejected(format!(
                "no {} variable has value reference {vr}",
                ty.name()
            ))
        })
    }

    /// Recomputes the outputs if values changed since the last computation: in Co-Simulation by
    /// [`Model::calculate`], in Model Exchange by [`Model::calculate_trial`] (a function of the values and
    /// the model's state, which only [`Instance::accept`] advances).
    pub fn update(&mut self) -> Outcome {
        if !self.stale {
            return Ok(Status::Ok);
        }
        let status = match self.interface {
            Interface::CoSimulation => self.model.calculate(&mut self.values, &self.log),
            Interface::ModelExchange => self.model.calculate_trial(&mut self.values, &self.log),
        }
        .map_err(Failure::Failed)?;
        self.stale = false;
        Ok(status)
    }

    /// Model Exchange: accepts the current point (after initialization, at `fmi2EnterContinuousTimeMode`
    /// and `fmi2CompletedIntegratorStep`): brings the outputs to the current values and advances the
    /// model's state as [`Model::calculate`] at these values would ([`Model::accept`]).
    pub fn accept(&mut self) -> Outcome {
        let status = self.update()?;
        let accepted = self
            .model
            .accept(&self.values, &self.log)
            .map_err(Failure::Failed)?;
        Ok(status.max(accepted))
    }

    /// Reads values of one type, handing the k-th to `out(k, value)`. In initialization mode, at
    /// communication points and in the Model Exchange event and continuous-time modes, stale outputs are
    /// recomputed first, so that outputs always belong to the current inputs. Every value reference is
    /// checked before any value is handed out; nothing is allocated (a master calls this every step).
    pub fn get(
        &mut self,
        vrs: &[u32],
        ty: Type,
        mut out: impl FnMut(usize, &Value),
    ) -> Result<Status, Failure> {
        let mut wants_output = false;
        for vr in vrs {
            let i = self.index(*vr, ty)?;
            wants_output |= self.values.table()[i].causality == Causality::Output;
        }
        let status = if wants_output
            && matches!(
                self.state,
                State::InitializationMode
                    | State::StepComplete
                    | State::EventMode
                    | State::ContinuousTimeMode
            ) {
            self.update()?
        } else {
            Status::Ok
        };
        for (k, vr) in vrs.iter().enumerate() {
            out(k, &self.values.list()[self.index(*vr, ty)?]);
        }
        Ok(status)
    }

    /// Reads Strings; the returned pointers stay valid until the next `fmi2GetString` of this instance.
    pub fn get_strings(
        &mut self,
        vrs: &[u32],
    ) -> Result<(Vec<*const std::ffi::c_char>, Status), Failure> {
        let mut strings = Vec::with_capacity(vrs.len());
        let status = self.get(vrs, Type::String, |_, v| match v {
            Value::String(s) => strings.push(super::logging::to_c_string(s)),
            _ => unreachable!("get hands out values of the requested type"),
        })?;
        self.strings = strings;
        Ok((self.strings.iter().map(|s| s.as_ptr()).collect(), status))
    }

    /// Writes values: every value is checked first (known reference, settable causality in this state,
    /// finite Reals); one bad value rejects the whole call. Changing any value marks the outputs stale.
    /// `value(k)` converts the k-th value of the call (called twice per value: to check, then to write; so
    /// the call allocates nothing for numbers).
    pub fn set(&mut self, vrs: &[u32], value: impl Fn(usize) -> Result<Value, Failure>) -> Outcome {
        let table = self.values.table();
        for (k, vr) in vrs.iter().enumerate() {
            let value = value(k)?;
            let var = &table[self.index(*vr, value.kind())?];
            match var.causality {
                Causality::Output => {
                    return Err(Failure::Rejected(format!(
                        "{} is an output and cannot be set",
                        var.name
                    )));
                }
                Causality::Parameter if !state::SET_FIXED_PARAMETER.allows(self.state) => {
                    return Err(Failure::Rejected(format!(
                        "parameter {} is fixed after initialization",
                        var.name
                    )));
                }
                _ => {}
            }
            if let Value::Real(x) = value
                && !x.is_finite()
            {
                return Err(Failure::Rejected(format!(
                    "{} = {x} is not a finite number",
                    var.name
                )));
            }
        }
        for (k, vr) in vrs.iter().enumerate() {
            let value = value(k)?;
            let i = self.index(*vr, value.kind())?;
            if self.values.list()[i] != value {
                self.values.set(i, value);
                self.stale = true;
            }
        }
        Ok(Status::Ok)
    }

    /// `fmi2SetupExperiment`: the start time.
    pub fn setup_experiment(&mut self, start_time: f64) -> Outcome {
        if !start_time.is_finite() {
            return Err(Failure::Rejected(format!(
                "start time {start_time} is not finite"
            )));
        }
        self.time = start_time;
        Ok(Status::Ok)
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self) -> Outcome {
        self.state = State::InitializationMode;
        self.log.event("entered initialization mode");
        Ok(Status::Ok)
    }

    /// `fmi2ExitInitializationMode`: computes the outputs of the current inputs; a Co-Simulation instance
    /// is then at its first communication point, a Model Exchange instance in event mode with this point
    /// accepted.
    pub fn exit_initialization_mode(&mut self) -> Outcome {
        let status = match self.interface {
            Interface::CoSimulation => {
                let status = self.update()?;
                self.state = State::StepComplete;
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

    /// `fmi2SetTime`.
    pub fn set_time(&mut self, time: f64) -> Outcome {
        if !time.is_finite() {
            return Err(Failure::Rejected(format!("time {time} is not finite")));
        }
        self.time = time;
        Ok(Status::Ok)
    }

    /// `fmi2EnterEventMode`.
    pub fn enter_event_mode(&mut self) -> Outcome {
        self.state = State::EventMode;
        Ok(Status::Ok)
    }

    /// `fmi2EnterContinuousTimeMode`: the event's values are accepted.
    pub fn enter_continuous_time_mode(&mut self) -> Outcome {
        let status = self.accept()?;
        self.state = State::ContinuousTimeMode;
        Ok(status)
    }

    /// `fmi2DoStep`: quasi-static, so the step brings the outputs to the current inputs and advances time.
    pub fn do_step(&mut self, current: f64, step: f64) -> Outcome {
        if !(current.is_finite() && step.is_finite() && step >= 0.0) {
            return Err(Failure::Rejected(format!(
                "invalid communication point {current} or step size {step}"
            )));
        }
        let status = self.update()?;
        self.time = current + step;
        self.last_step = status;
        Ok(status)
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Outcome {
        self.state = State::Terminated;
        self.log.event("terminated");
        Ok(Status::Ok)
    }

    /// `fmi2Reset`: back to Instantiated with start values.
    pub fn reset(&mut self) -> Outcome {
        self.values = Values::start(M::info().variables);
        self.stale = true;
        self.time = 0.0;
        self.last_step = Status::Ok;
        self.model.reset();
        self.state = State::Instantiated;
        self.log.event("reset");
        Ok(Status::Ok)
    }

    /// A snapshot of the instance (`fmi2GetFMUstate`).
    pub fn snapshot(&self) -> Snapshot<M::State> {
        Snapshot {
            values: self.values.clone(),
            stale: self.stale,
            time: self.time,
            state: self.state,
            model: self.model.state(),
        }
    }

    /// Restores a snapshot (`fmi2SetFMUstate`), state-machine state and the model's state included. A
    /// snapshot taken in a state of the other interface type's time integration (e.g. of a Co-Simulation
    /// instance at a communication point, into a Model Exchange instance) is refused.
    pub fn restore(&mut self, s: &Snapshot<M::State>) -> Outcome {
        if !s.state.belongs_to(self.interface) {
            return Err(Failure::Rejected(format!(
                "the FMU state was taken in state {:?}, which a {} instance does not have",
                s.state,
                self.interface.name()
            )));
        }
        self.values = s.values.clone();
        self.stale = s.stale;
        self.time = s.time;
        self.state = s.state;
        self.model.set_state(&s.model);
        Ok(Status::Ok)
    }

    /// `fmi2GetDirectionalDerivative`: Real outputs with respect to Real inputs at the current values.
    pub fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
    ) -> Result<Vec<f64>, Failure> {
        let table = self.values.table();
        let pick = |vrs: &[u32], causality: Causality| -> Result<Vec<usize>, Failure> {
            vrs.iter()
                .map(|vr| {
                    self.values
                        .index_of(*vr, Type::Real)
                        .filter(|i| table[*i].causality == causality)
                        .ok_or_else(|| {
                            Failure::Rejected(format!(
                                "value reference {vr} is not a Real {causality:?}; derivatives are provided for Real \
                                 outputs with respect to Real inputs"
                            ))
                        })
                })
                .collect()
        };
        let unknown_idx = pick(unknowns, Causality::Output)?;
        let known_idx = pick(knowns, Causality::Input)?;
        if let Some(s) = seed.iter().find(|s| !s.is_finite()) {
            return Err(Failure::Rejected(format!("seed value {s} is not finite")));
        }
        self.model
            .directional_derivative(&self.values, &unknown_idx, &known_idx, seed, &self.log)
            .map_err(Failure::Rejected)
    }
}
