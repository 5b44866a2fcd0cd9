//! What a scene names, given in memory: the bytes of a file it names (read by a game's asset
//! server), an image or a mesh made in code, each under the name the scene uses for it. A name
//! found here is never read from disk; one not found is read through [`crate::files`] (where
//! the `files` feature is on). A [`Scene`](crate::Scene) carries its contents beside its
//! values, so a field grows, and the CPU sampler answers, from the same bytes wherever it goes.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crate::mesh::Mesh;

/// One thing a scene names, given in memory.
#[derive(Clone, Debug)]
pub enum Content {
    /// A file's bytes, read as the file would be (a PNG, an OBJ or glTF mesh, a glTF buffer).
    File(Arc<[u8]>),
    /// An image, decoded: a height map, a paint or weight map.
    Image(Arc<image::DynamicImage>),
    /// A ground or body mesh, its triangles as sward grows on them (scaled by the scene's
    /// `scale` like a mesh file).
    Mesh(Arc<Mesh>),
}

/// A content with the serial number it was given when added: contents compare by it, so
/// comparing two scenes never compares their images, and a changed image is a changed scene.
#[derive(Clone, Debug)]
struct Given {
    serial: u64,
    content: Content,
}

/// The contents a scene names, by name (cheap to clone: shared).
#[derive(Clone, Default)]
pub struct Contents(Arc<BTreeMap<String, Given>>);

impl Contents {
    /// These contents with `content` under `name` (replacing what was there).
    pub fn with(mut self, name: impl Into<String>, content: Content) -> Contents {
        self.insert(name, content);
        self
    }

    /// Put `content` under `name`, replacing what was there (the very same content, shared,
    /// is left as it was: the contents stay equal).
    pub fn insert(&mut self, name: impl Into<String>, content: Content) {
        static SERIALS: AtomicU64 = AtomicU64::new(1);
        let name = name.into();
        if self.0.get(&name).is_some_and(|g| g.content.is(&content)) {
            return;
        }
        let serial = SERIALS.fetch_add(1, Ordering::Relaxed);
        Arc::make_mut(&mut self.0).insert(name, Given { serial, content });
    }

    /// What is under `name`, if anything.
    pub fn get(&self, name: &str) -> Option<&Content> {
        self.0.get(name).map(|g| &g.content)
    }

    /// The serial number of what is under `name`: a different one is different content.
    pub fn serial(&self, name: &str) -> Option<u64> {
        self.0.get(name).map(|g| g.serial)
    }

    /// The names given, in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.0.keys().map(String::as_str)
    }

    /// Whether nothing is given.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The bytes of the file at `path`: those given under its name, else the file's on disk.
    pub fn read(&self, path: &Path) -> Result<Vec<u8>, String> {
        match self.get(&path.display().to_string()) {
            Some(Content::File(bytes)) => Ok(bytes.to_vec()),
            Some(other) => Err(format!("it was given as {}, not as a file's bytes", other.kind())),
            None => crate::files::read(path),
        }
    }

    /// The image at `path`: the one given under its name (decoded from bytes where given as a
    /// file's), else the file's on disk.
    pub fn read_image(&self, path: &Path) -> Result<image::DynamicImage, String> {
        match self.get(&path.display().to_string()) {
            Some(Content::Image(image)) => Ok(image.as_ref().clone()),
            Some(Content::File(bytes)) => crate::files::decode_image(bytes),
            Some(other) => Err(format!("it was given as {}, not as an image", other.kind())),
            None => crate::files::read_image(path),
        }
    }

    /// The mesh given under `path`'s name, where one was given as a mesh.
    pub fn mesh(&self, path: &Path) -> Option<Arc<Mesh>> {
        match self.get(&path.display().to_string()) {
            Some(Content::Mesh(mesh)) => Some(mesh.clone()),
            _ => None,
        }
    }
}

impl Content {
    /// Whether `other` is this very content (shared, not a copy).
    fn is(&self, other: &Content) -> bool {
        match (self, other) {
            (Content::File(a), Content::File(b)) => Arc::ptr_eq(a, b),
            (Content::Image(a), Content::Image(b)) => Arc::ptr_eq(a, b),
            (Content::Mesh(a), Content::Mesh(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }

    /// What it is, in words.
    fn kind(&self) -> &'static str {
        match self {
            Content::File(_) => "a file's bytes",
            Content::Image(_) => "an image",
            Content::Mesh(_) => "a mesh",
        }
    }
}

impl PartialEq for Contents {
    fn eq(&self, other: &Contents) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
            || (self.0.len() == other.0.len()
                && self
                    .0
                    .iter()
                    .zip(other.0.iter())
                    .all(|((a, x), (b, y))| a == b && x.serial == y.serial))
    }
}

impl std::fmt::Debug for Contents {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(side: u32, value: u8) -> Content {
        Content::Image(Arc::new(image::DynamicImage::ImageLuma8(image::GrayImage::from_pixel(
            side,
            side,
            image::Luma([value]),
        ))))
    }

    #[test]
    fn a_given_name_is_read_from_memory_and_compares_by_what_was_given() {
        let one = Contents::default().with("maps/density.png", grey(4, 200));
        let image = one.read_image(Path::new("maps/density.png")).unwrap();
        assert_eq!(image.into_luma8().get_pixel(1, 1).0, [200]);
        assert_eq!(one, one.clone(), "a clone is the same contents");
        let again = Contents::default().with("maps/density.png", grey(4, 200));
        assert_ne!(
            one, again,
            "content given again is new content, even with the same pixels"
        );
        let shared = one.get("maps/density.png").unwrap().clone();
        assert_eq!(
            one.clone().with("maps/density.png", shared),
            one,
            "the very same content again"
        );
        let e = one.read(Path::new("maps/density.png")).unwrap_err();
        assert!(e.contains("given as an image"), "{e}");
        assert!(one.mesh(Path::new("maps/density.png")).is_none());
    }

    #[test]
    fn bytes_given_as_a_file_decode_as_the_file_would() {
        let mut png = Vec::new();
        image::DynamicImage::ImageLuma8(image::GrayImage::from_pixel(3, 2, image::Luma([77])))
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let given = Contents::default().with("h.png", Content::File(png.into()));
        let image = given.read_image(Path::new("h.png")).unwrap();
        assert_eq!((image.width(), image.height()), (3, 2));
        assert_eq!(image.into_luma8().get_pixel(2, 1).0, [77]);
    }
}
