//! The one door from sward-core to the file system: scene, mesh, height and paint map files are
//! read here, and only where the `files` feature is on (the app, the Vulkan renderer). Without it
//! (the Bevy plugin as a browser builds it, which reads through Bevy's asset server) a file named
//! by a scene gets one sentence saying this build reads none. What a scene names may instead be
//! given in memory ([`crate::content`]), and is then never read here.

use std::path::Path;

/// The bytes of the file at `path`, or why they could not be read (one sentence, no path: the
/// caller names the file).
pub fn read(path: &Path) -> Result<Vec<u8>, String> {
    read_from_disk(path)
}

/// The pixels of the image file at `path`, its format told by its first bytes (PNG is the one
/// sward reads), or why they could not be read.
pub fn read_image(path: &Path) -> Result<image::DynamicImage, String> {
    decode_image(&read(path)?)
}

/// The pixels of an image file's bytes, its format told by its first bytes (PNG is the one
/// sward reads), or why they could not be decoded.
pub fn decode_image(bytes: &[u8]) -> Result<image::DynamicImage, String> {
    image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?
        .decode()
        .map_err(|e| e.to_string())
}

#[cfg(feature = "files")]
#[allow(clippy::disallowed_methods)] // This is the door the lint keeps the rest of the crate to.
fn read_from_disk(path: &Path) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| e.to_string())
}

#[cfg(not(feature = "files"))]
fn read_from_disk(_: &Path) -> Result<Vec<u8>, String> {
    Err(NO_FILES.to_string())
}

/// Why a build without the `files` feature reads no file.
#[cfg(not(feature = "files"))]
const NO_FILES: &str = "this build reads no files (sward-core without its `files` feature, as in a \
     browser): a scene there grows on a plane, a sphere or terrain, with no maps or mesh files";
