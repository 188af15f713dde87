//! Microcontact by direct quadrature (GW + Zhao–Maietta–Chang, MODEL.md §4): accurate but slow; to be
//! replaced by the fast tabulated evaluation.
use crate::error::{Error, Result};
use crate::materials::MaterialState;
use crate::params::Roughness;
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    pub z_s: f64,
    pub r_a: f64,
    pub eta_s: f64,
}
impl Surface {
    pub fn from_roughness(r: &Roughness) -> Self {
        Self {
            z_s: r.z_s(),
            r_a: r.r_a(),
            eta_s: r.eta_s(),
        }
    }
}
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicroState {
    pub separation: f64,
    pub area_fraction: f64,
    pub load: f64,
    pub d_load_d_separation: f64,
}
pub struct SeparationSolve {
    pub state: MicroState,
    pub iterations: usize,
    pub residual: f64,
    pub converged: bool,
}
pub struct Microcontact {
    s: Surface,
    gl: Vec<(f64, f64)>,
}

pub fn asperity_contact(w: f64, r: f64, es: f64, h: f64, nu: f64) -> (f64, f64) {
    if w <= 0.0 {
        return (0.0, 0.0);
    }
    let k = 0.454 + 0.41 * nu;
    let wc = (PI * k * h / (2.0 * es)).powi(2) * r;
    let wp = 54.0 * wc;
    if w <= wc {
        (PI * r * w, 4.0 / 3.0 * es * r.sqrt() * w.powf(1.5))
    } else if w < wp {
        let t = (w - wc) / (wp - wc);
        let a = PI * r * w * (1.0 - 2.0 * t * t * t + 3.0 * t * t);
        (
            a,
            a * (h - h * (1.0 - 2.0 * k / 3.0) * (wp.ln() - w.ln()) / (wp.ln() - wc.ln())),
        )
    } else {
        (2.0 * PI * r * w, 2.0 * PI * r * w * h)
    }
}

impl Microcontact {
    pub fn new(r: &Roughness) -> Result<Self> {
        // 16-point Gauss-Legendre via Golub-Welsch-free Newton
        let n = 16;
        let mut gl = vec![];
        for i in 1..=n {
            let mut x = (PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            gl.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
        }
        Ok(Self {
            s: Surface::from_roughness(r),
            gl,
        })
    }
    pub fn surface(&self) -> &Surface {
        &self.s
    }
    fn integrate(&self, d: f64, m: &MaterialState) -> (f64, f64) {
        let zs = self.s.z_s;
        let r = self.s.r_a;
        let k = 0.454 + 0.41 * m.poisson;
        let wc = (PI * k * m.hardness / (2.0 * m.e_star)).powi(2) * r;
        let top = d.max(-9.0 * zs) + 0.0;
        let end = 9.0 * zs;
        if d >= end {
            return (0.0, 0.0);
        }
        let mut br = vec![d, d + wc, d + 54.0 * wc, end];
        br.retain(|x| *x <= end);
        br.push(end);
        br.sort_by(|a, b| a.total_cmp(b));
        br.dedup();
        let _ = top;
        let (mut aa, mut pp) = (0.0, 0.0);
        for w in br.windows(2) {
            let (a, b) = (w[0], w[1]);
            if b <= a {
                continue;
            }
            let panels = 12;
            let hpan = (b - a) / panels as f64;
            for p in 0..panels {
                let (lo, hi) = (a + p as f64 * hpan, a + (p + 1) as f64 * hpan);
                for (x, wt) in &self.gl {
                    let z = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
                    let phi = (-0.5 * (z / zs).powi(2)).exp() / ((2.0 * PI).sqrt() * zs);
                    let (ar, pr) = asperity_contact(z - d, r, m.e_star, m.hardness, m.poisson);
                    aa += 0.5 * (hi - lo) * wt * ar * phi;
                    pp += 0.5 * (hi - lo) * wt * pr * phi;
                }
            }
        }
        (self.s.eta_s * aa, self.s.eta_s * pp)
    }
    pub fn evaluate(&self, d: f64, m: &MaterialState) -> MicroState {
        let (a, p) = self.integrate(d, m);
        let e = 1e-6 * self.s.z_s;
        let dl = (self.integrate(d + e, m).1 - self.integrate(d - e, m).1) / (2.0 * e);
        MicroState {
            separation: d,
            area_fraction: a,
            load: p,
            d_load_d_separation: dl,
        }
    }
    pub fn separation_for_load(&self, load: f64, m: &MaterialState) -> Result<SeparationSolve> {
        let zs = self.s.z_s;
        let (mut lo, mut hi) = (-8.5 * zs, 8.5 * zs);
        if self.integrate(lo, m).1 < load {
            return Err(Error::Numerical {
                stage: "microcontact",
                reason: "load too high".into(),
            });
        }
        let mut it = 0;
        while hi - lo > 1e-13 * zs && it < 200 {
            it += 1;
            let mid = 0.5 * (lo + hi);
            if self.integrate(mid, m).1 > load {
                lo = mid
            } else {
                hi = mid
            }
        }
        let st = self.evaluate(0.5 * (lo + hi), m);
        Ok(SeparationSolve {
            residual: (st.load - load).abs() / load.max(1.0),
            state: st,
            iterations: it,
            converged: true,
        })
    }
}
