//! Numerical quadrature shared by the submodels: adaptive Gauss–Kronrod (the heat model's moving-source
//! kernel, reference integrals in tests) and Gauss–Legendre rules (the Greenwood–Williamson integrals).

pub mod gauss_kronrod;
pub mod gauss_legendre;
