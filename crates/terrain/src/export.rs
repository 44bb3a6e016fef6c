//! Export: 16-bit PNG and EXR height maps (through natura-core), flow, wetness
//! and hill-shade images, and triangle meshes as binary glTF 2.0 (`.glb`) or
//! Wavefront OBJ. All files are written atomically (temporary name, then rename).
//!
//! Images are in map orientation: north (+y) up, so image row 0 is the grid
//! row of largest y, as in natura-core's height-map files.

use std::io::Write;
use std::path::Path;

use glam::Vec3;
use natura_core::io::{WriteError, write_atomic};
use natura_core::{Grid2, HeightField, Image, Ramp};

use crate::error::{Result, invalid};

/// Writes a 16-bit greyscale PNG spanning the field's own height range (a flat
/// field gets a 1 m range), with the range and cell size stored in the file.
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) naming the file if it cannot be written (the
/// file is written atomically: nothing is left half-written).
pub fn save_height_png16(hf: &HeightField, path: impl AsRef<Path>) -> Result<()> {
    let (lo, hi) = hf.min_max();
    let hi = if hi > lo { hi } else { lo + 1.0 };
    Ok(hf.save_png16(path, (lo, hi))?)
}

/// Writes a 32-bit float EXR height map (bit-exact).
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) naming the file if it cannot be written (the
/// file is written atomically: nothing is left half-written).
pub fn save_height_exr(hf: &HeightField, path: impl AsRef<Path>) -> Result<()> {
    Ok(hf.save_exr(path)?)
}

/// Flips a grid-indexed colour function into a north-up image.
fn map_image(nx: usize, ny: usize, f: impl Fn(usize, usize) -> Vec3) -> Result<Image> {
    Ok(Image::from_fn(nx, ny, |x, r| f(x, ny - 1 - r))?)
}

/// A hill-shaded grey image lit from `sun` (unit vector toward the sun, z up),
/// with a little ambient light so shadowed slopes keep detail.
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) for a zero or non-finite `sun`.
pub fn hillshade_image(hf: &HeightField, sun: Vec3) -> Result<Image> {
    let shade = hf.hillshade(sun)?;
    map_image(hf.nx(), hf.ny(), |x, y| {
        Vec3::splat(0.08 + 0.92 * shade[(x, y)])
    })
}

/// A hill-shaded image tinted by altitude through natura-core's terrain ramp
/// (the ramp's sea colours are skipped: the lowest cell is lowland green).
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) for a zero or non-finite `sun`.
pub fn relief_image(hf: &HeightField, sun: Vec3) -> Result<Image> {
    let shade = hf.hillshade(sun)?;
    let (lo, hi) = hf.min_max();
    let hi = if hi > lo { hi } else { lo + 1.0 };
    let lo = lo - 0.3 * (hi - lo);
    let h = hf.heights();
    map_image(hf.nx(), hf.ny(), |x, y| {
        Ramp::Terrain.map(h[(x, y)], lo, hi) * (0.2 + 0.8 * shade[(x, y)])
    })
}

/// A flow-accumulation image: `log(area)` mapped from the smallest to the
/// largest area, white land fading to deep blue rivers.
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the image cannot be allocated.
pub fn flow_image(area: &Grid2<f32>) -> Result<Image> {
    crate::error::check_grid("area", area)?;
    let (lo, hi) = area.min_max();
    let (l0, l1) = (lo.max(1e-12).ln(), hi.max(1e-12).ln());
    let span = (l1 - l0).max(1e-6);
    let (nx, ny) = area.dims();
    map_image(nx, ny, |x, y| {
        let t = ((area[(x, y)].max(1e-12).ln() - l0) / span).clamp(0.0, 1.0);
        let t = t * t;
        Vec3::new(0.97, 0.97, 0.95).lerp(Vec3::new(0.02, 0.12, 0.45), t)
    })
}

/// A wetness image: the index mapped through natura-core's viridis ramp, dry (low) to wet (high).
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the image cannot be allocated.
pub fn wetness_image(index: &Grid2<f32>) -> Result<Image> {
    crate::error::check_grid("wetness index", index)?;
    let (lo, hi) = index.min_max();
    let hi = if hi > lo { hi } else { lo + 1.0 };
    let (nx, ny) = index.dims();
    map_image(nx, ny, |x, y| Ramp::Viridis.map(index[(x, y)], lo, hi))
}

/// A triangle mesh of the height field sampled every `step` cells: positions
/// (metres, z up), smooth vertex normals and counter-clockwise triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals.
    pub normals: Vec<Vec3>,
    /// Triangle vertex indices, three per triangle, counter-clockwise seen from above.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Checks that the mesh has triangles, one normal per position and only
    /// indices of existing vertices (its fields are public, so a caller may
    /// have edited it).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
    /// naming `mesh` otherwise.
    pub fn check(&self) -> Result<()> {
        let n = self.positions.len();
        if self.indices.is_empty() || !self.indices.len().is_multiple_of(3) {
            return Err(invalid(
                "mesh",
                format!("{} indices", self.indices.len()),
                "must hold at least one triangle, three indices each",
            ));
        }
        if self.normals.len() != n {
            return Err(invalid(
                "mesh",
                format!("{n} positions, {} normals", self.normals.len()),
                "needs one normal per position",
            ));
        }
        if let Some(&i) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Err(invalid(
                "mesh",
                format!("index {i} of {n} vertices"),
                "indices must name existing vertices",
            ));
        }
        Ok(())
    }
}

/// Builds a [`Mesh`] sampling every `step` cells (the last row and column are
/// always included). Refuses `step = 0` and meshes over 2³² vertices.
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) for `step = 0`, a field of fewer
/// than 2 × 2 samples or a mesh of more than 2³² vertices.
pub fn mesh(hf: &HeightField, step: usize) -> Result<Mesh> {
    if step == 0 {
        return Err(invalid("step", step, "must be ≥ 1"));
    }
    if hf.nx() < 2 || hf.ny() < 2 {
        return Err(invalid(
            "height field",
            format!("{} × {}", hf.nx(), hf.ny()),
            "a mesh needs at least 2 × 2 samples",
        ));
    }
    let pick = |n: usize| {
        let mut v: Vec<usize> = (0..n).step_by(step).collect();
        if *v.last().unwrap_or(&0) != n - 1 {
            v.push(n - 1);
        }
        v
    };
    let (xs, ys) = (pick(hf.nx()), pick(hf.ny()));
    if (xs.len() as u64) * (ys.len() as u64) > u64::from(u32::MAX) {
        return Err(invalid("step", step, "mesh would exceed 2^32 vertices"));
    }
    let mut positions = Vec::with_capacity(xs.len() * ys.len());
    let mut normals = Vec::with_capacity(xs.len() * ys.len());
    for &j in &ys {
        for &i in &xs {
            positions.push(hf.point(i, j));
            normals.push(hf.normal_at_sample(i, j));
        }
    }
    let w = xs.len() as u32;
    let mut indices = Vec::with_capacity((xs.len() - 1) * (ys.len() - 1) * 6);
    for r in 0..ys.len() as u32 - 1 {
        for c in 0..w - 1 {
            let a = r * w + c;
            let (b, d, e) = (a + 1, a + w, a + w + 1);
            indices.extend_from_slice(&[a, b, e, a, e, d]);
        }
    }
    Ok(Mesh {
        positions,
        normals,
        indices,
    })
}

/// Writes `mesh` as Wavefront OBJ (positions, normals, faces).
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `mesh` if it has no
/// triangles, a normal count other than its position count or an index past its
/// vertices; [`TerrainError::Core`](crate::TerrainError::Core) naming the file if it cannot be written (the
/// file is written atomically: nothing is left half-written).
pub fn save_obj(m: &Mesh, path: impl AsRef<Path>) -> Result<()> {
    save_obj_impl(m, path.as_ref())
}

/// The body of [`save_obj`]: not generic, so it is compiled once, here, and not again in every
/// crate that calls it.
fn save_obj_impl(m: &Mesh, path: &Path) -> Result<()> {
    m.check()?;
    Ok(write_atomic(path, |w| {
        writeln!(w, "# natura-terrain height-field mesh (z up, metres)")?;
        for p in &m.positions {
            writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
        }
        for n in &m.normals {
            writeln!(w, "vn {} {} {}", n.x, n.y, n.z)?;
        }
        for t in m.indices.chunks_exact(3) {
            let (a, b, c) = (t[0] + 1, t[1] + 1, t[2] + 1);
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        }
        Ok::<(), WriteError>(())
    })?)
}

/// Writes `mesh` as binary glTF 2.0 (`.glb`): one mesh, POSITION and NORMAL
/// (f32) and u32 indices. glTF is y-up, so the mesh is stored as
/// `(x, z, −y)` (a rotation; winding and handedness are preserved).
///
/// # Errors
///
/// As [`save_obj`]; also [`TerrainError::Core`](crate::TerrainError::Core) if the file would
/// exceed glTF's 4 GiB limit.
pub fn save_glb(m: &Mesh, path: impl AsRef<Path>) -> Result<()> {
    save_glb_impl(m, path.as_ref())
}

/// The body of [`save_glb`]: not generic, so it is compiled once, here, and not again in every
/// crate that calls it.
fn save_glb_impl(m: &Mesh, path: &Path) -> Result<()> {
    m.check()?;
    let conv = |v: Vec3| [v.x, v.z, -v.y];
    let mut bin: Vec<u8> = Vec::with_capacity(m.positions.len() * 24 + m.indices.len() * 4);
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &p in &m.positions {
        let q = conv(p);
        lo = lo.min(Vec3::from(q));
        hi = hi.max(Vec3::from(q));
        q.iter()
            .for_each(|v| bin.extend_from_slice(&v.to_le_bytes()));
    }
    let pos_len = bin.len();
    for &n in &m.normals {
        conv(n)
            .iter()
            .for_each(|v| bin.extend_from_slice(&v.to_le_bytes()));
    }
    let nrm_len = bin.len() - pos_len;
    for &i in &m.indices {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let idx_len = bin.len() - pos_len - nrm_len;
    let vcount = m.positions.len();
    let json = format!(
        concat!(
            r#"{{"asset":{{"version":"2.0","generator":"natura-terrain"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"#,
            r#""meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2,"mode":4}}]}}],"#,
            r#""buffers":[{{"byteLength":{total}}}],"#,
            r#""bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{pl},"target":34962}},{{"buffer":0,"byteOffset":{pl},"byteLength":{nl},"target":34962}},{{"buffer":0,"byteOffset":{io},"byteLength":{il},"target":34963}}],"#,
            r#""accessors":[{{"bufferView":0,"componentType":5126,"count":{vc},"type":"VEC3","min":[{lx},{ly},{lz}],"max":[{hx},{hy},{hz}]}},"#,
            r#"{{"bufferView":1,"componentType":5126,"count":{vc},"type":"VEC3"}},{{"bufferView":2,"componentType":5125,"count":{ic},"type":"SCALAR"}}]}}"#
        ),
        total = bin.len(),
        pl = pos_len,
        nl = nrm_len,
        io = pos_len + nrm_len,
        il = idx_len,
        vc = vcount,
        ic = m.indices.len(),
        lx = lo.x,
        ly = lo.y,
        lz = lo.z,
        hx = hi.x,
        hy = hi.y,
        hz = hi.z,
    );
    let glb = natura_core::io::glb::Glb {
        json: &json,
        bin: Some(&bin),
    };
    Ok(glb.write(path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("natura-terrain-export-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    #[test]
    fn mesh_counts_and_files() {
        let hf = HeightField::from_fn(9, 6, 2.0, |i, j| (i * j) as f32).unwrap();
        let m = mesh(&hf, 2).unwrap();
        assert_eq!(m.positions.len(), 5 * 4);
        assert_eq!(m.indices.len(), 4 * 3 * 6);
        // Counter-clockwise from above: the first triangle's normal points up.
        let [a, b, c] = [0, 1, 2].map(|k| m.positions[m.indices[k] as usize]);
        assert!((b - a).cross(c - a).z > 0.0);
        let glb = scratch("t.glb");
        save_glb(&m, &glb).unwrap();
        let bytes = std::fs::read(&glb).unwrap();
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
            bytes.len()
        );
        let obj = scratch("t.obj");
        save_obj(&m, &obj).unwrap();
        let text = std::fs::read_to_string(&obj).unwrap();
        assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 24);
        assert!(mesh(&hf, 0).is_err());
        let png = scratch("h.png");
        save_height_png16(&hf, &png).unwrap();
        let back = HeightField::load_png16(&png, None, None).unwrap();
        assert!((back.heights()[(8, 5)] - 40.0).abs() < 1e-2);
    }

    #[test]
    fn degenerate_fields_and_meshes_are_refused_not_written_empty() {
        for (nx, ny) in [(1, 1), (1, 5), (5, 1)] {
            let hf = HeightField::from_fn(nx, ny, 1.0, |_, _| 0.0).unwrap();
            let e = mesh(&hf, 1).unwrap_err().to_string();
            assert!(e.contains("2 × 2"), "{e}");
        }
        let good = mesh(&HeightField::from_fn(3, 3, 1.0, |_, _| 0.0).unwrap(), 1).unwrap();
        let empty = Mesh {
            indices: Vec::new(),
            ..good.clone()
        };
        let wild = Mesh {
            indices: vec![0, 1, 99],
            ..good.clone()
        };
        let short = Mesh {
            normals: Vec::new(),
            ..good
        };
        for m in [empty, wild, short] {
            let (obj, glb) = (scratch("bad.obj"), scratch("bad.glb"));
            assert!(save_obj(&m, &obj).is_err() && !obj.exists());
            assert!(save_glb(&m, &glb).is_err() && !glb.exists());
        }
    }
}
