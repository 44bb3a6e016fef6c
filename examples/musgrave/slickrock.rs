//! Musgrave 1998, figs. 15.13–15.15: "Slickrock I" (ridged terrain under
//! a subtle random fBm colouring squashed into strata), "Slickrock III"
//! (the same terrain in a GIT texture) and a GIT-filtered picture; and
//! Musgrave 1993, Plate 4.1, "Slickrock" in exponential mist with the
//! Rayleigh approximation over a black background.

use natura::atmos::Medium;
use natura::atmos::medium::{ExponentialMist, HomogeneousFog, RayleighRgb};
use natura::core::camera::PinholeCamera;
use natura::core::glam::{DVec3, Vec3};
use natura::core::{HeightField, Image, NoProgress};
use natura::texture::Footprint;
use natura::texture::git::{ColourEllipsoid, Git, GitFilterParams, GitParams, git_filter};
use natura::trace::MipmapTracer;

use crate::R;
use crate::landscape::{Landscape, desert_sky, picture_size, ridged_field, supersampled};

/// Slickrock: ridged terrain "with ridges everywhere and at all scales"
/// (the ridged basis, 9 octaves, H = 1), 6 km across, 700 m high, first
/// wavelength 2.4 km; the lowest fifth cut off as a sandy floor.
fn slickrock_field(seed: u64, quick: bool) -> R<HeightField> {
    let n = if quick { 257 } else { 1025 };
    ridged_field(seed, n, 6000.0, 2400.0, 0.2, 700.0, |_, _| 1.0)
}

/// Fig. 15.13's colouring: random fBm colour (vector fBm read as RGB,
/// the three channels' axes, as the book's Fig. 20.9) subtly perturbing a
/// sandstone, the domain squashed 12:1 vertically into strata.
pub(crate) fn slickrock_i_texture(seed: u64) -> R<Git> {
    Ok(Git::new(GitParams {
        seed,
        ellipsoid: ColourEllipsoid::new(
            DVec3::new(0.64, 0.40, 0.26),
            [DVec3::X, DVec3::Y, DVec3::Z],
            [0.03, 0.03, 0.03],
        )?,
        txtscale: 1.0 / 400.0,
        stretch: DVec3::new(1.0, 1.0, 12.0),
        ..GitParams::default()
    })?)
}

/// Fig. 15.14's GIT texture: juxtaposed colour averaging to a sandstone,
/// varying most from blue-grey to yellow (the source's example), strata as in Fig. 15.13.
pub(crate) fn slickrock_iii_texture(seed: u64) -> R<Git> {
    Ok(Git::new(GitParams {
        seed,
        ellipsoid: ColourEllipsoid::along(
            DVec3::new(0.64, 0.40, 0.26),
            DVec3::new(1.0, 1.0, -1.0),
            [0.08, 0.03, 0.02],
        )?,
        txtscale: 1.0 / 400.0,
        stretch: DVec3::new(1.0, 1.0, 12.0),
        ..GitParams::default()
    })?)
}

/// The light haze of Figs. 15.13–15.15.
fn haze() -> R<HomogeneousFog> {
    Ok(HomogeneousFog::new(
        DVec3::new(1.2e-5, 1.5e-5, 2.0e-5),
        DVec3::new(0.80, 0.84, 0.92),
    )?)
}

/// Where the camera looks: from `above` metres over the ground at the
/// middle of the southern edge (a 24th of the way in), or at least at
/// altitude `floor`, north and down by `pitch` radians, `fov` radians
/// from the picture's top to bottom.
#[derive(Clone, Copy)]
pub(crate) struct View {
    pub above: f32,
    pub floor: f32,
    pub pitch: f32,
    pub fov: f32,
}

/// The terrain seen from `view` under a high
/// morning sun through `medium`, coloured by `texture` with the level of
/// detail the pixel's footprint sets (ss × ss rays a pixel).
pub(crate) fn render<M: Medium>(
    hf: &HeightField,
    texture: &Git,
    (w, h): (u32, u32),
    ss: usize,
    medium: &M,
    sky: fn(Vec3) -> Vec3,
    view: View,
) -> R<Image> {
    let tracer = MipmapTracer::new(hf)?;
    let fov = view.fov;
    // The footprint of one ray: the pixel's angle over the rays per side.
    let ray_angle = f64::from(fov) / f64::from(h) / ss as f64;
    let albedo = |p: DVec3, distance: f64| {
        let fp = Footprint::new(distance * ray_angle).unwrap_or(Footprint::POINT);
        texture.colour(p, fp).as_vec3()
    };
    let scene = Landscape {
        tracer: &tracer,
        albedo: &albedo,
        medium,
        sun: Vec3::new(0.45, -0.55, 0.70).normalize(),
        sky: &sky,
        shadows: false,
    };
    let side = (hf.nx() - 1) as f32 * hf.cell_size();
    let (x0, y0) = (side * 0.5, side / 24.0);
    let ground = hf.height_at(x0, y0).unwrap_or(0.0).max(0.0);
    let eye = Vec3::new(x0, y0, (ground + view.above).max(view.floor));
    let (s, c) = view.pitch.sin_cos();
    let camera = PinholeCamera::look_at(eye, eye + Vec3::new(0.0, c, -s), Vec3::Z, fov, w, h)?;
    supersampled(w, h, ss, |x, y| {
        scene.look(eye, camera.ray_at(x, y).dir.normalize())
    })
}

/// The view of Figs. 15.13–15.15: 260 m over the rise, 9° down.
const OVER_THE_RISE: View = View {
    above: 260.0,
    floor: 0.0,
    pitch: 0.158_655_25,
    fov: 0.698_131_7,
};

/// Figs. 15.13 and 15.14: the same slickrock under the random fBm colour
/// and under the GIT texture.
pub(crate) fn pair(seed: u64, quick: bool) -> R<Vec<Image>> {
    let hf = slickrock_field(seed, quick)?;
    let (size, ss) = picture_size(quick);
    let haze = haze()?;
    let view = |t: &Git| render(&hf, t, size, ss, &haze, desert_sky, OVER_THE_RISE);
    Ok(vec![
        view(&slickrock_i_texture(seed)?)?,
        view(&slickrock_iii_texture(seed)?)?,
    ])
}

/// Fig. 15.15: a picture repainted by the GIT filter, enlarged three
/// times: natura's Slickrock I at a third of the size stands in for the
/// source's photograph.
pub(crate) fn git_filtered(seed: u64, quick: bool) -> R<Image> {
    let hf = slickrock_field(seed, quick)?;
    let small = if quick { (107, 60) } else { (400, 225) };
    let picture = render(
        &hf,
        &slickrock_i_texture(seed)?,
        small,
        2,
        &haze()?,
        desert_sky,
        OVER_THE_RISE,
    )?;
    Ok(git_filter(
        &picture,
        &GitFilterParams {
            seed,
            expand: 3,
            ..GitFilterParams::default()
        },
        &NoProgress,
    )?)
}

/// Plate 4.1's mist: Musgrave's Rayleigh approximation, extinction in the
/// ratio 1 : 3 : 20 (red : green : blue), 4·10⁻⁶ per metre in red at the
/// valley floor, falling by e every 1500 m; off-white, "as seen at the
/// horizon" (the source gives neither number).
fn rayleigh_mist() -> R<ExponentialMist> {
    rayleigh_mist_of(4.0e-6, 1500.0)
}

/// Off-white mist whose extinction is `red` per metre in red at altitude 0
/// and in Musgrave's Rayleigh ratio 1 : 3 : 20 across red, green and blue,
/// falling by e every `scale_height` metres.
pub(crate) fn rayleigh_mist_of(red: f64, scale_height: f64) -> R<ExponentialMist> {
    Ok(ExponentialMist::new(
        RayleighRgb::musgrave_1_3_20(red),
        DVec3::new(0.93, 0.92, 0.88),
        0.0,
        scale_height,
    )?)
}

/// Plate 4.1, "Slickrock": ridged terrain 24 km across and 1.8 km high
/// (the ridged basis, first wavelength 7 km) in the subtle strata colour of
/// Fig. 15.13, level of detail by footprint, seen through exponential mist
/// with the Rayleigh approximation over a black background: the mist
/// alone makes the sky blue overhead and off-white at the horizon, and the
/// far ridges bluer and paler.
pub(crate) fn plate(seed: u64, quick: bool) -> R<Image> {
    let n = if quick { 257 } else { 1025 };
    let hf = ridged_field(seed, n, 24_000.0, 7000.0, 0.2, 1800.0, |_, _| 1.0)?;
    let (size, ss) = picture_size(quick);
    let texture = Git::new(GitParams {
        txtscale: 1.0 / 1200.0,
        ..*slickrock_i_texture(seed)?.params()
    })?;
    render(
        &hf,
        &texture,
        size,
        ss,
        &rayleigh_mist()?,
        |_| Vec3::ZERO,
        View {
            above: 600.0,
            floor: 0.0,
            pitch: 0.09,
            fov: 0.698_131_7,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura::texture::git::ColourEllipsoid;

    #[test]
    fn the_rayleigh_mist_blues_the_black_sky_and_pales_the_horizon() {
        // Plate 4.1: over a black background the mist's own light is the
        // sky: blue overhead (blue's extinction is 20 times red's) and
        // nearly its off-white colour along the horizon.
        use natura::atmos::Dir3;
        let mist = rayleigh_mist().unwrap();
        let o = DVec3::new(0.0, 0.0, 600.0);
        let sky = |d: DVec3| {
            mist.attenuation_to_infinity(o, Dir3::new(d).unwrap())
                .apply(DVec3::ZERO)
        };
        let up = sky(DVec3::Z);
        assert!(up.z > 4.0 * up.x && up.z > 2.0 * up.y, "{up}");
        let fog = mist.params().fog_colour;
        let level = sky(DVec3::Y);
        assert!((level - fog).abs().max_element() < 1e-9, "{level}");
        // Just above the horizon: pale in every channel, blue the palest.
        let low = sky(DVec3::new(0.0, 1.0, 0.002));
        assert!(
            low.min_element() > 0.75 && low.z / fog.z > low.x / fog.x,
            "{low}"
        );
        // A far ridge (20 km) is bluer than a near one (2 km).
        let far = mist.composite(o, DVec3::new(0.0, 20_000.0, 600.0), DVec3::splat(0.2));
        let near = mist.composite(o, DVec3::new(0.0, 2_000.0, 600.0), DVec3::splat(0.2));
        assert!(far.z - far.x > 2.0 * (near.z - near.x), "{far} {near}");
    }

    #[test]
    fn slickrock_iii_juxtaposes_colours_around_its_mean_along_its_axis() {
        // Fig. 15.14: the colours the texture puts on the rock, gathered
        // over the terrain's extent, average to the ellipsoid's mean and
        // vary most along its major axis.
        let git = slickrock_iii_texture(7).unwrap();
        let e = git.params().ellipsoid;
        let colours: Vec<DVec3> = (0..8000)
            .map(|k| {
                let t = f64::from(k);
                let p = DVec3::new(t * 7.31 % 6000.0, t * 3.77 % 6000.0, t * 0.0913 % 700.0);
                git.display_colour(p, Footprint::POINT)
            })
            .collect();
        let found = ColourEllipsoid::from_colours(&colours).unwrap();
        assert!((found.mean - e.mean).length() < 0.01, "{:?}", found.mean);
        assert!(
            found.axes[0].dot(e.axes[0]).abs() > 0.98,
            "{:?}",
            found.axes[0]
        );
    }
}
