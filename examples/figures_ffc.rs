//! Fournier, Fussell & Carpenter's figures (Fournier et al. 1982) re-made
//! with natura-terrain's stochastic subdivision, with the source's
//! parameters where it gives them.
//!
//! ```text
//! cargo run --release --example figures_ffc                  # into ./figures_ffc/
//! cargo run --release --example figures_ffc -- --quick --out /tmp/ffc
//! cargo run --release --example figures_ffc -- --only australia --only planet
//! cargo run --release --example figures_ffc -- --help        # every flag and its default
//! ```
//!
//! One picture per figure or group of figures (`ffc_fig01-03_paths.png`,
//! …); docs/figures.md sets each beside the source's caption. The curves
//! are drawn without text: panels read left to right, top to bottom, in
//! the order of the source's figures.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure};
use common::plot::{Canvas, Panel, Pen, colour};
use common::{Exit, Run, outln};
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::core::preview::{PreviewCamera, PreviewProjection, Projector, Raster, facing, lambert};
use natura::core::{HeightField, Image, Ramp};
use natura::terrain::Seed;
use natura::terrain::analysis::{path_h, surface_area};
use natura::terrain::synth::{
    EndpointMode, MidpointParams, SubdivisionParams, SubdivisionScheme, TriMesh, bspline_surface,
    fractal_polyline, midpoint_1d, subdivide, subdivide_mesh,
};

/// Fournier, Fussell & Carpenter's figures (Fournier et al. 1982) re-made
/// with natura-terrain's stochastic subdivision: fBm paths, the same path
/// at two resolutions, a normal-displaced polyline, Australia
/// stochastically interpolated, a B-spline mountain, the subdivided planet
/// and its zoom, crumpled paper.
#[derive(Parser)]
#[command(name = "figures_ffc", version)]
struct Cli {
    /// Small and fast (CI): smaller pictures, fewer subdivision levels
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Random seed
    #[arg(long, default_value_t = 1982)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_ffc")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Figs. 1-3: fBm sample paths, H = 0.5, 0.3, 0.7
    Paths,
    /// Fig. 5: one path at 17 and at 257 points
    TwoResolutions,
    /// Fig. 7: a normal-displaced polyline with 0, 3 and 255 interpolated points
    Polyline,
    /// Figs. 9-13: Australia's 8 points, stochastically interpolated at h = 0.5, 0.7, 0.87, 1
    Australia,
    /// Fig. 15: a B-spline surface on stochastic control points
    Bspline,
    /// Figs. 17-19: the subdivided planet at levels 2-5, at equal point spacing, and a zoom
    Planet,
    /// Fig. 20: crumpled paper, h = 0.3, 0.5, 0.7, 0.9 at constant area
    Paper,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[
        Fig::Paths,
        Fig::TwoResolutions,
        Fig::Polyline,
        Fig::Australia,
        Fig::Bspline,
        Fig::Planet,
        Fig::Paper,
    ];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::Paths => &["ffc_fig01-03_paths.png"],
            Fig::TwoResolutions => &["ffc_fig05_two_resolutions.png"],
            Fig::Polyline => &["ffc_fig07_polyline.png"],
            Fig::Australia => &["ffc_fig09-13_australia.png"],
            Fig::Bspline => &["ffc_fig15_bspline_mountain.png"],
            Fig::Planet => &[
                "ffc_fig17_planet_levels.png",
                "ffc_fig18_planet_sizes.png",
                "ffc_fig19_planet_zoom.png",
            ],
            Fig::Paper => &["ffc_fig20_crumpled_paper.png"],
        }
    }
}

type R<T> = Result<T, Exit>;

/// One layer of a picture: positions, triangles and the colour of a point.
type Layer<'a> = (&'a [Vec3], &'a [[u32; 3]], &'a dyn Fn(Vec3) -> Vec3, Shade);

/// How a layer's triangles are lit.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shade {
    /// By each facet's normal.
    Facet,
    /// By the normal of a sphere about the origin (a smooth sea).
    Sphere,
}

fn main() -> ExitCode {
    common::run(figures)
}

fn figures() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let seed = Seed(cli.seed);
    let q = cli.quick;
    figures::make(&out, &cli.only, |fig| {
        Ok(match fig {
            Fig::Paths => vec![paths(seed, q)?],
            Fig::TwoResolutions => vec![two_resolutions(seed)?],
            Fig::Polyline => vec![polyline(seed)?],
            Fig::Australia => vec![australia(seed)?],
            Fig::Bspline => vec![bspline(seed, q)?],
            Fig::Planet => planet(seed, q)?,
            Fig::Paper => vec![paper(seed, q)?],
        })
    })
}

/// Midpoint parameters with Hurst exponent `h` and roughness `scale`.
fn law(h: f64, scale: f64, endpoints: EndpointMode) -> MidpointParams {
    MidpointParams {
        h,
        scale,
        endpoints,
        ..MidpointParams::default()
    }
}

/// `(t, value)` pairs of a path on `[0, 1]`.
fn graph(v: &[f64]) -> Vec<(f64, f64)> {
    let n = (v.len() - 1) as f64;
    v.iter()
        .enumerate()
        .map(|(i, &y)| (i as f64 / n, y))
        .collect()
}

/// A y range around `v` with a margin.
fn y_range(v: &[f64]) -> [f64; 2] {
    let lo = v.iter().copied().fold(f64::MAX, f64::min);
    let hi = v.iter().copied().fold(f64::MIN, f64::max);
    let m = 0.08 * (hi - lo).max(1e-9);
    [lo - m, hi + m]
}

/// Figs. 1-3: sample paths for H = 0.5, 0.3, 0.7 (Fournier et al. 1982,
/// §2), stacked top to bottom. Each path's measured dimension D = 2 − H is
/// printed.
fn paths(seed: Seed, quick: bool) -> R<Image> {
    let levels = if quick { 9 } else { 11 };
    let mut c = Canvas::new(900, 600);
    let rows = c.grid(1, 3, 10.0, [0.0, 1.0, 0.0, 1.0]);
    for (k, h) in [0.5, 0.3, 0.7].into_iter().enumerate() {
        let p = MidpointParams {
            variance_correction: true,
            ..law(h, 1.0, EndpointMode::Random)
        };
        let v = midpoint_1d(&p, levels, seed.derive_index(k as u64))?;
        let [lo, hi] = y_range(&v);
        let panel = Panel::new(rows[k].rect, [0.0, 1.0, lo, hi]);
        c.axes(&panel, [0.125, 0.0]);
        c.line(&panel, &graph(&v), Pen::solid(colour::INK, 1.2));
        let d = 2.0 - path_h(&v, 1, 16)?;
        outln(format_args!(
            "  Fig. {}: H = {h}, measured D = 2 − H = {d:.3}",
            k + 1
        ))?;
    }
    Ok(c.into_image()?)
}

/// Fig. 5: the same path at 17 and 257 points (levels 4 and 8), h = 0.8
/// (the caption; the text says 0.6). The coarse points are checked to be
/// the fine path's every 16th point, bit for bit.
fn two_resolutions(seed: Seed) -> R<Image> {
    let p = law(0.8, 1.0, EndpointMode::Random);
    let (coarse, fine) = (midpoint_1d(&p, 4, seed)?, midpoint_1d(&p, 8, seed)?);
    if coarse
        .iter()
        .enumerate()
        .any(|(k, c)| c.to_bits() != fine[16 * k].to_bits())
    {
        return Err(Exit::new(
            1,
            "Fig. 5: the 17 points are not on the 257-point path",
        ));
    }
    let mut c = Canvas::new(900, 420);
    let [lo, hi] = y_range(&fine);
    let rows = c.grid(1, 2, 10.0, [0.0, 1.0, lo, hi]);
    c.axes(&rows[0], [0.0625, 0.0]);
    c.line(&rows[0], &graph(&coarse), Pen::solid(colour::INK, 1.5));
    c.dots(&rows[0], &graph(&coarse), colour::RED, 3.0);
    c.axes(&rows[1], [0.0625, 0.0]);
    c.line(&rows[1], &graph(&fine), Pen::solid(colour::INK, 1.2));
    c.dots(&rows[1], &graph(&coarse), colour::RED, 2.5);
    Ok(c.into_image()?)
}

/// Fig. 7: one segment subdivided 0, 2 and 8 times (0, 3 and 255
/// interpolated points) with displacements along the local segment normal,
/// h = 0.5, side by side.
fn polyline(seed: Seed) -> R<Image> {
    let ends = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0)];
    let p = law(0.5, 0.15, EndpointMode::Fixed(0.0, 0.0));
    let mut c = Canvas::new(900, 300);
    let cells = c.grid(3, 1, 10.0, [0.0, 1.0, 0.0, 1.0]);
    let xy = |levels| -> R<Vec<(f64, f64)>> {
        let pts = fractal_polyline(&ends, false, &p, levels, seed)?;
        Ok(pts.iter().map(|v| (v.x, v.y)).collect())
    };
    // The 5 points of the middle panel lie on the finest curve too.
    let five = xy(2)?;
    for (k, levels) in [0u32, 2, 8].into_iter().enumerate() {
        let panel = Panel::equal_aspect(cells[k].rect, [-0.05, 1.05], 0.0);
        c.axes(&panel, [0.0, 0.0]);
        c.line(&panel, &xy(levels)?, Pen::solid(colour::INK, 1.3));
        c.dots(
            &panel,
            &five[..if k == 0 { 0 } else { 5 }],
            colour::RED,
            2.5,
        );
    }
    Ok(c.into_image()?)
}

/// Australia as 8 points (longitude, latitude in degrees), clockwise from
/// Cape York: the Gulf of Carpentaria at Karumba, the Cobourg Peninsula,
/// North West Cape, Cape Leeuwin, the head of the Great Australian Bight,
/// Wilsons Promontory and Cape Byron. The source digitised its 8 points
/// from a map and does not list them.
const AUSTRALIA: [(f64, f64); 8] = [
    (142.5, -10.7),
    (140.8, -17.5),
    (132.3, -11.3),
    (114.0, -21.8),
    (115.1, -34.4),
    (131.2, -31.5),
    (146.4, -39.1),
    (153.6, -28.6),
];

/// The 8 points on a plane: degrees of longitude shrunk by cos 25°.
fn australia_points() -> Vec<DVec2> {
    let c = 25f64.to_radians().cos();
    AUSTRALIA
        .iter()
        .map(|&(lon, lat)| DVec2::new((lon - 134.0) * c, lat + 25.0))
        .collect()
}

/// The coastline of Figs. 10-13: 8 points and 8 × 127 interpolated ones.
fn coastline(h: f64, seed: Seed) -> R<Vec<DVec2>> {
    let p = law(h, 0.3, EndpointMode::Fixed(0.0, 0.0));
    Ok(fractal_polyline(&australia_points(), true, &p, 7, seed)?)
}

/// Figs. 9-13: the polygon, then the stochastic interpolations at h = 0.5,
/// 0.7, 0.87 (the coastline's measured H) and 1.0, in a 3 × 2 sheet.
fn australia(seed: Seed) -> R<Image> {
    let base = australia_points();
    let mut c = Canvas::new(900, 560);
    let cells = c.grid(3, 2, 8.0, [0.0, 1.0, 0.0, 1.0]);
    let frame = |k: usize| Panel::equal_aspect(cells[k].rect, [-22.0, 22.0], 0.0);
    let closed = |v: &[DVec2]| -> Vec<(f64, f64)> {
        v.iter().chain(v.first()).map(|p| (p.x, p.y)).collect()
    };
    let dots: Vec<(f64, f64)> = base.iter().map(|p| (p.x, p.y)).collect();
    c.line(&frame(0), &closed(&base), Pen::solid(colour::INK, 1.3));
    c.dots(&frame(0), &dots, colour::RED, 3.0);
    for (k, h) in [0.5, 0.7, 0.87, 1.0].into_iter().enumerate() {
        let line = coastline(h, seed)?;
        c.line(&frame(k + 1), &closed(&line), Pen::solid(colour::INK, 1.0));
        c.dots(&frame(k + 1), &dots, colour::RED, 2.5);
    }
    Ok(c.into_image()?)
}

/// A height field as triangles: positions and index triples, two per cell.
fn field_mesh(hf: &HeightField, scale: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (nx, ny) = (hf.nx(), hf.ny());
    let pos = (0..nx * ny)
        .map(|k| hf.point(k % nx, k / nx) * scale)
        .collect();
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = |a: usize, b: usize| ((b * nx) + a) as u32;
            tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    (pos, tris)
}

/// Draws flat-shaded triangles: the facet's (or the sphere's) normal turned
/// to the viewer, Lambert with an ambient term, colour `paint(centroid)`.
fn draw(frame: &mut Raster, view: &Projector, layer: &Layer<'_>, light: Vec3) -> R<()> {
    let &(pos, tris, paint, shade) = layer;
    let screen: Vec<Option<[f32; 3]>> = pos.iter().map(|&p| view.project(p)).collect();
    let light = light.normalize();
    for t in tris {
        let [a, b, c] = t.map(|i| i as usize);
        let (Some(pa), Some(pb), Some(pc)) = (screen[a], screen[b], screen[c]) else {
            continue;
        };
        let centre = (pos[a] + pos[b] + pos[c]) / 3.0;
        let n = match shade {
            Shade::Facet => (pos[b] - pos[a]).cross(pos[c] - pos[a]).normalize_or_zero(),
            Shade::Sphere => centre.normalize_or_zero(),
        };
        let n = facing(n, view.to_viewer(centre));
        let col = paint(centre) * lambert(n, light, 0.22);
        frame.triangle([pa, pb, pc], |_| col)?;
    }
    Ok(())
}

/// A picture of triangles through `camera`.
fn picture(
    size: (u32, u32),
    camera: &PreviewCamera,
    background: Vec3,
    layers: &[Layer<'_>],
    light: Vec3,
) -> R<Image> {
    let mut frame = Raster::new(size.0, size.1, 2, background)?;
    let (w, h) = frame.samples();
    let view = Projector::new(camera, w, h)?;
    for layer in layers {
        draw(&mut frame, &view, layer, light)?;
    }
    Ok(frame.resolve()?)
}

/// Fig. 15: a mountain: 5 × 5 coarse heights of a cone, stochastically
/// interpolated to a 17 × 17 net (quadrilateral subdivision, h = 0.7, the
/// coarse points kept), shown as its facets (left) and as the control net
/// of a bicubic B-spline surface (right).
fn bspline(seed: Seed, quick: bool) -> R<Image> {
    let cone = |i: usize, j: usize| {
        let r = (((i as f64 - 8.0).powi(2) + (j as f64 - 8.0).powi(2)).sqrt()) / 8.0;
        7.0 * (1.0 - r).max(0.0)
    };
    let sub = SubdivisionParams {
        midpoint: law(0.7, 1.6, EndpointMode::Fixed(0.0, 0.0)),
        scheme: SubdivisionScheme::Quad,
        levels: Some(2),
    };
    let noise = subdivide(17, 17, 1.0, &sub, seed)?;
    // The coarse points every 4 cells, joined bilinearly; the subdivision
    // is zero there, so the net passes through them.
    let base = |i: usize, j: usize| {
        let (a, b) = (i / 4 * 4, j / 4 * 4);
        let (a1, b1) = ((a + 4).min(16), (b + 4).min(16));
        let (u, v) = ((i - a) as f64 / 4.0, (j - b) as f64 / 4.0);
        let top = cone(a, b) * (1.0 - u) + cone(a1, b) * u;
        let bottom = cone(a, b1) * (1.0 - u) + cone(a1, b1) * u;
        top * (1.0 - v) + bottom * v
    };
    let net = HeightField::from_fn(17, 17, 1.0, |i, j| {
        (base(i, j) + f64::from(noise.heights()[(i, j)])) as f32
    })?;
    let smooth = bspline_surface(&net, if quick { 6 } else { 16 })?;
    let (lo, hi) = net.heights().min_max();
    let paint = move |p: Vec3| Ramp::Terrain.eval(((p.z - lo) / (hi - lo)).clamp(0.0, 1.0));
    let size = if quick { (240, 180) } else { (440, 330) };
    let sky = Vec3::new(0.55, 0.68, 0.85);
    let light = Vec3::new(-0.6, -0.4, 0.7);
    let mut shots = Vec::new();
    // The B-spline's domain starts one control point in: shift it back.
    for (hf, offset) in [(&net, 0.0), (&smooth, 1.0)] {
        let (mut pos, tris) = field_mesh(hf, 1.0);
        for p in &mut pos {
            *p += Vec3::new(offset, offset, 0.0);
        }
        let mut cam = PreviewCamera::framing(
            Vec3::new(0.0, 0.0, lo),
            Vec3::new(16.0, 16.0, hi),
            Vec3::new(0.5, 1.0, -0.45),
            Some(30.0),
            size.0 as f32 / size.1 as f32,
        )?;
        // The framing allows for any view of the box; this one needs less.
        cam.projection = PreviewProjection::Perspective { fov_y_deg: 21.0 };
        let layer: Layer<'_> = (&pos, &tris, &paint, Shade::Facet);
        shots.push(picture(size, &cam, sky, &[layer], light)?);
    }
    Ok(Image::contact_sheet(&shots, 2, 6, Vec3::ONE)?)
}

/// Vertices of a sphere: an icosahedron split `n` times, projected.
fn icosphere(n: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    #[rustfmt::skip]
    let corners = [
        (-1.0, t, 0.0), (1.0, t, 0.0), (-1.0, -t, 0.0), (1.0, -t, 0.0),
        (0.0, -1.0, t), (0.0, 1.0, t), (0.0, -1.0, -t), (0.0, 1.0, -t),
        (t, 0.0, -1.0), (t, 0.0, 1.0), (-t, 0.0, -1.0), (-t, 0.0, 1.0),
    ];
    let mut pos: Vec<DVec3> = corners
        .iter()
        .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
        .collect();
    #[rustfmt::skip]
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    for _ in 0..n {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        let mut m = |a: u32, b: u32, pos: &mut Vec<DVec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pos.push((pos[a as usize] + pos[b as usize]).normalize());
                (pos.len() - 1) as u32
            })
        };
        for [a, b, c] in tris {
            let (ab, bc, ca) = (m(a, b, &mut pos), m(b, c, &mut pos), m(c, a, &mut pos));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        tris = next;
    }
    (pos, tris)
}

/// The planet's land and sea at subdivision `level`: the base sphere's
/// points raised by a Gaussian altitude each (the database), subdivided
/// with h = 0.6 along the mean of the endpoints' normals; the sea is the
/// same base without any stochastic component, so coastlines are where the
/// two surfaces cross (drawn with a depth buffer, as in the source).
/// `keep` selects the base triangles to subdivide (all for whole planets).
fn planet_meshes(
    seed: Seed,
    base_splits: u32,
    level: u32,
    relief: f64,
    keep: &dyn Fn([DVec3; 3]) -> bool,
) -> R<(TriMesh, TriMesh)> {
    let (pos, tris) = icosphere(base_splits);
    let tris: Vec<[u32; 3]> = tris
        .into_iter()
        .filter(|t| keep(t.map(|i| pos[i as usize])))
        .collect();
    let ids: Vec<u64> = (0..pos.len() as u64).collect();
    let p0 = law(0.6, relief, EndpointMode::Fixed(0.0, 0.0));
    let lifted: Vec<DVec3> = pos
        .iter()
        .enumerate()
        .map(|(i, &p)| p * (1.0 + relief * (seed.gaussian1(i as i64) - 0.25)))
        .collect();
    let land = TriMesh::with_normals(lifted, pos.clone(), ids.clone(), tris.clone())?;
    let sea = TriMesh::with_normals(pos.clone(), pos, ids, tris)?;
    let land = subdivide_mesh(&land, &p0, level, seed)?;
    let sea = subdivide_mesh(
        &sea,
        &law(0.6, 0.0, EndpointMode::Fixed(0.0, 0.0)),
        level,
        seed,
    )?;
    Ok((land, sea))
}

fn to_f32(m: &TriMesh) -> Vec<Vec3> {
    m.positions.iter().map(|p| p.as_vec3()).collect()
}

/// A picture of the planet's land and sea through an orthographic camera
/// looking along +y at `target`, `height` world units tall.
fn planet_view(land: &TriMesh, sea: &TriMesh, px: u32, target: Vec3, height: f32) -> R<Image> {
    let cam = PreviewCamera {
        eye: target - Vec3::Y * 4.0,
        target,
        up: Vec3::Z,
        projection: PreviewProjection::Orthographic { height },
    };
    let ocean = |_: Vec3| Vec3::new(0.05, 0.16, 0.45);
    let ground = |p: Vec3| {
        let alt = (p.length() - 1.0) / 0.1;
        Ramp::Terrain.eval((0.3 + 0.7 * alt).clamp(0.0, 1.0))
    };
    let (lp, sp) = (to_f32(land), to_f32(sea));
    picture(
        (px, px),
        &cam,
        Vec3::ZERO,
        &[
            (&sp[..], &sea.triangles[..], &ocean, Shade::Sphere),
            (&lp[..], &land.triangles[..], &ground, Shade::Facet),
        ],
        Vec3::new(-0.5, -0.8, 0.45),
    )
}

/// The highest point of a planet above the unit sphere, in radii.
fn highest_peak(m: &TriMesh) -> f64 {
    m.positions
        .iter()
        .map(|p| p.length() - 1.0)
        .fold(0.0f64, f64::max)
}

/// The relief that puts the highest peak of the whole planet at `level`
/// about 0.1 radii up: a first pass at a small relief fixes the scale.
fn planet_relief(seed: Seed, base: u32, level: u32) -> R<f64> {
    let (probe, _) = planet_meshes(seed, base, level, 0.02, &|_| true)?;
    Ok(0.02 * 0.1 / highest_peak(&probe).max(1e-9))
}

/// Figs. 17-19: the planet at levels 2, 3, 4, 5 at one size (17), at sizes
/// that keep the spacing of computed points on screen the same (18), and
/// four views zooming twice at each step into its lower left, one level
/// deeper each (19). The relief is scaled so the highest peak of the
/// deepest whole planet is about 10% of the radius, as in the source.
fn planet(seed: Seed, quick: bool) -> R<Vec<Image>> {
    let (base, px, zooms) = if quick { (1, 160, 2) } else { (2, 256, 4) };
    let levels = [2u32, 3, 4, 5];
    let all = |_: [DVec3; 3]| true;
    let relief = planet_relief(seed, base, levels[3])?;
    let mut same_size = Vec::new();
    let mut sized = Vec::new();
    for (k, &l) in levels.iter().enumerate() {
        let (land, sea) = planet_meshes(seed, base, l, relief, &all)?;
        same_size.push(planet_view(&land, &sea, px, Vec3::ZERO, 2.3)?);
        let s = (px as f32 * 0.5f32.powi(3 - k as i32)).max(24.0) as u32;
        sized.push(planet_view(&land, &sea, s, Vec3::ZERO, 2.3)?);
        if k == 3 {
            outln(format_args!(
                "  Figs. 17-18: h = 0.6, levels {levels:?} over a {}-face sphere; highest peak {:.3} radii",
                20 * 4u32.pow(base),
                highest_peak(&land)
            ))?;
        }
    }
    // Fig. 19: zoom into the lower left; only the base triangles in view
    // are subdivided (their points are the whole planet's, keyed by ids).
    // Centred on the coast: the point of the deepest whole planet nearest
    // sea level close to the lower left of the view.
    let (land, _) = planet_meshes(seed, base, levels[3], relief, &all)?;
    let nominal = DVec3::new(-0.5, -0.5f64.sqrt(), -0.5);
    let spot = land
        .positions
        .iter()
        .filter(|p| p.normalize().dot(nominal) > 0.2f64.cos())
        .min_by(|a, b| {
            let f = |p: &DVec3| (p.length() - 1.0).abs() + 0.02 * p.normalize().dot(nominal).acos();
            f(a).total_cmp(&f(b))
        })
        .map_or(nominal, |p| p.normalize());
    let mut zoomed = Vec::new();
    for z in 0..zooms {
        let height = 2.3 / 2f32.powi(z as i32 + 1);
        let reach = 0.75 * f64::from(height);
        let near = move |t: [DVec3; 3]| {
            let c = (t[0] + t[1] + t[2]) / 3.0;
            let r = t.iter().map(|v| v.distance(c)).fold(0.0, f64::max);
            c.normalize().dot(spot).clamp(-1.0, 1.0).acos() < reach + r + 0.05
        };
        let (land, sea) = planet_meshes(seed, base, levels[3] + z, relief, &near)?;
        let target = Vec3::new(spot.x as f32, 0.0, spot.z as f32);
        zoomed.push(planet_view(&land, &sea, px * 3 / 4, target, height)?);
    }
    Ok(vec![
        Image::contact_sheet(&same_size, 4, 4, Vec3::ZERO)?,
        Image::contact_sheet(&sized, 4, 4, Vec3::ZERO)?,
        Image::contact_sheet(&zoomed, 4, 4, Vec3::ZERO)?,
    ])
}

/// The paper of Fig. 20 at `h`: a unit sheet displaced by the grid fill
/// (fixed corners), rescaled so its area is `area` (or left as it is for
/// `None`); returns it with the scale applied.
fn sheet(seed: Seed, h: f64, levels: u32, area: Option<f64>) -> R<(HeightField, f32)> {
    let n = (1usize << levels) + 1;
    let sub = SubdivisionParams {
        midpoint: law(h, 0.12, EndpointMode::Fixed(0.0, 0.0)),
        scheme: SubdivisionScheme::DiamondSquare,
        levels: Some(levels),
    };
    let hf = subdivide(n, n, 1.0 / (n - 1) as f32, &sub, seed)?;
    let s = match area {
        Some(a) => (a / surface_area(&hf)?).sqrt() as f32,
        None => 1.0,
    };
    Ok((hf, s))
}

/// Fig. 20: the sheet at h = 0.3, 0.5, 0.7, 0.9 (one seed), each rescaled
/// to the area of the smoothest, all framed alike.
fn paper(seed: Seed, quick: bool) -> R<Image> {
    let levels = if quick { 5 } else { 7 };
    let (smooth, _) = sheet(seed, 0.9, levels, None)?;
    let area = surface_area(&smooth)?;
    let size = if quick { (160, 130) } else { (320, 260) };
    let mut cam = PreviewCamera::framing(
        Vec3::new(0.05, 0.05, -0.15),
        Vec3::new(0.95, 0.95, 0.15),
        Vec3::new(0.5, 1.0, -0.9),
        Some(28.0),
        size.0 as f32 / size.1 as f32,
    )?;
    // The framing allows for any view of the box; this one needs less.
    cam.projection = PreviewProjection::Perspective { fov_y_deg: 25.0 };
    let paint = |_: Vec3| Vec3::new(0.93, 0.92, 0.86);
    let mut shots = Vec::new();
    for h in [0.3, 0.5, 0.7, 0.9] {
        let (hf, s) = sheet(seed, h, levels, Some(area))?;
        let (mut pos, tris) = field_mesh(&hf, s);
        // Centre the shrunk sheet where the full one lies.
        let shift = Vec3::new(0.5 - 0.5 * s, 0.5 - 0.5 * s, 0.0);
        for p in &mut pos {
            *p += shift;
        }
        let light = Vec3::new(-0.4, -0.7, 0.6);
        let layer: Layer<'_> = (&pos, &tris, &paint, Shade::Facet);
        shots.push(picture(
            size,
            &cam,
            Vec3::new(0.2, 0.22, 0.25),
            &[layer],
            light,
        )?);
        outln(format_args!(
            "  Fig. 20: h = {h}: scaled by {s:.3} to area {area:.3}"
        ))?;
    }
    Ok(Image::contact_sheet(&shots, 4, 4, Vec3::ONE)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_picture_docs_figures_md_links_exists() {
        // docs/figures.md: one row per figure of the sources, each linking
        // natura's pictures (or saying "not yet"); the links must resolve.
        let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
        let text = std::fs::read_to_string(docs.join("figures.md")).unwrap();
        let rows = text
            .lines()
            .filter(|l| l.starts_with("| ") && !l.starts_with("| figure"));
        let mut n = 0;
        for row in rows {
            n += 1;
            let links: Vec<&str> = row.split("](gallery/").skip(1).collect();
            assert!(!links.is_empty() || row.contains("not yet"), "{row}");
            for l in links {
                let path = &l[..l.find(')').unwrap()];
                assert!(docs.join("gallery").join(path).is_file(), "{path} in {row}");
            }
        }
        assert_eq!(n, 118, "rows in docs/figures.md");
        // The header's tally is the rows' statuses.
        let count = |status: &str| text.matches(&format!("| {status} |")).count();
        let (made, partly, missing) = (count("re-made"), count("partly"), count("missing"));
        assert_eq!(made + partly + missing, n);
        let tally = format!(
            "Of the {n}, {made} are re-made, {partly} partly (a flat colour map where the\nsource shows a rendered patch, a different scene, a missing element) and\n{missing} missing"
        );
        assert!(text.contains(&tally), "the header should read: {tally}");
        let missing = common::figures::unlisted_in_figures_md::<Fig>();
        assert!(missing.is_empty(), "not in docs/figures.md: {missing:?}");
    }

    #[test]
    fn the_coarse_path_is_the_fine_path_subsampled() {
        // Fig. 5: 17 and 257 points of the same sample path.
        let p = law(0.8, 1.0, EndpointMode::Random);
        let (c, f) = (
            midpoint_1d(&p, 4, Seed(3)).unwrap(),
            midpoint_1d(&p, 8, Seed(3)).unwrap(),
        );
        assert_eq!((c.len(), f.len()), (17, 257));
        assert!(
            c.iter()
                .zip(f.iter().step_by(16))
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }

    #[test]
    fn the_coastline_keeps_australias_8_points_and_adds_8_x_127() {
        let line = coastline(0.87, Seed(1)).unwrap();
        assert_eq!(line.len(), 8 + 8 * 127);
        for (k, p) in australia_points().iter().enumerate() {
            assert_eq!(line[k * 128], *p);
        }
    }

    #[test]
    fn the_papers_have_one_area() {
        let (smooth, _) = sheet(Seed(2), 0.9, 4, None).unwrap();
        let area = surface_area(&smooth).unwrap();
        for h in [0.3, 0.5, 0.7] {
            let (hf, s) = sheet(Seed(2), h, 4, Some(area)).unwrap();
            let scaled = HeightField::from_fn(hf.nx(), hf.ny(), hf.cell_size() * s, |i, j| {
                hf.heights()[(i, j)] * s
            })
            .unwrap();
            let a = surface_area(&scaled).unwrap();
            assert!((a / area - 1.0).abs() < 1e-4, "h {h}: {a} vs {area}");
            assert!(s < 1.0, "a rougher sheet is shrunk");
        }
    }

    #[test]
    fn the_planets_peaks_are_a_tenth_of_its_radius_and_the_zoom_draws_its_points() {
        // Figs. 17-19: h = 0.6, the highest peaks about 10% of the radius.
        let seed = Seed(1982);
        let relief = planet_relief(seed, 1, 4).unwrap();
        let (land, _) = planet_meshes(seed, 1, 4, relief, &|_| true).unwrap();
        assert!(
            (highest_peak(&land) - 0.1).abs() < 0.01,
            "{}",
            highest_peak(&land)
        );
        // A zoom subdivides only some base triangles; every point it draws
        // is the whole planet's point with that identifier, bit for bit.
        let spot = DVec3::new(-0.5, -0.5f64.sqrt(), -0.5);
        let near = |t: [DVec3; 3]| t.iter().any(|v| v.dot(spot) > 0.8);
        let (part, _) = planet_meshes(seed, 1, 4, relief, &near).unwrap();
        assert!(part.triangles.len() < land.triangles.len() / 4);
        let whole: std::collections::HashMap<u64, DVec3> = land
            .ids
            .iter()
            .copied()
            .zip(land.positions.iter().copied())
            .collect();
        for (id, p) in part.ids.iter().zip(&part.positions) {
            let q = whole.get(id).expect("a point of the whole planet");
            assert_eq!(p.to_array(), q.to_array());
        }
    }

    #[test]
    fn the_planets_land_and_sea_share_their_base() {
        let all = |_: [DVec3; 3]| true;
        let (land, sea) = planet_meshes(Seed(5), 0, 2, 0.05, &all).unwrap();
        assert_eq!(land.triangles.len(), 20 * 16);
        assert_eq!(land.triangles, sea.triangles);
        // The sea has no stochastic component: its base points are on the sphere.
        assert!(
            sea.positions[..12]
                .iter()
                .all(|p| (p.length() - 1.0).abs() < 1e-12)
        );
    }
}
