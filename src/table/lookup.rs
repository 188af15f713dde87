//! The evaluation of a table: the operating point in the table's coordinates and the stored quadrant, the
//! tensor-product interpolation (`Table::core`: the linear corners and the cubic Hermite along φ̂, then
//! the monotone splines along η̂ and ξ̂), and the outputs and their Jacobian in the caller's frame.

use super::axes::{DIMS, ETA, FORCE, LINEAR_DIMS, PHI, SPEED, WET, XI};
use super::coords::Ellipse;
use super::file::OUTPUTS;
use super::flags::{BESIDE_ETA, BESIDE_UNRESOLVED, BESIDE_XI, NEAR_UNCONVERGED, UNRESOLVED};
use super::interp::{Corners, CubicStencil, Fraction, Offsets};
use super::kernel::{Hermite, corner_sum, window_sums};
use super::layout::{LAST_CELL, ROW, Row, SLOPE, VAL, rows_id};
use super::{INPUTS, JACOBIAN_ROWS, Jacobian, Table, TableOutput};
use crate::error::{Error, Result};
use crate::params::OperatingPoint;

/// Interpolated normalised outputs and their derivatives with respect to the (mirrored, clamped)
/// coordinates.
pub(super) struct Core {
    pub(super) v: [f64; OUTPUTS],
    pub(super) d: [[f64; DIMS]; OUTPUTS],
    pub(super) converged: bool,
    pub(super) resolved: bool,
}

impl Table {
    /// The evaluation of `point` with contact `e`, whose geometry coordinates are `geometry`
    /// ([`Coordinates::geometry`]).
    #[inline(always)]
    pub(super) fn eval<const JAC: bool, const K: u8>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        point.validate()?;
        if !(e.a > 0.0 && e.b > 0.0 && e.a.is_finite() && e.b.is_finite()) {
            return Err(Error::out_of_range(
                "semi-axes",
                e.a.min(e.b),
                "finite and > 0 m",
            ));
        }
        let at = self.coordinates.of_geometry(point, e, geometry)?;
        let (signed, m) = (at.q, at.m);
        let (mut q, mx, my) = self.stored_quadrant(signed);
        let mut inside = [true; DIMS];
        for d in 0..DIMS {
            (q[d], inside[d]) = self.interp[d].clamp(q[d]);
        }
        let mut core = self.core::<JAC, K>(&q);
        // the heat is interpolated per unit of the direction factor Λ (`heating`): times the query's own
        let lambda = at.heating;
        let heat = core.v[3];
        core.v[3] *= lambda;
        core.v[5] *= lambda;
        // undo the mirrors: output signs S and input signs D (J = S·J'·D)
        let sx = if mx { -1.0 } else { 1.0 };
        let sy = if my { -1.0 } else { 1.0 };
        let out_sign = [sx, sy, sy, 1.0, 1.0, 1.0];
        let in_sign = [sx, sy, sy, 1.0, 1.0, 1.0, 1.0, 1.0];
        let mut g = [0.0; OUTPUTS];
        for (o, x) in g.iter_mut().enumerate() {
            *x = out_sign[o] * core.v[o];
        }
        let f = point.normal_force;
        let c = e.radius();
        let max_temperature = self.rise.temperature(core.v[3]);
        let out = TableOutput {
            force_x: f * g[0],
            force_y: f * g[1],
            spin_moment: f * c * g[2],
            // (|g| ≤ a few: no overflow to guard against, as hypot does at 5× the cost)
            traction_coefficient: (g[0] * g[0] + g[1] * g[1]).sqrt(),
            max_temperature: max_temperature.max(self.bulk_temperature),
            fluid_load_fraction: core.v[4].clamp(0.0, 1.0),
            frictional_power: self
                .has_power
                .then(|| (f * point.speed.abs() * core.v[5]).max(0.0)),
            in_range: inside.iter().all(|x| *x) && self.within_raw_limits(&at.raw),
            converged: core.converged,
            resolved: core.resolved,
        };
        let mut jac = [[0.0; INPUTS]; JACOBIAN_ROWS];
        if JAC {
            // derivatives of the normalised outputs g by the coordinates, in the caller's frame
            let mut dq = [[0.0; DIMS]; OUTPUTS];
            for o in 0..OUTPUTS {
                for d in 0..DIMS {
                    if inside[d] {
                        dq[o][d] = out_sign[o] * core.d[o][d] * in_sign[d];
                    }
                }
            }
            // chained to the inputs (ξ, η, φ, F_N, V, w): ∂q/∂(raw creepage), F_N through every
            // coordinate that moves with it (the creepage scales k through k·∂q/∂k, p_ref for semi-axes
            // ∝ F_N^e, with similarity the equivalent's spin and speed; `coords::Located`), V through its
            // coordinate
            let mut dg = [[0.0; INPUTS]; OUTPUTS];
            for o in 0..OUTPUTS {
                for d in 0..3 {
                    dg[o][d] = dq[o][d] * m[d].dx;
                }
                dg[o][FORCE] = (0..DIMS).map(|d| dq[o][d] * at.dlnf[d]).sum::<f64>() / f;
                dg[o][FORCE + 1] = dq[o][SPEED] * at.dv;
                dg[o][FORCE + 2] = dq[o][WET];
            }
            // G = Λ·Ĝ: Λ·∂Ĝ + Ĝ·∂Λ (Λ moves with ξ, η, φ and, through c·φ, with F_N)
            let dlambda = [
                at.dheating[0],
                at.dheating[1],
                at.dheating[2],
                at.dheating[3] / f,
                0.0,
                0.0,
            ];
            for (x, dl) in dg[3].iter_mut().zip(dlambda) {
                *x = lambda * *x + heat * dl;
            }
            let f_t = out.traction_coefficient;
            let t_free = max_temperature > self.bulk_temperature;
            let dt_dg = self.rise.temperature_slope(core.v[3]);
            let l_free = core.v[4] > 0.0 && core.v[4] < 1.0;
            for d in 0..INPUTS {
                jac[0][d] = f * dg[0][d];
                jac[1][d] = f * dg[1][d];
                jac[2][d] = f * c * dg[2][d];
                if f_t > 0.0 {
                    jac[3][d] = (g[0] * dg[0][d] + g[1] * dg[1][d]) / f_t;
                }
                jac[4][d] = if t_free { dt_dg * dg[3][d] } else { 0.0 };
                jac[5][d] = if l_free { dg[4][d] } else { 0.0 };
            }
            // the normalisation's own F_N dependence: F = F_N·g, M = F_N·c·g, c ∝ F_N^e
            jac[0][FORCE] += g[0];
            jac[1][FORCE] += g[1];
            jac[2][FORCE] += c * g[2] * (1.0 + e.load_exponent);
        }
        Ok((out, jac))
    }

    /// Table coordinates `q` brought into the stored quadrant ξ ≥ 0 (if the ξ axis is mirrored), η ≥ 0 (the
    /// η mirror also reverses φ), and whether the ξ and the η mirror were applied.
    #[inline(always)]
    pub(crate) fn stored_quadrant(&self, mut q: [f64; DIMS]) -> ([f64; DIMS], bool, bool) {
        let mx = q[XI] < 0.0 && self.axes.0[XI].mirrored;
        let my = q[ETA] < 0.0;
        if mx {
            q[XI] = -q[XI];
        }
        if my {
            q[ETA] = -q[ETA];
            q[PHI] = -q[PHI];
        }
        (q, mx, my)
    }

    /// Tensor-product interpolation at stored-quadrant coordinates `q` (inside the ranges).
    ///
    /// At each of the 4 × 4 (ξ̂, η̂) window points and the two ends of the φ̂ interval, the 16 corners of
    /// the linear stencil over (F_N, V, w, a/b, p_ref) (see `interp`) are contracted, for the values and their precomputed
    /// Steffen slopes along φ̂; the cubic Hermite along φ̂ follows (linear in values and slopes), then the
    /// monotone splines along η̂ and ξ̂ evaluated on the contracted values. With derivatives, each stage
    /// carries them forward (the fibre weights are the partial derivatives, see `interp`). Ghost points of
    /// mirrored axes read the mirror-image point (φ̂ index reversed by the η mirror, which also reverses the
    /// φ̂ slope) with the symmetry's output signs. Next to an unresolved cell along η̂ or ξ̂ (a jump of the
    /// model) the spline takes the one-sided slope at the shared node: the window node beyond is replaced by
    /// the extrapolation of the cell's secant ([`super::interp::CubicStencil::beyond`]; docs/model.md §12.3).
    #[inline(always)]
    pub(super) fn core<const JAC: bool, const K: u8>(&self, q: &[f64; DIMS]) -> Core {
        const L: usize = LINEAR_DIMS;
        let window = self.window(q);
        let (cx, cy, flags) = (window.cx, window.cy, window.flags);
        let resolved = flags & UNRESOLVED == 0;
        // stages 0 and 1: values [j][i·OUTPUTS + o] after φ (the layout of the η stage's lanes), with
        // derivatives [i][j][o][F_N, V, w, a/b, p_ref, φ]
        // (the derivatives only with the Jacobian: a value does not clear their 4.6 kB)
        let mut c1 = [[0.0; 4 * OUTPUTS]; 4];
        let mut t1_rows;
        let t1: &mut [[[[f64; L + 1]; OUTPUTS]; 4]] = if JAC {
            t1_rows = [[[[0.0; L + 1]; OUTPUTS]; 4]; 4];
            &mut t1_rows
        } else {
            &mut []
        };
        let converged = self.phi_stage::<JAC, K>(&window, &mut c1, t1);
        // next to a cell that holds a jump of the model (unresolved), the spline of this cell takes the
        // one-sided slope at the shared node: the window's node beyond is replaced by the extrapolation of
        // this cell's secant (its values, and with the Jacobian their derivatives)
        // (the cell's flags say which neighbours are unresolved: [`beside_unresolved`]; out of line, so that
        // the common path compiles as without)
        if flags & BESIDE_ETA != 0 {
            one_sided(&cy, BESIDE_UNRESOLVED[1], flags, &mut c1, t1);
        }
        // stage 2: along η, all 4·OUTPUTS fibres at once; derivatives (F_N, V, w, a/b, p_ref, φ, η)
        let mut c2 = [[0.0; OUTPUTS]; 4];
        let mut t2 = [[[0.0; L + 2]; OUTPUTS]; 4];
        eta_stage::<JAC>(&cy, &c1, t1, &mut c2, &mut t2);
        if flags & BESIDE_XI != 0 {
            let derivatives = if JAC {
                std::slice::from_mut(&mut t2)
            } else {
                &mut []
            };
            one_sided(&cx, BESIDE_UNRESOLVED[0], flags, &mut c2, derivatives);
        }
        // stage 3: along ξ
        let mut v = [0.0; OUTPUTS];
        let mut d = [[0.0; DIMS]; OUTPUTS];
        xi_stage::<JAC>(&cx, &c2, &t2, &mut v, &mut d);
        Core {
            v,
            d,
            converged,
            resolved,
        }
    }

    /// The lookup's [`Window`] at stored-quadrant coordinates `q`, and whether it prefetches (`core`).
    #[inline(always)]
    fn window(&self, q: &[f64; DIMS]) -> Window {
        const L: usize = LINEAR_DIMS;
        let cx = self.interp[XI].cubic(q[XI]);
        let cy = self.interp[ETA].cubic(q[ETA]);
        let (k0, hw, hdw) = self.interp[PHI].cubic(q[PHI]).hermite();
        // (loops, not `array::from_fn`, whose closures stay calls outside this kernel's instruction set)
        let mut fractions = [Fraction::default(); L];
        let mut linear_strides = [0; L];
        let st = &self.strides;
        for k in 0..L {
            fractions[k] = self.interp[FORCE + k].fraction(q[FORCE + k]);
            linear_strides[k] = st[FORCE + k];
        }
        let n_phi = self.axes.0[PHI].points.len() as isize;
        // the point's cell, by its lowest corner (which keeps the cell's flags)
        let cell = cx.lower() * st[XI]
            + cy.lower() * st[ETA]
            + k0.unsigned_abs() * st[PHI]
            + (0..L)
                .map(|k| fractions[k].start * linear_strides[k])
                .sum::<usize>();
        let flags = if self.cell_flags.is_empty() {
            0
        } else {
            self.cell_flags
                .get(cell)
                .copied()
                .unwrap_or(UNRESOLVED | NEAR_UNCONVERGED)
        };
        // prefetch only when this thread's previous lookup was in another cell (or table): in the same
        // cell the stencil is that lookup's, still in the caches
        let prefetch = self.prefetch && {
            let key = (rows_id(&self.rows), cell);
            LAST_CELL.with(|last| last.replace(key) != key)
        };
        Window {
            cx,
            cy,
            k0,
            hw,
            hdw,
            fractions,
            linear_strides,
            n_phi,
            flags,
            prefetch,
        }
    }

    /// Stages 0 and 1 of `core` (the linear corners, then the cubic Hermite along φ̂) at the 4 × 4 (ξ̂, η̂)
    /// points of `window`: the values `c1` [j][i·OUTPUTS + o] and, with the Jacobian, their derivatives `t1`
    /// [i][j][o][F_N, V, w, a/b, p_ref, φ]; whether every point the values depend on converged.
    #[inline(always)]
    fn phi_stage<const JAC: bool, const K: u8>(
        &self,
        window: &Window,
        c1: &mut [[f64; 4 * OUTPUTS]; 4],
        t1: &mut [PhiDerivatives],
    ) -> bool {
        const L: usize = LINEAR_DIMS;
        let Window {
            cx,
            cy,
            hw,
            hdw,
            fractions,
            linear_strides,
            flags,
            prefetch,
            ..
        } = *window;
        let st = &self.strides;
        // whether the cell's stencil holds an unconverged point: then which corners of non-zero weight do
        let check_converged = flags & NEAR_UNCONVERGED != 0;
        // the linear corners' row offsets from the creepage node and weights (with the Jacobian, also the
        // weights' derivatives)
        // (a value skips the corners beyond coordinates on a node, of weight 0; the Jacobian needs every
        // corner, whose weights' derivatives need not vanish with the weight)
        let stencil = if JAC {
            Offsets::of(&fractions, &linear_strides)
        } else {
            Offsets::of_value(&fractions, &linear_strides)
        };
        let dl = JAC.then(|| Corners::of(&fractions).dw);
        let (off, wl) = (&stencil.off[..stencil.n], &stencil.w[..stencil.n]);
        let max_off = stencil.farthest();
        let rows = &self.rows[..];
        // the Hermite weights of node k0 and k0 + 1 per lane of a row vector ([value, value, slope, slope]),
        // for the lower and the upper row in memory: reversed on a ghost η̂ node (index 1)
        let ends = [[hw[0], hw[0], hw[1], hw[1]], [hw[2], hw[2], hw[3], hw[3]]];
        let hermite = [ends, [ends[1], ends[0]]];
        let mut converged = true;
        for i in 0..4 {
            if prefetch && i < 3 {
                self.prefetch_node(window, off, i as isize + 1);
            }
            let gi = cx.start + i as isize;
            let (ii, fx) = (gi.unsigned_abs(), gi < 0);
            // the η̂ window points of this ξ̂ node: first rows and Hermite weights
            let mut bases = [0; 4];
            let mut hs = [Hermite {
                ends: &hermite[0],
                signs: &SIGN_LANES[0],
            }; 4];
            for j in 0..4 {
                let gj = cy.start + j as isize;
                let (jj, fy) = (gj.unsigned_abs(), gj < 0);
                bases[j] = ii * st[XI] + jj * st[ETA] + window.lower(fy);
                hs[j] = Hermite {
                    ends: &hermite[usize::from(fy)],
                    signs: &SIGN_LANES[2 * usize::from(fx) + usize::from(fy)],
                };
            }
            if !JAC {
                let v = window_sums::<K>(rows, &bases, off, max_off, wl, &hs);
                for (c1j, v) in c1.iter_mut().zip(v) {
                    c1j[i * OUTPUTS..(i + 1) * OUTPUTS].copy_from_slice(&v);
                }
            }
            for (j, c1j) in c1.iter_mut().enumerate() {
                let fy = cy.start + (j as isize) < 0;
                let (base, h) = (bases[j], hs[j]);
                if JAC {
                    let mut pair = [0.0; 2 * ROW];
                    let v = corner_sum::<K, true>(rows, base, off, max_off, wl, h, &mut pair);
                    c1j[i * OUTPUTS..(i + 1) * OUTPUTS].copy_from_slice(&v);
                    let (sv, sd) = signs(fx, fy);
                    // the corner sums at the lower and the upper φ̂ node in memory; a0 at k0, a1 at k0 + 1
                    let (lo, hi) = pair.split_at(ROW);
                    let (a0, a1) = if fy { (hi, lo) } else { (lo, hi) };
                    // the corner sums with the weights' derivatives along each linear dimension
                    // instead of the weights, in memory order as `pair` (by the same kernel; its
                    // Hermite stage is not needed here); the rows at k0 and k0 + 1 start at m0, m1
                    let mut dpair = [[0.0; 2 * ROW]; L];
                    for (dp, dlk) in dpair.iter_mut().zip(dl.iter().flatten()) {
                        corner_sum::<K, true>(rows, base, off, max_off, &dlk[..off.len()], h, dp);
                    }
                    let (m0, m1) = if fy { (ROW, 0) } else { (0, ROW) };
                    for o in 0..OUTPUTS {
                        let (y0, d0) = (sv[o] * a0[VAL[o]], sd[o] * a0[SLOPE[o]]);
                        let (y1, d1) = (sv[o] * a1[VAL[o]], sd[o] * a1[SLOPE[o]]);
                        for (k, dp) in dpair.iter().enumerate() {
                            t1[i][j][o][k] = sv[o]
                                * (hw[0] * dp[m0 + VAL[o]] + hw[2] * dp[m1 + VAL[o]])
                                + sd[o] * (hw[1] * dp[m0 + SLOPE[o]] + hw[3] * dp[m1 + SLOPE[o]]);
                        }
                        t1[i][j][o][L] = hdw[0] * y0 + hdw[1] * d0 + hdw[2] * y1 + hdw[3] * d1;
                    }
                }
                if check_converged {
                    // the nodes the value depends on (corners of non-zero weight), as in both paths
                    converged &= off.iter().zip(wl).all(|(o, w)| {
                        *w == 0.0
                            || (self.converged[base + o] == 1 && self.converged[base + o + 1] == 1)
                    });
                }
            }
        }
        converged
    }

    /// Prefetches the corner rows (`off` from each window point's first row) of ξ̂ window node `i` of
    /// `window`, all η̂ and both φ̂ ends, while the node before it is computed (`phi_stage`): on a table far
    /// larger than the caches the loads then find their lines on the way.
    #[inline(always)]
    fn prefetch_node(&self, window: &Window, off: &[usize], i: isize) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            let st = &self.strides;
            let p0 = self.rows.as_ptr().cast::<i8>();
            let ii = (window.cx.start + i).unsigned_abs();
            for j in 0..4 {
                let gj = window.cy.start + j as isize;
                let base = ii * st[XI] + gj.unsigned_abs() * st[ETA] + window.lower(gj < 0);
                for o in off {
                    let ptr = p0.wrapping_add((base + *o) * std::mem::size_of::<Row>());
                    // SAFETY: a prefetch is only a hint: it never faults and changes no memory
                    // (the addresses are those of the corner's two rows in any case).
                    unsafe {
                        for line in [0, 2 * std::mem::size_of::<Row>() - 1] {
                            _mm_prefetch::<_MM_HINT_T0>(ptr.wrapping_add(line));
                        }
                    }
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (window, off, i);
    }
}

/// The derivatives of one ξ̂ window node's φ̂-stage values (`Table::core`): [j][o][F_N, V, w, a/b, p_ref, φ].
type PhiDerivatives = [[[f64; LINEAR_DIMS + 1]; OUTPUTS]; 4];

/// The derivatives of the η̂-stage values (`Table::core`): [i][o][F_N, V, w, a/b, p_ref, φ, η].
type EtaDerivatives = [[[f64; LINEAR_DIMS + 2]; OUTPUTS]; 4];

/// Where a lookup lies (`Table::core`): the cubic windows along ξ̂ (`cx`) and η̂ (`cy`), the φ̂ interval's
/// lower node `k0` and its Hermite weights `hw` and their derivatives `hdw`, the fractions and row strides
/// of the linear dimensions (F_N, V, w, a/b, p_ref), the number of φ̂ nodes, the flags of the cell and
/// whether the lookup prefetches the rows of the next ξ̂ node.
#[derive(Clone, Copy)]
struct Window {
    cx: CubicStencil,
    cy: CubicStencil,
    k0: isize,
    hw: [f64; 4],
    hdw: [f64; 4],
    fractions: [Fraction; LINEAR_DIMS],
    linear_strides: [usize; LINEAR_DIMS],
    n_phi: isize,
    flags: u8,
    prefetch: bool,
}

impl Window {
    /// The lower φ̂ node of the interval at a window point: k0, or on a ghost η̂ node (`fy`: φ̂ reversed)
    /// the mirror image of k0 + 1, n_φ − 2 − k0, so that the φ̂ ends run backwards.
    #[inline(always)]
    fn lower(&self, fy: bool) -> usize {
        (if fy {
            self.n_phi - 2 - self.k0
        } else {
            self.k0
        }) as usize
    }
}

/// Stage 2 of `Table::core`: the splines along η̂ of the φ̂-stage values `c1` (and their derivatives `t1`
/// with the Jacobian), all 4·OUTPUTS fibres at once, into the values per ξ̂ node and output `c2` and their
/// derivatives `t2` (F_N, V, w, a/b, p_ref, φ, η).
#[inline(always)]
fn eta_stage<const JAC: bool>(
    cy: &CubicStencil,
    c1: &[[f64; 4 * OUTPUTS]; 4],
    t1: &[PhiDerivatives],
    c2: &mut [[f64; OUTPUTS]; 4],
    t2: &mut EtaDerivatives,
) {
    const L: usize = LINEAR_DIMS;
    if JAC {
        for i in 0..4 {
            for o in 0..OUTPUTS {
                let f = cy.eval(&std::array::from_fn(|j| c1[j][i * OUTPUTS + o]));
                c2[i][o] = f.v;
                for a in 0..=L {
                    t2[i][o][a] = (0..4).map(|j| f.w[j] * t1[i][j][o][a]).sum();
                }
                t2[i][o][L + 1] = f.dv;
            }
        }
    } else {
        let flat = cy.value(c1);
        for (i, c) in c2.iter_mut().enumerate() {
            c.copy_from_slice(&flat[i * OUTPUTS..(i + 1) * OUTPUTS]);
        }
    }
}

/// Stage 3 of `Table::core`: the splines along ξ̂ of the η̂-stage values `c2` (and their derivatives `t2`
/// with the Jacobian), into the outputs `v` and their derivatives by the coordinates `d`.
#[inline(always)]
fn xi_stage<const JAC: bool>(
    cx: &CubicStencil,
    c2: &[[f64; OUTPUTS]; 4],
    t2: &EtaDerivatives,
    v: &mut [f64; OUTPUTS],
    d: &mut [[f64; DIMS]; OUTPUTS],
) {
    const L: usize = LINEAR_DIMS;
    if JAC {
        for o in 0..OUTPUTS {
            let f = cx.eval(&std::array::from_fn(|i| c2[i][o]));
            v[o] = f.v;
            let t: [f64; L + 2] =
                std::array::from_fn(|a| (0..4).map(|i| f.w[i] * t2[i][o][a]).sum());
            d[o][XI] = f.dv;
            d[o][ETA] = t[L + 1];
            d[o][PHI] = t[L];
            d[o][FORCE..].copy_from_slice(&t[..L]);
        }
    } else {
        *v = cx.value(c2);
    }
}

/// The one-sided slopes of a cubic stage next to unresolved cells (`core`): in the window values `values`
/// and in every window of their derivatives `derivatives`, the node beyond the interval on each side whose
/// flag in `bits` (below, above) is set in the cell's `flags` becomes the extrapolation of the interval.
#[cold]
#[inline(never)]
pub(super) fn one_sided<V: Lanes, D: Lanes>(
    window: &CubicStencil,
    bits: [u8; 2],
    flags: u8,
    values: &mut [V; 4],
    derivatives: &mut [[D; 4]],
) {
    for (bit, upper) in bits.into_iter().zip([false, true]) {
        if let Some(node) = window.beyond(upper).filter(|_| flags & bit != 0) {
            extrapolate(values, node);
            for d in derivatives.iter_mut() {
                extrapolate(d, node);
            }
        }
    }
}

/// Window values of a cubic stage (per window node: a flat array of lanes, or per lane its derivatives).
pub(super) trait Lanes: Copy {
    fn lanes(&self) -> &[f64];
    fn lanes_mut(&mut self) -> &mut [f64];
}

impl<const N: usize> Lanes for [f64; N] {
    fn lanes(&self) -> &[f64] {
        self
    }
    fn lanes_mut(&mut self) -> &mut [f64] {
        self
    }
}

impl<const N: usize, const M: usize> Lanes for [[f64; N]; M] {
    fn lanes(&self) -> &[f64] {
        self.as_flattened()
    }
    fn lanes_mut(&mut self) -> &mut [f64] {
        self.as_flattened_mut()
    }
}

/// The window node `beyond` of [`interp::CubicStencil::beyond`], (beyond, near, far, r), set to the linear
/// extrapolation of the window's interval, y_beyond = (1 + r)·y_near − r·y_far, in every lane.
#[inline(always)]
pub(super) fn extrapolate<T: Lanes>(
    window: &mut [T; 4],
    (beyond, near, far, r): (usize, usize, usize, f64),
) {
    let (n, f) = (window[near], window[far]);
    for ((y, n), f) in window[beyond]
        .lanes_mut()
        .iter_mut()
        .zip(n.lanes())
        .zip(f.lanes())
    {
        *y = (1.0 + r) * n - r * f;
    }
}

/// The symmetry signs of a window point on a ghost ξ̂ node (`fx`) or a ghost η̂ node (`fy`), of the values
/// and of the φ̂ slopes per output: the ξ mirror flips F_x, the η mirror flips F_y and M_z and reverses φ̂
/// (the slopes flip once more).
#[inline(always)]
pub(super) const fn signs(fx: bool, fy: bool) -> ([f64; OUTPUTS], [f64; OUTPUTS]) {
    let sx = if fx { -1.0 } else { 1.0 };
    let sy = if fy { -1.0 } else { 1.0 };
    ([sx, sy, sy, 1.0, 1.0, 1.0], [sx * sy, 1.0, 1.0, sy, sy, sy])
}

/// [`signs`] per kind of window point (2·[ghost ξ̂ node] + [ghost η̂ node]) in the row layout: per 4-wide
/// vector k of a row, the signs of the values of outputs 2k, 2k + 1 and of their slopes.
pub(super) const SIGN_LANES: [[[f64; 4]; 3]; 4] = {
    let mut lanes = [[[0.0; 4]; 3]; 4];
    let mut g = 0;
    while g < 4 {
        let (sv, sd) = signs(g >> 1 == 1, g & 1 == 1);
        let mut k = 0;
        while k < 3 {
            lanes[g][k] = [sv[2 * k], sv[2 * k + 1], sd[2 * k], sd[2 * k + 1]];
            k += 1;
        }
        g += 1;
    }
    lanes
};
