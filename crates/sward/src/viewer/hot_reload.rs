//! Shader hot reload: watch `shaders/` and recompile every stage when a file changes. The caller
//! swaps pipelines only when everything compiled, so a broken edit keeps the last good ones.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use sward_gpu::shaders::ShaderSet;

pub struct ShaderWatch {
    dir: PathBuf,
    stamp: Option<SystemTime>,
    next_check: Instant,
}

const CHECK_EVERY: Duration = Duration::from_millis(500);

impl ShaderWatch {
    /// Watch `./shaders` or the source tree's `shaders/` if either exists.
    pub fn find() -> Option<ShaderWatch> {
        let candidates = [
            PathBuf::from("shaders"),
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shaders"),
        ];
        let dir = candidates.into_iter().find(|d| d.join("common.glsl").is_file())?;
        let dir = dir.canonicalize().unwrap_or(dir);
        let stamp = newest_change(&dir);
        Some(ShaderWatch {
            dir,
            stamp,
            next_check: Instant::now() + CHECK_EVERY,
        })
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// `None` if nothing changed since the last look; else the freshly compiled set or the error.
    pub fn poll(&mut self) -> Option<Result<ShaderSet, String>> {
        if Instant::now() < self.next_check {
            return None;
        }
        self.next_check = Instant::now() + CHECK_EVERY;
        let stamp = newest_change(&self.dir);
        if stamp == self.stamp {
            return None;
        }
        self.stamp = stamp;
        Some(ShaderSet::compile(&self.dir))
    }
}

fn newest_change(dir: &Path) -> Option<SystemTime> {
    std::fs::read_dir(dir)
        .ok()?
        .flatten()
        .filter_map(|e| e.metadata().ok()?.modified().ok())
        .max()
}
