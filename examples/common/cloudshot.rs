//! One picture of a cloud for the cloud programs (`clouds`,
//! `figures_ebert`): a density baked to voxels, shadow tables, the fast
//! renderer with multiple scattering, ACES tone mapping.

use natura::core::glam::Vec3;
use natura::core::{Image, Progress};
use natura::volume::Density;
use natura::volume::cloud::{Cloud, CloudParams, cloud, nine_sphere_cumulus};
use natura::volume::detail::{DetailParams, Detailed};
use natura::volume::grid::GridDensity;
use natura::volume::transport::{
    CacheParams, FastRenderer, FastSettings, LookAtCamera, MediumParams, Scattering, Scene,
    Shadows, Sun,
};

use super::Exit;

/// The units of work [`render`] reports: the bake, the shadow tables and
/// the render.
pub const SHOT: u64 = 3;

/// The size of a shot and of its voxels.
pub struct Look {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Voxel size, metres.
    pub cell: f32,
    /// Nodes of the shadow table along the volume's longest axis.
    pub shadow_nodes: usize,
    /// Scattering events the multiple-scattering cache traces (its set-up
    /// cost; its noise falls as the inverse square root).
    pub cache_events: u32,
}

impl Look {
    /// The cloud programs' shot: 480 × 320 pixels of 8 cm voxels, a
    /// 96-node shadow table and the cache's default 4 M events; with
    /// `quick` (CI), 96 × 64 pixels of 40 cm voxels, 24 nodes and 100 000
    /// events.
    pub fn new(quick: bool) -> Self {
        if quick {
            Self {
                width: 96,
                height: 64,
                cell: 0.4,
                shadow_nodes: 24,
                cache_events: 100_000,
            }
        } else {
            Self {
                width: 480,
                height: 320,
                cell: 0.08,
                shadow_nodes: 96,
                cache_events: 4_000_000,
            }
        }
    }
}

/// The optical density of a cumulus in these shots: extinction per unit
/// density (1/m). Ebert's cumulus density peaks at `√0.3 ≈ 0.55` (its
/// density scale 0.3 under the exponent 0.5), so a cloud 10 m across is
/// about 100 mean free paths thick, as a real cumulus is (the source
/// gives densities, not an extinction). Thinner, the cloud is a pale haze
/// the sky shows through.
pub const CUMULUS_EXTINCTION: f32 = 40.0;

/// Where the cumulus is seen from: a direction from its centre, in
/// bounding radii.
pub const CUMULUS_VIEW: Vec3 = Vec3::new(0.0, -2.4, 0.25);

/// Ebert's nine-sphere cumulus (Fig. 1) with the source's parameters and
/// noise `seed`, and its shot as the cloud programs show it ([`render`],
/// advancing `bar` as it does).
pub fn cumulus(look: &Look, seed: u64, bar: &dyn Progress) -> Result<(Cloud, Image), Exit> {
    let c = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), seed)?;
    let img = render(&c, look, CUMULUS_EXTINCTION, CUMULUS_VIEW, bar)?;
    Ok((c, img))
}

/// Bakes `d`, builds its shadow tables and renders it from `view` (a
/// direction from the centre, in bounding radii), advancing `bar` by one
/// unit after each ([`SHOT`] in all).
///
/// The light is a clear afternoon's: the sun 30° up on the left, a little
/// toward the camera, so the cloud shows a sunlit side and a shaded one; a
/// deep blue sky about a seventh as bright as a white surface facing the
/// sun; water droplets that absorb one part in a thousand (albedo 0.999);
/// half a stop of exposure, so the sunlit side is near white.
pub fn render(
    d: &dyn Density,
    look: &Look,
    extinction: f32,
    view: Vec3,
    bar: &dyn Progress,
) -> Result<Image, Exit> {
    render_detailed(d, look, extinction, view, None, bar)
}

/// [`render`], the baked voxels eroded by `detail` (when given) down to
/// the footprint of a pixel at each point, or of the march's density
/// samples where those are farther apart; the march then takes
/// [`DetailParams::MARCH_SUBSTEPS`] density samples a step.
pub fn render_detailed(
    d: &dyn Density,
    look: &Look,
    extinction: f32,
    view: Vec3,
    detail: Option<(DetailParams, u64)>,
    bar: &dyn Progress,
) -> Result<Image, Exit> {
    let b = d.bounds();
    let c = (b.min + b.max) * 0.5;
    let r = (b.max - b.min).length() * 0.5;
    let fov = 40f32.to_radians();
    let eye = c + view * r;
    let step = look.cell * 0.5;
    let baked = GridDensity::bake(d, look.cell)?;
    let (density, substeps) = match detail {
        Some((p, seed)) => {
            // The footprint of the march's parts at the cloud's near side.
            let parts = step / DetailParams::MARCH_SUBSTEPS as f32 / (view.length() - 1.0) / r;
            let angle = (fov / look.height as f32).max(parts);
            (
                Detailed::new(baked, &p.seen_from(eye, angle), seed)?,
                DetailParams::MARCH_SUBSTEPS,
            )
        }
        None => (Detailed::without_detail(baked), 1),
    };
    bar.advance(1);
    let scene = Scene {
        sun: Some(Sun {
            direction: Vec3::new(-0.85, -0.25, 0.5).normalize(),
            irradiance: Vec3::new(3.2, 3.0, 2.7),
        }),
        ..Scene::new(
            &density,
            MediumParams {
                extinction,
                albedo: 0.999,
                ..MediumParams::default()
            },
            Vec3::new(0.09, 0.15, 0.275),
        )
    };
    let settings = FastSettings {
        step,
        substeps,
        shadows: Shadows::Table(look.shadow_nodes),
        scattering: Scattering::Cache(CacheParams {
            events: look.cache_events,
            ..CacheParams::default()
        }),
        ..FastSettings::default()
    };
    let camera =
        LookAtCamera::look_at(eye, c, Vec3::Z, fov, look.width as u32, look.height as u32)?;
    let fast = FastRenderer::new(&scene, settings)?;
    bar.advance(1);
    let image = fast.render(&camera)?;
    bar.advance(1);
    Ok(image.tone_mapped(0.5, natura::core::ToneMap::AcesFilmic))
}

/// Images side by side with 4 px white gaps.
pub fn strip(shots: &[Image]) -> natura::core::Result<Image> {
    let (w, h) = (shots[0].width(), shots[0].height());
    Image::from_fn(w * shots.len() + 4 * (shots.len() - 1), h, |x, y| {
        let (k, r) = (x / (w + 4), x % (w + 4));
        if r >= w {
            Vec3::ONE
        } else {
            shots[k].get(r, y).unwrap_or(Vec3::ONE)
        }
    })
}
