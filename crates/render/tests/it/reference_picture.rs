//! The main job's picture against its reference: the landscape example's
//! `--quick` render of the default scene (its terrain on 256 samples, the
//! erosion, the forest of five species with its far canopy, the layer
//! clouds, the terrain's procedural detail, 320 × 180 pixels at 4 samples)
//! compared with `tests/reference/landscape_quick.png`.
//!
//! A change meant to keep the picture (a faster path, a new data layout)
//! must reproduce it bit for bit, or, where an approximation moves a
//! sample, stay within [`BOUND`]: such a change moves a hit within the
//! detail tracer's tolerance, and a pixel changes only where one of its
//! samples crossed an edge (a silhouette, a shadow's edge, the snow line).
//! A change meant to alter the picture re-blesses the reference:
//! `NATURA_BLESS=1 cargo test --release -p natura-render --test it -- reference_picture::`.
//!
//! The bound was set against a real approximation: the detail tracer's
//! over-relaxed march, which moves hits within a quarter of a pixel's
//! footprint, changed this picture by a mean of 0.0006 level and no
//! channel by more than 2 levels (the full-size picture: 0.06 % of its
//! pixels by more than one level, none by more than 43). The checks below
//! show that the same picture with the detail off, or exposed a tenth of a
//! stop brighter, falls outside it.

use std::path::PathBuf;

use natura_core::{Image, NoProgress};
use natura_render::{SceneDesc, render_scene};

use crate::common::quick_preview;

/// The difference between two pictures of the same size, over the 8-bit
/// sRGB channels of the displayed image (and, as [`BOUND`], the largest a
/// render may show and still be "the same picture").
#[derive(Debug, Clone, Copy, PartialEq)]
struct Difference {
    /// Mean absolute difference over all channels, in levels.
    mean_abs: f64,
    /// Fraction of pixels with a channel more than 2 levels off.
    moved: f64,
    /// Largest difference of any channel, in levels.
    max: u8,
}

/// The stated error: a mean of at most 0.05 level, at most 0.25 % of the
/// pixels (144 of 57 600) more than two levels off, none more than 64
/// levels (a pixel one of whose 4 samples crossed from shade onto sunlit
/// snow moves by about a quarter of the range under the camera's filter).
const BOUND: Difference = Difference {
    mean_abs: 0.05,
    moved: 0.0025,
    max: 64,
};

impl Difference {
    fn of(a: &Image, b: &Image) -> Self {
        assert_eq!(
            (a.width(), a.height()),
            (b.width(), b.height()),
            "the pictures differ in size"
        );
        let (a, b) = (a.to_srgb8(), b.to_srgb8());
        let d: Vec<u8> = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).collect();
        let pixels = d.len() / 3;
        Difference {
            mean_abs: d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64,
            moved: d.chunks(3).filter(|p| p.iter().any(|&v| v > 2)).count() as f64 / pixels as f64,
            max: d.iter().copied().max().unwrap_or(0),
        }
    }

    fn identical(&self) -> bool {
        self.max == 0
    }

    fn within(&self, bound: Difference) -> bool {
        self.mean_abs <= bound.mean_abs && self.moved <= bound.moved && self.max <= bound.max
    }
}

/// The landscape example's `--quick` scene.
fn main_job_quick() -> SceneDesc {
    quick_preview(&SceneDesc::default())
}

fn reference_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference/landscape_quick.png")
}

#[test]
fn the_main_jobs_picture_matches_its_reference() {
    let rendered = render_scene(&main_job_quick(), &NoProgress).unwrap();
    let shown = rendered.display();
    let path = reference_path();
    if std::env::var_os("NATURA_BLESS").is_some() {
        shown.save_png(&path).unwrap();
        eprintln!("blessed {}", path.display());
        return;
    }
    let reference = Image::load_png(&path).unwrap();
    let diff = Difference::of(&shown, &reference);
    eprintln!(
        "against the reference: {}; {diff:?}",
        if diff.identical() {
            "identical"
        } else {
            "changed"
        }
    );
    assert!(
        diff.within(BOUND),
        "the picture moved beyond the stated bound {BOUND:?}: {diff:?} \
         (a deliberate change re-blesses with NATURA_BLESS=1)"
    );

    // The bound sees a picture that is not the same: a tenth of a stop of
    // exposure, which shifts every lit pixel by a level or two.
    let brighter = rendered
        .image
        .tone_mapped(rendered.exposure_ev + 0.1, rendered.tone_map);
    let diff = Difference::of(&brighter, &reference);
    assert!(!diff.within(BOUND), "a tenth of a stop passed: {diff:?}");
}

/// The bound sees a change of geometry: the same scene without the
/// terrain's procedural detail falls outside it.
#[test]
fn the_bound_sees_the_detail_turned_off() {
    let mut s = main_job_quick();
    s.detail.enabled = false;
    let shown = render_scene(&s, &NoProgress).unwrap().display();
    let reference = Image::load_png(reference_path()).unwrap();
    let diff = Difference::of(&shown, &reference);
    eprintln!("without the detail: {diff:?}");
    assert!(
        !diff.within(BOUND),
        "the picture without detail passed: {diff:?}"
    );
}

#[test]
fn the_difference_is_zero_for_the_same_picture_and_counts_a_changed_pixel() {
    let a = Image::from_fn(4, 2, |x, y| {
        natura_core::glam::Vec3::splat((x + 4 * y) as f32 / 8.0)
    })
    .unwrap();
    let d = Difference::of(&a, &a);
    assert!(d.identical() && d.within(BOUND));
    let mut b = a.clone();
    b.set(1, 1, natura_core::glam::Vec3::ONE);
    let d = Difference::of(&a, &b);
    assert!(!d.identical());
    assert_eq!(d.moved, 1.0 / 8.0);
    assert!(d.max > 2);
}
