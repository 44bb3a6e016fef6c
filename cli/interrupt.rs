//! Clean exits: on Ctrl-C (SIGINT), SIGTERM or SIGHUP the temporary files
//! being written are removed before the process exits with status 130, and
//! a closed standard output (`natura print-scene | head -1`) ends the
//! command quietly.

use std::io::Write as _;

use crate::error::{CliError, Result};

/// Exit status after an interrupt (128 + SIGINT). The handler cannot tell
/// SIGINT from SIGTERM or SIGHUP, so all three exit with it.
pub const INTERRUPTED: u8 = 130;

/// Installs the handler: every `.natura-tmp-…` file this process is
/// writing (natura-core keeps the registry) is removed, then the process
/// exits with [`INTERRUPTED`]. Files already renamed into place are kept.
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        let n = natura::core::io::remove_temp_files();
        let _ = writeln!(
            std::io::stderr(),
            "natura: interrupted: removed {n} temporary file(s); finished files are kept"
        );
        std::process::exit(i32::from(INTERRUPTED));
    });
}

/// Writes `text` to standard output. A reader that has gone away (a broken
/// pipe) is [`CliError::Closed`], which ends the command quietly.
pub fn say(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::BrokenPipe => CliError::Closed,
            _ => CliError::Other(format!("standard output: {e}")),
        })
}
