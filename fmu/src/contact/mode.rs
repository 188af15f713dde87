//! The `mode` and `table_file` parameters: the library's evaluation mode ([`wheelrail::model::Mode`]) and
//! the lookup table they select, by default the one bundled in the FMU's resources.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use wheelrail::model::Mode;
use wheelrail::table::Table;

/// The evaluation mode of a `mode` parameter value: 0 auto, 1 table only, 2 exact only.
pub fn mode_of(code: i32) -> Result<Mode, String> {
    match code {
        0 => Ok(Mode::Auto),
        1 => Ok(Mode::TableOnly),
        2 => Ok(Mode::ExactOnly),
        _ => Err(format!(
            "invalid value for mode: {code} (allowed: 0 auto, 1 table only, 2 exact only)"
        )),
    }
}

/// Where the lookup table is: `table_file` if given, else `resources/table` of the unpacked FMU.
pub fn table_location(table_file: &str, resources: Option<&Path>) -> Option<PathBuf> {
    if table_file.is_empty() {
        resources.map(|r| r.join("table"))
    } else {
        Some(PathBuf::from(table_file))
    }
}

/// Where the lookup tables are, in the order they are tried: `table_file` holds one table directory or
/// several separated by `;`, each as [`table_location`] (an empty entry is the bundled table, e.g.
/// `/tables/flange;` for a table of flange-root contacts, then the bundled one).
pub fn table_locations(table_file: &str, resources: Option<&Path>) -> Vec<Option<PathBuf>> {
    table_file
        .split(';')
        .map(|entry| table_location(entry, resources))
        .collect()
}

/// The table at a location (loaded once per process and directory, shared read-only between instances),
/// or why it is not usable. A table of format version 1 is not: it does not store the frictional power.
fn load(location: Option<&Path>) -> Result<Arc<Table>, String> {
    match location {
        None => Err("table_file is empty and the FMU's resources directory is unknown".into()),
        Some(p) if !p.exists() => Err(format!("there is no lookup table at {}", p.display())),
        Some(p) => match Table::load_shared(p) {
            Err(e) => Err(format!("the lookup table cannot be used: {e}")),
            // the output frictional_power needs it
            Ok(t) if !t.stores_frictional_power() => Err(format!(
                "the lookup table at {} is of format version 1, which does not store the frictional \
                 power (output frictional_power): rebuild it with `wheelrail table build`",
                p.display()
            )),
            Ok(t) => Ok(t),
        },
    }
}

/// The tables of `mode` at `locations` ([`table_locations`]), and the warning to log once if mode auto
/// goes without some of them (without all, every point is solved exactly). Mode exact only needs none;
/// in mode table only, a table that is not usable is an error.
pub fn resolve(
    mode: Mode,
    locations: &[Option<PathBuf>],
) -> Result<(Vec<Arc<Table>>, Option<String>), String> {
    if mode == Mode::ExactOnly {
        return Ok((Vec::new(), None));
    }
    let mut tables = Vec::new();
    let mut unusable = Vec::new();
    for location in locations {
        match load(location.as_deref()) {
            Ok(t) => tables.push(t),
            Err(why) if mode == Mode::TableOnly => {
                return Err(format!(
                    "mode 1 (table only) needs a usable lookup table, but {why}"
                ));
            }
            Err(why) => unusable.push(why),
        }
    }
    let warning = (!unusable.is_empty()).then(|| {
        let rest = if tables.is_empty() {
            "using the exact solver"
        } else {
            "using the other lookup tables and the exact solver"
        };
        format!("{}; {rest}", unusable.join("; "))
    });
    Ok((tables, warning))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_and_table_resolution() {
        assert_eq!(mode_of(1), Ok(Mode::TableOnly));
        assert!(mode_of(3).unwrap_err().contains("mode: 3"));
        let res = Path::new("/nonexistent/resources");
        let loc = table_location("", Some(res)).unwrap();
        assert_eq!(loc, res.join("table"));
        assert_eq!(
            table_location("/x/t", Some(res)).unwrap(),
            PathBuf::from("/x/t")
        );
        assert_eq!(table_location("", None), None);
        // several tables separated by ';', an empty entry the bundled one
        assert_eq!(table_locations("", Some(res)), [Some(res.join("table"))]);
        assert_eq!(
            table_locations("/x/t;/y/u;", Some(res)),
            [
                Some(PathBuf::from("/x/t")),
                Some(PathBuf::from("/y/u")),
                Some(res.join("table"))
            ]
        );
        let (table, warning) = resolve(Mode::ExactOnly, &[None]).unwrap();
        assert!(table.is_empty() && warning.is_none());
        let (table, warning) = resolve(Mode::Auto, &[Some(loc.clone())]).unwrap();
        assert!(table.is_empty());
        assert!(
            warning
                .unwrap()
                .contains("no lookup table at /nonexistent/resources/table")
        );
        let err = resolve(Mode::TableOnly, &[Some(loc.clone())]).unwrap_err();
        assert!(
            err.contains("table only") && err.contains("/nonexistent"),
            "{err}"
        );
        assert!(
            resolve(Mode::TableOnly, &[None])
                .unwrap_err()
                .contains("resources directory is unknown")
        );
    }

    /// A table another model computed (its probe nodes disagree with the exact solver): auto mode goes on
    /// with the exact solver and one warning naming it, table-only mode is an error.
    #[test]
    fn a_stale_table_is_refused_with_the_reason() {
        let dir =
            std::env::temp_dir().join(format!("wheelrail-fmu-stale-table-{}", std::process::id()));
        let axes = wheelrail::table::Axes::from_toml_file(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/small-axes.toml"),
        )
        .unwrap();
        let mut params = wheelrail::Params::default();
        params.grid.nx = 6;
        params.grid.ny = 6;
        let mut files = wheelrail::table::build(&params, &axes, None, &|| ()).unwrap();
        files.write(&dir).unwrap();
        let t = Table::load(&dir).unwrap();
        for n in t.probe_nodes() {
            files.outputs[0][n] *= 1.001;
        }
        drop(t);
        files.write(&dir).unwrap();
        let (table, warning) = resolve(Mode::Auto, &[Some(dir.clone())]).unwrap();
        assert!(table.is_empty());
        let warning = warning.unwrap();
        assert!(
            warning.contains("computed by another model")
                && warning.contains("using the exact solver"),
            "{warning}"
        );
        assert!(
            resolve(Mode::TableOnly, &[Some(dir.clone())])
                .unwrap_err()
                .contains("computed by another model")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
