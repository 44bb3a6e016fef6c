//! Animated scenes: a number of frames at a frame rate, a camera path given
//! by keys, and the time that moves the water.
//!
//! A scene with `[animation]` describes a sequence; [`SceneDesc::at_frame`]
//! gives the still scene of one frame, which renders like any other scene.
//! The terrain and erosion sections never change along a sequence, so every
//! frame shares one eroded terrain.

use serde::{Deserialize, Serialize};

use super::SceneDesc;
use super::validate::{MAX_AZIMUTH_DEG, in_range};
use crate::error::{RenderError, Result, fmt_f64};

/// Longest sequence, seconds: its time moves the ocean
/// (`water.ocean_time_s`, within ±1e6 s) and carries the clouds.
pub const MAX_DURATION_S: f64 = 1e6;

/// The animation of a scene: frames, frame rate and the camera path.
///
/// Frame `f` is at time `f / fps` seconds; the ocean's snapshot time
/// (`water.ocean_time_s`) advances by that time, and the clouds drift with
/// `clouds.wind_m_s` for it. Between two keys every keyed
/// value is interpolated linearly in the frame number; before the first key
/// and after the last the nearest key holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AnimationDesc {
    /// Frames in the sequence (1 = a still).
    pub frames: u32,
    /// Frames per second.
    pub fps: f64,
    /// Keys of the camera and sun, by strictly increasing frame (none = the
    /// `[camera]` and `[sun]` sections in every frame).
    pub keys: Vec<AnimationKey>,
}

/// The camera (and optionally the sun) at one frame of an animation. A
/// value left out takes the `[camera]` or `[sun]` section's value.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AnimationKey {
    /// The frame this key holds at.
    pub frame: u32,
    /// Camera position across the terrain, `[u, v]` in `[0, 1]`.
    pub position_uv: Option<[f64; 2]>,
    /// Point the camera looks toward, `[u, v]` in `[0, 1]`.
    pub target_uv: Option<[f64; 2]>,
    /// Height of the eye above the ground or water below it, metres.
    pub height_above_ground_m: Option<f64>,
    /// Pitch of the view, degrees.
    pub pitch_deg: Option<f64>,
    /// Sun elevation, degrees.
    pub sun_elevation_deg: Option<f64>,
    /// Sun compass azimuth, degrees.
    pub sun_azimuth_deg: Option<f64>,
}

impl Default for AnimationDesc {
    fn default() -> Self {
        Self {
            frames: 1,
            fps: 24.0,
            keys: Vec::new(),
        }
    }
}

impl AnimationDesc {
    /// Checks the frame count, frame rate and keys, naming the first bad key.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] for zero or more than a million
    /// frames, a frame rate outside `(0, 1000]`, a sequence longer than
    /// [`MAX_DURATION_S`], keys out of frame order or past the last frame,
    /// and keyed values outside their section's range (named as the key
    /// writes them: `animation.keys[3].position_uv[0]`).
    pub fn validate(&self) -> Result<()> {
        if !(1..=1_000_000).contains(&self.frames) {
            return Err(RenderError::invalid(
                "animation.frames",
                self.frames,
                "1 to 1 000 000",
            ));
        }
        if !(self.fps > 0.0 && self.fps <= 1000.0) {
            return Err(RenderError::invalid(
                "animation.fps",
                fmt_f64(self.fps),
                "in (0, 1000] frames per second",
            ));
        }
        let duration = self.time_s(self.frames - 1);
        if duration > MAX_DURATION_S {
            return Err(RenderError::invalid(
                "animation.frames, animation.fps",
                format_args!("{}, {}", self.frames, fmt_f64(self.fps)),
                &format!(
                    "a sequence of at most {} s (frames − 1) / fps; this one lasts {} s",
                    fmt_f64(MAX_DURATION_S),
                    fmt_f64(duration)
                ),
            ));
        }
        let mut previous: Option<u32> = None;
        for (i, k) in self.keys.iter().enumerate() {
            let name = |field: &str| format!("animation.keys[{i}].{field}");
            if k.frame >= self.frames {
                return Err(RenderError::invalid(
                    &name("frame"),
                    k.frame,
                    &format!("below animation.frames = {}", self.frames),
                ));
            }
            if previous.is_some_and(|p| k.frame <= p) {
                return Err(RenderError::invalid(
                    &name("frame"),
                    k.frame,
                    "keys in strictly increasing frame order",
                ));
            }
            previous = Some(k.frame);
            // Each key as written, against its own section's range, so an
            // error names the key rather than a frame interpolated from it.
            let uv = |field: &str, p: Option<[f64; 2]>| -> Result<()> {
                for (j, v) in p.into_iter().flatten().enumerate() {
                    in_range(&name(&format!("{field}[{j}]")), v, 0.0, 1.0)?;
                }
                Ok(())
            };
            uv("position_uv", k.position_uv)?;
            uv("target_uv", k.target_uv)?;
            let az = MAX_AZIMUTH_DEG;
            for (field, v, lo, hi) in [
                ("height_above_ground_m", k.height_above_ground_m, 0.01, 1e6),
                ("pitch_deg", k.pitch_deg, -89.0, 89.0),
                ("sun_elevation_deg", k.sun_elevation_deg, -90.0, 90.0),
                ("sun_azimuth_deg", k.sun_azimuth_deg, -az, az),
            ] {
                if let Some(v) = v {
                    in_range(&name(field), v, lo, hi)?;
                }
            }
        }
        Ok(())
    }

    /// Time of frame `frame` from the start of the sequence, seconds.
    #[must_use]
    pub fn time_s(&self, frame: u32) -> f64 {
        f64::from(frame) / self.fps
    }

    /// The value keyed by `get` at `frame` (`base` where a key leaves it
    /// out), linear between the keys around `frame`.
    fn keyed(&self, frame: u32, base: f64, get: impl Fn(&AnimationKey) -> Option<f64>) -> f64 {
        let at = |k: &AnimationKey| get(k).unwrap_or(base);
        let (Some(first), Some(last)) = (self.keys.first(), self.keys.last()) else {
            return base;
        };
        if frame <= first.frame {
            return at(first);
        }
        if frame >= last.frame {
            return at(last);
        }
        let i = self.keys.partition_point(|k| k.frame <= frame);
        let (a, b) = (&self.keys[i - 1], &self.keys[i]);
        let s = f64::from(frame - a.frame) / f64::from(b.frame - a.frame);
        let (va, vb) = (at(a), at(b));
        va + (vb - va) * s
    }
}

impl SceneDesc {
    /// The still scene of frame `frame` of this scene's animation: the
    /// camera and sun at that frame, the ocean at its time, the clouds
    /// carried by the wind for that time (`clouds.wind_m_s`). Every other key
    /// is this scene's; frame 0 of a scene without keys is the scene itself.
    ///
    /// # Errors
    ///
    /// Returns [`RenderError::Invalid`] if the scene is invalid or `frame` is
    /// not below `animation.frames`.
    pub fn at_frame(&self, frame: u32) -> Result<SceneDesc> {
        self.validate()?;
        let a = &self.animation;
        if frame >= a.frames {
            return Err(RenderError::invalid(
                "frame",
                frame,
                &format!("0 to {} (animation.frames = {})", a.frames - 1, a.frames),
            ));
        }
        let mut s = self.clone();
        let c = &self.camera;
        for i in 0..2 {
            s.camera.position_uv[i] =
                a.keyed(frame, c.position_uv[i], |k| k.position_uv.map(|p| p[i]));
            s.camera.target_uv[i] = a.keyed(frame, c.target_uv[i], |k| k.target_uv.map(|p| p[i]));
        }
        s.camera.height_above_ground_m =
            a.keyed(frame, c.height_above_ground_m, |k| k.height_above_ground_m);
        s.camera.pitch_deg = a.keyed(frame, c.pitch_deg, |k| k.pitch_deg);
        s.sun.elevation_deg = a.keyed(frame, self.sun.elevation_deg, |k| k.sun_elevation_deg);
        s.sun.azimuth_deg = a.keyed(frame, self.sun.azimuth_deg, |k| k.sun_azimuth_deg);
        if frame > 0 {
            let t = a.time_s(frame);
            s.water.ocean_time_s += t;
            for i in 0..2 {
                s.clouds.layer.wind_offset[i] += (self.clouds.wind_m_s[i] * t) as f32;
            }
        }
        s.validate().map_err(|e| match e {
            RenderError::Invalid {
                name,
                value,
                reason,
            } => RenderError::Invalid {
                name,
                value,
                reason: format!("{reason} (at frame {frame} of the animation)"),
            },
            other => other,
        })?;
        Ok(s)
    }

    /// Checks the animation's keys against the rest of the scene: a sun
    /// keyed below the horizon without twilight, a camera keyed onto its
    /// own target, a sequence that moves the ocean's time out of range.
    pub(super) fn validate_animation_keys(&self) -> Result<()> {
        let a = &self.animation;
        for (i, k) in a.keys.iter().enumerate() {
            let name = |field: &str| format!("animation.keys[{i}].{field}");
            if let Some(e) = k.sun_elevation_deg {
                self.sun
                    .check_above_horizon(&name("sun_elevation_deg"), e)?;
            }
            let position = k.position_uv.unwrap_or(self.camera.position_uv);
            let target = k.target_uv.unwrap_or(self.camera.target_uv);
            if position == target {
                let (key, other) = if k.position_uv.is_some() {
                    ("position_uv", "target_uv")
                } else {
                    ("target_uv", "position_uv")
                };
                return Err(RenderError::invalid(
                    &name(key),
                    format!("{position:?}"),
                    &format!("must differ from the key's {other} (or camera.{other})"),
                ));
            }
        }
        let end = self.water.ocean_time_s + a.time_s(a.frames - 1);
        if end > 1e6 {
            return Err(RenderError::invalid(
                "water.ocean_time_s, animation.frames, animation.fps",
                fmt_f64(end),
                "the ocean's time at the last frame must lie in [-1e6, 1e6] s",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn animated() -> SceneDesc {
        let text = "[animation]\nframes = 5\nfps = 10.0\n\
            [[animation.keys]]\nframe = 1\nposition_uv = [0.2, 0.4]\npitch_deg = -2.0\n\
            [[animation.keys]]\nframe = 3\nposition_uv = [0.6, 0.8]\n";
        SceneDesc::from_toml_str(text, "a.toml").unwrap()
    }

    #[test]
    fn keys_interpolate_linearly_and_hold_outside() {
        let s = animated();
        let at = |f| s.at_frame(f).unwrap();
        assert_eq!(at(0).camera.position_uv, [0.2, 0.4]);
        assert_eq!(at(1).camera.position_uv, [0.2, 0.4]);
        let mid = at(2).camera.position_uv;
        approx::assert_abs_diff_eq!(mid[0], 0.4, epsilon = 1e-12);
        approx::assert_abs_diff_eq!(mid[1], 0.6, epsilon = 1e-12);
        assert_eq!(at(4).camera.position_uv, [0.6, 0.8]);
        // The second key leaves the pitch out: it takes the camera's.
        let base = s.camera.pitch_deg;
        approx::assert_abs_diff_eq!(at(2).camera.pitch_deg, (-2.0 + base) / 2.0, epsilon = 1e-12);
        // Time moves the ocean; the terrain never changes.
        approx::assert_abs_diff_eq!(at(3).water.ocean_time_s, s.water.ocean_time_s + 0.3);
        // The clouds drift with the wind: 0.3 s at the default wind.
        let drift = at(3).clouds.layer.wind_offset;
        let w = s.clouds.wind_m_s;
        approx::assert_abs_diff_eq!(f64::from(drift[0]), 0.3 * w[0], epsilon = 1e-5);
        approx::assert_abs_diff_eq!(f64::from(drift[1]), 0.3 * w[1], epsilon = 1e-5);
        assert_eq!(at(0).clouds.layer.wind_offset, s.clouds.layer.wind_offset);
        assert_eq!(at(4).terrain, s.terrain);
        assert_eq!(at(4).erosion, s.erosion);
    }

    #[test]
    fn a_still_scene_is_its_own_frame_zero() {
        let s = SceneDesc::default();
        assert_eq!(s.at_frame(0).unwrap(), s);
        assert!(s.at_frame(1).unwrap_err().to_string().contains("frame"));
    }

    #[test]
    fn bad_animations_are_refused_by_name() {
        let bad = |text: &str, key: &str| {
            let s = SceneDesc::from_toml_str(text, "b.toml").unwrap();
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        };
        bad("[animation]\nframes = 0\n", "animation.frames");
        bad("[animation]\nfps = 0.0\n", "animation.fps");
        bad("[clouds]\nwind_m_s = [500.0, 0.0]\n", "clouds.wind_m_s[0]");
        bad("[clouds]\nwind_m_s = [0.0, nan]\n", "clouds.wind_m_s[1]");
        bad(
            "[animation]\nframes = 4\n[[animation.keys]]\nframe = 4\n",
            "animation.keys[0].frame",
        );
        bad(
            "[animation]\nframes = 4\n[[animation.keys]]\nframe = 2\n[[animation.keys]]\nframe = 2\n",
            "animation.keys[1].frame",
        );
        bad(
            "[animation]\nframes = 4\n[[animation.keys]]\nframe = 2\npitch_deg = nan\n",
            "animation.keys[0].pitch_deg",
        );
    }
}
