//! The driver the figure programs share: the figures a command line asks
//! for (every one when it names none), each made, timed and written under
//! a temporary name, and all renamed into place together at the end, so a
//! failure leaves the previous pictures as they were.

use std::path::{Path, PathBuf};
use std::time::Instant;

use natura::core::glam::Vec3;
use natura::core::{Grid2, Image, io::OutputSet};

use super::{Exit, Run, outln};

/// The figures of one source, in the source's order.
pub trait Figure: Copy + PartialEq + std::fmt::Debug + 'static {
    /// Every figure, in the source's order.
    const ALL: &'static [Self];

    /// The files the figure writes, in the order its maker returns images.
    fn files(self) -> &'static [&'static str];
}

/// The figures of `F` that `only` asks for (every one when it is empty),
/// in the source's order.
pub fn selected<F: Figure>(only: &[F]) -> Vec<F> {
    F::ALL
        .iter()
        .copied()
        .filter(|f| only.is_empty() || only.contains(f))
        .collect()
}

/// Makes the figures `only` asks for with `draw` (one image per file of
/// the figure), writes them as PNGs into `out` and prints each figure's
/// time and then the files written.
///
/// Fails when `draw` fails, when it returns a different number of images
/// than the figure has files, or when a file cannot be written; nothing is
/// renamed into place then.
pub fn make<F: Figure>(
    out: &Path,
    only: &[F],
    mut draw: impl FnMut(F) -> Result<Vec<Image>, Exit>,
) -> Run {
    let figs = selected(only);
    let targets: Vec<PathBuf> = figs
        .iter()
        .flat_map(|f| f.files().iter().map(|n| out.join(n)))
        .collect();
    let set = OutputSet::new(&targets)?;
    let width = F::ALL
        .iter()
        .map(|f| format!("{f:?}").len())
        .max()
        .unwrap_or(0);
    for fig in figs {
        let t0 = Instant::now();
        let images = draw(fig)?;
        if images.len() != fig.files().len() {
            return Err(Exit::new(
                2,
                format!(
                    "figure {fig:?} made {} pictures for {} files",
                    images.len(),
                    fig.files().len()
                ),
            ));
        }
        for (img, name) in images.iter().zip(fig.files()) {
            img.save_png(set.stage(out.join(name))?)?;
        }
        outln(format_args!(
            "{:<width$} {:6.2} s",
            format!("{fig:?}"),
            t0.elapsed().as_secs_f64()
        ))?;
    }
    set.commit()?;
    for t in &targets {
        outln(format_args!("wrote {}", t.display()))?;
    }
    Ok(())
}

/// The files of `F`'s figures that docs/figures.md does not link (as
/// `gallery/figures/NAME`); a figure program's test asserts there are none.
///
/// # Panics
///
/// If docs/figures.md cannot be read.
pub fn unlisted_in_figures_md<F: Figure>() -> Vec<&'static str> {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    let text = std::fs::read_to_string(docs.join("figures.md")).expect("docs/figures.md");
    F::ALL
        .iter()
        .flat_map(|f| f.files().iter().copied())
        .filter(|name| !text.contains(&format!("gallery/figures/{name}")))
        .collect()
}

/// `img` enlarged `k` times with bilinear filtering, for pictures of small
/// grids (a simulation's cells, one pixel each).
///
/// # Errors
///
/// As [`Grid2::from_fn`] (a picture too large).
pub fn enlarge(img: &Image, k: usize) -> Result<Image, Exit> {
    let (w, h) = (img.width(), img.height());
    let at = |x: usize, y: usize| img.get(x.min(w - 1), y.min(h - 1)).unwrap_or(Vec3::ZERO);
    Ok(Image::from_grid(Grid2::from_fn(w * k, h * k, |x, y| {
        let fx = ((x as f32 + 0.5) / k as f32 - 0.5).max(0.0);
        let fy = ((y as f32 + 0.5) / k as f32 - 0.5).max(0.0);
        let (x0, y0) = (fx as usize, fy as usize);
        let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
        let top = at(x0, y0).lerp(at(x0 + 1, y0), tx);
        let bottom = at(x0, y0 + 1).lerp(at(x0 + 1, y0 + 1), tx);
        top.lerp(bottom, ty)
    })?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Two {
        A,
        B,
    }

    impl Figure for Two {
        const ALL: &'static [Self] = &[Two::A, Two::B];
        fn files(self) -> &'static [&'static str] {
            match self {
                Two::A => &["a.png"],
                Two::B => &["b1.png", "b2.png"],
            }
        }
    }

    #[test]
    fn an_empty_choice_is_every_figure_in_order() {
        assert_eq!(selected::<Two>(&[]), vec![Two::A, Two::B]);
        assert_eq!(selected(&[Two::B, Two::A]), vec![Two::A, Two::B]);
        assert_eq!(selected(&[Two::B]), vec![Two::B]);
    }

    fn tiny() -> Image {
        Image::new(2, 2, natura::core::glam::Vec3::ONE).expect("a 2x2 image")
    }

    #[test]
    fn a_figure_with_too_few_pictures_writes_nothing() {
        let dir = std::env::temp_dir().join(format!("natura-figures-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary directory");
        let r = make(&dir, &[], |f: Two| {
            Ok(match f {
                Two::A => vec![tiny()],
                Two::B => vec![tiny()],
            })
        });
        assert!(r.is_err());
        assert!(!dir.join("a.png").exists() && !dir.join("b1.png").exists());
        make(&dir, &[], |f: Two| Ok(vec![tiny(); f.files().len()])).expect("every figure written");
        for n in ["a.png", "b1.png", "b2.png"] {
            assert!(dir.join(n).is_file(), "{n}");
        }
        std::fs::remove_dir_all(&dir).expect("clean-up");
    }
}
