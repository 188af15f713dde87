//! The on-disk format: one `.npy` array per stored output plus `converged.npy`, and the JSON
//! sidecar `table.json` with the format version, axes with units, outputs, the full parameter set and its
//! fingerprint, the model version, build date and duration, and the SHA-256 of every array file.
//!
//! Arrays are little-endian f32 (u8 for the converged flags) in C order over (ξ̂, η̂, φ̂, F_N, V, w, a/b,
//! p_ref); a shard (one of N parts of a build) holds 1-D arrays of its points instead. A full table may
//! store its outputs as 16-bit codes instead (`storage = "u16"` in the sidecar, [`Storage`]): half the
//! bytes, each value offset + step·code with the array's own [`Quantization`] in its record, so a value
//! lies within step/2 ≈ range/131 070 of the computed one (F/F_N ≈ 1e-5, T_max ≈ 0.01 K). Interpolation
//! then runs on those values as on f32 ones: the outputs stay smooth in the inputs (no jitter). Storage
//! `u16z` holds the same codes compressed ([`compress_codes`]: differences to the neighbour along φ̂ and
//! along V, byte planes, zlib), the same values in about a third of the bytes of `u16`; `u16x` the same
//! prediction compressed by xz (LZMA2), about 40 % fewer bytes again. Shards
//! always store f32 and record the storage of the table they merge into. Array bytes depend
//! only on the parameters and the axes, never on the thread count or the date: those live only in the
//! sidecar's `build` record. Reading verifies everything and names what does not match.
//!
//! Format version 1 (f64 arrays over raw ξ, η, φ, F_N, V, w of the parameters' own contact geometry, from
//! curvatures) is read as a table of that single geometry: its a/b and p_ref axes are the one point of
//! the Hertz contact of its parameters.

use super::axes::{
    Axes, Axis, DIMENSIONS, DIMS, Interpolation, PHI, RATIO, REFERENCE_FORCE, SPEED,
};
use crate::error::{Error, Result};
use crate::params::{OperatingPoint, Params};
use ndarray::{ArrayD, IxDyn};
use ndarray_npy::{ReadNpyExt, WriteNpyExt};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Value of the sidecar's `format` field.
pub const FORMAT: &str = "wheelrail-table";
/// Version of the format this build writes (it also reads version 1, see the module documentation).
pub const FORMAT_VERSION: u32 = 2;
/// File name of the sidecar.
pub const SIDECAR: &str = "table.json";
/// Name (file stem) of the per-point converged flags.
pub const CONVERGED: &str = "converged";
/// Name (file stem) of the per-point film-intake states ([`FilmIntake`]).
pub const FILM_INTAKE: &str = "film_intake";
/// Version of the model (the crate version) recorded in and required of every table.
pub const MODEL_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Number of stored outputs (format version 1 stored the first five).
pub const OUTPUTS: usize = 6;

/// One stored output: name (= file stem), unit, meaning.
pub struct OutputInfo {
    /// Name and file stem.
    pub name: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// Meaning.
    pub description: &'static str,
}

/// The stored outputs, in row order.
pub const OUTPUT_INFO: [OutputInfo; OUTPUTS] = [
    OutputInfo {
        name: "force_x_per_normal_force",
        unit: "-",
        description: "F_x/F_N (Kalker's sign convention: force on the wheel)",
    },
    OutputInfo {
        name: "force_y_per_normal_force",
        unit: "-",
        description: "F_y/F_N",
    },
    OutputInfo {
        name: "spin_moment_per_normal_force_radius",
        unit: "-",
        description: "M_z/(F_N·c), c = sqrt(a·b) of the contact",
    },
    OutputInfo {
        name: "max_temperature",
        unit: "K",
        description: "highest surface temperature in the contact",
    },
    OutputInfo {
        name: "fluid_load_fraction",
        unit: "-",
        description: "share of the normal force carried by fluid pressure",
    },
    OutputInfo {
        name: "frictional_power_per_normal_force_speed",
        unit: "-",
        description: "P_f/(F_N·V), P_f = Σ|τ|·|s|·ΔA the frictional power dissipated in the contact",
    },
];

/// One axis in the sidecar.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisRecord {
    /// Dimension name (operating-point field).
    pub name: String,
    /// Symbol.
    pub symbol: String,
    /// Unit.
    pub unit: String,
    /// Interpolation along the axis.
    pub interpolation: Interpolation,
    /// Only values ≥ 0 stored; the negative half by symmetry (see `symmetry`).
    pub mirrored: bool,
    /// The stored points.
    pub points: Vec<f64>,
    /// Normalised creepage axes: the largest raw |creepage| served.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_limit: Option<f64>,
    /// Knee-blended creepage axes: the raw scale k_r (see `coords`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_scale: Option<f64>,
    /// Knee-blended spin axes: the contact size the raw scale applies to (see `coords`) [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_length: Option<f64>,
    /// The speed axis of a table built by similarity: equivalent speeds at the reference load
    /// (docs/model.md §9.1).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub similarity: bool,
    /// Linear axes: the point from which on the cells are interpolated linearly in √x.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sqrt_from: Option<f64>,
}

/// How a full table stores its output arrays (the converged flags are always u8).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Storage {
    /// Little-endian f32 (4 bytes per value).
    #[default]
    F32,
    /// 16-bit codes with a per-array offset and step ([`Quantization`]; 2 bytes per value).
    U16,
    /// The codes of [`Storage::U16`], predicted and compressed by zlib ([`compress_codes`], files
    /// `NAME.u16z`, the converged flags `converged.u8z`): the same values in about 0.6 bytes per value.
    U16z,
    /// The predicted codes of [`Storage::U16z`] compressed by xz instead of zlib (files `NAME.u16x`, the
    /// converged flags `converged.u8x`): about 0.35 bytes per value, slower to write and to read.
    U16x,
}

/// The general-purpose compressor of a compressed storage ([`Storage::codec`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Codec {
    /// One zlib stream (RFC 1950), best compression (flate2).
    Zlib,
    /// One xz stream (LZMA2, preset 9; lzma-rust2, pure Rust), as Python's `lzma` reads it.
    Xz,
}

impl Codec {
    /// The last letter of the file extensions (`NAME.u16z`, `converged.u8z`).
    fn letter(self) -> char {
        match self {
            Codec::Zlib => 'z',
            Codec::Xz => 'x',
        }
    }

    /// The name of the stream format, for messages.
    fn name(self) -> &'static str {
        match self {
            Codec::Zlib => "zlib",
            Codec::Xz => "xz",
        }
    }

    /// The file of an output array `name` of a table stored with this codec.
    pub fn output_file(self, name: &str) -> String {
        format!("{name}.u16{}", self.letter())
    }

    /// The file of a per-point u8 array `name` (converged flags, film-intake states: compressed as they
    /// are).
    pub fn flags_file(self, name: &str) -> String {
        format!("{name}.u8{}", self.letter())
    }

    /// `bytes` as one stream of this codec.
    pub fn compress(self, bytes: &[u8]) -> Vec<u8> {
        use std::io::Write;
        let memory = "writing to memory cannot fail";
        match self {
            Codec::Zlib => {
                let mut z =
                    flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
                z.write_all(bytes).expect(memory);
                z.finish().expect(memory)
            }
            Codec::Xz => {
                let options = lzma_rust2::XzOptions::with_preset(9);
                let mut x = lzma_rust2::XzWriter::new(Vec::new(), options).expect(memory);
                x.write_all(bytes).expect(memory);
                x.finish().expect(memory)
            }
        }
    }

    /// The `n` bytes of one stream of this codec; an error if it is not one or holds any other number of
    /// bytes (read no further than n + 1, so a corrupt stream cannot claim more memory).
    pub fn decompress(self, bytes: &[u8], n: usize) -> std::result::Result<Vec<u8>, String> {
        use std::io::Read;
        let mut out = Vec::with_capacity(n);
        let limit = n as u64 + 1;
        match self {
            Codec::Zlib => flate2::read::ZlibDecoder::new(bytes)
                .take(limit)
                .read_to_end(&mut out),
            Codec::Xz => lzma_rust2::XzReader::new(bytes, false)
                .take(limit)
                .read_to_end(&mut out),
        }
        .map_err(|e| format!("not a valid {} stream: {e}", self.name()))?;
        if out.len() != n {
            return Err(format!(
                "the compressed array holds {}{} bytes, expected {n}",
                out.len().min(n),
                if out.len() > n { " or more" } else { "" }
            ));
        }
        Ok(out)
    }
}

impl Storage {
    /// Whether this is the default f32 storage (not recorded in the sidecar, so that f32 tables keep
    /// their sidecars byte for byte).
    pub fn is_f32(&self) -> bool {
        *self == Storage::F32
    }

    /// The compressor of a compressed storage (u16z, u16x).
    pub fn codec(self) -> Option<Codec> {
        match self {
            Storage::F32 | Storage::U16 => None,
            Storage::U16z => Some(Codec::Zlib),
            Storage::U16x => Some(Codec::Xz),
        }
    }
}

impl std::fmt::Display for Storage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Storage::F32 => "f32",
            Storage::U16 => "u16",
            Storage::U16z => "u16z",
            Storage::U16x => "u16x",
        })
    }
}

/// The coarsest code steps a quantised table may use (`table build --resolution`, recorded in the
/// sidecar): an array's codes step by max(range/65 535, its resolution), so a value lies within half of
/// that of the computed one. The interpolation errors the accuracy targets allow are some 1e-3 of F/F_N and
/// K of T_max, so e.g. 1e-4 and 0.1 K cost no accuracy, and the fewer distinct codes compress to about half
/// the bytes (docs/model.md §12.3, Storage).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Resolution {
    /// The outputs relative to the normal force (unit "-": F_x/F_N, F_y/F_N, M_z/(F_N·c), the fluid load
    /// fraction, P_f/(F_N·V)).
    pub per_normal_force: f64,
    /// T_max [K].
    pub temperature: f64,
}

impl Resolution {
    /// The resolution `F,T` (F of the outputs per F_N, T of T_max in K; both finite and > 0).
    pub fn parse(text: &str) -> std::result::Result<Resolution, String> {
        let bad = || {
            format!(
                "resolution {text:?}: expected F,T (e.g. 1e-4,0.1: steps of the outputs per normal force \
                 and of T_max in K, both finite and > 0)"
            )
        };
        let (f, t) = text.split_once(',').ok_or_else(bad)?;
        let r = Resolution {
            per_normal_force: f.trim().parse().map_err(|_| bad())?,
            temperature: t.trim().parse().map_err(|_| bad())?,
        };
        r.valid().then_some(r).ok_or_else(bad)
    }

    /// Whether both steps are finite and > 0.
    fn valid(&self) -> bool {
        [self.per_normal_force, self.temperature]
            .iter()
            .all(|s| s.is_finite() && *s > 0.0)
    }

    /// The coarsest step of an output (by its unit: K is T_max, the others are per normal force).
    pub fn of(&self, output: &OutputInfo) -> f64 {
        if output.unit == "K" {
            self.temperature
        } else {
            self.per_normal_force
        }
    }
}

impl std::fmt::Display for Resolution {
    /// As [`Resolution::parse`] reads it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{}", self.per_normal_force, self.temperature)
    }
}

/// The linear 16-bit code of one array: value = offset + step·code, code 0..=65535, offset the array's
/// smallest value and step its range / 65535 (0 for a constant array): rounding to the nearest code errs
/// by at most step/2. With a coarser step (a [`Resolution`]) the offset is a whole multiple of the step if
/// the codes still fit, so that 0 has a code: a force that is exactly 0 (at zero creepage) stays 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantization {
    /// Value of code 0 (the smallest value).
    pub offset: f64,
    /// Value step per code (≥ 0).
    pub step: f64,
}

impl Quantization {
    /// Largest code.
    const TOP: f64 = u16::MAX as f64;

    /// The quantisation of `values` and their codes, with a step of at least `coarsest` (0: the finest
    /// the codes allow); an error for a non-finite value.
    pub fn of(
        values: &[f32],
        coarsest: f64,
    ) -> std::result::Result<(Quantization, Vec<u16>), String> {
        if values.iter().any(|v| !v.is_finite()) {
            return Err("non-finite values cannot be stored as u16".into());
        }
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(f64::from(*v)), hi.max(f64::from(*v)))
            });
        let q = if hi <= lo {
            Quantization {
                offset: if lo.is_finite() { lo } else { 0.0 },
                step: 0.0,
            }
        } else if coarsest > (hi - lo) / Self::TOP {
            let offset = coarsest * (lo / coarsest).floor();
            Quantization {
                offset: if ((hi - offset) / coarsest).round() <= Self::TOP {
                    offset
                } else {
                    lo
                },
                step: coarsest,
            }
        } else {
            Quantization {
                offset: lo,
                step: (hi - lo) / Self::TOP,
            }
        };
        let codes = values
            .iter()
            .map(|v| {
                if q.step > 0.0 {
                    ((f64::from(*v) - q.offset) / q.step)
                        .round()
                        .clamp(0.0, Self::TOP) as u16
                } else {
                    0
                }
            })
            .collect();
        Ok((q, codes))
    }

    /// The value of `code`, rounded to the f32 the table keeps in memory.
    pub fn value(&self, code: u16) -> f32 {
        (self.offset + self.step * f64::from(code)) as f32
    }

    /// Whether offset and step are finite and the step is not negative.
    fn valid(&self) -> bool {
        self.offset.is_finite() && self.step.is_finite() && self.step >= 0.0
    }
}

/// One array file in the sidecar.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArrayRecord {
    /// Output name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// Meaning.
    pub description: String,
    /// File name inside the table directory.
    pub file: String,
    /// SHA-256 of the file's bytes (lower-case hex).
    pub sha256: String,
    /// The code of a u16 array ([`Storage::U16`]; absent for f32 and u8 arrays).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quantization: Option<Quantization>,
}

/// A stored point whose exact solution did not converge even after the retry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnconvergedRecord {
    /// Flat (C-order) index in the full table.
    pub index: usize,
    /// The operating point.
    pub point: OperatingPoint,
    /// Final residual of the coupled iteration.
    pub residual: f64,
}

/// This directory holds part `index` of `count` (1-based) of a build: the points whose flat index i has
/// i mod count = index − 1, as 1-D arrays in index order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardRecord {
    /// Part number, 1 ..= count.
    pub index: usize,
    /// Number of parts.
    pub count: usize,
}

/// When and how the arrays were computed (the only fields that differ between identical builds).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuildRecord {
    /// UTC date and time of completion (ISO 8601).
    pub date: String,
    /// Wall-clock duration [s] (merged: the sum over the shards).
    pub duration_seconds: f64,
    /// Worker threads (merged: the largest over the shards).
    pub threads: usize,
    /// Shards merged into this table (0: built in one piece).
    pub merged_shards: usize,
}

/// The sidecar `table.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`FORMAT_VERSION`].
    pub format_version: u32,
    /// Crate version of the model that computed the values.
    pub model_version: String,
    /// SHA-256 of the canonical JSON of `params` (see [`fingerprint`]).
    pub fingerprint: String,
    /// The full parameter set the values were computed with.
    pub params: Params,
    /// The axes in storage order.
    pub axes: Vec<AxisRecord>,
    /// The symmetries used for mirrored axes.
    pub symmetry: Vec<String>,
    /// Stored outputs and their files.
    pub outputs: Vec<ArrayRecord>,
    /// Per-point converged flags (1 converged, 0 not).
    pub converged: ArrayRecord,
    /// Points that did not converge (also flagged 0 in `converged`).
    pub unconverged: Vec<UnconvergedRecord>,
    /// Per-point film-intake states ([`FilmIntake`]); absent from tables built before they were recorded
    /// (such a table marks no cell unresolved by them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub film_intake: Option<ArrayRecord>,
    /// Format version 1 only: the normalisation of the spin moment by the contact radius c(F_N) of its
    /// geometry, which is √(a·b) of the contact, as in version 2 (kept to read such sidecars; unused).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moment_scale: Option<serde_json::Value>,
    /// Set for one part of a sharded build.
    pub shard: Option<ShardRecord>,
    /// How the outputs are stored ([`Storage`]; a shard stores f32 and records the storage of the table
    /// it merges into).
    #[serde(default, skip_serializing_if = "Storage::is_f32")]
    pub storage: Storage,
    /// The coarsest code steps of a quantised storage ([`Resolution`]; absent: range/65 535 per array).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolution: Option<Resolution>,
    /// Date, duration, threads.
    pub build: BuildRecord,
}

impl Sidecar {
    /// Whether the output arrays are stored as u16 codes: a full table whose storage is u16, u16z or u16x (a
    /// shard stores f32 whatever storage it records).
    pub fn quantised(&self) -> bool {
        self.storage != Storage::F32 && self.shard.is_none()
    }

    /// The compressor of the arrays: that of a full table whose storage is compressed (u16z, u16x).
    pub fn compressed(&self) -> Option<Codec> {
        self.storage.codec().filter(|_| self.shard.is_none())
    }
}

/// The symmetry statements recorded in the sidecar.
pub fn symmetry_notes(axes: &Axes) -> Vec<String> {
    let mut v = vec![
        "creepage_y mirrored (exact): (eta, phi) -> (-eta, -phi) gives (F_x, F_y, M_z) -> (F_x, -F_y, -M_z), \
         temperature and fluid load unchanged"
            .to_string(),
    ];
    if axes.0[super::axes::XI].mirrored {
        v.push(
            "creepage_x mirrored (exact dry; wet up to about 1e-2 F_N at the onset of boundary lubrication in \
             full slip): xi -> -xi gives \
             (F_x, F_y, M_z) -> (-F_x, F_y, M_z), temperature and fluid load unchanged"
                .to_string(),
        );
    }
    v
}

/// Axes records of `axes`.
pub fn axis_records(axes: &Axes) -> Vec<AxisRecord> {
    axes.0
        .iter()
        .zip(DIMENSIONS.iter())
        .enumerate()
        .map(|(dim, (a, d))| AxisRecord {
            name: d.name.into(),
            symbol: d.symbol.into(),
            unit: d.unit.into(),
            interpolation: a.interpolation(dim),
            mirrored: a.mirrored,
            points: a.points.clone(),
            raw_limit: a.raw_limit,
            raw_scale: a.raw_scale,
            raw_length: a.raw_length,
            similarity: a.similarity,
            sqrt_from: a.sqrt_from,
        })
        .collect()
}

/// The axes of sidecar records, checked against the dimensions this build knows. Format version 1 lists
/// the first six; its geometry axes are the single point of its parameters' contact (see the module
/// documentation).
fn axes_of(sidecar: &Sidecar, path: &Path) -> Result<Axes> {
    let records = &sidecar.axes;
    let listed = if sidecar.format_version == 1 {
        RATIO
    } else {
        DIMS
    };
    if records.len() != listed {
        return Err(corrupt(
            path,
            format!("{} axes listed, expected {listed}", records.len()),
        ));
    }
    let mut axes = Vec::with_capacity(DIMS);
    for (r, d) in records.iter().zip(DIMENSIONS.iter()) {
        // a linear dimension may be interpolated in ln x
        let logarithmic =
            d.interpolation == Interpolation::Linear && r.interpolation == Interpolation::Log;
        if r.name != d.name
            || r.unit != d.unit
            || (r.interpolation != d.interpolation && !logarithmic)
        {
            return Err(corrupt(
                path,
                format!(
                    "axis {} [{}] ({:?}) where {} [{}] ({:?}) is expected",
                    r.name, r.unit, r.interpolation, d.name, d.unit, d.interpolation
                ),
            ));
        }
        axes.push(Axis {
            points: r.points.clone(),
            mirrored: r.mirrored,
            raw_limit: r.raw_limit,
            raw_scale: r.raw_scale,
            raw_length: r.raw_length,
            logarithmic,
            similarity: r.similarity,
            sqrt_from: r.sqrt_from,
        });
    }
    if sidecar.format_version == 1 {
        if sidecar.params.geometry.semi_axes.is_some() {
            return Err(corrupt(
                path,
                "is of format version 1 with prescribed semi-axes, whose p_ref changes with the load: \
                 rebuild it",
            ));
        }
        let h = crate::solver::normal_contact(&sidecar.params, REFERENCE_FORCE)
            .map_err(|e| corrupt(path, format!("no contact for its parameters: {e}")))?;
        for x in [h.a / h.b, h.p0] {
            axes.push(Axis::linear(vec![x]));
        }
    }
    let axes = Axes(axes.try_into().expect("eight axes"));
    axes.validate()
        .map_err(|e| corrupt(path, format!("invalid axes: {e}")))?;
    if sidecar.format_version > 1 && !axes.normalised() {
        return Err(corrupt(path, "creepage axes without raw limits"));
    }
    Ok(axes)
}

/// Error about a table directory.
pub fn corrupt(path: &Path, reason: impl std::fmt::Display) -> Error {
    Error::Table {
        path: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// Lower-case hex SHA-256 of bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// JSON text with object keys sorted at every level and no whitespace; numbers as serde_json prints them
/// (shortest text that reads back to the same f64).
fn canonical_json(v: &serde_json::Value, out: &mut String) {
    match v {
        serde_json::Value::Object(m) => {
            let mut keys: Vec<&String> = m.keys().collect();
            keys.sort();
            out.push('{');
            for (i, k) in keys.into_iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                out.push_str(&serde_json::Value::String(k.clone()).to_string());
                out.push(':');
                canonical_json(&m[k], out);
            }
            out.push('}');
        }
        serde_json::Value::Array(a) => {
            out.push('[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                canonical_json(x, out);
            }
            out.push(']');
        }
        other => out.push_str(&other.to_string()),
    }
}

/// Fingerprint of a parameter set: SHA-256 of its canonical JSON (sorted keys, no whitespace). Any change
/// of any parameter — physics, grid or solver controls — changes it.
pub fn fingerprint(params: &Params) -> String {
    let v = serde_json::to_value(params).expect("parameters serialise");
    let mut s = String::new();
    canonical_json(&v, &mut s);
    sha256_hex(s.as_bytes())
}

/// UTC date and time of a Unix time, ISO 8601 (days-to-civil after H. Hinnant, "chrono-compatible
/// low-level date algorithms").
pub fn iso8601(unix_seconds: u64) -> String {
    let days = (unix_seconds / 86_400) as i64;
    let secs = unix_seconds % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs % 3600 / 60,
        secs % 60
    )
}

/// Now, ISO 8601 UTC.
pub fn now_iso8601() -> String {
    let s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    iso8601(s)
}

/// The contents of a table directory: sidecar and arrays (per output, flat; converged flags).
#[derive(Debug, Clone, PartialEq)]
pub struct TableFiles {
    /// The sidecar.
    pub sidecar: Sidecar,
    /// The axes (from the sidecar).
    pub axes: Axes,
    /// Per output: values in flat order (full table: C order; shard: the shard's points in index order),
    /// in the stored precision.
    pub outputs: Vec<Vec<f32>>,
    /// Per point: 1 converged, 0 not.
    pub converged: Vec<u8>,
    /// Per point: the [`FilmIntake`] code of its solution (None: not recorded).
    pub film_intake: Option<Vec<u8>>,
}

/// Whether the film enters every cell of a point's contact, as code of the `film_intake` array. The film
/// model treats a cell that GW's metallic area covers (A_m/A_n at the dry separation reaching 1) as a wall
/// that takes in none of the film carried to it (docs/model.md §8.5): downstream of it the contact runs
/// dry, so the friction of a wet contact rises steeply over a few per cent of p0 once its centre is
/// covered (at about 1.49 GPa for the default contact cold, earlier hot). A table cell whose corners hold
/// both [`FilmIntake::All`] and [`FilmIntake::Limited`] straddles that onset ([`crate::table::Table`] marks
/// it unresolved).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum FilmIntake {
    /// Wet, and every cell takes in all the film carried to it (θ = 1, [`crate::fluid::intake_share`]).
    All = 0,
    /// Wet, and the metal covers part of the contact: some cell takes in less (θ < 1).
    Limited = 1,
    /// No film (wetness 0): the walls change nothing.
    Dry = 2,
}

impl FilmIntake {
    /// The state of a solution at wetness `wetness` whose largest A_m/A_n(d_dry) is
    /// `max_dry_area_fraction` (None: a law without the microcontact, treated as dry).
    pub fn of(wetness: f64, max_dry_area_fraction: Option<f64>) -> FilmIntake {
        match max_dry_area_fraction {
            Some(a) if wetness > 0.0 => {
                if crate::fluid::takes_in_all(a) {
                    FilmIntake::All
                } else {
                    FilmIntake::Limited
                }
            }
            _ => FilmIntake::Dry,
        }
    }
}

/// `.npy` bytes of a flat array in the given shape.
fn npy_bytes<T: ndarray_npy::WritableElement + Clone>(data: &[T], shape: &[usize]) -> Vec<u8> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), data.to_vec()).expect("shape matches the data");
    let mut out = Vec::new();
    a.write_npy(&mut out)
        .expect("writing to memory cannot fail");
    out
}

/// The `.npy` bytes (header and values) of an array of `shape` with elements `T`, as [`npy_bytes`]
/// writes them, without the values.
fn npy_len<T: ndarray_npy::WritableElement>(shape: &[usize]) -> u64 {
    let header = ndarray_npy::npy::header::Header {
        type_descriptor: T::type_descriptor(),
        layout: ndarray_npy::npy::header::Layout::Standard,
        shape: shape.to_vec(),
    };
    let header = header
        .to_bytes()
        .expect("a table's header fits the format")
        .len();
    (header + shape.iter().product::<usize>() * std::mem::size_of::<T>()) as u64
}

/// The bytes of the arrays of a full table with `axes` in an uncompressed storage (f32 or u16: the
/// outputs, the converged flags and the film-intake states, as [`TableFiles::write`] writes them, the
/// sidecar not counted); None for the compressed storages, whose bytes depend on the values.
pub fn array_bytes(axes: &Axes, storage: Storage) -> Option<u64> {
    let shape = axes.shape();
    let outputs = match storage {
        Storage::F32 => npy_len::<f32>(&shape),
        Storage::U16 => npy_len::<u16>(&shape),
        Storage::U16z | Storage::U16x => return None,
    };
    Some(OUTPUTS as u64 * outputs + 2 * npy_len::<u8>(&shape))
}

impl TableFiles {
    /// Shape of every array: the axes' for a full table, (points,) for a shard.
    pub fn array_shape(&self) -> Vec<usize> {
        self.shape_of(self.sidecar.format_version)
    }

    /// [`TableFiles::array_shape`] as written in format `version` (version 1: six dimensions).
    fn shape_of(&self, version: u32) -> Vec<usize> {
        let dims = if version == 1 { RATIO } else { DIMS };
        match self.sidecar.shard {
            Some(_) => vec![self.converged.len()],
            None => self.axes.shape()[..dims].to_vec(),
        }
    }

    /// Writes the arrays, then the sidecar (with their hashes), into `dir` (created if missing), in the
    /// current format version. With u16 storage the outputs in memory become the values of their codes.
    pub fn write(&mut self, dir: &Path) -> Result<()> {
        let io = |p: &Path, e: std::io::Error| corrupt(p, format!("cannot write: {e}"));
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        if self.sidecar.format_version != FORMAT_VERSION || self.sidecar.moment_scale.is_some() {
            self.sidecar.format_version = FORMAT_VERSION;
            self.sidecar.moment_scale = None;
            self.sidecar.axes = axis_records(&self.axes);
        }
        let shape = self.array_shape();
        let quantised = self.sidecar.quantised();
        let compressed = self.sidecar.compressed();
        let mut records = Vec::with_capacity(OUTPUTS);
        for (info, data) in OUTPUT_INFO.iter().zip(self.outputs.iter_mut()) {
            let file = match compressed {
                Some(c) => c.output_file(info.name),
                None => format!("{}.npy", info.name),
            };
            let path = dir.join(&file);
            let (bytes, quantization) = if quantised {
                let coarsest = self.sidecar.resolution.map_or(0.0, |r| r.of(info));
                let (q, codes) = Quantization::of(data, coarsest).map_err(|e| corrupt(&path, e))?;
                // the table in memory holds what a read of the files gives
                for (v, c) in data.iter_mut().zip(&codes) {
                    *v = q.value(*c);
                }
                let bytes = match compressed {
                    Some(c) => compress_codes(&codes, &shape, c),
                    None => npy_bytes(&codes, &shape),
                };
                (bytes, Some(q))
            } else {
                (npy_bytes(data, &shape), None)
            };
            std::fs::write(&path, &bytes).map_err(|e| io(&path, e))?;
            records.push(ArrayRecord {
                name: info.name.into(),
                unit: info.unit.into(),
                description: info.description.into(),
                file,
                sha256: sha256_hex(&bytes),
                quantization,
            });
        }
        self.sidecar.outputs = records;
        self.sidecar.converged = write_flags(
            dir,
            CONVERGED,
            "1: the exact solution at this point converged; 0: it did not (see unconverged)",
            &self.converged,
            &shape,
            compressed,
        )?;
        self.sidecar.film_intake = match &self.film_intake {
            Some(f) => Some(write_flags(
                dir,
                FILM_INTAKE,
                "0: wet, every cell takes in the film carried to it; 1: wet, the metal covers part of the \
                 contact (A_m/A_n at the dry separation >= 0.995: walls, docs/model.md 8.5); 2: no film",
                f,
                &shape,
                compressed,
            )?),
            None => None,
        };
        let text = serde_json::to_string_pretty(&self.sidecar).expect("sidecar serialises") + "\n";
        let path = dir.join(SIDECAR);
        std::fs::write(&path, text).map_err(|e| io(&path, e))
    }

    /// Reads and verifies a table directory (full table or shard): format and model version, parameter
    /// fingerprint, axes, outputs, each array's SHA-256, dtype and shape, finite values.
    pub fn read(dir: &Path) -> Result<TableFiles> {
        let side_path = dir.join(SIDECAR);
        let text = std::fs::read_to_string(&side_path).map_err(|e| {
            corrupt(
                dir,
                format!("cannot read the sidecar {SIDECAR}: {e} (is this a table directory?)"),
            )
        })?;
        let sidecar: Sidecar = serde_json::from_str(&text)
            .map_err(|e| corrupt(&side_path, format!("malformed sidecar: {e}")))?;
        check_sidecar(&sidecar, &side_path)?;
        let axes = axes_of(&sidecar, &side_path)?;
        let stored = stored_outputs(&sidecar, &side_path)?;
        let shape = array_shape(&sidecar, &axes, &side_path)?;
        check_resolution(&sidecar, &side_path)?;
        let mut outputs = Vec::with_capacity(OUTPUTS);
        for rec in &sidecar.outputs {
            outputs.push(read_output(dir, &sidecar, rec, &shape)?);
        }
        if stored < OUTPUTS {
            // format version 1 has no frictional power: NaN, which the table reports as absent
            outputs.push(vec![f32::NAN; outputs[0].len()]);
        }
        let converged = read_flags(dir, &sidecar.converged, &shape, sidecar.compressed(), 1)?;
        let film_intake = match &sidecar.film_intake {
            Some(rec) => Some(read_flags(
                dir,
                rec,
                &shape,
                sidecar.compressed(),
                FilmIntake::Dry as u8,
            )?),
            None => None,
        };
        Ok(TableFiles {
            sidecar,
            axes,
            outputs,
            converged,
            film_intake,
        })
    }
}

/// The checks of a sidecar read from `side_path` (the first stage of [`TableFiles::read`]): its format, a
/// format version this build reads, the present model version, a valid parameter set and its fingerprint.
fn check_sidecar(sidecar: &Sidecar, side_path: &Path) -> Result<()> {
    if sidecar.format != FORMAT {
        return Err(corrupt(
            side_path,
            format!("format is {:?}, expected {FORMAT:?}", sidecar.format),
        ));
    }
    if !(1..=FORMAT_VERSION).contains(&sidecar.format_version) {
        return Err(corrupt(
            side_path,
            format!(
                "format version {} is not supported (this build reads versions 1 to \
                 {FORMAT_VERSION})",
                sidecar.format_version
            ),
        ));
    }
    if sidecar.model_version != MODEL_VERSION {
        return Err(corrupt(
            side_path,
            format!(
                "built by model version {}, this is {MODEL_VERSION}: rebuild the table",
                sidecar.model_version
            ),
        ));
    }
    sidecar
        .params
        .validate()
        .map_err(|e| corrupt(side_path, format!("invalid parameter set: {e}")))?;
    let fp = fingerprint(&sidecar.params);
    if fp != sidecar.fingerprint {
        return Err(corrupt(
            side_path,
            format!(
                "parameter fingerprint mismatch: recorded {}, the recorded parameters give {fp}",
                sidecar.fingerprint
            ),
        ));
    }
    Ok(())
}

/// The number of stored outputs of a sidecar read from `side_path` (all of [`OUTPUT_INFO`]; format version 1
/// lacks the frictional power), checked against its output records.
fn stored_outputs(sidecar: &Sidecar, side_path: &Path) -> Result<usize> {
    let names: Vec<&str> = sidecar.outputs.iter().map(|o| o.name.as_str()).collect();
    let stored = if sidecar.format_version == 1 {
        OUTPUTS - 1
    } else {
        OUTPUTS
    };
    let want: Vec<&str> = OUTPUT_INFO[..stored].iter().map(|o| o.name).collect();
    if names != want {
        return Err(corrupt(
            side_path,
            format!("outputs {names:?}, expected {want:?}"),
        ));
    }
    Ok(stored)
}

/// The shape of a table's arrays on `axes` (1-D for a shard, checked; version 1 without the geometry axes).
fn array_shape(sidecar: &Sidecar, axes: &Axes, side_path: &Path) -> Result<Vec<usize>> {
    Ok(match sidecar.shard {
        Some(s) => {
            if s.count == 0 || s.index == 0 || s.index > s.count {
                return Err(corrupt(
                    side_path,
                    format!("invalid shard {}/{}", s.index, s.count),
                ));
            }
            vec![shard_len(axes, s)]
        }
        None if sidecar.format_version == 1 => axes.shape()[..RATIO].to_vec(),
        None => axes.shape().to_vec(),
    })
}

/// The check of a sidecar's recorded resolution: only with a u16 storage, and with valid steps.
fn check_resolution(sidecar: &Sidecar, side_path: &Path) -> Result<()> {
    if let Some(r) = sidecar.resolution
        && (!r.valid() || sidecar.storage.is_f32())
    {
        return Err(corrupt(
            side_path,
            format!(
                "resolution {r} needs a u16 storage (not {}) and steps finite and > 0",
                sidecar.storage
            ),
        ));
    }
    Ok(())
}

/// One output's array of a table in `dir` as the f32 values the table keeps in memory, from its record
/// `rec` of `sidecar` and the arrays' `shape`: f64 (version 1) rounded, u16 codes (compressed or not)
/// decoded by the record's quantisation, or f32; every value finite.
fn read_output(
    dir: &Path,
    sidecar: &Sidecar,
    rec: &ArrayRecord,
    shape: &[usize],
) -> Result<Vec<f32>> {
    let quantised = sidecar.quantised();
    let compressed = sidecar.compressed();
    let path = dir.join(&rec.file);
    if rec.quantization.is_some() != quantised {
        return Err(corrupt(
            &path,
            format!(
                "storage {} of a {} needs {} array",
                sidecar.storage,
                if sidecar.shard.is_some() {
                    "shard"
                } else {
                    "table"
                },
                if quantised {
                    "a quantised u16"
                } else {
                    "an f32"
                }
            ),
        ));
    }
    // version 1 stored f64: rounded to the f32 the table keeps in memory
    let v: Vec<f32> = if sidecar.format_version == 1 {
        let a: ArrayD<f64> = read_array(dir, rec, shape)?;
        a.iter().map(|x| *x as f32).collect()
    } else if let Some(q) = rec.quantization {
        if !q.valid() {
            return Err(corrupt(&path, format!("invalid quantisation {q:?}")));
        }
        let codes = match compressed {
            Some(c) => {
                decompress_codes(&read_bytes(dir, rec)?, shape, c).map_err(|e| corrupt(&path, e))?
            }
            None => {
                read_array::<u16>(dir, rec, shape)?
                    .into_raw_vec_and_offset()
                    .0
            }
        };
        codes.iter().map(|c| q.value(*c)).collect()
    } else {
        read_array::<f32>(dir, rec, shape)?
            .into_raw_vec_and_offset()
            .0
    };
    if v.iter().any(|x| !x.is_finite()) {
        return Err(corrupt(&dir.join(&rec.file), "non-finite values"));
    }
    Ok(v)
}

/// Writes a per-point u8 array `name` into `dir` (`.npy`, or compressed by `codec` as it is) and returns
/// its record.
fn write_flags(
    dir: &Path,
    name: &str,
    description: &str,
    data: &[u8],
    shape: &[usize],
    codec: Option<Codec>,
) -> Result<ArrayRecord> {
    let (file, bytes) = match codec {
        Some(c) => (c.flags_file(name), c.compress(data)),
        None => (format!("{name}.npy"), npy_bytes(data, shape)),
    };
    let path = dir.join(&file);
    std::fs::write(&path, &bytes).map_err(|e| corrupt(&path, format!("cannot write: {e}")))?;
    Ok(ArrayRecord {
        name: name.into(),
        unit: "-".into(),
        description: description.into(),
        file,
        sha256: sha256_hex(&bytes),
        quantization: None,
    })
}

/// Reads the per-point u8 array of `rec` ([`write_flags`]) of `shape`; an error naming the file if it is
/// not one or holds a value above `max`.
fn read_flags(
    dir: &Path,
    rec: &ArrayRecord,
    shape: &[usize],
    codec: Option<Codec>,
    max: u8,
) -> Result<Vec<u8>> {
    let path = dir.join(&rec.file);
    let v = match codec {
        Some(c) => c
            .decompress(&read_bytes(dir, rec)?, shape.iter().product())
            .map_err(|e| corrupt(&path, e))?,
        None => {
            read_array::<u8>(dir, rec, shape)?
                .into_raw_vec_and_offset()
                .0
        }
    };
    match v.iter().find(|x| **x > max) {
        Some(x) => Err(corrupt(&path, format!("holds {x}, not a code 0..={max}"))),
        None => Ok(v),
    }
}

/// Number of points of one creepage cube: all (ξ̂, η̂, φ̂) nodes at fixed (F_N, V, w, a/b, p_ref).
pub fn cube_len(axes: &Axes) -> usize {
    axes.shape()[..3].iter().product()
}

/// Number of creepage cubes: the (F_N, V, w, a/b, p_ref) nodes. A point of flat index i lies in cube
/// i mod cube_count (the creepage dimensions are the slowest).
pub fn cube_count(axes: &Axes) -> usize {
    axes.shape()[3..].iter().product()
}

/// The flat indices (ascending) of shard K/N: every point of the creepage cubes t with t mod N = K − 1 —
/// whole cubes, so that each shard keeps its continuation chains and the coverage windows of its cubes
/// (build.rs).
pub fn shard_indices(axes: &Axes, s: ShardRecord) -> Vec<usize> {
    let cubes = cube_count(axes);
    (0..axes.len())
        .filter(|i| (i % cubes) % s.count == s.index - 1)
        .collect()
}

/// Number of points of shard `s` (1 ≤ K ≤ N) of a table with `axes`.
pub fn shard_len(axes: &Axes, s: ShardRecord) -> usize {
    let cubes = cube_count(axes);
    (cubes + s.count - s.index) / s.count * cube_len(axes)
}

/// Reads one array file: the bytes must hash to the recorded SHA-256 and hold an array of `shape`.
fn read_array<T: ndarray_npy::ReadableElement>(
    dir: &Path,
    rec: &ArrayRecord,
    shape: &[usize],
) -> Result<ArrayD<T>> {
    let path: PathBuf = dir.join(&rec.file);
    let bytes = read_bytes(dir, rec)?;
    let a = ArrayD::<T>::read_npy(&bytes[..]).map_err(|e| {
        corrupt(
            &path,
            format!("not a valid .npy array of the expected type: {e}"),
        )
    })?;
    if a.shape() != shape {
        return Err(corrupt(
            &path,
            format!("shape {:?}, expected {shape:?}", a.shape()),
        ));
    }
    Ok(a)
}

/// The bytes of one array file, which must hash to the recorded SHA-256.
fn read_bytes(dir: &Path, rec: &ArrayRecord) -> Result<Vec<u8>> {
    if rec.file.contains(['/', '\\']) || rec.file.starts_with('.') {
        return Err(corrupt(
            dir,
            format!("array file name {:?} not allowed", rec.file),
        ));
    }
    let path: PathBuf = dir.join(&rec.file);
    let bytes =
        std::fs::read(&path).map_err(|e| corrupt(&path, format!("cannot read array: {e}")))?;
    let sha = sha256_hex(&bytes);
    if sha != rec.sha256 {
        return Err(corrupt(
            &path,
            format!(
                "SHA-256 mismatch (file {sha}, sidecar {}): the file is corrupt or was modified",
                rec.sha256
            ),
        ));
    }
    Ok(bytes)
}

/// The axes along which [`compress_codes`] predicts a code by its neighbour: φ̂ and V, along which the
/// outputs vary least from node to node (measured on the running-surface table: 16.3 MB against 19.5 MB
/// predicted along φ̂ only and 27 MB unpredicted, for 55 MB of codes).
const PREDICTED: [usize; 2] = [PHI, SPEED];

/// The stride of dimension `d` of a C-order array of `shape`, and its length.
fn stride_of(shape: &[usize], d: usize) -> (usize, usize) {
    (shape[d + 1..].iter().product(), shape[d])
}

/// The bytes of a [`Storage::U16z`] array: the codes (C order over `shape`, the full table's eight
/// dimensions) replaced by their differences to the previous node along φ̂, then along V (wrapping
/// modulo 2¹⁶; the first node of an axis keeps its code), split into the n low bytes followed by the n
/// high bytes (the high bytes of small differences are 0x00 or 0xFF), compressed as one stream of `codec`.
/// NumPy decodes it with `zlib.decompress` (`lzma.decompress` for xz), the two byte planes,
/// `np.cumsum(…, axis, dtype=np.uint16)` along V and φ̂ (axes 4 and 2), then offset + step·code.
pub fn compress_codes(codes: &[u16], shape: &[usize], codec: Codec) -> Vec<u8> {
    let mut r = codes.to_vec();
    for d in PREDICTED {
        let (stride, len) = stride_of(shape, d);
        // backwards, so that every difference reads its neighbour's code before that changes
        for i in (0..r.len()).rev() {
            if (i / stride) % len > 0 {
                r[i] = r[i].wrapping_sub(r[i - stride]);
            }
        }
    }
    let planes: Vec<u8> = r
        .iter()
        .map(|c| c.to_le_bytes()[0])
        .chain(r.iter().map(|c| c.to_le_bytes()[1]))
        .collect();
    codec.compress(&planes)
}

/// The codes of a [`compress_codes`] array of `shape`; an error for a stream that is not one of `codec` or
/// does not hold exactly the array.
pub fn decompress_codes(
    bytes: &[u8],
    shape: &[usize],
    codec: Codec,
) -> std::result::Result<Vec<u16>, String> {
    let n: usize = shape.iter().product();
    let planes = codec.decompress(bytes, 2 * n)?;
    let mut c: Vec<u16> = (0..n)
        .map(|i| u16::from_le_bytes([planes[i], planes[n + i]]))
        .collect();
    for d in PREDICTED.iter().rev() {
        let (stride, len) = stride_of(shape, *d);
        for i in 0..n {
            if (i / stride) % len > 0 {
                c[i] = c[i].wrapping_add(c[i - stride]);
            }
        }
    }
    Ok(c)
}

#[cfg(test)]
mod tests;
