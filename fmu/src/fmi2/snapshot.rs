//! FMU states (`fmi2GetFMUstate`, `fmi2SetFMUstate`) and their versioned byte serialization.
//!
//! A snapshot holds everything that defines an instance: the values of all variables (parameters, inputs
//! and the last outputs), whether the outputs are stale, the communication time, the state-machine state
//! and the model's own state ([`ModelState`]: what the model remembers between calls that influences later
//! outputs, such as an inner solver's warm start), so that an instance restored from it continues bit for
//! bit as the instance it was taken of.
//!
//! Byte layout (little-endian), format version 2:
//! `b"FMI2SNAP"`, version u32, GUID (u32 length + UTF-8), state u16, time f64, stale u8, variable count u32,
//! then per variable in table order: Real f64 | Integer i32 | Boolean u8 | String (u32 length + UTF-8),
//! then the model's state ([`ModelState::write`]), and finally the FNV-1a 64 checksum of all preceding
//! bytes (u64). Every field is checked when reading: wrong magic, version, GUID, count, type, UTF-8,
//! non-finite Real, an invalid model state, trailing bytes or checksum are errors. (Version 1 had no model
//! state; its blobs are refused, since they cannot restore an instance exactly.)

use super::state::State;
use super::variables::{Type, Value, Values, Variable};
use std::fmt::Debug;

const MAGIC: &[u8; 8] = b"FMI2SNAP";
const VERSION: u32 = 2;

/// What a model keeps between calls that influences its later outputs, as part of an FMU state, with its
/// byte encoding inside the serialized state.
pub trait ModelState: Clone + Debug + PartialEq {
    /// Appends the encoding to `out`.
    fn write(&self, out: &mut Vec<u8>);
    /// Reads the encoding written by [`ModelState::write`], checking every field (an `Err` names what is
    /// wrong).
    fn read(r: &mut Reader<'_>) -> Result<Self, String>;
}

/// The state of a model that remembers nothing that influences its outputs: no bytes.
impl ModelState for () {
    fn write(&self, _: &mut Vec<u8>) {}
    fn read(_: &mut Reader<'_>) -> Result<(), String> {
        Ok(())
    }
}

/// A copy of an instance's defining data; `S` is the model's own state.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot<S> {
    /// Values of all variables.
    pub values: Values,
    /// Whether the outputs are stale (values were set after the last computation).
    pub stale: bool,
    /// Current communication time [s].
    pub time: f64,
    /// State-machine state.
    pub state: State,
    /// The model's own state.
    pub model: S,
}

/// FNV-1a, 64 bit (Fowler–Noll–Vo): a checksum against accidental corruption, not a cryptographic hash.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Appends a u32 (little-endian).
pub fn put_u32(out: &mut Vec<u8>, x: u32) {
    out.extend_from_slice(&x.to_le_bytes());
}

/// Appends f64 values (little-endian bit patterns: exact).
pub fn put_f64s(out: &mut Vec<u8>, xs: &[f64]) {
    for x in xs {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

/// Appends a string (u32 length + UTF-8).
pub fn put_str(out: &mut Vec<u8>, s: &str) {
    put_u32(out, s.len() as u32);
    out.extend_from_slice(s.as_bytes());
}

/// Appends the values of all variables: their count u32, then per variable in table order Real f64 |
/// Integer i32 | Boolean u8 | String (u32 length + UTF-8).
pub fn put_values(out: &mut Vec<u8>, values: &Values) {
    out.extend_from_slice(&(values.list().len() as u32).to_le_bytes());
    for v in values.list() {
        match v {
            Value::Real(x) => out.extend_from_slice(&x.to_le_bytes()),
            Value::Integer(x) => out.extend_from_slice(&x.to_le_bytes()),
            Value::Boolean(x) => out.push(u8::from(*x)),
            Value::String(s) => put_str(out, s),
        }
    }
}

/// The start of a serialized FMU state: `magic`, `version` u32, the model's identity `id` (u32 length +
/// UTF-8).
pub fn begin(magic: &[u8; 8], version: u32, id: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(256);
    out.extend_from_slice(magic);
    out.extend_from_slice(&version.to_le_bytes());
    put_str(&mut out, id);
    out
}

/// A serialized FMU state begun by [`begin`], finished with the FNV-1a 64 checksum of its bytes (u64).
pub fn seal(mut out: Vec<u8>) -> Vec<u8> {
    let sum = fnv1a64(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// A reader of the fields after the identity of a serialized FMU state, once its header (`magic`), checksum,
/// format `version` and identity (`id`, named `id_name` in the message) are checked.
pub fn open<'a>(
    bytes: &'a [u8],
    magic: &[u8; 8],
    version: u32,
    id: &str,
    id_name: &str,
) -> Result<Reader<'a>, String> {
    if bytes.len() < magic.len() + 8 || &bytes[..magic.len()] != magic {
        return Err("not a serialized FMU state of this FMU (bad header)".into());
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    if fnv1a64(body).to_le_bytes() != sum {
        return Err("serialized FMU state is corrupt (checksum mismatch)".into());
    }
    let mut r = Reader::new(&body[magic.len()..]);
    let theirs = r.u32()?;
    if theirs != version {
        return Err(format!(
            "serialized FMU state has format version {theirs}, expected {version}"
        ));
    }
    let their_id = r.string()?;
    if their_id != id {
        return Err(format!(
            "serialized FMU state belongs to another FMU ({id_name} {their_id})"
        ));
    }
    Ok(r)
}

impl<S: ModelState> Snapshot<S> {
    /// The serialized bytes; `guid` identifies the model.
    pub fn to_bytes(&self, guid: &str) -> Vec<u8> {
        let mut out = begin(MAGIC, VERSION, guid);
        out.extend_from_slice(&(self.state as u16).to_le_bytes());
        out.extend_from_slice(&self.time.to_le_bytes());
        out.push(u8::from(self.stale));
        put_values(&mut out, &self.values);
        self.model.write(&mut out);
        seal(out)
    }

    /// Reads serialized bytes written by [`Snapshot::to_bytes`] for the same model.
    pub fn from_bytes(
        bytes: &[u8],
        guid: &str,
        table: &'static [Variable],
    ) -> Result<Snapshot<S>, String> {
        let mut r = open(bytes, MAGIC, VERSION, guid, "GUID")?;
        let code = u16::from_le_bytes(r.array()?);
        let state = State::ALL
            .into_iter()
            .find(|s| *s as u16 == code)
            .ok_or_else(|| format!("serialized FMU state has an unknown state code {code}"))?;
        let time = f64::from_le_bytes(r.array()?);
        let stale = r.flag()?;
        let values = r.values(table)?;
        let model = S::read(&mut r)?;
        if r.pos != r.bytes.len() || !time.is_finite() {
            return Err("serialized FMU state is corrupt (trailing bytes or bad time)".into());
        }
        Ok(Snapshot {
            values,
            stale,
            time,
            state,
            model,
        })
    }
}

/// Reads the fields of a serialized FMU state in order; every read checks the length.
pub struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// A reader of `bytes` from their start.
    pub fn new(bytes: &'a [u8]) -> Reader<'a> {
        Reader { bytes, pos: 0 }
    }

    /// The values of all variables of `table`, as [`put_values`] wrote them (count, types and finite Reals
    /// checked).
    pub fn values(&mut self, table: &'static [Variable]) -> Result<Values, String> {
        let count = u32::from_le_bytes(self.array()?) as usize;
        if count != table.len() {
            return Err(format!(
                "serialized FMU state has {count} variables, this FMU has {}",
                table.len()
            ));
        }
        let mut list = Vec::with_capacity(count);
        for var in table {
            list.push(match var.ty() {
                Type::Real => {
                    let x = f64::from_le_bytes(self.array()?);
                    if !x.is_finite() {
                        return Err(format!(
                            "serialized FMU state has a non-finite value of {}",
                            var.name
                        ));
                    }
                    Value::Real(x)
                }
                Type::Integer => Value::Integer(i32::from_le_bytes(self.array()?)),
                Type::Boolean => Value::Boolean(self.flag()?),
                Type::String => Value::String(self.string()?),
            });
        }
        Ok(Values::from_list(table, list).expect("types follow the table"))
    }

    /// Whether every byte was read.
    pub fn at_end(&self) -> bool {
        self.pos == self.bytes.len()
    }

    /// The next u32.
    pub fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    /// The next `n` f64 values, each finite (else an error naming `what`).
    pub fn finite_f64s(&mut self, n: usize, what: &str) -> Result<Vec<f64>, String> {
        // the length is checked before anything is allocated
        let bytes = self.take(
            n.checked_mul(8)
                .ok_or("serialized FMU state is truncated")?,
        )?;
        let xs: Vec<f64> = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("chunks of 8")))
            .collect();
        match xs.iter().all(|x| x.is_finite()) {
            true => Ok(xs),
            false => Err(format!(
                "serialized FMU state has a non-finite value in {what}"
            )),
        }
    }

    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.pos.checked_add(n).filter(|e| *e <= self.bytes.len());
        let end = end.ok_or("serialized FMU state is truncated")?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    /// The next `N` bytes.
    pub fn array<const N: usize>(&mut self) -> Result<[u8; N], String> {
        Ok(self.take(N)?.try_into().expect("length checked"))
    }

    /// The next Boolean byte (0 or 1).
    pub fn flag(&mut self) -> Result<bool, String> {
        match self.array::<1>()?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(format!(
                "serialized FMU state has an invalid Boolean byte {b}"
            )),
        }
    }

    /// The next string (u32 length + UTF-8).
    pub fn string(&mut self) -> Result<String, String> {
        let n = u32::from_le_bytes(self.array()?) as usize;
        let s = self.take(n)?;
        String::from_utf8(s.to_vec()).map_err(|_| "serialized FMU state has invalid UTF-8".into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::variables::{Causality, Kind, Variability};

    static TABLE: [Variable; 4] = [
        Variable {
            name: "x",
            vr: 0,
            causality: Causality::Input,
            variability: Variability::Continuous,
            kind: Kind::Real {
                unit: "1",
                start: Some(1.5),
                min: None,
                max: None,
                nominal: None,
            },
            description: "",
        },
        Variable {
            name: "n",
            vr: 1,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            kind: Kind::Integer {
                start: Some(-3),
                min: None,
                max: None,
            },
            description: "",
        },
        Variable {
            name: "b",
            vr: 2,
            causality: Causality::Output,
            variability: Variability::Discrete,
            kind: Kind::Boolean { start: None },
            description: "",
        },
        Variable {
            name: "s",
            vr: 3,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            kind: Kind::String {
                start: Some("päth/%20"),
            },
            description: "",
        },
    ];

    /// A model state of some numbers, optional.
    #[derive(Debug, Clone, PartialEq)]
    struct Numbers(Option<Vec<f64>>);

    impl ModelState for Numbers {
        fn write(&self, out: &mut Vec<u8>) {
            out.push(u8::from(self.0.is_some()));
            if let Some(xs) = &self.0 {
                put_u32(out, xs.len() as u32);
                put_f64s(out, xs);
            }
        }
        fn read(r: &mut Reader<'_>) -> Result<Self, String> {
            if !r.flag()? {
                return Ok(Numbers(None));
            }
            let n = r.u32()? as usize;
            Ok(Numbers(Some(r.finite_f64s(n, "the numbers")?)))
        }
    }

    fn sample() -> Snapshot<Numbers> {
        let mut values = Values::start(&TABLE);
        values.set(2, Value::Boolean(true));
        Snapshot {
            values,
            stale: true,
            time: 0.25,
            state: State::StepComplete,
            // bit patterns that a text round trip would not keep
            model: Numbers(Some(vec![0.1 + 0.2, -0.0, 5e-324, f64::MAX])),
        }
    }

    #[test]
    fn round_trip() {
        let s = sample();
        let bytes = s.to_bytes("{g}");
        let back = Snapshot::from_bytes(&bytes, "{g}", &TABLE).unwrap();
        assert_eq!(back, s);
        let bits = |s: &Snapshot<Numbers>| {
            s.model
                .0
                .as_ref()
                .map(|xs| xs.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
        };
        assert_eq!(bits(&back), bits(&s));
        let none = Snapshot {
            model: Numbers(None),
            ..s
        };
        assert_eq!(
            Snapshot::from_bytes(&none.to_bytes("{g}"), "{g}", &TABLE).unwrap(),
            none
        );
    }

    #[test]
    fn an_invalid_model_state_or_an_older_version_is_rejected_by_name() {
        // a non-finite number with a valid checksum
        let mut s = sample();
        s.model = Numbers(Some(vec![1.0, f64::NAN]));
        let e = Snapshot::<Numbers>::from_bytes(&s.to_bytes("{g}"), "{g}", &TABLE).unwrap_err();
        assert!(e.contains("non-finite value in the numbers"), "{e}");
        // a count beyond the bytes: truncated, nothing allocated
        let mut bytes = sample().to_bytes("{g}");
        let body = bytes.len() - 8 - 4 * 8 - 4;
        bytes[body..body + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        let n = bytes.len() - 8;
        let sum = fnv1a64(&bytes[..n]);
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
        let e = Snapshot::<Numbers>::from_bytes(&bytes, "{g}", &TABLE).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
        // format version 1 (no model state)
        let mut bytes = sample().to_bytes("{g}");
        bytes[8..12].copy_from_slice(&1u32.to_le_bytes());
        let n = bytes.len() - 8;
        let sum = fnv1a64(&bytes[..n]);
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
        let e = Snapshot::<Numbers>::from_bytes(&bytes, "{g}", &TABLE).unwrap_err();
        assert!(e.contains("format version 1, expected 2"), "{e}");
    }

    #[test]
    fn every_corruption_is_rejected() {
        let bytes = sample().to_bytes("{g}");
        // any flipped byte: header, checksum or payload
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0x40;
            assert!(
                Snapshot::<Numbers>::from_bytes(&b, "{g}", &TABLE).is_err(),
                "byte {i}"
            );
        }
        for n in 0..bytes.len() {
            assert!(
                Snapshot::<Numbers>::from_bytes(&bytes[..n], "{g}", &TABLE).is_err(),
                "truncated to {n}"
            );
        }
        let e = Snapshot::<Numbers>::from_bytes(&bytes, "{other}", &TABLE).unwrap_err();
        assert!(e.contains("another FMU"), "{e}");
        assert!(
            Snapshot::<Numbers>::from_bytes(&bytes, "{g}", &TABLE[..3])
                .unwrap_err()
                .contains("variables")
        );
    }

    #[test]
    fn checksum_matches_the_published_fnv1a_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }
}
