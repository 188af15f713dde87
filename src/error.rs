//! Error type of the library: every failure is a value, never a panic.

use thiserror::Error;

/// Everything that can go wrong in the model: bad input, bad parameters, numerical failure, I/O.
#[derive(Debug, Error)]
pub enum Error {
    /// An input or parameter outside its allowed range (NaN and infinities included).
    #[error("invalid value for {name}: {value} (allowed: {allowed})")]
    OutOfRange {
        /// Name of the quantity as the user spells it (TOML key or CLI flag).
        name: String,
        /// The offending value, formatted.
        value: String,
        /// The allowed range with units.
        allowed: String,
    },
    /// A parameter file that cannot be read or parsed.
    #[error("cannot read parameters from {path}: {reason}")]
    ParameterFile {
        /// The file path.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// A numerical procedure that failed outright (as opposed to an unconverged but reported result).
    #[error("numerical failure in {stage}: {reason}")]
    Numerical {
        /// Which submodel failed.
        stage: &'static str,
        /// What went wrong.
        reason: String,
    },
    /// A lookup table that cannot be built, read or used: missing or corrupt files, a format, model or
    /// parameter mismatch.
    #[error("table {path}: {reason}")]
    Table {
        /// The table directory or file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// A lookup table asked to evaluate for parameters other than those it was built for.
    #[error(
        "table {path}: was built for other parameters (fingerprint {built}, these give {given})"
    )]
    TableParameters {
        /// The table directory ("<memory>" for a table built in memory).
        path: String,
        /// Fingerprint of the parameters the table was built for.
        built: String,
        /// Fingerprint of the parameters asked for.
        given: String,
    },
    /// An evaluation mode that evaluates by lookup table, given none.
    #[error("evaluation mode {mode} needs a lookup table")]
    NoTable {
        /// The mode.
        mode: crate::model::Mode,
    },
}

/// Result alias of the library.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Builds an [`Error::OutOfRange`].
    pub fn out_of_range(name: &str, value: f64, allowed: &str) -> Self {
        Error::OutOfRange {
            name: name.to_string(),
            value: format!("{value}"),
            allowed: allowed.to_string(),
        }
    }
}

/// Checks that `value` is finite and inside `[lo, hi]`; the error names the value and the range.
pub fn check_range(name: &str, value: f64, lo: f64, hi: f64, unit: &str) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::out_of_range(
            name,
            value,
            format!("finite, {lo} ..= {hi} {unit}").trim_end(),
        ))
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn check_positive(name: &str, value: f64, unit: &str) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::out_of_range(
            name,
            value,
            format!("finite, > 0 {unit}").trim_end(),
        ))
    }
}

/// Checks that `value` is finite (any sign).
pub fn check_finite(name: &str, value: f64, unit: &str) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::out_of_range(
            name,
            value,
            format!("finite {unit}").trim_end(),
        ))
    }
}
