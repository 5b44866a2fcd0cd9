//! Shader hot reload: watch `shaders/` and recompile every stage when a file changes. The caller
//! swaps pipelines only when everything compiled, so a broken edit keeps the last good ones.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use sward_gpu::shaders::ShaderSet;

pub struct ShaderWatch {
    dir: PathBuf,
    stamp: Option<SystemTime>,
    next_check: Instant,
    interval: Duration,
}

const CHECK_EVERY: Duration = Duration::from_millis(500);

impl ShaderWatch {
    /// Watch `./shaders`, or the Vulkan renderer's tessellation stages in the source tree
    /// (`crates/sward-gpu/shaders/`), whichever holds them first.
    pub fn find() -> Option<ShaderWatch> {
        let candidates = [
            PathBuf::from("shaders"),
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../sward-gpu/shaders"),
        ];
        let dir = candidates.into_iter().find(|d| d.join("blade.tese").is_file())?;
        Some(Self::watch(dir.canonicalize().unwrap_or(dir), CHECK_EVERY))
    }

    fn watch(dir: PathBuf, interval: Duration) -> ShaderWatch {
        let stamp = newest_change(&dir);
        ShaderWatch {
            dir,
            stamp,
            next_check: Instant::now() + interval,
            interval,
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// `None` if nothing changed since the last look; else the freshly compiled set or the error.
    pub fn poll(&mut self) -> Option<Result<ShaderSet, String>> {
        if Instant::now() < self.next_check {
            return None;
        }
        self.next_check = Instant::now() + self.interval;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edit_recompiles_and_a_broken_edit_reports_the_error() {
        let dir = std::env::temp_dir().join(format!("sward-watch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("../sward-gpu/shaders");
        for entry in std::fs::read_dir(shipped).unwrap().flatten() {
            std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
        }
        let mut watch = ShaderWatch::watch(dir.clone(), Duration::ZERO);
        assert!(watch.poll().is_none(), "nothing changed yet");

        // The tessellation stages stay GLSL whatever moves to WGSL.
        let stage = dir.join("blade.tese");
        let text = std::fs::read_to_string(&stage).unwrap();
        std::thread::sleep(Duration::from_millis(20));
        let broken = text.replace("gl_Position = vertex.clip;", "gl_Position = vertex.clipped;");
        assert_ne!(broken, text, "the edit must break something");
        write_later(&stage, &broken, 1);
        match watch.poll() {
            Some(Err(e)) => assert!(e.contains("blade.tese"), "{e}"),
            other => panic!(
                "expected a compile error, got {:?}",
                other.map(|r| r.map(|_| "shaders"))
            ),
        }

        write_later(&stage, &text, 2);
        assert!(matches!(watch.poll(), Some(Ok(_))), "the fixed shaders should compile");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Write `text` to `path` stamped `seconds` in the future, so the change is seen even on file
    /// systems with coarse modification times.
    fn write_later(path: &Path, text: &str, seconds: u64) {
        std::fs::write(path, text).unwrap();
        let stamp = SystemTime::now() + Duration::from_secs(seconds);
        std::fs::File::options()
            .write(true)
            .open(path)
            .unwrap()
            .set_modified(stamp)
            .unwrap();
    }
}
