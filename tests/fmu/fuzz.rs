//! A fuzzer of FMI 2.0 Co-Simulation call sequences against the FMU's shared library
//! (`libWheelRailFriction.so`, loaded as a master loads it: the exported C symbols, the variadic logger
//! through the C logger of the parent module, which like the Reference-FMUs' `fmusim` interprets what
//! it is given as a `printf` format).
//!
//! Each sequence is a list of calls generated from its own 64-bit seed (a deterministic PRNG): every
//! co-simulation function in random order on up to two instances (legal life cycles most of the time,
//! illegal orders often), FMU states got, set, freed twice or freed by the state itself (as `fmusim` does),
//! serialized blobs truncated and bit-flipped, value references out of range, NaN, ±inf, huge, negative
//! and subnormal inputs, bad string parameters (null, non-UTF-8, `%` formats, missing, empty and
//! byte-wise corrupted table directories), null component and array pointers.
//!
//! Invariants checked on every call: the status is an FMI status; a call that the FMI 2.0 co-simulation
//! state machine forbids in every state the instance may be in returns `fmi2Error`; after `fmi2OK` or
//! `fmi2Warning` every value read is finite, and after a step or initialization every Real output is; a
//! status other than OK comes with a log line of at least that severity (unless the master switched that
//! category off, or there is no logger or instance); every log line names its instance verbatim.
//!
//! Sequences run in child processes (this test binary, re-run with `WHEELRAIL_FUZZ_WORKER`), two at a
//! time, each with a watchdog: a crash or a hang is reported with the sequence's seed. A failing sequence
//! is shrunk (calls removed while the failure persists, each attempt in a child) and printed as the call
//! log that reproduces it (`WHEELRAIL_FUZZ_REPLAY=<seed>` replays one seed). Budget:
//! `WHEELRAIL_FUZZ_SEQUENCES` (default 10 000, a few seconds on two cores), `WHEELRAIL_FUZZ_SEED`
//! (default 16); `make fuzz` runs 100 000. The tables: the small table of `tests/fixtures/small-axes.toml`
//! (grid 6, default parameters, built once into `target/fmu-fuzz`), byte-wise corrupted and truncated
//! copies of it, and the bundled table.

use super::*;
use std::io::{BufRead, BufReader, Write};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use wheelrail::table::Table;

const DEFAULT_SEQUENCES: u64 = 10_000;
const DEFAULT_SEED: u64 = 16;
const WORKERS: u64 = 2;
/// A sequence running longer than this is a hang.
const WATCHDOG: Duration = Duration::from_secs(60);
const WORKER_ENV: &str = "WHEELRAIL_FUZZ_WORKER";
const REPLAY_ENV: &str = "WHEELRAIL_FUZZ_REPLAY";
const KEEP_ENV: &str = "WHEELRAIL_FUZZ_KEEP";
const FATAL: c_int = 4;

/// SplitMix64 (Steele, Lea, Flood 2014): a small deterministic PRNG.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn chance(&mut self, p: f64) -> bool {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 > 1.0 - p
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len() as u64) as usize]
    }
}

/// The seed of sequence `i` of a run with seed `base`.
fn sequence_seed(base: u64, i: u64) -> u64 {
    Rng(base ^ i.wrapping_mul(0xd1b5_4a32_d192_ed03)).next()
}

/// The FMI type of a variable.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Ty {
    Real,
    Integer,
    Boolean,
    String,
}

/// One variable of modelDescription.xml.
#[derive(Debug, Clone)]
struct Var {
    name: String,
    vr: u32,
    ty: Ty,
    causality: String,
}

fn variables() -> &'static [Var] {
    static VARS: OnceLock<Vec<Var>> = OnceLock::new();
    VARS.get_or_init(|| {
        let xml =
            std::fs::read_to_string(root().join("modelDescription/modelDescription.xml")).unwrap();
        let attr = |text: &str, key: &str| -> String {
            let start = text.find(&format!(" {key}=\"")).unwrap() + key.len() + 3;
            text[start..start + text[start..].find('"').unwrap()].to_string()
        };
        xml.split("<ScalarVariable ")
            .skip(1)
            .map(|s| {
                let s = &format!(" {}", &s[..s.find("</ScalarVariable>").unwrap()]);
                let ty = [
                    ("<Real", Ty::Real),
                    ("<Integer", Ty::Integer),
                    ("<Boolean", Ty::Boolean),
                    ("<String", Ty::String),
                ]
                .into_iter()
                .find(|(tag, _)| s.contains(tag))
                .unwrap()
                .1;
                Var {
                    name: attr(s, "name"),
                    vr: attr(s, "valueReference").parse().unwrap(),
                    ty,
                    causality: attr(s, "causality"),
                }
            })
            .collect()
    })
}

fn var(vr: u32, ty: Ty) -> Option<&'static Var> {
    variables().iter().find(|v| v.vr == vr && v.ty == ty)
}

/// Where the fuzzer's tables are (prepared by the parent process).
fn fuzz_dir() -> PathBuf {
    target_dir().join("fmu-fuzz")
}

/// A `table_file` value.
#[derive(Debug, Clone, Copy)]
enum TableArg {
    /// The small table of the fixture axes, grid 6, default parameters.
    Small,
    /// The bundled table of the FMU.
    Bundled,
    /// A byte-wise corrupted or truncated copy of the small table (one of [`CORRUPT`]).
    Corrupt(usize),
    /// A directory without a table.
    EmptyDir,
    /// A file where a directory belongs.
    AFile,
    /// A path that does not exist.
    Missing,
}

const CORRUPT: usize = 12;

impl TableArg {
    fn path(self) -> String {
        let p = match self {
            TableArg::Small => fuzz_dir().join("small"),
            TableArg::Bundled => root().join("fmu/resources/table"),
            TableArg::Corrupt(i) => fuzz_dir().join(format!("corrupt-{i}")),
            TableArg::EmptyDir => fuzz_dir().join("empty"),
            TableArg::AFile => fuzz_dir().join("small/table.json"),
            TableArg::Missing => fuzz_dir().join("no such table %s%n%d"),
        };
        p.to_str().unwrap().to_string()
    }
}

/// A string argument.
#[derive(Debug, Clone)]
enum Str {
    Null,
    Table(TableArg),
    /// Several tables separated by `;` (a trailing `;`: then the bundled one).
    Tables(Vec<TableArg>, bool),
    Text(String),
    /// Bytes that are not UTF-8.
    Bytes(Vec<u8>),
}

impl Str {
    fn c(&self) -> Option<CString> {
        match self {
            Str::Null => None,
            Str::Table(t) => Some(CString::new(t.path()).unwrap()),
            Str::Tables(t, bundled) => {
                let mut s: Vec<String> = t.iter().map(|t| t.path()).collect();
                if *bundled {
                    s.push(String::new());
                }
                Some(CString::new(s.join(";")).unwrap())
            }
            Str::Text(s) => Some(CString::new(s.as_str()).unwrap()),
            Str::Bytes(b) => Some(CString::new(b.clone()).unwrap()),
        }
    }
}

/// What happens to a serialized state before it is deserialized.
#[derive(Debug, Clone, Copy)]
enum Blob {
    Intact,
    Truncated(usize),
    Flipped(usize, u8),
    Extended,
    Empty,
}

/// One call of a sequence. `i` is an instance slot (None: a null component), `s` a state slot, `b` a
/// blob slot.
#[derive(Debug, Clone)]
enum Call {
    Instantiate {
        i: usize,
        name: Str,
        fmu_type: c_int,
        guid_ok: bool,
        resources: Str,
        logger: bool,
        logging_on: bool,
    },
    FreeInstance(Option<usize>),
    SetDebugLogging {
        i: Option<usize>,
        on: bool,
        categories: Vec<Str>,
    },
    SetupExperiment(Option<usize>, f64),
    EnterInitializationMode(Option<usize>),
    ExitInitializationMode(Option<usize>),
    Terminate(Option<usize>),
    Reset(Option<usize>),
    SetReal(Option<usize>, Vec<u32>, Vec<f64>),
    SetInteger(Option<usize>, Vec<u32>, Vec<c_int>),
    SetBoolean(Option<usize>, Vec<u32>, Vec<c_int>),
    SetString(Option<usize>, Vec<u32>, Vec<Str>),
    /// A Set of `n` values with null arrays.
    SetNull(Option<usize>, Ty, usize),
    Get(Option<usize>, Ty, Vec<u32>),
    DoStep(Option<usize>, f64, f64),
    CancelStep(Option<usize>),
    /// `fmi2Get{,Real,Integer,Boolean,String}Status` (`which` 0–4) of a kind.
    GetStatus(Option<usize>, usize, c_int),
    GetFmuState(Option<usize>, usize),
    SetFmuState(Option<usize>, usize),
    /// `itself`: the state passed where its address belongs (fmusim).
    FreeFmuState(Option<usize>, usize, bool),
    Serialize {
        i: Option<usize>,
        s: usize,
        b: usize,
        size_delta: i64,
    },
    Deserialize {
        i: Option<usize>,
        b: usize,
        blob: Blob,
        s: usize,
    },
    DirectionalDerivative(Option<usize>, Vec<u32>, Vec<u32>, Vec<f64>),
    SetRealInputDerivatives(Option<usize>),
    GetRealOutputDerivatives(Option<usize>),
}

const INSTANCES: usize = 2;
const STATES: usize = 3;
const BLOBS: usize = 2;

/// A value reference: mostly one of type `ty` (of the causality `want` if given), sometimes any or out
/// of range.
fn gen_vr(r: &mut Rng, ty: Ty, want: Option<&str>) -> u32 {
    if r.chance(0.06) {
        return r.pick(&[34, 35, 100, 1000, u32::MAX, 0, 24]);
    }
    let vs: Vec<u32> = variables()
        .iter()
        .filter(|v| v.ty == ty && want.is_none_or(|c| v.causality == c))
        .map(|v| v.vr)
        .collect();
    if vs.is_empty() { 0 } else { r.pick(&vs) }
}

/// A Real value for the variable `vr`: physical most of the time, else special.
fn gen_real(r: &mut Rng, vr: u32) -> f64 {
    if r.chance(0.1) {
        return r.pick(&[
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e300,
            -1e300,
            f64::MAX,
            -f64::MAX,
            5e-324,
            -0.0,
            0.0,
            1e-12,
            -1.0,
            1e6,
        ]);
    }
    if r.chance(0.02) {
        return f64::from_bits(r.next());
    }
    let name = var(vr, Ty::Real).map_or("", |v| v.name.as_str());
    // two draws for the cases that mix a typical and a wide range
    let (u, w) = (r.uniform(0.0, 1.0), r.uniform(0.0, 1.0));
    match name {
        "creepage_longitudinal" | "creepage_lateral" => r.uniform(-0.012, 0.012),
        "spin_creepage" => r.uniform(-0.6, 0.6),
        "normal_force" => r.pick(&[0.0, 1e-4, 60e3 + 80e3 * u, -1e5 + 4e5 * w]),
        "rolling_speed" => r.pick(&[0.0, 15.0 + 30.0 * u, -45.0 + 90.0 * w]),
        "wetness" => r.pick(&[0.0, 0.1, -0.5 + 2.0 * u]),
        "minimum_speed" => r.pick(&[0.1, 1.0, -1.0 + 6.0 * u]),
        "semi_axis_a" | "semi_axis_b" => r.pick(&[0.0, 0.006, 0.0106, -0.01 + 0.06 * u]),
        _ => (4.0 * u - 2.0) * 10f64.powi(r.below(8) as i32 - 3),
    }
}

fn gen_str(r: &mut Rng) -> Str {
    match r.below(10) {
        0..=3 => Str::Table(TableArg::Small),
        4 => Str::Table(TableArg::Corrupt(r.below(CORRUPT as u64) as usize)),
        5 => Str::Table(r.pick(&[
            TableArg::Bundled,
            TableArg::EmptyDir,
            TableArg::AFile,
            TableArg::Missing,
        ])),
        6 => Str::Text(String::new()),
        7 => Str::Null,
        8 => Str::Bytes(vec![b'/', 0xff, 0xfe, b'%', b's']),
        _ if r.chance(0.5) => {
            let n = 1 + r.below(3) as usize;
            let tables = (0..n)
                .map(|_| {
                    r.pick(&[
                        TableArg::Small,
                        TableArg::Bundled,
                        TableArg::Missing,
                        TableArg::Corrupt(0),
                    ])
                })
                .collect();
            Str::Tables(tables, r.chance(0.3))
        }
        _ => Str::Text("%s%s%n%x #r0# garbage/table".into()),
    }
}

fn gen_ints(r: &mut Rng, vr: u32) -> c_int {
    let name = var(vr, Ty::Integer).map_or("", |v| v.name.as_str());
    if r.chance(0.1) {
        return r.pick(&[i32::MIN, -1, 0, 3, 1000, i32::MAX, 401, 3]);
    }
    match name {
        "grid_size" => r.pick(&[6, 6, 6, 4, 5, 8]),
        "mode" => r.pick(&[0, 1, 1, 2]),
        _ => r.below(4) as c_int,
    }
}

fn gen_instance(r: &mut Rng, live: &[bool; INSTANCES]) -> Option<usize> {
    if r.chance(0.02) {
        return None;
    }
    let lives: Vec<usize> = (0..INSTANCES).filter(|i| live[*i]).collect();
    if lives.is_empty() || r.chance(0.05) {
        Some(r.below(INSTANCES as u64) as usize)
    } else {
        Some(r.pick(&lives))
    }
}

/// The calls that set an instance up: parameters, then initialization (mostly legal).
fn prologue(r: &mut Rng, i: usize, calls: &mut Vec<Call>) {
    let name = match r.below(20) {
        0 => Str::Null,
        1 => Str::Text(String::new()),
        2 => Str::Text(format!("inst%s%n%d #i{i}#")),
        _ => Str::Text(format!("instance{i}")),
    };
    let resources = match r.below(12) {
        0 => Str::Null,
        1 => Str::Text("not a uri".into()),
        2 => Str::Text("file:///nonexistent%20dir/resources".into()),
        3 => Str::Bytes(vec![b'f', b'i', b'l', b'e', b':', 0xff]),
        _ => Str::Text(format!("file://{}", root().join("fmu/resources").display())),
    };
    calls.push(Call::Instantiate {
        i,
        name,
        fmu_type: if r.chance(0.03) {
            r.pick(&[0, 2, -1])
        } else {
            1
        },
        guid_ok: !r.chance(0.03),
        resources,
        logger: !r.chance(0.05),
        logging_on: r.chance(0.5),
    });
    let vr = |n: &str| variables().iter().find(|v| v.name == n).unwrap().vr;
    calls.push(Call::SetInteger(
        Some(i),
        vec![vr("grid_size"), vr("mode")],
        vec![r.pick(&[6, 6, 6, 6, 4, 30]), r.pick(&[1, 1, 0, 0, 2])],
    ));
    if r.chance(0.8) {
        calls.push(Call::SetString(
            Some(i),
            vec![vr("table_file")],
            vec![if r.chance(0.6) {
                Str::Table(TableArg::Small)
            } else {
                gen_str(r)
            }],
        ));
    }
    if r.chance(0.3) {
        let p = gen_vr(r, Ty::Real, Some("parameter"));
        calls.push(Call::SetReal(Some(i), vec![p], vec![gen_real(r, p)]));
    }
    if r.chance(0.3) {
        calls.push(Call::SetBoolean(
            Some(i),
            vec![vr("warm_start")],
            vec![r.pick(&[0, 1, 7])],
        ));
    }
    if r.chance(0.9) {
        calls.push(Call::SetupExperiment(
            Some(i),
            if r.chance(0.05) {
                f64::NAN
            } else {
                r.pick(&[0.0, 1.5, -3.0])
            },
        ));
    }
    calls.push(Call::EnterInitializationMode(Some(i)));
    calls.push(Call::ExitInitializationMode(Some(i)));
}

/// A state slot: mostly one that probably holds a state.
fn state_slot(r: &mut Rng, got: &[bool; STATES]) -> usize {
    let full: Vec<usize> = (0..STATES).filter(|s| got[*s]).collect();
    if full.is_empty() || r.chance(0.15) {
        r.below(STATES as u64) as usize
    } else {
        r.pick(&full)
    }
}

/// The calls of one sequence.
fn generate(seed: u64) -> Vec<Call> {
    let mut r = Rng(seed);
    let mut calls = Vec::new();
    let mut live = [false; INSTANCES];
    let n = 5 + r.below(30);
    if r.chance(0.9) {
        prologue(&mut r, 0, &mut calls);
        live[0] = true;
    }
    let mut t = 0.0;
    // the state slots an FMU state was probably put in
    let mut got = [false; STATES];
    while (calls.len() as u64) < n {
        let inst = gen_instance(&mut r, &live);
        let call = match r.below(100) {
            0..=2 => {
                let i = r.below(INSTANCES as u64) as usize;
                prologue(&mut r, i, &mut calls);
                live[i] = true;
                continue;
            }
            3 => {
                if let Some(i) = inst {
                    live[i] = false;
                }
                Call::FreeInstance(inst)
            }
            4 => Call::SetDebugLogging {
                i: inst,
                on: r.chance(0.5),
                categories: (0..r.below(3))
                    .map(|_| match r.below(6) {
                        0 => Str::Null,
                        1 => Str::Text("nonsense%n".into()),
                        _ => Str::Text(
                            r.pick(&["logEvents", "logStatusWarning", "logStatusError", "logAll"])
                                .into(),
                        ),
                    })
                    .collect(),
            },
            5 => Call::SetupExperiment(inst, 0.0),
            6 => Call::EnterInitializationMode(inst),
            7 => Call::ExitInitializationMode(inst),
            8 => Call::Terminate(inst),
            9 => Call::Reset(inst),
            10..=31 => {
                let k = 1 + r.below(3) as usize;
                let vrs: Vec<u32> = (0..k)
                    .map(|_| {
                        let want = if r.chance(0.1) { None } else { Some("input") };
                        gen_vr(&mut r, Ty::Real, want)
                    })
                    .collect();
                let vals = vrs.iter().map(|vr| gen_real(&mut r, *vr)).collect();
                Call::SetReal(inst, vrs, vals)
            }
            32..=34 => {
                let vr = gen_vr(&mut r, Ty::Integer, None);
                Call::SetInteger(inst, vec![vr], vec![gen_ints(&mut r, vr)])
            }
            35..=36 => Call::SetBoolean(
                inst,
                vec![gen_vr(&mut r, Ty::Boolean, None)],
                vec![r.pick(&[0, 1, -1, 2])],
            ),
            37..=38 => Call::SetString(
                inst,
                vec![gen_vr(&mut r, Ty::String, None)],
                vec![gen_str(&mut r)],
            ),
            39 => Call::SetNull(
                inst,
                r.pick(&[Ty::Real, Ty::Integer, Ty::Boolean, Ty::String]),
                r.pick(&[0, 1, 3]),
            ),
            40..=54 => {
                let ty = r.pick(&[
                    Ty::Real,
                    Ty::Real,
                    Ty::Real,
                    Ty::Integer,
                    Ty::Boolean,
                    Ty::String,
                ]);
                let k = r.below(5) as usize;
                Call::Get(inst, ty, (0..k).map(|_| gen_vr(&mut r, ty, None)).collect())
            }
            55..=69 => {
                let h = if r.chance(0.05) {
                    r.pick(&[-1e-3, f64::NAN, f64::INFINITY, 0.0, 1e300])
                } else {
                    1e-3
                };
                let at = if r.chance(0.05) {
                    r.pick(&[f64::NAN, -5.0, 1e308])
                } else {
                    t
                };
                t += 1e-3;
                Call::DoStep(inst, at, h)
            }
            70 => Call::CancelStep(inst),
            71..=72 => Call::GetStatus(inst, r.below(5) as usize, r.pick(&[0, 1, 2, 3, -1, 99])),
            73..=76 => {
                let s = r.below(STATES as u64) as usize;
                got[s] = true;
                Call::GetFmuState(inst, s)
            }
            77..=79 => Call::SetFmuState(inst, state_slot(&mut r, &got)),
            80..=82 => {
                let s = state_slot(&mut r, &got);
                got[s] = false;
                Call::FreeFmuState(inst, s, r.chance(0.3))
            }
            83..=85 => Call::Serialize {
                i: inst,
                s: state_slot(&mut r, &got),
                b: r.below(BLOBS as u64) as usize,
                size_delta: if r.chance(0.1) {
                    r.pick(&[-1, 1, -1000])
                } else {
                    0
                },
            },
            86..=89 => Call::Deserialize {
                i: inst,
                b: r.below(BLOBS as u64) as usize,
                blob: match r.below(6) {
                    0 | 1 => Blob::Intact,
                    2 => Blob::Truncated(r.below(400) as usize),
                    3 => Blob::Flipped(r.below(400) as usize, 1 << r.below(8)),
                    4 => Blob::Extended,
                    _ => Blob::Empty,
                },
                s: {
                    let s = r.below(STATES as u64) as usize;
                    got[s] = true;
                    s
                },
            },
            90..=96 => {
                let nu = r.below(4) as usize;
                let nk = r.below(4) as usize;
                let unknowns = (0..nu)
                    .map(|_| gen_vr(&mut r, Ty::Real, Some("output")))
                    .collect();
                let knowns: Vec<u32> = (0..nk)
                    .map(|_| gen_vr(&mut r, Ty::Real, Some("input")))
                    .collect();
                let seeds = knowns
                    .iter()
                    .map(|_| {
                        if r.chance(0.05) {
                            f64::NAN
                        } else {
                            r.uniform(-2.0, 2.0)
                        }
                    })
                    .collect();
                Call::DirectionalDerivative(inst, unknowns, knowns, seeds)
            }
            97 => Call::SetRealInputDerivatives(inst),
            98 => Call::GetRealOutputDerivatives(inst),
            _ => Call::Get(
                inst,
                Ty::Real,
                variables().iter().map(|v| v.vr).take(14).collect(),
            ),
        };
        calls.push(call);
    }
    for (i, live) in live.into_iter().enumerate() {
        if live && r.chance(0.5) {
            calls.push(Call::Terminate(Some(i)));
        }
    }
    calls
}

/// The FMI 2.0 co-simulation states (standard §4.2.4) as bits, for the set of states an instance may be
/// in (after an `fmi2Error` of a computation, the instance may or may not be in the error state).
const INSTANTIATED: u8 = 1;
const INIT: u8 = 2;
const STEP_COMPLETE: u8 = 4;
const TERMINATED: u8 = 8;
const ERROR_STATE: u8 = 16;

/// An instance of the sequence, with what the fuzzer knows of it.
struct Inst {
    c: Comp,
    name: String,
    log: Arc<Mutex<Vec<Message>>>,
    _env: Box<LogEnv>,
    _callbacks: Box<Callbacks>,
    has_logger: bool,
    /// The states it may be in.
    states: u8,
    /// Whether warnings and errors reach the logger (the categories' switches).
    categories: [bool; 4],
}

impl Inst {
    fn reports(&self, status: c_int) -> bool {
        let c = &self.categories;
        self.has_logger
            && match status {
                WARNING | DISCARD => c[1] || c[3],
                _ => c[2] || c[3],
            }
    }
}

/// The symbols the parent module's function table does not carry.
struct Extra {
    get_integer_status: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int,
    get_boolean_status: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int,
    get_string_status: unsafe extern "C" fn(Comp, c_int, *mut *const c_char) -> c_int,
    set_input_derivatives:
        unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *const f64) -> c_int,
    get_output_derivatives:
        unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *mut f64) -> c_int,
}

fn extra() -> &'static Extra {
    static EXTRA: OnceLock<Extra> = OnceLock::new();
    EXTRA.get_or_init(|| {
        fn sym<T: Copy>(name: &str) -> T {
            unsafe { *library().get::<T>(name).unwrap() }
        }
        Extra {
            get_integer_status: sym("fmi2GetIntegerStatus"),
            get_boolean_status: sym("fmi2GetBooleanStatus"),
            get_string_status: sym("fmi2GetStringStatus"),
            set_input_derivatives: sym("fmi2SetRealInputDerivatives"),
            get_output_derivatives: sym("fmi2GetRealOutputDerivatives"),
        }
    })
}

/// The executor of one sequence.
#[derive(Default)]
struct Exec {
    inst: [Option<Inst>; INSTANCES],
    /// Live FMU states by slot, with the states the instance may have been in when it was taken (a freed
    /// state is never passed again: that would be the master's use-after-free, undefined in any FMU).
    states: [Option<(*mut c_void, u8)>; STATES],
    /// Serialized states, with the states of the instance they were taken of.
    blobs: [Option<(Vec<u8>, u8)>; BLOBS],
    /// How many calls returned each status (OK, Warning, Discard, Error, Fatal).
    counts: [u64; 5],
    /// The last call's status and log lines (for the trace of a replay).
    outcome: String,
}

/// Which states a call is legal in, by the FMI 2.0 co-simulation state machine; None: legal anywhere.
fn legal_states(call: &Call) -> Option<u8> {
    let set = |vrs: &[u32], ty: Ty| {
        // setting an output, or a variable that does not exist, is illegal everywhere; a parameter only
        // before the end of initialization; inputs at communication points too
        let mut ok = INSTANTIATED | INIT | STEP_COMPLETE;
        for vr in vrs {
            match var(*vr, ty).map(|v| v.causality.as_str()) {
                Some("input") => {}
                Some("parameter") => ok &= INSTANTIATED | INIT,
                _ => ok = 0,
            }
        }
        ok
    };
    Some(match call {
        Call::SetupExperiment(..) | Call::EnterInitializationMode(_) => INSTANTIATED,
        Call::ExitInitializationMode(_) => INIT,
        Call::Terminate(_) | Call::DoStep(..) => STEP_COMPLETE,
        Call::CancelStep(_) => 0,
        Call::SetReal(_, vrs, _) => set(vrs, Ty::Real),
        Call::SetInteger(_, vrs, _) => set(vrs, Ty::Integer),
        Call::SetBoolean(_, vrs, _) => set(vrs, Ty::Boolean),
        Call::SetString(_, vrs, _) => set(vrs, Ty::String),
        Call::Get(_, ty, vrs) if vrs.iter().any(|vr| var(*vr, *ty).is_none()) => 0,
        Call::Get(..) => INIT | STEP_COMPLETE | TERMINATED | ERROR_STATE,
        Call::GetStatus(..) => STEP_COMPLETE | TERMINATED | ERROR_STATE,
        Call::DirectionalDerivative(..) => INIT | STEP_COMPLETE | TERMINATED | ERROR_STATE,
        Call::GetRealOutputDerivatives(_) => STEP_COMPLETE | TERMINATED | ERROR_STATE,
        Call::SetRealInputDerivatives(_) => INSTANTIATED | INIT | STEP_COMPLETE,
        _ => return None,
    })
}

/// The states after a call that returned `status` (OK or Warning: the transition; Error: unchanged, or
/// the error state after a failed computation).
fn next_states(call: &Call, states: u8, status: c_int) -> u8 {
    if status >= ERROR {
        return states | ERROR_STATE;
    }
    match call {
        Call::EnterInitializationMode(_) => INIT,
        Call::ExitInitializationMode(_) => STEP_COMPLETE,
        Call::Terminate(_) => TERMINATED,
        Call::Reset(_) => INSTANTIATED,
        _ => states,
    }
}

fn instance_of(call: &Call) -> Option<usize> {
    match call {
        Call::Instantiate { i, .. } => Some(*i),
        Call::FreeInstance(i)
        | Call::SetDebugLogging { i, .. }
        | Call::SetupExperiment(i, _)
        | Call::EnterInitializationMode(i)
        | Call::ExitInitializationMode(i)
        | Call::Terminate(i)
        | Call::Reset(i)
        | Call::SetReal(i, ..)
        | Call::SetInteger(i, ..)
        | Call::SetBoolean(i, ..)
        | Call::SetString(i, ..)
        | Call::SetNull(i, ..)
        | Call::Get(i, ..)
        | Call::DoStep(i, ..)
        | Call::CancelStep(i)
        | Call::GetStatus(i, ..)
        | Call::GetFmuState(i, _)
        | Call::SetFmuState(i, _)
        | Call::FreeFmuState(i, ..)
        | Call::Serialize { i, .. }
        | Call::Deserialize { i, .. }
        | Call::DirectionalDerivative(i, ..)
        | Call::SetRealInputDerivatives(i)
        | Call::GetRealOutputDerivatives(i) => *i,
    }
}

fn finite(xs: &[f64], what: &str) -> Result<(), String> {
    match xs.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(format!("{what} returned {x} with a status below fmi2Error")),
        None => Ok(()),
    }
}

impl Exec {
    /// Runs one call and checks the invariants; Err describes a violation.
    fn run(&mut self, call: &Call) -> Result<(), String> {
        if let Call::Instantiate { .. } = call {
            return self.instantiate(call);
        }
        let slot = instance_of(call);
        // a call on a freed or never created instance would be the master's use-after-free: such calls
        // go to a null component instead, which must be refused
        let c = slot
            .and_then(|i| self.inst[i].as_ref())
            .map_or(null_mut(), |x| x.c);
        if let Call::FreeInstance(_) = call {
            if let Some(x) = slot.and_then(|i| self.inst[i].take()) {
                unsafe { (fmi().free_instance)(x.c) };
            } else {
                unsafe { (fmi().free_instance)(null_mut()) };
            }
            return Ok(());
        }
        let logged_before = slot
            .and_then(|i| self.inst[i].as_ref())
            .map_or(0, |x| x.log.lock().unwrap().len());
        let status = unsafe { self.call(c, call)? };
        if !(0..=FATAL).contains(&status) {
            return Err(format!("status {status} is not an fmi2Status"));
        }
        self.counts[status as usize] += 1;
        let Some(x) = slot.and_then(|i| self.inst[i].as_mut()) else {
            return match status {
                ERROR => Ok(()),
                s => Err(format!("a null component gave status {s}, not fmi2Error")),
            };
        };
        if let Some(legal) = legal_states(call)
            && legal & x.states == 0
            && status < ERROR
        {
            return Err(format!(
                "status {status} for a call that is illegal in every state the instance may be in \
                     ({:#b})",
                x.states
            ));
        }
        let new: Vec<Message> = x.log.lock().unwrap()[logged_before..].to_vec();
        self.outcome = format!(
            "status {status}; logged {:?}",
            new.iter().map(|m| &m.text).collect::<Vec<_>>()
        );
        if let Some(m) = new.iter().find(|m| m.instance != x.name) {
            return Err(format!(
                "a log line names instance {:?}, not {:?}: {}",
                m.instance, x.name, m.text
            ));
        }
        if status >= WARNING && x.reports(status) {
            let severity = if status == DISCARD { WARNING } else { status };
            if !new.iter().any(|m| m.status >= severity) {
                return Err(format!(
                    "status {status} without a log line of that severity"
                ));
            }
        }
        if let Call::SetDebugLogging { on, categories, .. } = call
            && status == OK
        {
            let names = ["logEvents", "logStatusWarning", "logStatusError", "logAll"];
            if categories.is_empty() {
                x.categories = [*on; 4];
            }
            for c in categories {
                if let Str::Text(t) = c
                    && let Some(k) = names.iter().position(|n| n == t)
                {
                    x.categories[k] = *on;
                }
            }
        }
        x.states = match call {
            // the state's own machine state comes along
            Call::SetFmuState(_, s) if status < ERROR => self.states[*s].map_or(x.states, |p| p.1),
            _ => next_states(call, x.states, status),
        };
        if let Call::GetFmuState(_, s) = call
            && let Some(p) = &mut self.states[*s]
            && status < ERROR
        {
            p.1 = x.states;
        }
        if matches!(call, Call::DoStep(..) | Call::ExitInitializationMode(_)) && status < ERROR {
            let outputs: Vec<u32> = variables()
                .iter()
                .filter(|v| v.ty == Ty::Real && v.causality == "output")
                .map(|v| v.vr)
                .collect();
            let mut y = vec![f64::NAN; outputs.len()];
            let s = unsafe { (fmi().get_real)(c, outputs.as_ptr(), outputs.len(), y.as_mut_ptr()) };
            if s >= ERROR {
                return Err(format!(
                    "reading the outputs after a step with status {status} failed"
                ));
            }
            finite(&y, "the outputs after a step")?;
        }
        Ok(())
    }

    fn instantiate(&mut self, call: &Call) -> Result<(), String> {
        let Call::Instantiate {
            i,
            name,
            fmu_type,
            guid_ok,
            resources,
            logger,
            logging_on,
        } = call
        else {
            unreachable!()
        };
        if let Some(old) = self.inst[*i].take() {
            unsafe { (fmi().free_instance)(old.c) };
        }
        let log = Arc::new(Mutex::new(Vec::new()));
        let env = Box::new(LogEnv {
            sink: collect,
            messages: Arc::as_ptr(&log),
        });
        let callbacks = Box::new(Callbacks {
            logger: logger.then(c_logger),
            allocate: null(),
            free: null(),
            step_finished: null(),
            env: &*env as *const LogEnv as *mut c_void,
        });
        let cname = name.c();
        let guid = if *guid_ok {
            fmi().guid.clone()
        } else {
            CString::new("{00000000-%s-%n}").unwrap()
        };
        let res = resources.c();
        let c = unsafe {
            (fmi().instantiate)(
                cname.as_ref().map_or(null(), |n| n.as_ptr()),
                *fmu_type,
                guid.as_ptr(),
                res.as_ref().map_or(null(), |r| r.as_ptr()),
                &*callbacks,
                0,
                c_int::from(*logging_on),
            )
        };
        let valid_name = cname.as_ref().is_some_and(|n| !n.as_bytes().is_empty());
        // fmuType 0 is Model Exchange (tests/fmu/model_exchange.rs drives those); this fuzzer drives
        // Co-Simulation instances and frees a Model Exchange one at once
        let model_exchange = *fmu_type == 0;
        let should_work = valid_name && (*fmu_type == 1 || model_exchange) && *guid_ok;
        self.outcome = format!(
            "instance {c:?}; logged {:?}",
            log.lock()
                .unwrap()
                .iter()
                .map(|m| &m.text)
                .collect::<Vec<_>>()
        );
        if c.is_null() {
            if should_work {
                return Err(format!("instantiation failed: {:?}", log.lock().unwrap()));
            }
            if *logger && !log.lock().unwrap().iter().any(|m| m.status == ERROR) {
                return Err("a refused instantiation without an error log line".into());
            }
            return Ok(());
        }
        if !should_work {
            unsafe { (fmi().free_instance)(c) };
            return Err("an instantiation that must fail gave an instance".into());
        }
        if model_exchange {
            unsafe { (fmi().free_instance)(c) };
            return Ok(());
        }
        let name = cname.unwrap().into_string().unwrap();
        if let Some(m) = log.lock().unwrap().iter().find(|m| m.instance != name) {
            return Err(format!(
                "instantiation logged for instance {:?}",
                m.instance
            ));
        }
        if *logger
            && *logging_on
            && !log.lock().unwrap().iter().any(|m| {
                m.text
                    .contains(&format!("instance {} created", name.replace('#', "##")))
            })
        {
            return Err(format!(
                "the instance name {name:?} did not reach the logger verbatim: {:?}",
                log.lock().unwrap()
            ));
        }
        self.inst[*i] = Some(Inst {
            c,
            name,
            log,
            _env: env,
            _callbacks: callbacks,
            has_logger: *logger,
            states: INSTANTIATED,
            categories: [*logging_on, true, true, *logging_on],
        });
        Ok(())
    }

    /// The C call of `call` on `c`; its status.
    unsafe fn call(&mut self, c: Comp, call: &Call) -> Result<c_int, String> {
        let f = fmi();
        unsafe {
            Ok(match call {
                Call::Instantiate { .. } | Call::FreeInstance(_) => unreachable!(),
                Call::SetDebugLogging { on, categories, .. } => {
                    let cs: Vec<Option<CString>> = categories.iter().map(Str::c).collect();
                    let ptrs: Vec<*const c_char> = cs
                        .iter()
                        .map(|s| s.as_ref().map_or(null(), |s| s.as_ptr()))
                        .collect();
                    (f.set_debug_logging)(c, c_int::from(*on), ptrs.len(), ptrs.as_ptr())
                }
                Call::SetupExperiment(_, t) => (f.setup_experiment)(c, 0, 0.0, *t, 0, 0.0),
                Call::EnterInitializationMode(_) => (f.enter_initialization_mode)(c),
                Call::ExitInitializationMode(_) => (f.exit_initialization_mode)(c),
                Call::Terminate(_) => (f.terminate)(c),
                Call::Reset(_) => (f.reset)(c),
                Call::SetReal(_, vrs, xs) => (f.set_real)(c, vrs.as_ptr(), vrs.len(), xs.as_ptr()),
                Call::SetInteger(_, vrs, xs) => {
                    (f.set_integer)(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
                }
                Call::SetBoolean(_, vrs, xs) => {
                    (f.set_boolean)(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
                }
                Call::SetString(_, vrs, xs) => {
                    let cs: Vec<Option<CString>> = xs.iter().map(Str::c).collect();
                    let ptrs: Vec<*const c_char> = cs
                        .iter()
                        .map(|s| s.as_ref().map_or(null(), |s| s.as_ptr()))
                        .collect();
                    (f.set_string)(c, vrs.as_ptr(), vrs.len(), ptrs.as_ptr())
                }
                Call::SetNull(_, ty, n) => {
                    let vrs = vec![0u32; *n];
                    match ty {
                        Ty::Real => (f.set_real)(c, vrs.as_ptr(), *n, null()),
                        Ty::Integer => (f.set_integer)(c, null(), *n, null()),
                        Ty::Boolean => (f.set_boolean)(c, vrs.as_ptr(), *n, null()),
                        Ty::String => (f.set_string)(c, vrs.as_ptr(), *n, null()),
                    }
                }
                Call::Get(_, ty, vrs) => {
                    let n = vrs.len();
                    match ty {
                        Ty::Real => {
                            let mut y = vec![f64::NAN; n];
                            let s = (f.get_real)(c, vrs.as_ptr(), n, y.as_mut_ptr());
                            if s < ERROR {
                                finite(&y, "fmi2GetReal")?;
                            }
                            s
                        }
                        Ty::Integer => {
                            let mut y = vec![0; n];
                            (f.get_integer)(c, vrs.as_ptr(), n, y.as_mut_ptr())
                        }
                        Ty::Boolean => {
                            let mut y = vec![-7; n];
                            let s = (f.get_boolean)(c, vrs.as_ptr(), n, y.as_mut_ptr());
                            if s < ERROR && y.iter().any(|b| *b != 0 && *b != 1) {
                                return Err(format!("fmi2GetBoolean gave {y:?}"));
                            }
                            s
                        }
                        Ty::String => {
                            let mut y = vec![null(); n];
                            let s = (f.get_string)(c, vrs.as_ptr(), n, y.as_mut_ptr());
                            if s < ERROR {
                                for p in &y {
                                    if p.is_null() {
                                        return Err("fmi2GetString gave a null string".into());
                                    }
                                    if CStr::from_ptr(*p).to_str().is_err() {
                                        return Err("fmi2GetString gave non-UTF-8".into());
                                    }
                                }
                            }
                            s
                        }
                    }
                }
                Call::DoStep(_, t, h) => (f.do_step)(c, *t, *h, 0),
                Call::CancelStep(_) => (f.cancel_step)(c),
                Call::GetStatus(_, which, kind) => {
                    let mut i = -7;
                    let mut x = f64::NAN;
                    let mut s = null();
                    let e = extra();
                    let status = match which {
                        0 => (f.get_status)(c, *kind, &mut i),
                        1 => (f.get_real_status)(c, *kind, &mut x),
                        2 => (e.get_integer_status)(c, *kind, &mut i),
                        3 => (e.get_boolean_status)(c, *kind, &mut i),
                        _ => (e.get_string_status)(c, *kind, &mut s),
                    };
                    if status == OK && *which == 1 {
                        finite(&[x], "fmi2GetRealStatus")?;
                    }
                    status
                }
                Call::GetFmuState(_, s) => {
                    let mut p = self.states[*s].map_or(null_mut(), |p| p.0);
                    let status = (f.get_fmu_state)(c, &mut p);
                    if status < ERROR {
                        if p.is_null() {
                            return Err("fmi2GetFMUstate gave a null state".into());
                        }
                        // the machine states are filled in by the caller
                        self.states[*s] = Some((p, 0));
                    }
                    status
                }
                Call::SetFmuState(_, s) => match self.states[*s] {
                    Some((p, _)) => (f.set_fmu_state)(c, p),
                    None => (f.set_fmu_state)(c, null_mut()),
                },
                Call::FreeFmuState(_, s, itself) => match (self.states[*s], itself) {
                    (Some((p, _)), true) => {
                        let status = (f.free_fmu_state)(c, p as *mut *mut c_void);
                        if status < ERROR {
                            self.states[*s] = None;
                        }
                        status
                    }
                    (p, _) => {
                        let mut p = p.map_or(null_mut(), |p| p.0);
                        let status = (f.free_fmu_state)(c, &mut p);
                        if status < ERROR {
                            if !p.is_null() {
                                return Err("fmi2FreeFMUstate left the state variable set".into());
                            }
                            self.states[*s] = None;
                        }
                        status
                    }
                },
                Call::Serialize {
                    s, b, size_delta, ..
                } => {
                    let (p, machine) = self.states[*s].unwrap_or((null_mut(), 0));
                    let mut size = 0usize;
                    let status = (f.serialized_size)(c, p, &mut size);
                    if status >= ERROR {
                        return Ok(status);
                    }
                    let n = (size as i64 + size_delta).max(0) as usize;
                    let mut bytes = vec![0 as c_char; n];
                    let status = (f.serialize)(c, p, bytes.as_mut_ptr(), n);
                    if status < ERROR {
                        if *size_delta != 0 {
                            return Err("fmi2SerializeFMUstate accepted a wrong size".into());
                        }
                        self.blobs[*b] = Some((bytes.iter().map(|x| *x as u8).collect(), machine));
                    }
                    status
                }
                Call::Deserialize { b, blob, s, .. } => {
                    let (mut bytes, machine) = self.blobs[*b].clone().unwrap_or_default();
                    match blob {
                        Blob::Intact => {}
                        Blob::Truncated(n) => bytes.truncate(*n % (bytes.len() + 1)),
                        Blob::Flipped(k, bit) if !bytes.is_empty() => {
                            let k = k % bytes.len();
                            bytes[k] ^= bit;
                        }
                        Blob::Flipped(..) => {}
                        Blob::Extended => bytes.extend_from_slice(&[0, 1, 2]),
                        Blob::Empty => bytes.clear(),
                    }
                    let mut p = self.states[*s].map_or(null_mut(), |p| p.0);
                    let status = (f.deserialize)(
                        c,
                        if bytes.is_empty() {
                            null()
                        } else {
                            bytes.as_ptr().cast()
                        },
                        bytes.len(),
                        &mut p,
                    );
                    if status < ERROR {
                        self.states[*s] = Some((p, machine));
                    }
                    status
                }
                Call::DirectionalDerivative(_, unknowns, knowns, seeds) => {
                    let mut out = vec![f64::NAN; unknowns.len()];
                    let status = (f.directional_derivative)(
                        c,
                        unknowns.as_ptr(),
                        unknowns.len(),
                        knowns.as_ptr(),
                        knowns.len(),
                        seeds.as_ptr(),
                        out.as_mut_ptr(),
                    );
                    if status < ERROR {
                        finite(&out, "fmi2GetDirectionalDerivative")?;
                    }
                    status
                }
                Call::SetRealInputDerivatives(_) => {
                    let (vr, order, x) = (0u32, 1, 0.0);
                    (extra().set_input_derivatives)(c, &vr, 1, &order, &x)
                }
                Call::GetRealOutputDerivatives(_) => {
                    let (vr, order, mut x) = (6u32, 1, 0.0);
                    (extra().get_output_derivatives)(c, &vr, 1, &order, &mut x)
                }
            })
        }
    }
}

impl Drop for Exec {
    fn drop(&mut self) {
        // states are freed through a live instance, then the instances
        if let Some(x) = self.inst.iter().flatten().next() {
            for (p, _) in self.states.iter_mut().flatten() {
                unsafe { (fmi().free_fmu_state)(x.c, p) };
            }
        }
        for x in self.inst.iter_mut().filter_map(Option::take) {
            unsafe { (fmi().free_instance)(x.c) };
        }
    }
}

/// Runs the calls of a sequence (those at `keep`, if given), printing each first if `trace`; the
/// first violation, with the index of its call, or how many calls returned each status.
fn execute(
    calls: &[Call],
    keep: Option<&[usize]>,
    trace: bool,
) -> Result<[u64; 5], (usize, String)> {
    let mut exec = Exec::default();
    for (k, call) in calls.iter().enumerate() {
        if keep.is_some_and(|keep| !keep.contains(&k)) {
            continue;
        }
        if trace {
            println!("FUZZ call {k}: {call:?}");
            std::io::stdout().flush().unwrap();
        }
        exec.outcome.clear();
        exec.run(call).map_err(|e| (k, e))?;
        if trace {
            println!("FUZZ   -> {}", exec.outcome);
        }
    }
    Ok(exec.counts)
}

/// Two instances that live as long as the worker, in mode 1 with the bundled and with the small table:
/// a table is loaded once per process while an instance holds it, so the sequences' instances share
/// these (loading the bundled table takes about 0.1 s; the corrupted tables, never loaded, are read
/// again every time).
fn keepers() -> [Fmu; 2] {
    let bundled = Fmu::new("keeper-bundled", Some(&root().join("fmu/resources")));
    let small = Fmu::new("keeper-small", None);
    let path = CString::new(TableArg::Small.path()).unwrap();
    assert_eq!(
        unsafe { (fmi().set_string)(small.c, &vr("table_file"), 1, &path.as_ptr()) },
        OK
    );
    assert_eq!(small.set_int("grid_size", 6), OK);
    for f in [&bundled, &small] {
        assert_eq!(f.set_int("mode", 1), OK);
        assert_eq!(f.initialize(), OK, "{:?}", f.messages());
    }
    [bundled, small]
}

/// The child's side: WORKER_ENV = "base,first,count" runs those sequences, reporting each; REPLAY_ENV =
/// a sequence seed runs it (KEEP_ENV: the call indices kept), tracing every call.
fn child() {
    if let Ok(spec) = std::env::var(REPLAY_ENV) {
        let seed: u64 = spec.parse().unwrap();
        let keep: Option<Vec<usize>> = std::env::var(KEEP_ENV).ok().map(|k| {
            k.split(',')
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().unwrap())
                .collect()
        });
        let calls = generate(seed);
        if let Err((k, e)) = execute(&calls, keep.as_deref(), true) {
            println!("FUZZ fail {seed} at call {k}: {e}");
            std::io::stdout().flush().unwrap();
            std::process::exit(3);
        }
        return;
    }
    let _keepers = keepers();
    let spec = std::env::var(WORKER_ENV).unwrap();
    let v: Vec<u64> = spec.split(',').map(|s| s.parse().unwrap()).collect();
    let (base, first, count) = (v[0], v[1], v[2]);
    let mut out = std::io::stdout().lock();
    for i in first..first + count {
        let seed = sequence_seed(base, i);
        writeln!(out, "FUZZ start {i} {seed}").unwrap();
        out.flush().unwrap();
        let calls = generate(seed);
        let start = Instant::now();
        match execute(&calls, None, false) {
            Ok(counts) => writeln!(
                out,
                "FUZZ ok {i} {} {counts:?}",
                start.elapsed().as_micros()
            )
            .unwrap(),
            Err((k, e)) => writeln!(out, "FUZZ fail {i} {seed} at call {k}: {e}").unwrap(),
        }
        out.flush().unwrap();
    }
}

/// This test binary, re-run for `fuzz::sequences` only, with `env`.
fn spawn(env: &[(&str, String)], stdout: Stdio, stderr: Stdio) -> Child {
    let mut cmd = Command::new(std::env::current_exe().unwrap());
    cmd.args([
        "fmu::fuzz::sequences",
        "--exact",
        "--nocapture",
        "--test-threads=1",
    ])
    .stdout(stdout)
    .stderr(stderr);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.spawn().unwrap()
}

/// A failure found: the sequence's seed and what happened.
#[derive(Debug, Clone)]
struct Found {
    seed: u64,
    what: String,
}

/// What [`drive`] gives.
type Driven = (u64, [u64; 5], (u64, u64), Vec<Found>);

/// Runs sequences `first..first + count` in children (restarted after a crash or hang); the sequences
/// run, how many calls returned each status, the slowest sequence (seed, µs) and the failures.
fn drive(base: u64, first: u64, count: u64) -> Driven {
    let mut found = Vec::new();
    let mut slowest = (0, 0);
    let (mut next, end, mut statuses) = (first, first + count, [0; 5]);
    // the worker's standard error: what a worker that dies outside a sequence printed
    let stderr = fuzz_dir().join(format!("worker-{first}-{}.stderr", std::process::id()));
    while next < end {
        let mut child = spawn(
            &[(WORKER_ENV, format!("{base},{next},{}", end - next))],
            Stdio::piped(),
            Stdio::from(std::fs::File::create(&stderr).unwrap()),
        );
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                if tx.send(line.unwrap_or_default()).is_err() {
                    break;
                }
            }
        });
        let mut current: Option<(u64, u64)> = None;
        loop {
            match rx.recv_timeout(WATCHDOG) {
                Ok(line) => {
                    // libtest may print the test's name before the first line, on the same line
                    let line = line.find("FUZZ ").map_or("", |k| &line[k..]);
                    let w: Vec<&str> = line.splitn(5, ' ').collect();
                    match w.as_slice() {
                        ["FUZZ", "start", i, seed] => {
                            current = Some((i.parse().unwrap(), seed.parse().unwrap()));
                        }
                        ["FUZZ", "ok", i, micros, counts] => {
                            next = i.parse::<u64>().unwrap() + 1;
                            let micros = micros.parse().unwrap();
                            if micros > slowest.1 {
                                slowest = (current.unwrap().1, micros);
                            }
                            let counts = counts.trim_matches(['[', ']']).split(", ");
                            for (c, n) in statuses.iter_mut().zip(counts) {
                                *c += n.parse::<u64>().unwrap();
                            }
                            current = None;
                        }
                        ["FUZZ", "fail", i, seed, what] => {
                            next = i.parse::<u64>().unwrap() + 1;
                            println!("FMI fuzz: sequence {i} (seed {seed}) failed: {what}");
                            found.push(Found {
                                seed: seed.parse().unwrap(),
                                what: what.to_string(),
                            });
                            current = None;
                        }
                        _ => {}
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    child.kill().ok();
                    child.wait().ok();
                    let (i, seed) = current.expect("a hang outside a sequence");
                    println!("FMI fuzz: sequence {i} (seed {seed}) hangs");
                    found.push(Found {
                        seed,
                        what: format!("hang: sequence {i} ran longer than {WATCHDOG:?}"),
                    });
                    next = i + 1;
                    break;
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = child.wait().unwrap();
                    if let Some((i, seed)) = current {
                        println!("FMI fuzz: sequence {i} (seed {seed}) crashed: {status}");
                        found.push(Found {
                            seed,
                            what: format!("crash: {status}"),
                        });
                        next = i + 1;
                    } else {
                        assert!(
                            next >= end || status.success(),
                            "worker ended: {status}; its standard error:\n{}",
                            std::fs::read_to_string(&stderr).unwrap_or_default()
                        );
                    }
                    break;
                }
            }
        }
    }
    std::fs::remove_file(&stderr).ok();
    (end - first, statuses, slowest, found)
}

/// Replays `seed` with only the calls `keep` in a child (killed after [`WATCHDOG`]): whether it still
/// fails (crash, hang or violation), and the replay command with its call trace.
fn replay(seed: u64, keep: &[usize]) -> (bool, String) {
    let keep: Vec<String> = keep.iter().map(usize::to_string).collect();
    let log = fuzz_dir().join(format!("replay-{}.log", std::process::id()));
    let mut child = spawn(
        &[(REPLAY_ENV, seed.to_string()), (KEEP_ENV, keep.join(","))],
        Stdio::from(std::fs::File::create(&log).unwrap()),
        Stdio::null(),
    );
    let start = Instant::now();
    let outcome = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break (!status.success(), format!("exit {status}"));
        }
        if start.elapsed() > WATCHDOG {
            child.kill().ok();
            child.wait().ok();
            break (true, format!("killed after {WATCHDOG:?}"));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let trace: Vec<String> = std::fs::read_to_string(&log)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| l.find("FUZZ ").map(|k| l[k..].to_string()))
        .collect();
    std::fs::remove_file(&log).ok();
    (
        outcome.0,
        format!(
            "replay: {REPLAY_ENV}={seed} {KEEP_ENV}={} cargo test --release -p wheelrail --test \
             integration fmu::fuzz::sequences -- --exact --nocapture\n{}\n({})",
            keep.join(","),
            trace.join("\n"),
            outcome.1
        ),
    )
}

/// The smallest subsequence of the calls of a failure found that still fails (chunks removed, halving;
/// a hang is not shrunk, each attempt would take the watchdog's time), and its trace.
fn shrink(found: &Found) -> String {
    let mut keep: Vec<usize> = (0..generate(found.seed).len()).collect();
    let mut chunk = keep.len().div_ceil(2);
    while chunk >= 1 && !found.what.starts_with("hang") {
        let mut start = 0;
        while start < keep.len() {
            let trial: Vec<usize> = keep
                .iter()
                .enumerate()
                .filter(|(k, _)| *k < start || *k >= start + chunk)
                .map(|(_, x)| *x)
                .collect();
            if !trial.is_empty() && replay(found.seed, &trial).0 {
                keep = trial;
            } else {
                start += chunk;
            }
        }
        if chunk == 1 {
            break;
        }
        chunk = chunk.div_ceil(2);
    }
    replay(found.seed, &keep).1
}

/// The fuzzer's tables: the small table (built once, grid 6, default parameters) and corrupted copies.
fn prepare_tables() {
    let dir = fuzz_dir();
    let small = dir.join("small");
    if Table::load(&small).is_err() {
        let axes =
            wheelrail::table::Axes::from_toml_file(&root().join("tests/fixtures/small-axes.toml"))
                .unwrap();
        let mut params = Params::default();
        params.grid.nx = 6;
        params.grid.ny = 6;
        let mut files = wheelrail::table::build(&params, &axes, None, &|| ()).unwrap();
        files.write(&small).unwrap();
    }
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    let mut names: Vec<PathBuf> = std::fs::read_dir(&small)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    let mut r = Rng(0xc0ffee);
    for i in 0..CORRUPT {
        let to = dir.join(format!("corrupt-{i}"));
        std::fs::create_dir_all(&to).unwrap();
        let victim = r.below(names.len() as u64) as usize;
        for (k, f) in names.iter().enumerate() {
            let mut bytes = std::fs::read(f).unwrap();
            if k == victim {
                let at = r.below(bytes.len() as u64) as usize;
                match i % 3 {
                    0 => bytes[at] ^= 1 << r.below(8),
                    1 => bytes.truncate(at),
                    _ => bytes[at..].iter_mut().take(8).for_each(|b| *b = 0xff),
                }
            }
            std::fs::write(to.join(f.file_name().unwrap()), bytes).unwrap();
        }
    }
}

/// Runs `WHEELRAIL_FUZZ_SEQUENCES` sequences; see the module documentation.
#[test]
fn sequences() {
    if std::env::var_os(WORKER_ENV).is_some() || std::env::var_os(REPLAY_ENV).is_some() {
        return child();
    }
    let env = |k: &str, d: u64| std::env::var(k).map_or(d, |v| v.parse().unwrap());
    let total = env("WHEELRAIL_FUZZ_SEQUENCES", DEFAULT_SEQUENCES);
    let base = env("WHEELRAIL_FUZZ_SEED", DEFAULT_SEED);
    library_path();
    prepare_tables();
    let start = Instant::now();
    let per = total.div_ceil(WORKERS);
    let results: Vec<Driven> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..WORKERS)
            .map(|w| {
                let first = w * per;
                let count = per.min(total.saturating_sub(first));
                s.spawn(move || drive(base, first, count))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let secs = start.elapsed().as_secs_f64();
    let run: u64 = results.iter().map(|r| r.0).sum();
    let statuses: Vec<u64> = (0..5)
        .map(|k| results.iter().map(|r| r.1[k]).sum())
        .collect();
    let calls: u64 = statuses.iter().sum();
    let slowest = results
        .iter()
        .map(|r| r.2)
        .max_by_key(|s| s.1)
        .unwrap_or_default();
    let found: Vec<Found> = results.into_iter().flat_map(|r| r.3).collect();
    let crashes = found.iter().filter(|f| f.what.starts_with("crash")).count();
    let hangs = found.iter().filter(|f| f.what.starts_with("hang")).count();
    println!(
        "FMI fuzz: {run} sequences of seed {base} in {secs:.1} s ({:.0} sequences/s, {WORKERS} \
         workers), {calls} calls (OK {}, Warning {}, Discard {}, Error {}, Fatal {}): {} failures, \
         {crashes} crashes, {hangs} hangs; the slowest sequence (seed {}) took {:.2} s",
        run as f64 / secs,
        statuses[0],
        statuses[1],
        statuses[2],
        statuses[3],
        statuses[4],
        found.len(),
        slowest.0,
        slowest.1 as f64 * 1e-6,
    );
    if let Some(first) = found.first() {
        let report = shrink(first);
        panic!(
            "{} of {run} sequences failed; the first (seed {}): {}\nminimal call log:\n{report}\nall: {:#?}",
            found.len(),
            first.seed,
            first.what,
            found
        );
    }
}
