//! A client of `nffrt view` for the tests and the latency benchmark: starts the
//! server on a free port, speaks raw HTTP/1.1 (so that any `Host` or `Origin` can be
//! sent) and the WebSocket protocol of `src/cli/view/protocol.rs`.

// Each crate that includes this module uses a different subset of it.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::Value;
use tungstenite::client::IntoClientRequest;
use tungstenite::http::HeaderValue;
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

/// How long any single wait may take before a test fails (generous: the machine is
/// shared and builds run beside the tests).
pub const PATIENCE: Duration = Duration::from_secs(120);

/// A running `nffrt view`, stopped when dropped.
pub struct Server {
    child: Child,
    /// The lines of its standard output after the first, as they come.
    stdout: mpsc::Receiver<String>,
    /// The lines of its standard error, when kept.
    stderr: Arc<Mutex<Vec<String>>>,
    /// Its port.
    pub port: u16,
    /// Its access token.
    pub token: String,
    /// The URL it printed.
    pub url: String,
}

impl Server {
    /// Starts `nffrt view SCENE --no-open --port 0 EXTRA...` and reads its URL.
    pub fn start(scene: &Path, extra: &[&str]) -> Server {
        Server::start_with_input(scene, extra, None)
    }

    /// [`Server::start`] with `input` written to its standard input (then closed).
    pub fn start_with_input(scene: &Path, extra: &[&str], input: Option<&[u8]>) -> Server {
        Server::launch(scene, extra, input, Stdio::inherit())
    }

    /// [`Server::start`] with its standard error kept: [`Server::stderr`] reads it.
    pub fn start_keeping_stderr(scene: &Path, extra: &[&str]) -> Server {
        let mut server = Server::launch(scene, extra, None, Stdio::piped());
        let stderr = server.child.stderr.take().expect("piped stderr");
        let kept = server.stderr.clone();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                kept.lock().unwrap().push(line);
            }
        });
        server
    }

    fn launch(scene: &Path, extra: &[&str], input: Option<&[u8]>, stderr: Stdio) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_nffrt"))
            .arg("view")
            .arg(scene)
            .args(["--no-open", "--port", "0"])
            .args(extra)
            .stdin(if input.is_some() {
                Stdio::piped()
            } else {
                Stdio::null()
            })
            .stdout(Stdio::piped())
            .stderr(stderr)
            .spawn()
            .expect("nffrt starts");
        if let Some(bytes) = input {
            let mut stdin = child.stdin.take().expect("piped stdin");
            stdin.write_all(bytes).expect("the scene goes to standard input");
        }
        let stdout = child.stdout.take().expect("piped stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let line = rx.recv_timeout(PATIENCE).expect("nffrt view prints its URL");
        let url = line
            .trim()
            .strip_prefix("serving ")
            .unwrap_or_else(|| panic!("unexpected first line {line:?}"))
            .to_string();
        let rest = url.strip_prefix("http://127.0.0.1:").expect("a loopback URL");
        let (port, token) = rest.split_once("/?token=").expect("a token in the URL");
        Server {
            child,
            stdout: rx,
            stderr: Arc::default(),
            port: port.parse().expect("a port"),
            token: token.to_string(),
            url,
        }
    }

    /// Its process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// What it printed on standard error so far (with
    /// [`Server::start_keeping_stderr`]; empty otherwise).
    pub fn stderr(&self) -> Vec<String> {
        self.stderr.lock().unwrap().clone()
    }

    /// The server's `Host` header value.
    pub fn host(&self) -> String {
        format!("127.0.0.1:{}", self.port)
    }

    /// The lines it printed after its URL so far (waiting up to a second for each;
    /// for lines printed with the URL, before it served anything).
    pub fn printed_after_url(&self) -> Vec<String> {
        std::iter::from_fn(|| self.stdout.recv_timeout(Duration::from_secs(1)).ok()).collect()
    }

    /// True while the process runs.
    pub fn alive(&mut self) -> bool {
        self.child.try_wait().expect("process state").is_none()
    }

    /// Sends SIGINT (Ctrl-C) to the server and waits for it to exit: its exit code
    /// and what it printed after its URL.
    #[cfg(unix)]
    pub fn interrupt(&mut self) -> (Option<i32>, Vec<String>) {
        let sent = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status();
        assert!(sent.is_ok_and(|s| s.success()), "kill -INT");
        let t0 = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().expect("process state") {
                // The reader thread ends with the pipe, once the process has exited.
                return (status.code(), self.stdout.iter().collect());
            }
            assert!(t0.elapsed() < PATIENCE, "the server did not stop on SIGINT");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// A WebSocket session with the right token, Host and Origin.
    pub fn connect(&self) -> Client {
        let origin = format!("http://{}", self.host());
        self.connect_with(&format!("/ws?token={}", self.token), Some(&origin))
            .expect("the WebSocket opens")
    }

    /// A WebSocket to `path_and_query`, with `origin` if any.
    pub fn connect_with(
        &self,
        path_and_query: &str,
        origin: Option<&str>,
    ) -> Result<Client, tungstenite::Error> {
        let mut request = format!("ws://{}{path_and_query}", self.host()).into_client_request()?;
        if let Some(o) = origin {
            request
                .headers_mut()
                .insert("Origin", HeaderValue::from_str(o).unwrap());
        }
        let stream = TcpStream::connect(("127.0.0.1", self.port)).expect("connect");
        stream.set_read_timeout(Some(PATIENCE)).unwrap();
        let (socket, _) =
            tungstenite::client(request, MaybeTlsStream::Plain(stream)).map_err(|e| match e {
                tungstenite::HandshakeError::Failure(e) => e,
                tungstenite::HandshakeError::Interrupted(_) => panic!("blocking handshake interrupted"),
            })?;
        Ok(Client { socket })
    }

    /// `GET path_and_query` with these headers (`Host` defaults to the server's):
    /// the status code and the body.
    pub fn get(&self, path_and_query: &str, headers: &[(&str, &str)]) -> (u16, Vec<u8>) {
        self.get_via(&self.host(), path_and_query, headers)
    }

    /// [`Server::get`] through `address` (`IP:PORT`, IPv6 in brackets), which is
    /// also the default `Host`.
    pub fn get_via(&self, address: &str, path_and_query: &str, headers: &[(&str, &str)]) -> (u16, Vec<u8>) {
        let target: std::net::SocketAddr = address.parse().expect("an IP:PORT address");
        let mut stream = TcpStream::connect(target).expect("connect");
        stream.set_read_timeout(Some(PATIENCE)).unwrap();
        let mut request = format!("GET {path_and_query} HTTP/1.1\r\nConnection: close\r\n");
        if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("host")) {
            request += &format!("Host: {address}\r\n");
        }
        for (k, v) in headers {
            request += &format!("{k}: {v}\r\n");
        }
        request += "\r\n";
        stream.write_all(request.as_bytes()).expect("send");
        let mut response = Vec::new();
        stream.read_to_end(&mut response).expect("read");
        let end = response
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .expect("a header");
        let head = String::from_utf8_lossy(&response[..end]).to_string();
        let status = head
            .split(' ')
            .nth(1)
            .and_then(|s| s.parse().ok())
            .expect("a status");
        (status, response[end + 4..].to_vec())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A message from the server.
#[derive(Debug)]
pub enum Msg {
    /// A JSON text message.
    Json(Value),
    /// A binary message: its JSON header and payload.
    Binary(Value, Vec<u8>),
    /// The connection closed.
    Closed,
}

/// One WebSocket session.
pub struct Client {
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
}

impl Client {
    /// Sends a JSON message.
    pub fn send(&mut self, msg: &Value) {
        self.send_text(&msg.to_string());
    }

    /// Sends raw text.
    pub fn send_text(&mut self, text: &str) {
        self.socket.send(Message::text(text)).expect("send");
    }

    /// Sends a binary message: a 4-byte little-endian length, `header` as JSON, then
    /// `payload` (a reference upload's framing).
    pub fn send_binary(&mut self, header: &Value, payload: &[u8]) {
        let json = header.to_string();
        let mut bytes = (json.len() as u32).to_le_bytes().to_vec();
        bytes.extend_from_slice(json.as_bytes());
        bytes.extend_from_slice(payload);
        self.socket.send(Message::binary(bytes)).expect("send");
    }

    /// Sends raw text that the server may refuse by closing the connection while it
    /// is still being written (a broken pipe or a reset is then no failure).
    pub fn send_text_to_be_refused(&mut self, text: &str) {
        use std::io::ErrorKind::{BrokenPipe, ConnectionReset};
        match self.socket.send(Message::text(text)) {
            Ok(()) => {}
            Err(tungstenite::Error::Io(e)) if matches!(e.kind(), BrokenPipe | ConnectionReset) => {}
            Err(e) => panic!("send: {e}"),
        }
    }

    /// The next message (pings and pongs skipped); `Closed` after [`PATIENCE`].
    pub fn recv(&mut self) -> Msg {
        loop {
            match decode(self.socket.read()) {
                Outcome::Msg(m) => return m,
                Outcome::TimedOut => return Msg::Closed,
                Outcome::Skipped => {}
            }
        }
    }

    /// The next message if one arrives within `timeout`.
    pub fn try_recv(&mut self, timeout: Duration) -> Option<Msg> {
        self.set_timeout(timeout.max(Duration::from_micros(100)));
        let read = decode(self.socket.read());
        self.set_timeout(PATIENCE);
        match read {
            Outcome::Msg(m) => Some(m),
            Outcome::TimedOut | Outcome::Skipped => None,
        }
    }

    fn set_timeout(&mut self, timeout: Duration) {
        if let MaybeTlsStream::Plain(s) = self.socket.get_mut() {
            s.set_read_timeout(Some(timeout)).unwrap();
        }
    }

    /// Reads until a JSON message of type `kind` arrives (failing on a close or
    /// after [`PATIENCE`]); `seen` gets every message on the way.
    pub fn until_json(&mut self, kind: &str, mut seen: impl FnMut(&Msg)) -> Value {
        let t0 = Instant::now();
        loop {
            assert!(t0.elapsed() < PATIENCE, "no {kind} message in time");
            let m = self.recv();
            seen(&m);
            match m {
                Msg::Json(v) if v["type"] == kind => return v,
                Msg::Closed => panic!("closed while waiting for {kind}"),
                _ => {}
            }
        }
    }

    /// Reads until the converged frame of generation `gen`; `seen` gets every
    /// message on the way. Its header and RGB payload.
    pub fn until_complete(&mut self, gen: u64, mut seen: impl FnMut(&Msg)) -> (Value, Vec<u8>) {
        let t0 = Instant::now();
        loop {
            assert!(
                t0.elapsed() < PATIENCE,
                "generation {gen} did not converge in time"
            );
            let m = self.recv();
            seen(&m);
            match m {
                Msg::Binary(h, rgb) if h["gen"] == gen && h["complete"] == true => return (h, rgb),
                Msg::Closed => panic!("closed while waiting for generation {gen}"),
                _ => {}
            }
        }
    }
}

/// What one read gave.
enum Outcome {
    Msg(Msg),
    TimedOut,
    Skipped,
}

fn decode(read: Result<Message, tungstenite::Error>) -> Outcome {
    match read {
        Ok(Message::Text(t)) => Outcome::Msg(Msg::Json(serde_json::from_str(t.as_str()).expect("JSON"))),
        Ok(Message::Binary(b)) => {
            let n = u32::from_le_bytes(b[..4].try_into().unwrap()) as usize;
            let header = serde_json::from_slice(&b[4..4 + n]).expect("a JSON header");
            Outcome::Msg(Msg::Binary(header, b[4 + n..].to_vec()))
        }
        Ok(Message::Close(_)) => Outcome::Msg(Msg::Closed),
        Ok(_) => Outcome::Skipped,
        Err(tungstenite::Error::Io(e))
            if matches!(
                e.kind(),
                std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
            ) =>
        {
            Outcome::TimedOut
        }
        Err(_) => Outcome::Msg(Msg::Closed),
    }
}

/// A render request.
pub fn render_msg(camera: &Value, width: u32, height: u32, spp: u32) -> Value {
    serde_json::json!({
        "type": "render",
        "camera": camera,
        "options": {
            "width": width, "height": height, "max_depth": 5, "spp": spp,
            "lens": true, "soft_shadows": true
        }
    })
}

/// `camera` turned by `degrees` about its up axis through its look-at point, each
/// number rounded to the `f32` the server reads: a scene file written with these
/// numbers has this very camera.
pub fn orbit(camera: &Value, degrees: f64) -> Value {
    let v = |key: &str| -> [f64; 3] { std::array::from_fn(|i| camera[key][i].as_f64().unwrap()) };
    let (from, at, up) = (v("from"), v("at"), v("up"));
    let n = (up[0] * up[0] + up[1] * up[1] + up[2] * up[2]).sqrt();
    let k = [up[0] / n, up[1] / n, up[2] / n];
    let p = [from[0] - at[0], from[1] - at[1], from[2] - at[2]];
    let (c, s) = (degrees.to_radians().cos(), degrees.to_radians().sin());
    let kxp = [
        k[1] * p[2] - k[2] * p[1],
        k[2] * p[0] - k[0] * p[2],
        k[0] * p[1] - k[1] * p[0],
    ];
    let kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
    let turned: Vec<f32> = (0..3)
        .map(|i| (at[i] + p[i] * c + kxp[i] * s + k[i] * kp * (1.0 - c)) as f32)
        .collect();
    let mut out = camera.clone();
    out["from"] = serde_json::json!(turned);
    out
}
