//! Tests of the table files: storages, codes, sidecars, shards.

use super::*;

/// The bytes [`array_bytes`] counts are those of the `.npy` files [`TableFiles::write`] writes: six
/// outputs of f32 or u16 codes and two u8 flag arrays in the axes' shape; none for compressed storages.
#[test]
fn array_bytes_are_those_of_the_written_npy_files() {
    let spec: crate::table::AxesSpec =
        toml::from_str(include_str!("../../../tests/fixtures/small-axes.toml")).unwrap();
    let axes = Axes::from_spec(&spec).unwrap();
    let shape = axes.shape();
    let n = axes.len();
    let flags = 2 * npy_bytes(&vec![0u8; n], &shape).len() as u64;
    let f32s = npy_bytes(&vec![0f32; n], &shape).len() as u64;
    let u16s = npy_bytes(&vec![0u16; n], &shape).len() as u64;
    assert_eq!(array_bytes(&axes, Storage::F32), Some(6 * f32s + flags));
    assert_eq!(array_bytes(&axes, Storage::U16), Some(6 * u16s + flags));
    assert_eq!(array_bytes(&axes, Storage::U16x), None);
    assert_eq!(OUTPUTS, 6);
}

#[test]
fn iso8601_matches_known_dates() {
    assert_eq!(iso8601(0), "1970-01-01T00:00:00Z");
    assert_eq!(
        iso8601(951_782_400),
        ["2000", "02", "29T00:00:00Z"].join("-")
    );
    assert_eq!(
        iso8601(1_700_000_000),
        ["2023", "11", "14T22:13:20Z"].join("-")
    );
    assert_eq!(iso8601(4_107_542_399), "2100-02-28T23:59:59Z");
}

#[test]
fn sha256_of_known_input() {
    // FIPS 180-2 example
    assert_eq!(
        sha256_hex(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
}

#[test]
fn canonical_json_sorts_keys_at_every_level() {
    let v: serde_json::Value =
        serde_json::from_str(r#"{"b": {"z": 1, "a": [2, {"y": 0.1, "x": null}]}, "a": true}"#)
            .unwrap();
    let mut s = String::new();
    canonical_json(&v, &mut s);
    assert_eq!(s, r#"{"a":true,"b":{"a":[2,{"x":null,"y":0.1}],"z":1}}"#);
}

#[test]
fn fingerprint_follows_every_parameter() {
    let p = Params::default();
    let f0 = fingerprint(&p);
    assert_eq!(f0.len(), 64);
    assert_eq!(f0, fingerprint(&p.clone()));
    let mut q = p.clone();
    q.roughness.k_r = 0.5000000001;
    assert_ne!(fingerprint(&q), f0);
    let mut q = p.clone();
    q.grid.nx = 31;
    assert_ne!(fingerprint(&q), f0);
    let mut q = p;
    q.solver.heat = false;
    assert_ne!(fingerprint(&q), f0);
}

/// The interfacial layer is part of the fingerprint when set (thickness or G₃), and absent from it when
/// not, so that a table built without a layer keeps its fingerprint and serves no parameters with one.
#[test]
fn fingerprint_follows_the_layer_only_when_set() {
    let p = Params::default();
    let json = serde_json::to_string(&p).unwrap();
    assert!(!json.contains("layer"), "{json}");
    let mut q = p.clone();
    q.layer.thickness = 1e-4;
    assert_ne!(fingerprint(&q), fingerprint(&p));
    let mut r = p.clone();
    r.layer.shear_modulus = 5e9;
    assert_ne!(fingerprint(&r), fingerprint(&p));
    assert_ne!(fingerprint(&r), fingerprint(&q));
}

#[test]
fn parameters_round_trip_through_the_sidecar_json_bit_for_bit() {
    // the fingerprint of the parameters read back must equal the recorded one: every f64 must survive
    // JSON exactly, also with 17 significant digits
    let mut p = Params::default();
    p.roughness.k_r = 1.0 / 3.0;
    p.fluid.h_bl = 0.1e-6 * (1.0 + f64::EPSILON);
    p.material.conductivity = 0.1 + 0.2;
    p.fluid.flow_resistance = 1.2345678901234567e-3;
    let text = serde_json::to_string(&p).unwrap();
    let back: Params = serde_json::from_str(&text).unwrap();
    assert_eq!(back, p);
    assert_eq!(fingerprint(&back), fingerprint(&p));
}

#[test]
fn quantisation_codes_span_the_range_and_round_to_the_nearest_code() {
    let values: Vec<f32> = (0..1000)
        .map(|i| (f64::from(i) * 0.37).sin() as f32 * 0.6 + 300.0)
        .collect();
    let (q, codes) = Quantization::of(&values, 0.0).unwrap();
    assert_eq!(*codes.iter().min().unwrap(), 0);
    assert_eq!(*codes.iter().max().unwrap(), u16::MAX);
    for (v, c) in values.iter().zip(&codes) {
        let back = f64::from(q.value(*c));
        // half a step, plus the f32 rounding of a value near 300
        assert!(
            (back - f64::from(*v)).abs() <= 0.5 * q.step + 3e-5,
            "{v} {back}"
        );
    }
    // a constant array: step 0, every code 0, the value itself
    let (q, codes) = Quantization::of(&[0.25; 7], 0.0).unwrap();
    assert_eq!((q.offset, q.step), (0.25, 0.0));
    assert!(codes.iter().all(|c| *c == 0) && q.value(0) == 0.25);
    assert!(Quantization::of(&[1.0, f32::NAN], 0.0).is_err());
    assert!(Quantization::of(&[f32::INFINITY], 1e-3).is_err());
}

#[test]
fn a_coarsest_step_rounds_to_its_multiples_and_keeps_zero_exact() {
    // an odd function sampled symmetrically, as F_y over (η, φ) -> (-η, -φ), with exact zeros
    let values: Vec<f32> = (-500..=500)
        .map(|i| (f64::from(i) * 0.0123).sin() as f32 * 0.37)
        .collect();
    let (q, codes) = Quantization::of(&values, 1e-3).unwrap();
    assert_eq!(q.step, 1e-3);
    // the offset a whole multiple of the step: codes of one array are multiples of the step
    assert_eq!((q.offset / q.step).round() * q.step, q.offset);
    let back: Vec<f32> = codes.iter().map(|c| q.value(*c)).collect();
    for (v, b) in values.iter().zip(&back) {
        assert!(
            (f64::from(*v) - f64::from(*b)).abs() <= 0.5e-3 + 1e-8,
            "{v} {b}"
        );
    }
    assert_eq!(back[500], 0.0);
    // symmetric values keep their symmetry
    for i in 0..500 {
        assert_eq!(back[i], -back[1000 - i], "{i}");
    }
    // fewer distinct codes than the finest quantisation uses
    let fine = Quantization::of(&values, 0.0).unwrap();
    assert!(fine.0.step < 1.2e-5 && fine.1.iter().max() == Some(&u16::MAX));
    assert!(*codes.iter().max().unwrap() <= 741);
    // a step finer than range/65 535 changes nothing; a constant array stays exact
    assert_eq!(Quantization::of(&values, 1e-6).unwrap(), fine);
    let (c, _) = Quantization::of(&[0.3; 4], 1e-3).unwrap();
    assert_eq!((c.offset, c.step), (f64::from(0.3f32), 0.0));
    // a range just below 65 535 steps, its offset snapped down, would need code 65 536: not snapped
    let wide = [0.00099f32, 65.53589];
    let (w, wc) = Quantization::of(&wide, 1e-3).unwrap();
    assert_eq!((w.offset, w.step), (f64::from(0.00099f32), 1e-3));
    assert_eq!(wc, [0, 65535]);
}

#[test]
fn resolutions_parse_display_and_refuse_bad_steps() {
    let r = Resolution::parse("1e-4, 0.1").unwrap();
    assert_eq!((r.per_normal_force, r.temperature), (1e-4, 0.1));
    assert_eq!(Resolution::parse(&r.to_string()).unwrap(), r);
    assert_eq!(r.of(&OUTPUT_INFO[3]), 0.1);
    assert!(OUTPUT_INFO.iter().filter(|o| r.of(o) == 1e-4).count() == OUTPUTS - 1);
    for bad in ["1e-4", "0,0.1", "1e-4,-1", "nan,0.1", "1e-4,inf", "a,b", ""] {
        let e = Resolution::parse(bad).unwrap_err();
        assert!(e.contains("F,T"), "{bad}: {e}");
    }
}

#[test]
fn compressed_codes_decompress_to_the_same_codes_and_corrupt_streams_are_refused() {
    // eight dimensions with single-node axes, smooth codes along φ̂ and V and jumps across the whole
    // code range (differences that wrap modulo 2¹⁶)
    let shape = [3, 2, 5, 1, 4, 3, 1, 2];
    let n: usize = shape.iter().product();
    let mut rng = crate::table::verify::SplitMix64::new(3);
    let codes: Vec<u16> = (0..n)
        .map(|i| match i % 7 {
            0 => 0,
            1 => u16::MAX,
            _ => (30_000.0 + 20_000.0 * (i as f64 * 0.01).sin() + 100.0 * rng.uniform()) as u16,
        })
        .collect();
    let ramp: Vec<u16> = (0..n)
        .map(|i| {
            let (phi, v) = ((i / 24) % 5, (i / 6) % 4);
            (1000 * phi + 300 * v + i / 120) as u16
        })
        .collect();
    for codec in [Codec::Zlib, Codec::Xz] {
        let bytes = compress_codes(&codes, &shape, codec);
        assert_eq!(decompress_codes(&bytes, &shape, codec).unwrap(), codes);
        // the prediction is what makes smooth codes small: a ramp along φ̂ and V compresses to a few
        // bytes (xz's container adds some 60)
        let small = compress_codes(&ramp, &shape, codec);
        assert_eq!(decompress_codes(&small, &shape, codec).unwrap(), ramp);
        let container = if codec == Codec::Xz { 60 } else { 0 };
        assert!(
            small.len() < n / 4 + container,
            "{codec:?}: {} bytes for {n} codes",
            small.len()
        );
        // another shape, a cut stream, a longer one, the other codec's stream, not a stream at all
        let e = decompress_codes(&bytes, &[3, 2, 5, 1, 4, 3, 1, 3], codec).unwrap_err();
        assert!(e.contains("expected"), "{e}");
        let e = decompress_codes(&bytes, &[3, 2, 5, 1, 4, 3, 1, 1], codec).unwrap_err();
        assert!(e.contains("or more"), "{e}");
        assert!(decompress_codes(&bytes[..bytes.len() / 2], &shape, codec).is_err());
        let other = if codec == Codec::Zlib {
            Codec::Xz
        } else {
            Codec::Zlib
        };
        let e = decompress_codes(&bytes, &shape, other).unwrap_err();
        assert!(e.contains(other.name()), "{e}");
        let e = decompress_codes(b"not a compressed stream", &shape, codec).unwrap_err();
        assert!(e.contains(codec.name()), "{e}");
    }
    // xz compresses the smooth part of a table's codes further than zlib
    let smooth: Vec<u16> = (0..4096 * 6)
        .map(|i| (30_000.0 + 20_000.0 * (i as f64 * 0.001).sin() + 30.0 * rng.uniform()) as u16)
        .collect();
    let long = [4096, 1, 6, 1, 1, 1, 1, 1];
    let (z, x) = (
        compress_codes(&smooth, &long, Codec::Zlib),
        compress_codes(&smooth, &long, Codec::Xz),
    );
    assert!(x.len() < z.len(), "xz {} bytes, zlib {}", x.len(), z.len());
}

#[test]
fn shards_partition_the_points_into_whole_creepage_cubes() {
    use crate::table::{AxesSpec, AxisSpec};
    let pts = |p: &[f64], raw_limit: Option<f64>| {
        Some(AxisSpec {
            points: Some(p.to_vec()),
            raw_limit,
            ..Default::default()
        })
    };
    let axes = Axes::from_spec(&AxesSpec {
        creepage_x: pts(&[0.0, 0.5, 2.0, 10.0], Some(0.1)),
        creepage_y: pts(&[0.0, 0.3, 1.0, 5.0], Some(0.02)),
        spin: pts(&[-1.0, -0.1, 0.1, 1.0], Some(1.0)),
        normal_force: pts(&[50e3, 100e3], None),
        speed: pts(&[10.0, 30.0], None),
        wetness: pts(&[0.0, 1.0], None),
        semi_axis_ratio: pts(&[0.5, 2.0], None),
        reference_pressure: pts(&[0.8e9], None),
    })
    .unwrap();
    let cubes = cube_count(&axes);
    assert_eq!(cubes, 16);
    assert_eq!(cubes * cube_len(&axes), axes.len());
    for count in [1, 2, 5, 7, cubes, cubes + 3] {
        let mut seen = vec![0; axes.len()];
        for index in 1..=count {
            let s = ShardRecord { index, count };
            let idx = shard_indices(&axes, s);
            assert_eq!(idx.len(), shard_len(&axes, s));
            assert!(idx.windows(2).all(|w| w[0] < w[1]));
            for i in &idx {
                seen[*i] += 1;
                // the whole creepage cube of every point is in the shard
                assert!((0..cube_len(&axes)).all(|c| idx.contains(&(c * cubes + i % cubes))));
            }
        }
        assert!(seen.iter().all(|n| *n == 1), "count {count}");
    }
}
