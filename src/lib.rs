//! # wheelrail
//!
//! The Tomberger–Dietmaier–Sextro–Six wheel–rail friction model (Wear 271, 2011): Hertz contact, Greenwood–
//! Williamson/Zhao–Maietta–Chang microcontact, temperature-dependent failure stress, FASTSIM with locally
//! varying adhesion limit, moving-source contact temperature and an interfacial fluid, solved as one coupled
//! fixed point. SI units throughout; temperatures in kelvin. See `README.md` for conventions.
//!
//! Entry points: [`Model`] (a validated parameter set: `solve`, `solve_from`, `sweep`) and
//! [`model::Evaluator`], the evaluation policy that the FMU and the command line share (lookup table or
//! exact solver, lifted wheel, rolling backwards, standstill); `model` describes the data path of one
//! evaluation.

#![warn(missing_docs)]

pub mod baselines;
pub mod contact;
pub mod error;
pub mod fluid;
pub(crate) mod friction;
pub mod materials;
pub mod microcontact;
pub mod model;
pub mod params;
pub mod quadrature;
pub mod solver;
pub mod table;
pub mod tangential;
pub mod thermal;

pub use error::{Error, Result};
pub use model::Model;
pub use params::{FrictionLaw, OperatingPoint, Params, Pressure, Tangential};
pub use solver::{Solution, solve, solve_from};
