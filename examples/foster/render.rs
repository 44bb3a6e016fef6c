//! A small ray tracer for liquid in a tank, as Foster & Fedkiw render their
//! figures: the implicit surface ray-marched through its grid with a root
//! search, normals from the level set's gradient (Foster & Fedkiw 2001, §5.2),
//! escaped particles as small drops. The water reflects (Fresnel, Schlick's
//! approximation at n = 1.33) and refracts into an absorbing body; the
//! tank's floor and back walls are tiled so the refraction shows.

use natura::core::Image;
use natura::core::glam::Vec3;
use natura::fluid::levelset::LevelSet;
use natura::fluid::shape::Shape;
use rayon::prelude::*;

/// What a picture shows: the liquid's level set in a tank of `size`
/// (the grid's extent), solid shapes and drops.
pub struct Tank<'a> {
    /// The liquid (negative inside).
    pub phi: &'a LevelSet,
    /// The tank's extent (m), from the origin.
    pub size: Vec3,
    /// Solid shapes drawn in `solid_colour`.
    pub solids: Vec<Shape>,
    /// Colour of the solids (linear).
    pub solid_colour: Vec3,
    /// Drops: centre and radius (m).
    pub drops: Vec<(Vec3, f32)>,
    /// Markers (centre and radius, m), drawn dark red: a control curve's
    /// moving points.
    pub markers: Vec<(Vec3, f32)>,
    /// An opaque liquid of this colour (mud) instead of water.
    pub opaque: Option<Vec3>,
}

/// A pinhole camera.
pub struct View {
    /// Eye (m).
    pub eye: Vec3,
    /// Point looked at (m).
    pub target: Vec3,
    /// Vertical field of view (degrees).
    pub fov_deg: f32,
    /// Picture width (pixels).
    pub width: usize,
    /// Picture height (pixels).
    pub height: usize,
}

const SUN: Vec3 = Vec3::new(0.45, -0.55, 0.70);
/// Absorption of the water body (1/m): reds go first.
const ABSORB: Vec3 = Vec3::new(3.2, 1.1, 0.7);
const ETA: f32 = 1.0 / 1.33;

fn sun() -> Vec3 {
    SUN.normalize()
}

fn sky(d: Vec3) -> Vec3 {
    let up = d.z.max(0.0);
    let horizon = Vec3::new(0.80, 0.86, 0.92);
    let zenith = Vec3::new(0.30, 0.50, 0.82);
    if d.z < 0.0 {
        Vec3::splat(0.22)
    } else {
        horizon.lerp(zenith, up.powf(0.6))
    }
}

/// The slab interval of the ray with the box `[0, size]`.
fn box_span(o: Vec3, d: Vec3, size: Vec3) -> Option<(f32, f32)> {
    let inv = d.recip();
    let a = (Vec3::ZERO - o) * inv;
    let b = (size - o) * inv;
    let t0 = a.min(b).max_element().max(0.0);
    let t1 = a.max(b).min_element();
    (t1 > t0).then_some((t0, t1))
}

fn schlick(cos: f32) -> f32 {
    let f0 = 0.02;
    f0 + (1.0 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

impl Tank<'_> {
    fn phi_at(&self, p: Vec3) -> f32 {
        let h = self.phi.h();
        let q = p.clamp(Vec3::splat(0.5 * h), self.size - Vec3::splat(0.5 * h));
        self.phi.value_at(q)
    }

    fn normal(&self, p: Vec3) -> Vec3 {
        unit_gradient(|q| self.phi_at(q), p, 0.5 * self.phi.h())
    }

    /// The first crossing of the liquid's surface along the ray, from
    /// outside (`inside` false) or from inside, with bisection.
    fn march(&self, o: Vec3, d: Vec3, inside: bool, t_max: f32) -> Option<f32> {
        let (t0, t1) = box_span(o, d, self.size)?;
        let t1 = t1.min(t_max);
        let h = self.phi.h();
        let s = if inside { -1.0 } else { 1.0 };
        let (mut t, mut prev) = (t0, t0);
        while t <= t1 {
            let v = s * self.phi_at(o + d * t);
            if v < 0.0 {
                let (mut a, mut b) = (prev, t);
                for _ in 0..14 {
                    let m = 0.5 * (a + b);
                    if s * self.phi_at(o + d * m) < 0.0 {
                        b = m;
                    } else {
                        a = m;
                    }
                }
                return Some(0.5 * (a + b));
            }
            prev = t;
            t += (0.8 * v).clamp(0.3 * h, 2.0 * h);
        }
        None
    }

    /// The nearest solid along the ray (sphere tracing the union).
    fn solid(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        if self.solids.is_empty() {
            return None;
        }
        let (t0, t1) = box_span(o, d, self.size)?;
        let t1 = t1.min(t_max);
        let mut t = t0;
        let eps = 0.1 * self.phi.h();
        while t <= t1 {
            let s = self.solid_sdf(o + d * t);
            if s < eps {
                return Some(t);
            }
            t += (0.8 * s).max(0.25 * eps);
        }
        None
    }

    fn solid_sdf(&self, p: Vec3) -> f32 {
        self.solids
            .iter()
            .map(|s| s.sdf(p))
            .fold(f32::INFINITY, f32::min)
    }

    fn solid_normal(&self, p: Vec3) -> Vec3 {
        unit_gradient(|q| self.solid_sdf(q), p, 0.2 * self.phi.h())
    }

    fn drop_hit(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, Vec3)> {
        sphere_hit(&self.drops, o, d, t_max)
    }
}

/// The direction of `f`'s gradient at `p` by central differences of step
/// `e` (up where it vanishes).
fn unit_gradient(f: impl Fn(Vec3) -> f32, p: Vec3, e: f32) -> Vec3 {
    let d = |a: Vec3| f(p + a * e) - f(p - a * e);
    Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z))
        .try_normalize()
        .unwrap_or(Vec3::Z)
}

/// The nearest of `spheres` along the ray before `t_max`: distance and normal.
fn sphere_hit(spheres: &[(Vec3, f32)], o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, Vec3)> {
    let mut best: Option<(f32, Vec3)> = None;
    for &(c, r) in spheres {
        let oc = o - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - r * r);
        if disc < 0.0 {
            continue;
        }
        let t = -b - disc.sqrt();
        if t > 1e-5 && t < t_max && best.is_none_or(|(bt, _)| t < bt) {
            best = Some((t, ((o + d * t) - c) / r));
        }
    }
    best
}

impl Tank<'_> {
    /// The tank's floor and back walls, tiled, or the sky: what a ray sees
    /// when it meets no liquid, solid or drop.
    fn room(&self, o: Vec3, d: Vec3) -> (f32, Vec3) {
        let s = self.size;
        let mut best = (f32::INFINITY, sky(d));
        let mut plane = |t: f32, p: Vec3, n: Vec3, u: f32, v: f32, base: Vec3| {
            if t > 1e-5 && t < best.0 {
                let tile = ((u / 0.05).floor() + (v / 0.05).floor()).rem_euclid(2.0);
                let c = base * (0.85 + 0.15 * tile);
                let lit = 0.35 + 0.65 * n.dot(sun()).max(0.0);
                let _ = p;
                best = (t, c * lit);
            }
        };
        if d.z < 0.0 {
            let t = -o.z / d.z;
            let p = o + d * t;
            if (0.0..=s.x).contains(&p.x) && (0.0..=s.y).contains(&p.y) {
                plane(t, p, Vec3::Z, p.x, p.y, Vec3::new(0.62, 0.60, 0.56));
            } else {
                plane(t, p, Vec3::Z, 0.0, 0.0, Vec3::splat(0.30));
            }
        }
        if d.y > 0.0 {
            let t = (s.y - o.y) / d.y;
            let p = o + d * t;
            if (0.0..=s.x).contains(&p.x) && (0.0..=s.z).contains(&p.z) {
                plane(t, p, -Vec3::Y, p.x, p.z, Vec3::new(0.70, 0.72, 0.74));
            }
        }
        for (x, n) in [(0.0, Vec3::X), (s.x, -Vec3::X)] {
            if d.x.abs() > 1e-6 {
                let t = (x - o.x) / d.x;
                let p = o + d * t;
                if (0.0..=s.y).contains(&p.y) && (0.0..=s.z).contains(&p.z) && n.dot(d) < 0.0 {
                    plane(t, p, n, p.y, p.z, Vec3::new(0.66, 0.68, 0.70));
                }
            }
        }
        best
    }

    /// What a ray sees without the liquid's surface (used inside and after
    /// reflection): the room, solids and drops.
    fn behind(&self, o: Vec3, d: Vec3) -> (f32, Vec3) {
        let (tr, mut c) = self.room(o, d);
        let mut t = tr;
        if let Some(ts) = self.solid(o, d, t) {
            t = ts;
            c = self.shade_solid(o + d * ts);
        }
        if let Some((td, n)) = self.drop_hit(o, d, t) {
            t = td;
            c = self.shade_drop(d, n);
        }
        if let Some((tm, n)) = sphere_hit(&self.markers, o, d, t) {
            t = tm;
            c = Vec3::new(0.55, 0.06, 0.05) * (0.35 + 0.65 * n.dot(sun()).max(0.0));
        }
        (t, c)
    }

    fn shade_solid(&self, p: Vec3) -> Vec3 {
        let n = self.solid_normal(p);
        self.solid_colour * (0.3 + 0.7 * n.dot(sun()).max(0.0))
    }

    fn shade_drop(&self, d: Vec3, n: Vec3) -> Vec3 {
        let f = schlick(-d.dot(n));
        let r = d - 2.0 * d.dot(n) * n;
        Vec3::new(0.55, 0.70, 0.80).lerp(sky(r), f.max(0.25))
            + Vec3::splat(3.0 * r.dot(sun()).max(0.0).powi(60))
    }

    /// The colour along a camera ray.
    pub fn trace(&self, o: Vec3, d: Vec3) -> Vec3 {
        let (t_behind, c_behind) = self.behind(o, d);
        let Some(tw) = self.march(o, d, false, t_behind) else {
            return c_behind;
        };
        let p = o + d * tw;
        // Where the liquid meets the tank's side the ray enters it through
        // the (glass) side: its normal, not the level set's (which the
        // clamped samples flatten there).
        let h = self.phi.h();
        let n = if p.y < 0.25 * h {
            -Vec3::Y
        } else if p.x < 0.25 * h {
            -Vec3::X
        } else if p.x > self.size.x - 0.25 * h {
            Vec3::X
        } else {
            self.normal(p)
        };
        let cos = (-d.dot(n)).max(0.0);
        let f = schlick(cos);
        let r = d - 2.0 * d.dot(n) * n;
        if let Some(albedo) = self.opaque {
            // Mud: diffuse under the sun and sky, a wet sheen.
            let diffuse = albedo * (0.3 + 0.7 * n.dot(sun()).max(0.0));
            return diffuse * (1.0 - f)
                + self.behind(p + n * 1e-3, r).1 * f
                + Vec3::splat(0.6 * r.dot(sun()).max(0.0).powi(40));
        }
        let reflected = self.behind(p + n * 1e-3, r).1;
        let spec = Vec3::splat(6.0 * r.dot(sun()).max(0.0).powi(200));
        // Refraction into the body, absorbed along the path inside.
        let k = 1.0 - ETA * ETA * (1.0 - cos * cos);
        let transmitted = if k > 0.0 {
            let dt = (ETA * d + (ETA * cos - k.sqrt()) * n).normalize();
            let q = p - n * 1e-3;
            let (t_in, c_in) = self.behind(q, dt);
            let t_out = self.march(q, dt, true, t_in).unwrap_or(t_in);
            let len = t_out.min(t_in).min(2.0 * self.size.max_element());
            let c = if t_out < t_in {
                // Leaves the body through the surface: what lies beyond.
                self.behind(q + dt * (t_out + 1e-3), dt).1
            } else {
                c_in
            };
            c * (-ABSORB * len).exp() + Vec3::new(0.02, 0.06, 0.08) * (1.0 - (-len * 2.0).exp())
        } else {
            Vec3::ZERO
        };
        transmitted * (1.0 - f) + (reflected + spec) * f
    }
}

/// Renders `tank` from `view`, rows in parallel (each pixel's colour
/// depends on nothing else, so the picture is the same on any thread count).
///
/// # Errors
///
/// As [`Image::from_fn`] (a zero or too large size).
pub fn render(tank: &Tank<'_>, view: &View) -> natura::core::Result<Image> {
    let (w, h) = (view.width, view.height);
    let fwd = (view.target - view.eye).normalize();
    let right = fwd.cross(Vec3::Z).normalize();
    let up = right.cross(fwd);
    let half = (0.5 * view.fov_deg.to_radians()).tan();
    let aspect = w as f32 / h as f32;
    let rows: Vec<Vec<Vec3>> = (0..h)
        .into_par_iter()
        .map(|y| {
            (0..w)
                .map(|x| {
                    // 2 × 2 samples a pixel.
                    let mut c = Vec3::ZERO;
                    for (sx, sy) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                        let u = (2.0 * (x as f32 + sx) / w as f32 - 1.0) * half * aspect;
                        let v = (1.0 - 2.0 * (y as f32 + sy) / h as f32) * half;
                        let d = (fwd + right * u + up * v).normalize();
                        c += tank.trace(view.eye, d);
                    }
                    c * 0.25
                })
                .collect()
        })
        .collect();
    Image::from_fn(w, h, |x, y| rows[y][x])
}
