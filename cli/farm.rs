//! Job descriptions for farms: a Slurm job array and an Open Job
//! Description template. Both run the same three steps: `prepare` (the
//! world cache, once), `render` over frame × tile, and `assemble` per frame
//! once every tile is done.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What a job renders and where.
#[derive(Clone, Debug)]
pub struct Job {
    /// The `natura` executable the farm runs (absolute path).
    pub natura: PathBuf,
    /// The scene file (absolute path).
    pub scene: PathBuf,
    /// The output directory (absolute path).
    pub out: PathBuf,
    /// First frame.
    pub first: u32,
    /// Last frame (inclusive).
    pub last: u32,
    /// Tiles per frame.
    pub tiles: u32,
    /// Most render tasks running at once (Slurm's array throttle).
    pub throttle: u32,
    /// Threads per render task.
    pub cpus: u32,
}

/// Quotes `s` for a POSIX shell.
fn sh(s: &Path) -> String {
    format!("'{}'", s.display().to_string().replace('\'', r"'\''"))
}

/// Quotes `s` as a YAML single-quoted scalar.
fn yaml(s: &str) -> String {
    format!("'{}'", s.replace('\'', "''"))
}

/// The Slurm scripts of `job`: `(file name, contents)` for `prepare.sbatch`,
/// `render.sbatch` (the array), `assemble.sbatch` (an array over frames) and
/// `submit.sh`, which submits the three with `afterok` dependencies.
pub fn slurm(job: &Job) -> Vec<(&'static str, String)> {
    let (natura, scene, out) = (sh(&job.natura), sh(&job.scene), sh(&job.out));
    let frames = job.last - job.first + 1;
    let tasks = frames * job.tiles;
    let logs = sh(&job.out.join("logs"));
    let head = |name: &str, extra: &str| {
        format!(
            "#!/bin/bash\n#SBATCH --job-name=natura-{name}\n#SBATCH --ntasks=1\n\
             #SBATCH --cpus-per-task={cpus}\n{extra}\
             #SBATCH --output={log}/{name}-%A_%a.log\nset -euo pipefail\n\
             export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{cpus}}}\"\n",
            cpus = job.cpus,
            log = job.out.join("logs").display(),
        )
    };
    let prepare = format!(
        "{}# The world cache, computed once for every frame and tile, and each\n\
         # frame's cache (clouds, forest), computed once for the frame's tiles.\n\
         exec {natura} prepare {scene} --frames {first}-{last} --out {out}\n",
        head("prepare", ""),
        first = job.first,
        last = job.last,
    );
    let render = format!(
        "{}# Array index -> frame and tile: index = (frame - {first}) * {n} + tile.\n\
         i=\"$SLURM_ARRAY_TASK_ID\"\nframe=$(( {first} + i / {n} ))\ntile=$(( i % {n} ))\n\
         exec {natura} render {scene} --frame \"$frame\" --tile \"$tile/{n}\" --out {out}\n",
        head(
            "render",
            &format!("#SBATCH --array=0-{}%{}\n", tasks - 1, job.throttle)
        ),
        first = job.first,
        n = job.tiles,
    );
    let assemble = format!(
        "{}exec {natura} assemble {out} --frame \"$SLURM_ARRAY_TASK_ID\"\n",
        head(
            "assemble",
            &format!("#SBATCH --array={}-{}\n", job.first, job.last)
        ),
    );
    let submit = format!(
        "#!/bin/bash\n# Submits prepare, then the render array after it, then the\n\
         # assembly after every render task has succeeded. Prints the job ids.\n\
         set -euo pipefail\ncd \"$(dirname \"$0\")\"\nmkdir -p {logs}\n\
         id() {{ cut -d';' -f1; }}\n\
         prepare=$(sbatch --parsable \"$@\" prepare.sbatch | id)\n\
         render=$(sbatch --parsable \"$@\" --dependency=afterok:$prepare render.sbatch | id)\n\
         assemble=$(sbatch --parsable \"$@\" --dependency=afterok:$render assemble.sbatch | id)\n\
         echo \"$prepare $render $assemble\"\n"
    );
    vec![
        ("prepare.sbatch", prepare),
        ("render.sbatch", render),
        ("assemble.sbatch", assemble),
        ("submit.sh", submit),
    ]
}

/// `to` relative to the directory `from` (both absolute), with `..` where
/// needed: Open Job Description joins default paths to the template's
/// directory.
fn relative(from: &Path, to: &Path) -> String {
    let (a, b): (Vec<_>, Vec<_>) = (from.components().collect(), to.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut parts: Vec<String> = vec!["..".into(); a.len() - common];
    parts.extend(
        b[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    if parts.is_empty() {
        ".".into()
    } else {
        parts.join("/")
    }
}

/// The `default:` line of a path parameter: the path relative to the
/// template's directory `dir`, or none (the parameter must then be given)
/// where the path lies outside it, which the format does not allow.
fn default(dir: &Path, path: &Path) -> String {
    let r = relative(dir, path);
    if r.starts_with("..") {
        String::new()
    } else {
        format!("  default: {}\n", yaml(&r))
    }
}

/// The Open Job Description template (2023-09) of `job`, to be stored in
/// the directory `dir`: parameters for the scene, output directory (their
/// defaults relative to `dir` when inside it, as the format wants) and executable
/// (defaulting to `job`'s), a
/// `Prepare` step, a `Render` step over frame × tile that depends on it,
/// and an `Assemble` step over frames that depends on `Render`.
pub fn openjd(job: &Job, dir: &Path) -> String {
    let frames = format!("{}-{}", job.first, job.last);
    let name = job
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let mut t = String::new();
    let _ = write!(
        t,
        "specificationVersion: 'jobtemplate-2023-09'\n\
         name: {name}\n\
         parameterDefinitions:\n\
         - name: Scene\n  type: PATH\n  objectType: FILE\n  dataFlow: IN\n{scene}\
         - name: OutDir\n  type: PATH\n  objectType: DIRECTORY\n  dataFlow: OUT\n{out}\
         - name: Natura\n  type: STRING\n  default: {natura}\n\
         steps:\n\
         - name: Prepare\n  script:\n    actions:\n      onRun:\n        command: '{{{{Param.Natura}}}}'\n\
         \x20       args: ['prepare', '{{{{Param.Scene}}}}', '--frames', '{frames}', '--out', '{{{{Param.OutDir}}}}']\n\
         - name: Render\n  dependencies:\n  - dependsOn: Prepare\n  parameterSpace:\n\
         \x20   taskParameterDefinitions:\n\
         \x20   - name: Frame\n      type: INT\n      range: '{frames}'\n\
         \x20   - name: Tile\n      type: INT\n      range: '0-{last_tile}'\n\
         \x20 script:\n    actions:\n      onRun:\n        command: '{{{{Param.Natura}}}}'\n\
         \x20       args: ['render', '{{{{Param.Scene}}}}', '--frame', '{{{{Task.Param.Frame}}}}',\n\
         \x20              '--tile', '{{{{Task.Param.Tile}}}}/{n}', '--out', '{{{{Param.OutDir}}}}']\n\
         - name: Assemble\n  dependencies:\n  - dependsOn: Render\n  parameterSpace:\n\
         \x20   taskParameterDefinitions:\n\
         \x20   - name: Frame\n      type: INT\n      range: '{frames}'\n\
         \x20 script:\n    actions:\n      onRun:\n        command: '{{{{Param.Natura}}}}'\n\
         \x20       args: ['assemble', '{{{{Param.OutDir}}}}', '--frame', '{{{{Task.Param.Frame}}}}']\n",
        name = yaml(&format!("natura {name}")),
        scene = default(dir, &job.scene),
        out = default(dir, &job.out),
        natura = yaml(&job.natura.display().to_string()),
        last_tile = job.tiles - 1,
        n = job.tiles,
    );
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_walk_up_only_where_needed() {
        let p = |s: &str| PathBuf::from(s);
        assert_eq!(relative(&p("/a/b"), &p("/a/b")), ".");
        assert_eq!(relative(&p("/a/b"), &p("/a/b/c/s.toml")), "c/s.toml");
        assert_eq!(relative(&p("/a/b"), &p("/a/s.toml")), "../s.toml");
        assert_eq!(default(&p("/a/b"), &p("/a/s.toml")), "");
        assert_eq!(default(&p("/a/b"), &p("/a/b")), "  default: '.'\n");
    }

    #[test]
    fn every_array_index_maps_to_one_frame_and_tile() {
        let job = Job {
            natura: "/bin/natura".into(),
            scene: "/s it's.toml".into(),
            out: "/o".into(),
            first: 4,
            last: 6,
            tiles: 5,
            throttle: 3,
            cpus: 2,
        };
        let files = slurm(&job);
        let render = &files[1].1;
        assert!(render.contains("#SBATCH --array=0-14%3"), "{render}");
        assert!(render.contains("'/s it'\\''s.toml'"), "{render}");
        // The script's arithmetic, index by index.
        let mut seen = std::collections::BTreeSet::new();
        for i in 0..15u32 {
            seen.insert((4 + i / 5, i % 5));
        }
        assert_eq!(seen.len(), 15);
        assert!(seen.iter().all(|&(f, t)| (4..=6).contains(&f) && t < 5));
        assert!(files[2].1.contains("#SBATCH --array=4-6"));
    }
}
