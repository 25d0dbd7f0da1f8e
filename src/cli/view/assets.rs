//! The page, compiled into the binary: no build step, no CDN, works offline.
//! `index.html` names its script and style with `__TOKEN__`, which the server fills in.

/// The page.
pub const INDEX_HTML: &str = include_str!("assets/index.html");
/// Its script: the WebSocket client, camera controls, ray-tree panel.
pub const APP_JS: &str = include_str!("assets/app.js");
/// Its second script: the reference picture, the A/B flip, the FLIP map and the
/// plot of the error against the samples.
pub const COMPARE_JS: &str = include_str!("assets/compare.js");
/// Its style.
pub const APP_CSS: &str = include_str!("assets/app.css");
