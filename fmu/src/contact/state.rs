//! The wheel–rail model's part of an FMU state: the exact solver's warm start, with its byte encoding.
//!
//! With `warm_start` on, an exact solve starts from the state of the last exact solve of a step, so its
//! result depends on that state (within the solver tolerance, not bit for bit): an instance restored from
//! an FMU state must start its next solve from the same state as the instance the FMU state was taken of.
//!
//! Encoding (little-endian, inside the serialized FMU state): present u8 (0 or 1); if present, nx u32,
//! ny u32 and the four per-cell fields temperature, separation, fluid pressure, fluid height, each as a
//! count u32 and that many f64 bit patterns (exact). Read back, every count is checked against the bytes
//! left and every value must be finite.

use crate::fmi2::snapshot::{ModelState, Reader, put_f64s, put_u32};
use wheelrail::model::WarmStart;

/// What the wheel–rail model remembers between steps that influences later outputs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContactState {
    /// The state of the last exact solve of a step, the next exact solve's start (parameter
    /// `warm_start`; None before the first exact solve and after `fmi2Reset`).
    pub warm: Option<WarmStart>,
}

impl ModelState for ContactState {
    fn write(&self, out: &mut Vec<u8>) {
        out.push(u8::from(self.warm.is_some()));
        if let Some(w) = &self.warm {
            put_u32(out, w.nx as u32);
            put_u32(out, w.ny as u32);
            for field in [
                &w.temperature,
                &w.separation,
                &w.fluid_pressure,
                &w.fluid_height,
            ] {
                put_u32(out, field.len() as u32);
                put_f64s(out, field);
            }
        }
    }

    fn read(r: &mut Reader<'_>) -> Result<Self, String> {
        if !r.flag()? {
            return Ok(ContactState { warm: None });
        }
        let (nx, ny) = (r.u32()? as usize, r.u32()? as usize);
        let mut field = |what: &str| {
            let n = r.u32()? as usize;
            r.finite_f64s(n, &format!("the warm start's {what}"))
        };
        Ok(ContactState {
            warm: Some(WarmStart {
                nx,
                ny,
                temperature: field("temperature")?,
                separation: field("separation")?,
                fluid_pressure: field("fluid pressure")?,
                fluid_height: field("fluid height")?,
            }),
        })
    }
}
