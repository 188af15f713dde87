//! A lookup in the bundled table (`fmu/resources/table`, loaded with `Table::load`, which verifies its
//! files and re-solves its probe nodes), set beside the exact solve of the same point; run it with
//! `cargo run --release -p wheelrail --example table_lookup`.
//!
//! The check: the table's forces agree with the exact solver's within the accuracy target of a table,
//! |ΔF|/F_N ≤ `TARGET_MAX` (3 %; `wheelrail table verify` measures p99 and max over random points), its
//! T_max within 10 K, and the point lies inside the table's ranges.

use std::path::Path;
use wheelrail::table::verify::TARGET_MAX;
use wheelrail::table::{Ellipse, Table};
use wheelrail::{Model, OperatingPoint};

fn main() -> wheelrail::Result<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fmu/resources/table");
    let table = Table::load(&dir)?;
    let params = table.params().clone();
    let point = OperatingPoint {
        creepage_x: 0.004,
        creepage_y: 0.0015,
        spin: 0.05,
        normal_force: 80e3,
        speed: 25.0,
        wetness: 0.0,
    };
    // the contact ellipse of the table's geometry at this load (Hertz, a, b ∝ F_N^(1/3))
    let hertz = wheelrail::solver::normal_contact(&params, point.normal_force)?;
    let ellipse = Ellipse {
        a: hertz.a,
        b: hertz.b,
        load_exponent: Ellipse::HERTZ,
    };
    let t = table.evaluate(&point, &ellipse)?;
    let exact = Model::new(params)?.solve(&point)?;
    let g = &exact.global;
    println!("table {} ({} points)", dir.display(), table.axes().len());
    println!("{:>22} {:>12} {:>12}", "", "table", "exact");
    println!("{:>22} {:12.1} {:12.1}", "F_x [N]", t.force_x, g.force_x);
    println!("{:>22} {:12.1} {:12.1}", "F_y [N]", t.force_y, g.force_y);
    println!(
        "{:>22} {:12.2} {:12.2}",
        "M_z [N·m]",
        t.spin_moment,
        g.spin_moment.unwrap_or(f64::NAN)
    );
    println!(
        "{:>22} {:12.1} {:12.1}",
        "T_max [°C]",
        t.max_temperature - 273.15,
        g.max_temperature.unwrap_or(f64::NAN) - 273.15
    );

    assert!(
        t.in_range && t.converged,
        "the point is inside the table's ranges"
    );
    assert!(exact.report.converged);
    let df = (t.force_x - g.force_x).hypot(t.force_y - g.force_y) / point.normal_force;
    println!("|ΔF|/F_N = {df:.2e} (target: at most {TARGET_MAX})");
    assert!(df <= TARGET_MAX, "|ΔF|/F_N = {df}");
    let dt = (t.max_temperature - g.max_temperature.unwrap()).abs();
    assert!(dt <= 10.0, "|ΔT_max| = {dt} K");
    Ok(())
}
