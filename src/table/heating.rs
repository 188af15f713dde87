//! The direction factor of FASTSIM's frictional heat, which a table divides out of the heat it interpolates:
//!
//!   Λ = L/L1 = (|ξ| + (L2/L1)·|η| + (L3/L1)·|z|)/sqrt(ξ² + η² + z²),  z = c·φ  [-]
//!
//! with L FASTSIM's combined flexibility and L1, L2, L3 Kalker's (docs/model.md §6.2), c = sqrt(a·b).
//!
//! Why (docs/model.md §12.3): FASTSIM turns the traction excess of a slipping cell into slip with the one
//! combined flexibility L of the creepages' direction; the tractions do not depend on L. So at given
//! tractions the slip, the frictional power density τ·|s|, the frictional power P_f and the temperature
//! rise are proportional to L — and L has a kink wherever a creepage changes sign, so T_max and P_f rise
//! like |η| and |φ| from η = 0 and φ = 0 on both sides while the forces stay smooth (exact solver, a/b 0.72,
//! p0 1.51 GPa, V 158 m/s, ξ 0.25 %, wet: T_max rises by 18 K per 0.1 % of |η|, linearly from |η| = 1e-5 on,
//! on every grid). A table's creepage axes have nodes at η̂ = 0 and φ̂ = 0, where its monotone cubic splines
//! are C¹ with slope 0 (the η mirror's ghost nodes; Steffen's limit where the secants change sign): they
//! interpolate such a kink as a parabola lagging by up to 4/27 of the rise over the node's cells. Divided by
//! Λ at its nodes, the rise G of T_max ([`super::rise`]) and P_f/(F_N·V) lose the kink — exactly where the
//! temperature does not act back on the tractions, to first order where it does — and the interpolated
//! value is multiplied by the query's own Λ. Tables of the exact tangential solver, which has no combined
//! flexibility, use Λ = 1.

use super::axes::{Axes, DIMS, ETA, FORCE, PHI, PRESSURE, RATIO, XI};
use super::coords::Coordinates;
use crate::error::Result;
use crate::params::{Params, Tangential};
use crate::tangential::Flexibilities;

/// Whether tables of `params` interpolate the heat per unit of Λ: tables of FASTSIM.
pub fn applies(params: &Params) -> bool {
    params.tangential == Tangential::Fastsim
}

/// Λ at one point and its slopes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Heating {
    /// Λ [-]: 1 for a single creepage along ξ, and where all creepages vanish (nothing slips there).
    pub value: f64,
    /// ∂Λ/∂(ξ, η, z) [-, -, -] (a creepage of value 0 contributes the mean of its two one-sided slopes).
    pub slope: [f64; 3],
}

impl Heating {
    /// Λ ≡ 1 (tables of the exact tangential solver).
    pub const ONE: Heating = Heating {
        value: 1.0,
        slope: [0.0; 3],
    };
}

/// The flexibility ratios of one contact, L2/L1 and L3/L1 [-] (docs/model.md §6.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlexibilityRatios {
    lateral: f64,
    spin: f64,
}

impl FlexibilityRatios {
    /// The ratios of flexibilities `f`.
    pub fn of(f: &Flexibilities) -> Self {
        Self {
            lateral: f.l2 / f.l1,
            spin: f.l3 / f.l1,
        }
    }

    /// Λ of creepages ξ, η [-] and z = c·φ [-] (the module's formula; Λ·L1 is
    /// [`Flexibilities::combined`]) and its slopes ∂Λ/∂x = (r_x·sgn x − Λ·x/D)/D, D = sqrt(ξ² + η² + z²).
    #[inline]
    pub fn at(&self, xi: f64, eta: f64, z: f64) -> Heating {
        let norm = (xi * xi + eta * eta + z * z).sqrt();
        if norm == 0.0 {
            return Heating::ONE;
        }
        let sign = |x: f64| {
            if x == 0.0 { 0.0 } else { x.signum() }
        };
        let inv = 1.0 / norm;
        let value = (xi.abs() + self.lateral * eta.abs() + self.spin * z.abs()) * inv;
        let slope = |r: f64, x: f64| (r * sign(x) - value * x * inv) * inv;
        Heating {
            value,
            slope: [
                slope(1.0, xi),
                slope(self.lateral, eta),
                slope(self.spin, z),
            ],
        }
    }
}

/// Λ at every node of a table, from the raw creepages of the nodes' contacts ([`Coordinates::point`]): it
/// depends on the creepage coordinates and the contact (F_N, a/b, p_ref) only, so it is computed once per
/// contact of the table for all its creepage nodes.
pub struct NodeFactors {
    /// Per contact (C order over F_N, a/b, p_ref), Λ of the creepage nodes (C order over ξ̂, η̂, φ̂).
    values: Vec<f64>,
    /// Number of creepage nodes nξ̂·nη̂·nφ̂.
    per_contact: usize,
    shape: [usize; DIMS],
}

impl NodeFactors {
    /// Λ at the nodes of `axes` located by `coords`; None for a table of the exact tangential solver
    /// (Λ = 1).
    pub fn new(coords: &Coordinates, axes: &Axes) -> Result<Option<Self>> {
        let shape = axes.shape();
        let (nx, ny, np) = (shape[XI], shape[ETA], shape[PHI]);
        let per_contact = nx * ny * np;
        let contacts = shape[FORCE] * shape[RATIO] * shape[PRESSURE];
        let mut values = Vec::with_capacity(contacts * per_contact);
        let point = |d: usize, i: usize| axes.0[d].points[i];
        for f in 0..shape[FORCE] {
            for r in 0..shape[RATIO] {
                for p in 0..shape[PRESSURE] {
                    // the raw creepages of each creepage node of this contact (speed and wetness do not
                    // enter Λ: their first nodes)
                    let mut q = std::array::from_fn(|d| axes.0[d].points[0]);
                    (q[FORCE], q[RATIO], q[PRESSURE]) =
                        (point(FORCE, f), point(RATIO, r), point(PRESSURE, p));
                    let Some(ratios) = coords.flexibility_ratios(&coords.point(&q)?.1)? else {
                        return Ok(None);
                    };
                    let mut raw = [vec![0.0; nx], vec![0.0; ny], vec![0.0; np]];
                    for m in 0..nx.max(ny).max(np) {
                        let [i, j, k] = [m.min(nx - 1), m.min(ny - 1), m.min(np - 1)];
                        (q[XI], q[ETA], q[PHI]) = (point(XI, i), point(ETA, j), point(PHI, k));
                        let (node, e) = coords.point(&q)?;
                        (raw[0][i], raw[1][j]) = (node.creepage_x, node.creepage_y);
                        raw[2][k] = node.spin * e.radius();
                    }
                    for x in &raw[0] {
                        for y in &raw[1] {
                            for z in &raw[2] {
                                values.push(ratios.at(*x, *y, *z).value);
                            }
                        }
                    }
                }
            }
        }
        Ok(Some(Self {
            values,
            per_contact,
            shape,
        }))
    }

    /// Λ at the node of indices `idx` along the axes.
    #[inline]
    pub fn at(&self, idx: &[usize; DIMS]) -> f64 {
        let s = &self.shape;
        let contact = (idx[FORCE] * s[RATIO] + idx[RATIO]) * s[PRESSURE] + idx[PRESSURE];
        let creep = (idx[XI] * s[ETA] + idx[ETA]) * s[PHI] + idx[PHI];
        self.values[contact * self.per_contact + creep]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{OperatingPoint, Params};
    use crate::tangential::{Creepages, kalker_coefficients};

    fn flexibilities(a: f64, b: f64) -> Flexibilities {
        let p = Params::default();
        let m = p.material.at(p.material.bulk_temperature);
        Flexibilities::new(
            a,
            b,
            m.shear_modulus,
            &kalker_coefficients(a, b, m.poisson).unwrap(),
        )
    }

    #[test]
    fn the_factor_is_the_combined_flexibility_over_l1_and_its_slopes_are_its_derivatives() {
        for (a, b) in [(5.9e-3, 10.5e-3), (9e-3, 2e-3)] {
            let f = flexibilities(a, b);
            let r = FlexibilityRatios::of(&f);
            let c = (a * b).sqrt();
            for (xi, eta, phi) in [
                (2e-3, 0.0, 0.0),
                (0.0, 1e-3, 0.0),
                (0.0, 0.0, 0.3),
                (2.5e-3, -9e-4, 0.26),
                (-0.05, 0.01, -1.2),
            ] {
                let h = r.at(xi, eta, c * phi);
                let want = f.combined(Creepages { xi, eta, phi }, c) / f.l1;
                assert!((h.value - want).abs() < 1e-14 * want, "{xi} {eta} {phi}");
                // single creepages: the ratio of their own flexibility to L1
                if eta == 0.0 && phi == 0.0 {
                    assert!((h.value - 1.0).abs() < 1e-15);
                }
                for d in 0..3 {
                    let mut x = [xi, eta, c * phi];
                    if x[d] == 0.0 {
                        continue;
                    }
                    let step = 1e-7 * x[d].abs();
                    x[d] += step;
                    let up = r.at(x[0], x[1], x[2]).value;
                    x[d] -= 2.0 * step;
                    let down = r.at(x[0], x[1], x[2]).value;
                    let fd = (up - down) / (2.0 * step);
                    assert!(
                        (h.slope[d] - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                        "{d}: {h:?} {fd}"
                    );
                }
            }
            assert_eq!(r.at(0.0, 0.0, 0.0), Heating::ONE);
            // the kink: one-sided slopes ±L2/(L1·|ξ|) at η = 0, their mean reported
            let (up, down) = (r.at(2e-3, 1e-9, 0.0), r.at(2e-3, -1e-9, 0.0));
            assert!((up.value - down.value).abs() < 1e-12);
            let one_sided = (up.value - 1.0) / 1e-9;
            assert!((one_sided - f.l2 / f.l1 / 2e-3).abs() < 1e-3 * one_sided);
            assert_eq!(r.at(2e-3, 0.0, 0.0).slope[1], 0.0);
        }
    }

    #[test]
    fn node_factors_are_the_factors_of_the_nodes_contacts() {
        let params = Params::default();
        for axes in [super::super::tiny_axes(), super::super::small_axes()] {
            let coords = Coordinates::new(&params, &axes);
            let nodes = NodeFactors::new(&coords, &axes).unwrap().unwrap();
            let shape = axes.shape();
            for flat in (0..axes.len()).step_by(7) {
                let mut idx = [0; DIMS];
                let mut rest = flat;
                for d in (0..DIMS).rev() {
                    idx[d] = rest % shape[d];
                    rest /= shape[d];
                }
                let (p, e): (OperatingPoint, _) = coords.point(&axes.coordinates(flat)).unwrap();
                let f = flexibilities(e.a, e.b);
                let want = if p.creepage_x == 0.0 && p.creepage_y == 0.0 && p.spin == 0.0 {
                    1.0
                } else {
                    let creep = Creepages {
                        xi: p.creepage_x,
                        eta: p.creepage_y,
                        phi: p.spin,
                    };
                    f.combined(creep, e.radius()) / f.l1
                };
                assert!((nodes.at(&idx) - want).abs() < 1e-12 * want, "{flat}");
            }
        }
    }
}
