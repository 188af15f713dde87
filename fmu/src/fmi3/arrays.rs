//! A model of one element (one contact) as an FMI 3.0 instance of several: what the model says about its
//! arrays, and how the FMI 3.0 value references map onto the elements' variables.
//!
//! Every input and output of the model's variable table is an array with one value per element, dimensioned
//! by the structural parameter [`ArrayInfo::size`] (UInt64, set in configuration mode); so are the
//! parameters the model lists in [`ArrayInfo::element_parameters`]. Every other parameter is one value that
//! all elements share. [`ArrayInfo::threads`] (UInt64 parameter, 0 = the cores the process may use) is how
//! many threads evaluate the elements of a step. The value references of the table's variables are
//! those of the table; the two UInt64 parameters and the independent variable `time` have their own.

use crate::fmi2::model::Model;
use crate::fmi2::variables::{Causality, Type, Variable};

/// A UInt64 parameter of the FMI 3.0 layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count {
    /// Name.
    pub name: &'static str,
    /// Value reference (none of the variable table's).
    pub vr: u32,
    /// Start value.
    pub start: u64,
    /// Smallest allowed value.
    pub min: u64,
    /// Largest allowed value.
    pub max: u64,
    /// Description.
    pub description: &'static str,
}

/// What a model says about its FMI 3.0 arrays.
#[derive(Debug, Clone, Copy)]
pub struct ArrayInfo {
    /// The structural parameter: the number of elements.
    pub size: Count,
    /// The number of threads that evaluate the elements (0: the cores the process may use).
    pub threads: Count,
    /// The value reference of the independent variable `time` (Float64, the instance's time [s]).
    pub time_vr: u32,
    /// The parameters (table indices) that have a value per element.
    pub element_parameters: &'static [usize],
    /// What one element is called in log messages ("contact": "contact 3: …").
    pub element: &'static str,
    /// `description` of the FMI 3.0 model.
    pub description: &'static str,
}

/// A model behind the FMI 3.0 layer: a [`Model`] of one element that can run on any thread.
pub trait ArrayModel: Model + Send {
    /// The model's arrays.
    fn arrays() -> &'static ArrayInfo;
}

/// Where an FMI 3.0 value reference points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// A variable of the table (index) with one value that all elements share.
    Shared(usize),
    /// A variable of the table (index) with a value per element.
    PerElement(usize),
    /// The number of elements.
    Size,
    /// The number of threads.
    Threads,
    /// The independent variable (time).
    Time,
}

/// Whether table variable `v` (index `i`) is an array.
pub fn is_array(arrays: &ArrayInfo, i: usize, v: &Variable) -> bool {
    v.causality != Causality::Parameter || arrays.element_parameters.contains(&i)
}

/// The slot of value reference `vr` for values of type `ty` (`None`: UInt64), if any.
pub fn slot(table: &[Variable], arrays: &ArrayInfo, vr: u32, ty: Option<Type>) -> Option<Slot> {
    match ty {
        None if vr == arrays.size.vr => Some(Slot::Size),
        None if vr == arrays.threads.vr => Some(Slot::Threads),
        None => None,
        Some(Type::Real) if vr == arrays.time_vr => Some(Slot::Time),
        Some(ty) => {
            let i = table.iter().position(|v| v.vr == vr && v.ty() == ty)?;
            Some(match is_array(arrays, i, &table[i]) {
                true => Slot::PerElement(i),
                false => Slot::Shared(i),
            })
        }
    }
}

/// The FMI 3.0 type name of a table type.
pub fn type_name(ty: Option<Type>) -> &'static str {
    match ty {
        Some(Type::Real) => "Float64",
        Some(Type::Integer) => "Int32",
        Some(Type::Boolean) => "Boolean",
        Some(Type::String) => "String",
        None => "UInt64",
    }
}
