//! Stray bright pixels (natura-render's `stray::stray_pixels`) in quick
//! renders of the landscape, a panorama of the same world and the valley
//! morning scene, at the scene's 4 samples a pixel: none in any of them,
//! so a change that adds specks fails here.
//!
//! Fixed at their causes:
//!
//! * Rows of lone white pixels on the far snowy slopes: the snow's edge
//!   noise was band-limited to the pixel's width across the view, while on
//!   a slope seen at a slant the pixel covers ten times more along it; the
//!   cover now sees the footprint on the ground (as the water's waves do).
//! * Lone bright pixels in the water along far shores: a ray reflected off
//!   the water met the shore triangle of its cell within centimetres of the
//!   level and was taken for water, mirroring the sky at the horizon; a
//!   rising ray now always meets the bare bank.
//! * Pixels on a silhouette against a far brighter background, one of
//!   whose four samples passed over the crest (the valley's ridge against
//!   the sky, 0.9 m and 1.3 m above it at 2.3 km; in the panorama a near
//!   ridge against the lake 8 km away, 0.12 m above the crest at 3.7 km):
//!   the background covers a few per cent of such a pixel, four samples
//!   counted a quarter, and the sky is 15 to 20 times brighter than the
//!   ridge in the shade. Such a pixel's samples disagree, so it now takes
//!   16 (`render.adaptive_samples`), which count the sky within a
//!   sixteenth.
//!
//! The forest is held to the count it shows today instead of none: its
//! crowns at these sizes are lit tips and sun-flecks a pixel wide among
//! shade. Where a pixel covers many leaves the sun on them is now the mean
//! through the crowns as turbid media, and the shade is lit from below,
//! which halved the count in the default landscape. The camera's blur, the
//! Gaussian pixel filter of σ = 0.5 pixel now on by default, spreads a lit
//! tip over its neighbours as a lens does: the quick forest's count fell
//! from 141 to 11, the full-size landscape's from 2949 to 637.
//!
//! Over the whole gallery (an ignored test CI runs on its quick run of
//! every example): every preview picture the crates draw was a box over
//! one to four samples a pixel, which left aliased specks in textures,
//! planets, plants and stars (25 000 over the full-size gallery). They are
//! now resolved by the same camera filter from 4 to 9 samples a pixel, and
//! each picture is held to the count it shows today.

use natura_core::NoProgress;
use natura_render::scene::CameraKind;
use natura_render::stray::stray_pixels;
use natura_render::{SceneDesc, render_scene};

use crate::common::quick_preview;

/// The landscape example's `--quick` set-up, without the forest.
fn quick(s: &SceneDesc) -> SceneDesc {
    let mut s = quick_preview(s);
    s.vegetation.enabled = false;
    s
}

/// Stray pixels in the quick landscape with its forest, today (141 under
/// the box filter).
const KNOWN_FOREST_STRAYS: usize = 8;

/// Fails if `scene` shows more than `known` stray pixels.
fn at_most(scene: &SceneDesc, known: usize) {
    let found = count(scene);
    eprintln!("{} stray pixels: {found:?}", found.len());
    assert!(
        found.len() <= known,
        "{} stray pixels: {found:?}",
        found.len()
    );
}

fn count(scene: &SceneDesc) -> Vec<(usize, usize)> {
    // The picture as shown: exposed and tone-mapped.
    let r = render_scene(scene, &NoProgress).unwrap();
    stray_pixels(&r.display())
}

#[test]
fn quick_landscape_has_no_stray_pixels() {
    let s = quick(&SceneDesc::default());
    at_most(&s, 0);
}

/// The panorama under the box filter, which guards the silhouettes' fix
/// (a near ridge against the lake 8 km away): under the default Gaussian
/// filter one pixel at the tip of a one-pixel sliver of the lake between
/// two ridges is flagged, (55, 61), whose neighbours along the sliver the
/// filter has dimmed below the detector's ratio: the sliver's own light at
/// the detector's threshold, not a sample's accident.
#[test]
fn quick_panorama_has_no_stray_pixels() {
    let mut s = quick(&SceneDesc::default());
    s.camera.kind = CameraKind::Cylindrical;
    s.camera.hfov_deg = 220.0;
    s.camera.vfov_deg = 40.0;
    s.render.width = 480;
    s.render.height = 87;
    s.render.filter_sigma_px = 0.0;
    at_most(&s, 0);
}

#[test]
fn quick_valley_morning_has_no_stray_pixels() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/valley_morning.toml"
    );
    let s = quick(&SceneDesc::load(path).unwrap());
    at_most(&s, 0);
}

/// The detector over full-size pictures: the PNG files named in
/// `STRAY_PICTURES` (separated by `:`), or else the gallery's render
/// pictures. Each count is printed; the test fails if any is not 0.
#[test]
#[ignore = "reads full-size pictures: cargo test --release -p natura-render --test it -- stray_pixels:: --ignored --nocapture"]
fn pictures_have_no_stray_pixels() {
    let paths: Vec<std::path::PathBuf> = match std::env::var("STRAY_PICTURES") {
        Ok(list) => list.split(':').map(Into::into).collect(),
        Err(_) => {
            let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/gallery/render");
            let mut v: Vec<_> = std::fs::read_dir(dir)
                .unwrap()
                .map(|e| e.unwrap().path())
                .filter(|p| p.extension().is_some_and(|e| e == "png"))
                .collect();
            v.sort();
            v
        }
    };
    let mut stray = 0;
    for p in &paths {
        let image = natura_core::Image::load_png(p).unwrap();
        let found = stray_pixels(&image);
        eprintln!("{}: {} stray pixels", p.display(), found.len());
        stray += found.len();
    }
    assert_eq!(stray, 0, "stray pixels in {} pictures", paths.len());
}

/// The stray pixels each picture of the quick gallery is known to show
/// today (`scripts/gallery.sh --quick`, relative path and count, tab
/// separated); a picture not listed must show none.
const QUICK_GALLERY_CEILINGS: &str = include_str!("../stray_ceilings.tsv");

/// The detector over every PNG picture of a quick gallery, the folder
/// `STRAY_GALLERY` names (CI sets it to the folder its quick run of every
/// example wrote): no picture may show more stray pixels than
/// `stray_ceilings.tsv` lists for it, and one it does not list none, so a
/// change that adds specks anywhere in the gallery fails. Fails, never
/// skips, when `STRAY_GALLERY` is not set or holds no pictures.
#[test]
#[ignore = "needs the quick gallery: STRAY_GALLERY=<dir> cargo test --release -p natura-render --test it -- --ignored stray_pixels::quick_gallery"]
fn quick_gallery_has_no_more_stray_pixels_than_known() {
    let dir = std::path::PathBuf::from(
        std::env::var("STRAY_GALLERY").expect("STRAY_GALLERY must name the quick gallery's folder"),
    );
    let ceilings: std::collections::HashMap<&str, usize> = QUICK_GALLERY_CEILINGS
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let (path, n) = l.split_once('\t').expect("path<TAB>count");
            (path, n.trim().parse().expect("a count"))
        })
        .collect();
    let mut pictures = Vec::new();
    let mut stack = vec![dir.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "png") {
                pictures.push(p);
            }
        }
    }
    pictures.sort();
    assert!(!pictures.is_empty(), "no pictures under {}", dir.display());
    let (mut over, mut total) = (Vec::new(), 0);
    for p in &pictures {
        let rel = p
            .strip_prefix(&dir)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let image = natura_core::Image::load_png(p).unwrap();
        let found = stray_pixels(&image).len();
        let known = ceilings.get(rel.as_str()).copied().unwrap_or(0);
        total += found;
        if found > 0 || known > 0 {
            eprintln!("{rel}\t{found}\t(known {known})");
        }
        if found > known {
            over.push(format!("{rel}: {found} > {known}"));
        }
    }
    eprintln!("{} pictures, {total} stray pixels", pictures.len());
    assert!(over.is_empty(), "more stray pixels than known: {over:?}");
}

/// The quick landscape with its forest. The forest's lit crowns among
/// shade still leave specks (the target is none); this holds the count
/// known today, so a change that adds specks fails here.
#[test]
fn quick_forest_has_no_more_stray_pixels_than_known() {
    let mut s = quick(&SceneDesc::default());
    s.vegetation.enabled = true;
    at_most(&s, KNOWN_FOREST_STRAYS);
}
