//! An EXR file is a function of its contents: the same channels and
//! attributes give the same bytes, whatever order the encoder's hash map
//! would put the header's attributes in, and the file still reads back.

use natura_core::io::exr::{read_exr, write_exr};

#[test]
fn the_same_image_gives_the_same_bytes() {
    let dir = std::env::temp_dir().join(format!("natura-exr-bytes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (w, h) = (7, 5);
    let y: Vec<f32> = (0..w * h).map(|i| i as f32 * 0.25).collect();
    let a: Vec<f32> = (0..w * h).map(|i| 1.0 - i as f32 / 64.0).collect();
    let attributes = [
        ("nx", "7"),
        ("ny", "5"),
        ("nz", "1"),
        ("cell_size_m", "0.5"),
        ("seed", "42"),
        ("frame", "3"),
        ("scene", "test"),
    ];
    let mut files = Vec::new();
    for k in 0..6 {
        let p = dir.join(format!("v{k}.exr"));
        write_exr(&p, w, h, &[("Y", &y), ("A", &a)], &attributes).unwrap();
        files.push(std::fs::read(&p).unwrap());
    }
    for f in &files[1..] {
        assert!(f == &files[0], "two writes of one image differ");
    }
    let back = read_exr(dir.join("v0.exr")).unwrap();
    assert_eq!((back.width, back.height), (w, h));
    let y_back = &back.channels.iter().find(|(n, _)| n == "Y").unwrap().1;
    assert_eq!(y_back, &y);
    for (k, v) in attributes {
        assert!(
            back.attributes.iter().any(|(bk, bv)| bk == k && bv == v),
            "attribute {k} lost: {:?}",
            back.attributes
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
