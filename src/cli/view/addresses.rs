//! The URLs `nffrt view` prints: one per address a browser can open. Listening on
//! an unspecified address (`--host 0.0.0.0` or `::`) means every interface, but no
//! browser opens `http://0.0.0.0:PORT/`: for it the loopback address (this machine)
//! and this machine's address on the network (for the others) are printed instead.
//!
//! The network address is the one the system would send from towards the outside:
//! a UDP socket "connected" to a documentation address (TEST-NET-1, 2001:db8::/32)
//! sends nothing, but takes its local address from the routing table. The standard
//! library lists no interfaces; this one address (the default route's) is the one
//! other machines most likely reach, and there is none without a route.

use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};

/// The hosts to show for a server listening on `host`: `host` itself, or for an
/// unspecified address the loopback address, then the network address if any.
pub fn hosts_to_show(host: IpAddr) -> Vec<IpAddr> {
    if !host.is_unspecified() {
        return vec![host];
    }
    let loopback = match host {
        IpAddr::V4(_) => IpAddr::V4(Ipv4Addr::LOCALHOST),
        IpAddr::V6(_) => IpAddr::V6(Ipv6Addr::LOCALHOST),
    };
    let mut hosts = vec![loopback];
    hosts.extend(network_address(host));
    hosts
}

/// The address of `family` this machine would send from to reach another network,
/// if it has a route there.
fn network_address(family: IpAddr) -> Option<IpAddr> {
    let (local, remote): (SocketAddr, SocketAddr) = match family {
        IpAddr::V4(_) => (
            (Ipv4Addr::UNSPECIFIED, 0).into(),
            (Ipv4Addr::new(192, 0, 2, 1), 9).into(),
        ),
        IpAddr::V6(_) => (
            (Ipv6Addr::UNSPECIFIED, 0).into(),
            (Ipv6Addr::new(0x2001, 0xdb8, 0, 0, 0, 0, 0, 1), 9).into(),
        ),
    };
    let socket = UdpSocket::bind(local).ok()?;
    socket.connect(remote).ok()?;
    let ip = socket.local_addr().ok()?.ip();
    (!ip.is_unspecified() && !ip.is_loopback()).then_some(ip)
}

/// The page's URL on `host`.
pub fn url(host: IpAddr, port: u16, token: &str) -> String {
    match host {
        IpAddr::V6(h) => format!("http://[{h}]:{port}/?token={token}"),
        IpAddr::V4(h) => format!("http://{h}:{port}/?token={token}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_named_host_is_shown_as_it_is() {
        for host in ["127.0.0.1", "192.168.4.7", "::1"] {
            let host: IpAddr = host.parse().unwrap();
            assert_eq!(hosts_to_show(host), [host]);
        }
    }

    #[test]
    fn an_unspecified_host_shows_loopback_first_and_never_itself() {
        for (any, loopback) in [("0.0.0.0", "127.0.0.1"), ("::", "::1")] {
            let hosts = hosts_to_show(any.parse().unwrap());
            assert_eq!(hosts[0], loopback.parse::<IpAddr>().unwrap());
            assert!(hosts.len() <= 2, "{hosts:?}");
            assert!(hosts.iter().all(|h| !h.is_unspecified()), "{hosts:?}");
            assert!(hosts[1..].iter().all(|h| !h.is_loopback()), "{hosts:?}");
        }
    }

    #[test]
    fn urls_bracket_ipv6_hosts() {
        assert_eq!(
            url("10.0.0.2".parse().unwrap(), 80, "t"),
            "http://10.0.0.2:80/?token=t"
        );
        assert_eq!(
            url("::1".parse().unwrap(), 8080, "t"),
            "http://[::1]:8080/?token=t"
        );
    }
}
