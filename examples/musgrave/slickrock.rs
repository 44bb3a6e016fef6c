//! Musgrave 1998, figs. 15.13–15.15: "Slickrock I" (ridged terrain under
//! a subtle random fBm colouring squashed into strata), "Slickrock III"
//! (the same terrain in a GIT texture) and a GIT-filtered picture.

use natura::atmos::medium::HomogeneousFog;
use natura::core::camera::PinholeCamera;
use natura::core::glam::{DVec3, Vec3};
use natura::core::{HeightField, Image, NoProgress};
use natura::texture::Footprint;
use natura::texture::git::{ColourEllipsoid, Git, GitFilterParams, GitParams, git_filter};
use natura::trace::MipmapTracer;

use crate::R;
use crate::landscape::{Landscape, desert_sky, ridged_field, supersampled};

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

/// The terrain seen from a rise at its southern edge, looking north under
/// a high morning sun through light haze, coloured by `texture` with the
/// level of detail the pixel's footprint sets (ss × ss rays a pixel).
fn render(hf: &HeightField, texture: &Git, (w, h): (u32, u32), ss: usize) -> R<Image> {
    let tracer = MipmapTracer::new(hf)?;
    let haze = HomogeneousFog::new(
        DVec3::new(1.2e-5, 1.5e-5, 2.0e-5),
        DVec3::new(0.80, 0.84, 0.92),
    )?;
    let fov = 40f32.to_radians();
    // The footprint of one ray: the pixel's angle over the rays per side.
    let ray_angle = f64::from(fov) / f64::from(h) / ss as f64;
    let albedo = |p: DVec3, distance: f64| {
        let fp = Footprint::new(distance * ray_angle).unwrap_or(Footprint::POINT);
        texture.colour(p, fp).as_vec3()
    };
    let scene = Landscape {
        tracer: &tracer,
        albedo: &albedo,
        medium: &haze,
        sun: Vec3::new(0.45, -0.55, 0.70).normalize(),
        sky: desert_sky,
        shadows: false,
    };
    let x0 = 3000.0;
    let ground = hf.height_at(x0, 250.0).unwrap_or(0.0).max(0.0);
    let eye = Vec3::new(x0, 250.0, ground + 260.0);
    let camera = PinholeCamera::look_at(eye, eye + Vec3::new(0.0, 1.0, -0.16), Vec3::Z, fov, w, h)?;
    supersampled(w, h, ss, |x, y| {
        scene.look(eye, camera.ray_at(x, y).dir.normalize())
    })
}

/// Figs. 15.13 and 15.14: the same slickrock under the random fBm colour
/// and under the GIT texture.
pub(crate) fn pair(seed: u64, quick: bool) -> R<Vec<Image>> {
    let hf = slickrock_field(seed, quick)?;
    let size = if quick { (320, 180) } else { (1200, 675) };
    let ss = if quick { 1 } else { 2 };
    Ok(vec![
        render(&hf, &slickrock_i_texture(seed)?, size, ss)?,
        render(&hf, &slickrock_iii_texture(seed)?, size, ss)?,
    ])
}

/// Fig. 15.15: a picture repainted by the GIT filter, enlarged three
/// times: natura's Slickrock I at a third of the size stands in for the
/// source's photograph.
pub(crate) fn git_filtered(seed: u64, quick: bool) -> R<Image> {
    let hf = slickrock_field(seed, quick)?;
    let small = if quick { (107, 60) } else { (400, 225) };
    let picture = render(&hf, &slickrock_i_texture(seed)?, small, 2)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use natura::texture::git::ColourEllipsoid;

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
