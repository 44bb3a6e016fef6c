//! glTF 2.0 binary (`.glb`) export of plant meshes, with instancing by
//! `EXT_mesh_gpu_instancing` (Khronos 2021, glTF 2.0 §4.4 "GLB file format
//! specification"; Khronos EXT_mesh_gpu_instancing).
//!
//! glTF is y-up; natura is z-up. Every position, normal and translation is
//! stored as `(x, z, −y)` (a rotation: handedness and winding are kept),
//! quaternions likewise rotate their vector part, and scales swap y and z.

use super::{Instance, Material, PlantMesh, invalid};
use crate::error::Result;
use glam::{Quat, Vec3};
pub use natura_core::io::glb::Glb;
use natura_core::io::{WriteError, write_atomic};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

#[inline]
fn yup(v: Vec3) -> [f32; 3] {
    [v.x, v.z, -v.y]
}

/// The binary buffer and the JSON arrays being assembled.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Builder {
    /// Appends `data` as a buffer view (4-byte aligned) and returns its index.
    fn view(&mut self, data: impl Iterator<Item = f32>, target: Option<u32>) -> usize {
        let start = self.bin.len();
        for x in data {
            self.bin.extend_from_slice(&x.to_le_bytes());
        }
        self.push_view(start, target)
    }

    fn push_view(&mut self, start: usize, target: Option<u32>) -> usize {
        let len = self.bin.len() - start;
        let mut v = format!(r#"{{"buffer":0,"byteOffset":{start},"byteLength":{len}"#);
        if let Some(t) = target {
            let _ = write!(v, r#","target":{t}"#);
        }
        v.push('}');
        self.views.push(v);
        self.views.len() - 1
    }

    /// Appends an accessor and returns its index.
    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        view: usize,
        offset: usize,
        ctype: u32,
        count: usize,
        ty: &str,
        bounds: Option<(&[f32], &[f32])>,
    ) -> usize {
        let mut a = format!(
            r#"{{"bufferView":{view},"byteOffset":{offset},"componentType":{ctype},"count":{count},"type":"{ty}""#
        );
        if let Some((lo, hi)) = bounds {
            let list = |v: &[f32]| {
                v.iter()
                    .map(|x| format!("{x}"))
                    .collect::<Vec<_>>()
                    .join(",")
            };
            let _ = write!(a, r#","min":[{}],"max":[{}]"#, list(lo), list(hi));
        }
        a.push('}');
        self.accessors.push(a);
        self.accessors.len() - 1
    }
}

fn min_max<const N: usize>(it: impl Iterator<Item = [f32; N]>) -> ([f32; N], [f32; N]) {
    let mut lo = [f32::INFINITY; N];
    let mut hi = [f32::NEG_INFINITY; N];
    for v in it {
        for k in 0..N {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    (lo, hi)
}

fn colour_json(c: Vec3) -> String {
    format!("[{},{},{},1]", c.x, c.y, c.z)
}

/// Returns the bytes of a `.glb` holding each mesh once, placed at each of
/// its instances with `EXT_mesh_gpu_instancing` (declared in
/// `extensionsUsed`), or at the origin where its instance list is empty.
///
/// Vertex attributes: `POSITION` (with `min`/`max`), `NORMAL`, `TEXCOORD_0`
/// and the application-specific `_WIND` (the wind weight, a float scalar).
/// One primitive per material, with u32 indices. Materials (only those
/// used) are PBR metallic-roughness: `bark` (rough, single-sided) and `leaf` (double-sided,
/// `alphaMode` `OPAQUE`: the leaves are modelled as geometry, with no cut-out
/// texture that `MASK` would need).
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if there is no mesh, a mesh fails
/// [`PlantMesh::check`] or has no triangles, an instance fails
/// [`Instance::validate`]; [`PlantError::Core`](crate::PlantError::Core) if the file would exceed
/// glTF's 4 GiB limit.
pub fn glb_bytes(items: &[(&PlantMesh, &[Instance])]) -> Result<Vec<u8>> {
    if items.is_empty() {
        return Err(invalid("meshes", 0, "a glTF scene needs at least one mesh"));
    }
    // Only the materials some primitive uses are written (bark first).
    let uses = |mat: Material| {
        items.iter().any(|(m, _)| {
            m.primitives
                .iter()
                .any(|p| p.material == mat && p.count > 0)
        })
    };
    let (bark_used, leaf_used) = (uses(Material::Bark), uses(Material::Leaf));
    let mut b = Builder::default();
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    let mut instanced = false;
    for (mi, (m, inst)) in items.iter().enumerate() {
        m.check()?;
        if m.indices.is_empty() {
            return Err(invalid("mesh", mi, "has no triangles"));
        }
        for i in inst.iter() {
            i.validate()?;
        }
        meshes.push(mesh_json(&mut b, mi, m, bark_used));
        if inst.is_empty() {
            nodes.push(format!(r#"{{"name":"plant{mi}","mesh":{mi}}}"#));
        } else {
            instanced = true;
            nodes.push(instanced_node_json(&mut b, mi, inst));
        }
    }
    let materials = materials_json(bark_used, leaf_used);
    let node_list = (0..nodes.len())
        .map(|k| k.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let ext = if instanced {
        r#""extensionsUsed":["EXT_mesh_gpu_instancing"],"#
    } else {
        ""
    };
    let json = format!(
        concat!(
            r#"{{"asset":{{"version":"2.0","generator":"natura-plant"}},{ext}"scene":0,"scenes":[{{"nodes":[{nl}]}}],"#,
            r#""nodes":[{nodes}],"meshes":[{meshes}],"#,
            r#""materials":[{materials}],"#,
            r#""buffers":[{{"byteLength":{blen}}}],"bufferViews":[{views}],"accessors":[{accs}]}}"#
        ),
        ext = ext,
        nl = node_list,
        nodes = nodes.join(","),
        meshes = meshes.join(","),
        materials = materials.join(","),
        blen = b.bin.len(),
        views = b.views.join(","),
        accs = b.accessors.join(","),
    );
    let glb = Glb {
        json: &json,
        bin: Some(&b.bin),
    };
    Ok(glb.to_bytes()?)
}

/// Writes mesh `mi`'s vertex attributes and indices to the buffer and
/// returns its glTF mesh: one primitive per material it uses (bark is
/// material 0; leaf is 1 where bark is used, else 0).
fn mesh_json(b: &mut Builder, mi: usize, m: &PlantMesh, bark_used: bool) -> String {
    let n = m.vertex_count();
    let pos: Vec<[f32; 3]> = m.positions.iter().map(|&p| yup(p)).collect();
    let (lo, hi) = min_max(pos.iter().copied());
    let v = b.view(pos.iter().flatten().copied(), Some(ARRAY_BUFFER));
    let a_pos = b.accessor(v, 0, FLOAT, n, "VEC3", Some((&lo, &hi)));
    let v = b.view(m.normals.iter().flat_map(|&p| yup(p)), Some(ARRAY_BUFFER));
    let a_nrm = b.accessor(v, 0, FLOAT, n, "VEC3", None);
    let v = b.view(m.uvs.iter().flat_map(|p| p.to_array()), Some(ARRAY_BUFFER));
    let a_uv = b.accessor(v, 0, FLOAT, n, "VEC2", None);
    let (wlo, whi) = min_max(m.wind.iter().map(|&w| [w]));
    let v = b.view(m.wind.iter().copied(), Some(ARRAY_BUFFER));
    let a_wind = b.accessor(v, 0, FLOAT, n, "SCALAR", Some((&wlo, &whi)));
    let start = b.bin.len();
    for &i in &m.indices {
        b.bin.extend_from_slice(&i.to_le_bytes());
    }
    let iv = b.push_view(start, Some(ELEMENT_ARRAY_BUFFER));
    let prims: Vec<String> = m
        .primitives
        .iter()
        .filter(|p| p.count > 0)
        .map(|p| {
            let a = b.accessor(
                iv,
                p.first as usize * 4,
                UNSIGNED_INT,
                p.count as usize,
                "SCALAR",
                None,
            );
            let mat = match p.material {
                Material::Bark => 0,
                Material::Leaf => usize::from(bark_used),
            };
            format!(
                r#"{{"attributes":{{"POSITION":{a_pos},"NORMAL":{a_nrm},"TEXCOORD_0":{a_uv},"_WIND":{a_wind}}},"indices":{a},"material":{mat},"mode":4}}"#
            )
        })
        .collect();
    format!(
        r#"{{"name":"plant{mi}","primitives":[{}]}}"#,
        prims.join(",")
    )
}

/// Writes the translations, rotations and scales of mesh `mi`'s (non-empty)
/// instances to the buffer and returns the node placing the mesh at each
/// (`EXT_mesh_gpu_instancing`).
fn instanced_node_json(b: &mut Builder, mi: usize, inst: &[Instance]) -> String {
    let c = inst.len();
    let t: Vec<[f32; 3]> = inst.iter().map(|i| yup(i.translation)).collect();
    let v = b.view(t.iter().flatten().copied(), None);
    let (lo, hi) = min_max(t.iter().copied());
    let a_t = b.accessor(v, 0, FLOAT, c, "VEC3", Some((&lo, &hi)));
    let v = b.view(
        inst.iter().flat_map(|i| {
            let q: Quat = i.rotation.normalize();
            [q.x, q.z, -q.y, q.w]
        }),
        None,
    );
    let a_r = b.accessor(v, 0, FLOAT, c, "VEC4", None);
    let v = b.view(
        inst.iter().flat_map(|i| [i.scale.x, i.scale.z, i.scale.y]),
        None,
    );
    let a_s = b.accessor(v, 0, FLOAT, c, "VEC3", None);
    format!(
        r#"{{"name":"plants{mi}","mesh":{mi},"extensions":{{"EXT_mesh_gpu_instancing":{{"attributes":{{"TRANSLATION":{a_t},"ROTATION":{a_r},"SCALE":{a_s}}}}}}}}}"#
    )
}

/// The glTF materials of the used ones, bark first.
fn materials_json(bark_used: bool, leaf_used: bool) -> Vec<String> {
    let mut materials = Vec::new();
    if bark_used {
        materials.push(format!(
            r#"{{"name":"bark","pbrMetallicRoughness":{{"baseColorFactor":{},"metallicFactor":0,"roughnessFactor":0.9}}}}"#,
            colour_json(Material::Bark.base_colour())
        ));
    }
    if leaf_used {
        materials.push(format!(
            r#"{{"name":"leaf","pbrMetallicRoughness":{{"baseColorFactor":{},"metallicFactor":0,"roughnessFactor":0.6}},"doubleSided":true,"alphaMode":"OPAQUE"}}"#,
            colour_json(Material::Leaf.base_colour())
        ));
    }
    materials
}

/// Writes one mesh as a `.glb` at the origin (see [`glb_bytes`]), atomically.
///
/// # Errors
///
/// As [`glb_bytes`]; [`PlantError::Core`](crate::PlantError::Core) naming the file if it cannot be written.
pub fn save_glb(mesh: &PlantMesh, path: impl AsRef<Path>) -> Result<()> {
    save_glb_instanced(&[(mesh, &[])], path)
}

/// Writes several meshes, each at its instances, as one `.glb` (see [`glb_bytes`]), atomically.
///
/// # Errors
///
/// As [`glb_bytes`]; [`PlantError::Core`](crate::PlantError::Core) naming the file if it cannot be written.
pub fn save_glb_instanced(
    items: &[(&PlantMesh, &[Instance])],
    path: impl AsRef<Path>,
) -> Result<()> {
    let bytes = glb_bytes(items)?;
    Ok(write_atomic(path, |w| {
        w.write_all(&bytes).map_err(WriteError::Io)
    })?)
}
