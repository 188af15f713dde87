//! WheelRailFriction.fmu's shared library driven through its C interface, as an importer would.
//!
//! The library is `libWheelRailFriction.so` of `target/release` or `target/debug` (the newer one; override
//! with `WHEELRAIL_FMU_LIB`). `make test` builds it first (`make fmu-lib`); if it is missing, these tests
//! build it with `cargo build --release -p wheelrail-fmu`, and they refuse a library older than the
//! sources. The FMI logger is variadic, which Rust cannot define: the tests compile a six-line C logger
//! (`vsnprintf` into a buffer, then a call into Rust) with the system C compiler (`$CC`, default `cc`, the
//! same compiler that links Rust programs) and load it like the FMU.
//!
//! Value references and the GUID are read from the committed `modelDescription/modelDescription.xml`.
//! The Model Exchange interface of the same library is tested in `fmu/model_exchange.rs`.

use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use wheelrail::{OperatingPoint, Params};

mod fmi3;
mod fuzz;

const OK: c_int = 0;
const WARNING: c_int = 1;
const DISCARD: c_int = 2;
const ERROR: c_int = 3;
const GRID: i32 = 12;

type Comp = *mut c_void;
type Sink = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);
type Logger = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

#[repr(C)]
struct Callbacks {
    logger: Option<Logger>,
    allocate: *const c_void,
    free: *const c_void,
    step_finished: *const c_void,
    env: *mut c_void,
}

/// What the C logger calls: the environment pointer is a `LogEnv`.
#[repr(C)]
struct LogEnv {
    sink: Sink,
    messages: *const Mutex<Vec<Message>>,
}

/// One logged message.
#[derive(Debug, Clone)]
struct Message {
    instance: String,
    status: c_int,
    category: String,
    text: String,
}

unsafe extern "C" fn collect(
    env: *mut c_void,
    instance: *const c_char,
    status: c_int,
    category: *const c_char,
    text: *const c_char,
) {
    let s = |p: *const c_char| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    let m = unsafe { &*(env as *const Mutex<Vec<Message>>) };
    m.lock().unwrap().push(Message {
        instance: s(instance),
        status,
        category: s(category),
        text: s(text),
    });
}

const LOGGER_C: &str = r#"
#include <stdarg.h>
#include <stdio.h>
typedef void (*sink_t)(void *, const char *, int, const char *, const char *);
struct env { sink_t sink; void *messages; };
void test_logger(void *env, const char *instance, int status, const char *category, const char *fmt, ...) {
    char buf[8192]; va_list ap; va_start(ap, fmt); vsnprintf(buf, sizeof buf, fmt, ap); va_end(ap);
    struct env *e = env; e->sink(e->messages, instance, status, category, buf);
}
"#;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"))
}

/// The newest modification time of the sources cargo's dep-info file (`<lib>.d`) lists for `lib`.
fn newest_source(lib: &Path) -> Option<std::time::SystemTime> {
    let info = std::fs::read_to_string(lib.with_extension("d")).ok()?;
    let (_, deps) = info.lines().next()?.split_once(": ")?;
    deps.replace("\\ ", "\0")
        .split_whitespace()
        .filter_map(|p| {
            std::fs::metadata(p.replace('\0', " "))
                .ok()?
                .modified()
                .ok()
        })
        .max()
}

fn library_path() -> PathBuf {
    if let Some(p) = std::env::var_os("WHEELRAIL_FMU_LIB") {
        return p.into();
    }
    let candidates = || {
        ["release", "debug"]
            .iter()
            .map(|p| target_dir().join(p).join("libWheelRailFriction.so"))
            .filter(|p| p.exists())
            .max_by_key(|p| p.metadata().unwrap().modified().unwrap())
    };
    let lib = candidates().unwrap_or_else(|| {
        let ok = std::process::Command::new(std::env::var("CARGO").unwrap_or("cargo".into()))
            .args(["build", "--release", "-p", "wheelrail-fmu", "--lib"])
            .current_dir(root())
            .status()
            .expect("running cargo build");
        assert!(ok.success(), "cargo build -p wheelrail-fmu failed");
        candidates().expect("the build produced no libWheelRailFriction.so")
    });
    let built = lib.metadata().unwrap().modified().unwrap();
    assert!(
        newest_source(&lib).is_none_or(|sources| built >= sources),
        "{} is older than the sources: rebuild it with `make fmu-lib` (cargo build --release -p wheelrail-fmu)",
        lib.display()
    );
    lib
}

fn c_logger() -> Logger {
    static LIB: OnceLock<libloading::Library> = OnceLock::new();
    let lib = LIB.get_or_init(|| {
        let dir = target_dir().join("fmu-test-logger");
        std::fs::create_dir_all(&dir).unwrap();
        // per process: the fuzzer's workers compile it at the same time, and a source one of them is
        // rewriting is a truncated file to the others' compiler
        let src = dir.join(format!("logger-{}.c", std::process::id()));
        let so = dir.join(format!("liblogger-{}.so", std::process::id()));
        std::fs::write(&src, LOGGER_C).unwrap();
        let cc = std::env::var("CC").unwrap_or("cc".into());
        let ok = std::process::Command::new(&cc)
            .args(["-shared", "-fPIC", "-O1", "-o"])
            .arg(&so)
            .arg(&src)
            .status()
            .unwrap_or_else(|e| panic!("running the C compiler {cc}: {e}"));
        assert!(ok.success(), "compiling the test logger failed");
        let lib = unsafe { libloading::Library::new(so.to_str().unwrap()) }.unwrap();
        // a loaded library stays mapped after its file is removed
        std::fs::remove_file(&so).ok();
        std::fs::remove_file(&src).ok();
        lib
    });
    unsafe { *lib.get::<Logger>("test_logger").unwrap() }
}

/// The exported functions.
#[allow(clippy::type_complexity)]
struct Fmi {
    instantiate: unsafe extern "C" fn(
        *const c_char,
        c_int,
        *const c_char,
        *const c_char,
        *const Callbacks,
        c_int,
        c_int,
    ) -> Comp,
    free_instance: unsafe extern "C" fn(Comp),
    set_debug_logging: unsafe extern "C" fn(Comp, c_int, usize, *const *const c_char) -> c_int,
    setup_experiment: unsafe extern "C" fn(Comp, c_int, f64, f64, c_int, f64) -> c_int,
    enter_initialization_mode: unsafe extern "C" fn(Comp) -> c_int,
    exit_initialization_mode: unsafe extern "C" fn(Comp) -> c_int,
    terminate: unsafe extern "C" fn(Comp) -> c_int,
    reset: unsafe extern "C" fn(Comp) -> c_int,
    get_real: unsafe extern "C" fn(Comp, *const u32, usize, *mut f64) -> c_int,
    get_integer: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int,
    get_boolean: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int,
    get_string: unsafe extern "C" fn(Comp, *const u32, usize, *mut *const c_char) -> c_int,
    set_real: unsafe extern "C" fn(Comp, *const u32, usize, *const f64) -> c_int,
    set_integer: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int,
    set_boolean: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int,
    set_string: unsafe extern "C" fn(Comp, *const u32, usize, *const *const c_char) -> c_int,
    get_fmu_state: unsafe extern "C" fn(Comp, *mut *mut c_void) -> c_int,
    set_fmu_state: unsafe extern "C" fn(Comp, *mut c_void) -> c_int,
    free_fmu_state: unsafe extern "C" fn(Comp, *mut *mut c_void) -> c_int,
    serialized_size: unsafe extern "C" fn(Comp, *mut c_void, *mut usize) -> c_int,
    serialize: unsafe extern "C" fn(Comp, *mut c_void, *mut c_char, usize) -> c_int,
    deserialize: unsafe extern "C" fn(Comp, *const c_char, usize, *mut *mut c_void) -> c_int,
    directional_derivative: unsafe extern "C" fn(
        Comp,
        *const u32,
        usize,
        *const u32,
        usize,
        *const f64,
        *mut f64,
    ) -> c_int,
    do_step: unsafe extern "C" fn(Comp, f64, f64, c_int) -> c_int,
    cancel_step: unsafe extern "C" fn(Comp) -> c_int,
    get_status: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int,
    get_real_status: unsafe extern "C" fn(Comp, c_int, *mut f64) -> c_int,
    get_version: unsafe extern "C" fn() -> *const c_char,
    vr: HashMap<String, u32>,
    guid: CString,
}

/// All FMI 2.0 functions a co-simulation FMU exports (fmi2Functions.h).
const FUNCTIONS: [&str; 34] = [
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

fn library() -> &'static libloading::Library {
    static LIB: OnceLock<libloading::Library> = OnceLock::new();
    LIB.get_or_init(|| {
        unsafe { libloading::Library::new(library_path().to_str().unwrap()) }.unwrap()
    })
}

fn fmi() -> &'static Fmi {
    static FMI: OnceLock<Fmi> = OnceLock::new();
    FMI.get_or_init(|| {
        let lib = library();
        fn sym<T: Copy>(lib: &libloading::Library, name: &str) -> T {
            unsafe { *lib.get::<T>(name).unwrap_or_else(|e| panic!("{name}: {e}")) }
        }
        let xml =
            std::fs::read_to_string(root().join("modelDescription/modelDescription.xml")).unwrap();
        let attr = |text: &str, key: &str| -> String {
            let start = text.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
            text[start..start + text[start..].find('"').unwrap()].to_string()
        };
        let vr = xml
            .split("<ScalarVariable ")
            .skip(1)
            .map(|s| (attr(s, "name"), attr(s, "valueReference").parse().unwrap()))
            .collect();
        Fmi {
            instantiate: sym(lib, "fmi2Instantiate"),
            free_instance: sym(lib, "fmi2FreeInstance"),
            set_debug_logging: sym(lib, "fmi2SetDebugLogging"),
            setup_experiment: sym(lib, "fmi2SetupExperiment"),
            enter_initialization_mode: sym(lib, "fmi2EnterInitializationMode"),
            exit_initialization_mode: sym(lib, "fmi2ExitInitializationMode"),
            terminate: sym(lib, "fmi2Terminate"),
            reset: sym(lib, "fmi2Reset"),
            get_real: sym(lib, "fmi2GetReal"),
            get_integer: sym(lib, "fmi2GetInteger"),
            get_boolean: sym(lib, "fmi2GetBoolean"),
            get_string: sym(lib, "fmi2GetString"),
            set_real: sym(lib, "fmi2SetReal"),
            set_integer: sym(lib, "fmi2SetInteger"),
            set_boolean: sym(lib, "fmi2SetBoolean"),
            set_string: sym(lib, "fmi2SetString"),
            get_fmu_state: sym(lib, "fmi2GetFMUstate"),
            set_fmu_state: sym(lib, "fmi2SetFMUstate"),
            free_fmu_state: sym(lib, "fmi2FreeFMUstate"),
            serialized_size: sym(lib, "fmi2SerializedFMUstateSize"),
            serialize: sym(lib, "fmi2SerializeFMUstate"),
            deserialize: sym(lib, "fmi2DeSerializeFMUstate"),
            directional_derivative: sym(lib, "fmi2GetDirectionalDerivative"),
            do_step: sym(lib, "fmi2DoStep"),
            cancel_step: sym(lib, "fmi2CancelStep"),
            get_status: sym(lib, "fmi2GetStatus"),
            get_real_status: sym(lib, "fmi2GetRealStatus"),
            get_version: sym(lib, "fmi2GetVersion"),
            guid: CString::new(attr(&xml, "guid")).unwrap(),
            vr,
        }
    })
}

/// One FMU instance with its own log.
struct Fmu {
    c: Comp,
    log: Arc<Mutex<Vec<Message>>>,
    _env: Box<LogEnv>,
    _callbacks: Box<Callbacks>,
}

// The instance is used by one thread at a time (moved into the thread that drives it).
unsafe impl Send for Fmu {}

fn vr(name: &str) -> u32 {
    *fmi()
        .vr
        .get(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
}

impl Fmu {
    /// A co-simulation instance with the C logger, all log categories on, and `resources` as resource
    /// location (none if `None`).
    fn new(name: &str, resources: Option<&Path>) -> Fmu {
        Fmu::instantiate(name, resources, 1)
    }

    /// An instance of `fmu_type` (0 Model Exchange, 1 Co-Simulation), otherwise as [`Fmu::new`].
    fn instantiate(name: &str, resources: Option<&Path>, fmu_type: c_int) -> Fmu {
        let log = Arc::new(Mutex::new(Vec::new()));
        let env = Box::new(LogEnv {
            sink: collect,
            messages: Arc::as_ptr(&log),
        });
        let callbacks = Box::new(Callbacks {
            logger: Some(c_logger()),
            allocate: null(),
            free: null(),
            step_finished: null(),
            env: &*env as *const LogEnv as *mut c_void,
        });
        let name = CString::new(name).unwrap();
        let uri = resources.map(|p| CString::new(format!("file://{}", p.display())).unwrap());
        let c = unsafe {
            (fmi().instantiate)(
                name.as_ptr(),
                fmu_type,
                fmi().guid.as_ptr(),
                uri.as_ref().map_or(null(), |u| u.as_ptr()),
                &*callbacks,
                0,
                1,
            )
        };
        assert!(
            !c.is_null(),
            "instantiation failed: {:?}",
            log.lock().unwrap()
        );
        Fmu {
            c,
            log,
            _env: env,
            _callbacks: callbacks,
        }
    }

    fn set(&self, name: &str, x: f64) -> c_int {
        unsafe { (fmi().set_real)(self.c, &vr(name), 1, &x) }
    }

    fn set_int(&self, name: &str, x: i32) -> c_int {
        unsafe { (fmi().set_integer)(self.c, &vr(name), 1, &x) }
    }

    fn set_bool(&self, name: &str, x: bool) -> c_int {
        unsafe { (fmi().set_boolean)(self.c, &vr(name), 1, &c_int::from(x)) }
    }

    fn get(&self, name: &str) -> f64 {
        let mut x = f64::NAN;
        assert_eq!(
            unsafe { (fmi().get_real)(self.c, &vr(name), 1, &mut x) },
            OK,
            "{:?}",
            self.errors()
        );
        x
    }

    fn get_int(&self, name: &str) -> i32 {
        let mut x = -1;
        assert_eq!(
            unsafe { (fmi().get_integer)(self.c, &vr(name), 1, &mut x) },
            OK
        );
        x
    }

    fn get_bool(&self, name: &str) -> bool {
        let mut x = -1;
        assert_eq!(
            unsafe { (fmi().get_boolean)(self.c, &vr(name), 1, &mut x) },
            OK
        );
        x != 0
    }

    /// Small grid, then setup and initialization; returns the status of fmi2ExitInitializationMode.
    fn init(&self) -> c_int {
        assert_eq!(self.set_int("grid_size", GRID), OK);
        self.initialize()
    }

    /// Setup and initialization with the parameters as set; returns the status of
    /// fmi2ExitInitializationMode.
    fn initialize(&self) -> c_int {
        unsafe {
            assert_eq!((fmi().setup_experiment)(self.c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!((fmi().enter_initialization_mode)(self.c), OK);
            (fmi().exit_initialization_mode)(self.c)
        }
    }

    fn step(&self, t: f64) -> c_int {
        unsafe { (fmi().do_step)(self.c, t, 1e-3, 1) }
    }

    /// `fmi2GetDirectionalDerivative` of `unknown` with respect to `known` along `seed` into `out`.
    fn derivative(&self, unknown: &[u32], known: &[u32], seed: &[f64], out: &mut [f64]) -> c_int {
        assert!(known.len() == seed.len() && unknown.len() == out.len());
        unsafe {
            (fmi().directional_derivative)(
                self.c,
                unknown.as_ptr(),
                unknown.len(),
                known.as_ptr(),
                known.len(),
                seed.as_ptr(),
                out.as_mut_ptr(),
            )
        }
    }

    fn forces(&self) -> [f64; 3] {
        ["force_longitudinal", "force_lateral", "spin_moment"].map(|n| self.get(n))
    }

    fn messages(&self) -> Vec<Message> {
        self.log.lock().unwrap().clone()
    }

    fn errors(&self) -> Vec<String> {
        self.messages()
            .into_iter()
            .filter(|m| m.status == ERROR)
            .map(|m| m.text)
            .collect()
    }

    fn last_error(&self) -> String {
        self.errors().pop().unwrap_or_default()
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { (fmi().free_instance)(self.c) }
    }
}

/// The library's own solution of an operating point on the test grid.
fn library_forces(p: impl FnOnce(&mut Params), pt: OperatingPoint) -> [f64; 3] {
    let mut params = Params::default();
    params.grid.nx = GRID as usize;
    params.grid.ny = GRID as usize;
    p(&mut params);
    let s = wheelrail::solve(&params, &pt).unwrap();
    [
        s.global.force_x,
        s.global.force_y,
        s.global.spin_moment.unwrap(),
    ]
}

fn close(a: [f64; 3], b: [f64; 3], rel: f64) -> bool {
    let scale = a.iter().chain(&b).fold(1.0_f64, |m, x| m.max(x.abs()));
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= rel * scale)
}

#[test]
fn exports_every_fmi2_cosimulation_function() {
    for name in FUNCTIONS {
        assert!(
            unsafe { library().get::<*const c_void>(name) }.is_ok(),
            "{name} is not exported"
        );
    }
    assert_eq!(
        unsafe { CStr::from_ptr((fmi().get_version)()) }
            .to_str()
            .unwrap(),
        "2.0"
    );
}

#[test]
fn life_cycle_outputs_belong_to_the_current_inputs() {
    let f = Fmu::new("life", None);
    // cold solves: the outputs must be the library's bit for bit (warm starts agree only to the solver
    // tolerance; the FMU's unit tests check those)
    assert_eq!(f.set_bool("warm_start", false), OK);
    assert_eq!(f.set("creepage_longitudinal", 0.002), OK);
    assert_eq!(
        f.init(),
        WARNING,
        "auto mode without a table warns once: {:?}",
        f.messages()
    );
    assert!(
        f.messages()
            .iter()
            .any(|m| m.status == WARNING && m.text.contains("using the exact solver"))
    );
    let point = |xi: f64, eta: f64| OperatingPoint {
        creepage_x: xi,
        creepage_y: eta,
        ..OperatingPoint::default()
    };
    let first = f.forces();
    assert!(
        close(first, library_forces(|_| {}, point(0.002, 0.0)), 1e-12),
        "{first:?}"
    );
    // Kalker's sign convention: the force on the wheel opposes the slip
    assert!(first[0] < 0.0 && first[1].abs() < 1e-9 * first[0].abs());
    assert_eq!(f.get_int("evaluation_mode"), 2);
    assert!(f.get_bool("converged"));
    assert_eq!(f.set("creepage_lateral", -0.001), OK);
    assert_eq!(f.step(0.0), OK);
    let second = f.forces();
    assert!(close(
        second,
        library_forces(|_| {}, point(0.002, -0.001)),
        1e-12
    ));
    assert!(second[1] > 0.0);
    let mut t = 0.0;
    assert_eq!(unsafe { (fmi().get_real_status)(f.c, 2, &mut t) }, OK);
    assert!((t - 1e-3).abs() < 1e-15);
    let mut s = -1;
    assert_eq!(unsafe { (fmi().get_status)(f.c, 0, &mut s) }, OK);
    assert_eq!(s, OK);
    let f_n = f.get("normal_force");
    let mu = f.get("traction_coefficient");
    assert!((mu - second[0].hypot(second[1]) / f_n).abs() < 1e-12);
    assert!(f.get("max_temperature") > 293.15);
    assert_eq!(unsafe { (fmi().terminate)(f.c) }, OK);
    assert_eq!(unsafe { (fmi().reset)(f.c) }, OK);
    // after a reset the instance is back in Instantiated, where values cannot be read
    let mut mode = 0;
    assert_eq!(
        unsafe { (fmi().get_integer)(f.c, &vr("mode"), 1, &mut mode) },
        ERROR
    );
    assert_eq!(f.init(), WARNING);
}

#[test]
fn reversing_turns_the_frame_and_standstill_is_regularised() {
    let f = Fmu::new("reverse", None);
    assert_eq!(f.set_int("mode", 2), OK);
    assert_eq!(f.set("creepage_longitudinal", 0.003), OK);
    assert_eq!(f.set("creepage_lateral", 0.001), OK);
    assert_eq!(f.init(), OK);
    let forward = f.forces();
    assert_eq!(f.set("rolling_speed", -30.0), OK);
    assert_eq!(f.step(0.0), OK);
    let backward = f.forces();
    // without spin the forces depend on the slip only; the moment of the (trailing-edge) slip zone reverses
    // with the rolling direction
    let mirrored = [backward[0], backward[1], -backward[2]];
    assert!(
        close(forward, mirrored, 1e-9),
        "{forward:?} vs {backward:?}"
    );
    assert!(forward[2].abs() > 1.0);
    // spin alone: the lateral force changes sign with the rolling direction, the moment does not
    assert_eq!(f.set("creepage_longitudinal", 0.0), OK);
    assert_eq!(f.set("creepage_lateral", 0.0), OK);
    assert_eq!(f.set("spin_creepage", 0.5), OK);
    assert_eq!(f.step(0.0), OK);
    let [_, fy_back, mz_back] = f.forces();
    assert_eq!(f.set("rolling_speed", 30.0), OK);
    assert_eq!(f.step(0.0), OK);
    let [_, fy_fwd, mz_fwd] = f.forces();
    assert!(fy_fwd < 0.0, "Kalker: F_y = -G c^3 C23 phi for phi > 0");
    assert!((fy_back + fy_fwd).abs() <= 1e-9 * fy_fwd.abs());
    assert!((mz_back - mz_fwd).abs() <= 1e-9 * mz_fwd.abs());
    // standstill: finite, equal to the solve at minimum_speed
    assert_eq!(f.set("spin_creepage", 0.0), OK);
    assert_eq!(f.set("creepage_longitudinal", 0.003), OK);
    assert_eq!(f.set("rolling_speed", 0.01), OK);
    assert_eq!(f.step(0.0), OK);
    let at_minimum = f.forces();
    for v in [0.0, 1e-9, -1e-9] {
        assert_eq!(f.set("rolling_speed", v), OK);
        assert_eq!(f.step(0.0), OK);
        let still = f.forces();
        assert!(still.iter().all(|x| x.is_finite()));
        assert!(
            close(still, at_minimum, 1e-5),
            "V = {v}: {still:?} vs {at_minimum:?}"
        );
    }
}

#[test]
fn lifted_wheel_gives_zero_forces_without_error() {
    let f = Fmu::new("lifted", None);
    assert_eq!(f.set("normal_force", 0.0), OK);
    assert_eq!(f.set("creepage_longitudinal", 0.01), OK);
    assert_eq!(f.set("bulk_temperature", 300.0), OK);
    assert_eq!(f.set_int("mode", 2), OK);
    assert_eq!(f.init(), OK);
    for load in [0.0, -5e3] {
        assert_eq!(f.set("normal_force", load), OK);
        assert_eq!(f.step(0.0), OK);
        assert_eq!(f.forces(), [0.0; 3]);
        assert_eq!(f.get("traction_coefficient"), 0.0);
        assert_eq!(f.get("max_temperature"), 300.0);
        assert!(f.get_bool("converged"));
    }
    assert!(f.errors().is_empty());
}

/// `frictional_power` [W]: in mode 2 the exact solver's Σ|τ|·|s|·dA (the library's, bit for bit), which in
/// full sliding approaches |F|·|V|·|ξ| (every cell slips at about the rigid slip speed) and in partial slip
/// stays below it (the stick zone dissipates nothing); in mode 1 the bundled table's, within its accuracy
/// of the exact one; 0 for a lifted wheel.
#[test]
fn frictional_power_is_the_dissipation_in_every_mode() {
    let table = root().join("fmu/resources/table");
    let table = CString::new(table.to_str().unwrap()).unwrap();
    let exact = Fmu::new("power-exact", None);
    assert_eq!(exact.set_int("mode", 2), OK);
    assert_eq!(exact.set_bool("warm_start", false), OK);
    let by_table = Fmu::new("power-table", None);
    assert_eq!(by_table.set_int("mode", 1), OK);
    assert_eq!(
        unsafe { (fmi().set_string)(by_table.c, &vr("table_file"), 1, &table.as_ptr()) },
        OK
    );
    // the table's grid (the default 30 × 30), not the tests' small one of `Fmu::init`
    for f in [&exact, &by_table] {
        assert_eq!(f.set("creepage_longitudinal", 0.002), OK);
        assert_eq!(f.initialize(), OK, "{:?}", f.messages());
    }
    let (speed, load) = (exact.get("rolling_speed"), exact.get("normal_force"));
    for xi in [0.002, 0.08] {
        for f in [&exact, &by_table] {
            assert_eq!(f.set("creepage_longitudinal", xi), OK);
            assert_eq!(f.step(0.0), OK);
        }
        let p = exact.get("frictional_power");
        let mut params = Params::default();
        params.grid.nx = 30;
        params.grid.ny = 30;
        let pt = OperatingPoint {
            creepage_x: xi,
            ..OperatingPoint::default()
        };
        let library = wheelrail::solve(&params, &pt)
            .unwrap()
            .global
            .frictional_power;
        assert_eq!(p.to_bits(), library.to_bits(), "{p} vs {library}");
        let creep_power = exact.get("force_longitudinal").abs() * speed * xi;
        if xi > 0.05 {
            assert!((p / creep_power - 1.0).abs() < 0.02, "{p} vs {creep_power}");
        } else {
            assert!(p > 0.0 && p < creep_power, "{p} vs {creep_power}");
        }
        // the table's value within 1 % of F_N·V·ξ of the exact one
        let t = by_table.get("frictional_power");
        assert_eq!(by_table.get_int("evaluation_mode"), 1);
        assert!((t - p).abs() < 0.01 * load * speed * xi, "{t} vs {p}");
    }
    assert_eq!(exact.set("normal_force", 0.0), OK);
    assert_eq!(exact.step(0.0), OK);
    assert_eq!(exact.get("frictional_power"), 0.0);
}

#[test]
fn non_finite_inputs_are_rejected_by_name_and_wetness_is_clamped_once() {
    let f = Fmu::new("bad", None);
    assert_eq!(f.set_int("mode", 2), OK);
    assert_eq!(f.init(), OK);
    for (name, x) in [
        ("creepage_lateral", f64::NAN),
        ("normal_force", f64::INFINITY),
        ("wetness", f64::NEG_INFINITY),
    ] {
        assert_eq!(f.set(name, x), ERROR);
        let e = f.last_error();
        assert!(e.contains(name) && e.contains("not a finite number"), "{e}");
    }
    // rejected values change nothing: the instance goes on
    assert_eq!(f.step(0.0), OK);
    assert_eq!(f.set("wetness", 1.5), OK);
    assert_eq!(f.step(0.0), WARNING);
    let clamped = f.forces();
    assert_eq!(f.set("wetness", -0.5), OK);
    assert_eq!(f.step(0.0), OK);
    assert_eq!(f.set("wetness", 1.0), OK);
    assert_eq!(f.step(0.0), OK);
    assert_eq!(f.forces(), clamped);
    let warnings = f
        .messages()
        .iter()
        .filter(|m| m.status == WARNING && m.text.contains("wetness"))
        .count();
    assert_eq!(warnings, 1);
    // out of the model's range: the step fails naming the variable, and the instance needs a reset
    assert_eq!(f.set("creepage_longitudinal", 2.5), OK);
    assert_eq!(f.step(0.0), ERROR);
    assert!(
        f.last_error().contains("creepage_longitudinal: 2.5"),
        "{}",
        f.last_error()
    );
    assert_eq!(f.step(0.0), ERROR);
    assert!(f.last_error().contains("Illegal call sequence"));
    assert_eq!(unsafe { (fmi().reset)(f.c) }, OK);
    assert_eq!(f.init(), WARNING);
}

#[test]
fn illegal_call_sequences_and_null_pointers_are_errors() {
    let f = Fmu::new("seq", None);
    assert_eq!(f.step(0.0), ERROR);
    assert!(
        f.last_error().contains("fmi2DoStep: Illegal call sequence"),
        "{:?}",
        f.errors()
    );
    let mut x = 0.0;
    assert_eq!(
        unsafe { (fmi().get_real)(f.c, &vr("force_longitudinal"), 1, &mut x) },
        ERROR
    );
    assert!(f.last_error().contains("Illegal call sequence"));
    assert_eq!(unsafe { (fmi().exit_initialization_mode)(f.c) }, ERROR);
    assert_eq!(unsafe { (fmi().cancel_step)(f.c) }, ERROR);
    f.init();
    assert_eq!(f.set("roughness", 0.1), ERROR);
    assert!(f.last_error().contains("parameter roughness is fixed"));
    assert_eq!(f.set("force_lateral", 1.0), ERROR);
    assert_eq!(unsafe { (fmi().enter_initialization_mode)(f.c) }, ERROR);
    // null pointers
    unsafe {
        assert_eq!((fmi().get_real)(f.c, null(), 1, &mut x), ERROR);
        assert!(f.last_error().contains("vr[] is a null pointer"));
        assert_eq!(
            (fmi().get_real)(f.c, &vr("force_lateral"), 1, null_mut()),
            ERROR
        );
        assert_eq!((fmi().set_real)(f.c, &vr("wetness"), 1, null()), ERROR);
        assert_eq!((fmi().get_fmu_state)(f.c, null_mut()), ERROR);
        assert_eq!((fmi().set_fmu_state)(f.c, null_mut()), ERROR);
        assert_eq!((fmi().do_step)(null_mut(), 0.0, 1.0, 0), ERROR);
        assert_eq!(
            (fmi().directional_derivative)(f.c, null(), 1, null(), 1, null(), null_mut()),
            ERROR
        );
        let nulls = [null::<c_char>()];
        assert_eq!((fmi().set_debug_logging)(f.c, 1, 1, nulls.as_ptr()), ERROR);
        let unknown = [c"logNonsense".as_ptr()];
        assert_eq!(
            (fmi().set_debug_logging)(f.c, 1, 1, unknown.as_ptr()),
            ERROR
        );
        assert!(f.last_error().contains("logNonsense"));
        assert!(
            (fmi().instantiate)(c"x".as_ptr(), 1, fmi().guid.as_ptr(), null(), null(), 0, 0)
                .is_null()
        );
        (fmi().free_instance)(null_mut());
    }
    // everything above left the instance usable
    assert_eq!(f.step(0.0), OK);
}

#[test]
fn instantiation_checks_guid_and_type() {
    let log = Arc::new(Mutex::new(Vec::new()));
    let env = LogEnv {
        sink: collect,
        messages: Arc::as_ptr(&log),
    };
    let cb = Callbacks {
        logger: Some(c_logger()),
        allocate: null(),
        free: null(),
        step_finished: null(),
        env: &env as *const LogEnv as *mut c_void,
    };
    unsafe {
        assert!(
            (fmi().instantiate)(c"g".as_ptr(), 1, c"{wrong}".as_ptr(), null(), &cb, 0, 0).is_null()
        );
        assert!(
            (fmi().instantiate)(c"g".as_ptr(), 2, fmi().guid.as_ptr(), null(), &cb, 0, 0).is_null()
        );
    }
    let msgs = log.lock().unwrap().clone();
    assert!(msgs[0].text.contains("fmuGUID does not match") && msgs[0].instance == "g");
    assert!(
        msgs[1]
            .text
            .contains("fmuType 2 is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)")
            && msgs[1].category == "logStatusError",
        "{msgs:?}"
    );
}

/// Exact mode with `tangential` = 1: the outputs are the library's with Kalker's exact steady rolling (a
/// cold solve: bit for bit), not FASTSIM's.
#[test]
fn exact_mode_with_tangential_one_gives_the_librarys_exact_tangential_result() {
    let f = Fmu::new("tangential", None);
    assert_eq!(f.set_bool("warm_start", false), OK);
    assert_eq!(f.set_int("mode", 2), OK);
    assert_eq!(f.set_int("tangential", 1), OK);
    assert_eq!(f.set("creepage_longitudinal", 0.002), OK);
    assert_eq!(f.set("creepage_lateral", 0.0005), OK);
    assert_eq!(f.init(), OK, "{:?}", f.messages());
    let pt = OperatingPoint {
        creepage_x: 0.002,
        creepage_y: 0.0005,
        ..OperatingPoint::default()
    };
    let got = f.forces();
    let exact = library_forces(|p| p.tangential = wheelrail::Tangential::Exact, pt);
    assert!(close(got, exact, 1e-12), "{got:?} vs {exact:?}");
    let fastsim = library_forces(|_| {}, pt);
    assert!(!close(got, fastsim, 1e-3), "{got:?} vs FASTSIM {fastsim:?}");
    assert_eq!(f.get_int("evaluation_mode"), 2);
    assert!(f.get_bool("converged"));
    // an unknown method is refused by name at initialization
    let g = Fmu::new("tangential-bad", None);
    assert_eq!(g.set_int("mode", 2), OK);
    assert_eq!(g.set_int("tangential", 3), OK);
    assert_eq!(g.init(), ERROR);
    assert!(
        g.last_error().contains("tangential: 3"),
        "{}",
        g.last_error()
    );
}

/// The interfacial layer's parameters reach the model: in exact mode the outputs are the library's with
/// the layer (a cold solve: bit for bit), whose linear slope is lower; the bundled table, built without a
/// layer, refuses them in table-only mode and leaves them to the exact solver in auto mode.
#[test]
fn the_layer_parameters_reach_the_model_and_the_bundled_table_leaves_them_to_the_exact_solver() {
    let (h, g3) = (4e-4, 6e9);
    let pt = OperatingPoint {
        creepage_x: 0.0005,
        ..OperatingPoint::default()
    };
    let layered = |mode: i32| {
        let f = Fmu::new("layer", None);
        assert_eq!(f.set_bool("warm_start", false), OK);
        assert_eq!(f.set_int("mode", mode), OK);
        assert_eq!(f.set("layer_thickness", h), OK);
        assert_eq!(f.set("layer_shear_modulus", g3), OK);
        assert_eq!(f.set("creepage_longitudinal", pt.creepage_x), OK);
        f
    };
    let f = layered(2);
    assert_eq!(f.init(), OK, "{:?}", f.messages());
    let got = f.forces();
    let want = library_forces(
        |p| {
            p.layer.thickness = h;
            p.layer.shear_modulus = g3;
        },
        pt,
    );
    assert!(close(got, want, 1e-12), "{got:?} vs {want:?}");
    let without = library_forces(|_| {}, pt);
    assert!(
        got[0] > 0.8 * without[0] && got[0] < 0.0,
        "{got:?} vs {without:?}"
    );
    // the bundled table's parameters (the default grid) with and without the layer: table only takes
    // them without it and refuses them with it at initialization; auto solves exactly, with a warning
    let table = CString::new(root().join("fmu/resources/table").to_str().unwrap()).unwrap();
    let no_layer = wheelrail::params::Layer::default();
    for (mode, layer, status) in [
        (1, [no_layer.thickness, no_layer.shear_modulus], OK),
        (1, [h, g3], ERROR),
        (0, [h, g3], WARNING),
    ] {
        let f = layered(mode);
        assert_eq!(f.set("layer_thickness", layer[0]), OK);
        assert_eq!(f.set("layer_shear_modulus", layer[1]), OK);
        assert_eq!(
            unsafe { (fmi().set_string)(f.c, &vr("table_file"), 1, &table.as_ptr()) },
            OK
        );
        assert_eq!(f.initialize(), status, "mode {mode}: {:?}", f.messages());
        if layer[0] == 0.0 {
            assert_eq!(f.step(0.0), OK);
            assert_eq!(f.get_int("evaluation_mode"), 1);
        } else if mode == 1 {
            assert!(
                f.last_error()
                    .contains("parameters differ from those the lookup table"),
                "{}",
                f.last_error()
            );
        } else {
            assert_eq!(f.step(0.0), OK);
            assert_eq!(f.get_int("evaluation_mode"), 2);
        }
    }
}

#[test]
fn table_only_mode_without_a_table_fails_at_initialization() {
    let dir = target_dir().join(format!("fmu-test-resources-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = Fmu::new("table", Some(&dir));
    assert_eq!(f.set_int("mode", 1), OK);
    assert_eq!(f.init(), ERROR);
    let e = f.last_error();
    assert!(
        e.contains("table only")
            && e.contains(&format!(
                "no lookup table at {}",
                dir.join("table").display()
            )),
        "{e}"
    );
    assert_eq!(f.step(0.0), ERROR);
    // auto mode falls back with one warning, naming the missing table
    let g = Fmu::new("auto", Some(&dir));
    let missing = CString::new("/nonexistent/wheelrail.table").unwrap();
    assert_eq!(
        unsafe { (fmi().set_string)(g.c, &vr("table_file"), 1, &missing.as_ptr()) },
        OK
    );
    assert_eq!(g.init(), WARNING);
    assert_eq!(g.step(0.0), OK);
    let warnings: Vec<_> = g
        .messages()
        .into_iter()
        .filter(|m| m.status == WARNING)
        .collect();
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].text.contains("/nonexistent/wheelrail.table")
            && warnings[0].category == "logStatusWarning"
    );
    assert_eq!(g.get_int("evaluation_mode"), 2);
    let mut s: *const c_char = null();
    assert_eq!(
        unsafe { (fmi().get_string)(g.c, &vr("table_file"), 1, &mut s) },
        OK
    );
    assert_eq!(unsafe { CStr::from_ptr(s) }, missing.as_c_str());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn fmu_states_round_trip_in_memory_and_serialized() {
    let f = Fmu::new("state", None);
    assert_eq!(f.set("roughness", 0.8), OK);
    assert_eq!(f.set_int("mode", 2), OK);
    f.init();
    assert_eq!(f.set("creepage_longitudinal", 0.004), OK);
    assert_eq!(f.step(0.0), OK);
    let a = f.forces();
    let mut state: *mut c_void = null_mut();
    assert_eq!(unsafe { (fmi().get_fmu_state)(f.c, &mut state) }, OK);
    assert_eq!(f.set("creepage_longitudinal", 0.01), OK);
    assert_eq!(f.step(1e-3), OK);
    assert_ne!(f.forces(), a);
    assert_eq!(unsafe { (fmi().set_fmu_state)(f.c, state) }, OK);
    assert_eq!(f.forces(), a);
    assert_eq!(f.get("creepage_longitudinal"), 0.004);
    // serialize, restore into a fresh instance with other parameters
    let mut size = 0usize;
    assert_eq!(
        unsafe { (fmi().serialized_size)(f.c, state, &mut size) },
        OK
    );
    let mut bytes = vec![0 as c_char; size];
    assert_eq!(
        unsafe { (fmi().serialize)(f.c, state, bytes.as_mut_ptr(), size) },
        OK
    );
    let g = Fmu::new("state-copy", None);
    let mut restored: *mut c_void = null_mut();
    assert_eq!(
        unsafe { (fmi().deserialize)(g.c, bytes.as_ptr(), size, &mut restored) },
        OK
    );
    assert_eq!(unsafe { (fmi().set_fmu_state)(g.c, restored) }, OK);
    assert_eq!(g.forces(), a);
    assert_eq!(g.get("roughness"), 0.8);
    assert_eq!(g.step(1e-3), OK);
    assert_eq!(g.forces(), a);
    // corrupt and truncated bytes are rejected
    for (i, bad) in [size / 3, size - 1].into_iter().enumerate() {
        let mut b = bytes.clone();
        b[bad] ^= 0x10;
        assert_eq!(
            unsafe { (fmi().deserialize)(g.c, b.as_ptr(), size, &mut restored) },
            ERROR,
            "case {i}"
        );
        assert!(g.last_error().contains("corrupt"), "{}", g.last_error());
    }
    assert_eq!(
        unsafe { (fmi().deserialize)(g.c, bytes.as_ptr(), size - 9, &mut restored) },
        ERROR
    );
    assert_eq!(
        unsafe { (fmi().deserialize)(g.c, bytes.as_ptr(), 3, &mut restored) },
        ERROR
    );
    unsafe {
        assert_eq!((fmi().free_fmu_state)(f.c, &mut state), OK);
        assert_eq!((fmi().free_fmu_state)(g.c, &mut restored), OK);
    }
    assert!(state.is_null() && restored.is_null());
}

#[test]
fn two_instances_with_different_parameters_run_side_by_side() {
    let make = |name: &str, roughness: f64, bulk: f64| {
        let f = Fmu::new(name, None);
        assert_eq!(f.set("roughness", roughness), OK);
        assert_eq!(f.set("bulk_temperature", bulk), OK);
        assert_eq!(f.set_int("mode", 2), OK);
        assert_eq!(f.set_bool("warm_start", false), OK);
        assert_eq!(f.init(), OK);
        f
    };
    let smooth = make("smooth", 0.1, 293.15);
    let rough = make("rough", 0.9, 320.0);
    let run = |f: Fmu, xi: f64| {
        std::thread::spawn(move || {
            let mut out = Vec::new();
            for k in 1..=4 {
                assert_eq!(f.set("creepage_longitudinal", xi * f64::from(k)), OK);
                assert_eq!(f.step(0.0), OK);
                out.push(f.forces());
            }
            (f, out)
        })
    };
    let (ta, tb) = (run(smooth, 0.002), run(rough, 0.002));
    let (smooth, a) = ta.join().unwrap();
    let (rough, b) = tb.join().unwrap();
    for k in 0..4 {
        let pt = OperatingPoint {
            creepage_x: 0.002 * (k + 1) as f64,
            ..OperatingPoint::default()
        };
        let la = library_forces(|p| p.roughness.k_r = 0.1, pt);
        let lb = library_forces(
            |p| {
                p.roughness.k_r = 0.9;
                p.material.bulk_temperature = 320.0;
            },
            pt,
        );
        assert!(close(a[k], la, 1e-12) && close(b[k], lb, 1e-12), "step {k}");
    }
    assert_ne!(a[3], b[3]);
    assert!(smooth.messages().iter().all(|m| m.instance == "smooth"));
    assert!(rough.messages().iter().all(|m| m.instance == "rough"));
}

/// How one of the concurrent instances evaluates and which contacts its steps have.
struct Lane {
    name: &'static str,
    /// `mode`: 0 auto (the bundled table, the exact solver where it does not serve), 1 table only,
    /// 2 exact only.
    mode: i32,
    /// `grid_size` (None: the default, which the bundled table was built for).
    grid: Option<i32>,
    /// `tangential`: 0 FASTSIM, 1 Kalker's exact steady rolling.
    tangential: i32,
    wet: bool,
    contact: LaneContact,
}

/// The contact geometry of a lane's steps.
#[derive(Clone, Copy, PartialEq)]
enum LaneContact {
    /// The default gap curvatures (the bundled table's contact).
    Default,
    /// New gap curvatures A, B every step.
    Curvatures,
    /// New prescribed semi-axes a, b every step.
    SemiAxes,
    /// In turn the default contact, new curvatures and a prescribed flange-root ellipse (a/b 2–4, p_ref
    /// 1.0–1.2 GPa: outside the bundled table).
    Mixed,
}

/// The inputs a lane sets before each step, in the order of [`Lane::inputs`].
const LANE_INPUTS: [&str; 10] = [
    "creepage_longitudinal",
    "creepage_lateral",
    "spin_creepage",
    "normal_force",
    "rolling_speed",
    "wetness",
    "curvature_longitudinal",
    "curvature_lateral",
    "semi_axis_a",
    "semi_axis_b",
];

/// Steps per lane.
const LANE_STEPS: usize = 30;

/// What a step leaves: its status, the bits of every Real output, `evaluation_mode` and `converged`.
type LaneStep = (c_int, [u64; REAL_OUTPUTS.len()], i32, bool);

impl Lane {
    /// The lane's deterministic input sequence (its own seed: `seed`), inside the bundled table's range of
    /// creepage, load, speed and wetness.
    fn inputs(&self, seed: u64) -> Vec<[f64; LANE_INPUTS.len()]> {
        let mut rng = wheelrail::table::verify::SplitMix64::new(seed);
        let defaults = Params::default().geometry;
        (0..LANE_STEPS)
            .map(|k| {
                let mut u = || rng.uniform();
                let (xi, eta, spin) = (0.008 * u() - 0.002, 0.004 * u() - 0.002, 0.4 * u() - 0.2);
                let (load, speed) = (70e3 + 60e3 * u(), 10.0 + 30.0 * u());
                let wetness = if self.wet { 0.02 + 0.98 * u() } else { 0.0 };
                let mut geometry = [defaults.curvature_x, defaults.curvature_y, 0.0, 0.0];
                let contact = match (self.contact, k % 3) {
                    (LaneContact::Mixed, 0) => LaneContact::Default,
                    (LaneContact::Mixed, 1) => LaneContact::Curvatures,
                    (c, _) => c,
                };
                match contact {
                    LaneContact::Default => {}
                    LaneContact::Curvatures => {
                        geometry[..2].copy_from_slice(&[0.5 + u(), 0.3 + u()])
                    }
                    LaneContact::SemiAxes | LaneContact::Mixed => {
                        let (ratio, p_ref) = if self.contact == LaneContact::Mixed {
                            (2.0 + 2.0 * u(), 1.0e9 + 0.2e9 * u())
                        } else {
                            (0.4 + 2.6 * u(), 0.7e9 + 0.5e9 * u())
                        };
                        let [a, b] = wheelrail::table::coords::semi_axes(ratio, p_ref, load);
                        geometry[2..].copy_from_slice(&[a, b]);
                    }
                }
                let [a_x, b_y, a, b] = geometry;
                [xi, eta, spin, load, speed, wetness, a_x, b_y, a, b]
            })
            .collect()
    }

    /// A new, initialised instance of the lane (warm starts on unless `warm` is false).
    fn instance(&self, warm: bool) -> Fmu {
        let f = Fmu::new(self.name, None);
        assert_eq!(f.set_int("mode", self.mode), OK);
        assert_eq!(f.set_int("tangential", self.tangential), OK);
        assert_eq!(f.set_bool("warm_start", warm), OK);
        if let Some(grid) = self.grid {
            assert_eq!(f.set_int("grid_size", grid), OK);
        }
        if self.mode != 2 {
            let table = CString::new(root().join("fmu/resources/table").to_str().unwrap()).unwrap();
            assert_eq!(
                unsafe { (fmi().set_string)(f.c, &vr("table_file"), 1, &table.as_ptr()) },
                OK
            );
        }
        assert_eq!(f.initialize(), OK, "{}: {:?}", self.name, f.messages());
        f
    }
}

/// Steps `f` through `inputs` (every step at most a warning), returning what each step left.
fn run_lane(f: &Fmu, inputs: &[[f64; LANE_INPUTS.len()]]) -> Vec<LaneStep> {
    inputs
        .iter()
        .enumerate()
        .map(|(k, x)| {
            for (name, value) in LANE_INPUTS.iter().zip(x) {
                assert_eq!(
                    f.set(name, *value),
                    OK,
                    "{name} = {value}: {:?}",
                    f.errors()
                );
            }
            let status = f.step(1e-3 * k as f64);
            assert!(status <= WARNING, "step {k}: {:?}", f.messages());
            let (outputs, mode) = f.outputs();
            (
                status,
                outputs.map(f64::to_bits),
                mode,
                f.get_bool("converged"),
            )
        })
        .collect()
}

/// Eight instances, each with its own parameters and input sequence, stepped concurrently on eight threads
/// (started together at a barrier, so their steps interleave): exact mode on small grids, dry and wet, with
/// new gap curvatures or prescribed semi-axes every step, one with Kalker's exact tangential solver; table
/// mode with the bundled table, dry and wet; mode auto with the bundled table at contacts in turn inside it
/// and outside it (the exact fallback); warm starts on. Each must give bit for bit the outputs of a fresh
/// instance of the same lane stepped after the others on one thread (the table lanes repeat their steps,
/// each time with the same outputs, while the others solve). Concurrent first, so that the
/// process-wide memos (influence tables of the heat model, the microcontact tables, the shared table) are
/// filled by the racing threads.
///
/// What a race would break: a warm start, set-up or output that leaked from one instance into another, or
/// a memo entry read half-written, changes the solve from which an instance starts or the tables it sums,
/// and with that the last digits of its outputs (a warm start alone does: checked below against a cold
/// instance), and the lanes' outputs differ from each other at every step, so outputs landing in the
/// wrong instance would differ too.
#[test]
fn eight_instances_stepped_concurrently_give_the_outputs_of_the_same_stepped_one_after_another() {
    use LaneContact::*;
    let lane = |name, mode, grid, tangential, wet, contact| Lane {
        name,
        mode,
        grid,
        tangential,
        wet,
        contact,
    };
    let lanes = [
        lane("exact-dry-curvatures", 2, Some(10), 0, false, Curvatures),
        lane("exact-wet-curvatures", 2, Some(12), 0, true, Curvatures),
        lane("exact-wet-semi-axes", 2, Some(10), 0, true, SemiAxes),
        lane(
            "exact-tangential-dry-semi-axes",
            2,
            Some(8),
            1,
            false,
            SemiAxes,
        ),
        lane("table-dry", 1, None, 0, false, Default),
        lane("table-wet", 1, None, 0, true, Default),
        lane("auto-dry-fallback", 0, None, 0, false, Mixed),
        lane("auto-wet-fallback", 0, None, 0, true, Mixed),
    ];
    let inputs: Vec<_> = (0..lanes.len())
        .map(|i| lanes[i].inputs(0x5eed + i as u64))
        .collect();
    let start = std::sync::Barrier::new(lanes.len());
    // the lanes that solve, still running: the table lanes (microseconds a step) repeat their steps
    // until none is, so that their lookups run alongside the solves
    let solving = AtomicUsize::new(lanes.iter().filter(|l| l.mode != 1).count());
    let concurrent: Vec<_> = std::thread::scope(|s| {
        let threads: Vec<_> = lanes
            .iter()
            .zip(&inputs)
            .map(|(lane, inputs)| {
                let (start, solving) = (&start, &solving);
                s.spawn(move || {
                    let f = lane.instance(true);
                    start.wait();
                    let steps = run_lane(&f, inputs);
                    if lane.mode == 1 {
                        while solving.load(Ordering::Relaxed) > 0 {
                            assert_eq!(run_lane(&f, inputs), steps, "{}, repeated", lane.name);
                        }
                    } else {
                        solving.fetch_sub(1, Ordering::Relaxed);
                    }
                    (f, steps)
                })
            })
            .collect();
        threads.into_iter().map(|t| t.join().unwrap()).collect()
    });
    for ((lane, inputs), (f, steps)) in lanes.iter().zip(&inputs).zip(&concurrent) {
        let alone = run_lane(&lane.instance(true), inputs);
        for (k, (a, b)) in steps.iter().zip(&alone).enumerate() {
            assert_eq!(
                a,
                b,
                "{}, step {k}: outputs {:?} vs {:?}",
                lane.name,
                a.1.map(f64::from_bits),
                b.1.map(f64::from_bits)
            );
        }
        assert!(
            f.messages().iter().all(|m| m.instance == lane.name),
            "{}: {:?}",
            lane.name,
            f.messages()
        );
        // how each lane evaluated: the exact solver, the table, or (auto) both
        let modes: std::collections::BTreeSet<i32> = steps.iter().map(|s| s.2).collect();
        let expected = match lane.mode {
            0 => vec![1, 2],
            mode => vec![mode],
        };
        assert_eq!(
            modes.into_iter().collect::<Vec<_>>(),
            expected,
            "{}",
            lane.name
        );
    }
    // the lanes differ from each other at every step
    for (i, (_, a)) in concurrent.iter().enumerate() {
        for (j, (_, b)) in concurrent.iter().enumerate().skip(i + 1) {
            for k in 0..LANE_STEPS {
                assert_ne!(
                    a[k].1, b[k].1,
                    "{} and {}, step {k}",
                    lanes[i].name, lanes[j].name
                );
            }
        }
    }
    // a warm start shows in the bits: a cold instance of the first lane differs at some step
    let cold = run_lane(&lanes[0].instance(false), &inputs[0]);
    assert_ne!(cold, concurrent[0].1);
}

#[test]
fn directional_derivatives_match_differences_and_kalkers_linear_stiffness() {
    let f = Fmu::new("jacobian", None);
    assert_eq!(f.set_int("mode", 2), OK);
    assert_eq!(f.set("creepage_longitudinal", 0.002), OK);
    assert_eq!(f.set("creepage_lateral", 0.001), OK);
    assert_eq!(f.init(), OK);
    let unknown = [vr("force_longitudinal"), vr("force_lateral")];
    let known = [vr("creepage_longitudinal"), vr("creepage_lateral")];
    let mut d = [0.0; 2];
    let seed = [1.0, 0.5];
    assert_eq!(f.derivative(&unknown, &known, &seed, &mut d), OK);
    // central difference of the outputs along the same direction
    let h = 2e-5;
    let at = |s: f64| {
        assert_eq!(f.set("creepage_longitudinal", 0.002 + s * h), OK);
        assert_eq!(f.set("creepage_lateral", 0.001 + s * h * 0.5), OK);
        [f.get("force_longitudinal"), f.get("force_lateral")]
    };
    let (up, down) = (at(1.0), at(-1.0));
    for i in 0..2 {
        let central = (up[i] - down[i]) / (2.0 * h);
        assert!(
            (d[i] - central).abs() < 0.01 * central.abs(),
            "output {i}: {} vs {central}",
            d[i]
        );
    }
    // small creepage: dF_x/dxi = -G c^2 C11 (Kalker's linear theory; FASTSIM on 12 x 12 cells within 5 %)
    assert_eq!(f.set("creepage_longitudinal", 1e-7), OK);
    assert_eq!(f.set("creepage_lateral", 0.0), OK);
    assert_eq!(
        f.derivative(&unknown[..1], &known[..1], &[1.0], &mut d[..1]),
        OK
    );
    let p = Params::default();
    let hertz = wheelrail::solver::normal_contact(&p, 100e3).unwrap();
    let m = p.material.at(p.material.bulk_temperature);
    let k = wheelrail::tangential::kalker_coefficients(hertz.a, hertz.b, m.poisson).unwrap();
    let linear = -m.shear_modulus * hertz.a * hertz.b * k.c11;
    assert!((d[0] / linear - 1.0).abs() < 0.05, "{} vs {linear}", d[0]);
    // only Real outputs with respect to Real inputs
    let wrong = [vr("evaluation_mode")];
    assert_eq!(
        f.derivative(&wrong, &known[..1], &[1.0], &mut d[..1]),
        ERROR
    );
    let mut s = 0;
    assert_eq!(unsafe { (fmi().get_status)(f.c, 1, &mut s) }, DISCARD);
}

/// The Real outputs compared bit for bit after a restored state.
const REAL_OUTPUTS: [&str; 10] = [
    "force_longitudinal",
    "force_lateral",
    "spin_moment",
    "traction_coefficient",
    "max_temperature",
    "fluid_load_fraction",
    "contact_semi_axis_a",
    "contact_semi_axis_b",
    "peak_pressure",
    "frictional_power",
];

impl Fmu {
    /// Sets ξ, η, F_N, V, w (no spin).
    fn set_inputs(&self, [xi, eta, load, speed, wetness]: [f64; 5]) {
        for (name, x) in [
            ("creepage_longitudinal", xi),
            ("creepage_lateral", eta),
            ("normal_force", load),
            ("rolling_speed", speed),
            ("wetness", wetness),
        ] {
            assert_eq!(self.set(name, x), OK, "{:?}", self.errors());
        }
    }

    /// Sets ξ, η, F_N, V, w (no spin) and steps.
    fn step_at(&self, t: f64, inputs: [f64; 5]) -> c_int {
        self.set_inputs(inputs);
        self.step(t)
    }

    /// Every Real output and `evaluation_mode`.
    fn outputs(&self) -> ([f64; REAL_OUTPUTS.len()], i32) {
        (
            REAL_OUTPUTS.map(|n| self.get(n)),
            self.get_int("evaluation_mode"),
        )
    }

    /// The serialized bytes of the current FMU state.
    fn serialized_state(&self) -> Vec<c_char> {
        let mut state: *mut c_void = null_mut();
        let mut size = 0usize;
        let mut bytes;
        unsafe {
            assert_eq!((fmi().get_fmu_state)(self.c, &mut state), OK);
            assert_eq!((fmi().serialized_size)(self.c, state, &mut size), OK);
            bytes = vec![0 as c_char; size];
            assert_eq!(
                (fmi().serialize)(self.c, state, bytes.as_mut_ptr(), size),
                OK
            );
            assert_eq!((fmi().free_fmu_state)(self.c, &mut state), OK);
        }
        bytes
    }

    /// Deserializes `bytes` and sets the state into this instance.
    fn restore_from(&self, bytes: &[c_char]) {
        let mut state: *mut c_void = null_mut();
        unsafe {
            assert_eq!(
                (fmi().deserialize)(self.c, bytes.as_ptr(), bytes.len(), &mut state),
                OK,
                "{}",
                self.last_error()
            );
            assert_eq!((fmi().set_fmu_state)(self.c, state), OK);
            assert_eq!((fmi().free_fmu_state)(self.c, &mut state), OK);
        }
    }
}

/// Instances a and b (other parameters) stepped at ξ 0.005, F_N 100 kN, V 30 m/s,
/// wetness 0.5; a's state set into b (the snapshot itself) and, serialized and deserialized, into d (other
/// parameters, as b) and into a fresh instance c; then all continue with varying inputs and must agree bit
/// for bit with a, in modes 0, 1 and 2, warm start on and off; and a, rolled back to its state, repeats
/// its own steps bit for bit. Mode 1 needs a table of a's parameters: a has the defaults with the bundled
/// table, b and d are in mode 0 with roughness 0.8 (the restore brings mode, parameters and table along).
#[test]
fn a_restored_state_continues_bit_for_bit_in_every_mode_with_and_without_warm_start() {
    let table = root().join("fmu/resources/table");
    let table = CString::new(table.to_str().unwrap()).unwrap();
    let make = |name: &str, mode: i32, roughness: f64, warm: bool| {
        let f = Fmu::new(name, None);
        assert_eq!(f.set_int("mode", mode), OK);
        assert_eq!(f.set_bool("warm_start", warm), OK);
        if mode == 1 {
            assert_eq!(
                unsafe { (fmi().set_string)(f.c, &vr("table_file"), 1, &table.as_ptr()) },
                OK
            );
        } else {
            assert_eq!(f.set("roughness", roughness), OK);
            assert_eq!(f.set_int("grid_size", GRID), OK);
        }
        unsafe {
            assert_eq!((fmi().setup_experiment)(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!((fmi().enter_initialization_mode)(f.c), OK);
            assert!((fmi().exit_initialization_mode)(f.c) <= WARNING);
        }
        f
    };
    let before = [0.005, 0.0, 100e3, 30.0, 0.5];
    let after = [
        [0.02, 0.001, 80e3, 20.0, 0.0],
        [0.01, -0.002, 90e3, 25.0, 0.3],
        [0.003, 0.0, 110e3, 30.0, 1.0],
        [0.03, 0.004, 70e3, 15.0, 0.0],
    ];
    for mode in [0, 1, 2] {
        for warm in [true, false] {
            let case = format!("mode {mode}, warm start {warm}");
            let other_mode = if mode == 1 { 0 } else { mode };
            let a = make("a", mode, 0.2, warm);
            let b = make("b", other_mode, 0.8, warm);
            let d = make("d", other_mode, 0.8, warm);
            for f in [&a, &b, &d] {
                assert!(f.step_at(0.0, before) <= WARNING, "{case}");
            }
            assert_ne!(b.outputs(), a.outputs(), "{case}");
            let mut state: *mut c_void = null_mut();
            assert_eq!(unsafe { (fmi().get_fmu_state)(a.c, &mut state) }, OK);
            assert_eq!(unsafe { (fmi().set_fmu_state)(b.c, state) }, OK);
            let bytes = a.serialized_state();
            d.restore_from(&bytes);
            let c = Fmu::new("c", None);
            c.restore_from(&bytes);
            let mut first = Vec::new();
            for (k, inputs) in after.into_iter().enumerate() {
                let t = 1e-3 * (k + 1) as f64;
                assert!(a.step_at(t, inputs) <= WARNING, "{case}, step {k}");
                first.push(a.outputs());
                for (name, f) in [("b", &b), ("c", &c), ("d", &d)] {
                    assert!(f.step_at(t, inputs) <= WARNING, "{case}, step {k}, {name}");
                    assert_eq!(f.outputs(), a.outputs(), "{case}, step {k}, {name}");
                }
            }
            assert_eq!(a.get_int("evaluation_mode"), if mode == 1 { 1 } else { 2 });
            // a rolled back to its own state repeats its steps
            assert_eq!(unsafe { (fmi().set_fmu_state)(a.c, state) }, OK);
            for (k, inputs) in after.into_iter().enumerate() {
                assert!(a.step_at(1e-3 * (k + 1) as f64, inputs) <= WARNING);
                assert_eq!(a.outputs(), first[k], "{case}, repeated step {k}");
            }
            assert_eq!(unsafe { (fmi().free_fmu_state)(a.c, &mut state) }, OK);
        }
    }
}

/// The derivative's unperturbed point is solved from the warm start: back at the same values after other
/// steps (another warm start), the derivative is that of a fresh instance restored to this state, not a
/// reuse of the one solved from the earlier warm start.
#[test]
fn derivatives_after_a_restore_or_a_return_to_the_same_values_are_those_of_the_state() {
    let f = Fmu::new("derivatives", None);
    assert_eq!(f.set_int("mode", 2), OK);
    f.init();
    let at = [0.004, 0.0, 100e3, 30.0, 0.5];
    let (unknown, known) = ([vr("force_longitudinal")], [vr("creepage_longitudinal")]);
    let derivative = |f: &Fmu| {
        let mut d = [f64::NAN];
        assert_eq!(f.derivative(&unknown, &known, &[1.0], &mut d), OK);
        d[0]
    };
    assert_eq!(f.step_at(0.0, at), OK);
    let first = derivative(&f);
    assert_eq!(f.step_at(1e-3, [0.02, 0.002, 80e3, 20.0, 0.0]), OK);
    assert_eq!(f.step_at(2e-3, at), OK);
    let again = derivative(&f);
    let g = Fmu::new("fresh", None);
    let bytes = f.serialized_state();
    g.restore_from(&bytes);
    assert_eq!(derivative(&g), again);
    // bit-flipped in the warm start, or truncated: refused, with the reason logged
    let mut flipped = bytes.clone();
    flipped[bytes.len() - 100] ^= 1;
    for (bad, why) in [
        (&flipped[..], "corrupt"),
        (&bytes[..bytes.len() / 2], "corrupt"),
    ] {
        let mut state: *mut c_void = null_mut();
        let status = unsafe { (fmi().deserialize)(g.c, bad.as_ptr(), bad.len(), &mut state) };
        assert_eq!(status, ERROR);
        assert!(
            state.is_null() && g.last_error().contains(why),
            "{}",
            g.last_error()
        );
    }
    assert_eq!(g.outputs(), f.outputs());
    // the warm starts differ, so the solves do (in the last digits)
    assert_ne!(again, first);
}

mod model_exchange;

/// `table_file` naming several tables separated by `;`: each step goes to the first table that covers its
/// contact and holds the point (bit for bit that table's result alone), a contact none covers to the
/// exact solver with one warning naming every table; a missing table is a warning in mode 0 (the others
/// are used) and an error in mode 1. Two tables for the tests' parameters: the small test table (the
/// default running-surface contact) and one over flange-root contacts (a/b 2–2.4, p_ref 1.0–1.2 GPa).
#[test]
fn several_tables_serve_the_contacts_each_covers() {
    let mut params = Params::default();
    params.grid.nx = GRID as usize;
    params.grid.ny = GRID as usize;
    let small =
        wheelrail::table::Axes::from_toml_file(&root().join("tests/fixtures/small-axes.toml"))
            .unwrap();
    let mut flange = small.clone();
    flange.0[6].points = vec![2.0, 2.4];
    flange.0[7].points = vec![1.0e9, 1.2e9];
    let dirs: Vec<PathBuf> = [("tread", &small), ("flange", &flange)]
        .into_iter()
        .map(|(name, axes)| {
            let dir = std::env::temp_dir().join(format!(
                "wheelrail-fmu-tables-{name}-{}",
                std::process::id()
            ));
            let mut files = wheelrail::table::build(&params, axes, None, &|| ()).unwrap();
            files.write(&dir).unwrap();
            dir
        })
        .collect();
    let make = |name: &str, mode: i32, table_file: &str| {
        let f = Fmu::new(name, None);
        assert_eq!(f.set_int("mode", mode), OK);
        let s = CString::new(table_file).unwrap();
        assert_eq!(
            unsafe { (fmi().set_string)(f.c, &vr("table_file"), 1, &s.as_ptr()) },
            OK
        );
        let status = f.init();
        (f, status)
    };
    let path = |d: &PathBuf| d.to_str().unwrap().to_string();
    let both = format!("{};{}", path(&dirs[0]), path(&dirs[1]));
    let (set, status) = make("set", 0, &both);
    assert_eq!(status, OK, "{:?}", set.messages());
    let (tread, _) = make("tread", 0, &path(&dirs[0]));
    let (root_only, _) = make("flange", 0, &path(&dirs[1]));
    // the default contact: the tread table; a flange-root ellipse (a/b 2.2, p_ref 1.1 GPa): the other
    let [a, b] = wheelrail::table::coords::semi_axes(2.2, 1.1e9, 100e3);
    for (semi_axes, alone) in [([0.0, 0.0], &tread), ([a, b], &root_only)] {
        for f in [&set, alone] {
            assert_eq!(f.set("semi_axis_a", semi_axes[0]), OK);
            assert_eq!(f.set("semi_axis_b", semi_axes[1]), OK);
            assert_eq!(f.set("creepage_longitudinal", 0.003), OK);
            assert_eq!(f.step(0.0), OK, "{:?}", f.messages());
            assert_eq!(f.get_int("evaluation_mode"), 1);
        }
        assert_eq!(set.forces(), alone.forces(), "{semi_axes:?}");
        assert!(set.forces()[0] < 0.0, "{:?}", set.forces());
    }
    // the log says which table serves the contact, at the first step by each table; back on the tread
    // table nothing more (an instance of one table logs none)
    assert_eq!(set.set("semi_axis_a", 0.0), OK);
    assert_eq!(set.set("semi_axis_b", 0.0), OK);
    assert_eq!(set.step(0.0), OK);
    let served = |f: &Fmu| -> Vec<String> {
        f.messages()
            .into_iter()
            .filter(|m| m.status == OK && m.text.contains("serves this contact"))
            .map(|m| m.text)
            .collect()
    };
    let events = served(&set);
    assert_eq!(events.len(), 2, "{events:?}");
    for (k, (event, dir)) in events.iter().zip(&dirs).enumerate() {
        assert!(
            event.contains(&format!("at {} (table {} of 2", path(dir), k + 1)),
            "{event}"
        );
    }
    assert!(served(&tread).is_empty() && served(&root_only).is_empty());
    // an ellipse between them (a/b 1): the exact solver, one warning naming both tables
    let [a, b] = wheelrail::table::coords::semi_axes(1.0, 0.9e9, 100e3);
    assert_eq!(set.set("semi_axis_a", a), OK);
    assert_eq!(set.set("semi_axis_b", b), OK);
    assert_eq!(set.step(0.0), WARNING);
    assert_eq!(set.get_int("evaluation_mode"), 2);
    assert_eq!(set.step(0.0), OK);
    let warnings: Vec<String> = set
        .messages()
        .into_iter()
        .filter(|m| m.status == WARNING)
        .map(|m| m.text)
        .collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("contact geometry") && warnings[0].contains(&both.replace(';', "; ")),
        "{warnings:?}"
    );
    // a missing table: mode 0 warns and uses the other, mode 1 refuses
    let with_missing = format!("{};/nonexistent/table", path(&dirs[0]));
    let (f, status) = make("missing", 0, &with_missing);
    assert_eq!(status, WARNING);
    assert!(
        f.messages()
            .iter()
            .any(|m| m.text.contains("no lookup table at /nonexistent/table")
                && m.text.contains("using the other lookup tables")),
        "{:?}",
        f.messages()
    );
    assert_eq!(f.step(0.0), OK);
    assert_eq!(f.get_int("evaluation_mode"), 1);
    let (f, status) = make("missing-only", 1, &with_missing);
    assert_eq!(status, ERROR);
    assert!(f.last_error().contains("table only"), "{}", f.last_error());
    for d in dirs {
        std::fs::remove_dir_all(d).unwrap();
    }
}
