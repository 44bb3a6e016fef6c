//! Mesh export: the glTF binary read back and checked against its own JSON,
//! corrupt inputs to the reader, OBJ files, and determinism across threads.

use glam::Vec3;
use natura_plant::mesh::{Glb, Instance, glb_bytes, save_glb_instanced, save_obj};
use natura_plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams};
use serde_json::Value;

const BUSH: &str = "angle: 22.5\naxiom: A\nA -> [&FL!A]/////'[&FL!A]///////'[&FL!A]\nF -> S/////F\nS -> FL\nL -> ['''^^~L(0.6,0.3)]";

fn plant(src: &str, n: u32) -> PlantMesh {
    let l = LSystem::parse(src).unwrap();
    let mut d = Derivation::new(&l, 1).unwrap();
    d.derive(n).unwrap();
    let g = Turtle::new(&l, TurtleParams::for_lsystem(&l))
        .unwrap()
        .interpret(d.string())
        .unwrap();
    PlantMesh::from_geometry(&g, &MeshParams::default()).unwrap()
}

fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("natura-plant-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn f32s(bin: &[u8], offset: usize, n: usize) -> Vec<f32> {
    bin[offset..offset + 4 * n]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Checks every accessor lies in its buffer view, the views in the BIN chunk,
/// min/max equal the data's, indices name existing vertices; returns the JSON.
fn check_glb(bytes: &[u8]) -> Value {
    let glb = Glb::parse(bytes).unwrap();
    let j: Value = serde_json::from_str(glb.json).unwrap();
    let bin = glb.bin.unwrap();
    assert_eq!(j["asset"]["version"], "2.0");
    assert!(j["buffers"][0]["byteLength"].as_u64().unwrap() as usize <= bin.len());
    let views = j["bufferViews"].as_array().unwrap();
    for v in views {
        let (o, l) = (
            v["byteOffset"].as_u64().unwrap(),
            v["byteLength"].as_u64().unwrap(),
        );
        assert!(o + l <= bin.len() as u64 && o % 4 == 0);
    }
    let comps = |t: &str| match t {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        _ => panic!("{t}"),
    };
    let accessors = j["accessors"].as_array().unwrap();
    for a in accessors {
        let v = &views[a["bufferView"].as_u64().unwrap() as usize];
        let n = a["count"].as_u64().unwrap() as usize;
        let c = comps(a["type"].as_str().unwrap());
        let off = (v["byteOffset"].as_u64().unwrap() + a["byteOffset"].as_u64().unwrap()) as usize;
        assert!(
            off + 4 * n * c
                <= (v["byteOffset"].as_u64().unwrap() + v["byteLength"].as_u64().unwrap()) as usize
        );
        if let (Some(lo), Some(hi)) = (a["min"].as_array(), a["max"].as_array()) {
            let data = f32s(bin, off, n * c);
            for k in 0..c {
                let col = data.iter().skip(k).step_by(c);
                let mn = col.clone().copied().fold(f32::INFINITY, f32::min);
                let mx = col.copied().fold(f32::NEG_INFINITY, f32::max);
                assert_eq!(lo[k].as_f64().unwrap() as f32, mn);
                assert_eq!(hi[k].as_f64().unwrap() as f32, mx);
            }
        }
    }
    for m in j["meshes"].as_array().unwrap() {
        for p in m["primitives"].as_array().unwrap() {
            let at = &p["attributes"];
            let nv = accessors[at["POSITION"].as_u64().unwrap() as usize]["count"]
                .as_u64()
                .unwrap();
            for name in ["NORMAL", "TEXCOORD_0", "_WIND"] {
                assert_eq!(
                    accessors[at[name].as_u64().unwrap() as usize]["count"]
                        .as_u64()
                        .unwrap(),
                    nv
                );
            }
            let ia = &accessors[p["indices"].as_u64().unwrap() as usize];
            assert_eq!(ia["componentType"], 5125);
            let v = &views[ia["bufferView"].as_u64().unwrap() as usize];
            let off =
                (v["byteOffset"].as_u64().unwrap() + ia["byteOffset"].as_u64().unwrap()) as usize;
            let n = ia["count"].as_u64().unwrap() as usize;
            assert_eq!(n % 3, 0);
            for c in bin[off..off + 4 * n].chunks_exact(4) {
                assert!(u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])) < nv);
            }
        }
    }
    j
}

#[test]
fn glb_reads_back_consistently() {
    let m = plant(BUSH, 4);
    let bytes = glb_bytes(&[(&m, &[])]).unwrap();
    let j = check_glb(&bytes);
    let prims = j["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(prims.len(), 2);
    assert_eq!(j["materials"][1]["doubleSided"], true);
    assert_eq!(j["materials"][0]["name"], "bark");
    let pos = &j["accessors"][prims[0]["attributes"]["POSITION"].as_u64().unwrap() as usize];
    assert_eq!(pos["count"].as_u64().unwrap() as usize, m.vertex_count());
    // z up becomes y up: the glTF y range is natura's z range.
    let (lo, hi) = m.bounds().unwrap();
    assert_eq!(pos["min"][1].as_f64().unwrap() as f32, lo.z);
    assert_eq!(pos["max"][2].as_f64().unwrap() as f32, -lo.y);
    assert_eq!(pos["max"][1].as_f64().unwrap() as f32, hi.z);
    assert!(j.get("extensionsUsed").is_none());
}

#[test]
fn instanced_glb() {
    let a = plant(BUSH, 3);
    let b = plant("axiom: F[+F]F", 0);
    let inst: Vec<Instance> = (0..5)
        .map(|k| {
            Instance::new(
                Vec3::new(k as f32, 2.0, 0.0),
                0.3 * k as f32,
                1.0 + 0.1 * k as f32,
            )
        })
        .collect();
    let path = scratch("forest.glb");
    save_glb_instanced(&[(&a, &inst), (&b, &inst[..2])], &path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let j = check_glb(&bytes);
    assert_eq!(j["extensionsUsed"][0], "EXT_mesh_gpu_instancing");
    let ext = &j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    let t = &j["accessors"][ext["TRANSLATION"].as_u64().unwrap() as usize];
    assert_eq!(t["count"], 5);
    // Translation (k, 2, 0) z-up is (k, 0, −2) y-up.
    assert_eq!(
        t["min"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect::<Vec<_>>(),
        vec![0.0, 0.0, -2.0]
    );
    assert_eq!(
        j["accessors"][ext["ROTATION"].as_u64().unwrap() as usize]["type"],
        "VEC4"
    );
    assert_eq!(j["nodes"][1]["mesh"], 1);
    // Bad instances and empty scenes are errors, and nothing is written.
    let bad = [Instance {
        scale: Vec3::new(1.0, 0.0, 1.0),
        ..Instance::default()
    }];
    let p2 = scratch("bad.glb");
    assert!(save_glb_instanced(&[(&a, &bad)], &p2).is_err() && !p2.exists());
    assert!(glb_bytes(&[]).is_err());
    assert!(glb_bytes(&[(&PlantMesh::default(), &[])]).is_err());
}

#[test]
fn corrupt_glb_is_an_error_not_a_panic() {
    let m = plant("axiom: F[+F~L]F", 0);
    let good = glb_bytes(&[(&m, &[])]).unwrap();
    assert!(Glb::parse(&good).is_ok());
    // Every truncation.
    for n in 0..good.len() {
        assert!(Glb::parse(&good[..n]).is_err(), "truncated to {n}");
    }
    // Every header and chunk-header byte changed.
    let json_len = u32::from_le_bytes([good[12], good[13], good[14], good[15]]) as usize;
    let heads: Vec<usize> = (0..20).chain(20 + json_len..28 + json_len).collect();
    for &k in &heads {
        for v in [0u8, 1, 0x7f, 0xff] {
            let mut b = good.clone();
            if b[k] == v {
                continue;
            }
            b[k] = v;
            let _ = Glb::parse(&b);
        }
    }
    // A later chunk of another type is skipped; one running past the end is an error.
    let mut b = good.clone();
    b.extend_from_slice(&4u32.to_le_bytes());
    b.extend_from_slice(b"XTRA");
    b.extend_from_slice(&[1, 2, 3, 4]);
    let n = b.len() as u32;
    b[8..12].copy_from_slice(&n.to_le_bytes());
    assert_eq!(
        Glb::parse(&b).unwrap().json,
        Glb::parse(&good).unwrap().json
    );
    let k = b.len() - 12;
    b[k] = 8;
    assert!(Glb::parse(&b).is_err());
    // A bad length field, magic, version.
    let mut b = good.clone();
    b[8] ^= 4;
    assert!(Glb::parse(&b).is_err());
    let mut b = good.clone();
    b[0] = b'x';
    assert!(Glb::parse(&b).is_err());
    let mut b = good.clone();
    b[4] = 1;
    assert!(Glb::parse(&b).is_err());
    let mut b = good.clone();
    b[12] = b[12].wrapping_add(4);
    assert!(Glb::parse(&b).is_err());
    // Invalid UTF-8 in the JSON chunk.
    let mut b = good;
    b[20] = 0xff;
    assert!(Glb::parse(&b).is_err());
}

#[test]
fn obj_and_mtl() {
    let m = plant(BUSH, 2);
    let path = scratch("bush.obj");
    save_obj(&m, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mtl = std::fs::read_to_string(path.with_extension("mtl")).unwrap();
    let count = |p: &str| text.lines().filter(|l| l.starts_with(p)).count();
    assert_eq!(count("v "), m.vertex_count());
    assert_eq!(count("vt "), m.vertex_count());
    assert_eq!(count("vn "), m.vertex_count());
    assert_eq!(count("f "), m.triangle_count());
    assert!(text.contains("mtllib bush.mtl") && text.contains("usemtl leaf"));
    assert!(mtl.contains("newmtl bark") && mtl.contains("newmtl leaf"));
    let mut bad = m.clone();
    bad.normals.pop();
    let p2 = scratch("bad.obj");
    assert!(save_obj(&bad, &p2).is_err() && !p2.exists() && !p2.with_extension("mtl").exists());
}

#[test]
fn derivation_and_meshing_identical_on_one_and_two_threads() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let m = plant("axiom: A\nA -> F[+A][-A] : 0.5\nA -> F[&A]/A : 0.5", 8);
                glb_bytes(&[(&m, &[])]).unwrap()
            })
    };
    assert_eq!(run(1), run(2));
}
