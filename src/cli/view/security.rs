//! Who may use the preview server: the holder of the run's token, from a page of
//! the server itself, reached under a name that cannot be rebound.
//!
//! As Jupyter's server does: a random token in the URL printed at start, required on
//! every request and WebSocket (compared in constant time); the `Host` header must be
//! `localhost` or an IP address with the server's port, so a DNS name an attacker
//! controls (DNS rebinding) is refused; an `Origin` header, when sent, must be the
//! server's own, so no other site's page can drive it.

use std::net::IpAddr;

/// The access token: 32 hex digits from the operating system's random source.
pub fn new_token() -> Result<String, String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| format!("no random source for the access token: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// `a == b` in time that depends on their lengths only.
pub fn same_secret(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// The value of `key` in a URL query string (`a=1&token=...`), undecoded (tokens
/// are hex digits).
pub fn query_value<'q>(query: Option<&'q str>, key: &str) -> Option<&'q str> {
    query?.split('&').find_map(|pair| {
        let (k, v) = pair.split_once('=')?;
        (k == key).then_some(v)
    })
}

/// True if a `Host` header names this server: `localhost` or an IP literal (IPv6
/// in brackets), with exactly `port`.
pub fn host_allowed(host: &str, port: u16) -> bool {
    let Some((name, p)) = host.rsplit_once(':') else {
        return false;
    };
    if p.parse::<u16>() != Ok(port) {
        return false;
    }
    let name = name
        .strip_prefix('[')
        .and_then(|n| n.strip_suffix(']'))
        .unwrap_or(name);
    name.eq_ignore_ascii_case("localhost") || name.parse::<IpAddr>().is_ok()
}

/// True if an `Origin` header is this server's own page, reached as `host`.
pub fn origin_allowed(origin: &str, host: &str) -> bool {
    origin
        .strip_prefix("http://")
        .is_some_and(|rest| rest.eq_ignore_ascii_case(host))
}

/// Why a request is refused, or `None` to serve it.
pub fn refusal(
    host: Option<&str>,
    origin: Option<&str>,
    query: Option<&str>,
    token: &str,
    port: u16,
) -> Option<&'static str> {
    let Some(host) = host.filter(|h| host_allowed(h, port)) else {
        return Some("unknown Host: use the address nffrt printed");
    };
    if origin.is_some_and(|o| !origin_allowed(o, host)) {
        return Some("requests from other sites are refused");
    }
    let given = query_value(query, "token").unwrap_or("");
    if !same_secret(given.as_bytes(), token.as_bytes()) {
        return Some("missing or wrong token: open the URL nffrt printed");
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_are_random_hex() {
        let (a, b) = (new_token().unwrap(), new_token().unwrap());
        assert_eq!(a.len(), 32);
        assert!(a.bytes().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a, b);
    }

    #[test]
    fn secrets_compare_whole() {
        assert!(same_secret(b"abc", b"abc"));
        assert!(!same_secret(b"abc", b"abd"));
        assert!(!same_secret(b"abc", b"ab"));
        assert!(!same_secret(b"", b"a"));
    }

    #[test]
    fn hosts_must_be_loopback_names_or_addresses_with_our_port() {
        for ok in [
            "127.0.0.1:8080",
            "localhost:8080",
            "LOCALHOST:8080",
            "[::1]:8080",
            "192.168.1.5:8080",
        ] {
            assert!(host_allowed(ok, 8080), "{ok}");
        }
        for bad in [
            "127.0.0.1:8081",
            "127.0.0.1",
            "evil.example:8080",
            "localhost.evil.example:8080",
            "[::1]:80800",
            "",
            ":8080",
        ] {
            assert!(!host_allowed(bad, 8080), "{bad}");
        }
    }

    #[test]
    fn requests_need_the_token_our_host_and_our_origin() {
        let t = "00ff";
        let ok = |h, o, q| refusal(Some(h), o, q, t, 9000).is_none();
        assert!(ok("127.0.0.1:9000", None, Some("token=00ff")));
        assert!(ok(
            "127.0.0.1:9000",
            Some("http://127.0.0.1:9000"),
            Some("a=b&token=00ff")
        ));
        assert!(!ok("127.0.0.1:9000", None, None));
        assert!(!ok("127.0.0.1:9000", None, Some("token=00fe")));
        assert!(!ok("127.0.0.1:9000", None, Some("token=00ff0")));
        assert!(!ok("evil.example:9000", None, Some("token=00ff")));
        assert!(!ok(
            "127.0.0.1:9000",
            Some("http://evil.example"),
            Some("token=00ff")
        ));
        assert!(!ok("127.0.0.1:9000", Some("null"), Some("token=00ff")));
        assert!(!ok(
            "127.0.0.1:9000",
            Some("http://localhost:9000"),
            Some("token=00ff")
        ));
        assert!(refusal(None, None, Some("token=00ff"), t, 9000).is_some());
    }
}
