//! Job descriptions for farms: a Slurm job array and an Open Job
//! Description template. Both run the same three steps: `prepare` (the
//! world cache, once), `render` over frame × tile, and `assemble` per frame
//! once every tile is done.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{CliError, Result};

/// What a job renders and where.
#[derive(Clone, Debug)]
pub struct Job {
    /// The `natura` executable the farm runs (absolute path).
    pub natura: PathBuf,
    /// The scene file (absolute path).
    pub scene: PathBuf,
    /// The output directory (absolute path).
    pub out: PathBuf,
    /// The directory the job files are written into (absolute path).
    pub job_dir: PathBuf,
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

/// `path` as text for a job file, or an error naming the flag it came from
/// (`flag`): job files are UTF-8 text, and a control character (a newline
/// above all) would end the line it is written on.
pub fn text<'a>(path: &'a Path, flag: &str) -> Result<&'a str> {
    let t = path.to_str().ok_or_else(|| {
        CliError::usage(format!(
            "{flag} {}: the path is not UTF-8; a job file cannot name it",
            path.display()
        ))
    })?;
    if let Some(c) = t.chars().find(|c| c.is_control()) {
        return Err(CliError::usage(format!(
            "{flag} {t:?}: the path holds the control character {c:?}; \
             a job file cannot name it (rename the file or folder)"
        )));
    }
    Ok(t)
}

/// Quotes `s` for a POSIX shell: single quotes, with each `'` written as
/// `'\''`. Nothing inside single quotes is special to the shell.
pub fn sh(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// `s` as a YAML double-quoted scalar: JSON's string syntax, which YAML
/// reads the same way, with every control character escaped.
pub fn yaml(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "''".into())
}

/// Checks the paths of `job` for `engine`'s job files: UTF-8 without
/// control characters; for Slurm also no backslash in the output directory
/// (a backslash turns off Slurm's `%A`/`%a` in the log file names).
pub fn check(job: &Job, engine: &str) -> Result<()> {
    text(&job.natura, "the natura executable's path")?;
    text(&job.scene, "SCENE")?;
    let out = text(&job.out, "--out")?;
    text(&job.job_dir, "--job-dir")?;
    if engine == "slurm" && out.contains('\\') {
        return Err(CliError::usage(format!(
            "--out {out:?}: Slurm's log file names cannot hold a backslash; \
             choose an output directory without one"
        )));
    }
    Ok(())
}

/// The Slurm scripts of `job`: `(file name, contents)` for `prepare.sbatch`,
/// `render.sbatch` (the array), `assemble.sbatch` (an array over frames) and
/// `submit.sh`, which submits the three with `afterok` dependencies.
///
/// The `#SBATCH` lines hold numbers and fixed names only; every path is
/// written once, shell-quoted, in a command line (`submit.sh` gives the log
/// files to `sbatch --output`, with `%` written `%%` as Slurm's file name
/// patterns want). Call [`check`] first.
pub fn slurm(job: &Job) -> Result<Vec<(&'static str, String)>> {
    let natura = sh(text(&job.natura, "the natura executable's path")?);
    let scene = sh(text(&job.scene, "SCENE")?);
    let out_text = text(&job.out, "--out")?;
    let out = sh(out_text);
    let frames = u64::from(job.last - job.first) + 1;
    let tasks = frames * u64::from(job.tiles);
    let logs = format!("{out_text}/logs");
    let head = |name: &str, extra: &str| {
        format!(
            "#!/bin/bash\n#SBATCH --job-name=natura-{name}\n#SBATCH --ntasks=1\n\
             #SBATCH --cpus-per-task={cpus}\n{extra}set -euo pipefail\n\
             export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{cpus}}}\"\n",
            cpus = job.cpus,
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
         # Extra arguments go to every sbatch.\n\
         set -euo pipefail\ncd \"$(dirname \"$0\")\"\n\
         logs={logs}\n\
         # The log files' name pattern: the folder with each % written %%.\n\
         pattern={pattern}\n\
         mkdir -p \"$logs\"\n\
         id() {{ cut -d';' -f1; }}\n\
         prepare=$(sbatch --parsable --output=\"$pattern/prepare-%A_%a.log\" \"$@\" prepare.sbatch | id)\n\
         render=$(sbatch --parsable --output=\"$pattern/render-%A_%a.log\" \"$@\" \
         --dependency=afterok:$prepare render.sbatch | id)\n\
         assemble=$(sbatch --parsable --output=\"$pattern/assemble-%A_%a.log\" \"$@\" \
         --dependency=afterok:$render assemble.sbatch | id)\n\
         echo \"$prepare $render $assemble\"\n",
        logs = sh(&logs),
        pattern = sh(&logs.replace('%', "%%")),
    );
    Ok(vec![
        ("prepare.sbatch", prepare),
        ("render.sbatch", render),
        ("assemble.sbatch", assemble),
        ("submit.sh", submit),
    ])
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
fn default(dir: &Path, path: &Path) -> Result<String> {
    let r = relative(dir, path);
    Ok(if r.starts_with("..") {
        String::new()
    } else {
        text(Path::new(&r), "a path")?;
        format!("  default: {}\n", yaml(&r))
    })
}

/// The Open Job Description template (2023-09) of `job`, to be stored in
/// its job directory: parameters for the scene, output directory (their
/// defaults relative to `dir` when inside it, as the format wants) and executable
/// (defaulting to `job`'s), a
/// `Prepare` step, a `Render` step over frame × tile that depends on it,
/// and an `Assemble` step over frames that depends on `Render`.
///
/// Every value is a YAML double-quoted scalar. The job's name (a format
/// string to Open Job Description, where `{{` starts an expression) keeps
/// only the letters, digits, `-`, `_` and `.` of the scene's file name.
/// Call [`check`] first.
pub fn openjd(job: &Job) -> Result<String> {
    let dir = &job.job_dir;
    let frames = format!("{}-{}", job.first, job.last);
    let name: String = job
        .scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
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
        scene = default(dir, &job.scene)?,
        out = default(dir, &job.out)?,
        natura = yaml(text(&job.natura, "the natura executable's path")?),
        last_tile = job.tiles - 1,
        n = job.tiles,
    );
    Ok(t)
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
        assert_eq!(default(&p("/a/b"), &p("/a/s.toml")).unwrap(), "");
        assert_eq!(
            default(&p("/a/b"), &p("/a/b")).unwrap(),
            "  default: \".\"\n"
        );
    }

    #[test]
    fn every_array_index_maps_to_one_frame_and_tile() {
        let job = Job {
            natura: "/bin/natura".into(),
            scene: "/s it's.toml".into(),
            out: "/o".into(),
            job_dir: "/o/slurm".into(),
            first: 4,
            last: 6,
            tiles: 5,
            throttle: 3,
            cpus: 2,
        };
        let files = slurm(&job).unwrap();
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

#[cfg(test)]
mod quoting {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Any text survives shell single-quoting and YAML quoting: the
        /// quoted form reads back as the text itself.
        #[test]
        fn quoted_values_read_back_unchanged(s in "[ -~\\n\\t]{0,40}") {
            let yaml_text = yaml(&s);
            let back: String = serde_json::from_str(&yaml_text).unwrap();
            prop_assert_eq!(&back, &s);
            prop_assert!(!yaml_text.contains('\n'));
            let q = sh(&s);
            // Inside single quotes only `'` ends the string; each one is
            // closed, escaped and reopened.
            let inner = &q[1..q.len() - 1];
            prop_assert_eq!(inner.replace(r"'\''", "'"), s.clone());
            prop_assert!(!inner.replace(r"'\''", "").contains('\''));
        }
    }

    #[test]
    fn control_characters_in_paths_are_refused_by_flag() {
        let e = text(Path::new("/a\nb"), "--out").unwrap_err().to_string();
        assert!(e.contains("--out") && e.contains("\\n"), "{e}");
        assert!(text(Path::new("/a b/it's $(x) `y` %z \""), "--out").is_ok());
    }
}
