//! Keyframe blocks (`k NAME { ... }`) and animated triangles (`tpa`): rows of keys,
//! each count checked against the rows that follow it and each key's time against
//! the one before.

use super::error::Read;
use super::parser::{invalid, loc, FileParser, Loc};
use super::scene::{AnimatedTriangle, Track, TriangleKey, VisibilityKey};
use super::spline::{PositionKey, PositionSpline, RotationKey, RotationSpline, Tcb};
use crate::nff::{parse_f32, ParseError, Token};

/// A kind of curve in a keyframe block and the names of its numbers in messages
/// (written once: a block may hold thousands of keys).
struct Curve {
    /// As written.
    name: &'static str,
    /// A key's time.
    time: &'static str,
    /// A key's value (`transl`, `scale`).
    value: &'static str,
    /// A key's tension, continuity and bias.
    tcb: [&'static str; 3],
}

macro_rules! curve {
    ($name:literal) => {
        Curve {
            name: $name,
            time: concat!("'", $name, "' key time"),
            value: concat!("'", $name, "' key x y z"),
            tcb: [
                concat!("'", $name, "' key tension"),
                concat!("'", $name, "' key continuity"),
                concat!("'", $name, "' key bias"),
            ],
        }
    };
}

/// The kinds of curve, in the order of [`Track`]'s fields.
const CURVES: [Curve; 4] = [
    curve!("transl"),
    curve!("rot"),
    curve!("scale"),
    curve!("visibility"),
];

/// The curves' keys need this many keys (the first and last only shape tangents).
const MIN_SPLINE_KEYS: u32 = 4;

impl FileParser<'_, '_, '_> {
    /// ```text
    /// k NAME {
    ///   transl N      time x y z  tension continuity bias        (N rows)
    ///   rot N         time ax ay az degrees  tension continuity bias
    ///   scale N       time sx sy sz  tension continuity bias
    ///   visibility N  time 0|1
    /// }
    /// ```
    /// Each curve at most once, in any order; `transl`, `rot` and `scale` take at
    /// least 4 keys. The block animates the transforms `x NAME`, the camera
    /// (`camera`) or a light (`la NAME`); a later block of the same name replaces it.
    pub(super) fn keyframes(&mut self, kw: &Token) -> Read {
        let (name, _) = self.name("the keyframe block's name")?;
        self.open_brace(&format!("'k {name}'"))?;
        let mut track = Track {
            name,
            translation: None,
            rotation: None,
            scale: None,
            visibility: Vec::new(),
            at: self.at(kw),
        };
        let mut seen = [false; 4];
        loop {
            let tok = self.p.next_token();
            let kind = match tok {
                Some(t) if t.text == b"}" => break,
                Some(t) => CURVES.iter().position(|c| c.name.as_bytes() == t.text),
                None => None,
            };
            let (Some(kind), Some(t)) = (kind, tok) else {
                return Err(self
                    .p
                    .expected(tok, "'transl', 'rot', 'scale', 'visibility' or '}'")
                    .into());
            };
            if std::mem::replace(&mut seen[kind], true) {
                return Err(invalid(
                    loc(&t),
                    format!("a second '{}' in one keyframe block", CURVES[kind].name),
                )
                .into());
            }
            let curve = &CURVES[kind];
            let (n, n_at) = self.p.count(&format!("the number of '{}' keys", curve.name))?;
            if kind != 3 && n < MIN_SPLINE_KEYS {
                let message = format!(
                    "'{}' needs at least {MIN_SPLINE_KEYS} keys (the first and the last only shape the curve), not {n}",
                    curve.name
                );
                return Err(invalid(n_at, message).into());
            }
            match kind {
                0 | 2 => {
                    let keys = self.position_keys(n, n_at, curve)?;
                    let spline = Some(PositionSpline::new(&keys));
                    if kind == 0 {
                        track.translation = spline;
                    } else {
                        track.scale = spline;
                    }
                }
                1 => track.rotation = Some(RotationSpline::new(&self.rotation_keys(n, n_at)?)),
                _ => track.visibility = self.visibility_keys(n, n_at)?,
            }
            self.no_more_rows(n, n_at, curve)?;
        }
        if !seen.contains(&true) {
            return Err(invalid(loc(kw), format!("keyframe block '{}' has no keys", track.name)).into());
        }
        self.add_track(track);
        Ok(())
    }

    /// Files a keyframe block under its name, replacing (with a warning) an earlier one.
    fn add_track(&mut self, track: Track) {
        match self.b.track_names.get(&track.name) {
            Some(&i) => {
                // A file included twice gives the same block twice: no news.
                let earlier = self.b.scene.tracks[i as usize].at;
                if earlier != track.at {
                    let message = format!(
                        "a second keyframe block '{}' replaces the one at {}",
                        track.name,
                        self.b.describe(earlier)
                    );
                    self.b.warn(track.at, message);
                }
                self.b.scene.tracks[i as usize] = track;
            }
            None => {
                let index = self.b.scene.tracks.len() as u32;
                self.b.track_names.insert(track.name.clone(), index);
                self.b.scene.tracks.push(track);
            }
        }
    }

    /// `n` rows of `time x y z tension continuity bias`.
    fn position_keys(&mut self, n: u32, n_at: Loc, curve: &Curve) -> Result<Vec<PositionKey>, ParseError> {
        let (mut keys, mut times) = (Vec::new(), Vec::new());
        for row in 0..n {
            let time = self.key_time(row, n, n_at, curve, &times)?;
            times.push(time);
            let value = self.p.vec3(curve.value)?;
            let tcb = self.tcb(curve)?;
            keys.push(PositionKey {
                time,
                value: [value.x, value.y, value.z].map(f64::from),
                tcb,
            });
        }
        Ok(keys)
    }

    /// `n` rows of `time ax ay az degrees tension continuity bias`.
    fn rotation_keys(&mut self, n: u32, n_at: Loc) -> Result<Vec<RotationKey>, ParseError> {
        let (mut keys, mut times) = (Vec::new(), Vec::new());
        for row in 0..n {
            let time = self.key_time(row, n, n_at, &CURVES[1], &times)?;
            times.push(time);
            let axis = self.p.vec3("'rot' key axis x y z")?;
            let degrees = self.p.number("'rot' key angle in degrees")?;
            let tcb = self.tcb(&CURVES[1])?;
            keys.push(RotationKey {
                time,
                axis: [axis.x, axis.y, axis.z].map(f64::from),
                angle: (degrees as f64).to_radians(),
                tcb,
            });
        }
        Ok(keys)
    }

    /// `n` rows of `time visible` (0 hides, any other whole number shows).
    fn visibility_keys(&mut self, n: u32, n_at: Loc) -> Result<Vec<VisibilityKey>, ParseError> {
        let mut keys = Vec::new();
        for row in 0..n {
            // In any order (see `Track::visible_at`).
            let time = self.key_time(row, n, n_at, &CURVES[3], &[])?;
            let (flag, _) = self.integer("'visibility' flag, 0 or 1")?;
            keys.push(VisibilityKey {
                time: time as f32,
                visible: flag != 0,
            });
        }
        Ok(keys)
    }

    /// A key's `tension continuity bias`.
    fn tcb(&mut self, curve: &Curve) -> Result<Tcb, ParseError> {
        Ok(Tcb {
            tension: self.p.number(curve.tcb[0])? as f64,
            continuity: self.p.number(curve.tcb[1])? as f64,
            bias: self.p.number(curve.tcb[2])? as f64,
        })
    }

    /// The time that starts row `row` of the `n` that the count at `n_at` promises,
    /// after keys at `before`. A time before the previous key's is tolerated (with a
    /// warning; BART's robot scene has one) and read as the original reads it: at
    /// each time the curve follows the first segment that reaches past it. Refused:
    /// a time equal to the key's two before (a Kochanek-Bartels tangent would divide
    /// by zero).
    fn key_time(
        &mut self,
        row: u32,
        n: u32,
        n_at: Loc,
        curve: &Curve,
        before: &[f64],
    ) -> Result<f64, ParseError> {
        let tok = match self.p.peek() {
            Some(t) if parse_f32(t.text).is_some() => t,
            tok => {
                let found = tok.map_or("the end of the file".to_string(), |t| {
                    format!("{} at line {}", t.quoted(), t.line)
                });
                let message = format!(
                    "'{} {n}' promises {n} keys, but {row} rows follow ({found} instead of row {})",
                    curve.name,
                    row + 1
                );
                return Err(invalid(n_at, message));
            }
        };
        let time = self.p.number(curve.time)? as f64;
        if before.len() >= 2 && before[before.len() - 2] == time {
            let message = format!(
                "a key at time {time} two keys after one at the same time: the curve's tangent is undefined"
            );
            return Err(invalid(loc(&tok), message));
        }
        if let Some(&last) = before.last().filter(|&&last| time < last) {
            let message = format!("key time {time} is before the previous key's, {last}: the curve takes the first keys that reach each time");
            self.warn(&tok, message);
        }
        Ok(time)
    }

    /// Refuses a row after the `n` that the count at `n_at` promised.
    fn no_more_rows(&self, n: u32, n_at: Loc, curve: &Curve) -> Result<(), ParseError> {
        match self.p.peek() {
            Some(t) if parse_f32(t.text).is_some() => Err(invalid(
                n_at,
                format!(
                    "'{} {n}' promises {n} keys, but more rows follow (line {})",
                    curve.name, t.line
                ),
            )),
            _ => Ok(()),
        }
    }

    /// ```text
    /// tpa N
    ///   time  x y z nx ny nz  x y z nx ny nz  x y z nx ny nz     (N times)
    /// ```
    /// A triangle given at `N` times, in increasing order: its corners and their
    /// normals move linearly between them.
    pub(super) fn animated_triangle(&mut self, kw: &Token) -> Read {
        let (n, n_at) = self.p.count("the number of times of the animated triangle")?;
        if n == 0 {
            return Err(invalid(n_at, "an animated triangle needs at least one time").into());
        }
        let mut keys: Vec<TriangleKey> = Vec::new();
        for _ in 0..n {
            let at = self.p.peek().map_or(n_at, |t| loc(&t));
            let time = self.p.number("the animated triangle's time")?;
            if let Some(last) = keys.last().filter(|k| time < k.time) {
                return Err(invalid(
                    at,
                    format!("time {time} is before the previous one, {}", last.time),
                )
                .into());
            }
            let mut key = TriangleKey {
                time,
                vertices: [crate::math::Vec3::ZERO; 3],
                normals: [crate::math::Vec3::ZERO; 3],
            };
            for corner in 0..3 {
                key.vertices[corner] = self.p.vec3("the animated triangle's vertex x y z")?;
                key.normals[corner] = self.p.vec3("the animated triangle's normal x y z")?;
            }
            keys.push(key);
        }
        self.admit_triangles(kw)?;
        let material = self.p.current_material(loc(kw));
        let triangle = AnimatedTriangle {
            node: self.b.node(),
            material,
            keys,
            at: self.at(kw),
        };
        self.b.scene.animated_triangles.push(triangle);
        Ok(())
    }
}
