//! Error type of the library: every failure is a value, never a panic.

use crate::params::Key;
use thiserror::Error;

/// Everything that can go wrong in the model: bad input, bad parameters, numerical failure, I/O.
#[derive(Debug, Error)]
pub enum Error {
    /// A value outside its allowed range that is not a parameter or input of the specification (a
    /// function's argument, a command-line option), named by a plain name.
    #[error("invalid value for {name}: {value} (allowed: {allowed})")]
    OutOfRange {
        /// Name of the quantity as the user spells it (TOML key or CLI flag).
        name: String,
        /// The offending value, formatted.
        value: String,
        /// The allowed range with units.
        allowed: String,
    },
    /// A parameter or operating-point input outside its allowed range (NaN and infinities included),
    /// named by its typed key (displayed as its TOML key or, for an input, its command-line flag).
    #[error("invalid value for {key}: {value} (allowed: {allowed})")]
    Invalid {
        /// Which parameter or input.
        key: Key,
        /// The offending value.
        value: f64,
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
        stage: Stage,
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
    /// A contact outside the geometry axes of a lookup table (mode table-only).
    #[error(
        "table {path}: the contact (a/b = {ratio}, p_ref = {reference_pressure} Pa) lies outside the contact \
         geometries it covers ({covered})"
    )]
    TableGeometry {
        /// The table directory ("<memory>" for a table built in memory).
        path: String,
        /// a/b of the contact [-].
        ratio: f64,
        /// p_ref of the contact [Pa] (in a table by similarity that of its equivalent at F_ref: its p0).
        reference_pressure: f64,
        /// The ranges the table covers.
        covered: String,
    },
    /// An evaluation mode that evaluates by lookup table, given none.
    #[error("evaluation mode {mode} needs a lookup table")]
    NoTable {
        /// The mode.
        mode: crate::model::Mode,
    },
}

/// The submodel or procedure in which a numerical failure happened ([`Error::Numerical`]); its text
/// (Display) names it in error messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Hertz contact: the ellipse from the gap curvatures.
    Hertz,
    /// Microcontact: the separation that carries a nominal pressure.
    Microcontact,
    /// The interfacial fluid film.
    Fluid,
    /// The heat model's setup on a contact grid.
    ThermalModel,
    /// The heat partition between wheel and rail.
    ThermalPartition,
    /// The heat model's convolution kernels and strip solver.
    ThermalConvolution,
    /// One moving-source influence coefficient.
    ThermalInfluenceCoefficient,
    /// The table of moving-source influence coefficients of a grid.
    ThermalInfluenceMatrix,
    /// The reproduction of the paper's figures.
    Reproduction,
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stage::Hertz => "hertz",
            Stage::Microcontact => "microcontact",
            Stage::Fluid => "fluid",
            Stage::ThermalModel => "thermal model",
            Stage::ThermalPartition => "thermal partition",
            Stage::ThermalConvolution => "thermal convolution",
            Stage::ThermalInfluenceCoefficient => "thermal influence coefficient",
            Stage::ThermalInfluenceMatrix => "thermal influence matrix",
            Stage::Reproduction => "reproduction",
        })
    }
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
#[inline]
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
#[inline]
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
#[inline]
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

#[cfg(test)]
mod stage_tests {
    use super::*;

    /// The stage texts of the error messages (unchanged from when stages were strings).
    #[test]
    fn numerical_errors_name_their_stage() {
        for (stage, text) in [
            (Stage::Hertz, "hertz"),
            (Stage::Microcontact, "microcontact"),
            (Stage::Fluid, "fluid"),
            (Stage::ThermalModel, "thermal model"),
            (Stage::ThermalPartition, "thermal partition"),
            (Stage::ThermalConvolution, "thermal convolution"),
            (
                Stage::ThermalInfluenceCoefficient,
                "thermal influence coefficient",
            ),
            (Stage::ThermalInfluenceMatrix, "thermal influence matrix"),
            (Stage::Reproduction, "reproduction"),
        ] {
            let e = Error::Numerical {
                stage,
                reason: "why".into(),
            };
            assert_eq!(e.to_string(), format!("numerical failure in {text}: why"));
        }
    }
}
