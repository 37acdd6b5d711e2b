//! A tour file made into a [`Tour`]: every entry validated against the
//! space (each error named by the file, the entry and the field), the legs
//! cut into pieces, the keyframes placed in the copies their words name,
//! the path through them built, and the settings and captions in force
//! from each entry on.

use super::file::{EntryDesc, MAX_KEYFRAMES, MAX_SECONDS, MAX_TOTAL_WORDS, MAX_WORD, SceneDesc, TourDesc, TourError};
use super::path::{PathKey, Segment, TourPath};
use super::{Tour, TourSettings};
use crate::geometry::isometry;
use crate::space::Space;
use crate::space::file::from_rows;
use crate::space::rule::{OnOff, Walls};
use crate::trace::Fog;
use glam::{DMat4, DVec3, DVec4};

/// How far off its model a position may be before it is an error (it is
/// then normalised exactly).
const POINT_TOLERANCE: f64 = 1e-6;
/// How far outside a face a keyframe may sit (chart units), as rounding.
const OUTSIDE_TOLERANCE: f64 = 1e-9;
/// Longest piece a leg is cut into: a screw of at most this length and
/// turn stays far from the half turn, where the screw between two poses
/// stops being unique.
const LEG_PIECE_DISTANCE: f64 = 1.0;
const LEG_PIECE_ANGLE: f64 = core::f64::consts::FRAC_PI_2;

impl TourDesc {
    /// Validates every entry against `space` (the space the file names,
    /// resolved by the caller) and builds the tour; `path` names the file
    /// in errors.
    ///
    /// # Errors
    /// The first bad field, named `keyframes[i].field`.
    pub fn build(&self, space: &Space, path: &str) -> Result<Tour, TourError> {
        let field = |field: String, message: String| TourError::Field {
            path: path.into(),
            field,
            message,
        };
        let g = space.geometry();
        let fov = self.fov_y_degrees;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(field("fov_y_degrees".into(), format!("must be in (0, 180), got {fov}")));
        }
        let reflections = self.scene.reflections;
        if reflections > crate::trace::MAX_REFLECTIONS {
            return Err(field(
                "scene.reflections".into(),
                format!("at most {}, got {reflections}", crate::trace::MAX_REFLECTIONS),
            ));
        }
        if self.keyframes.is_empty() {
            return Err(field("keyframes".into(), "a tour needs at least one keyframe".into()));
        }
        if self.keyframes.len() > MAX_KEYFRAMES {
            return Err(field(
                "keyframes".into(),
                format!("{} entries, more than {MAX_KEYFRAMES}", self.keyframes.len()),
            ));
        }
        let faces = space.faces().len();
        let check_word = |name: String, word: &[usize]| -> Result<(), TourError> {
            if word.len() > MAX_WORD {
                return Err(field(name, format!("{} faces, more than {MAX_WORD}", word.len())));
            }
            match word.iter().position(|&f| f >= faces) {
                Some(i) => Err(field(
                    format!("{name}[{i}]"),
                    format!("is face {}, but the space has {faces} faces", word[i]),
                )),
                None => Ok(()),
            }
        };
        let seconds = |name: String, s: f64| -> Result<f64, TourError> {
            if s.is_finite() && s > 0.0 && s <= MAX_SECONDS {
                Ok(s)
            } else {
                Err(field(
                    name,
                    format!("must be a positive number of seconds (at most {MAX_SECONDS}), got {s}"),
                ))
            }
        };

        let mut keys: Vec<PathKey> = Vec::new();
        // The faces the cells name in all: bounded, so any file is
        // checked in bounded time (each word is a product of exact
        // elements).
        let mut total_words = 0usize;
        let too_many_faces = |total: usize| {
            format!("the keyframes' cells and loops name {total} faces in all, more than {MAX_TOTAL_WORDS}")
        };
        let mut segments = Vec::new();
        // The file entry each path key came from.
        let mut key_entry = Vec::new();
        let mut settings = vec![(0.0, TourSettings::start(&self.scene))];
        let mut captions: Vec<(f64, String)> = Vec::new();
        for (i, e) in self.keyframes.iter().enumerate() {
            let name = |f: &str| format!("keyframes[{i}].{f}");
            let legs = [e.fly.is_some(), e.turn.is_some(), e.loop_.is_some()];
            let leg_count = legs.iter().filter(|&&b| b).count();
            let is_key = e.time.is_some();
            let has_pose = e.position.is_some() || e.isometry.is_some();
            if leg_count + usize::from(is_key) != 1 {
                return Err(field(
                    format!("keyframes[{i}]"),
                    "must be one keyframe (time and a pose) or one leg (fly, turn or loop)".into(),
                ));
            }
            let start = keys.last().map_or(0.0, |k| k.time);
            if is_key {
                let t = e.time.unwrap_or(0.0);
                if !(t.is_finite() && (0.0..=MAX_SECONDS).contains(&t)) {
                    return Err(field(
                        name("time"),
                        format!("must be a time in [0, {MAX_SECONDS}] s, got {t}"),
                    ));
                }
                if let Some(prev) = keys.last()
                    && t <= prev.time
                {
                    return Err(field(
                        name("time"),
                        format!(
                            "{t} s comes before or at the previous entry's end, {} s: times must increase",
                            prev.time
                        ),
                    ));
                }
                check_word(name("cell"), &e.cell)?;
                total_words += e.cell.len();
                if total_words > MAX_TOTAL_WORDS {
                    return Err(field(name("cell"), too_many_faces(total_words)));
                }
                let local = match (e.position, e.isometry) {
                    (Some(_), Some(_)) => {
                        return Err(field(
                            format!("keyframes[{i}]"),
                            "has both a position and an isometry".into(),
                        ));
                    }
                    (None, None) => {
                        return Err(field(
                            format!("keyframes[{i}]"),
                            "a keyframe needs a position or an isometry".into(),
                        ));
                    }
                    (Some(p), None) => pose_from_look(space, p, e.look, e.up).map_err(|(f, m)| field(name(f), m))?,
                    (None, Some(rows)) => {
                        if e.look.is_some() || e.up.is_some() {
                            return Err(field(
                                format!("keyframes[{i}]"),
                                "look and up go with a position, not an isometry".into(),
                            ));
                        }
                        let m = from_rows(rows);
                        if !m.is_finite() {
                            return Err(field(name("isometry"), "has a NaN or infinite entry".into()));
                        }
                        let err = isometry::isometry_error(g, m);
                        if err > 1e-6 {
                            return Err(field(
                                name("isometry"),
                                format!("is not an isometry of {g} space (form error {err:.2e})"),
                            ));
                        }
                        isometry::orthonormalize(g, m)
                    }
                };
                let which = if e.position.is_some() { "position" } else { "isometry" };
                if let Some(f) = space.outside_face(local.w_axis, OUTSIDE_TOLERANCE) {
                    return Err(field(
                        name(which),
                        format!("outside the fundamental domain, past face {f}: give the copy with `cell`"),
                    ));
                }
                if !keys.is_empty() {
                    segments.push(Segment::Smooth);
                }
                keys.push(PathKey {
                    time: t,
                    word: e.cell.clone(),
                    local,
                    stop: e.stop,
                });
                key_entry.push(i);
            } else {
                if has_pose || !e.cell.is_empty() || e.look.is_some() || e.up.is_some() {
                    return Err(field(
                        format!("keyframes[{i}]"),
                        "a leg starts where the previous entry ends: it takes no pose or cell".into(),
                    ));
                }
                let Some(prev) = keys.last().cloned() else {
                    return Err(field(
                        format!("keyframes[{i}]"),
                        "a leg needs a keyframe before it".into(),
                    ));
                };
                // The leg's pieces: (seconds, motion in the body frame, or
                // a loop's word).
                let (total, pieces): (f64, Vec<Piece>) = if let Some(f) = &e.fly {
                    let s = seconds(name("fly.seconds"), f.seconds)?;
                    if !f.speed.is_finite() || f.speed.abs() > 1e6 {
                        return Err(field(
                            name("fly.speed"),
                            format!("must be a finite speed, got {}", f.speed),
                        ));
                    }
                    let n = (f.speed.abs() * s / LEG_PIECE_DISTANCE).ceil().max(1.0);
                    if n as usize > MAX_KEYFRAMES {
                        return Err(field(
                            name("fly"),
                            format!("flies {:.0} units: too far for one leg", f.speed * s),
                        ));
                    }
                    let step = isometry::translation(g, DVec3::NEG_Z * (f.speed * s / n));
                    (s, vec![Piece::Motion(step); n as usize])
                } else if let Some(t) = &e.turn {
                    let s = seconds(name("turn.seconds"), t.seconds)?;
                    let angles = [t.yaw_degrees, t.pitch_degrees, t.roll_degrees];
                    if angles.iter().any(|a| !a.is_finite() || a.abs() > 1e5) {
                        return Err(field(name("turn"), "angles must be finite degrees".into()));
                    }
                    let [yaw, pitch, roll] = angles.map(f64::to_radians);
                    let biggest = yaw.abs().max(pitch.abs()).max(roll.abs());
                    let n = (biggest / LEG_PIECE_ANGLE).ceil().max(1.0);
                    let step = isometry::rotation(DVec3::Y, yaw / n)
                        * isometry::rotation(DVec3::X, pitch / n)
                        * isometry::rotation(DVec3::Z, roll / n);
                    (s, vec![Piece::Motion(step); n as usize])
                } else if let Some(l) = &e.loop_ {
                    let s = seconds(name("loop.seconds"), l.seconds)?;
                    check_word(name("loop.faces"), &l.faces)?;
                    total_words += l.faces.len();
                    if total_words > MAX_TOTAL_WORDS {
                        return Err(field(name("loop.faces"), too_many_faces(total_words)));
                    }
                    if l.faces.is_empty() || l.laps == 0 || l.laps as usize > MAX_KEYFRAMES {
                        return Err(field(name("loop"), "needs at least one face and 1 to 4096 laps".into()));
                    }
                    let element = space.cell_matrix(&space.cell_of_word(&l.faces));
                    if isometry::is_orientation_reversing(element) {
                        return Err(field(
                            name("loop.faces"),
                            "an odd number of mirror faces: a reflection is no motion; loop through an even number"
                                .into(),
                        ));
                    }
                    (s, vec![Piece::Word(l.faces.clone()); l.laps as usize])
                } else {
                    unreachable!("one leg, checked above")
                };
                if keys.len() + pieces.len() > MAX_KEYFRAMES {
                    return Err(field(
                        format!("keyframes[{i}]"),
                        format!("the tour's legs expand to more than {MAX_KEYFRAMES} keyframes"),
                    ));
                }
                let dt = total / pieces.len() as f64;
                let mut at = prev;
                for piece in pieces {
                    let mut next = match piece {
                        Piece::Motion(m) => {
                            let mut word = at.word.clone();
                            let (local, _) = space.wrap_with(at.local * m, 10_000, &mut |f| word.push(f));
                            PathKey {
                                time: at.time + dt,
                                word,
                                local,
                                stop: false,
                            }
                        }
                        Piece::Word(faces) => {
                            let mut word = at.word.clone();
                            word.extend_from_slice(&faces);
                            PathKey {
                                time: at.time + dt,
                                word,
                                local: at.local,
                                stop: false,
                            }
                        }
                    };
                    if next.word.len() > MAX_WORD {
                        return Err(field(
                            format!("keyframes[{i}]"),
                            format!("the leg leads more than {MAX_WORD} faces from the origin copy"),
                        ));
                    }
                    total_words += next.word.len();
                    if total_words > MAX_TOTAL_WORDS {
                        return Err(field(format!("keyframes[{i}]"), too_many_faces(total_words)));
                    }
                    next.stop = false;
                    segments.push(Segment::Screw);
                    keys.push(next.clone());
                    key_entry.push(i);
                    at = next;
                }
                if e.stop
                    && let Some(k) = keys.last_mut()
                {
                    k.stop = true;
                }
            }
            // Settings and captions start with the entry.
            let begins = if is_key {
                keys.last().map_or(0.0, |k| k.time)
            } else {
                start
            };
            let mut now = settings.last().map(|s| s.1.clone()).unwrap_or_default();
            let changed = now.apply(e).map_err(|(f, m)| field(name(f), m))?;
            if changed {
                settings.push((begins, now));
            }
            if let Some(c) = &e.caption {
                if c.len() > 4096 {
                    return Err(field(name("caption"), "longer than 4096 bytes".into()));
                }
                captions.push((begins, c.clone()));
            }
        }
        let path = TourPath::new(space, keys, segments).map_err(|e| {
            let entry = key_entry.get(e.key).copied().unwrap_or(0);
            field(format!("keyframes[{entry}]"), e.message)
        })?;
        Ok(Tour {
            fov_y_degrees: fov,
            scene: self.scene.clone(),
            path,
            settings,
            captions,
        })
    }
}

#[derive(Clone)]
enum Piece {
    Motion(DMat4),
    Word(Vec<usize>),
}

/// The pose at `position` looking along `look` with `up` up (both in the
/// frame parallel to the origin's), or the field that is wrong.
fn pose_from_look(
    space: &Space,
    position: [f64; 4],
    look: Option<[f64; 3]>,
    up: Option<[f64; 3]>,
) -> Result<DMat4, (&'static str, String)> {
    let g = space.geometry();
    let p = DVec4::from_array(position);
    if !g.is_point(p) {
        return Err(("position", format!("{position:?} is not a point of {g} space")));
    }
    let off = g.point_error::<f64>(p);
    if off > POINT_TOLERANCE * p.length().max(1.0) {
        return Err((
            "position",
            format!("{position:?} is not normalised for {g} space (off by {off:.2e})"),
        ));
    }
    let p = g.normalize_point::<f64>(p);
    let f = DVec3::from_array(look.unwrap_or([0.0, 0.0, -1.0]));
    let u = DVec3::from_array(up.unwrap_or([0.0, 1.0, 0.0]));
    if !f.is_finite() || f.length() < 1e-9 {
        return Err(("look", "must be a finite, non-zero direction".into()));
    }
    if !u.is_finite() || u.length() < 1e-9 {
        return Err(("up", "must be a finite, non-zero direction".into()));
    }
    let f = f.normalize();
    let r = f.cross(u);
    if r.length() < 1e-6 {
        return Err(("up", "is parallel to look".into()));
    }
    let r = r.normalize();
    let u = r.cross(f);
    let frame = DMat4::from_cols(r.extend(0.0), u.extend(0.0), (-f).extend(0.0), DVec4::W);
    Ok(isometry::orthonormalize(g, isometry::translation_to(g, p) * frame))
}

impl TourSettings {
    fn start(scene: &SceneDesc) -> TourSettings {
        TourSettings {
            suzanne: scene.suzanne,
            ..TourSettings::default()
        }
    }

    /// Applies an entry's settings; true when one was given.
    fn apply(&mut self, e: &EntryDesc) -> Result<bool, (&'static str, String)> {
        let mut changed = false;
        if let Some(l) = e.levels {
            if l > crate::trace::MAX_LEVELS {
                return Err(("levels", format!("{l}: at most {}", crate::trace::MAX_LEVELS)));
            }
            self.levels = l;
            changed = true;
        }
        if let Some(f) = &e.fog {
            if !(f.density.is_finite() && f.density >= 0.0) {
                return Err(("fog.density", format!("must be >= 0, got {}", f.density)));
            }
            if f.color.iter().any(|c| !c.is_finite() || *c < 0.0) {
                return Err(("fog.color", "must be three finite values >= 0".into()));
            }
            self.fog = (f.density > 0.0).then_some(Fog {
                density: f.density,
                color: f.color,
            });
            changed = true;
        }
        if let Some(s) = e.suzanne {
            self.suzanne = s;
            changed = true;
        }
        if let Some(c) = e.cell_colors {
            self.cell_colors = c;
            changed = true;
        }
        if let Some(h) = &e.hidden {
            if !(0.0..=1.0).contains(&h.on_fraction) {
                return Err((
                    "hidden.on_fraction",
                    format!("must be in [0, 1], got {}", h.on_fraction),
                ));
            }
            self.rule.hidden = (h.on_fraction < 1.0).then_some(OnOff {
                on_fraction: h.on_fraction,
                seed: h.seed,
            });
            changed = true;
        }
        if let Some(w) = &e.walls {
            if !(0.0..=1.0).contains(&w.density) {
                return Err(("walls.density", format!("must be in [0, 1], got {}", w.density)));
            }
            self.rule.walls = (w.density > 0.0).then_some(Walls {
                density: w.density,
                seed: w.seed,
            });
            changed = true;
        }
        Ok(changed)
    }
}
