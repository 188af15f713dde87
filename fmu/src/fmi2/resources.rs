//! `fmuResourceLocation`: the URI of the unpacked `resources/` directory (RFC 3986, `file` scheme).

use std::path::PathBuf;

/// The local path of a `file:` URI: `file:///p`, `file://localhost/p`, `file:/p`, percent-decoded. Other
/// schemes, remote hosts and malformed escapes give an error message.
pub fn path_from_uri(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file:")
        .ok_or_else(|| format!("resource location \"{uri}\" is not a file: URI"))?;
    let path = match rest.strip_prefix("//") {
        Some(authority_path) => {
            let slash = authority_path.find('/').unwrap_or(authority_path.len());
            let (host, path) = authority_path.split_at(slash);
            if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
                return Err(format!("resource location \"{uri}\" names a remote host"));
            }
            path
        }
        None => rest,
    };
    if !path.starts_with('/') {
        return Err(format!("resource location \"{uri}\" has no absolute path"));
    }
    percent_decode(path)
        .map(PathBuf::from)
        .ok_or_else(|| format!("resource location \"{uri}\" has a malformed %-escape"))
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
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
    }

    #[test]
    fn rejects_what_is_not_a_local_file() {
        for uri in [
            "http://x/y",
            "file://server/share",
            "file:relative",
            "file:///a%2",
            "file:///a%zz",
            "/plain",
        ] {
            assert!(path_from_uri(uri).is_err(), "{uri}");
        }
    }
}
