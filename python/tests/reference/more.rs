//! The reference values of the rendered scene, the ecosystem, the volumes,
//! the textures and the sky (the sections `render`, `eco`, `volume`,
//! `texture` and `sky` of `reference.json`), through natura's Rust API.

use natura_atmos::Dir3;
use natura_atmos::sky::{Atmosphere, AtmosphereParams};
use natura_core::{Grid2, HeightField, NoProgress};
use natura_fluid::plume::Plume;
use natura_noise::glam::{DVec3, Vec3};
use natura_plant::eco::{EcoParams, Ecosystem, Instancing};
use natura_render::{SceneDesc, render_scene};
use natura_texture::air::{PuffyClouds, PuffyCloudsParams};
use natura_texture::earth::{Terran, TerranParams};
use natura_texture::planet::{Planet, PlanetParams};
use natura_texture::{Footprint, SolidTexture};
use natura_volume::cloud::{CloudParams, cloud, nine_sphere_cumulus};
use natura_volume::grid::GridDensity;
use natura_volume::layer::{LayerClouds, LayerParams};

use super::{fnv, hash_f32, points3};

fn hash_f64(v: &[f64]) -> u64 {
    fnv(v.iter().flat_map(|x| x.to_le_bytes()))
}

/// The quick scene of `natura.render.QUICK` (natura-render's quick start)
/// at 48 × 27 pixels: the image's hash and the exposure's bits.
pub fn render() -> Vec<String> {
    let mut scene = SceneDesc::default();
    scene.terrain.size = 64;
    scene.terrain.cell_size_m = 960.0;
    scene.erosion.stream_power_steps = 3;
    scene.erosion.thermal_steps = 3;
    scene.clouds.enabled = false;
    scene.vegetation.enabled = false;
    scene.render.width = 48;
    scene.render.height = 27;
    scene.render.spp = 1;
    let out = render_scene(&scene, &NoProgress).unwrap();
    let px: Vec<f32> = out
        .image
        .pixels()
        .as_slice()
        .iter()
        .flat_map(|c| c.to_array())
        .collect();
    vec![
        format!("    \"quick_48x27\": {}", hash_f32(&px)),
        format!("    \"exposure_bits\": {}", out.exposure_ev.to_bits()),
    ]
}

/// The heights of the ecosystem test: `(i + j)·0.2` over 33 × 33, cell 2 m.
pub fn slope() -> HeightField {
    let g = Grid2::from_fn(33, 33, |i, j| (i + j) as f32 * 0.2).unwrap();
    HeightField::new(g, 2.0).unwrap()
}

/// An ecosystem of the default species grown 4 steps on [`slope`], with
/// 2 prototypes per species: its instance arrays' hashes.
pub fn eco() -> Vec<String> {
    let mut eco = Ecosystem::new(
        &slope(),
        EcoParams {
            steps: 4,
            ..EcoParams::default()
        },
    )
    .unwrap();
    eco.run(&NoProgress).unwrap();
    let inst = Instancing::new(&eco, 2).unwrap();
    let pos: Vec<f32> = inst
        .instances
        .iter()
        .flat_map(|i| i.position.to_array())
        .collect();
    let scale: Vec<f32> = inst.instances.iter().map(|i| i.scale).collect();
    let rot: Vec<f32> = inst.instances.iter().map(|i| i.rotation).collect();
    let species = fnv(inst.instances.iter().flat_map(|i| i.species.to_le_bytes()));
    let proto = fnv(inst
        .instances
        .iter()
        .flat_map(|i| i.prototype.to_le_bytes()));
    vec![
        format!("    \"plants\": {}", inst.instances.len()),
        format!("    \"prototypes\": {}", inst.prototypes.len()),
        format!("    \"positions\": {}", hash_f32(&pos)),
        format!("    \"scale\": {}", hash_f32(&scale)),
        format!("    \"rotation\": {}", hash_f32(&rot)),
        format!("    \"species\": {species}"),
        format!("    \"prototype\": {proto}"),
    ]
}

/// Ebert's cumulus (seed 7, density scale 0.35) baked at 0.5 m; layer
/// clouds over 4 km baked at 250 m; the plume of 24 cells after 3 steps.
pub fn volume() -> Vec<String> {
    let c = cloud(
        nine_sphere_cumulus(),
        CloudParams {
            density_scale: 0.35,
            ..CloudParams::default()
        },
        7,
    )
    .unwrap();
    let g = GridDensity::bake(&c, 0.5).unwrap();
    let layer = LayerClouds::new(
        LayerParams {
            region_min: [-2000.0, -2000.0],
            region_max: [2000.0, 2000.0],
            ..LayerParams::default()
        },
        3,
    )
    .unwrap();
    let l = GridDensity::bake(&layer, 250.0).unwrap();
    let plume = Plume {
        cells: 24,
        ..Plume::default()
    };
    let mut smoke = plume.build().unwrap();
    for _ in 0..3 {
        smoke.step(plume.dt()).unwrap();
    }
    let dims = |g: &GridDensity| {
        let (x, y, z) = g.grid().dims();
        format!("[{z}, {y}, {x}]")
    };
    vec![
        format!("    \"cumulus\": {}", hash_f32(g.grid().as_slice())),
        format!("    \"cumulus_shape\": {}", dims(&g)),
        format!("    \"cumulus_origin\": {:?}", g.origin().to_array()),
        format!("    \"layer\": {}", hash_f32(l.grid().as_slice())),
        format!("    \"layer_shape\": {}", dims(&l)),
        format!(
            "    \"smoke_density\": {}",
            hash_f32(smoke.density().as_slice())
        ),
        format!(
            "    \"smoke_temperature\": {}",
            hash_f32(smoke.temperature().as_slice())
        ),
    ]
}

/// Terran and puffy clouds at the 3-D points, footprint 10⁻³; the planet
/// Gaea on a 32 × 16 equirectangular map.
pub fn texture() -> Vec<String> {
    let fp = Footprint::new(1e-3).unwrap();
    let terran = Terran::new(TerranParams::default()).unwrap();
    let puffy = PuffyClouds::new(PuffyCloudsParams::default()).unwrap();
    let mut v = Vec::new();
    for (name, t) in [
        ("terran", &terran as &dyn SolidTexture),
        ("puffy_clouds", &puffy),
    ] {
        let s: Vec<_> = points3().iter().map(|&p| t.sample(p, fp)).collect();
        let c: Vec<f64> = s.iter().flat_map(|s| s.colour.to_array()).collect();
        let o: Vec<f64> = s.iter().map(|s| s.opacity).collect();
        let h: Vec<f64> = s.iter().map(|s| s.height).collect();
        v.push(format!("    \"{name}_colour\": {}", hash_f64(&c)));
        v.push(format!("    \"{name}_opacity\": {}", hash_f64(&o)));
        v.push(format!("    \"{name}_height\": {}", hash_f64(&h)));
    }
    let map = Planet::new(PlanetParams::gaea())
        .unwrap()
        .equirect(32, 16, &NoProgress)
        .unwrap();
    let colour: Vec<f32> = map
        .colour
        .as_slice()
        .iter()
        .flat_map(|c| c.to_array())
        .collect();
    v.push(format!("    \"gaea_colour\": {}", hash_f32(&colour)));
    v.push(format!(
        "    \"gaea_height\": {}",
        hash_f32(map.height.as_slice())
    ));
    v
}

/// The directions of the sky test: elevation `k·0.07 − 0.2`, azimuth
/// `k·0.37` for k in 0..40, in `f64` then rounded to `f32`.
pub fn sky_directions() -> Vec<Vec3> {
    (0..40)
        .map(|k| {
            let (e, a) = (f64::from(k) * 0.07 - 0.2, f64::from(k) * 0.37);
            DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin()).as_vec3()
        })
        .collect()
}

/// The default atmosphere's sky from 300 m with the sun at 12° elevation,
/// 40° azimuth.
pub fn sky() -> Vec<String> {
    let atm = Atmosphere::new(AtmosphereParams::default()).unwrap();
    let sun = Dir3::from_angles(12f64.to_radians(), 40f64.to_radians()).unwrap();
    let view = atm.sky_view(DVec3::new(0.0, 0.0, 300.0), sun).unwrap();
    let dirs = sky_directions();
    let mut out = vec![Vec3::ZERO; dirs.len()];
    view.radiance_batch(&dirs, &mut out).unwrap();
    let flat: Vec<f32> = out.iter().flat_map(|c| c.to_array()).collect();
    vec![format!("    \"radiance\": {}", hash_f32(&flat))]
}
