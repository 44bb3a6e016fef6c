//! Any bytes as a tile manifest line, and any set of such lines as a frame
//! to assemble: a checked line or an error naming the file, and a plan or a
//! list of problems; never a panic, and never more than the stated number
//! of problem lines however many tiles a line claims.
#![no_main]

#[allow(dead_code)]
#[path = "../../cli/check.rs"]
mod check;
#[allow(dead_code)]
#[path = "../../cli/error.rs"]
mod error;
#[allow(dead_code)]
#[path = "../../cli/limits.rs"]
mod limits;
#[allow(dead_code)]
#[path = "../../cli/manifest.rs"]
mod manifest;
#[allow(dead_code)]
#[path = "../../cli/tiles.rs"]
mod tiles;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Lines separated by a NUL byte: each a manifest file of its own.
    let mut lines = Vec::new();
    for (i, part) in data.split(|&b| b == 0).enumerate().take(64) {
        if let Ok(line) = manifest::TileLine::parse(part, &format!("tile{i}.json")) {
            line.check("again").expect("a parsed line passes its checks");
            lines.push(line);
        }
    }
    let frame = lines.first().map_or(0, |l| l.frame);
    let mut problems = check::Problems::default();
    let plan = check::check_lines(lines, frame, &mut problems);
    let problems = problems.into_lines();
    assert!(problems.len() <= limits::MAX_PROBLEMS + 1);
    if let Some(plan) = plan {
        assert!(plan.by_index.keys().all(|&i| i < plan.first.tiles));
    }
});
