//! Gauss–Legendre quadrature rules (Golub & Welsch 1969; nodes by Newton iteration on P_n, Abramowitz &
//! Stegun 25.4.29) used by the Greenwood–Williamson integrals.

/// An n-point Gauss–Legendre rule on [−1, 1]: exact for polynomials of degree ≤ 2n − 1.
#[derive(Debug, Clone)]
pub struct GaussLegendre {
    /// Nodes x_i ∈ (−1, 1), ascending.
    pub nodes: Vec<f64>,
    /// Weights w_i > 0, Σ w_i = 2.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// Builds the n-point rule (n ≥ 1). Each node is the root of the Legendre polynomial P_n found by
    /// Newton's method from Tricomi's estimate cos(π(i − ¼)/(n + ½)); weights w_i = 2/((1 − x_i²)·P_n'(x_i)²).
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for i in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre_with_derivative(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    let (_, d) = legendre_with_derivative(n, x);
                    dp = d;
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        Self { nodes, weights }
    }
}

/// Legendre polynomial P_n(x) and its derivative by the three-term recurrence.
fn legendre_with_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly_up_to_degree_2n_minus_1() {
        for n in [1, 2, 5, 8, 13, 24] {
            let r = GaussLegendre::new(n);
            for deg in 0..2 * n {
                let q: f64 = r
                    .nodes
                    .iter()
                    .zip(&r.weights)
                    .map(|(x, w)| w * x.powi(deg as i32))
                    .sum();
                let exact = if deg % 2 == 1 {
                    0.0
                } else {
                    2.0 / (deg as f64 + 1.0)
                };
                assert!((q - exact).abs() < 1e-14, "n={n} deg={deg}: {q} vs {exact}");
            }
        }
    }

    #[test]
    fn known_three_point_rule() {
        let r = GaussLegendre::new(3);
        assert!((r.nodes[2] - (0.6f64).sqrt()).abs() < 1e-15);
        assert!((r.weights[1] - 8.0 / 9.0).abs() < 1e-15);
        assert!((r.weights[0] - 5.0 / 9.0).abs() < 1e-15);
    }
}
