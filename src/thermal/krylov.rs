//! Restarted GMRES with right preconditioning (Saad & Schultz 1986; Saad, "Iterative Methods for Sparse
//! Linear Systems", 2nd ed. 2003, Alg. 9.5 in its flexible form 9.6): solves A·x = b for a matrix given only
//! as a product, here the heat partition's G_w + G_r applied as a convolution.

/// Outcome of an iterative linear solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrylovReport {
    /// Matrix–vector products spent in Arnoldi steps.
    pub iterations: usize,
    /// Final relative residual ‖b − A·x‖₂/‖b‖₂, recomputed from x (0 for b = 0).
    pub residual: f64,
    /// True if the residual reached the tolerance within the iteration budget.
    pub converged: bool,
}

/// Iteration limits of [`gmres`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GmresSettings {
    /// Relative residual ‖b − A·x‖₂/‖b‖₂ to reach.
    pub tolerance: f64,
    /// Krylov dimension before a restart.
    pub restart: usize,
    /// Largest total number of Arnoldi steps.
    pub max_iterations: usize,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Solves A·x = b from the initial guess in `x` with right preconditioner M (A·M⁻¹·u = b, x = M⁻¹·u):
/// `apply(v, out)` sets out = A·v, `precondition(v)` replaces v by M⁻¹·v. Returns the report and the final
/// residual vector r = b − A·x, recomputed from x (so the reported residual is the true one, not the
/// Arnoldi estimate). Modified Gram–Schmidt orthogonalisation, Givens rotations for the least-squares
/// problem; the preconditioned directions z_k = M⁻¹·v_k are kept, which saves one preconditioner
/// application per restart cycle.
pub fn gmres(
    mut apply: impl FnMut(&[f64], &mut [f64]),
    mut precondition: impl FnMut(&mut [f64]),
    b: &[f64],
    x: &mut [f64],
    settings: GmresSettings,
) -> (KrylovReport, Vec<f64>) {
    let n = b.len();
    let b_norm = norm(b);
    let mut report = KrylovReport {
        iterations: 0,
        residual: 0.0,
        converged: true,
    };
    let mut residual = vec![0.0; n];
    if b_norm == 0.0 {
        x.fill(0.0);
        return (report, residual);
    }
    let m = settings.restart.max(1);
    let target = settings.tolerance * b_norm;
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(m + 1);
    let mut directions: Vec<Vec<f64>> = Vec::with_capacity(m);
    // Hessenberg columns (after rotation) h[k][0..=k], rotations (c, s), right-hand side g
    let mut hessenberg: Vec<Vec<f64>> = Vec::with_capacity(m);
    let mut rotations: Vec<(f64, f64)> = Vec::with_capacity(m);
    let mut g = vec![0.0; m + 1];
    let mut w = vec![0.0; n];
    loop {
        apply(x, &mut w);
        for ((r, bi), wi) in residual.iter_mut().zip(b).zip(&w) {
            *r = bi - wi;
        }
        let beta = norm(&residual);
        report.residual = beta / b_norm;
        report.converged = beta <= target;
        if report.converged || report.iterations >= settings.max_iterations || !beta.is_finite() {
            return (report, residual);
        }
        basis.clear();
        directions.clear();
        hessenberg.clear();
        rotations.clear();
        g.fill(0.0);
        g[0] = beta;
        basis.push(residual.iter().map(|r| r / beta).collect());
        while directions.len() < m && report.iterations < settings.max_iterations {
            let k = directions.len();
            let mut z = basis[k].clone();
            precondition(&mut z);
            apply(&z, &mut w);
            directions.push(z);
            report.iterations += 1;
            let mut h = Vec::with_capacity(k + 2);
            for v in &basis {
                let hik = dot(&w, v);
                for (wi, vi) in w.iter_mut().zip(v) {
                    *wi -= hik * vi;
                }
                h.push(hik);
            }
            let h_next = norm(&w);
            for (i, &(c, s)) in rotations.iter().enumerate() {
                let (a, b) = (h[i], h[i + 1]);
                h[i] = c * a + s * b;
                h[i + 1] = -s * a + c * b;
            }
            let (a, b) = (h[k], h_next);
            let rho = a.hypot(b);
            let (c, s) = if rho == 0.0 {
                (1.0, 0.0)
            } else {
                (a / rho, b / rho)
            };
            h[k] = rho;
            rotations.push((c, s));
            g[k + 1] = -s * g[k];
            g[k] *= c;
            hessenberg.push(h);
            if g[k + 1].abs() <= target || h_next == 0.0 || !h_next.is_finite() {
                break;
            }
            basis.push(w.iter().map(|wi| wi / h_next).collect());
        }
        // y from the triangular system, x += Σ y_k·z_k
        let k = directions.len();
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let tail: f64 = (i + 1..k).map(|j| hessenberg[j][i] * y[j]).sum();
            y[i] = (g[i] - tail) / hessenberg[i][i];
        }
        for (yk, z) in y.iter().zip(&directions) {
            for (xi, zi) in x.iter_mut().zip(z) {
                *xi += yk * zi;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric, diagonally dominant test matrix A[i][j] = (i == j)·4 + 1/(1 + 2i + j).
    fn matrix(n: usize) -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| f64::from(u8::from(i == j)) * 4.0 + 1.0 / (1 + 2 * i + j) as f64)
                    .collect()
            })
            .collect()
    }

    fn product(a: &[Vec<f64>], v: &[f64], out: &mut [f64]) {
        for (o, row) in out.iter_mut().zip(a) {
            *o = dot(row, v);
        }
    }

    #[test]
    fn solves_to_the_tolerance_and_reports_the_true_residual() {
        let n = 40;
        let a = matrix(n);
        let exact: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin() + 1.0).collect();
        let mut b = vec![0.0; n];
        product(&a, &exact, &mut b);
        for restart in [5, 60] {
            let mut x = vec![0.0; n];
            let settings = GmresSettings {
                tolerance: 1e-13,
                restart,
                max_iterations: 200,
            };
            let (report, r) = gmres(|v, o| product(&a, v, o), |_| {}, &b, &mut x, settings);
            assert!(report.converged && report.residual <= 1e-13, "{report:?}");
            assert!(report.iterations > 1);
            let mut ax = vec![0.0; n];
            product(&a, &x, &mut ax);
            let true_residual: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
            assert!((norm(&true_residual) / norm(&b) - report.residual).abs() < 1e-15);
            assert!(
                r.iter()
                    .zip(&true_residual)
                    .all(|(a, b)| (a - b).abs() < 1e-15)
            );
            for (xi, ei) in x.iter().zip(&exact) {
                assert!((xi - ei).abs() < 1e-11, "restart {restart}: {xi} vs {ei}");
            }
        }
    }

    #[test]
    fn an_exact_preconditioner_converges_in_one_step() {
        // M = diag(A) for a diagonal A: one Arnoldi step.
        let n = 30;
        let d: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let b: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let mut x = vec![0.0; n];
        let settings = GmresSettings {
            tolerance: 1e-14,
            restart: 10,
            max_iterations: 10,
        };
        let (report, _) = gmres(
            |v, o| {
                o.iter_mut()
                    .zip(v)
                    .zip(&d)
                    .for_each(|((o, v), d)| *o = d * v)
            },
            |v| v.iter_mut().zip(&d).for_each(|(v, d)| *v /= d),
            &b,
            &mut x,
            settings,
        );
        assert!(report.converged && report.iterations == 1, "{report:?}");
    }

    #[test]
    fn an_exhausted_budget_is_reported_as_unconverged() {
        let n = 40;
        let a = matrix(n);
        let b = vec![1.0; n];
        let mut x = vec![0.0; n];
        let settings = GmresSettings {
            tolerance: 1e-14,
            restart: 3,
            max_iterations: 3,
        };
        let (report, _) = gmres(|v, o| product(&a, v, o), |_| {}, &b, &mut x, settings);
        assert!(!report.converged && report.iterations == 3, "{report:?}");
        assert!(report.residual > 1e-14 && report.residual < 1.0);
    }

    #[test]
    fn a_zero_right_hand_side_gives_zero() {
        let mut x = vec![1.0; 4];
        let settings = GmresSettings {
            tolerance: 1e-12,
            restart: 4,
            max_iterations: 4,
        };
        let (report, r) = gmres(
            |v, o| o.copy_from_slice(v),
            |_| {},
            &[0.0; 4],
            &mut x,
            settings,
        );
        assert!(report.converged && report.iterations == 0 && report.residual == 0.0);
        assert_eq!(x, vec![0.0; 4]);
        assert_eq!(r, vec![0.0; 4]);
    }
}
