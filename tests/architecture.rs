//! The import rules of ARCHITECTURE.md, checked on the sources: which module of the library may use which,
//! and that the FMU reaches the model only through the library's API (no physics in `fmu/`). Crate edges
//! (the library depends on no CLI, plotting or FMI crate) are enforced by the manifests themselves.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The library's top-level modules in layers: a module may use modules of its own layer (named in
/// `SAME_LAYER`) and of lower layers only.
const LAYERS: [&[&str]; 6] = [
    // foundations
    &["error", "quadrature"],
    // the parameter set and its specification
    &["params"],
    // the physical submodels
    &[
        "contact",
        "materials",
        "microcontact",
        "friction",
        "tangential",
        "thermal",
        "fluid",
        "baselines",
    ],
    // the coupled solution of one operating point
    &["solver"],
    // lookup tables of solutions
    &["table"],
    // the model and its evaluation policy (table / exact / auto, frame turn, lift-off)
    &["model"],
];

/// Uses of higher layers that are allowed: the error type carries the typed keys of parameters and inputs
/// and the evaluation mode its messages name (data only; no function of theirs is called).
const ERROR_NAMES: [(&str, &str); 2] = [("error", "params"), ("error", "model")];

/// Uses inside one layer that are allowed (user → used): the physical submodels build on the contact
/// geometry, the materials and each other, without cycles.
const SAME_LAYER: [(&str, &str); 8] = [
    ("microcontact", "contact"),
    ("microcontact", "materials"),
    ("tangential", "contact"),
    ("thermal", "contact"),
    ("fluid", "contact"),
    ("fluid", "materials"),
    ("fluid", "microcontact"),
    ("baselines", "tangential"),
];

fn layer(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The Rust sources under `dir`, recursively.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(sources(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// The text of a source without its unit-test module (`#[cfg(test)]` followed by `mod tests`, by the
/// project's convention the last item of a file): tests may use anything.
fn without_tests(text: &str) -> &str {
    match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    }
}

/// The names `prefix` is followed by (`crate::solver::x` → `solver`), also inside `use crate::{a, b}`.
fn used(text: &str, prefix: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    for (i, _) in text.match_indices(prefix) {
        let rest = &text[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name = ident(item.trim());
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        } else {
            let name = ident(rest);
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn library_modules_use_only_lower_layers() {
    let src = root().join("src");
    let mut violations = Vec::new();
    let mut seen = BTreeSet::new();
    for file in sources(&src) {
        let rel = file.strip_prefix(&src).unwrap();
        let module = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_str()
            .unwrap()
            .trim_end_matches(".rs")
            .to_string();
        // lib.rs re-exports; a module's unit tests in their own file (`#[cfg(test)] mod tests;`)
        if module == "lib" || file.file_name().is_some_and(|n| n == "tests.rs") {
            continue;
        }
        let Some(own) = layer(&module) else {
            violations.push(format!(
                "{}: module `{module}` is in no layer of ARCHITECTURE.md",
                rel.display()
            ));
            continue;
        };
        seen.insert(module.clone());
        let text = std::fs::read_to_string(&file).unwrap();
        for dep in used(without_tests(&text), "crate::") {
            if dep == module {
                continue;
            }
            let allowed = match layer(&dep) {
                Some(l) if l < own => true,
                Some(l) if l == own => SAME_LAYER.iter().any(|&(u, d)| u == module && d == dep),
                Some(_) => ERROR_NAMES.contains(&(module.as_str(), dep.as_str())),
                // re-exports of lib.rs (crate::Error, crate::Params, …) are foundations or params
                None => ["Error", "Result", "Params", "OperatingPoint", "FrictionLaw"]
                    .contains(&dep.as_str()),
            };
            if !allowed {
                violations.push(format!("{}: `{module}` uses `{dep}`", rel.display()));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
    // the rule list names every module that exists
    for l in LAYERS {
        for m in l {
            assert!(
                seen.contains(*m),
                "ARCHITECTURE.md layer names `{m}`, which does not exist"
            );
        }
    }
}

#[test]
fn the_fmu_reaches_the_model_only_through_the_library_api() {
    // the FMI layer translates values and statuses: no physical submodel, no solver internals
    let allowed = [
        "model",
        "table",
        "params",
        "error",
        "Error",
        "Params",
        "OperatingPoint",
    ];
    let src = root().join("fmu/src");
    let mut violations = Vec::new();
    for file in sources(&src) {
        let text = std::fs::read_to_string(&file).unwrap();
        for dep in used(without_tests(&text), "wheelrail::") {
            if !allowed.contains(&dep.as_str()) {
                violations.push(format!(
                    "{}: uses wheelrail::{dep}",
                    file.strip_prefix(root()).unwrap().display()
                ));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn the_rule_checker_sees_violations() {
    // the checker itself: a use of a higher layer and a grouped use are both found
    let text = "use crate::{solver::x, table};\nfn f() { crate::model::g(); }\n#[cfg(test)]\nmod tests { use crate::cli; }";
    let deps = used(without_tests(text), "crate::");
    assert_eq!(
        deps,
        ["model", "solver", "table"]
            .map(String::from)
            .into_iter()
            .collect()
    );
    assert!(layer("model") > layer("solver") && layer("solver") > layer("fluid"));
}
