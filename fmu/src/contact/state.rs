//! The wheel–rail model's part of an FMU state: the exact solver's warm start, with its byte encoding.
//!
//! With `warm_start` on, an exact solve starts from the state of the last exact solve of a step, so its
//! result depends on that state (within the solver tolerance, not bit for bit): an instance restored from
//! an FMU state must start its next solve from the same state as the instance the FMU state was taken of.
//!
//! Encoding (little-endian, inside the serialized FMU state): present u8 (0 or 1); if present, nx u32,
//! ny u32 and the six per-cell fields temperature, separation, fluid pressure, fluid height, traction x,
//! traction y, each as a count u32 and that many f64 bit patterns (exact). Read back, every count is
//! checked against the bytes left, the two traction components must be as many, and every value must be
//! finite.

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
            for k in 0..2 {
                let component: Vec<f64> = w.traction.iter().map(|t| t[k]).collect();
                put_u32(out, component.len() as u32);
                put_f64s(out, &component);
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
        let (temperature, separation, fluid_pressure, fluid_height) = (
            field("temperature")?,
            field("separation")?,
            field("fluid pressure")?,
            field("fluid height")?,
        );
        let (tx, ty) = (field("traction x")?, field("traction y")?);
        if tx.len() != ty.len() {
            return Err(format!(
                "the warm start's traction has {} x and {} y components",
                tx.len(),
                ty.len()
            ));
        }
        Ok(ContactState {
            warm: Some(WarmStart {
                nx,
                ny,
                temperature,
                separation,
                fluid_pressure,
                fluid_height,
                traction: tx.into_iter().zip(ty).map(|(x, y)| [x, y]).collect(),
            }),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> Result<ContactState, String> {
        ContactState::read(&mut Reader::new(bytes))
    }

    #[test]
    fn the_warm_start_round_trips_bit_for_bit_and_bad_encodings_are_refused() {
        let warm = WarmStart {
            nx: 3,
            ny: 2,
            temperature: vec![293.15, 0.1 + 0.2, 400.0 + 1e-13],
            separation: vec![1e-6 / 3.0, -2e-7, 5e-324],
            fluid_pressure: vec![0.0, -0.0, 1.5e6],
            fluid_height: vec![],
            traction: vec![[1e5 / 3.0, -0.0], [0.0, 2.5e8]],
        };
        for state in [
            ContactState { warm: None },
            ContactState { warm: Some(warm) },
        ] {
            let mut bytes = Vec::new();
            state.write(&mut bytes);
            let back = read(&bytes).unwrap();
            assert_eq!(back, state);
            let bits = |s: &ContactState| {
                s.warm.as_ref().map(|w| {
                    let traction: Vec<f64> = w.traction.iter().flatten().copied().collect();
                    [&w.temperature, &w.separation, &w.fluid_pressure, &traction]
                        .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                })
            };
            assert_eq!(bits(&back), bits(&state));
            for n in 0..bytes.len() {
                assert!(read(&bytes[..n]).is_err(), "truncated to {n}");
            }
        }
        let mut bytes = Vec::new();
        ContactState {
            warm: Some(WarmStart {
                nx: 1,
                ny: 1,
                temperature: vec![f64::INFINITY],
                separation: vec![],
                fluid_pressure: vec![],
                fluid_height: vec![],
                traction: vec![],
            }),
        }
        .write(&mut bytes);
        let e = read(&bytes).unwrap_err();
        assert!(
            e.contains("non-finite value in the warm start's temperature"),
            "{e}"
        );
        assert!(read(&[2]).unwrap_err().contains("Boolean byte 2"));
        // traction components of different lengths
        let mut bytes = vec![1];
        for n in [1, 1, 0, 0, 0, 0, 1] {
            put_u32(&mut bytes, n);
        }
        put_f64s(&mut bytes, &[1.0]);
        put_u32(&mut bytes, 0);
        let e = read(&bytes).unwrap_err();
        assert!(e.contains("1 x and 0 y components"), "{e}");
    }
}
