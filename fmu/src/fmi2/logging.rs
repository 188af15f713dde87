//! Logging through the importer's `fmi2CallbackLogger`, filtered by log category.
//!
//! Categories (declared in `modelDescription.xml`): `logEvents` (life cycle, OK status), `logStatusWarning`,
//! `logStatusError`, and `logAll` (everything). After `fmi2Instantiate(loggingOn = true)` every category is on;
//! with `loggingOn = false` only warnings and errors are passed on. `fmi2SetDebugLogging` switches categories.

use super::ffi::{Fmi2CallbackLogger, Fmi2ComponentEnvironment, Status};
use std::ffi::{CString, c_int};

/// The log categories, in `modelDescription.xml` order: (name, description).
pub const CATEGORIES: [(&str, &str); 4] = [
    (
        "logEvents",
        "Life-cycle events: instantiation, initialization, termination",
    ),
    (
        "logStatusWarning",
        "Messages with status fmi2Warning: clamped inputs, unconverged solves, fallbacks",
    ),
    (
        "logStatusError",
        "Messages with status fmi2Error: rejected calls, invalid values, failed solves",
    ),
    ("logAll", "All messages"),
];

const ALL: usize = 3;

fn category_of(status: Status) -> usize {
    match status {
        Status::Ok => 0,
        Status::Warning => 1,
        _ => 2,
    }
}

/// Where messages go: the importer's logger, or (in Rust tests) a closure.
pub type Sink = Box<dyn Fn(Status, &str, &str)>;

/// Builds a sink from the importer's C logger. The logger is variadic; it is called with the format `"%s"` and
/// the message, so that `%` in messages is harmless.
pub fn c_sink(
    logger: Fmi2CallbackLogger,
    environment: Fmi2ComponentEnvironment,
    instance_name: &str,
) -> Option<Sink> {
    let f = logger?;
    let name = to_c_string(instance_name);
    let env = environment as usize;
    Some(Box::new(
        move |status: Status, category: &str, message: &str| {
            let category = to_c_string(category);
            let message = to_c_string(message);
            // SAFETY: the importer guarantees that `logger` and its environment stay valid while the instance
            // lives; every string passed is NUL-terminated and outlives the call.
            unsafe {
                f(
                    env as Fmi2ComponentEnvironment,
                    name.as_ptr(),
                    status as c_int,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    message.as_ptr(),
                )
            }
        },
    ))
}

/// A C string of `text` with interior NUL bytes dropped.
pub fn to_c_string(text: &str) -> CString {
    CString::new(text.replace('\0', "")).expect("NUL bytes were removed")
}

/// A kept message: status, category, text.
pub type Message = (Status, String, String);

/// The categories a logger passes on (see [`Logger::keeping`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Categories([bool; 4]);

/// The messages a [`Logger::keeping`] kept.
#[derive(Default, Clone)]
pub struct Kept(std::rc::Rc<std::cell::RefCell<Vec<Message>>>);

impl Kept {
    /// The messages kept so far, which are forgotten here.
    pub fn take(&self) -> Vec<Message> {
        std::mem::take(&mut self.0.borrow_mut())
    }
}

/// The logging state of one instance.
pub struct Logger {
    sink: Option<Sink>,
    enabled: [bool; 4],
}

impl Logger {
    /// A logger with all categories on (`logging_on`) or only warnings and errors.
    pub fn new(sink: Option<Sink>, logging_on: bool) -> Logger {
        Logger {
            sink,
            enabled: [logging_on, true, true, logging_on],
        }
    }

    /// `fmi2SetDebugLogging`: with no categories, switches all; otherwise the named ones. An unknown name is
    /// an error that changes nothing.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Result<(), String> {
        if categories.is_empty() {
            self.enabled = [on; 4];
            return Ok(());
        }
        let mut idx = Vec::with_capacity(categories.len());
        for c in categories {
            match CATEGORIES.iter().position(|(n, _)| n == c) {
                Some(i) => idx.push(i),
                None => return Err(format!("unknown log category \"{c}\"")),
            }
        }
        for i in idx {
            self.enabled[i] = on;
        }
        Ok(())
    }

    /// Logs `message` under the category of `status`, if that category (or logAll) is on. `#` is doubled,
    /// since FMI loggers read `#<type><vr>#` as a variable reference.
    pub fn log(&self, status: Status, message: &str) {
        let cat = category_of(status);
        if let Some(sink) = &self.sink
            && (self.enabled[cat] || self.enabled[ALL])
        {
            sink(status, CATEGORIES[cat].0, &message.replace('#', "##"));
        }
    }

    /// A logger with this one's categories that keeps its messages instead of passing them on: made for a
    /// computation on another thread (a sink is not sent between threads), where the messages are taken
    /// with [`Kept::take`] and passed on later by [`Logger::forward`].
    pub fn keeping(enabled: Categories) -> (Logger, Kept) {
        let kept = Kept::default();
        let k = kept.clone();
        let sink: Sink = Box::new(move |status, category, message| {
            k.0.borrow_mut()
                .push((status, category.to_string(), message.to_string()))
        });
        (
            Logger {
                sink: Some(sink),
                enabled: enabled.0,
            },
            kept,
        )
    }

    /// The categories switched on, for [`Logger::keeping`].
    pub fn categories(&self) -> Categories {
        Categories(self.enabled)
    }

    /// Passes on messages a [`Logger::keeping`] kept (already filtered and escaped), each prefixed by
    /// `prefix`.
    pub fn forward(&self, messages: &[Message], prefix: &str) {
        if let Some(sink) = &self.sink {
            for (status, category, message) in messages {
                sink(*status, category, &format!("{prefix}{message}"));
            }
        }
    }

    /// A life-cycle event (`logEvents`).
    pub fn event(&self, message: &str) {
        self.log(Status::Ok, message);
    }

    /// A warning (`logStatusWarning`).
    pub fn warning(&self, message: &str) {
        self.log(Status::Warning, message);
    }

    /// An error (`logStatusError`).
    pub fn error(&self, message: &str) {
        self.log(Status::Error, message);
    }
}

#[cfg(test)]
pub mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::rc::Rc;

    /// Messages collected as (status, category, message).
    pub type Captured = Rc<RefCell<Vec<(Status, String, String)>>>;

    /// A logger whose messages are collected.
    pub fn capturing(logging_on: bool) -> (Logger, Captured) {
        let seen = Rc::new(RefCell::new(Vec::new()));
        let s = seen.clone();
        let sink: Sink = Box::new(move |st, cat, msg| {
            s.borrow_mut().push((st, cat.to_string(), msg.to_string()))
        });
        (Logger::new(Some(sink), logging_on), seen)
    }

    #[test]
    fn categories_filter_messages() {
        let (mut log, seen) = capturing(false);
        log.event("hidden");
        log.warning("w");
        log.error("e #1");
        assert_eq!(seen.borrow().len(), 2);
        assert_eq!(seen.borrow()[0].1, "logStatusWarning");
        assert_eq!(
            seen.borrow()[1],
            (Status::Error, "logStatusError".into(), "e ##1".into())
        );
        log.set_debug_logging(true, &["logEvents"]).unwrap();
        log.event("shown");
        assert_eq!(seen.borrow().last().unwrap().2, "shown");
        log.set_debug_logging(false, &[]).unwrap();
        log.error("hidden too");
        assert_eq!(seen.borrow().len(), 3);
        log.set_debug_logging(true, &["logAll"]).unwrap();
        log.event("all");
        assert_eq!(seen.borrow().len(), 4);
        assert!(
            log.set_debug_logging(true, &["logEvents", "nonsense"])
                .unwrap_err()
                .contains("nonsense")
        );
    }
}
