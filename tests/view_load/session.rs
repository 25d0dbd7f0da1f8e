//! One page of the load test: a WebSocket session that orbits, drags and changes
//! its settings until a deadline, and logs what it saw: the time from each request
//! to the first frame of its camera or a newer one, the frames, the converged
//! pictures, and anything the protocol forbids.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::view_client::{orbit, Client, Msg, PATIENCE};

/// Picture sizes a page asks for.
const SIZES: [(u32, u32); 5] = [(64, 48), (96, 72), (80, 80), (120, 90), (48, 36)];
/// Target samples per pixel.
const SPPS: [u32; 5] = [1, 2, 4, 8, 16];
/// Maximum depths.
const DEPTHS: [u32; 3] = [2, 5, 8];
/// Integrators, by their protocol names.
const INTEGRATORS: [&str; 2] = ["whitted", "path"];
/// Acceleration structures, by their protocol names.
const ACCELS: [&str; 3] = ["bvh", "grid", "none"];
/// The time between two camera messages of a drag (a mouse's 60 a second).
const DRAG_PERIOD: Duration = Duration::from_millis(16);
/// Every how many steps a page drags (2 to 5 cameras) instead of sending one.
const DRAG_EVERY: u64 = 3;
/// Every how many steps a page picks new settings.
const NEW_SETTINGS_EVERY: u64 = 4;
/// Every how many steps a page waits for its picture to converge.
const CONVERGE_EVERY: u64 = 5;

/// A page's render settings.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub max_depth: u32,
    pub integrator: &'static str,
    pub accel: &'static str,
}

impl Settings {
    fn pick(rng: &mut Rng) -> Settings {
        let (width, height) = SIZES[rng.below(SIZES.len())];
        Settings {
            width,
            height,
            spp: SPPS[rng.below(SPPS.len())],
            max_depth: DEPTHS[rng.below(DEPTHS.len())],
            integrator: INTEGRATORS[rng.below(INTEGRATORS.len())],
            accel: ACCELS[rng.below(ACCELS.len())],
        }
    }

    fn render_msg(&self, camera: &Value) -> Value {
        json!({
            "type": "render",
            "camera": camera,
            "options": {
                "width": self.width, "height": self.height, "max_depth": self.max_depth,
                "spp": self.spp, "lens": true, "soft_shadows": true,
                "integrator": self.integrator, "accel": self.accel
            }
        })
    }

    /// The same settings as `nffrt render` options.
    pub fn render_args(&self) -> Vec<String> {
        let pairs = [
            ("--width", self.width.to_string()),
            ("--height", self.height.to_string()),
            ("--spp", self.spp.to_string()),
            ("--max-depth", self.max_depth.to_string()),
            ("--integrator", self.integrator.to_string()),
            ("--accel", self.accel.to_string()),
        ];
        pairs.into_iter().flat_map(|(k, v)| [k.to_string(), v]).collect()
    }
}

/// A converged picture and what it was asked with.
pub struct Converged {
    pub gen: u64,
    pub camera: Value,
    pub settings: Settings,
    pub rgb: Vec<u8>,
}

impl std::fmt::Debug for Converged {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "generation {} ({:?})", self.gen, self.settings)
    }
}

/// What a page saw.
#[derive(Debug, Default)]
pub struct Log {
    /// For each request, the time until a frame of its camera or a newer one.
    pub latencies: Vec<Duration>,
    /// Frames received.
    pub frames: u64,
    /// Drags: several cameras sent 16 ms apart, each replacing the last.
    pub drags: u64,
    /// Changes of the settings.
    pub settings_changes: u64,
    /// The converged pictures.
    pub converged: Vec<Converged>,
    /// What went wrong.
    pub failures: Vec<String>,
}

/// xorshift64*: each page's own repeatable choices.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % n
    }
}

/// A session and what it waits for.
struct Page {
    client: Client,
    /// Requests sent and not yet acknowledged: when, with what.
    sent: VecDeque<(Instant, Value, Settings)>,
    /// Acknowledged generations without a frame yet, and when each was asked.
    waiting: Vec<(u64, Instant)>,
    /// The newest acknowledged generation and its request.
    current: Option<(u64, Value, Settings)>,
    /// True once the current generation's converged frame has come.
    complete: bool,
    log: Log,
}

/// Plays page number `seed` on the session `client` until `end`.
pub fn drive(mut client: Client, seed: u64, end: Instant) -> Log {
    let mut camera = client.until_json("scene", |_| {})["camera"].clone();
    let mut page = Page {
        client,
        sent: VecDeque::new(),
        waiting: Vec::new(),
        current: None,
        complete: false,
        log: Log::default(),
    };
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut settings = Settings::pick(&mut rng);
    let mut step = 0u64;
    while Instant::now() < end && page.log.failures.is_empty() {
        step += 1;
        if step.is_multiple_of(NEW_SETTINGS_EVERY) {
            settings = Settings::pick(&mut rng);
            page.log.settings_changes += 1;
        }
        let cameras = if step.is_multiple_of(DRAG_EVERY) {
            2 + rng.below(4)
        } else {
            1
        };
        if cameras > 1 {
            page.log.drags += 1;
        }
        for k in 0..cameras {
            camera = orbit(&camera, 1.0 + rng.below(10) as f64);
            page.send(&camera, settings);
            if k + 1 < cameras {
                page.read_for(DRAG_PERIOD);
            }
        }
        // Now and then the page stays until the picture converges; otherwise a
        // moment, as a user between two moves.
        let dwell = Duration::from_millis(rng.below(200) as u64);
        page.settle(step.is_multiple_of(CONVERGE_EVERY), dwell);
    }
    page.settle(false, Duration::ZERO);
    page.log
}

impl Page {
    fn send(&mut self, camera: &Value, settings: Settings) {
        // The clock starts before the message leaves (this thread may be
        // descheduled in between: then it counts against the server).
        let t = Instant::now();
        self.client.send(&settings.render_msg(camera));
        self.sent.push_back((t, camera.clone(), settings));
    }

    fn fail(&mut self, why: String) {
        self.log.failures.push(why);
    }

    /// Reads what comes for `time`.
    fn read_for(&mut self, time: Duration) {
        let until = Instant::now() + time;
        while let Some(left) = until.checked_duration_since(Instant::now()) {
            match self.client.try_recv(left) {
                Some(m) => self.handle(m),
                None => break,
            }
        }
    }

    /// Reads until every request has a frame (and, if `converge`, the current one
    /// its converged frame) and `dwell` has passed.
    fn settle(&mut self, converge: bool, dwell: Duration) {
        let t0 = Instant::now();
        loop {
            let answered = self.sent.is_empty() && self.waiting.is_empty();
            if answered && (!converge || self.complete) && t0.elapsed() >= dwell {
                return;
            }
            if !self.log.failures.is_empty() {
                return;
            }
            if t0.elapsed() > PATIENCE {
                let why = format!(
                    "stuck: {} unacknowledged, {:?} without a frame",
                    self.sent.len(),
                    self.waiting
                );
                return self.fail(why);
            }
            if let Some(m) = self.client.try_recv(Duration::from_millis(20)) {
                self.handle(m);
            }
        }
    }

    fn handle(&mut self, m: Msg) {
        match m {
            Msg::Json(v) if v["type"] == "view" => self.acknowledged(v["gen"].as_u64().unwrap_or(0)),
            Msg::Json(v) if v["type"] == "error" || v["type"] == "load_error" => {
                self.fail(format!("an error for a valid request: {v}"))
            }
            Msg::Json(v) => self.fail(format!("unexpected message {v}")),
            Msg::Binary(header, rgb) => self.frame(&header, rgb),
            Msg::Closed => self.fail("the connection closed".into()),
        }
    }

    fn acknowledged(&mut self, gen: u64) {
        let Some((t, camera, settings)) = self.sent.pop_front() else {
            return self.fail(format!("generation {gen} acknowledged, nothing asked"));
        };
        if self.current.as_ref().is_some_and(|c| c.0 >= gen) {
            return self.fail(format!("generation {gen} acknowledged after a newer one"));
        }
        self.waiting.push((gen, t));
        self.current = Some((gen, camera, settings));
        self.complete = false;
    }

    fn frame(&mut self, header: &Value, rgb: Vec<u8>) {
        let now = Instant::now();
        let gen = header["gen"].as_u64().unwrap_or(0);
        let Some((current, camera, s)) = self.current.clone() else {
            return self.fail(format!("a frame before any acknowledgement: {header}"));
        };
        if header["kind"] != "frame" || gen != current {
            return self.fail(format!(
                "a frame of generation {gen} while {current} is current: {header}"
            ));
        }
        self.log.frames += 1;
        let latencies = &mut self.log.latencies;
        self.waiting.retain(|&(g, t)| {
            let answered = g <= gen;
            if answered {
                latencies.push(now - t);
            }
            !answered
        });
        let stride = header["stride"].as_u64().unwrap_or(0).max(1) as u32;
        let pixels = s.width.div_ceil(stride) as usize * s.height.div_ceil(stride) as usize;
        if (header["width"] != s.width || header["height"] != s.height) || rgb.len() != 3 * pixels {
            return self.fail(format!(
                "a frame of another size than {s:?}: {header}, {} bytes",
                rgb.len()
            ));
        }
        if header["complete"] == true {
            if header["samples"] != s.spp {
                return self.fail(format!("converged at other samples than {s:?}: {header}"));
            }
            self.complete = true;
            self.log.converged.push(Converged {
                gen,
                camera,
                settings: s,
                rgb,
            });
        }
    }
}
