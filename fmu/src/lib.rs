//! FMI 2.0 boundary (see issue 4).
