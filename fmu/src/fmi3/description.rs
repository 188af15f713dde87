//! `modelDescription.xml` of FMI 3.0 (schema `fmi3ModelDescription.xsd`) generated from the same
//! [`ModelInfo`] as FMI 2.0's, with the model's [`ArrayInfo`], and the instantiation token.
//!
//! The one binary serves both interface types: `<ModelExchange>` and `<CoSimulation>` with the same
//! `modelIdentifier`. Capability flags: FMU states (get, set, serialize), directional and adjoint
//! derivatives, variable communication step size, Co-Simulation event mode (`hasEventMode`: there are no
//! events, it may be used) are provided; `needsCompletedIntegratorStep` is true (it accepts the point:
//! the warm start advances); no per-element dependencies, output derivatives, intermediate update or early
//! return.
//!
//! Variables: FMI 2.0 Real → `<Float64>`, Integer → `<Int32>`, Boolean → `<Boolean>`, String → `<String>`
//! with the same names, value references, units, display units, start values and ranges; inputs, outputs
//! and the per-element parameters carry `<Dimension valueReference="…"/>` of the structural parameter (a
//! single start value applies to every element, FMI 3.0 §2.4.7.5). `ModelStructure`: every output depends
//! on every input (direct feedthrough, no states), by value reference; the initial unknowns are the outputs.

use super::arrays::{ArrayInfo, Count, is_array};
use crate::fmi2::description::{categories_and_experiment, esc, real, unit_definitions, uuid_of};
use crate::fmi2::model::ModelInfo;
use crate::fmi2::variables::{Causality, Kind, Variability, Variable};
use std::fmt::Write;

fn variable_xml(out: &mut String, v: &Variable, array: Option<u32>, display_unit: Option<&str>) {
    let causality = match v.causality {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    };
    let variability = match v.variability {
        Variability::Fixed => "fixed",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    };
    let initial = match v.causality {
        Causality::Parameter => " initial=\"exact\"",
        Causality::Output => " initial=\"calculated\"",
        Causality::Input => "",
    };
    let attr = |name: &str, value: Option<String>| {
        value
            .map(|x| format!(" {name}=\"{x}\""))
            .unwrap_or_default()
    };
    let (element, attributes, start_element) = match v.kind {
        Kind::Real {
            unit,
            start,
            min,
            max,
            nominal,
        } => (
            "Float64",
            format!(
                " unit=\"{}\"{}{}{}{}{}",
                esc(unit),
                attr("displayUnit", display_unit.map(esc)),
                attr("start", start.map(real)),
                attr("min", min.map(real)),
                attr("max", max.map(real)),
                attr("nominal", nominal.map(real))
            ),
            None,
        ),
        Kind::Integer { start, min, max } => (
            "Int32",
            format!(
                "{}{}{}",
                attr("start", start.map(|x| x.to_string())),
                attr("min", min.map(|x| x.to_string())),
                attr("max", max.map(|x| x.to_string()))
            ),
            None,
        ),
        Kind::Boolean { start } => ("Boolean", attr("start", start.map(|x| x.to_string())), None),
        // String start values are elements (FMI 3.0 §2.4.7.5)
        Kind::String { start } => ("String", String::new(), start),
    };
    let _ = write!(
        out,
        "    <{element} name=\"{}\" valueReference=\"{}\" description=\"{}\" causality=\"{causality}\" \
         variability=\"{variability}\"{initial}{attributes}",
        esc(v.name),
        v.vr,
        esc(v.description),
    );
    if array.is_none() && start_element.is_none() {
        let _ = writeln!(out, "/>");
        return;
    }
    let _ = writeln!(out, ">");
    if let Some(s) = start_element {
        let _ = writeln!(out, "      <Start value=\"{}\"/>", esc(s));
    }
    if let Some(vr) = array {
        let _ = writeln!(out, "      <Dimension valueReference=\"{vr}\"/>");
    }
    let _ = writeln!(out, "    </{element}>");
}

fn count_xml(out: &mut String, c: &Count, causality: &str) {
    let _ = writeln!(
        out,
        "    <UInt64 name=\"{}\" valueReference=\"{}\" description=\"{}\" causality=\"{causality}\" \
         variability=\"fixed\" initial=\"exact\" start=\"{}\" min=\"{}\" max=\"{}\"/>",
        esc(c.name),
        c.vr,
        esc(c.description),
        c.start,
        c.min,
        c.max
    );
}

/// The document with `token` as `instantiationToken`.
fn document(info: &ModelInfo, arrays: &ArrayInfo, token: &str) -> String {
    let mut x = String::new();
    let _ = writeln!(x, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        x,
        "<fmiModelDescription fmiVersion=\"3.0\" modelName=\"{}\" instantiationToken=\"{token}\" \
         description=\"{}\" author=\"{}\" version=\"{}\" license=\"{}\" generationTool=\"{}\" \
         variableNamingConvention=\"flat\">",
        esc(info.model_name),
        esc(arrays.description),
        esc(info.author),
        esc(info.version),
        esc(info.license),
        esc(info.generation_tool)
    );
    let common = "canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\" \
                  providesDirectionalDerivatives=\"true\" providesAdjointDerivatives=\"true\" \
                  canBeInstantiatedOnlyOncePerProcess=\"false\" needsExecutionTool=\"false\"";
    let _ = writeln!(
        x,
        "  <ModelExchange modelIdentifier=\"{}\" needsCompletedIntegratorStep=\"true\" {common}/>",
        esc(info.model_identifier)
    );
    let _ = writeln!(
        x,
        "  <CoSimulation modelIdentifier=\"{}\" canHandleVariableCommunicationStepSize=\"true\" \
         hasEventMode=\"true\" maxOutputDerivativeOrder=\"0\" {common}/>",
        esc(info.model_identifier)
    );
    unit_definitions(&mut x, info);
    categories_and_experiment(&mut x, info, "fmi3");
    let _ = writeln!(x, "  <ModelVariables>");
    let _ = writeln!(
        x,
        "    <Float64 name=\"time\" valueReference=\"{}\" description=\"Simulation time\" \
         causality=\"independent\" variability=\"continuous\"/>",
        arrays.time_vr
    );
    count_xml(&mut x, &arrays.size, "structuralParameter");
    count_xml(&mut x, &arrays.threads, "parameter");
    for (i, v) in info.variables.iter().enumerate() {
        let array = is_array(arrays, i, v).then_some(arrays.size.vr);
        variable_xml(&mut x, v, array, (info.display_unit)(v));
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let vrs = |c: Causality| {
        info.variables
            .iter()
            .filter(move |v| v.causality == c)
            .map(|v| v.vr)
    };
    let inputs = vrs(Causality::Input)
        .map(|vr| vr.to_string())
        .collect::<Vec<_>>()
        .join(" ");
    let _ = writeln!(x, "  <ModelStructure>");
    for vr in vrs(Causality::Output) {
        let _ = writeln!(
            x,
            "    <Output valueReference=\"{vr}\" dependencies=\"{inputs}\"/>"
        );
    }
    for vr in vrs(Causality::Output) {
        let _ = writeln!(x, "    <InitialUnknown valueReference=\"{vr}\"/>");
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

/// The instantiation token: a deterministic UUID-shaped hash of the model description, so that any change
/// of the interface changes it.
pub fn token(info: &ModelInfo, arrays: &ArrayInfo) -> String {
    uuid_of(&document(info, arrays, ""))
}

/// The complete FMI 3.0 `modelDescription.xml`.
pub fn model_description(info: &ModelInfo, arrays: &ArrayInfo) -> String {
    document(info, arrays, &token(info, arrays))
}
