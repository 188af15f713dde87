//! The variable table of a model (the single source of `modelDescription.xml` and of get/set by value
//! reference) and the instance's current values.

/// FMI 2.0 `causality`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    /// Set by the importer before initialization, constant afterwards.
    Parameter,
    /// Set by the importer at every communication point.
    Input,
    /// Computed by the model.
    Output,
}

/// FMI 2.0 `variability`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    /// Fixed after initialization.
    Fixed,
    /// Changes only at communication points (Integer, Boolean, String values).
    Discrete,
    /// Real values that may change continuously.
    Continuous,
}

/// Type-specific attributes of a variable; `start` is `None` exactly for outputs (`initial="calculated"`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// `<Real>`.
    Real {
        /// Unit name, defined in [`Unit`] of the model.
        unit: &'static str,
        /// Start value.
        start: Option<f64>,
        /// Smallest allowed value.
        min: Option<f64>,
        /// Largest allowed value.
        max: Option<f64>,
        /// Nominal magnitude (scales finite-difference steps).
        nominal: Option<f64>,
    },
    /// `<Integer>`.
    Integer {
        /// Start value.
        start: Option<i32>,
        /// Smallest allowed value.
        min: Option<i32>,
        /// Largest allowed value.
        max: Option<i32>,
    },
    /// `<Boolean>`.
    Boolean {
        /// Start value.
        start: Option<bool>,
    },
    /// `<String>`.
    String {
        /// Start value.
        start: Option<&'static str>,
    },
}

/// One row of the variable table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variable {
    /// Name (flat naming convention).
    pub name: &'static str,
    /// Value reference.
    pub vr: u32,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// Type, unit, start and range.
    pub kind: Kind,
    /// Description (units and sign conventions included).
    pub description: &'static str,
}

/// The type of a variable, for messages and type checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type {
    /// fmi2Real.
    Real,
    /// fmi2Integer.
    Integer,
    /// fmi2Boolean.
    Boolean,
    /// fmi2String.
    String,
}

impl Type {
    /// The FMI type name.
    pub fn name(self) -> &'static str {
        match self {
            Type::Real => "Real",
            Type::Integer => "Integer",
            Type::Boolean => "Boolean",
            Type::String => "String",
        }
    }
}

impl Variable {
    /// The variable's type.
    pub fn ty(&self) -> Type {
        match self.kind {
            Kind::Real { .. } => Type::Real,
            Kind::Integer { .. } => Type::Integer,
            Kind::Boolean { .. } => Type::Boolean,
            Kind::String { .. } => Type::String,
        }
    }

    /// The nominal magnitude of a Real variable (1 when not declared).
    pub fn nominal(&self) -> f64 {
        match self.kind {
            Kind::Real {
                nominal: Some(n), ..
            } => n,
            _ => 1.0,
        }
    }
}

/// One value.
#[derive(Debug, Clone)]
pub enum Value {
    /// A Real.
    Real(f64),
    /// An Integer.
    Integer(i32),
    /// A Boolean.
    Boolean(bool),
    /// A String.
    String(String),
}

/// Values are equal when they are the same bits (a Real NaN equals itself: an output may be NaN, and
/// values are compared as cache keys and FMU states).
impl PartialEq for Value {
    fn eq(&self, other: &Value) -> bool {
        match (self, other) {
            (Value::Real(a), Value::Real(b)) => a.to_bits() == b.to_bits(),
            (Value::Integer(a), Value::Integer(b)) => a == b,
            (Value::Boolean(a), Value::Boolean(b)) => a == b,
            (Value::String(a), Value::String(b)) => a == b,
            _ => false,
        }
    }
}

impl Value {
    /// The value's type.
    pub fn kind(&self) -> Type {
        match self {
            Value::Real(_) => Type::Real,
            Value::Integer(_) => Type::Integer,
            Value::Boolean(_) => Type::Boolean,
            Value::String(_) => Type::String,
        }
    }
}

/// The current values of all variables, in table order.
#[derive(Debug, Clone)]
pub struct Values {
    table: &'static [Variable],
    values: Vec<Value>,
    /// Whether every variable's value reference is its table index (then [`Values::index_of`] looks a
    /// reference up directly instead of searching the table).
    indexed: bool,
    /// [`Values::parameters_stamp`].
    parameters: u64,
}

/// Values are equal when every variable's is (whatever their parameters' stamps).
impl PartialEq for Values {
    fn eq(&self, other: &Values) -> bool {
        self.table == other.table && self.values == other.values
    }
}

/// The last stamp handed out ([`Values::parameters_stamp`]).
static PARAMETER_STAMPS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// A stamp no values have had.
fn new_stamp() -> u64 {
    PARAMETER_STAMPS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1
}

/// Whether every variable of `table` has its table index as value reference.
fn indexed(table: &[Variable]) -> bool {
    table.iter().enumerate().all(|(i, v)| v.vr as usize == i)
}

impl Values {
    /// Every variable at its start value (outputs: zero, false or empty).
    pub fn start(table: &'static [Variable]) -> Values {
        let values = table
            .iter()
            .map(|v| match v.kind {
                Kind::Real { start, .. } => Value::Real(start.unwrap_or(0.0)),
                Kind::Integer { start, .. } => Value::Integer(start.unwrap_or(0)),
                Kind::Boolean { start } => Value::Boolean(start.unwrap_or(false)),
                Kind::String { start } => Value::String(start.unwrap_or("").to_string()),
            })
            .collect();
        Values {
            table,
            values,
            indexed: indexed(table),
            parameters: new_stamp(),
        }
    }

    /// Builds values from a list in table order; the types must match the table.
    pub fn from_list(table: &'static [Variable], values: Vec<Value>) -> Option<Values> {
        let ok = values.len() == table.len()
            && table.iter().zip(&values).all(|(var, val)| {
                matches!(
                    (var.ty(), val),
                    (Type::Real, Value::Real(_))
                        | (Type::Integer, Value::Integer(_))
                        | (Type::Boolean, Value::Boolean(_))
                        | (Type::String, Value::String(_))
                )
            });
        ok.then(|| Values {
            table,
            values,
            indexed: indexed(table),
            parameters: new_stamp(),
        })
    }

    /// A stamp of the parameters' values: new for every new set of values (start values, a list) and
    /// whenever a parameter is set, kept by copies. So equal stamps mean equal parameters, and a model's
    /// caches of what its parameters determine compare the stamp instead of the values every step.
    pub fn parameters_stamp(&self) -> u64 {
        self.parameters
    }

    /// The variable table.
    pub fn table(&self) -> &'static [Variable] {
        self.table
    }

    /// All values in table order.
    pub fn list(&self) -> &[Value] {
        &self.values
    }

    /// The table index of a value reference of the given type.
    pub fn index_of(&self, vr: u32, ty: Type) -> Option<usize> {
        if self.indexed {
            let i = vr as usize;
            return self.table.get(i).filter(|v| v.ty() == ty).map(|_| i);
        }
        self.table.iter().position(|v| v.vr == vr && v.ty() == ty)
    }

    /// The Real at table index `i`.
    ///
    /// # Panics
    /// If variable `i` is not a Real (a bug in the model's variable table, caught by its tests).
    pub fn real(&self, i: usize) -> f64 {
        match self.values[i] {
            Value::Real(x) => x,
            _ => panic!("variable {} is not a Real", self.table[i].name),
        }
    }

    /// The Integer at table index `i` (panics like [`Values::real`]).
    pub fn integer(&self, i: usize) -> i32 {
        match self.values[i] {
            Value::Integer(x) => x,
            _ => panic!("variable {} is not an Integer", self.table[i].name),
        }
    }

    /// The Boolean at table index `i` (panics like [`Values::real`]).
    pub fn boolean(&self, i: usize) -> bool {
        match self.values[i] {
            Value::Boolean(x) => x,
            _ => panic!("variable {} is not a Boolean", self.table[i].name),
        }
    }

    /// The String at table index `i` (panics like [`Values::real`]).
    pub fn string(&self, i: usize) -> &str {
        match &self.values[i] {
            Value::String(x) => x,
            _ => panic!("variable {} is not a String", self.table[i].name),
        }
    }

    /// Replaces the value at table index `i` (panics if the type differs from the table's); a parameter's
    /// renews the parameters' stamp. Always inlined: where the new value's type is known, the check and the
    /// old value's drop reduce to one comparison (out of line, a step's fourteen calls cost ~700
    /// instructions).
    #[inline(always)]
    pub fn set(&mut self, i: usize, value: Value) {
        assert!(
            std::mem::discriminant(&self.values[i]) == std::mem::discriminant(&value),
            "type mismatch writing {}",
            self.table[i].name
        );
        self.values[i] = value;
        if self.table[i].causality == Causality::Parameter {
            self.new_parameters();
        }
    }

    /// A new [`Values::parameters_stamp`] (out of line: parameters are set rarely, values every step).
    #[cold]
    #[inline(never)]
    fn new_parameters(&mut self) {
        self.parameters = new_stamp();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static TABLE: [Variable; 3] = [
        Variable {
            name: "u",
            vr: 7,
            causality: Causality::Input,
            variability: Variability::Continuous,
            kind: Kind::Real {
                unit: "m",
                start: Some(2.0),
                min: None,
                max: None,
                nominal: Some(0.5),
            },
            description: "input",
        },
        Variable {
            name: "n",
            vr: 7,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            kind: Kind::Integer {
                start: Some(3),
                min: None,
                max: None,
            },
            description: "same vr, other type",
        },
        Variable {
            name: "s",
            vr: 1,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            kind: Kind::String { start: None },
            description: "text",
        },
    ];

    #[test]
    fn value_references_are_resolved_per_type() {
        let v = Values::start(&TABLE);
        assert_eq!(v.index_of(7, Type::Real), Some(0));
        assert_eq!(v.index_of(7, Type::Integer), Some(1));
        assert_eq!(v.index_of(7, Type::Boolean), None);
        assert_eq!(v.real(0), 2.0);
        assert_eq!(v.integer(1), 3);
        assert_eq!(v.string(2), "");
        assert_eq!(TABLE[0].nominal(), 0.5);
        assert_eq!(TABLE[1].nominal(), 1.0);
    }

    /// A table whose value references are its indices is looked up directly, with the same answers as the
    /// search: the reference's own type only, nothing beyond the table.
    #[test]
    fn indexed_tables_resolve_references_directly() {
        static INDEXED: [Variable; 2] = [
            Variable { vr: 0, ..TABLE[2] },
            Variable { vr: 1, ..TABLE[0] },
        ];
        let v = Values::start(&INDEXED);
        assert!(v.indexed && !Values::start(&TABLE).indexed);
        assert_eq!(v.index_of(0, Type::String), Some(0));
        assert_eq!(v.index_of(1, Type::Real), Some(1));
        assert_eq!(v.index_of(1, Type::String), None);
        assert_eq!(v.index_of(2, Type::Real), None);
    }

    /// The parameters' stamp: new for new values and for every parameter set, not for an input; kept by a
    /// copy; equality of values ignores it.
    #[test]
    fn parameters_stamp_changes_with_the_parameters_only() {
        let mut v = Values::start(&TABLE);
        let other = Values::start(&TABLE);
        assert_ne!(v.parameters_stamp(), other.parameters_stamp());
        assert_eq!(v, other);
        let stamp = v.parameters_stamp();
        v.set(0, Value::Real(5.0));
        assert_eq!(v.parameters_stamp(), stamp, "an input");
        let copy = v.clone();
        assert_eq!(copy.parameters_stamp(), stamp);
        v.set(1, Value::Integer(4));
        assert_ne!(v.parameters_stamp(), stamp, "a parameter");
        let stamp = v.parameters_stamp();
        v.set(2, Value::String("t".into()));
        assert_ne!(v.parameters_stamp(), stamp, "another parameter");
        let listed = Values::from_list(&TABLE, v.list().to_vec()).unwrap();
        assert_ne!(listed.parameters_stamp(), v.parameters_stamp());
        assert_eq!(listed, v);
    }

    #[test]
    fn from_list_checks_length_and_types() {
        let good = vec![
            Value::Real(1.0),
            Value::Integer(1),
            Value::String("x".into()),
        ];
        assert!(Values::from_list(&TABLE, good).is_some());
        let wrong_type = vec![
            Value::Real(1.0),
            Value::Real(1.0),
            Value::String("x".into()),
        ];
        assert!(Values::from_list(&TABLE, wrong_type).is_none());
        assert!(Values::from_list(&TABLE, vec![Value::Real(1.0)]).is_none());
    }
}
