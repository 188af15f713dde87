//! `modelDescription.xml` generated from a [`ModelInfo`] (FMI 2.0.4 schema `fmi2ModelDescription.xsd`), and
//! the model's GUID.
//!
//! The one binary serves both interface types, so the document has a `<ModelExchange>` and a
//! `<CoSimulation>` element with the same `modelIdentifier`. Capability flags are those of the generic
//! layer: `canHandleVariableCommunicationStepSize`, `canGetAndSetFMUstate`, `canSerializeFMUstate`,
//! `providesDirectionalDerivative` and `canNotUseMemoryManagementFunctions` are true;
//! `canInterpolateInputs`, `canRunAsynchronuously`, `canBeInstantiatedOnlyOncePerProcess` and (Model
//! Exchange) `completedIntegratorStepNotNeeded` are false; `maxOutputDerivativeOrder` is 0. Model Exchange
//! has no continuous states and no event indicators (`numberOfEventIndicators="0"`, no `<Derivatives>`).
//!
//! `ModelStructure`: every output depends on every input (the model is quasi-static with direct
//! feedthrough; with no states, that is also the complete Model Exchange dependency list); initial
//! unknowns are the outputs, depending on all knowns (no `dependencies` attribute).

use super::logging::CATEGORIES;
use super::model::ModelInfo;
use super::snapshot::fnv1a64;
use super::variables::{Causality, Kind, Variability, Variable};
use std::fmt::Write;

/// XML-escapes text for attribute values.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A Real as XML text: shortest round-trip form (`{:?}` of f64 is exact and locale-free).
pub fn real(x: f64) -> String {
    format!("{x:?}")
}

fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    }
}

fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Fixed => "fixed",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

fn variable_xml(out: &mut String, v: &Variable, display_unit: Option<&str>) {
    let initial = match v.causality {
        Causality::Parameter => " initial=\"exact\"",
        Causality::Output => " initial=\"calculated\"",
        Causality::Input => "",
    };
    let _ = writeln!(
        out,
        "    <ScalarVariable name=\"{}\" valueReference=\"{}\" description=\"{}\" causality=\"{}\" variability=\"{}\"{}>",
        esc(v.name),
        v.vr,
        esc(v.description),
        causality(v.causality),
        variability(v.variability),
        initial
    );
    let attr = |name: &str, value: Option<String>| {
        value
            .map(|x| format!(" {name}=\"{x}\""))
            .unwrap_or_default()
    };
    let element = match v.kind {
        Kind::Real {
            unit,
            start,
            min,
            max,
            nominal,
        } => format!(
            "<Real unit=\"{}\"{}{}{}{}{}/>",
            esc(unit),
            attr("displayUnit", display_unit.map(esc)),
            attr("start", start.map(real)),
            attr("min", min.map(real)),
            attr("max", max.map(real)),
            attr("nominal", nominal.map(real))
        ),
        Kind::Integer { start, min, max } => format!(
            "<Integer{}{}{}/>",
            attr("start", start.map(|x| x.to_string())),
            attr("min", min.map(|x| x.to_string())),
            attr("max", max.map(|x| x.to_string()))
        ),
        Kind::Boolean { start } => {
            format!("<Boolean{}/>", attr("start", start.map(|x| x.to_string())))
        }
        Kind::String { start } => format!("<String{}/>", attr("start", start.map(esc))),
    };
    let _ = writeln!(out, "      {element}");
    let _ = writeln!(out, "    </ScalarVariable>");
}

/// `<UnitDefinitions>` (the same elements in FMI 2.0 and 3.0).
pub fn unit_definitions(x: &mut String, info: &ModelInfo) {
    let _ = writeln!(x, "  <UnitDefinitions>");
    for u in info.units {
        let exps = [("kg", u.kg), ("m", u.m), ("s", u.s), ("K", u.k)]
            .iter()
            .filter(|(_, e)| *e != 0)
            .map(|(n, e)| format!(" {n}=\"{e}\""))
            .collect::<String>();
        let _ = writeln!(x, "    <Unit name=\"{}\">", esc(u.name));
        let _ = writeln!(x, "      <BaseUnit{exps}/>");
        for d in u.display {
            let offset = if d.offset == 0.0 {
                String::new()
            } else {
                format!(" offset=\"{}\"", real(d.offset))
            };
            let _ = writeln!(
                x,
                "      <DisplayUnit name=\"{}\" factor=\"{}\"{offset}/>",
                esc(d.name),
                real(d.factor)
            );
        }
        let _ = writeln!(x, "    </Unit>");
    }
    let _ = writeln!(x, "  </UnitDefinitions>");
}

/// `<LogCategories>` and `<DefaultExperiment>` (the same elements in FMI 2.0 and 3.0); `statuses` names the
/// status values in the categories' descriptions (`fmi2`: fmi2Warning, `fmi3`: fmi3Warning).
pub fn categories_and_experiment(x: &mut String, info: &ModelInfo, statuses: &str) {
    let _ = writeln!(x, "  <LogCategories>");
    for (name, description) in CATEGORIES {
        let _ = writeln!(
            x,
            "    <Category name=\"{name}\" description=\"{}\"/>",
            esc(&description.replace("fmi2", statuses))
        );
    }
    let _ = writeln!(x, "  </LogCategories>");
    let e = info.default_experiment;
    let _ = writeln!(
        x,
        "  <DefaultExperiment startTime=\"{}\" stopTime=\"{}\" stepSize=\"{}\"/>",
        real(e.start_time),
        real(e.stop_time),
        real(e.step_size)
    );
}

/// The document with `guid` in the `guid` attribute.
fn document(info: &ModelInfo, guid: &str) -> String {
    let mut x = String::new();
    let _ = writeln!(x, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        x,
        "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{}\" guid=\"{}\" description=\"{}\" author=\"{}\" \
         version=\"{}\" license=\"{}\" generationTool=\"{}\" variableNamingConvention=\"flat\" \
         numberOfEventIndicators=\"0\">",
        esc(info.model_name),
        guid,
        esc(info.description),
        esc(info.author),
        esc(info.version),
        esc(info.license),
        esc(info.generation_tool)
    );
    // one binary serves both interface types: the same modelIdentifier
    let _ = writeln!(
        x,
        "  <ModelExchange modelIdentifier=\"{}\" needsExecutionTool=\"false\" \
         completedIntegratorStepNotNeeded=\"false\" canBeInstantiatedOnlyOncePerProcess=\"false\" \
         canNotUseMemoryManagementFunctions=\"true\" canGetAndSetFMUstate=\"true\" \
         canSerializeFMUstate=\"true\" providesDirectionalDerivative=\"true\"/>",
        esc(info.model_identifier)
    );
    let _ = writeln!(
        x,
        "  <CoSimulation modelIdentifier=\"{}\" needsExecutionTool=\"false\" \
         canHandleVariableCommunicationStepSize=\"true\" canInterpolateInputs=\"false\" \
         maxOutputDerivativeOrder=\"0\" canRunAsynchronuously=\"false\" \
         canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" \
         canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\" providesDirectionalDerivative=\"true\"/>",
        esc(info.model_identifier)
    );
    unit_definitions(&mut x, info);
    categories_and_experiment(&mut x, info, "fmi2");
    let _ = writeln!(x, "  <ModelVariables>");
    for (i, v) in info.variables.iter().enumerate() {
        let _ = writeln!(x, "    <!-- index {} -->", i + 1);
        variable_xml(&mut x, v, (info.display_unit)(v));
    }
    let _ = writeln!(x, "  </ModelVariables>");
    // ModelStructure refers to variables by 1-based index in ModelVariables
    let indices = |c: Causality| {
        info.variables
            .iter()
            .enumerate()
            .filter(move |(_, v)| v.causality == c)
            .map(|(i, _)| i + 1)
    };
    let inputs = indices(Causality::Input)
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(" ");
    let _ = writeln!(x, "  <ModelStructure>");
    let _ = writeln!(x, "    <Outputs>");
    for i in indices(Causality::Output) {
        let _ = writeln!(
            x,
            "      <Unknown index=\"{i}\" dependencies=\"{inputs}\"/>"
        );
    }
    let _ = writeln!(x, "    </Outputs>");
    let _ = writeln!(x, "    <InitialUnknowns>");
    for i in indices(Causality::Output) {
        let _ = writeln!(x, "      <Unknown index=\"{i}\"/>");
    }
    let _ = writeln!(x, "    </InitialUnknowns>");
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

/// The GUID: a deterministic UUID-shaped hash of the model description (which includes the model version
/// and every variable), so that any change of the interface changes the GUID.
pub fn guid(info: &ModelInfo) -> String {
    uuid_of(&document(info, ""))
}

/// A deterministic UUID-shaped hash of a text (two chained FNV-1a 64 hashes).
pub fn uuid_of(body: &str) -> String {
    let h1 = fnv1a64(body.as_bytes());
    let h2 = fnv1a64(format!("{h1:016x}{body}").as_bytes());
    let hex = format!("{h1:016x}{h2:016x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

/// The complete `modelDescription.xml`.
pub fn model_description(info: &ModelInfo) -> String {
    document(info, &guid(info))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::model::{DefaultExperiment, DisplayUnit, Unit};

    static VARS: [Variable; 2] = [
        Variable {
            name: "u",
            vr: 0,
            causality: Causality::Input,
            variability: Variability::Continuous,
            kind: Kind::Real {
                unit: "N",
                start: Some(1e5),
                min: Some(-1.0),
                max: None,
                nominal: None,
            },
            description: "a <force> & \"more\"",
        },
        Variable {
            name: "y",
            vr: 1,
            causality: Causality::Output,
            variability: Variability::Continuous,
            kind: Kind::Real {
                unit: "N",
                start: None,
                min: None,
                max: None,
                nominal: None,
            },
            description: "out",
        },
    ];
    static INFO: ModelInfo = ModelInfo {
        model_name: "M",
        model_identifier: "M",
        description: "d",
        author: "a",
        version: "1",
        license: "l",
        generation_tool: "t",
        units: &[Unit {
            name: "N",
            kg: 1,
            m: 1,
            s: -2,
            k: 0,
            display: &[DisplayUnit {
                name: "kN",
                factor: 1e-3,
                offset: 0.0,
            }],
        }],
        display_unit: |v| (v.name == "y").then_some("kN"),
        variables: &VARS,
        default_experiment: DefaultExperiment {
            start_time: 0.0,
            stop_time: 1.0,
            step_size: 1e-3,
        },
    };

    #[test]
    fn document_escapes_text_and_indexes_from_one() {
        let x = model_description(&INFO);
        assert!(x.contains("description=\"a &lt;force&gt; &amp; &quot;more&quot;\""));
        assert!(x.contains("<Real unit=\"N\" start=\"100000.0\" min=\"-1.0\"/>"));
        assert!(x.contains("<Unknown index=\"2\" dependencies=\"1\"/>"));
        assert!(x.contains("<BaseUnit kg=\"1\" m=\"1\" s=\"-2\"/>"));
        assert!(x.contains("<DisplayUnit name=\"kN\" factor=\"0.001\"/>"));
        assert!(x.contains("<Real unit=\"N\" displayUnit=\"kN\"/>"));
        assert!(x.contains("initial=\"calculated\""));
        // both interface types, one binary
        assert_eq!(x.matches("modelIdentifier=\"M\"").count(), 2);
        let (me, cs) = (
            x.find("<ModelExchange ").unwrap(),
            x.find("<CoSimulation ").unwrap(),
        );
        assert!(me < cs && cs < x.find("<UnitDefinitions>").unwrap());
        assert!(x.contains("completedIntegratorStepNotNeeded=\"false\""));
    }

    #[test]
    fn guid_is_deterministic_and_follows_the_interface() {
        let g = guid(&INFO);
        assert_eq!(g, guid(&INFO));
        assert_eq!(g.len(), 38);
        let mut other = INFO;
        other.version = "2";
        assert_ne!(g, guid(&other));
    }
}
