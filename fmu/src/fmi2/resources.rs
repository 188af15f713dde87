//! `fmuResourceLocation`: the URI of the unpacked `resources/` directory (FMI 2.0 §2.1.5: a URI after
//! RFC 3986 with the `file` scheme of RFC 8089), on every platform an FMU is built for.
//!
//! Accepted: `file:///p`, `file:/p` and `file://localhost/p` (RFC 8089 §2), with the path
//! percent-decoded (RFC 3986 §2.1, UTF-8). A path that starts with a Windows drive letter, `/C:/…` (RFC
//! 8089 Appendix E.2), is the Windows path `C:/…` (the leading slash is dropped), whatever the host the
//! parser runs on; a `%5C` in the path decodes to a backslash, which Windows reads as a separator.
//! Refused, each with a message naming the URI and the reason: other schemes, remote hosts (UNC shares),
//! relative paths, a literal backslash (not a URI character, RFC 3986 §2; importers must write `/` or
//! `%5C`), a query or fragment, malformed or NUL escapes and escapes that are not UTF-8.

use std::path::PathBuf;

/// The local path of a `file:` URI (see the module documentation for the accepted forms), or a message
/// saying why the URI is refused.
pub fn path_from_uri(uri: &str) -> Result<PathBuf, String> {
    let refuse = |why: &str| format!("resource location \"{uri}\" {why}");
    let rest = uri
        .get(..5)
        .filter(|scheme| scheme.eq_ignore_ascii_case("file:"))
        .map(|_| &uri[5..])
        .ok_or_else(|| refuse("is not a file: URI"))?;
    if rest.contains('\\') {
        return Err(refuse(
            "contains a backslash, which a URI cannot hold (RFC 3986): write / or %5C",
        ));
    }
    if rest.contains(['?', '#']) {
        return Err(refuse(
            "has a query or fragment (a ? or # in a path must be written %3F or %23)",
        ));
    }
    let path = match rest.strip_prefix("//") {
        Some(authority_path) => {
            let slash = authority_path.find('/').unwrap_or(authority_path.len());
            let (host, path) = authority_path.split_at(slash);
            if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
                return Err(refuse(&format!(
                    "names the remote host \"{host}\" (only local files are supported)"
                )));
            }
            path
        }
        None => rest,
    };
    if !path.starts_with('/') {
        return Err(refuse("has no absolute path"));
    }
    let decoded = percent_decode(path).map_err(|why| refuse(&why))?;
    Ok(PathBuf::from(match windows_drive_path(&decoded) {
        Some(drive_path) => drive_path,
        None => &decoded,
    }))
}

/// The Windows path of a URI path `/X:` or `/X:/…` (drive letter X): the path without the leading slash.
fn windows_drive_path(path: &str) -> Option<&str> {
    let b = path.as_bytes();
    let is_drive = b.len() >= 3
        && b[1].is_ascii_alphabetic()
        && b[2] == b':'
        && matches!(b.get(3), None | Some(b'/') | Some(b'\\'));
    is_drive.then(|| &path[1..])
}

/// Decodes the `%XX` escapes of a URI path (RFC 3986 §2.1) into UTF-8 text.
fn percent_decode(s: &str) -> Result<String, String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let byte = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or("has a malformed %-escape (% must be followed by two hex digits)")?;
            if byte == 0 {
                return Err("has an escaped NUL character (%00)".into());
            }
            out.push(byte);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "has %-escapes that are not UTF-8".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_the_spellings_importers_use() {
        for uri in [
            "file:///tmp/a%20b/resources",
            "file:/tmp/a%20b/resources",
            "file://localhost/tmp/a%20b/resources",
            "FILE://LocalHost/tmp/a%20b/resources",
        ] {
            assert_eq!(
                path_from_uri(uri).unwrap(),
                PathBuf::from("/tmp/a b/resources"),
                "{uri}"
            );
        }
        assert_eq!(
            path_from_uri("file:///t/%C3%A4/").unwrap(),
            PathBuf::from("/t/ä/")
        );
        assert_eq!(
            path_from_uri("file:///home/user/fmu/resources").unwrap(),
            PathBuf::from("/home/user/fmu/resources")
        );
    }

    #[test]
    fn windows_drive_letters_give_windows_paths() {
        for uri in [
            "file:///C:/Users/A%20B/resources",
            "file:/C:/Users/A%20B/resources",
            "file://localhost/C:/Users/A%20B/resources",
            "file:///C%3A/Users/A%20B/resources",
        ] {
            assert_eq!(
                path_from_uri(uri).unwrap().to_str().unwrap(),
                "C:/Users/A B/resources",
                "{uri}"
            );
        }
        assert_eq!(path_from_uri("file:///d:").unwrap().to_str(), Some("d:"));
        // an escaped backslash is a URI character; Windows reads it as a separator
        assert_eq!(
            path_from_uri("file:///C:%5Ctemp%5Cresources")
                .unwrap()
                .to_str(),
            Some("C:\\temp\\resources")
        );
        // not a drive: a directory named like one stays absolute
        assert_eq!(
            path_from_uri("file:///CD:x/r").unwrap().to_str(),
            Some("/CD:x/r")
        );
    }

    #[test]
    fn rejects_what_is_not_a_local_file_uri_with_the_reason() {
        for (uri, why) in [
            ("http://x/y", "is not a file: URI"),
            ("C:\\temp\\resources", "is not a file: URI"),
            ("/plain", "is not a file: URI"),
            ("", "is not a file: URI"),
            ("file://server/share", "names the remote host \"server\""),
            ("file:relative", "has no absolute path"),
            ("file:C:/temp", "has no absolute path"),
            ("file:///C:\\temp\\resources", "contains a backslash"),
            ("file:\\\\server\\share", "contains a backslash"),
            ("file:///tmp/r?x=1", "has a query or fragment"),
            ("file:///tmp/r#top", "has a query or fragment"),
            ("file:///a%2", "malformed %-escape"),
            ("file:///a%zz", "malformed %-escape"),
            ("file:///a%00b", "escaped NUL"),
            ("file:///a%C3", "not UTF-8"),
        ] {
            let e = path_from_uri(uri).unwrap_err();
            assert!(e.contains(why) && e.contains(uri), "{uri}: {e}");
        }
    }
}
