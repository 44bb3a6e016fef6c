//! Wavefront OBJ export with a material library (`.mtl`) beside it.

use super::{Material, PlantMesh};
use crate::error::Result;
use natura_core::io::{OutputSet, WriteError, write_atomic};
use std::io::Write as _;
use std::path::Path;

/// Writes `mesh` as `path` (OBJ: positions, texture coordinates, normals and
/// faces grouped by material, z up as in natura's other OBJ files) and its
/// material library beside it (`path` with extension `.mtl`: `bark` and
/// `leaf` with their diffuse colours). The two files appear together or not
/// at all. The wind weight has no place in OBJ and is not written.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if
/// the mesh fails [`PlantMesh::check`]; [`PlantError::Core`](crate::PlantError::Core)
/// naming a file that cannot be written (nothing is left half-written).
pub fn save_obj(mesh: &PlantMesh, path: impl AsRef<Path>) -> Result<()> {
    save_obj_impl(mesh, path.as_ref())
}

/// The body of [`save_obj`]: not generic, so it is compiled once, here, and not again in every
/// crate that calls it.
fn save_obj_impl(mesh: &PlantMesh, path: &Path) -> Result<()> {
    mesh.check()?;
    let mtl = path.with_extension("mtl");
    let mtl_name = mtl
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let set = OutputSet::new([path, mtl.as_path()])?;
    write_atomic(set.stage(&mtl)?, |w| {
        writeln!(w, "# natura-plant materials")?;
        for m in [Material::Bark, Material::Leaf] {
            let c = m.base_colour();
            writeln!(w, "newmtl {}", m.name())?;
            writeln!(w, "Kd {} {} {}", c.x, c.y, c.z)?;
            writeln!(w, "Ka 0 0 0\nKs 0 0 0\nillum 1")?;
        }
        Ok::<(), WriteError>(())
    })?;
    write_atomic(set.stage(path)?, |w| {
        writeln!(w, "# natura-plant mesh (z up, metres)")?;
        writeln!(w, "mtllib {mtl_name}")?;
        for p in &mesh.positions {
            writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
        }
        for t in &mesh.uvs {
            writeln!(w, "vt {} {}", t.x, t.y)?;
        }
        for n in &mesh.normals {
            writeln!(w, "vn {} {} {}", n.x, n.y, n.z)?;
        }
        for p in &mesh.primitives {
            writeln!(w, "usemtl {}", p.material.name())?;
            let r = p.first as usize..(p.first + p.count) as usize;
            for t in mesh.indices[r].chunks_exact(3) {
                let (a, b, c) = (t[0] + 1, t[1] + 1, t[2] + 1);
                writeln!(w, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
            }
        }
        Ok::<(), WriteError>(())
    })?;
    set.commit()?;
    Ok(())
}
