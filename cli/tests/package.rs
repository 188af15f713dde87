//! The FMU packager (`package-fmu`): binaries of several platforms land under `binaries/<platform>/` with
//! the platform's library name; the single-library form of the existing command line is unchanged; bad
//! libraries are refused with the reason. The libraries here are stand-ins with the right first bytes
//! (no Windows or macOS toolchain is needed).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const DLL: &[u8] = b"MZ\x90\x00 a win64 stand-in";
const SO: &[u8] = b"\x7fELF\x02\x01\x01 a linux64 stand-in";
const DYLIB: &[u8] = b"\xcf\xfa\xed\xfe a darwin64 stand-in";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("package-fmu-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(path: &Path, bytes: &[u8]) -> PathBuf {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, bytes).unwrap();
    path.to_path_buf()
}

fn package(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_package-fmu"))
        .args(args)
        .output()
        .unwrap()
}

/// Every file of the archive with its bytes.
fn contents(fmu: &Path) -> Vec<(String, Vec<u8>)> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    (0..zip.len())
        .map(|i| {
            let mut f = zip.by_index(i).unwrap();
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes).unwrap();
            (f.name().unwrap().to_string(), bytes)
        })
        .collect()
}

fn binaries(fmu: &Path) -> Vec<(String, Vec<u8>)> {
    contents(fmu)
        .into_iter()
        .filter(|(name, _)| name.starts_with("binaries/"))
        .collect()
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn binaries_of_several_platforms_land_under_their_platform_directories() {
    let dir = scratch("multi");
    let so = write(&dir.join("libWheelRailFriction.so"), SO);
    let dll = write(&dir.join("WheelRailFriction.dll"), DLL);
    let dylib = write(&dir.join("libWheelRailFriction.dylib"), DYLIB);
    let fmu = dir.join("multi.fmu");
    let out = package(&[
        "--library",
        &format!("linux64={}", path(&so)),
        "--library",
        &format!("win64={}", path(&dll)),
        "--library",
        &format!("darwin64={}", path(&dylib)),
        "--out",
        path(&fmu),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("binaries: linux64, win64, darwin64"));
    let mut got = binaries(&fmu);
    got.sort();
    assert_eq!(
        got,
        [
            (
                "binaries/darwin64/WheelRailFriction.dylib".into(),
                DYLIB.to_vec()
            ),
            ("binaries/linux64/WheelRailFriction.so".into(), SO.to_vec()),
            ("binaries/win64/WheelRailFriction.dll".into(), DLL.to_vec()),
        ]
    );
    let all = contents(&fmu);
    let xml = &all
        .iter()
        .find(|(n, _)| n == "modelDescription.xml")
        .unwrap()
        .1;
    let committed = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../modelDescription/modelDescription.xml"),
    )
    .unwrap();
    assert_eq!(xml, &committed);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_single_library_form_packs_linux64_as_before_and_a_directory_packs_each_platform() {
    let dir = scratch("single");
    let so = write(&dir.join("build/libWheelRailFriction.so"), SO);
    let fmu = dir.join("single.fmu");
    // `--library PATH` is the library of the platform the packager runs on
    if cfg!(all(target_os = "linux", target_pointer_width = "64")) {
        let out = package(&["--library", path(&so), "--out", path(&fmu)]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(
            binaries(&fmu),
            [("binaries/linux64/WheelRailFriction.so".into(), SO.to_vec())]
        );
    }
    // binaries built on each OS, collected as binaries/<platform>/ (as in an unpacked FMU)
    let collected = dir.join("collected");
    write(&collected.join("binaries/win64/WheelRailFriction.dll"), DLL);
    write(
        &collected.join("binaries/win64/WheelRailFriction.pdb"),
        b"debug info",
    );
    write(
        &collected.join("binaries/linux64/libWheelRailFriction.so"),
        SO,
    );
    let out = package(&["--binaries", path(&collected), "--out", path(&fmu)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut got = binaries(&fmu);
    got.sort();
    assert_eq!(
        got,
        [
            ("binaries/linux64/WheelRailFriction.so".into(), SO.to_vec()),
            ("binaries/win64/WheelRailFriction.dll".into(), DLL.to_vec()),
        ]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_libraries_and_platforms_are_refused_with_the_reason() {
    let dir = scratch("bad");
    let so = write(&dir.join("libWheelRailFriction.so"), SO);
    let fake_dll = write(&dir.join("WheelRailFriction.dll"), SO);
    let fmu = dir.join("bad.fmu");
    let refused = |args: &[&str], why: &str| {
        let mut all = args.to_vec();
        all.extend(["--out", path(&fmu)]);
        let out = package(&all);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(
            !out.status.success() && stderr.contains(why),
            "{args:?}: {stderr}"
        );
        assert!(!fmu.exists(), "{args:?} wrote an FMU");
    };
    let so_arg = format!("win64={}", path(&so));
    refused(
        &["--library", &so_arg],
        "a win64 library must be a .dll file",
    );
    let fake_arg = format!("win64={}", path(&fake_dll));
    refused(&["--library", &fake_arg], "is not a PE shared library");
    refused(
        &["--library", "windows=x.dll"],
        "unknown platform \"windows\"",
    );
    let twice = format!("linux64={}", path(&so));
    refused(
        &["--library", &twice, "--library", &twice],
        "platform linux64 is given more than once",
    );
    let unknown_dir = dir.join("collected");
    write(&unknown_dir.join("win128/WheelRailFriction.dll"), DLL);
    refused(
        &["--binaries", path(&unknown_dir)],
        "unknown platform \"win128\"",
    );
    let empty = dir.join("empty");
    std::fs::create_dir_all(empty.join("darwin64")).unwrap();
    refused(&["--binaries", path(&empty)], "holds no .dylib library");
    std::fs::remove_dir_all(&dir).unwrap();
}
