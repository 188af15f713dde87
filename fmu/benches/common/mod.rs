//! Shared set-up of the FMU benchmarks.

/// A table for the FMU's default parameters on a 6 × 6 grid (`tests/fixtures/small-axes.toml`, 1152
/// points).
#[allow(dead_code)] // not every bench uses it
pub fn small_table() -> std::path::PathBuf {
    small_table_of(false)
}

/// [`small_table`] built by similarity (docs/model.md §9.1): the normal force axis 100 kN alone, the speed
/// points (20, 40 m/s) equivalent speeds, so the linear stencil has 12 corners instead of 16.
#[allow(dead_code)] // not every bench uses it
pub fn small_table_by_similarity() -> std::path::PathBuf {
    small_table_of(true)
}

fn small_table_of(similarity: bool) -> std::path::PathBuf {
    let mut axes = wheelrail::table::Axes::from_toml_file(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/small-axes.toml"),
    )
    .unwrap();
    if similarity {
        axes.0[3].points = vec![wheelrail::table::axes::REFERENCE_FORCE];
        axes.0[4].similarity = true;
    }
    let mut params = wheelrail::Params::default();
    params.grid.nx = 6;
    params.grid.ny = 6;
    let dir = std::env::temp_dir().join(format!(
        "wheelrail-fmu-bench-table-{}{}",
        if similarity { "similarity-" } else { "" },
        std::process::id()
    ));
    let mut files = wheelrail::table::build(&params, &axes, None, &|| ()).unwrap();
    files.write(&dir).unwrap();
    dir
}

/// A table on the nodes of the whole-range table (`tools/whole-range-axes.toml`: 46 million points, 2.2 GB
/// in memory) of synthetic values with the exact solutions at its probe nodes
/// (`wheelrail::table::build::timing_files`), for the FMU's default parameters: FMU steps on the layout of
/// the table the FMU will bundle, without its ≈ 118 core-hours of build (a lookup costs the same whatever
/// the values). Written as f32 (1.2 GB on disk, in the temporary directory) and loaded in ≈ 15 s.
#[allow(dead_code)] // not every bench uses it
pub fn whole_range_timing_table() -> std::path::PathBuf {
    let axes = wheelrail::table::Axes::from_toml_file(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/whole-range-axes.toml"),
    )
    .unwrap();
    let dir = std::env::temp_dir().join(format!(
        "wheelrail-fmu-bench-whole-range-{}",
        std::process::id()
    ));
    let mut files =
        wheelrail::table::build::timing_files(&wheelrail::Params::default(), &axes).unwrap();
    files.write(&dir).unwrap();
    dir
}

/// How a benchmark instance evaluates.
pub struct Setup<'a> {
    /// `mode` (0 auto, 1 table only, 2 exact only).
    pub mode: i32,
    /// `grid_size`.
    pub grid: i32,
    /// `table_file` (None: the bundled default).
    pub table: Option<&'a std::ffi::CStr>,
    /// `wetness`.
    pub wetness: f64,
    /// `warm_start`.
    pub warm: bool,
}

/// An instance of the FMU through the exported C functions, set up and initialised (panics on any
/// non-OK status: a benchmark of a failing call would measure nothing).
///
/// # Safety
/// Calls the FMU's exported C functions; free the instance with `fmi2FreeInstance`.
pub unsafe fn instance(s: &Setup) -> WheelRailFriction::fmi2::ffi::Fmi2Component {
    use WheelRailFriction::contact::variables::*;
    use WheelRailFriction::exports::*;
    use WheelRailFriction::fmi2::ffi::{FMI2_COSIMULATION, Fmi2CallbackFunctions};
    use std::ptr::{null, null_mut};
    let guid = std::ffi::CString::new(WheelRailFriction::fmi2::description::guid(&INFO)).unwrap();
    let callbacks = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: null_mut(),
    };
    unsafe {
        let fmu = fmi2Instantiate(
            c"bench".as_ptr(),
            FMI2_COSIMULATION,
            guid.as_ptr(),
            null(),
            &callbacks,
            0,
            0,
        );
        assert!(!fmu.is_null());
        assert_eq!(fmi2SetInteger(fmu, &(MODE as u32), 1, &s.mode), 0);
        assert_eq!(fmi2SetInteger(fmu, &(GRID_SIZE as u32), 1, &s.grid), 0);
        if let Some(t) = s.table {
            assert_eq!(fmi2SetString(fmu, &(TABLE_FILE as u32), 1, &t.as_ptr()), 0);
        }
        assert_eq!(fmi2SetReal(fmu, &(WETNESS as u32), 1, &s.wetness), 0);
        assert_eq!(
            fmi2SetBoolean(fmu, &(WARM_START as u32), 1, &i32::from(s.warm)),
            0
        );
        assert_eq!(fmi2EnterInitializationMode(fmu), 0);
        assert_eq!(fmi2ExitInitializationMode(fmu), 0);
        fmu
    }
}

/// The CPU time this thread has used (`CLOCK_THREAD_CPUTIME_ID`): unlike the wall time it leaves out the
/// time the thread waits while the shared machine runs others (NaN where there is no such clock).
#[cfg(target_os = "linux")]
#[allow(dead_code)] // not every bench uses it
pub fn thread_cpu_ns() -> f64 {
    cpu_ns(3)
}

/// The CPU time all threads of this process have used (`CLOCK_PROCESS_CPUTIME_ID`; NaN where there is no
/// such clock).
#[cfg(target_os = "linux")]
#[allow(dead_code)] // not every bench uses it
pub fn process_cpu_ns() -> f64 {
    cpu_ns(2)
}

/// The CPU time of a `clock_gettime` clock [ns].
#[cfg(target_os = "linux")]
#[allow(dead_code)] // not every bench uses it
fn cpu_ns(clock: i32) -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, time: *mut Timespec) -> i32;
    }
    let mut t = Timespec { sec: 0, nsec: 0 };
    // SAFETY: a valid clock id and a pointer to a live timespec
    match unsafe { clock_gettime(clock, &mut t) } {
        0 => t.sec as f64 * 1e9 + t.nsec as f64,
        _ => f64::NAN,
    }
}

/// The CPU time this thread has used (NaN: no per-thread clock here).
#[cfg(not(target_os = "linux"))]
#[allow(dead_code)] // not every bench uses it
pub fn thread_cpu_ns() -> f64 {
    f64::NAN
}

/// The CPU time of this process (NaN: no such clock here).
#[cfg(not(target_os = "linux"))]
#[allow(dead_code)] // not every bench uses it
pub fn process_cpu_ns() -> f64 {
    f64::NAN
}
