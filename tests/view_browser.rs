//! `nffrt view` in a real browser: headless Chromium driven by chromedriver over the
//! WebDriver protocol (plain HTTP and JSON, spoken here directly). The page opens,
//! shows its first full frame, orbits on a drag, shows the ray tree of a clicked
//! pixel naming the sphere's line, and renders the scene again when the file
//! changes. Every wait is on a signal the page gives (its `data-*` attributes,
//! watched with a MutationObserver), with a generous deadline; screenshots go to
//! `target/view-browser/`.
//!
//! Skipped, saying so, when `chromedriver` is not installed; `.ci/run` installs it
//! and sets `NFFRT_BROWSER_TEST=require`, which turns the skip into a failure.

#[path = "common/skip.rs"]
mod skip;
mod view_client;

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use view_client::Server;

/// The scene: a floor, three spheres; the red one, on line 14, is at the look-at
/// point, so the centre pixel shows it from any orbit.
const SCENE: &str = "v\nfrom 0 -8 3\nat 0 0 1\nup 0 0 1\nangle 40\nhither 1\nresolution 320 240\n\
b 0.2 0.3 0.5\nl -5 -5 10\nl 5 -3 8\nf 0.8 0.8 0.8 0.7 0.3 20 0 1\n\
p 4 -6 -6 0 6 -6 0 6 6 0 -6 6 0\nf 0.9 0.3 0.2 0.7 0.3 30 0 1\ns 0 0 1 1\n\
f 0.2 0.5 0.9 0.6 0.4 40 0 1\ns 2 1 0.7 0.7\nf 1 1 1 0.1 0.1 50 0.9 1.5\ns -2 0.5 0.8 0.8\n";

const ELEMENT: &str = "element-6066-11e4-a52e-4f735466cecf";

fn find_on_path(program: &str) -> Option<PathBuf> {
    std::env::var_os("PATH")?
        .to_str()?
        .split(':')
        .map(|dir| Path::new(dir).join(program))
        .find(|p| p.is_file())
}

/// A chromedriver process and one browser session, both ended when dropped.
struct Browser {
    driver: Child,
    port: u16,
    session: String,
}

impl Browser {
    fn start(driver: &Path, profile: &Path) -> Browser {
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let driver = Command::new(driver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let mut b = Browser {
            driver,
            port,
            session: String::new(),
        };
        // Ready when /status answers ready (the only wait here without an event to
        // listen for: the process gives no other signal).
        let t0 = Instant::now();
        while b
            .call("GET", "/status", None)
            .ok()
            .map(|v| v["value"]["ready"] == true)
            != Some(true)
        {
            assert!(
                t0.elapsed() < view_client::PATIENCE,
                "chromedriver did not become ready"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        let chromium = find_on_path("chromium").or_else(|| find_on_path("chromium-browser"));
        let mut options = json!({"args": [
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--window-size=1280,900", format!("--user-data-dir={}", profile.display()),
        ]});
        if let Some(c) = chromium {
            options["binary"] = json!(c);
        }
        let caps = json!({"capabilities": {"alwaysMatch": {"browserName": "chrome", "goog:chromeOptions": options}}});
        let r = b.call("POST", "/session", Some(caps)).expect("a browser session");
        b.session = r["value"]["sessionId"]
            .as_str()
            .expect("a session id")
            .to_string();
        b.cmd(
            "POST",
            "timeouts",
            json!({"script": view_client::PATIENCE.as_millis() as u64}),
        );
        b
    }

    /// One WebDriver call: the response's JSON.
    fn call(&self, method: &str, path: &str, body: Option<Value>) -> std::io::Result<Value> {
        let mut s = TcpStream::connect(("127.0.0.1", self.port))?;
        s.set_read_timeout(Some(view_client::PATIENCE * 2))?;
        let body = body.map(|b| b.to_string()).unwrap_or_default();
        write!(
            s,
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
            self.port,
            body.len()
        )?;
        // The body's length is in the header (chromedriver may keep the connection).
        let mut response = Vec::new();
        let mut buf = [0u8; 65536];
        let (start, length) = loop {
            let n = s.read(&mut buf)?;
            if n == 0 {
                return Err(std::io::Error::other("closed before the header ended"));
            }
            response.extend_from_slice(&buf[..n]);
            if let Some(i) = response.windows(4).position(|w| w == b"\r\n\r\n") {
                let head = String::from_utf8_lossy(&response[..i]).to_ascii_lowercase();
                let length = head
                    .lines()
                    .find_map(|l| l.strip_prefix("content-length:"))
                    .and_then(|v| v.trim().parse::<usize>().ok())
                    .ok_or_else(|| std::io::Error::other("no content-length"))?;
                break (i + 4, length);
            }
        };
        while response.len() < start + length {
            let n = s.read(&mut buf)?;
            if n == 0 {
                break;
            }
            response.extend_from_slice(&buf[..n]);
        }
        serde_json::from_slice(&response[start..]).map_err(std::io::Error::other)
    }

    /// A call on the session; fails the test on a WebDriver error.
    fn cmd(&self, method: &str, path: &str, body: Value) -> Value {
        let path = format!("/session/{}/{path}", self.session);
        let body = (method == "POST").then_some(body);
        let r = self.call(method, &path, body).expect("chromedriver answers");
        assert!(r["value"]["error"].is_null(), "{path}: {r}");
        r["value"].clone()
    }

    fn run(&self, script: &str) -> Value {
        self.cmd("POST", "execute/sync", json!({"script": script, "args": []}))
    }

    /// Waits until `condition` (a JavaScript expression) holds, re-checking on every
    /// change to the page.
    fn wait_for(&self, condition: &str) {
        let script = format!(
            "const done = arguments[arguments.length - 1];\n\
             const check = () => {{ try {{ if ({condition}) {{ done(true); return true; }} }} catch (e) {{}} return false; }};\n\
             if (!check()) {{ const o = new MutationObserver(() => {{ if (check()) o.disconnect(); }});\n\
               o.observe(document.body, {{ attributes: true, childList: true, subtree: true, characterData: true }}); }}"
        );
        self.cmd("POST", "execute/async", json!({"script": script, "args": []}));
    }

    fn screenshot(&self, path: &Path) {
        let data = self.cmd("GET", "screenshot", Value::Null);
        std::fs::write(path, base64_decode(data.as_str().expect("base64"))).unwrap();
    }

    /// Pointer actions on the picture: from its centre, `moves` steps of (dx, dy).
    fn pointer_on_picture(&self, moves: &[(i64, i64)]) {
        let picture = self.cmd(
            "POST",
            "element",
            json!({"using": "css selector", "value": "#picture"}),
        );
        let mut actions = vec![
            json!({"type": "pointerMove", "duration": 0, "origin": {ELEMENT: picture[ELEMENT]}, "x": 0, "y": 0}),
            json!({"type": "pointerDown", "button": 0}),
        ];
        for (dx, dy) in moves {
            actions
                .push(json!({"type": "pointerMove", "duration": 100, "origin": "pointer", "x": dx, "y": dy}));
        }
        actions.push(json!({"type": "pointerUp", "button": 0}));
        let body = json!({"actions": [{"type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"}, "actions": actions}]});
        self.cmd("POST", "actions", body);
    }

    /// A checksum of the picture's pixels, and the generation drawn.
    fn picture(&self) -> (u64, u64) {
        let v = self.run(
            "const c = document.getElementById('picture');\n\
             const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;\n\
             let h = 0; for (let i = 0; i < d.length; i++) h = (h * 31 + d[i]) >>> 0;\n\
             return [h, Number(document.body.dataset.gen)];",
        );
        (v[0].as_u64().unwrap(), v[1].as_u64().unwrap())
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        if !self.session.is_empty() {
            let _ = self.call("DELETE", &format!("/session/{}", self.session), None);
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// Standard base64 (the screenshot's encoding), without a crate for it.
fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        _ => 63,
    };
    let digits: Vec<u8> = text
        .bytes()
        .filter(|c| c.is_ascii_alphanumeric() || *c == b'+' || *c == b'/')
        .map(value)
        .collect();
    digits
        .chunks(4)
        .flat_map(|q| {
            let n = q
                .iter()
                .enumerate()
                .fold(0u32, |n, (i, &d)| n | (d as u32) << (18 - 6 * i));
            let bytes = n.to_be_bytes();
            bytes[1..q.len()].to_vec()
        })
        .collect()
}

/// chromedriver, a folder for screenshots and a fresh work folder (with an empty
/// browser profile) named after `name`; or `None` after saying the test is skipped
/// (a failure under NFFRT_BROWSER_TEST=require).
fn setup(name: &str) -> Option<(PathBuf, PathBuf, PathBuf)> {
    let Some(driver) = find_on_path("chromedriver") else {
        assert!(
            std::env::var("NFFRT_BROWSER_TEST").as_deref() != Ok("require"),
            "NFFRT_BROWSER_TEST=require but chromedriver is not on PATH"
        );
        skip::skip("chromedriver is not installed (apt-get install chromium chromium-driver)");
        return None;
    };
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let shots = tmp.parent().unwrap().join("view-browser");
    let work = tmp.join(format!("view-browser-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&shots).unwrap();
    std::fs::create_dir_all(work.join("profile")).unwrap();
    Some((driver, shots, work))
}

#[test]
fn the_page_renders_orbits_explains_a_pixel_and_reloads() {
    let Some((driver, shots, work)) = setup("reload") else {
        return;
    };
    let file = work.join("spheres.nff");
    std::fs::write(&file, SCENE).unwrap();
    let server = Server::start(&file, &["--spp", "4"]);
    let browser = Browser::start(&driver, &work.join("profile"));
    browser.cmd("POST", "url", json!({"url": server.url}));

    // The first full frame, then the converged one.
    browser.wait_for("Number(document.body.dataset.fullFrames) >= 1");
    browser.wait_for("document.body.dataset.complete === 'true'");
    browser.screenshot(&shots.join("1-converged.png"));
    let (before, gen) = browser.picture();
    let slider = browser.run("return document.getElementById('animation').hidden;");
    assert_eq!(slider.as_bool(), Some(true), "an NFF scene has no time slider");

    // Drag to orbit: new generations, coarse frames while moving, a new picture.
    browser.pointer_on_picture(&[(30, 0), (30, 0), (30, 10), (30, 10)]);
    browser.wait_for(&format!(
        "Number(document.body.dataset.gen) > {gen} && document.body.dataset.complete === 'true'"
    ));
    let (after, gen) = browser.picture();
    assert_ne!(before, after, "the picture changed with the orbit");
    browser.screenshot(&shots.join("2-orbited.png"));

    // Click the centre: the red sphere of line 14.
    browser.pointer_on_picture(&[]);
    browser.wait_for("Number(document.body.dataset.trees) >= 1");
    let tree = browser.run("return document.getElementById('tree').innerText;");
    let tree = tree.as_str().unwrap();
    assert!(tree.contains("hit sphere (s) at line 14"), "{tree}");
    assert!(tree.contains("light 1"), "{tree}");
    // The rays are drawn over the picture.
    let drawn = browser.run(
        "try { drawRays(); } catch (e) { return String(e.stack); }\n\
         const o = document.getElementById('overlay');\n\
         const d = o.getContext('2d').getImageData(0, 0, o.width, o.height).data;\n\
         let n = 0; for (let i = 3; i < d.length; i += 4) n += d[i] > 0; return n;",
    );
    assert!(
        drawn.as_u64().is_some_and(|n| n > 20),
        "rays over the picture: {drawn}"
    );
    browser.screenshot(&shots.join("3-ray-tree.png"));

    // The file changes: the page shows the new picture.
    std::fs::write(&file, SCENE.replace("f 0.9 0.3 0.2", "f 0.2 0.9 0.3")).unwrap();
    browser.wait_for(&format!(
        "document.body.dataset.version === '1' && Number(document.body.dataset.gen) > {gen} \
         && document.body.dataset.complete === 'true'"
    ));
    let (edited, gen) = browser.picture();
    assert_ne!(edited, after, "the edit shows");
    browser.screenshot(&shots.join("4-reloaded.png"));

    // A broken file: the error, located; the picture stays.
    std::fs::write(&file, SCENE.replace("s 0 0 1 1", "s 0 0 1")).unwrap();
    browser.wait_for("document.body.dataset.loadError !== undefined");
    let banner = browser.run("return document.getElementById('load-error').innerText;");
    let expected = format!("{}:15:1: ", file.display());
    assert!(banner.as_str().unwrap().starts_with(&expected), "{banner}");
    assert_eq!(browser.picture(), (edited, gen), "the last good picture stays");
    browser.screenshot(&shots.join("5-load-error.png"));
    eprintln!("screenshots in {}", shots.display());
}

/// A P3F scene with a lens focused far behind its one sphere (so its eye rays leave
/// from all over the lens and hit a blurred spot), no reflection, and a light just
/// in front of the sphere (so the shadow rays drawn stay short on the picture).
const LENS_SCENE: &str = "bclr 0.1 0.1 0.2\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\n\
resolution 320 240\naperture 16\nfocal 2\nl 0.15 0.15 1.5 1 1 1\nf 0.9 0.3 0.2 1 1 1 1 0 30 0 1\ns 0 0 0 1\n";

impl Browser {
    /// Clicks picture pixel `(x, y)` wherever and however large the picture is drawn:
    /// at the first whole viewport position inside that pixel's square on screen.
    fn click_pixel(&self, x: u32, y: u32) {
        let at = self.run(&format!(
            "const c = document.getElementById('picture'), r = c.getBoundingClientRect();\n\
             const s = r.width / c.width;\n\
             return [Math.ceil(r.left + {x} * s), Math.ceil(r.top + {y} * s)];"
        ));
        let actions = vec![
            json!({"type": "pointerMove", "duration": 0, "origin": "viewport", "x": at[0], "y": at[1]}),
            json!({"type": "pointerDown", "button": 0}),
            json!({"type": "pointerUp", "button": 0}),
        ];
        let body = json!({"actions": [{"type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"}, "actions": actions}]});
        self.cmd("POST", "actions", body);
    }

    /// Clicks pixel `(x, y)` and waits for its ray tree: the tree's first line.
    fn tree_of_pixel(&self, x: u32, y: u32) -> String {
        let trees = self
            .run("return Number(document.body.dataset.trees);")
            .as_u64()
            .unwrap();
        self.click_pixel(x, y);
        self.wait_for(&format!("Number(document.body.dataset.trees) > {trees}"));
        let text = self.run("return document.getElementById('tree').innerText;");
        text.as_str().unwrap().lines().next().unwrap_or("").to_string()
    }

    /// The picture's box on screen (left, top, width, height), the window's inner
    /// size and the page's scale.
    fn picture_box(&self) -> Value {
        self.run(
            "const r = document.getElementById('picture').getBoundingClientRect();\n\
             return {left: r.left, top: r.top, width: r.width, height: r.height, right: r.right,\n\
                     bottom: r.bottom, window_width: window.innerWidth, window_height: window.innerHeight,\n\
                     scale: Number(document.body.dataset.scale)};",
        )
    }

    /// Types `text` into the field `id` and presses Enter.
    fn type_into(&self, id: &str, text: &str) {
        let field = self.cmd(
            "POST",
            "element",
            json!({"using": "css selector", "value": format!("#{id}")}),
        );
        let element = field[ELEMENT].as_str().unwrap().to_string();
        // (WebDriver's clear would commit the empty field: a change of its own.)
        self.run(&format!("document.getElementById('{id}').value = '';"));
        self.cmd(
            "POST",
            &format!("element/{element}/value"),
            json!({"text": format!("{text}\u{E007}")}),
        );
    }
}

/// The picture is fitted to the window (aspect kept), 1:1 on request, and a click
/// picks the pixel under it either way; a lens pixel's rays are drawn where they hit,
/// not as lines from the lens across the picture; a refused setting says why.
#[test]
fn the_picture_fits_clicks_find_their_pixel_lens_rays_stay_put_and_bad_settings_say_why() {
    let Some((driver, shots, work)) = setup("fit") else {
        return;
    };
    let file = work.join("lens.p3f");
    std::fs::write(&file, LENS_SCENE).unwrap();
    let server = Server::start(&file, &["--spp", "4"]);
    let browser = Browser::start(&driver, &work.join("profile"));
    browser.cmd("POST", "url", json!({"url": server.url}));
    browser.wait_for("document.body.dataset.complete === 'true'");

    // Fitted: scaled up to the room there is, 4:3 kept, all of it in the window.
    let fits = |b: &Value, w: f64, h: f64| {
        let f = |k: &str| b[k].as_f64().unwrap();
        assert!(
            f("bottom") <= f("window_height") && f("right") <= f("window_width"),
            "{b}"
        );
        assert!((f("width") / f("height") - w / h).abs() < 0.01, "aspect: {b}");
        assert!((f("width") - w * f("scale")).abs() < 0.5, "{b}");
    };
    let fitted = browser.picture_box();
    fits(&fitted, 320.0, 240.0);
    assert!(fitted["scale"].as_f64().unwrap() > 1.5, "scaled up: {fitted}");
    assert!(browser
        .tree_of_pixel(250, 60)
        .starts_with("pixel (250, 60) of 320x240"));

    // The lens pixel at the centre: its 4 eye rays hit the sphere in a small blurred
    // spot; nothing is drawn far from the clicked pixel (lines from the lens positions
    // used to fan out to the picture's edges).
    let head = browser.tree_of_pixel(160, 120);
    assert!(head.starts_with("pixel (160, 120)"), "{head}");
    let far = browser.run(
        "const o = document.getElementById('overlay');\n\
         const d = o.getContext('2d').getImageData(0, 0, o.width, o.height).data;\n\
         let painted = 0, far = 0;\n\
         for (let i = 3; i < d.length; i += 4) { if (d[i] === 0) continue; painted++;\n\
           const p = (i - 3) / 4, x = p % o.width, y = Math.floor(p / o.width);\n\
           if (Math.hypot(x - 160.5, y - 120.5) > 40) far++; }\n\
         return [painted, far];",
    );
    assert!(
        far[0].as_u64().unwrap() > 10 && far[1] == 0,
        "painted, far from the pixel: {far}"
    );
    browser.screenshot(&shots.join("6-lens-pixel.png"));

    // 1:1: one picture pixel per CSS pixel (device pixel ratio 1 here); clicks still
    // find their pixel.
    browser.cmd(
        "POST",
        "execute/sync",
        json!({"script": "document.getElementById('actual').click();", "args": []}),
    );
    browser.wait_for("document.body.dataset.actual === 'true'");
    let actual = browser.picture_box();
    assert_eq!(
        (actual["width"].as_f64(), actual["height"].as_f64()),
        (Some(320.0), Some(240.0)),
        "{actual}"
    );
    assert!(browser
        .tree_of_pixel(40, 200)
        .starts_with("pixel (40, 200) of 320x240"));
    browser.screenshot(&shots.join("7-one-to-one.png"));

    // A square picture of 512 x 512, fitted again: wider than tall room, so the height
    // decides, and none of it is cut off at the bottom.
    browser.cmd(
        "POST",
        "execute/sync",
        json!({"script": "document.getElementById('actual').click();", "args": []}),
    );
    browser.wait_for("document.body.dataset.actual === 'false'");
    browser.type_into("width", "512");
    browser.type_into("height", "512");
    browser.wait_for(
        "document.getElementById('picture').height === 512 && document.getElementById('picture').width === 512 \
         && document.body.dataset.complete === 'true'",
    );
    fits(&browser.picture_box(), 512.0, 512.0);
    assert!(browser
        .tree_of_pixel(500, 7)
        .starts_with("pixel (500, 7) of 512x512"));
    browser.screenshot(&shots.join("8-fitted-512.png"));

    // Refused settings say why, with the limits the server sent.
    for (typed, says) in [
        (
            "40000",
            "width: 40000 refused, a whole number from 1 to 32768; kept 512",
        ),
        (
            "abc",
            "width: abc refused, a whole number from 1 to 32768; kept 512",
        ),
    ] {
        browser.type_into("width", typed);
        browser.wait_for("document.body.dataset.optionsError !== undefined");
        let shown = browser.run("return document.getElementById('options-error').innerText;");
        assert_eq!(shown.as_str(), Some(says));
        assert_eq!(
            browser
                .run("return document.getElementById('width').value;")
                .as_str(),
            Some("512")
        );
        if typed == "40000" {
            browser.screenshot(&shots.join("9-width-error.png"));
        }
        browser.run("delete document.body.dataset.optionsError;");
    }
}

/// A P3F scene with what the course's later assignments add: a rough mirror sphere
/// over a plane, and a sphere moving along x while the shutter is open.
const EFFECTS_SCENE: &str = "bclr 0.6 0.7 0.9\nv\nfrom 0 1 6\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\n\
resolution 160 120\nl 2 3 4 1 1 1\nf 0.9 0.3 0.2 0.3 1 1 1 0.7 30 0 1 roughness 0.4\ns -1 0 0 0.8\n\
f 0.2 0.9 0.3 1 1 1 1 0 30 0 1\nsm 0.5 0 0 1.5 0 0 0.6 0 1\nf 0.8 0.8 0.8 1 1 1 1 0 30 0 1\npl 0 -1 0 1 -1 0 0 -1 -1\n";

impl Browser {
    /// Sets the select or field `id` to `value` as a user would, firing its change.
    fn set(&self, id: &str, value: &str) {
        self.run(&format!(
            "const e = document.getElementById('{id}'); e.value = '{value}';\n\
             e.dispatchEvent(new Event('change'));"
        ));
    }

    /// Clicks checkbox `id`.
    fn click(&self, id: &str) {
        self.run(&format!("document.getElementById('{id}').click();"));
    }

    /// Waits for the next generation's converged picture; its hash and generation.
    fn next_picture(&self, gen: u64) -> (u64, u64) {
        self.wait_for(&format!(
            "Number(document.body.dataset.gen) > {gen} && document.body.dataset.complete === 'true'"
        ));
        self.picture()
    }
}

/// The switches of the course's later work: path tracing with its progress and a
/// pixel's path, roughness off and on, the shutter; a shutter closing before it
/// opens is refused and says why; the grid and no acceleration give the BVH's picture.
#[test]
fn the_integrator_roughness_and_shutter_switch_and_a_path_tracing_pixel_shows_its_path() {
    let Some((driver, shots, work)) = setup("effects") else {
        return;
    };
    let file = work.join("effects.p3f");
    std::fs::write(&file, EFFECTS_SCENE).unwrap();
    let server = Server::start(&file, &["--spp", "4"]);
    let browser = Browser::start(&driver, &work.join("profile"));
    browser.cmd("POST", "url", json!({"url": server.url}));
    browser.wait_for("document.body.dataset.complete === 'true'");
    let (whitted, gen) = browser.picture();
    for id in ["rough", "shutter-open", "shutter-close", "integrator", "accel"] {
        let off = browser.run(&format!("return document.getElementById('{id}').disabled;"));
        assert_eq!(off.as_bool(), Some(false), "{id} is offered");
    }

    // Path tracing: another picture, its progress in samples per second.
    browser.set("integrator", "path");
    let (path, gen) = browser.next_picture(gen);
    assert_ne!(path, whitted);
    let status = browser.run("return document.getElementById('status').innerText;");
    let status = status.as_str().unwrap();
    assert!(
        status.contains("samples 4/4") && status.contains("samples/s"),
        "{status}"
    );
    browser.screenshot(&shots.join("10-path-traced.png"));

    // A pixel on the rough sphere: its paths, vertex by vertex, drawn over the picture.
    assert!(browser.tree_of_pixel(48, 60).starts_with("pixel (48, 60)"));
    let tree = browser.run("return document.getElementById('tree').innerText;");
    let tree = tree.as_str().unwrap();
    assert!(tree.contains("vertex 1: sphere (s) at line 11"), "{tree}");
    assert!(tree.contains("BSDF sample"), "{tree}");
    assert!(tree.contains("light sample at"), "{tree}");
    let drawn = browser.run(
        "const o = document.getElementById('overlay');\n\
         const d = o.getContext('2d').getImageData(0, 0, o.width, o.height).data;\n\
         let n = 0; for (let i = 3; i < d.length; i += 4) n += d[i] > 0; return n;",
    );
    assert!(
        drawn.as_u64().is_some_and(|n| n > 20),
        "paths over the picture: {drawn}"
    );
    browser.screenshot(&shots.join("11-path-pixel.png"));

    // Roughness off: the mirror turns sharp; back on: the picture as before.
    browser.click("rough");
    let (smooth, gen) = browser.next_picture(gen);
    assert_ne!(smooth, path);
    browser.click("rough");
    let (rough_again, gen) = browser.next_picture(gen);
    assert_eq!(rough_again, path, "the same settings give the same picture");

    // The shutter closes at 0.25: the moving sphere smears over a quarter of the way.
    browser.type_into("shutter-close", "0.25");
    let (short, gen) = browser.next_picture(gen);
    assert_ne!(short, path);
    browser.screenshot(&shots.join("12-short-shutter.png"));

    // Closing before it opens: refused, saying why; nothing rendered.
    browser.type_into("shutter-open", "0.5");
    browser.wait_for("document.body.dataset.optionsError !== undefined");
    let shown = browser.run("return document.getElementById('options-error').innerText;");
    assert_eq!(
        shown.as_str(),
        Some("shutter: 0.5 refused, the shutter must open no later than it closes; kept 0")
    );
    assert_eq!(browser.picture(), (short, gen));

    // Another acceleration structure: a new render, the same picture.
    browser.set("accel", "grid");
    let (grid, gen) = browser.next_picture(gen);
    assert_eq!(grid, short, "the grid renders the BVH's picture");
    browser.set("accel", "none");
    let (none, _) = browser.next_picture(gen);
    assert_eq!(none, short, "the scan renders the BVH's picture");
}

impl Browser {
    /// True if the picture's canvas holds exactly the 8-bit pixels of the global
    /// `expression` (compare.js's `reference`, `flipMap`).
    fn canvas_shows(&self, expression: &str) -> bool {
        let same = self.run(&format!(
            "const c = document.getElementById('picture'), shown = {expression};\n\
             const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;\n\
             if (!shown || shown.rgb.length * 4 !== d.length * 3) return false;\n\
             for (let i = 0, j = 0; j < d.length; i += 3, j += 4)\n\
               if (d[j] !== shown.rgb[i] || d[j + 1] !== shown.rgb[i + 1] || d[j + 2] !== shown.rgb[i + 2]) return false;\n\
             return true;"
        ));
        same == json!(true)
    }
}

/// The Cornell box (examples/cornell.p3f, path-traced) at 96 x 96.
fn small_cornell() -> String {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/cornell.p3f")).unwrap();
    text.replace("resolution 256 256", "resolution 96 96")
}

/// A reference beside the live picture: `--reference` at start, each pass measured
/// (FLIP falls as samples accumulate, plotted), A/B shows exactly the reference, the
/// FLIP map exactly the last pass's map, the file picker loads another (a float
/// one: HDR-FLIP); the denoise switch shows denoised frames while the samples
/// accumulate (greyed out, and skipped saying so, without Open Image Denoise).
#[test]
fn a_reference_flips_against_the_live_picture_with_its_flip_map_and_error_plot() {
    let Some((driver, shots, work)) = setup("compare") else {
        return;
    };
    let file = work.join("cornell.p3f");
    std::fs::write(&file, small_cornell()).unwrap();
    let (reference, float_reference) = (work.join("ref.png"), work.join("ref.pfm"));
    for (out, spp) in [(&reference, "256"), (&float_reference, "64")] {
        let made = Command::new(env!("CARGO_BIN_EXE_nffrt"))
            .args([
                "render",
                file.to_str().unwrap(),
                "--spp",
                spp,
                "-q",
                "-o",
                out.to_str().unwrap(),
            ])
            .status()
            .unwrap();
        assert!(made.success());
    }
    let server = Server::start(
        &file,
        &["--spp", "16", "--reference", reference.to_str().unwrap()],
    );
    let browser = Browser::start(&driver, &work.join("profile"));
    browser.cmd("POST", "url", json!({"url": server.url}));
    browser.wait_for(
        "document.body.dataset.reference === '96x96' && document.body.dataset.complete === 'true' \
         && Number(document.body.dataset.scores) >= 5",
    );
    let scores = browser.run("return scores.map((s) => [s.samples, s.mean]);");
    let scores: Vec<(u64, f64)> = serde_json::from_value(scores).unwrap();
    assert_eq!(scores.iter().map(|s| s.0).collect::<Vec<_>>(), [1, 2, 4, 8, 16]);
    assert!(
        scores[0].1 > scores[4].1 && scores[4].1 > 0.0,
        "FLIP falls: {scores:?}"
    );
    let plotted = browser.run(
        "const p = document.getElementById('plot'), d = p.getContext('2d').getImageData(0, 0, p.width, p.height).data;\n\
         let n = 0; for (let i = 0; i < d.length; i += 4) n += d[i] === 0x7c && d[i + 1] === 0xc4; return n;",
    );
    assert!(
        plotted.as_u64().is_some_and(|n| n > 30),
        "the plot's line: {plotted}"
    );

    // A/B: the reference, exactly; the FLIP map, exactly; back to the live picture.
    browser.click("view-ab");
    browser.wait_for("document.body.dataset.view === 'reference'");
    assert!(browser.canvas_shows("reference"), "A/B shows the reference");
    browser.screenshot(&shots.join("6-reference.png"));
    browser.click("show-flip");
    browser.wait_for("document.body.dataset.view === 'flip'");
    assert!(browser.canvas_shows("flipMap"), "the FLIP map is shown");
    browser.screenshot(&shots.join("7-flip-map.png"));
    browser.click("show-flip");
    browser.wait_for("document.body.dataset.view === 'live'");
    assert!(
        browser.canvas_shows("{rgb: lastLive.rgb}"),
        "the live picture again"
    );

    // The file picker: a float reference, measured by HDR-FLIP.
    let picker = browser.cmd(
        "POST",
        "element",
        json!({"using": "css selector", "value": "#reference-file"}),
    );
    let picker = picker[ELEMENT].as_str().unwrap().to_string();
    browser.cmd(
        "POST",
        &format!("element/{picker}/value"),
        json!({"text": float_reference.to_str().unwrap()}),
    );
    // (A new reference starts the count again.)
    browser.wait_for(
        "document.getElementById('reference-name').textContent.startsWith('ref.pfm: 96×96, HDR-FLIP') \
         && Number(document.body.dataset.scores) >= 5 && document.body.dataset.complete === 'true'",
    );

    // Denoised frames while the samples accumulate.
    let denoiser = browser.run("return scene.denoiser;");
    if denoiser.is_null() {
        assert_eq!(
            browser.run("return document.getElementById('denoise').disabled;"),
            json!(true)
        );
        skip::skip_unless_required(
            "NFFRT_REQUIRE_OIDN",
            "Open Image Denoise is not installed (pip install pyoidn, or NFFRT_OIDN)",
        );
        return;
    }
    let gen = browser
        .run("return Number(document.body.dataset.gen);")
        .as_u64()
        .unwrap();
    let noisy = browser.run("return scores.map((s) => s.mean);");
    let noisy: Vec<f64> = serde_json::from_value(noisy).unwrap();
    browser.click("denoise");
    browser.wait_for(&format!(
        "Number(document.body.dataset.gen) > {gen} && document.body.dataset.denoised === 'true' \
         && document.body.dataset.complete === 'true' && scores.filter((s) => s.denoised).length >= 5"
    ));
    let denoised = browser.run("return scores.filter((s) => s.denoised).map((s) => s.mean);");
    let denoised: Vec<f64> = serde_json::from_value(denoised).unwrap();
    let all = browser.run("return JSON.stringify(scores);");
    assert_eq!(denoised.len(), 5, "every pass measured denoised: {all}");
    assert!(
        denoised[0] < noisy[0],
        "one sample denoised is closer: {denoised:?} against {noisy:?}"
    );
    browser.screenshot(&shots.join("8-denoised.png"));
}

/// An AFF ball keyed across 4 frames (as tests/view_frames.rs's), on a grey
/// background so the pictures of two frames differ anywhere the ball goes.
const AFF_BALL: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 28 hither 1 resolution 160 120\n\
    b 0.2 0.2 0.3\nam 1 1 1\nfm 0.9 0.5 0.1  0 0 0  0 0 0  1 0 1\na 0 3 4\n\
    x ball { s 0 0 0 0.6 }\n\
    k ball { transl 4  -1 -2 0 0 0 0 0   0 -2 0 0 0 0 0   3 2 0 0 0 0 0   4 2 0 0 0 0 0 }\n";

/// An AFF scene's page: the time slider with its frame and time, a frame chosen on
/// it rendered and kept in the URL (and shown again after the page reloads), and
/// play moving through the frames until paused.
#[test]
fn an_animated_scene_has_a_time_slider_play_and_its_frame_in_the_url() {
    let Some((driver, shots, work)) = setup("animation") else {
        return;
    };
    let file = work.join("ball.aff");
    std::fs::write(&file, AFF_BALL).unwrap();
    let server = Server::start(&file, &[]);
    let browser = Browser::start(&driver, &work.join("profile"));
    browser.cmd("POST", "url", json!({"url": server.url}));
    browser.wait_for("document.body.dataset.complete === 'true'");
    let shown = browser.run(
        "const s = document.getElementById('frame-slider');\n\
         return [document.getElementById('animation').hidden, s.max, document.body.dataset.animFrame];",
    );
    assert_eq!(shown, json!([false, "3", "0"]), "the slider, frames 0 to 3, at 0");
    let (first, gen) = browser.picture();

    // Frame 2 on the slider: its picture, its time (0.75 x 2 = 1.5), the URL.
    browser.set_slider(2);
    let (second, _) = browser.next_picture(gen);
    assert_ne!(first, second, "frame 2 shows the ball elsewhere");
    let label = browser.run("return document.getElementById('frame-label').innerText;");
    assert_eq!(label, json!("2 / 3 · time 1.5"));
    let url = browser.run("return location.href;");
    assert!(url.as_str().unwrap().contains("frame=2"), "{url}");
    browser.screenshot(&shots.join("13-animation-frame-2.png"));

    // The page reloaded at that URL: frame 2 again, the same picture.
    browser.cmd("POST", "url", json!({"url": url}));
    browser.wait_for("document.body.dataset.complete === 'true'");
    assert_eq!(browser.run("return document.body.dataset.animFrame;"), json!("2"));
    let (again, gen) = browser.picture();
    assert_eq!(again, second, "the reloaded page shows frame 2");

    // Play: the frames move on (past the last, back to 0); pause: the frame refines.
    browser.run("document.getElementById('play').click();");
    browser.wait_for("document.body.dataset.animFrame === '3'");
    browser.wait_for("document.body.dataset.animFrame === '0'");
    browser.run("document.getElementById('play').click();");
    let paused =
        browser.run("return [document.body.dataset.playing, document.getElementById('play').innerText];");
    assert_eq!(paused, json!(["false", "Play"]));
    browser.next_picture(gen);
    eprintln!("screenshots in {}", shots.display());
}

impl Browser {
    /// Moves the time slider to `frame` as a user would, firing its input event.
    fn set_slider(&self, frame: u32) {
        self.run(&format!(
            "const e = document.getElementById('frame-slider'); e.value = '{frame}';\n\
             e.dispatchEvent(new Event('input'));"
        ));
    }
}
